//! Decides, when the tests are built, whether the tests that need the shared data run or
//! are reported as ignored: they are ignored only when the data is missing and
//! `ESTLAB_REQUIRE_SHARED_DATA=1` is not set. The choice is made here because the test
//! runner can only ignore a test by an attribute; `data_tests!` picks its attribute by the
//! cfg set below.

#[path = "src/locate.rs"]
mod locate;

fn main() {
    println!("cargo::rustc-check-cfg=cfg(estlab_shared_data_missing)");
    println!("cargo::rerun-if-env-changed=ESTLAB_SHARED_DATA");
    println!("cargo::rerun-if-env-changed=ESTLAB_REQUIRE_SHARED_DATA");
    println!("cargo::rerun-if-changed=build.rs");
    println!("cargo::rerun-if-changed=src/locate.rs");
    let dir = locate::shared_data_dir();
    // Run again when the data appears or changes. While the path does not exist, cargo
    // runs this script at every build and relinks the tests that use this crate: a few
    // seconds, so that the tests run as soon as the data is there.
    println!("cargo::rerun-if-changed={}", dir.join("el2320").display());
    if !locate::is_present(&dir) && !locate::required() {
        println!("cargo::rustc-cfg=estlab_shared_data_missing");
    }
}
