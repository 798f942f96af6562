//! The reference functions reproduce every case of the lab's original test fixtures.

use labs::exercises::ekf_localization::{FIXTURE_FILES, load_fixtures};
use labs::grading::{Contract, Tolerance};

testdata::data_tests!(every_original_fixture_case_is_reproduced);

fn every_original_fixture_case_is_reproduced() {
    let mut checked = 0;
    for (function, file) in FIXTURE_FILES {
        let text = testdata::read(&format!("el2320/test_cases/{file}"));
        let cases = load_fixtures(function, file, &text).unwrap();
        assert_eq!(cases.len(), 100, "{file}");
        for case in &cases {
            let got = case.call.reference_output().unwrap();
            let mismatches = case.check(&got, Tolerance::default());
            assert!(mismatches.is_empty(), "{}: {mismatches:#?}", case.id);
            checked += 1;
        }
    }
    assert_eq!(checked, 800);
}
