//! The rules of `ARCHITECTURE.md`, checked: the crate graph, each crate's module imports against
//! the allow-list written there, no circle between a crate's modules, no panic and no unchecked
//! `unwrap` on a library path (beyond a short list, each with its reason), files and functions
//! of one job (a length cap, beyond a list that may only shrink), and a repository that speaks
//! of the product, not of how it was made; and the Python package's lockfile at the
//! workspace's versions of the crates both build. The rules are read from the document's `rules`
//! block, so the document and the check cannot drift apart.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The allow-lists: `crate NAME: deps…` and `module CRATE/MODULE: deps…` lines.
struct Rules {
    crates: BTreeMap<String, BTreeSet<String>>,
    modules: BTreeMap<(String, String), BTreeSet<String>>,
}

fn rules() -> Rules {
    let text = std::fs::read_to_string(root().join("ARCHITECTURE.md")).unwrap();
    let start = text.find("```rules\n").expect("ARCHITECTURE.md has a ```rules block") + 9;
    let end = start + text[start..].find("```").expect("the rules block ends");
    let mut r = Rules { crates: BTreeMap::new(), modules: BTreeMap::new() };
    for line in text[start..end].lines().filter(|l| !l.trim().is_empty()) {
        let (head, deps) = line.split_once(':').unwrap_or_else(|| panic!("rule line {line:?}"));
        let deps: BTreeSet<String> = deps.split_whitespace().map(String::from).collect();
        match head.split_once(' ') {
            Some(("crate", name)) => {
                r.crates.insert(name.trim().into(), deps);
            }
            Some(("module", path)) => {
                let (c, m) = path.trim().split_once('/').expect("module CRATE/MODULE");
                r.modules.insert((c.into(), m.into()), deps);
            }
            _ => panic!("rule line {line:?}: starts with `crate` or `module`"),
        }
    }
    r
}

