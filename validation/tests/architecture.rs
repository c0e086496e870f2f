//! The rules of `ARCHITECTURE.md`, checked: the crate graph, each crate's module imports against
//! the allow-list written there, no circle between a crate's modules, and no panic on a library
//! path. The rules are read from the document's `rules` block, so the document and the check
//! cannot drift apart.

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

/// A file's code outside its tests (the test module sits at the end of each file) and with
/// comment lines dropped.
fn library_code(p: &Path) -> String {
    let s = std::fs::read_to_string(p).unwrap();
    let s = s.split("#[cfg(test)]").next().unwrap_or("");
    s.lines().filter(|l| !l.trim_start().starts_with("//")).collect::<Vec<_>>().join("\n")
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
    for dir in crate_dirs() {
        for p in sources(&root().join("crates").join(&dir).join("src")) {
            let code = library_code(&p);
            for b in banned {
                if code.contains(b) {
                    found.push(format!("{}: {b}", p.strip_prefix(root()).unwrap().display()));
                }
            }
        }
    }
    assert!(found.is_empty(), "{found:#?}");
}
