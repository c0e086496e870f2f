//! Tables of measured numbers, written by the xtask that measures them into
//! `docs/measured/NAME.md`, with the command that regenerates them, the date and the machine:
//! the docs link to these files instead of copying numbers by hand.

use anyhow::{Context, Result};
use std::path::{Path, PathBuf};

/// A table: a header row and rows of cells, already formatted.
pub struct Table {
    /// Column headers (with units).
    pub header: Vec<String>,
    /// Rows of cells.
    pub rows: Vec<Vec<String>>,
}

impl Table {
    /// A table with these column headers and no rows yet.
    pub fn new(header: &[&str]) -> Self {
        Self { header: header.iter().map(|h| h.to_string()).collect(), rows: vec![] }
    }

    /// The table as Markdown.
    pub fn markdown(&self) -> String {
        let line = |cells: &[String]| format!("| {} |\n", cells.join(" | "));
        let mut s = line(&self.header);
        s += &line(&vec!["---".to_string(); self.header.len()]);
        for r in &self.rows {
            s += &line(r);
        }
        s
    }
}

/// Where a generated page goes, beside the workspace's `docs/`.
pub fn page_path(name: &str) -> PathBuf {
    // A quick run's numbers are coarse grids': they never replace a measured page.
    let dir = if crate::quick() { "../target/quick-measured" } else { "../docs/measured" };
    Path::new(env!("CARGO_MANIFEST_DIR")).join(dir).join(format!("{name}.md"))
}

/// Writes `docs/measured/NAME.md`: a title, how it was made (`command`, the date, the cores),
/// `intro`, and the tables with their captions. Returns the path.
pub fn write(
    name: &str,
    title: &str,
    command: &str,
    intro: &str,
    tables: &[(&str, &Table)],
) -> Result<PathBuf> {
    let path = page_path(name);
    let dir = path.parent().context("docs/measured has a parent")?;
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let date = std::process::Command::new("date")
        .arg("-u")
        .arg("+%Y-%m-%d")
        .output()
        .ok()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_default();
    let cores = std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1);
    let mut s = format!(
        "# {title}\n\nWritten by `{command}` on {date}, on {cores} cores: rerun it to refresh this page \
         (do not edit it by hand). Timings on shared cores vary by 20–30 %: compare them as ratios \
         within one run.\n\n{intro}\n"
    );
    for (caption, t) in tables {
        s += &format!("\n{caption}\n\n{}", t.markdown());
    }
    std::fs::write(&path, s).with_context(|| format!("writing {}", path.display()))?;
    println!("wrote {}", path.display());
    Ok(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_table_is_markdown_with_its_header_rule_and_rows() {
        let mut t = Table::new(&["n", "time [s]"]);
        t.rows.push(vec!["65".into(), "0.010".into()]);
        assert_eq!(t.markdown(), "| n | time [s] |\n| --- | --- |\n| 65 | 0.010 |\n");
    }
}
