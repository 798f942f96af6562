//! The sensor-fusion exercise's student files graded as the server grades them, on a few
//! seeds (see `student/catalogue.rs`): `tests/student/sensor_fusion/correct.js` scores 1,
//! the starter 0, and every classic mistake of `tests/student/sensor_fusion/mistakes.json`
//! fails the test of the function it breaks with its hint and the trials it breaks. The
//! hints themselves are held to every mistake over many seeds in the exercise's unit tests
//! (`labs/src/exercises/sensor_fusion/hints.rs`); here few seeds keep the gradings quick.

use crate::student;

use student::catalogue::{Seeds, graded_as_the_server_grades};
use student::sensor_fusion::FILES;

/// The student seeds, each with the seed of its hidden cases and trials.
const SEEDS: [Seeds; 3] = [(1, 0x5eed_0001), (2320, 9_876_543_210), (7, 2_718_281_828)];

graded_as_the_server_grades!(FILES, SEEDS, 16);
