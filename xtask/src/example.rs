//! The README's example: its first command (`ehl compare seed --accuracy 5%`) run through the
//! same library path, the terminal table written to `docs/measured/example-compare.md` and into
//! the README between its markers, so that the README's numbers are a measured page's and the
//! two never disagree (a validation test compares them).

use crate::{measured, quick};
use anyhow::{Context, Result, bail};
use ehl_workbench::compare::{self, Schedule};
use std::path::Path;

/// The README's markers around the example's table.
const BEGIN: &str = "<!-- example-compare: written by `cargo xtask example` -->";
const END: &str = "<!-- /example-compare -->";

/// Runs the example and writes the page (and, unless quick, the README's block).
pub fn run(out: &Path) -> Result<()> {
    let seed = ehl_scene::builtin("seed")?;
    // Quickly, the seed's least grid for its films: the code path, not the README's numbers.
    let scene = if quick() { seed.with_points(129)? } else { seed.with_accuracy(0.05)? };
    let c = compare::run_checked(&scene, Schedule::SideBySide, true);
    let table = c.table();
    if !c.all_converged() {
        bail!("the example did not converge for every model:\n{table}");
    }
    c.write(out)?;
    let block = format!("```\n{}```\n", table);
    let intro = format!(
        "`ehl compare seed --accuracy 5%`, the README's first command: the seed's Table 1 through \
         every model on the grid the accuracy rule gives, each answer with its estimated error \
         (the README explains the columns). The README shows this table.\n\n{block}"
    );
    measured::write(
        "example-compare",
        "The README's example: `ehl compare seed --accuracy 5%`",
        "cargo xtask example",
        &intro,
        &[],
    )?;
    if !quick() {
        let readme = Path::new(env!("CARGO_MANIFEST_DIR")).join("../README.md");
        let text = std::fs::read_to_string(&readme).context("reading README.md")?;
        let (Some(b), Some(e)) = (text.find(BEGIN), text.find(END)) else {
            bail!("README.md lacks the markers {BEGIN} … {END}");
        };
        let new = format!("{}{BEGIN}\n{block}{}", &text[..b], &text[e..]);
        std::fs::write(&readme, new).context("writing README.md")?;
        println!("wrote {}", readme.display());
    }
    Ok(())
}
