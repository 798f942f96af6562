//! The gradebook: a row per student of the roster, as CSV (for any LMS) and as XLSX (for
//! a spreadsheet, where a name is a string cell whatever it starts with).

use crate::courses::class::ClassView;
use crate::courses::report::{self, State};
use crate::courses::rounds::{self, Reviewed};
use crate::store::{self, Store};
use labs::Exercise;
use rust_xlsxwriter::{Format, Workbook, XlsxError};
use std::collections::HashMap;

const HEADER: [&str; 9] = [
    "id",
    "name",
    "email",
    "status",
    "submissions",
    "score",
    "late_penalty",
    "final_score",
    "submitted_at",
];

/// What the gradebook adds to the code's columns: the closed review rounds, and each
/// student's report state where the exercise asks for a report.
pub struct HandIn {
    pub reviewed: Reviewed,
    pub reports: Option<HashMap<String, State>>,
}

impl HandIn {
    pub fn load(store: &Store, course: &str, lab: Exercise) -> Result<HandIn, store::Error> {
        Ok(HandIn {
            reviewed: rounds::reviewed(store, course, lab)?,
            reports: report::states(store, course, lab)?,
        })
    }

    /// A student's report state (a draft when they never wrote one) and whether they
    /// passed the lab with the code's `score`; none where the exercise asks for no report.
    pub fn report(&self, id: &str, score: Option<f64>) -> Option<(State, bool)> {
        let state = self
            .reports
            .as_ref()?
            .get(id)
            .copied()
            .unwrap_or(State::Draft);
        Some((state, report::lab_passed(score, state)))
    }

    /// A student's report columns: `report_status` and `lab_passed` (yes or no).
    fn report_cells(&self, id: &str, score: Option<f64>) -> Option<[&'static str; 2]> {
        self.report(id, score)
            .map(|(state, passed)| [state.name(), if passed { "yes" } else { "no" }])
    }
}

/// The whole header: `HEADER`, then `review_share_N, review_bonus_N` for each question
/// set N (from 1) with a closed review round, then `report_status, lab_passed` where the
/// exercise asks for a report.
fn header(hand_in: &HandIn) -> Vec<String> {
    let reports = hand_in
        .reports
        .as_ref()
        .map(|_| ["report_status", "lab_passed"]);
    HEADER
        .iter()
        .map(|h| h.to_string())
        .chain(hand_in.reviewed.parts.iter().flat_map(|(part, _)| {
            [
                format!("review_share_{}", part + 1),
                format!("review_bonus_{}", part + 1),
            ]
        }))
        .chain(reports.into_iter().flatten().map(String::from))
        .collect()
}

/// A student's review columns: (share, bonus) for each set of `reviewed`.
fn review_cells<'a>(
    reviewed: &'a Reviewed,
    id: &'a str,
) -> impl Iterator<Item = (Option<f64>, Option<&'static str>)> + 'a {
    reviewed.parts.iter().map(move |(_, tallies)| {
        let tally = tallies.get(id);
        let bonus = tally
            .and_then(|t| t.bonus)
            .map(|b| if b { "yes" } else { "no" });
        (tally.and_then(|t| t.share), bonus)
    })
}

/// One student's line of the gradebook; the last four are `None` for a student with no
/// graded submission.
struct Row<'a> {
    id: &'a str,
    name: &'a str,
    email: &'a str,
    status: &'static str,
    submissions: usize,
    score: Option<f64>,
    late_penalty: Option<f64>,
    final_score: Option<f64>,
    submitted_at: Option<&'a str>,
}

fn rows(view: &ClassView) -> impl Iterator<Item = Row<'_>> {
    view.students.iter().map(|s| {
        let counting = s.counting.as_ref();
        Row {
            id: &s.id,
            name: &s.name,
            email: &s.email,
            status: if s.dropped { "dropped" } else { "enrolled" },
            submissions: s.submissions,
            score: counting.and_then(|c| c.score),
            late_penalty: counting.map(|c| c.penalty),
            final_score: counting.and_then(|c| c.final_score),
            submitted_at: counting.map(|c| c.submitted_at.as_str()),
        }
    })
}

/// The gradebook as CSV. Columns: `id, name, email, status (enrolled or dropped),
/// submissions, score (of the submission that counts, in [0, 1]), late_penalty (its share
/// lost), final_score (score × (1 − late_penalty)), submitted_at (UTC)`; empty for a
/// student with no graded submission; then, for each question set N with a closed review
/// round, `review_share_N, review_bonus_N (yes or no)` of its latest, empty for a student
/// outside it; where the exercise asks for a report, `report_status` (draft, handed_in,
/// accepted or revise) and `lab_passed` (yes when the score is 1 and the report
/// accepted). Text cells are made inert (`inert`).
pub fn csv(view: &ClassView, hand_in: &HandIn) -> Vec<u8> {
    let mut csv = csv::Writer::from_writer(Vec::new());
    csv.write_record(header(hand_in))
        .expect("writing to memory");
    let number = |value: Option<f64>| value.map_or_else(String::new, |v| format!("{v:.4}"));
    for row in rows(view) {
        let reviews = review_cells(&hand_in.reviewed, row.id)
            .flat_map(|(share, bonus)| [number(share), bonus.unwrap_or_default().to_string()]);
        let report = hand_in
            .report_cells(row.id, row.score)
            .into_iter()
            .flatten();
        let cells = [
            inert(row.id),
            inert(row.name),
            inert(row.email),
            row.status.to_string(),
            row.submissions.to_string(),
            number(row.score),
            number(row.late_penalty),
            number(row.final_score),
            row.submitted_at.unwrap_or_default().to_string(),
        ];
        csv.write_record(
            cells
                .into_iter()
                .chain(reviews)
                .chain(report.map(String::from)),
        )
        .expect("writing to memory");
    }
    csv.into_inner().expect("writing to memory")
}

