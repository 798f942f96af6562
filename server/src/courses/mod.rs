//! What a course is made of, apart from its storage: the deadline and late policy of an
//! assignment, the class's view of it and its challenge's ranking, the sign-in codes and tokens (made here, kept only as hashes), and the
//! roster file an instructor imports, with the rules a student id keeps (`ids`).

pub mod challenge;
pub mod class;
pub mod codes;
pub mod deadline;
pub mod export;
pub mod ids;
pub mod questions;
pub mod report;
pub mod review;
pub mod roster;
pub mod rounds;
pub mod setup;

/// A course's short name (`el2320`): what `estlab course` and the database call it.
/// Letters, digits, `-`, `_` and `.`, at most 40.
pub fn check_course_name(name: &str) -> Result<(), String> {
    let valid = !name.is_empty()
        && name.len() <= 40
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.'));
    if valid {
        Ok(())
    } else {
        Err(format!(
            "{name:?} is not a course name: use 1 to 40 letters, digits, '-', '_' or '.'"
        ))
    }
}
