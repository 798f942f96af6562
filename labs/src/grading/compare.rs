//! Comparison of a student function's output with the reference output, for every
//! exercise: numbers within an absolute and relative tolerance, indices and flags exactly,
//! headings modulo 2 pi (but only within a few turns of [-pi, pi), since far enough out the
//! modulo hides any answer), and angles that the contract says are wrapped checked to lie
//! in [-pi, pi). An exercise's contract gives each output its [`Shape`].

use crate::angle::difference;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use std::f64::consts::{PI, TAU};
use ts_rs::TS;

/// What one element of an output is, which decides how it is compared.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Number,
    /// A heading in a returned state or control: compared modulo 2 pi, and only when it is
    /// within [`HEADING_TURNS`] turns of [-pi, pi).
    Heading,
    /// A bearing the contract says is wrapped: must lie in [-pi, pi).
    Bearing,
    /// A 0-based landmark index: compared exactly.
    Index,
    /// `true` or `false`: compared exactly.
    Flag,
}

/// The shape of an output: scalars of a kind, arrays with a shape per element, objects.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    Scalar(Kind),
    Array(Vec<Shape>),
    Object(Vec<(&'static str, Shape)>),
    /// An n x n matrix the contract says is symmetrised: besides matching, it must be
    /// exactly symmetric, as (A + A^T) / 2 is in floating point.
    Symmetric(usize),
}

/// How far from [-pi, pi) a heading compared modulo 2 pi may be, in whole turns. The
/// original fixtures do not wrap headings, and a heading may grow by a turn in a step;
/// far out (1e300, say) the difference modulo 2 pi is exactly 0 for any answer.
pub const HEADING_TURNS: f64 = 2.0;

/// n numbers.
pub fn numbers(n: usize) -> Shape {
    Shape::Array(vec![Shape::Scalar(Kind::Number); n])
}

/// A rows x cols matrix, as an array of rows.
pub fn matrix(rows: usize, cols: usize) -> Shape {
    Shape::Array(vec![numbers(cols); rows])
}

/// n elements of one shape.
pub fn repeat(n: usize, shape: Shape) -> Shape {
    Shape::Array(vec![shape; n])
}

/// A pose or a control: x, y, then a heading.
pub fn pose() -> Shape {
    Shape::Array(vec![
        Shape::Scalar(Kind::Number),
        Shape::Scalar(Kind::Number),
        Shape::Scalar(Kind::Heading),
    ])
}

/// A range-bearing pair with the bearing wrapped.
pub fn range_bearing() -> Shape {
    Shape::Array(vec![
        Shape::Scalar(Kind::Number),
        Shape::Scalar(Kind::Bearing),
    ])
}

/// How close a number must be: |got - expected| <= absolute + relative |expected|.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Tolerance {
    pub absolute: f64,
    pub relative: f64,
}

impl Default for Tolerance {
    fn default() -> Self {
        Tolerance {
            absolute: 1e-9,
            relative: 1e-9,
        }
    }
}

impl Problem {
    /// What is wrong, in words to follow the expected and the returned value ("" when
    /// the two values say it).
    pub fn explanation(self) -> String {
        match self {
            Problem::Differs => String::new(),
            Problem::NotWrapped => " (not wrapped to [-pi, pi))".to_owned(),
            Problem::TooManyTurns => format!(
                " (more than {HEADING_TURNS} turns outside [-pi, pi), where a comparison modulo 2 pi means nothing: wrap it)"
            ),
            Problem::WrongShape => " (not the contract's shape)".to_owned(),
            Problem::NotSymmetric => " (its mirror image across the diagonal differs)".to_owned(),
        }
    }
}

/// Whether a heading lies within [`HEADING_TURNS`] turns of [-pi, pi), where comparing
/// it modulo 2 pi still means something.
pub fn heading_within_turns(heading: f64) -> bool {
    let turns = HEADING_TURNS * TAU;
    (-PI - turns..PI + turns).contains(&heading)
}

/// One element of an output that is not what it should be.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
pub struct Mismatch {
    /// Where: `sigma_bar[1][2]`, `c`, `nu[3][1]`.
    pub path: String,
    pub expected: Value,
    pub got: Value,
    pub problem: Problem,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, TS)]