/// The crate's directories under `crates/`.
fn crate_dirs() -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(root().join("crates"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// Every `.rs` file under `dir`.
fn sources(dir: &Path) -> Vec<PathBuf> {
    let mut out = vec![];
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            out.extend(sources(&p));
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
    out
}

/// A file's code outside its tests and with comment lines dropped: the whole file, each item
/// under `#[cfg(test)]` (a test module, wherever it sits) cut out to its closing brace.
fn library_code(p: &Path) -> String {
    let s = std::fs::read_to_string(p).unwrap();
    without_tests(&s)
        .lines()
        .filter(|l| !l.trim_start().starts_with("//"))
        .collect::<Vec<_>>()
        .join("\n")
}

/// `code` with every `#[cfg(test)]` item removed: from the attribute to the end of the item it
/// marks (its braces matched; a `;` item ends at the `;`).
fn without_tests(code: &str) -> String {
    let mut out = String::new();
    let mut rest = code;
    while let Some(k) = rest.find("#[cfg(test)]") {
        out.push_str(&rest[..k]);
        let after = &rest[k..];
        let (mut depth, mut end) = (0usize, after.len());
        for (i, c) in after.char_indices() {
            match c {
                '{' => depth += 1,
                '}' => {
                    depth = depth.saturating_sub(1);
                    if depth == 0 {
                        end = i + 1;
                        break;
                    }
                }
                ';' if depth == 0 => {
                    end = i + 1;
                    break;
                }
                _ => {}
            }
        }
        rest = &after[end..];
    }
    out.push_str(rest);
    out
}

/// The library sources: every crate's `src` and the Python package's.
fn library_sources() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = crate_dirs()
        .iter()
        .flat_map(|d| sources(&root().join("crates").join(d).join("src")))
        .collect();
    v.extend(sources(&root().join("python/src")));
    v
}

/// A path as the lists here name it, from the workspace's root (`crates/core/src/dry.rs`).
fn rel(p: &Path) -> String {
    p.strip_prefix(root()).unwrap_or(p).display().to_string()
}

/// The names right after each `crate::` (both `crate::a::…` and `crate::{a, b::…}`).
fn crate_paths(code: &str) -> BTreeSet<String> {
    let ident = |s: &str| -> String {
        s.trim().chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect()
    };
    let mut out = BTreeSet::new();
    for (k, _) in code.match_indices("crate::") {
        let rest = &code[k + 7..];
        if let Some(group) = rest.strip_prefix('{') {
            let body = &group[..group.find('}').unwrap_or(group.len())];
            out.extend(body.split(',').map(ident).filter(|n| !n.is_empty()));
        } else {
            out.insert(ident(rest));
        }
    }
    out
}

/// The module graph of crate `c`: each top-level module and the modules of the crate it uses.
fn module_graph(c: &str) -> BTreeMap<String, BTreeSet<String>> {
    let src = root().join("crates").join(c).join("src");
    let files = sources(&src);
    let top = |p: &Path| -> String {
        let rel = p.strip_prefix(&src).unwrap();
        let first = rel.components().next().unwrap().as_os_str().to_string_lossy().into_owned();
        first.trim_end_matches(".rs").to_string()
    };
    let modules: BTreeSet<String> = files.iter().map(|p| top(p)).collect();
    let mut g: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for p in &files {
        let m = top(p);
        if m == "lib" || m == "main" {
            continue;
        }
        let used = crate_paths(&library_code(p));
        let e = g.entry(m.clone()).or_default();
        e.extend(used.into_iter().filter(|u| modules.contains(u) && *u != m && u != "lib"));
    }
    g
}

/// A circle through the graph, if any, as the modules along it.
fn circle(g: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    fn visit(
        n: &str,
        g: &BTreeMap<String, BTreeSet<String>>,
        path: &mut Vec<String>,
        done: &mut BTreeSet<String>,
    ) -> Option<Vec<String>> {
        if let Some(k) = path.iter().position(|p| p == n) {
            let mut c = path[k..].to_vec();
            c.push(n.into());
            return Some(c);
        }
        if done.contains(n) {
            return None;
        }
        path.push(n.into());
        for d in g.get(n).into_iter().flatten() {
            if let Some(c) = visit(d, g, path, done) {
                return Some(c);
            }
        }
        path.pop();
        done.insert(n.into());
        None
    }
    let mut done = BTreeSet::new();
    g.keys().find_map(|n| visit(n, g, &mut vec![], &mut done))
}

#[test]
fn each_crate_uses_only_the_crates_its_rule_allows() {
    let r = rules();
    for dir in crate_dirs() {
        let toml =
            std::fs::read_to_string(root().join("crates").join(&dir).join("Cargo.toml")).unwrap();
        let name = toml
            .lines()
            .find_map(|l| l.strip_prefix("name = \""))
            .map(|n| n.trim_end_matches('"').to_string())
            .unwrap();
        // The `[dependencies]` table only (dev-dependencies may reach further, for tests).
        let deps_table = toml.split("[dependencies]").nth(1).unwrap_or("");
        let deps_table = deps_table.split("\n[").next().unwrap_or("");
        let used: BTreeSet<String> = deps_table
            .lines()
            .filter_map(|l| l.split(['.', ' ', '=']).next())
            .filter(|n| n.starts_with("ehl-"))
            .map(String::from)
            .collect();
        let allowed = r.crates.get(&name).unwrap_or_else(|| {
            panic!("crate {name} has no `crate {name}:` rule in ARCHITECTURE.md")
        });
        let extra: Vec<_> = used.difference(allowed).collect();
        assert!(extra.is_empty(), "{name} depends on {extra:?}, which its rule does not allow");
    }
}

#[test]
fn each_module_imports_only_what_its_rule_allows_and_no_module_reaches_itself() {
    let r = rules();
    for dir in crate_dirs() {
        let g = module_graph(&dir);
        for (m, used) in &g {
            let allowed = r.modules.get(&(dir.clone(), m.clone())).unwrap_or_else(|| {
                panic!("module {dir}/{m} has no `module {dir}/{m}:` rule in ARCHITECTURE.md")
            });
            let extra: Vec<_> = used.difference(allowed).collect();
            assert!(extra.is_empty(), "{dir}/{m} imports {extra:?}, which its rule does not allow");
        }
        // A rule for a module that is gone is a stale document.
        for (c, m) in r.modules.keys().filter(|(c, _)| *c == dir) {
            assert!(g.contains_key(m), "ARCHITECTURE.md has a rule for {c}/{m}, which is gone");
        }
        assert_eq!(circle(&g), None, "a circle between {dir}'s modules");
    }
}

#[test]
fn the_checks_see_a_circle_and_both_import_forms() {
    // The reader of imports and the circle finder, on made-up inputs: a check that cannot fail
    // is no check.
    let code =
        "use crate::model::{self, X};\nuse crate::{plot, drive::Plan};\nlet a = crate::run::f();";
    let got: Vec<String> = crate_paths(code).into_iter().collect();
    assert_eq!(got, ["drive", "model", "plot", "run"]);
    let g: BTreeMap<String, BTreeSet<String>> = [
        ("a".to_string(), BTreeSet::from(["b".to_string()])),
        ("b".to_string(), BTreeSet::from(["c".to_string()])),
        ("c".to_string(), BTreeSet::from(["a".to_string()])),
    ]
    .into();
    assert_eq!(circle(&g).unwrap(), ["a", "b", "c", "a"]);
    let dag: BTreeMap<String, BTreeSet<String>> =
        [("a".to_string(), BTreeSet::from(["b".to_string()])), ("b".to_string(), BTreeSet::new())]
            .into();
    assert_eq!(circle(&dag), None);
}

#[test]
fn no_library_path_panics() {
    // A model that fails says what, where and when through its error; nothing on a library
    // path panics, and nothing catches a panic to pass it off as a diagnosis.
    let banned = [
        "panic!(",
        "unreachable!(",
        "expect(\"validated",
        "catch_unwind",
        "todo!(",
        "unimplemented!(",
    ];
    let mut found = vec![];
    for p in library_sources() {
        let code = library_code(&p);
        for b in banned {
            if code.contains(b) {
                found.push(format!("{}: {b}", rel(&p)));
            }
        }
    }
    assert!(found.is_empty(), "{found:#?}");
}

/// The library files allowed an `unwrap()` or `expect(…)`, how many, and why each cannot fail.
/// The list may only shrink: a count above it fails, and so does one below it (lower it).
const UNWRAP_ALLOWED: &[(&str, usize, &str)] = &[
    (
        "crates/core/src/dry.rs",
        15,
        "slices of arrays the solver allocated itself (standard layout), the last of a non-empty level list",
    ),
    ("crates/reynolds/src/level.rs", 1, "a row of the level's own arrays (standard layout)"),
    (
        "crates/reynolds/src/level/rows.rs",
        6,
        "slices of the level's own arrays (standard layout), and the seam's split of them; the ghost row checked present just before",
    ),
    (
        "crates/core/src/deformation.rs",
        6,
        "FFTs on buffers the plan sized (rustfft fails only on a length mismatch); a buffer pool's lock, poisoned only after a panic",
    ),
    (
        "crates/workbench/src/sweep/mod.rs",
        4,
        "the points' error slot's lock (poisoned only after a panic); a one-thread pool's build",
    ),
    (
        "crates/scene/src/sweep.rs",
        4,
        "serialising a unit enum and a plan to JSON text; a lubricant checked present before",
    ),
    ("crates/workbench/src/reynolds.rs", 1, "a report has its cycles"),
    ("crates/reynolds/src/solver.rs", 1, "the last of a non-empty grid list"),
    ("crates/reynolds/src/solver/fas.rs", 1, "a solve's diagnosis has at least one cycle"),
    (
        "crates/layer/src/laws.rs",
        2,
        "the seed fit compiled in (reference/seed-fit.json), read by a test",
    ),
    ("crates/workbench/src/progress.rs", 1, "a fixed progress template"),
    ("crates/workbench/src/plot.rs", 1, "the bundled font"),
    ("crates/workbench/src/drive.rs", 1, "the history has its start row"),
    ("crates/scene/src/builtins.rs", 1, "the built-in scenes, each parsed by a test"),
];

#[test]
fn no_library_path_unwraps_beyond_the_short_list_with_its_reasons() {
    let mut found = vec![];
    for p in library_sources() {
        let code = library_code(&p);
        let n = code.matches(".unwrap()").count() + code.matches(".expect(").count();
        let name = rel(&p);
        let allowed = UNWRAP_ALLOWED.iter().find(|a| a.0 == name).map_or(0, |a| a.1);
        if n != allowed {
            found.push(format!(
                "{name}: {n} unwrap/expect, {allowed} allowed (an error path, or lower the list)"
            ));
        }
    }
    assert!(found.is_empty(), "{found:#?}");
}

/// The longest a source file in `crates/` may be, in lines, and the files allowed more (the
/// list may only shrink: a file over its number fails).
const FILE_LINES: usize = 900;
const LONG_FILES: &[(&str, usize)] = &[];

/// The longest a function may be, in lines, and the functions allowed more, with why.
const FN_LINES: usize = 120;
const LONG_FNS: &[(&str, &str, usize, &str)] = &[
    (
        "crates/reynolds/src/level/smoother.rs",
        "relax_line",
        255,
        "the line relaxation: one pass over a line's equations, its cavitation and contact sets",
    ),
    (
        "crates/workbench/src/drive.rs",
        "drive",
        215,
        "the one march loop: steps, error control, snapshots, stop rules",
    ),
    (
        "crates/layer/src/steady.rs",
        "solve",
        200,
        "the direct steady solve's iteration with its stall watch",
    ),
    (
        "crates/core/src/dry.rs",
        "pcg",
        200,
        "the preconditioned conjugate-gradient loop with its active set",
    ),
    (
        "crates/workbench/src/sweep/merge.rs",
        "one_parameter",
        180,
        "a one-parameter sweep's charts, panel by panel",
    ),
    (
        "crates/workbench/src/plot.rs",
        "draw_panel",
        170,
        "one body for the four log and linear coordinate systems (a macro)",
    ),
    (
        "crates/reynolds/src/solver/steady.rs",
        "cycles",
        135,
        "the cycle loop with the full-multigrid start and the stop rules",
    ),
    ("crates/scene/src/sweep.rs", "validate", 135, "a sweep's checks, field by field"),
    (
        "crates/reynolds/src/level/smoother.rs",
        "relax_columns",
        135,
        "the column pass of the mass-conserving relaxation",
    ),
    (
        "crates/workbench/src/drive/plan.rs",
        "from_run",
        130,
        "the march's plan from the run block, phase by phase",
    ),
    (
        "crates/workbench/src/reynolds/figures.rs",
        "figures",
        125,
        "the Reynolds answer's figures, one after the other",
    ),
    (
        "crates/reynolds/src/solver/fas.rs",
        "cycle",
        125,
        "one FAS cycle: smoothing, restriction, the force balance, prolongation",
    ),
];

/// Every function of `code` (`fn name` at the start of a line, to the closing brace at its
/// indentation) with its length in lines.
fn functions(code: &str) -> Vec<(String, usize)> {
    let lines: Vec<&str> = code.lines().collect();
    let mut out = vec![];
    for (i, l) in lines.iter().enumerate() {
        let t = l.trim_start();
        let indent = &l[..l.len() - t.len()];
        // Any visibility: `pub`, `pub(crate)`, `pub(super)`, `pub(in …)`.
        let t = match t.strip_prefix("pub(") {
            Some(r) => r.split_once(") ").map_or(t, |(_, rest)| rest),
            None => t.trim_start_matches("pub "),
        };
        let t = t.trim_start_matches("const ");
        let Some(rest) = t.strip_prefix("fn ") else { continue };
        let name: String = rest.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
        let close = format!("{indent}}}");
        if let Some(j) = lines[i + 1..].iter().position(|m| *m == close) {
            out.push((name, j + 2));
        }
    }
    out
}

#[test]
fn files_and_functions_keep_to_one_job_beyond_the_short_list() {
    let mut found = vec![];
    for dir in crate_dirs() {
        for p in sources(&root().join("crates").join(&dir).join("src")) {
            let name = rel(&p);
            let text = std::fs::read_to_string(&p).unwrap();
            let n = text.lines().count();
            let most = LONG_FILES.iter().find(|f| f.0 == name).map_or(FILE_LINES, |f| f.1);
            if n > most {
                found.push(format!("{name}: {n} lines, at most {most}"));
            }
            for (f, len) in functions(&without_tests(&text)) {
                let most =
                    LONG_FNS.iter().find(|x| x.0 == name && x.1 == f).map_or(FN_LINES, |x| x.2);
                if len > most {
                    found.push(format!("{name}: fn {f} {len} lines, at most {most}"));
                }
            }
        }
    }
    assert!(found.is_empty(), "{found:#?}");
}

/// Words about how the project was made, not about the product: tracker numbers, work-log
/// words, notes of what was set aside (they belong on the design-decisions page), dates.
fn process_words(text: &str) -> Vec<String> {
    let lower = text.to_lowercase();
    let mut out = vec![];
    for (k, _) in lower.match_indices("issue ") {
        let digits: String = lower[k + 6..].chars().take_while(char::is_ascii_digit).collect();
        if !digits.is_empty() {
            out.push(format!("issue {digits}"));
        }
    }
    // Spelt in parts, so that this file does not hold the words it bans.
    let banned = [
        concat!("issue", "'s"),
        concat!("this ", "round"),
        concat!("tried and ", "not kept"),
        concat!(" sess", "ion"),
        concat!("sess", "ion "),
    ];
    for w in banned {
        if lower.contains(w) {
            out.push(w.trim().to_string());
        }
    }
    // A date: 20dd-dd-dd.
    let b = lower.as_bytes();
    for k in 0..(b.len() + 1).saturating_sub(10) {
        let d = |i: usize| b[k + i].is_ascii_digit();
        if b[k] == b'2'
            && b[k + 1] == b'0'
            && d(2)
            && d(3)
            && b[k + 4] == b'-'
            && d(5)
            && d(6)
            && b[k + 7] == b'-'
            && d(8)
            && d(9)
        {
            out.push(lower[k..k + 10].to_string());
        }
    }
    out
}

#[test]
fn the_repository_speaks_of_the_product_not_of_how_it_was_made() {
    let mut files: Vec<PathBuf> = library_sources();
    for d in ["xtask/src", "validation/tests", "validation/src"] {
        files.extend(sources(&root().join(d)));
    }
    for d in crate_dirs() {
        let t = root().join("crates").join(d).join("tests");
        if t.is_dir() {
            files.extend(sources(&t));
        }
    }
    for f in ["README.md", "ARCHITECTURE.md", "python/ehl/__init__.py", "python/examples/seed.py"] {
        files.push(root().join(f));
    }
    files.extend(
        std::fs::read_dir(root().join("docs"))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|x| x == "md")),
    );
    let mut found = vec![];
    for p in files {
        let name = rel(&p);
        // The measured pages carry the date they were measured on (their header says so); the
        // code that writes that header reads the date, and this check spells the patterns.
        let skip_dates =
            name.ends_with("xtask/src/measured.rs") || name.ends_with("architecture.rs");
        let words: Vec<String> = process_words(&std::fs::read_to_string(&p).unwrap())
            .into_iter()
            .filter(|w| !(skip_dates && w.starts_with("20")))
            .filter(|_| !name.ends_with("architecture.rs"))
            .collect();
        if !words.is_empty() {
            found.push(format!("{name}: {words:?}"));
        }
    }
    for p in std::fs::read_dir(root().join("docs/measured")).unwrap().map(|e| e.unwrap().path()) {
        let words: Vec<String> = process_words(&std::fs::read_to_string(&p).unwrap())
            .into_iter()
            .filter(|w| !w.starts_with("20"))
            .collect();
        if !words.is_empty() {
            found.push(format!("{}: {words:?}", rel(&p)));
        }
    }
    assert!(found.is_empty(), "{found:#?}");
}

