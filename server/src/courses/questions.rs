//! A question set: the written part of an assignment, as an instructor writes it in a
//! TOML file (imported like the roster, or edited on the web) and estlab ships for each
//! exercise. Every prompt, option and model answer is Markdown with math (`$...$`,
//! `$$...$$`), rendered in the browser. A question is one of four kinds:
//!
//! - `text`: an answer in words (and math), reviewed by peers against the model answer;
//! - `number`: a number, checked when the set gives its `answer`, within `tolerance`;
//! - `choice`: one of `options`, checked when the set names the `correct` one (from 1);
//! - `table`: a cell of text for each of `rows` and `columns`, reviewed by peers.
//!
//! ```toml
//! title = "Part I: before the lab"
//!
//! [[question]]
//! id = "gate"
//! kind = "number"
//! prompt = "The gate $\\lambda_M$ at $\\delta_M = 0.999$ with two degrees of freedom?"
//! answer = 13.8155
//! tolerance = 0.01
//! model = "$-2 \\ln(1 - \\delta_M)$"
//! ```
//!
//! A problem in a file names its line and the question's number and field.

use crate::store::{self, Store};
use labs::Exercise;
use serde::Deserialize;
use std::collections::HashSet;
use toml::Spanned;

/// The most questions a set holds.
pub const MAX_QUESTIONS: usize = 100;
/// The longest prompt, option, model answer or title, in characters.
pub const MAX_TEXT: usize = 20_000;
/// The longest answer of a student to one question (a table's cells together), in
/// characters.
pub const MAX_ANSWER: usize = 20_000;
/// The most options of a choice, and rows or columns of a table.
pub const MAX_ITEMS: usize = 30;

/// A question set, checked.
#[derive(Clone, Debug, PartialEq, serde::Serialize, ts_rs::TS)]
pub struct QuestionSet {
    pub title: String,
    /// Markdown shown before the first question.
    pub introduction: String,
    pub questions: Vec<Question>,
}

#[derive(Clone, Debug, PartialEq, serde::Serialize, ts_rs::TS)]
pub struct Question {
    /// Stable across edits of the set: answers are kept by it. Lower-case letters, digits
    /// and `-`; `q` and the question's number when the file gives none.
    pub id: String,
    /// A short heading (Markdown); none: the question's number alone.
    pub title: String,
    pub prompt: String,
    #[serde(flatten)]
    #[ts(flatten)]
    pub kind: Kind,
    /// The model answer or rubric reviewers mark against (Markdown); shown to students
    /// once the review round has closed.
    pub model: String,
}

#[derive(Clone, Debug, PartialEq, serde::Serialize, ts_rs::TS)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum Kind {
    Text,
    Number {
        /// The answer the number is checked against; none: reviewed by peers.
        answer: Option<f64>,
        /// How far from `answer` a number is still right (absolute).
        tolerance: f64,
        /// The unit the answer is in, shown beside the field.
        unit: String,
    },
    Choice {
        options: Vec<String>,
        /// The correct option, counting from 0; none: reviewed by peers.
        #[ts(type = "number | null")]
        correct: Option<usize>,
    },
    Table {
        rows: Vec<String>,
        columns: Vec<String>,
    },
}

/// A student's answer to one question, as the browser sends it.
#[derive(Clone, Debug, PartialEq, serde::Serialize, Deserialize, ts_rs::TS)]
#[serde(tag = "kind", content = "value", rename_all = "kebab-case")]
pub enum Answer {
    Text(String),
    /// The number as typed (`1.5e-3`, `-2`): what the student wrote is kept.
    Number(String),
    /// The chosen option, counting from 0.
    #[ts(type = "number")]
    Choice(usize),
    /// The cells, row by row.
    Table(Vec<Vec<String>>),
}

