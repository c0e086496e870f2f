//! The writer never deletes what is not its own, and a stop asked for while it writes leaves the
//! output folder as it was. One test in its own process: the stop request is process-wide.

use ehl_workbench::{Error, cancel, output};
use std::path::{Path, PathBuf};

/// Fills a stage with `n` files, asking for a stop after `stop_after` of them (if any).
fn filler(
    n: usize,
    stop_after: Option<usize>,
) -> impl FnOnce(&Path) -> ehl_workbench::error::Result<Vec<PathBuf>> {
    move |stage: &Path| {
        let mut files = vec![];
        for k in 0..n {
            if Some(k) == stop_after {
                cancel::request();
            }
            let f = stage.join(format!("f{k}.txt"));
            ehl_workbench::error::write_file(&f, format!("{k}"))?;
            files.push(f);
        }
        Ok(files)
    }
}

fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn the_writer_replaces_only_its_own_folders_and_a_stop_leaves_them_as_they_were() {
    let tmp = tempfile::tempdir().unwrap();
    let top = tmp.path();

    // A folder of the user's: refused before anything is done, its file untouched.
    let thesis = top.join("thesis");
    std::fs::create_dir_all(thesis.join("chapters")).unwrap();
    std::fs::write(thesis.join("chapters/ch1.tex"), "x").unwrap();
    let e = output::replace_dir(&thesis, filler(3, None)).unwrap_err();
    assert!(matches!(e, Error::Refused(_)) && e.to_string().contains("not an ehl output"), "{e}");
    assert_eq!(std::fs::read_to_string(thesis.join("chapters/ch1.tex")).unwrap(), "x");

    // A file, and a folder under a file: refused, the file as it was.
    let file = top.join("afile");
    std::fs::write(&file, "mine").unwrap();
    for target in [file.clone(), file.join("sub")] {
        let e = output::replace_dir(&target, filler(1, None)).unwrap_err();
        assert!(e.to_string().contains("is a file"), "{e}");
    }
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "mine");

    // An empty folder and a new one are taken; the output carries the marker.
    let out = top.join("out");
    std::fs::create_dir(&out).unwrap();
    output::replace_dir(&out, filler(2, None)).unwrap();
    assert_eq!(names(&out), [".ehl-output", "f0.txt", "f1.txt"]);

    // A stop asked for while the writer fills its stage: the stage is gone, the earlier output
    // is whole, and the error says so.
    let e = output::replace_dir(&out, filler(50, Some(10))).unwrap_err();
    assert!(matches!(e, Error::Interrupted(_)) && e.to_string().contains("as it was"), "{e}");
    cancel::clear();
    assert_eq!(names(&out), [".ehl-output", "f0.txt", "f1.txt"]);
    assert_eq!(names(top), ["afile", "out", "thesis"], "a stage left behind");

    // What a killed run left (its process gone: a pid no system reaches): its stage is removed
    // and its set-aside output, the folder itself missing, put back; a folder that only looks
    // like one but is not ours (no marker, not empty) stays.
    let dead = 4_000_000_000u32;
    for (name, marked) in
        [(format!(".out.partial-{dead}"), true), (format!(".out.old-{dead}-0"), true)]
    {
        let d = top.join(name);
        std::fs::create_dir(&d).unwrap();
        if marked {
            std::fs::write(d.join(".ehl-output"), "").unwrap();
        }
        std::fs::write(d.join("f0.txt"), "old").unwrap();
    }
    let foreign = top.join(format!(".out.partial-{}", dead + 1));
    std::fs::create_dir(&foreign).unwrap();
    std::fs::write(foreign.join("notes.txt"), "keep").unwrap();
    std::fs::remove_dir_all(&out).unwrap();
    // This run is stopped too: what stands afterwards is the killed run's output, put back.
    assert!(output::replace_dir(&out, filler(5, Some(2))).is_err());
    cancel::clear();
    assert_eq!(std::fs::read_to_string(out.join("f0.txt")).unwrap(), "old");
    output::replace_dir(&out, filler(1, None)).unwrap();
    assert_eq!(names(&out), [".ehl-output", "f0.txt"]);
    assert_eq!(std::fs::read_to_string(out.join("f0.txt")).unwrap(), "0");
    let mut left = names(top);
    left.retain(|n| n.starts_with(".out."));
    assert_eq!(
        left,
        [format!(".out.partial-{}", dead + 1)],
        "leftovers not tidied, or a foreign folder removed"
    );

    // A name of 250 bytes: its staging folder still fits a file name.
    let long = top.join("x".repeat(250));
    output::replace_dir(&long, filler(1, None)).unwrap();
    output::replace_dir(&long, filler(2, None)).unwrap();
    assert_eq!(names(&long), [".ehl-output", "f0.txt", "f1.txt"]);

    // A sweep writes into a new or empty folder or its own (its plan.json), never into a folder
    // of other files.
    let sw = ehl_scene::Sweep::from_json(
        r#"{"name": "s", "scene": "hertz", "parameters": [{"parameter": "conditions.load_n", "values": [10, 20]}]}"#,
        "test",
    )
    .unwrap();
    let plan = ehl_workbench::sweep::Plan::new(&sw, None).unwrap();
    let e = plan.write(&thesis).unwrap_err();
    assert!(e.to_string().contains("no sweep's plan.json"), "{e}");
    assert_eq!(names(&thesis), ["chapters"]);
    let fresh = top.join("sweep");
    plan.write(&fresh).unwrap();
    plan.write(&fresh).unwrap();

    // The working folder, and a folder holding it, are never replaced.
    let here = std::env::current_dir().unwrap();
    let e = output::check_out_dir(&here).unwrap_err();
    assert!(e.to_string().contains("working folder"), "{e}");
}
