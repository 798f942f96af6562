//! Gives the build an identity of its sources: `ESTLAB_SOURCES`, a hash of everything
//! that decides how estlab grades (the reference filters, the server, the harness and the
//! pages, the locked dependencies), which `estlab --version` prints. `estlab package`
//! compares it with the static build it packages, so that a package never carries a
//! grader older than the estlab that made it.

use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};

/// What the hash covers, from the server crate's folder.
const INPUTS: [&str; 6] = [
    "../labs/src",
    "src",
    "templates",
    "../static/src",
    "../static/pages.json",
    "../Cargo.lock",
];

fn main() {
    let mut files = Vec::new();
    for input in INPUTS {
        println!("cargo:rerun-if-changed={input}");
        collect(Path::new(input), &mut files);
    }
    files.sort();
    let mut hash = Sha256::new();
    for file in &files {
        let bytes = std::fs::read(file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        hash.update(file.to_string_lossy().as_bytes());
        hash.update((bytes.len() as u64).to_le_bytes());
        hash.update(&bytes);
    }
    let digest = hash.finalize();
    let short: String = digest[..6].iter().map(|b| format!("{b:02x}")).collect();
    println!("cargo:rustc-env=ESTLAB_SOURCES={short}");
}

/// Every file under `path` (or `path` itself).
fn collect(path: &Path, files: &mut Vec<PathBuf>) {
    if path.is_file() {
        files.push(path.to_owned());
    } else if let Ok(entries) = std::fs::read_dir(path) {
        for entry in entries.flatten() {
            collect(&entry.path(), files);
        }
    }
}
