//! Every exercise's views of its runs for the browser's grader (`wasm.rs` in its folder
//! under `labs/src/exercises/`, when it has one) become a module of this crate: the
//! exercise keeps them in its folder, and no list of exercises is kept here.

use std::fmt::Write;
use std::path::Path;

fn main() {
    let exercises = Path::new(env!("CARGO_MANIFEST_DIR")).join("../labs/src/exercises");
    println!("cargo::rerun-if-changed={}", exercises.display());
    let mut folders: Vec<_> = std::fs::read_dir(&exercises)
        .unwrap_or_else(|e| panic!("{}: {e}", exercises.display()))
        .map(|entry| entry.expect("a folder entry").path())
        .filter(|path| path.join("wasm.rs").is_file())
        .collect();
    folders.sort();
    let mut modules = String::new();
    for folder in folders {
        let name = folder
            .file_name()
            .and_then(|n| n.to_str())
            .expect("a folder's name");
        let file = folder
            .join("wasm.rs")
            .canonicalize()
            .expect("the file exists");
        writeln!(
            modules,
            "#[path = {:?}]\nmod {name};",
            file.display().to_string()
        )
        .expect("writing to a string");
    }
    let out =
        Path::new(&std::env::var("OUT_DIR").expect("cargo sets OUT_DIR")).join("exercises.rs");
    std::fs::write(&out, modules).unwrap_or_else(|e| panic!("{}: {e}", out.display()));
}
