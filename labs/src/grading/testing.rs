//! What the tests of every exercise's hints share: the hint a case's output gets, and the
//! check that each classic mistake gets its own hint in the generated cases.

use super::compare::{Mismatch, Tolerance, compare};
use super::contract::{Case, Contract};
use super::hints::{HintKind, Mistake};
use super::suite::{CASES_PER_FUNCTION, Generator};
use serde_json::Value;

/// The hint the grader gives `got` as the output of `case`, if any.
pub fn diagnosed<C: Contract>(case: &Case<C>, got: &Value) -> Option<HintKind> {
    let mismatches = case.check(got, Tolerance::default());
    let expected = case.call.reference().unwrap();
    case.call
        .diagnose(&expected, got, &mismatches)
        .map(|hint| hint.kind)
}

/// Whether `a` and `b` are one output of the case's call, within the default tolerance.
pub fn same<C: Contract>(case: &Case<C>, a: &Value, b: &Value) -> bool {
    compare(&case.call.output_shape(), a, b, Tolerance::default()).is_empty()
}

/// What each classic mistake makes of a call's answer, as an exercise's hints work it out.
pub type Mistakes<C> =
    fn(&C, &<C as Contract>::Answer) -> Vec<(<C as Contract>::Mistake, <C as Contract>::Answer)>;

/// In the cases of every seed of `seeds`, as many of each function as a variant has: a
/// right answer gets no hint; every mistake made in a case (each answer of `mistakes` that
/// is not the right one) gets its own hint, unless another mistake gives the same answer
/// there, or `rivalled` says another mistake explains its mismatches (then none); and each
/// of `shown_in_every_seed` gets its own hint in some case of every seed.
pub fn each_mistake_gets_its_hint<C: Contract>(
    generate: Generator<C>,
    seeds: impl IntoIterator<Item = u64>,
    mistakes: Mistakes<C>,
    rivalled: impl Fn(&C, &[Mismatch], HintKind) -> bool,
    shown_in_every_seed: &[C::Mistake],
) {
    for seed in seeds {
        let mut recognised = Vec::new();
        for case in generate(seed, CASES_PER_FUNCTION) {
            let at = format!("seed {seed}, {} ({})", case.id, case.note);
            assert_eq!(diagnosed(&case, &case.expected), None, "{at}");
            let variants: Vec<(HintKind, Value)> =
                mistakes(&case.call, &case.call.reference().unwrap())
                    .into_iter()
                    .map(|(kind, answer)| (kind.kind(), serde_json::to_value(answer).unwrap()))
                    .collect();
            for (kind, wrong) in &variants {
                if same(&case, &case.expected, wrong) {
                    continue;
                }
                let mismatches = case.check(wrong, Tolerance::default());
                let rivalled = variants
                    .iter()
                    .any(|(other, answer)| other != kind && same(&case, answer, wrong))
                    || rivalled(&case.call, &mismatches, *kind);
                assert_eq!(
                    diagnosed(&case, wrong),
                    (!rivalled).then_some(*kind),
                    "{at}: {}",
                    kind.name()
                );
                if !rivalled {
                    recognised.push(*kind);
                }
            }
        }
        for kind in shown_in_every_seed.iter().map(|m| m.kind()) {
            assert!(
                recognised.contains(&kind),
                "seed {seed}: {} gets its hint in no case",
                kind.name()
            );
        }
    }
}
