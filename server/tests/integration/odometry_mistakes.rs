//! The odometry exercise's student files graded as the server grades them, on several
//! seeds (see `student/catalogue.rs`): `tests/student/odometry/correct.js` scores 1, the
//! starter 0, and every classic mistake of `tests/student/odometry/mistakes.json` fails
//! the test of the function it breaks with its hint and the paths it breaks.

use crate::student;

use student::catalogue::{Seeds, graded_as_the_server_grades};
use student::odometry::FILES;

/// The student seeds, each with the seed of its hidden cases and paths.
const SEEDS: [Seeds; 6] = [
    (1, 0x5eed_0001),
    (17, 4242),
    (2320, 9_876_543_210),
    (99, 1),
    (123_456_789, 31_337),
    (7, 2_718_281_828),
];

graded_as_the_server_grades!(FILES, SEEDS, 12);
