//! Where the tests find the reference data in `../shared/data`, and what they do when it
//! is missing.
//!
//! A test that needs the data is declared with [`data_tests!`]. When the data is missing
//! at build time, the test runner reports such a test as `ignored`, with the reason, so
//! that a run without the data never looks like a run that checked it; with
//! `ESTLAB_REQUIRE_SHARED_DATA=1` (as CI sets it) the tests run anyway and fail, saying
//! where the data was looked for.
//!
//! ```no_run
//! testdata::data_tests!(reads_the_map);
//!
//! fn reads_the_map() {
//!     assert!(!testdata::read("el2320/datasets/map_o3.txt").is_empty());
//! }
//! # fn main() {}
//! ```

use std::path::PathBuf;

mod locate;

/// Declares the tests of a file that need the shared data, by the names of plain
/// functions of that file: a test `needs_shared_data::NAME` that calls `NAME()` for each.
/// When the data was missing as they were built (and `ESTLAB_REQUIRE_SHARED_DATA=1` was
/// not set), the tests are `#[ignore]`d with a reason saying so, and the runner reports
/// them as ignored. Once per file.
#[cfg(not(estlab_shared_data_missing))]
#[macro_export]
macro_rules! data_tests {
    ($($name:ident),+ $(,)?) => {
        mod needs_shared_data {
            $(#[test] fn $name() { super::$name() })+
        }
    };
}

/// Declares the tests of a file that need the shared data (here: ignored, as the data was
/// missing when they were built).
#[cfg(estlab_shared_data_missing)]
#[macro_export]
macro_rules! data_tests {
    ($($name:ident),+ $(,)?) => {
        mod needs_shared_data {
            $(
                #[test]
                #[ignore = "needs the EL2320 data in ../shared/data or $ESTLAB_SHARED_DATA, \
                            missing when this test was built"]
                fn $name() { super::$name() }
            )+
        }
    };
}

/// The shared data directory: `ESTLAB_SHARED_DATA` (relative to the workspace root), or
/// `../shared/data` beside the repository. Panics, saying where it looked, when the data
/// is not there: a test that asks for it cannot check anything without it.
pub fn shared_data() -> PathBuf {
    let dir = locate::shared_data_dir();
    if !locate::is_present(&dir) {
        panic!(
            "the shared reference data is not at {} (set ESTLAB_SHARED_DATA to the directory \
             that holds el2320/)",
            dir.display()
        );
    }
    dir
}

/// The text of a file under the shared data directory. Panics when it cannot be read.
pub fn read(relative: &str) -> String {
    let path = shared_data().join(relative);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()))
}

/// For the benchmarks, which have no way to be reported as ignored: the text of a file
/// under the shared data directory, or `None` (after a note on stderr) when the data is
/// missing and `ESTLAB_REQUIRE_SHARED_DATA=1` is not set.
pub fn read_if_present(relative: &str) -> Option<String> {
    if !locate::is_present(&locate::shared_data_dir()) && !locate::required() {
        eprintln!(
            "note: no shared data at {}, {relative} left out",
            locate::shared_data_dir().display()
        );
        return None;
    }
    Some(read(relative))
}
