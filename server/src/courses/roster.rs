//! A roster file as an instructor exports it from the university's system: CSV, UTF-8,
//! a header row naming the columns `id`, `name` and `email` (in any order, others
//! ignored), one student a line.

use std::collections::HashSet;

/// One student of the roster.
#[derive(Debug, PartialEq, Eq)]
pub struct Student {
    pub id: String,
    pub name: String,
    pub email: String,
}

/// Reads a roster; a problem names its line (as a spreadsheet numbers it: the header is
/// line 1) and column.
pub fn read(text: &str) -> Result<Vec<Student>, String> {
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
    let mut students = Vec::new();
    let mut seen = HashSet::new();
    for record in reader.records() {
        let record = record.map_err(|e| match e.position() {
            Some(position) => format!("line {}: {e}", position.line()),
            None => e.to_string(),
        })?;
        let line = record.position().map_or(0, |p| p.line());
        if record.iter().all(str::is_empty) {
            continue;
        }
        let field = |i: usize| record.get(i).unwrap_or("").to_string();
        let student = Student {
            id: field(id),
            name: field(name),
            email: field(email),
        };
        if student.id.is_empty() {
            return Err(format!("line {line}: the id is empty"));
        }
        if student.id.chars().count() > 100 || student.id.chars().any(char::is_control) {
            return Err(format!(
                "line {line}: the id {:?} is not at most 100 printable characters",
                student.id
            ));
        }
        if student.id.contains(['/', '\\']) || student.id.starts_with('.') {
            return Err(format!(
                "line {line}: the id {:?} may not contain / or \\ nor start with a dot (it names the student's files in exports)",
                student.id
            ));
        }
        if !student.email.is_empty() && !student.email.contains('@') {
            return Err(format!(
                "line {line}: {:?} is not an email address",
                student.email
            ));
        }
        if !seen.insert(student.id.clone()) {
            return Err(format!(
                "line {line}: the id {:?} appears a second time",
                student.id
            ));
        }
        students.push(student);
    }
    Ok(students)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_roster_reads_in_any_column_order_with_a_bom_and_blank_lines() {
        let roster = read("\u{feff}email,ID,name,programme\nada@kth.se, u1 ,Ada Lovelace,CDATE\n\n\"b@kth.se\",u2,\"Hopper, Grace\",X\n").unwrap();
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
            read("id,name\nu1,Ada\n").unwrap_err(),
            "line 1 (the header): no column \"email\"; the columns are id, name, email (found: id, name)"
        );
        assert!(
            read("id,name,email\nu1,Ada,a@x\nu2,Grace\n")
                .unwrap_err()
                .starts_with("line 3:")
        );
        assert_eq!(
            read("id,name,email\nu1,Ada,a@x\n,Grace,g@x\n").unwrap_err(),
            "line 3: the id is empty"
        );
        assert_eq!(
            read("id,name,email\nu1,Ada,a@x\nu1,Grace,g@x\n").unwrap_err(),
            "line 3: the id \"u1\" appears a second time"
        );
        assert!(
            read("id,name,email\n../../x,Ada,a@x\n")
                .unwrap_err()
                .starts_with("line 2: the id \"../../x\" may not contain /")
        );
        assert!(read("id,name,email\n.hidden,Ada,a@x\n").is_err());
        assert_eq!(
            read("id,name,email\nu1,Ada,ada.kth.se\n").unwrap_err(),
            "line 2: \"ada.kth.se\" is not an email address"
        );
    }
}
