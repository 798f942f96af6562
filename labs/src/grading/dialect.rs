//! The hints in the student's language. Every hint is written once, in the terms of the
//! contract's JavaScript (arrays of rows, objects with fields, `M[0][j]`, JavaScript's
//! `%`); a file in another language reads the same hints with those few phrases in its
//! own terms, as its starter states its conventions: each entry below is a phrase of the
//! texts and what the language says instead.

use super::result::GradeResult;
use crate::Language;

/// Python with NumPy: 2-D arrays indexed `[i, j]`, several outputs as a tuple or a dict,
/// a `%` that already takes the divisor's sign.
const PYTHON: &[(&str, &str)] = &[
    (
        "minding that JavaScript's % keeps the sign of its left operand",
        "which Python's % gives as it is (its result takes the sign of 2 pi)",
    ),
    (
        "indices are 0-based in JavaScript (landmark j is M[0][j], M[1][j], and c counts \
         from 0)",
        "indices are 0-based in Python (landmark j is M[0, j], M[1, j], and c counts from 0)",
    ),
    ("F_p[0][2] and F_p[1][2]", "F_p[0, 2] and F_p[1, 2]"),
    (" array of rows", " array"),
    ("an object with the fields", "a tuple or dict of"),
    ("The returned object has", "The returned dict has"),
    (
        "(an index past the end of an array?)",
        "(0 divided by 0, or an infinite noise?)",
    ),
];

/// MATLAB as the lab writes it: matrices indexed `(i, j)` from 1, vectors, several
/// outputs declared in order, `mod` taking the divisor's sign.
const MATLAB: &[(&str, &str)] = &[
    (
        "minding that JavaScript's % keeps the sign of its left operand",
        "with mod, whose result takes the sign of 2 pi (rem keeps the sign of its first \
         argument)",
    ),
    (
        "indices are 0-based in JavaScript (landmark j is M[0][j], M[1][j], and c counts \
         from 0), not 1-based as in MATLAB",
        "c is one more than the landmark's own index (landmark j is M(:, j), counting from \
         1 as the lab does)",
    ),
    ("F_p[0][2] and F_p[1][2]", "F_p(1, 3) and F_p(2, 3)"),
    ("theta = mu[2]", "theta = mu(3)"),
    ("u[2]", "u(3)"),
    (" array of rows", " matrix"),
    ("an array of", "a vector of"),
    ("an object with the fields", "the outputs"),
    ("NaN or Infinity", "NaN or Inf"),
    (
        "(an index past the end of an array?)",
        "(0 divided by 0, or an infinite noise?)",
    ),
    ("(A + A^T) / 2", "(A + A') / 2"),
];

fn phrases(language: Language) -> &'static [(&'static str, &'static str)] {
    match language {
        Language::JavaScript => &[],
        Language::Python => PYTHON,
        Language::Matlab => MATLAB,
    }
}

/// `text` in the terms of `language`.
pub fn in_language(text: &str, language: Language) -> String {
    phrases(language)
        .iter()
        .fold(text.to_owned(), |text, (from, to)| text.replace(from, to))
}

impl GradeResult {
    /// The result with its hints (and where the messages say them) in the terms of the
    /// student's `language`.
    pub fn in_language(mut self, language: Language) -> GradeResult {
        if language == Language::JavaScript {
            return self;
        }
        for test in &mut self.tests {
            for hint in test.failures.iter_mut().filter_map(|f| f.hint.as_mut()) {
                // The message says the hint: said anew there, and nothing else of it
                // (the student's own error, the harness's words) changed.
                let said = in_language(&hint.text, language);
                test.message = test.message.replace(&hint.text, &said);
                hint.text = said;
            }
        }
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grading::hints::{HintKind, describe};
    use serde_json::json;

    /// Every phrase a language replaces is said by some hint, or by the words of a
    /// shape: none is left over from a text since rewritten.
    #[test]
    fn every_phrase_is_said_by_a_hint() {
        let shapes = [
            json!([[1, 2], [3, 4]]),
            json!([1, 2, 3]),
            json!({"mu": 1, "sigma": 2}),
        ]
        .iter()
        .map(describe)
        .collect::<Vec<_>>()
        .join(" ");
        let texts: Vec<&str> = HintKind::every().iter().map(|kind| kind.text()).collect();
        let said = texts.join(" ") + " " + &shapes + " The returned object has";
        for language in [Language::Python, Language::Matlab] {
            for (from, _) in phrases(language) {
                assert!(
                    said.contains(from),
                    "{language}: {from:?} is said by no hint"
                );
            }
        }
    }

    #[test]
    fn a_hint_speaks_the_students_language() {
        let wrapped = "wrap it, minding that JavaScript's % keeps the sign of its left operand.";
        assert_eq!(in_language(wrapped, Language::JavaScript), wrapped);
        assert!(in_language(wrapped, Language::Python).contains("Python's %"));
        assert!(in_language(wrapped, Language::Matlab).contains("with mod"));
        let shape = "`F_p` should be a 3 x 3 array of rows, but is an array of 2 numbers.";
        assert_eq!(
            in_language(shape, Language::Matlab),
            "`F_p` should be a 3 x 3 matrix, but is a vector of 2 numbers."
        );
        assert_eq!(
            in_language(shape, Language::Python),
            "`F_p` should be a 3 x 3 array, but is an array of 2 numbers."
        );
    }
}
