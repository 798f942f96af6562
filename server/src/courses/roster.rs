//! A roster file as an instructor exports it from the university's system: CSV, UTF-8,
//! a header row naming the columns `id`, `name` and `email` (in any order, others
//! ignored), one student a line. Ids are checked as `ids` says (normalised to NFKC, safe
//! as file names, none too like another of the file or of the course); names and emails
//! are normalised to NFC and may hold no control or text-direction character.

use super::ids::{self, Alike};
use std::collections::HashMap;

/// One student of the roster.
#[derive(Debug, PartialEq, Eq)]
pub struct Student {
    pub id: String,
    pub name: String,
    pub email: String,
}

/// Where an id that a new one is too like was seen.
#[derive(Clone, Copy)]
enum Seen {
    Line(u64),
    Course,
}

/// Reads a roster for a course whose roster already holds `course_ids`; a problem names
/// its line (as a spreadsheet numbers it: the header is line 1) and column.
pub fn read(text: &str, course_ids: &[String]) -> Result<Vec<Student>, String> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .flexible(false)
        .from_reader(text.as_bytes());
    let header = reader
        .headers()
        .map_err(|e| format!("line 1 (the header): {e}"))?
        .clone();
    let column = |name: &str| {
        header
            .iter()
            .position(|h| h.eq_ignore_ascii_case(name))
            .ok_or_else(|| {
                format!(
                    "line 1 (the header): no column {name:?}; the columns are id, name, email (found: {})",
                    header.iter().collect::<Vec<_>>().join(", ")
                )
            })
    };
    let (id, name, email) = (column("id")?, column("name")?, column("email")?);
    let mut course = Alike::default();
    for known in course_ids {
        course.insert(known, Seen::Course);
    }
    let mut students = Vec::new();
    let mut lines: HashMap<String, u64> = HashMap::new();
    let mut file = Alike::default();
    for record in reader.records() {
        let record = record.map_err(|e| match e.position() {
            Some(position) => format!("line {}: {e}", position.line()),
            None => e.to_string(),
        })?;
        let line = record.position().map_or(0, |p| p.line());
        if record.iter().all(str::is_empty) {
            continue;
        }
        let field = |i: usize| record.get(i).unwrap_or("");
        let student = Student {
            id: ids::normalise(field(id)),
            name: ids::normalise_text(field(name)),
            email: ids::normalise_text(field(email)),
        };
        let as_written = field(id);
        if student.id.is_empty() {
            return Err(format!("line {line}: the id is empty"));
        }
        if let Some(problem) = ids::problem(&student.id) {
            return Err(format!("line {line}: the id {as_written:?} {problem}"));
        }
        for (what, text) in [("name", &student.name), ("email", &student.email)] {
            if let Some(problem) = ids::text_problem(text) {
                return Err(format!("line {line}: the {what} {text:?} {problem}"));
            }
        }
        if !student.email.is_empty() && !student.email.contains('@') {
            return Err(format!(
                "line {line}: {:?} is not an email address",
                student.email
            ));
        }
        if let Some(first) = lines.get(&student.id) {
            return Err(format!(
                "line {line}: the id {as_written:?} appears a second time (first on line {first})"
            ));
        }
        let new_to_course = !course_ids.contains(&student.id);
        let alike = file
            .find(&student.id)
            .or_else(|| course.find(&student.id).filter(|_| new_to_course));
        if let Some((other, seen)) = alike {
            let whose = match seen {
                Seen::Line(first) => format!("{other:?} of line {first}"),
                Seen::Course => format!("{other:?}, already on the course's roster"),
            };
            return Err(format!(
                "line {line}: the id {as_written:?} is too like {whose}: ids must differ in more than case or look-alike letters (file systems on Windows and macOS ignore case, and the dashboard would show them as one)"
            ));
        }
        lines.insert(student.id.clone(), line);
        file.insert(&student.id, Seen::Line(line));
        students.push(student);
    }
    Ok(students)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read_alone(text: &str) -> Result<Vec<Student>, String> {
        read(text, &[])
    }

    #[test]
    fn a_roster_reads_in_any_column_order_with_a_bom_and_blank_lines() {
        let roster = read_alone("\u{feff}email,ID,name,programme\nada@kth.se, u1 ,Ada Lovelace,CDATE\n\n\"b@kth.se\",u2,\"Hopper, Grace\",X\n").unwrap();
        assert_eq!(
            roster,
            vec![
                Student {
                    id: "u1".into(),
                    name: "Ada Lovelace".into(),
                    email: "ada@kth.se".into()
                },
                Student {
                    id: "u2".into(),
                    name: "Hopper, Grace".into(),
                    email: "b@kth.se".into()
                },
            ]
        );
    }

    #[test]
    fn a_bad_line_is_named_by_its_number() {
        assert_eq!(
            read_alone("id,name\nu1,Ada\n").unwrap_err(),
            "line 1 (the header): no column \"email\"; the columns are id, name, email (found: id, name)"
        );
        assert!(
            read_alone("id,name,email\nu1,Ada,a@x\nu2,Grace\n")
                .unwrap_err()
                .starts_with("line 3:")
        );
        assert_eq!(
            read_alone("id,name,email\nu1,Ada,a@x\n,Grace,g@x\n").unwrap_err(),
            "line 3: the id is empty"
        );
        assert_eq!(
            read_alone("id,name,email\nu1,Ada,a@x\nu1,Grace,g@x\n").unwrap_err(),
            "line 3: the id \"u1\" appears a second time (first on line 2)"
        );
        assert!(
            read_alone("id,name,email\n../../x,Ada,a@x\n")
                .unwrap_err()
                .starts_with("line 2: the id \"../../x\" holds '/'")
        );
        assert!(read_alone("id,name,email\n.hidden,Ada,a@x\n").is_err());
        assert_eq!(
            read_alone("id,name,email\nu1,Ada,ada.kth.se\n").unwrap_err(),
            "line 2: \"ada.kth.se\" is not an email address"
        );
    }

    #[test]
    fn ids_are_normalised_and_refused_when_unsafe_or_too_like_another() {
        let roster = read_alone("id,name,email\n\u{ff55}\u{ff11},Jose\u{301},j@x\n").unwrap();
        assert_eq!(
            (roster[0].id.as_str(), roster[0].name.as_str()),
            ("u1", "José")
        );
        let refused = |text: &str, known: &[&str]| {
            let known: Vec<String> = known.iter().map(|k| k.to_string()).collect();
            read(&format!("id,name,email\n{text}"), &known).unwrap_err()
        };
        assert_eq!(
            refused("alice,A,a@x\nALICE,B,b@x\n", &[]),
            "line 3: the id \"ALICE\" is too like \"alice\" of line 2: ids must differ in more than case or look-alike letters (file systems on Windows and macOS ignore case, and the dashboard would show them as one)"
        );
        assert!(
            refused("ace,A,a@x\n\u{430}\u{441}\u{435},B,b@x\n", &[])
                .starts_with("line 3: the id \"асе\" is too like \"ace\" of line 2")
        );
        assert!(
            refused("\u{430}ce,A,a@x\n", &["ace"])
                .starts_with("line 2: the id \"аce\" mixes scripts")
        );
        assert!(refused("Bob,B,b@x\n", &["bob"]).starts_with(
            "line 2: the id \"Bob\" is too like \"bob\", already on the course's roster"
        ));
        // Those already on the roster are themselves, however alike an earlier release let them be.
        assert!(read("id,name,email\nbob,B,b@x\n", &["bob".into(), "BOB".into()]).is_ok());
        assert!(
            refused("a\u{200b}b,A,a@x\n", &[])
                .starts_with("line 2: the id \"a\\u{200b}b\" holds U+200B")
        );
        assert!(refused("u1,A,a@x\nCON,B,b@x\n", &[]).starts_with("line 3: the id \"CON\" is CON"));
        assert!(
            refused("x\u{ff0f}y,A,a@x\n", &[]).starts_with("line 2: the id \"x／y\" holds '/'")
        );
        assert!(
            refused("u1,Ada\u{202e}txt.exe,a@x\n", &[])
                .starts_with("line 2: the name \"Ada\\u{202e}txt.exe\" holds U+202E")
        );
        assert!(refused("u1,Ada,a\u{200f}@x\n", &[]).starts_with("line 2: the email"));
    }
}
