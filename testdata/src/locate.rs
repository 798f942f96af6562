// Shared by the library and its build script (`#[path]`), so that both look in the same
// place.

use std::path::{Path, PathBuf};

/// The shared data directory: `ESTLAB_SHARED_DATA` (a relative path is taken from the
/// workspace root, whichever crate's tests run), or `../shared/data` beside the
/// repository.
pub fn shared_data_dir() -> PathBuf {
    let workspace = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    match std::env::var_os("ESTLAB_SHARED_DATA").filter(|dir| !dir.is_empty()) {
        Some(dir) => workspace.join(dir),
        None => workspace.join("../shared/data"),
    }
}

/// Whether `dir` holds the EL2320 files the tests read.
pub fn is_present(dir: &Path) -> bool {
    dir.join("el2320").is_dir()
}

/// Whether `ESTLAB_REQUIRE_SHARED_DATA=1`: missing data is then a failure, never a skip.
pub fn required() -> bool {
    std::env::var("ESTLAB_REQUIRE_SHARED_DATA").as_deref() == Ok("1")
}