/// The file's form of a question, before it is checked.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSet {
    title: String,
    #[serde(default)]
    introduction: String,
    #[serde(default)]
    question: Vec<Spanned<RawQuestion>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawQuestion {
    id: Option<String>,
    #[serde(default)]
    title: String,
    kind: String,
    prompt: String,
    #[serde(default)]
    model: String,
    answer: Option<f64>,
    tolerance: Option<f64>,
    unit: Option<String>,
    options: Option<Vec<String>>,
    correct: Option<usize>,
    rows: Option<Vec<String>>,
    columns: Option<Vec<String>>,
}

/// The line (from 1) of byte `offset` of `text`.
fn line_of(text: &str, offset: usize) -> usize {
    text[..offset.min(text.len())].matches('\n').count() + 1
}

/// Reads and checks a question set written in TOML; a problem names its line, and the
/// question's number and field where it is one of a question.
pub fn read(text: &str) -> Result<QuestionSet, String> {
    let raw: RawSet = toml::from_str(text).map_err(|e| {
        let line = e
            .span()
            .map(|span| format!("line {}: ", line_of(text, span.start)));
        format!("{}{}", line.unwrap_or_default(), e.message())
    })?;
    let title = checked_text("title", raw.title, true)?;
    let introduction = checked_text("introduction", raw.introduction, false)?;
    if raw.question.is_empty() {
        return Err("the set has no question: add one under [[question]]".into());
    }
    if raw.question.len() > MAX_QUESTIONS {
        return Err(format!(
            "the set has {} questions, more than {MAX_QUESTIONS}",
            raw.question.len()
        ));
    }
    let mut ids = HashSet::new();
    let mut questions = Vec::with_capacity(raw.question.len());
    for (i, spanned) in raw.question.into_iter().enumerate() {
        let line = line_of(text, spanned.span().start);
        let question = check_question(i, spanned.into_inner())
            .map_err(|e| format!("line {line}: question {}: {e}", i + 1))?;
        if !ids.insert(question.id.clone()) {
            return Err(format!(
                "line {line}: question {}: the id {:?} is another question's too",
                i + 1,
                question.id
            ));
        }
        questions.push(question);
    }
    Ok(QuestionSet {
        title,
        introduction,
        questions,
    })
}

/// The question `raw`, the `index`th of its set (from 0), checked.
fn check_question(index: usize, raw: RawQuestion) -> Result<Question, String> {
    let id = match raw.id {
        Some(id) => {
            let valid = !id.is_empty()
                && id.len() <= 40
                && id
                    .chars()
                    .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-');
            if !valid {
                return Err(format!(
                    "id {id:?}: use 1 to 40 lower-case letters, digits or '-'"
                ));
            }
            id
        }
        None => format!("q{}", index + 1),
    };
    // The fields only some kinds take, and whether the file gives each.
    let given = [
        ("answer", raw.answer.is_some()),
        ("tolerance", raw.tolerance.is_some()),
        ("unit", raw.unit.is_some()),
        ("options", raw.options.is_some()),
        ("correct", raw.correct.is_some()),
        ("rows", raw.rows.is_some()),
        ("columns", raw.columns.is_some()),
    ];
    let fields = |taken: &[&str]| -> Result<(), String> {
        match given.iter().find(|(name, is)| *is && !taken.contains(name)) {
            Some((name, _)) => Err(format!(
                "{name} is not a field of a question of kind {:?}",
                raw.kind
            )),
            None => Ok(()),
        }
    };
    let kind = match raw.kind.as_str() {
        "text" => {
            fields(&[])?;
            Kind::Text
        }
        "number" => {
            fields(&["answer", "tolerance", "unit"])?;
            if let Some(answer) = raw.answer
                && !answer.is_finite()
            {
                return Err(format!("answer {answer} is not a finite number"));
            }
            let tolerance = raw.tolerance.unwrap_or(0.0);
            if !(tolerance.is_finite() && tolerance >= 0.0) {
                return Err(format!(
                    "tolerance {tolerance}: give a finite number, 0 or more"
                ));
            }
            if raw.tolerance.is_some() && raw.answer.is_none() {
                return Err("tolerance without an answer to be within it of".into());
            }
            Kind::Number {
                answer: raw.answer,
                tolerance,
                unit: checked_text("unit", raw.unit.unwrap_or_default(), false)?,
            }
        }
        "choice" => {
            fields(&["options", "correct"])?;
            let options = checked_items("options", raw.options, 2)?;
            let correct = match raw.correct {
                Some(n) if (1..=options.len()).contains(&n) => Some(n - 1),
                Some(n) => {
                    return Err(format!(
                        "correct = {n}: name an option from 1 to {}",
                        options.len()
                    ));
                }
                None => None,
            };
            Kind::Choice { options, correct }
        }
        "table" => {
            fields(&["rows", "columns"])?;
            Kind::Table {
                rows: checked_items("rows", raw.rows, 1)?,
                columns: checked_items("columns", raw.columns, 1)?,
            }
        }
        other => {
            return Err(format!(
                "kind {other:?}: a question is of kind \"text\", \"number\", \"choice\" or \"table\""
            ));
        }
    };
    Ok(Question {
        id,
        title: checked_text("title", raw.title, false)?,
        prompt: checked_text("prompt", raw.prompt, true)?,
        kind,
        model: checked_text("model", raw.model, false)?,
    })
}

