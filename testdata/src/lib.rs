//! Where the tests find the reference data in `../shared/data`, and what they do when it
//! is missing: say so loudly, and fail when `ESTLAB_REQUIRE_SHARED_DATA=1`.

use std::path::{Path, PathBuf};

/// The shared data directory: `ESTLAB_SHARED_DATA`, or `../shared/data` beside the
/// repository. `None` (after a loud warning) when it is absent and not required; a panic
/// when it is absent and `ESTLAB_REQUIRE_SHARED_DATA=1`.
pub fn shared_data() -> Option<PathBuf> {
    let dir = match std::env::var_os("ESTLAB_SHARED_DATA") {
        Some(dir) => PathBuf::from(dir),
        None => Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/data"),
    };
    if dir.join("el2320").is_dir() {
        return Some(dir);
    }
    let message = format!(
        "the shared reference data is not at {} (set ESTLAB_SHARED_DATA to its directory)",
        dir.display()
    );
    if std::env::var("ESTLAB_REQUIRE_SHARED_DATA").as_deref() == Ok("1") {
        panic!("{message}, and ESTLAB_REQUIRE_SHARED_DATA=1 requires it");
    }
    eprintln!("\n!!! SKIPPED: {message}; this test checks nothing without it !!!\n");
    None
}

/// The text of a file under the shared data directory, if that directory is there.
pub fn read(relative: &str) -> Option<String> {
    let path = shared_data()?.join(relative);
    Some(
        std::fs::read_to_string(&path)
            .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display())),
    )
}
