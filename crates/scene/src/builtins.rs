//! The built-in scenes (`validation/scenes/`, compiled in) and loading a scene by name or path.

use super::*;

macro_rules! builtin_scenes {
    ($($name:literal),*) => {
        &[$(($name, include_str!(concat!("../../../validation/scenes/", $name, ".json")))),*]
    };
}

pub(crate) const BUILTINS: &[(&str, &str)] = builtin_scenes!(
    "seed",
    "hertz",
    "squeeze-steady",
    "rolling-from-squeezed",
    "rolling-from-uniform",
    "rolling-steady",
    "squeeze-after-stop",
    "dent-deep",
    "dent-shallow",
    "dent-shallow-compare",
    "hole",
    "hole-compare",
    "hole-starved-compare",
    "stop-compare",
    "stop-start-compare",
    "rolling-from-squeezed-compare",
    "startup-ramp-compare",
    "waviness-compare",
    "waviness-flooded-compare",
    "roughness-compare",
    "roughness-mixed-compare",
    "reynolds-m20-l10",
    "reynolds-m20-l10-dent",
    "reynolds-seed"
);

/// Names of the built-in scenes.
pub fn builtin_names() -> Vec<&'static str> {
    BUILTINS.iter().map(|(n, _)| *n).collect()
}

/// All built-in scenes, parsed and checked.
pub fn builtins() -> Vec<Scene> {
    BUILTINS.iter().map(|(n, _)| builtin(n).expect("built-in scenes are valid")).collect()
}

/// A built-in scene by name.
pub fn builtin(name: &str) -> Result<Scene, SceneError> {
    let (_, text) = BUILTINS
        .iter()
        .find(|(n, _)| *n == name)
        .ok_or_else(|| SceneError::Unknown(name.into()))?;
    Scene::from_json(text, &format!("`{name}` (built-in)"))
}

/// A built-in name, or else a path to a JSON file. A name that is both (a file `hertz` in the
/// working folder) is refused as ambiguous rather than guessed. A file's relative
/// `comparison` path is read from the file's own folder.
///
/// ```
/// let s = ehl_scene::load("hertz").unwrap();
/// assert_eq!(s.grid.nx, 129);
/// // A field out of its range is refused, naming it and what it allows.
/// let e = s.with_points(3).unwrap_err().to_string();
/// assert!(e.contains("grid.nx") && e.contains("5 ..= 4097"));
/// ```
pub fn load(name_or_path: &str) -> Result<Scene, SceneError> {
    let path = Path::new(name_or_path);
    let named = BUILTINS.iter().any(|(n, _)| *n == name_or_path);
    // A folder named like a built-in (an output folder `seed`) is no scene file: no clash.
    match (named, path.is_file()) {
        (true, false) => return builtin(name_or_path),
        (true, true) => {
            return Err(SceneError::Ambiguous { name: name_or_path.into(), kind: "scene" });
        }
        (false, false) => return Err(SceneError::Unknown(name_or_path.into())),
        (false, true) => {}
    }
    let text = std::fs::read_to_string(path)
        .map_err(|e| SceneError::Io { path: name_or_path.into(), message: e.to_string() })?;
    let text = with_height_maps_found(text, path);
    let mut scene = Scene::from_json(&text, &format!("file {name_or_path}"))?;
    if let Some(c) = &scene.comparison
        && !BUILTINS.iter().any(|(n, _)| n == c)
        && Path::new(c).is_relative()
        && let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty())
    {
        scene.comparison = Some(dir.join(c).to_string_lossy().into_owned());
    }
    Ok(scene)
}

/// The scene file's text with each height map's relative `path` taken from the file's folder
/// (as the comparison's scene is), before the scene is read and checked; the text as it was
/// when it is not a JSON object (its reading then says why).
fn with_height_maps_found(text: String, path: &Path) -> String {
    let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) else { return text };
    let Ok(mut v) = serde_json::from_str::<serde_json::Value>(&text) else { return text };
    let Some(features) = v.pointer_mut("/run/features").and_then(|f| f.as_array_mut()) else {
        return text;
    };
    let mut changed = false;
    for f in features {
        if let Some(p) = f.pointer_mut("/height-map/path")
            && let Some(rel) = p.as_str().filter(|r| Path::new(r).is_relative())
        {
            *p = dir.join(rel).to_string_lossy().into_owned().into();
            changed = true;
        }
    }
    // Untouched otherwise: a refusal's place in the file stays the file's own.
    if changed { v.to_string() } else { text }
}

/// Deserialises scene-crate JSON (scenes, sweeps), a refusal naming the field's path. The text
/// must be one JSON object and nothing after it: a second scene pasted below the first, or a
/// merge's leftover, is refused rather than ignored.
pub(crate) fn parse<T: serde::de::DeserializeOwned>(
    text: &str,
    origin: &str,
) -> Result<T, SceneError> {
    let refuse =
        |message: String| SceneError::Parse { origin: origin.into(), path: String::new(), message };
    match text.trim_start().chars().next() {
        Some('{') => {}
        Some(c) => {
            return Err(refuse(format!(
                "expected a JSON object `{{ … }}`, found text starting with `{c}`"
            )));
        }
        None => return Err(refuse("the text is empty: expected a JSON object".into())),
    }
    let de = &mut serde_json::Deserializer::from_str(text);
    let value = serde_path_to_error::deserialize(&mut *de).map_err(|e| {
        let path = e.path().to_string();
        SceneError::Parse {
            origin: origin.into(),
            path: if path == "." { String::new() } else { path },
            message: e.into_inner().to_string(),
        }
    })?;
    de.end().map_err(|e| {
        refuse(format!(
            "more text after the JSON object ends (line {}, column {}): one object per file",
            e.line(),
            e.column()
        ))
    })?;
    Ok(value)
}