/// `text` as the field `name`: at most `MAX_TEXT` characters, no control character but
/// line breaks and tabs, and not blank where `required`.
fn checked_text(name: &str, text: String, required: bool) -> Result<String, String> {
    if required && text.trim().is_empty() {
        return Err(format!("{name} is empty"));
    }
    if text.chars().count() > MAX_TEXT {
        return Err(format!("{name} is longer than {MAX_TEXT} characters"));
    }
    if let Some(c) = text
        .chars()
        .find(|c| c.is_control() && !matches!(c, '\n' | '\t' | '\r'))
    {
        return Err(format!("{name} holds the control character {c:?}"));
    }
    Ok(text)
}

/// The list `name`, required, of `least` to `MAX_ITEMS` texts, none of them empty.
fn checked_items(
    name: &str,
    items: Option<Vec<String>>,
    least: usize,
) -> Result<Vec<String>, String> {
    let items = items.ok_or_else(|| format!("{name} is missing"))?;
    if !(least..=MAX_ITEMS).contains(&items.len()) {
        return Err(format!(
            "{name}: {} given; give {least} to {MAX_ITEMS}",
            items.len()
        ));
    }
    items
        .into_iter()
        .enumerate()
        .map(|(i, item)| checked_text(&format!("{name}[{}]", i + 1), item, true))
        .collect()
}

/// The question sets of an assignment: those its instructors gave it, or the exercise's
/// own.
pub fn of_assignment(
    store: &Store,
    course: &str,
    lab: Exercise,
) -> Result<Vec<QuestionSet>, store::Error> {
    read_all(&sources(store, course, lab)?)
        .map_err(|e| store::Error::Conflict(format!("the questions of {lab}: {e}")))
}

/// The TOML of the question sets of an assignment: those its instructors gave it, or the
/// exercise's own.
pub fn sources(store: &Store, course: &str, lab: Exercise) -> Result<Vec<String>, store::Error> {
    Ok(store.questions(course, lab)?.unwrap_or_else(|| own(lab)))
}

/// The exercise's own question sets (in its folder's `questions/`), as TOML.
pub fn own(lab: Exercise) -> Vec<String> {
    lab.declaration()
        .questions
        .iter()
        .map(|&t| t.to_owned())
        .collect()
}

/// Reads the sets `texts`, in order; a problem names the set (from 1) as well.
pub fn read_all(texts: &[String]) -> Result<Vec<QuestionSet>, String> {
    texts
        .iter()
        .enumerate()
        .map(|(i, text)| read(text).map_err(|e| format!("set {}: {e}", i + 1)))
        .collect()
}

impl QuestionSet {
    /// The set as a student sees it before the review: the answers it checks against and
    /// the model answers left out.
    pub fn for_students(&self) -> QuestionSet {
        self.without_keys(false)
    }

    /// The set as a reviewer marks against it: the model answers, without the answers
    /// numbers and choices are checked against (which the reviewer could use for their own
    /// answers).
    pub fn for_reviewers(&self) -> QuestionSet {
        self.without_keys(true)
    }

