//! Running the `omnee` binary and reading what it wrote.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub fn omnee() -> Command {
    Command::new(env!("CARGO_BIN_EXE_omnee"))
}

pub fn run_in(dir: &Path, args: &[&str]) -> Output {
    omnee()
        .current_dir(dir)
        .args(args)
        .output()
        .expect("omnee runs")
}

pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

pub fn json(o: &Output) -> serde_json::Value {
    assert!(o.status.success(), "omnee failed: {}", stderr(o));
    serde_json::from_slice(&o.stdout).unwrap_or_else(|e| panic!("not JSON ({e}): {}", stdout(o)))
}

pub fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// Every channel of an EXR file by name.
pub fn channels(path: &Path) -> HashMap<String, Vec<f32>> {
    use exr::prelude::*;
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .expect("a readable EXR");
    image
        .layer_data
        .channel_data
        .list
        .iter()
        .map(|c| (c.name.to_string(), c.sample_data.values_as_f32().collect()))
        .collect()
}

pub fn files_in(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// Writes the default scene with `edit` applied to its text.
pub fn scene_with(dir: &Path, name: &str, edit: impl Fn(String) -> String) -> PathBuf {
    let out = omnee().arg("default-scene").output().unwrap();
    let text = edit(String::from_utf8(out.stdout).unwrap());
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

pub fn replace_line(text: &str, starts: &str, with: &str) -> String {
    let mut found = false;
    let out = text
        .lines()
        .map(|l| {
            if l.starts_with(starts) && !found {
                found = true;
                with.to_string()
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    assert!(found, "no line starts with {starts}");
    out
}