#[test]
fn the_checks_cut_test_items_and_see_process_words() {
    let code = "fn a() {}\n#[cfg(test)]\nmod tests {\n fn b() { panic!(\"x\") }\n}\nfn c() {}\n#[cfg(test)]\nuse x::y;\nfn d() {}";
    let kept = without_tests(code);
    assert!(kept.contains("fn a") && kept.contains("fn c") && kept.contains("fn d"));
    assert!(!kept.contains("panic!") && !kept.contains("use x::y"));
    let text = concat!("as iss", "ue 25 says, on 2026-11-26");
    assert_eq!(process_words(text), [concat!("iss", "ue 25"), "2026-11-26"]);
    assert!(process_words("the solver's issue with films").is_empty());
    let f =
        functions("fn one() {\n    x\n}\n    pub fn two(a: u8) {\n        y\n        z\n    }\n");
    assert_eq!(f, [("one".to_string(), 3), ("two".to_string(), 4)]);
}

/// The fenced block that follows `marker` in `text` (the block's lines, without the fences).
fn block_after(text: &str, marker: &str) -> Option<String> {
    let rest = &text[text.find(marker)? + marker.len()..];
    let start = rest.find("```\n")? + 4;
    let len = rest[start..].find("```")?;
    Some(rest[start..start + len].to_string())
}