    fn without_keys(&self, models: bool) -> QuestionSet {
        let questions = self
            .questions
            .iter()
            .map(|q| Question {
                kind: match &q.kind {
                    Kind::Number { unit, .. } => Kind::Number {
                        answer: None,
                        tolerance: 0.0,
                        unit: unit.clone(),
                    },
                    Kind::Choice { options, .. } => Kind::Choice {
                        options: options.clone(),
                        correct: None,
                    },
                    other => other.clone(),
                },
                model: if models {
                    q.model.clone()
                } else {
                    String::new()
                },
                ..q.clone()
            })
            .collect();
        QuestionSet {
            questions,
            ..self.clone()
        }
    }
}

impl Question {
    /// Whether `answer` is one this question takes (its kind, a listed option, the
    /// table's shape, within `MAX_ANSWER`); what is wrong otherwise.
    pub fn accepts(&self, answer: &Answer) -> Result<(), String> {
        let length = match answer {
            Answer::Text(text) | Answer::Number(text) => text.chars().count(),
            Answer::Choice(_) => 0,
            Answer::Table(rows) => rows.iter().flatten().map(|c| c.chars().count()).sum(),
        };
        if length > MAX_ANSWER {
            return Err(format!(
                "the answer to {} is longer than {MAX_ANSWER} characters",
                self.id
            ));
        }
        match (&self.kind, answer) {
            (Kind::Text, Answer::Text(_)) | (Kind::Number { .. }, Answer::Number(_)) => Ok(()),
            (Kind::Choice { options, .. }, Answer::Choice(i)) if *i < options.len() => Ok(()),
            (Kind::Choice { options, .. }, Answer::Choice(i)) => Err(format!(
                "{} has {} options, not an option {}",
                self.id,
                options.len(),
                i + 1
            )),
            (Kind::Table { rows, columns }, Answer::Table(cells))
                if cells.len() == rows.len() && cells.iter().all(|r| r.len() == columns.len()) =>
            {
                Ok(())
            }
            (Kind::Table { rows, columns }, Answer::Table(_)) => Err(format!(
                "{} is a table of {} rows and {} columns",
                self.id,
                rows.len(),
                columns.len()
            )),
            (kind, _) => Err(format!(
                "{} takes an answer of kind {:?}",
                self.id,
                kind.name()
            )),
        }
    }

    /// Whether `answer` is right, where the set says what is right (a number with its
    /// answer, a choice with its correct option); `None` where peers judge it.
    pub fn check(&self, answer: &Answer) -> Option<bool> {
        match (&self.kind, answer) {
            (
                Kind::Number {
                    answer: Some(expected),
                    tolerance,
                    ..
                },
                Answer::Number(typed),
            ) => Some(
                parse_number(typed).is_some_and(|given| (given - expected).abs() <= *tolerance),
            ),
            (
                Kind::Choice {
                    correct: Some(correct),
                    ..
                },
                Answer::Choice(chosen),
            ) => Some(chosen == correct),
            _ => None,
        }
    }
}

impl Kind {
    pub fn name(&self) -> &'static str {
        match self {
            Kind::Text => "text",
            Kind::Number { .. } => "number",
            Kind::Choice { .. } => "choice",
            Kind::Table { .. } => "table",
        }
    }
}

