//! The exercise on the UKF and the particle filter: its student files graded as the
//! server grades them, on a few seeds (see `student/catalogue.rs`):
//! `tests/student/ukf_particle/correct.js` scores 1, the starter 0, and every classic
//! mistake of `tests/student/ukf_particle/mistakes.json` fails the test of the function it
//! breaks with its hint (and those of the functions that call it), and the runs it
//! breaks. The hints themselves are held to every mistake over many seeds in the
//! exercise's unit tests (`labs/src/exercises/ukf_particle/hints.rs`).

use crate::student;

use student::catalogue::{Seeds, graded_as_the_server_grades};
use student::ukf_particle::FILES;

/// The student seeds, each with the seed of its hidden cases and runs.
const SEEDS: [Seeds; 3] = [(1, 0x5eed_0001), (2320, 9_876_543_210), (7, 2_718_281_828)];

graded_as_the_server_grades!(FILES, SEEDS, 12);