#[test]
fn the_readme_example_is_its_measured_page_s_table() {
    // The README's table and docs/measured/example-compare.md come from one run of
    // `cargo xtask example`: a hand edit of either shows here.
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let page = std::fs::read_to_string(root().join("docs/measured/example-compare.md")).unwrap();
    let shown = block_after(&readme, "<!-- example-compare").expect("the README's example block");
    let measured = block_after(&page, "README's first command").expect("the page's table");
    assert!(shown.starts_with("scene seed"), "{shown}");
    assert_eq!(shown, measured, "README.md's example differs from its measured page");
}

/// `name → versions` of a `Cargo.lock`.
fn locked(path: &Path) -> BTreeMap<String, BTreeSet<String>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut out: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for block in text.split("[[package]]").skip(1) {
        let field = |key: &str| {
            block.lines().find_map(|l| l.strip_prefix(key)).map(|v| v.trim_matches('"').to_string())
        };
        if let (Some(name), Some(version)) = (field("name = "), field("version = ")) {
            out.entry(name).or_default().insert(version);
        }
    }
    out
}

#[test]
fn the_python_package_locks_the_crates_it_shares_with_the_workspace_at_the_workspace_s_versions() {
    // Both build in one target folder (python/.cargo/config.toml): one crate at another version
    // there (a serde_json dependency, say) rebuilds every workspace crate above it, minutes of
    // CI. Crates locked at one version in each file must agree.
    let workspace = locked(&root().join("Cargo.lock"));
    let python = locked(&root().join("python/Cargo.lock"));
    let differ: Vec<String> = python
        .iter()
        .filter_map(|(name, v)| {
            let w = workspace.get(name)?;
            (v.len() == 1 && w.len() == 1 && v != w).then(|| format!("{name} {v:?} against {w:?}"))
        })
        .collect();
    assert!(!python.is_empty() && workspace.contains_key("serde_json"));
    assert!(differ.is_empty(), "python/Cargo.lock differs from Cargo.lock: {differ:?}");
}