/// A number as a student types it: decimal, with a point or a comma, an exponent
/// (`1.5e-3`, `2E4`) or `×10^` (`1.5×10^-3`), spaces around it; `None` for anything else.
pub fn parse_number(typed: &str) -> Option<f64> {
    let typed = typed.trim().replace(',', ".");
    let normal = match typed.split_once(['×', 'x', '*']) {
        Some((mantissa, power)) => {
            let exponent = power.trim().strip_prefix("10^")?;
            format!("{}e{}", mantissa.trim(), exponent.trim())
        }
        None => typed,
    };
    let looks_numeric = normal
        .chars()
        .all(|c| c.is_ascii_digit() || matches!(c, '.' | '-' | '+' | 'e' | 'E'));
    normal
        .parse::<f64>()
        .ok()
        .filter(|n| looks_numeric && n.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const SET: &str = r#"
title = "Warm-up"
introduction = "Answer before the lab."

[[question]]
kind = "text"
prompt = "Why does $P$ grow in the prediction?"
model = "Process noise is added: $P^- = A P A^T + R$."

[[question]]
id = "gate"
kind = "number"
prompt = "The gate at $\\delta_M = 0.999$?"
answer = 13.8155
tolerance = 0.01

[[question]]
kind = "choice"
prompt = "Which update uses every reading at once?"
options = ["sequential", "batch"]
correct = 2

[[question]]
kind = "table"
prompt = "Dimensions"
rows = ["x", "P"]
columns = ["dimension"]
"#;

    #[test]
    fn a_set_reads_with_its_kinds_and_ids() {
        let set = read(SET).unwrap();
        assert_eq!(set.title, "Warm-up");
        let ids: Vec<&str> = set.questions.iter().map(|q| q.id.as_str()).collect();
        assert_eq!(ids, ["q1", "gate", "q3", "q4"]);
        assert_eq!(
            set.questions[2].kind,
            Kind::Choice {
                options: vec!["sequential".into(), "batch".into()],
                correct: Some(1)
            }
        );
        let gate = &set.questions[1];
        assert_eq!(gate.check(&Answer::Number("13.81".into())), Some(true));
        assert_eq!(gate.check(&Answer::Number("13,82".into())), Some(true));
        assert_eq!(gate.check(&Answer::Number("1.38155e1".into())), Some(true));
        assert_eq!(gate.check(&Answer::Number("13.7".into())), Some(false));
        assert_eq!(gate.check(&Answer::Number("about 14".into())), Some(false));
        assert_eq!(set.questions[2].check(&Answer::Choice(1)), Some(true));
        assert_eq!(set.questions[2].check(&Answer::Choice(0)), Some(false));
        assert_eq!(set.questions[0].check(&Answer::Text("noise".into())), None);
    }

    #[test]
    fn answers_of_the_wrong_shape_are_refused() {
        let set = read(SET).unwrap();
        let [text, gate, choice, table] = &set.questions[..] else {
            panic!("four questions")
        };
        assert!(text.accepts(&Answer::Text("a".into())).is_ok());
        assert!(text.accepts(&Answer::Choice(0)).is_err());
        assert!(gate.accepts(&Answer::Text("1".into())).is_err());
        assert!(choice.accepts(&Answer::Choice(2)).is_err());
        assert!(
            table
                .accepts(&Answer::Table(vec![vec!["3".into()], vec!["3x3".into()]]))
                .is_ok()
        );
        assert!(
            table
                .accepts(&Answer::Table(vec![vec!["3".into()]]))
                .is_err()
        );
        let long = "x".repeat(MAX_ANSWER + 1);
        assert!(text.accepts(&Answer::Text(long)).is_err());
    }

    #[test]
    fn problems_name_their_line_question_and_field() {
        let cases = [
            ("title = \"t\"\n", "no question"),
            (
                "title = \"t\"\n[[question]]\nkind = \"essay\"\nprompt = \"p\"\n",
                "line 2: question 1: kind \"essay\"",
            ),
            (
                "title = \"t\"\n[[question]]\nkind = \"text\"\nprompt = \"p\"\n\n[[question]]\nkind = \"choice\"\nprompt = \"p\"\noptions = [\"a\", \"b\"]\ncorrect = 3\n",
                "line 6: question 2: correct = 3",
            ),
            (
                "title = \"t\"\n[[question]]\nkind = \"text\"\nprompt = \"p\"\nanswer = 2\n",
                "question 1: answer is not a field of a question of kind \"text\"",
            ),
            (
                "title = \"t\"\n[[question]]\nkind = \"text\"\nprompt = \" \"\n",
                "question 1: prompt is empty",
            ),
            (
                "title = \"t\"\n[[question]]\nid = \"a\"\nkind = \"text\"\nprompt = \"p\"\n[[question]]\nid = \"a\"\nkind = \"text\"\nprompt = \"p\"\n",
                "line 6: question 2: the id \"a\"",
            ),
            (
                "title = \"t\"\n[[question]]\nkind = \"text\"\nprompt = \"p\"\nhint = \"h\"\n",
                "line 5",
            ),
            (
                "title = \"t\"\n[[question]]\nkind = \"number\"\nprompt = \"p\"\ntolerance = 1\n",
                "tolerance without an answer",
            ),
            (
                "title = \"t\"\n[[question]]\nid = \"Big\"\nkind = \"text\"\nprompt = \"p\"\n",
                "id \"Big\"",
            ),
            (
                "title = \"t\"\n[[question]]\nkind = \"table\"\nprompt = \"p\"\nrows = []\ncolumns = [\"c\"]\n",
                "rows: 0 given; give 1 to 30",
            ),
            ("title = \"t\n", "line 1"),
        ];
        for (text, expected) in cases {
            let error = read(text).unwrap_err();
            assert!(error.contains(expected), "{text:?}: {error}");
        }
    }

    #[test]
    fn typed_numbers() {
        for (typed, value) in [
            ("2", 2.0),
            (" -0.5 ", -0.5),
            ("1,5", 1.5),
            ("1.5e-3", 1.5e-3),
            ("1.5×10^-3", 1.5e-3),
            ("2 x 10^4", 2e4),
            ("+3E2", 300.0),
        ] {
            assert_eq!(parse_number(typed), Some(value), "{typed}");
        }
        for typed in ["", "two", "inf", "NaN", "1e999", "0x10", "1/2", "10^3"] {
            assert_eq!(parse_number(typed), None, "{typed}");
        }
    }

    /// The sets each exercise starts an assignment with read, and the answers they check
    /// against are the reference's.
    #[test]
    fn the_exercises_sets_read() {
        for &exercise in labs::Exercise::ALL {
            let sets = exercise.declaration().questions;
            assert!(!sets.is_empty(), "{exercise:?}");
            for text in sets {
                let set = read(text).unwrap_or_else(|e| panic!("{exercise:?}: {e}"));
                assert!(
                    set.questions.iter().all(|q| !q.model.trim().is_empty()),
                    "{}",
                    set.title
                );
            }
        }
        let [part1, part2] = labs::Exercise::EkfLocalization.declaration().questions else {
            panic!("the lab's two parts")
        };
        assert_eq!(read(part1).unwrap().questions.len(), 15);
        let part2 = read(part2).unwrap();
        let gate = part2
            .questions
            .iter()
            .find(|q| q.id == "gate-value")
            .unwrap();
        let reference = labs::ekf::lambda_m(0.999);
        assert_eq!(
            gate.check(&Answer::Number(format!("{reference:.2}"))),
            Some(true)
        );
        assert_eq!(
            gate.check(&Answer::Number(format!("{:.2}", reference + 0.02))),
            Some(false)
        );
    }

    /// The example set in the README reads, and means what it says.
    #[test]
    fn the_readmes_example_reads() {
        let readme = include_str!("../../../README.md");
        let section = &readme[readme.find("### The written questions").unwrap()..];
        let start = section.find("```toml\n").unwrap() + "```toml\n".len();
        let example = &section[start..start + section[start..].find("```").unwrap()];
        let set = read(example).unwrap();
        assert_eq!(set.questions.len(), 3);
        assert_eq!(set.questions[1].check(&Answer::Choice(1)), Some(true));
        assert_eq!(
            set.questions[0].check(&Answer::Number("13.81".into())),
            Some(true)
        );
    }

    proptest! {
        /// A number typed as Rust prints it is read back, and checked against itself.
        #[test]
        fn printed_numbers_read_back(n in -1e12..1e12f64) {
            prop_assert_eq!(parse_number(&n.to_string()), Some(n));
            prop_assert_eq!(parse_number(&format!("{n:e}")), Some(n));
        }
    }
}