#[serde(rename_all = "snake_case")]
pub enum Problem {
    /// Both are numbers (or indices, or flags) of the right kind, and they differ.
    Differs,
    /// A bearing outside [-pi, pi).
    NotWrapped,
    /// A heading more than [`HEADING_TURNS`] turns outside [-pi, pi): modulo 2 pi it
    /// would match anything.
    TooManyTurns,
    /// A value of the wrong type or an array of the wrong length, or a missing field.
    WrongShape,
    /// An element of a matrix that should be symmetric differs from its mirror image
    /// (`expected` holds the mirror image).
    NotSymmetric,
}

/// Every element of `got` that differs from `expected`, for an output of this shape.
pub fn compare(
    shape: &(&str, Shape),
    expected: &Value,
    got: &Value,
    tolerance: Tolerance,
) -> Vec<Mismatch> {
    let mut mismatches = Vec::new();
    walk(
        &shape.1,
        shape.0.to_owned(),
        expected,
        got,
        tolerance,
        &mut mismatches,
    );
    mismatches
}

fn walk(
    shape: &Shape,
    path: String,
    expected: &Value,
    got: &Value,
    tolerance: Tolerance,
    out: &mut Vec<Mismatch>,
) {
    let mut mismatch = |problem| {
        out.push(Mismatch {
            path: path.clone(),
            expected: expected.clone(),
            got: got.clone(),
            problem,
        })
    };
    match shape {
        Shape::Scalar(kind) => {
            if let Some(problem) = compare_scalar(*kind, expected, got, tolerance) {
                mismatch(problem);
            }
        }
        Shape::Array(elements) => match (expected.as_array(), got.as_array()) {
            (Some(e), Some(g)) if e.len() == elements.len() && g.len() == elements.len() => {
                for (i, ((shape, e), g)) in elements.iter().zip(e).zip(g).enumerate() {
                    walk(shape, format!("{path}[{i}]"), e, g, tolerance, out);
                }
            }
            _ => mismatch(Problem::WrongShape),
        },
        Shape::Symmetric(n) => {
            let before = out.len();
            walk(&matrix(*n, *n), path.clone(), expected, got, tolerance, out);
            let shaped = out[before..]
                .iter()
                .all(|m| m.problem != Problem::WrongShape);
            if shaped {
                for i in 0..*n {
                    for j in 0..i {
                        let (a, b) = (&got[i][j], &got[j][i]);
                        if a.as_f64() != b.as_f64() {
                            out.push(Mismatch {
                                path: format!("{path}[{i}][{j}]"),
                                expected: b.clone(),
                                got: a.clone(),
                                problem: Problem::NotSymmetric,
                            });
                        }
                    }
                }
            }
        }
        Shape::Object(fields) => match (expected.as_object(), got.as_object()) {
            (Some(e), Some(g)) => {
                for (name, shape) in fields {
                    let (e, g) = (&e[*name], g.get(*name).unwrap_or(&Value::Null));
                    let field_path = if path.is_empty() {
                        (*name).to_owned()
                    } else {
                        format!("{path}.{name}")
                    };
                    walk(shape, field_path, e, g, tolerance, out);
                }
            }
            _ => mismatch(Problem::WrongShape),
        },
    }
}

fn compare_scalar(
    kind: Kind,
    expected: &Value,
    got: &Value,
    tolerance: Tolerance,
) -> Option<Problem> {
    match kind {
        Kind::Index => match (expected.as_u64(), got.as_u64()) {
            (Some(e), Some(g)) => (e != g).then_some(Problem::Differs),
            _ => Some(Problem::WrongShape),
        },
        Kind::Flag => match (expected.as_bool(), got.as_bool()) {
            (Some(e), Some(g)) => (e != g).then_some(Problem::Differs),
            _ => Some(Problem::WrongShape),
        },
        Kind::Number | Kind::Heading | Kind::Bearing => {
            let (Some(e), Some(g)) = (expected.as_f64(), got.as_f64()) else {
                return Some(Problem::WrongShape);
            };
            if kind == Kind::Bearing && !(-PI..PI).contains(&g) {
                return Some(Problem::NotWrapped);
            }
            if kind == Kind::Heading && !heading_within_turns(g) {
                return Some(Problem::TooManyTurns);
            }
            let gap = if kind == Kind::Number {
                g - e
            } else {
                difference(g, e)
            };
            (gap.abs() > tolerance.absolute + tolerance.relative * e.abs())
                .then_some(Problem::Differs)
        }
    }
}
