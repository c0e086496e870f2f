//! `cargo xtask mutants`: mutation testing of the numerical crates with cargo-mutants, file by
//! file, each mutant tested by its own crate's tests (the workspace's validation suite is too slow
//! to run hundreds of times); a table of caught / missed / timeout / unviable per file.

use anyhow::{Context, Result, bail};
use serde_json::Value;
use std::path::Path;
use std::process::Command;

/// The files the test-strength target covers (issue: laws, formulas, params, hertz, deformation,
/// dry, level, transport, stepper).
pub const DEFAULT_FILES: &[&str] = &[
    "crates/core/src/laws.rs",
    "crates/layer/src/laws.rs",
    "crates/reynolds/src/formulas.rs",
    "crates/reynolds/src/params.rs",
    "crates/core/src/params.rs",
    "crates/core/src/hertz.rs",
    "crates/core/src/deformation.rs",
    "crates/core/src/dry.rs",
    "crates/layer/src/transport.rs",
    "crates/layer/src/stepper.rs",
    "crates/reynolds/src/level.rs",
];

fn package_of(file: &str) -> Result<&'static str> {
    Ok(match file.split('/').nth(1) {
        Some("core") => "ehl-core",
        Some("layer") => "ehl-layer",
        Some("reynolds") => "ehl-reynolds",
        _ => bail!(
            "--file {file}: expected a file under crates/core, crates/layer or crates/reynolds"
        ),
    })
}

/// Counts of one file's run.
#[derive(Default, Debug)]
pub struct Counts {
    pub caught: usize,
    pub missed: usize,
    pub timeout: usize,
    pub unviable: usize,
    pub missed_names: Vec<String>,
}

impl Counts {
    /// Caught among the viable mutants (a timeout counts as caught: the mutant did not pass).
    pub fn score(&self) -> f64 {
        let viable = self.caught + self.missed + self.timeout;
        if viable == 0 { 1.0 } else { (self.caught + self.timeout) as f64 / viable as f64 }
    }
}

/// Counts per file of one cargo-mutants output.
fn read_outcomes(path: &Path) -> Result<std::collections::BTreeMap<String, Counts>> {
    let v: Value = serde_json::from_str(
        &std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?,
    )?;
    let mut by_file = std::collections::BTreeMap::<String, Counts>::new();
    for o in v["outcomes"].as_array().context("outcomes.json without outcomes")? {
        let Some(m) = o["scenario"].get("Mutant") else { continue }; // the baseline
        let c = by_file.entry(m["file"].as_str().unwrap_or("?").to_string()).or_default();
        match o["summary"].as_str().unwrap_or("") {
            "CaughtMutant" => c.caught += 1,
            "MissedMutant" => {
                c.missed += 1;
                c.missed_names.push(m["name"].as_str().unwrap_or("?").to_string());
            }
            "Timeout" => c.timeout += 1,
            "Unviable" => c.unviable += 1,
            other => bail!("unknown mutant outcome {other}"),
        }
    }
    Ok(by_file)
}

/// Runs cargo-mutants on the files (all of `DEFAULT_FILES` when `files` is empty), one run per
/// crate (one baseline build each), optionally one shard `k/n`; prints and writes
/// (`OUT/summary.json`) the counts per file.
pub fn run(files: &[String], shard: Option<&str>, timeout_s: u64, out: &Path) -> Result<()> {
    let files: Vec<String> = if files.is_empty() {
        DEFAULT_FILES.iter().map(|s| s.to_string()).collect()
    } else {
        files.to_vec()
    };
    let have = Command::new("cargo").args(["mutants", "--version"]).output();
    if !have.is_ok_and(|o| o.status.success()) {
        bail!(
            "cargo-mutants is not installed: cargo install --locked cargo-mutants (v27, ~1.5 min)"
        );
    }
    std::fs::create_dir_all(out)?;
    let mut packages = std::collections::BTreeMap::<&str, Vec<&String>>::new();
    for f in &files {
        packages.entry(package_of(f)?).or_default().push(f);
    }
    let mut rows = vec![];
    for (package, files) in packages {
        let dir = out.join(package);
        let mut cmd = Command::new("cargo");
        cmd.args(["mutants", "--package", package, "--test-workspace=false"])
            .args(["--timeout", &timeout_s.to_string(), "--output"])
            .arg(&dir);
        for f in &files {
            cmd.args(["--file", f]);
        }
        if let Some(s) = shard {
            // Round-robin: a shard is an even sample of the file's mutants, not its first lines.
            cmd.args(["--shard", s, "--sharding", "round-robin"]);
        }
        println!(
            "mutating {package}: {files:?}{}",
            shard.map(|s| format!(", shard {s}")).unwrap_or_default()
        );
        // cargo-mutants exits non-zero when mutants are missed: the counts tell, not the status.
        let status = cmd.status().context("running cargo mutants")?;
        let outcomes = dir.join("mutants.out/outcomes.json");
        if !outcomes.exists() {
            bail!("cargo mutants on {package} wrote no outcomes (exit {status})");
        }
        for (file, c) in read_outcomes(&outcomes)? {
            println!(
                "  {file}: caught {}, missed {}, timeout {}, unviable {}: {:.0} % of viable caught",
                c.caught,
                c.missed,
                c.timeout,
                c.unviable,
                100.0 * c.score()
            );
            for m in &c.missed_names {
                println!("    missed: {m}");
            }
            rows.push(serde_json::json!({
                "file": file, "shard": shard, "caught": c.caught, "missed": c.missed,
                "timeout": c.timeout, "unviable": c.unviable, "score": c.score(),
                "missed_mutants": c.missed_names,
            }));
        }
    }
    println!("\n| file | caught | missed | timeout | unviable | caught of viable |");
    println!("| ---- | ------ | ------ | ------- | -------- | ---------------- |");
    for r in &rows {
        println!(
            "| `{}` | {} | {} | {} | {} | {:.0} % |",
            r["file"].as_str().unwrap(),
            r["caught"],
            r["missed"],
            r["timeout"],
            r["unviable"],
            100.0 * r["score"].as_f64().unwrap()
        );
    }
    let f = out.join("summary.json");
    std::fs::write(&f, serde_json::to_string_pretty(&rows)? + "\n")?;
    println!("wrote {}", f.display());
    Ok(())
}