/// The gradebook as XLSX, one sheet `grades` with the CSV's columns: ids, names, emails
/// and the dates as string cells (never formulas, so they need no `'`), the counts and
/// scores as numbers.
pub fn xlsx(view: &ClassView, hand_in: &HandIn) -> Vec<u8> {
    write_xlsx(view, hand_in).expect("a gradebook within Excel's limits, written to memory")
}

fn write_xlsx(view: &ClassView, hand_in: &HandIn) -> Result<Vec<u8>, XlsxError> {
    let mut workbook = Workbook::new();
    let sheet = workbook.add_worksheet();
    sheet.set_name("grades")?;
    let bold = Format::new().set_bold();
    let share_format = Format::new().set_num_format("0.0000");
    for (col, title) in (0..).zip(header(hand_in)) {
        sheet.write_string_with_format(0, col, title, &bold)?;
    }
    sheet.set_freeze_panes(1, 0)?;
    for (row, line) in (1..).zip(rows(view)) {
        sheet.write_string(row, 0, within_a_cell(line.id))?;
        sheet.write_string(row, 1, within_a_cell(line.name))?;
        sheet.write_string(row, 2, within_a_cell(line.email))?;
        sheet.write_string(row, 3, line.status)?;
        sheet.write_number(row, 4, line.submissions as f64)?;
        for (col, value) in [
            (5, line.score),
            (6, line.late_penalty),
            (7, line.final_score),
        ] {
            if let Some(value) = value {
                sheet.write_number_with_format(row, col, value, &share_format)?;
            }
        }
        if let Some(at) = line.submitted_at {
            sheet.write_string(row, 8, at)?;
        }
        let mut col = 9;
        for (share, bonus) in review_cells(&hand_in.reviewed, line.id) {
            if let Some(share) = share {
                sheet.write_number_with_format(row, col, share, &share_format)?;
            }
            if let Some(bonus) = bonus {
                sheet.write_string(row, col + 1, bonus)?;
            }
            col += 2;
        }
        for (cell, col) in hand_in
            .report_cells(line.id, line.score)
            .into_iter()
            .flatten()
            .zip(col..)
        {
            sheet.write_string(row, col, cell)?;
        }
    }
    workbook.save_to_buffer()
}

/// Text cut to what an Excel cell holds (32,767 UTF-16 units); no roster's name comes
/// near it, but a stored one is not refused for it.
fn within_a_cell(text: &str) -> &str {
    const LIMIT: usize = 32_767;
    let mut units = 0;
    for (at, c) in text.char_indices() {
        units += c.len_utf16();
        if units > LIMIT {
            return &text[..at];
        }
    }
    text
}

/// Where a spreadsheet may start a new cell inside a CSV cell: the separators of every
/// locale's CSV (`,`; `;` where the decimal mark is a comma, as in Swedish; tab) and line
/// breaks (which start a row when a reader splits the quoting otherwise).
fn separates(c: char) -> bool {
    matches!(c, ',' | ';' | '\t' | '\r' | '\n')
}

/// What makes a spreadsheet read a cell as a formula.
fn starts_formula(c: char) -> bool {
    matches!(c, '=' | '+' | '-' | '@' | '\t' | '\r')
}

/// A text cell no spreadsheet will run, in any locale: every piece of it that a reader
/// may take for a cell of its own (the start, and whatever follows a separator, after
/// spaces and quotes) and that starts like a formula gets a `'` before it, which
/// spreadsheets show as text. So `nils;=2*21;x` becomes `nils;'=2*21;x`: a Swedish Excel,
/// splitting it at the `;`, shows `'=2*21` as text.
pub fn inert(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut at_cell_start = true;
    for c in text.chars() {
        if at_cell_start && starts_formula(c) {
            out.push('\'');
        }
        out.push(c);
        at_cell_start = separates(c) || (at_cell_start && matches!(c, ' ' | '"'));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cell_that_looks_like_a_formula_is_kept_as_text() {
        assert_eq!(
            inert("=HYPERLINK(\"http://x\")"),
            "'=HYPERLINK(\"http://x\")"
        );
        assert_eq!(inert("+46 8 790 60 00"), "'+46 8 790 60 00");
        assert_eq!(inert("@SUM(A1)"), "'@SUM(A1)");
        assert_eq!(inert("-1"), "'-1");
        assert_eq!(inert("Ada Lovelace"), "Ada Lovelace");
        assert_eq!(inert("Anne-Marie"), "Anne-Marie");
        assert_eq!(inert("u1"), "u1");
    }

    #[test]
    fn a_formula_after_any_separator_is_kept_as_text_too() {
        assert_eq!(inert("nils;=2*21;x"), "nils;'=2*21;x");
        assert_eq!(inert("x;=2+3;"), "x;'=2+3;");
        assert_eq!(inert("a,+1"), "a,'+1");
        assert_eq!(inert("a\t@x"), "a\t'@x");
        assert_eq!(inert("a\n-1"), "a\n'-1");
        assert_eq!(inert("a; \"=1+2"), "a; \"'=1+2");
        assert_eq!(inert("\t\t=1"), "'\t'\t'=1");
        assert_eq!(inert("a;b=1"), "a;b=1");
    }

    #[test]
    fn a_cell_is_cut_to_what_excel_holds() {
        let long = "é".repeat(40_000);
        assert_eq!(within_a_cell(&long).chars().count(), 32_767);
        assert_eq!(within_a_cell("Ada"), "Ada");
    }
}
