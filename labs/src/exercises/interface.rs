//! An exercise's student functions as the harness of a native language needs them (Python,
//! MATLAB): their arguments and outputs by name, what each output is (its rank, whether it
//! holds indices, flags or headings), and where the lab's MATLAB files differ from the
//! contract. The harness in JavaScript checks every answer as it checks a JavaScript
//! function's; a native harness only carries values across, in its language's shapes.

use super::starter::{Signature, signatures};
use super::{Exercise, Graded, Visit};
use crate::grading::{Contract, Kind, Shape};
use serde::Serialize;

/// Where the lab's MATLAB functions differ from the contract (`../shared/data/README.md`
/// lists the lab's own), which the MATLAB harness converts both ways so that a student's
/// lab files grade as they are.
#[derive(Debug)]
pub struct MatlabConventions {
    /// Arguments that are landmark indices, 1-based in MATLAB: (function, argument).
    pub index_arguments: &'static [(&'static str, &'static str)],
    /// Outputs that list one item per landmark, which MATLAB lays along the last
    /// dimension (`nu` 2 x N, `S` 2 x 2 x N for the contract's N x 2, N x 2 x 2):
    /// (function, output).
    pub stacked_outputs: &'static [(&'static str, &'static str)],
    /// Arguments that some editions of the lab keep in global variables instead, by the
    /// global's name: (argument, global). A function declared with fewer arguments than
    /// the contract's gets these as globals, and the others in order.
    pub globals: &'static [(&'static str, &'static str)],
    /// Arguments the lab declares after the contract's, and the value the harness passes
    /// when a function declares them: (function, value).
    pub trailing: &'static [(&'static str, f64)],
}

impl MatlabConventions {
    /// An exercise whose MATLAB functions follow the contract but for MATLAB's own shapes
    /// (column vectors, matrices as they are).
    pub const NONE: MatlabConventions = MatlabConventions {
        index_arguments: &[],
        stacked_outputs: &[],
        globals: &[],
        trailing: &[],
    };
}

/// One student function, as a native harness calls it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Function {
    pub name: &'static str,
    pub arguments: Vec<Argument>,
    /// What it returns: one value, or the contract's named fields in order.
    pub outputs: Vec<Output>,
    /// The value of the argument the lab declares after the contract's, if any.
    pub trailing: Option<f64>,
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Argument {
    pub name: &'static str,
    /// A 0-based index in the contract, 1-based in MATLAB.
    pub index: bool,
    /// The global variable some editions of the lab read it from.
    pub global_variable: Option<&'static str>,
}

/// One returned value, and what the contract makes of it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Output {
    pub name: &'static str,
    /// Its dimensions in the contract: 0 a number, 1 a vector, 2 a matrix (or a list of
    /// vectors), 3 a list of matrices; `None` where the contract's cases do not tell (the
    /// settings `init` returns), and the value is carried as it comes.
    pub rank: Option<usize>,
    /// Its numbers are 0-based indices (1-based in MATLAB).
    pub index: bool,
    /// Its numbers are flags (`true`, `false`; MATLAB's 0 and 1 too).
    pub flag: bool,
    /// The positions, in a vector, of headings, which the contract compares modulo 2 pi
    /// and MATLAB's lab does not wrap: the MATLAB harness wraps them.
    pub headings: Vec<usize>,
    /// MATLAB lays its items along the last dimension (see
    /// [`MatlabConventions::stacked_outputs`]).
    pub stacked: bool,
}

impl Exercise {
    /// Every student function the exercise's template declares, as a native harness
    /// calls it.
    pub fn interface(self) -> Vec<Function> {
        self.visit(Interface)
    }
}

struct Interface;

impl Visit for Interface {
    type Output = Vec<Function>;
    fn visit<G: Graded>(self) -> Vec<Function> {
        let declaration = &G::DECLARATION;
        let shapes: Vec<(&'static str, Shape)> = (G::GENERATE)(0, 1)
            .iter()
            .map(|case| (case.call.function(), case.call.output_shape().1))
            .collect();
        signatures(declaration.starter_template)
            .into_iter()
            .map(|signature| {
                let shape = shapes
                    .iter()
                    .find(|(name, _)| *name == signature.name)
                    .map(|(_, shape)| shape);
                function(signature, shape, &declaration.matlab)
            })
            .collect()
    }
}

fn function(signature: Signature, shape: Option<&Shape>, matlab: &MatlabConventions) -> Function {
    let name = signature.name;
    let arguments = signature
        .arguments
        .iter()
        .map(|&argument| Argument {
            name: argument,
            index: matlab.index_arguments.contains(&(name, argument)),
            global_variable: matlab
                .globals
                .iter()
                .find(|(given, _)| *given == argument)
                .map(|&(_, global)| global),
        })
        .collect();
    let described = |output: &'static str, shape: Option<&Shape>| {
        let mut described = shape.map_or_else(|| Output::unknown(output), Output::of);
        described.name = output;
        described.stacked = matlab.stacked_outputs.contains(&(name, output));
        described
    };
    let outputs = match (shape, signature.outputs.as_slice()) {
        (Some(Shape::Object(fields)), _) => fields
            .iter()
            .map(|(field, shape)| described(field, Some(shape)))
            .collect(),
        (shape, names) => names
            .iter()
            .map(|&output| described(output, shape))
            .collect(),
    };
    Function {
        name,
        arguments,
        outputs,
        trailing: matlab
            .trailing
            .iter()
            .find(|(function, _)| *function == name)
            .map(|&(_, value)| value),
    }
}

impl Output {
    fn unknown(name: &'static str) -> Output {
        Output {
            name,
            rank: None,
            index: false,
            flag: false,
            headings: Vec::new(),
            stacked: false,
        }
    }

    /// What a value of `shape` is.
    fn of(shape: &Shape) -> Output {
        let mut kinds = Vec::new();
        let rank = rank(shape, &mut kinds);
        let all = |kind: Kind| !kinds.is_empty() && kinds.iter().all(|&k| k == kind);
        let headings = match shape {
            Shape::Array(items) => items
                .iter()
                .enumerate()
                .filter(|(_, item)| **item == Shape::Scalar(Kind::Heading))
                .map(|(at, _)| at)
                .collect(),
            _ => Vec::new(),
        };
        Output {
            name: "",
            rank,
            index: all(Kind::Index),
            flag: all(Kind::Flag),
            headings,
            stacked: false,
        }
    }
}

/// The dimensions of a value of `shape` (`None` for an empty list, whose items do not
/// tell), gathering the kinds of its numbers.
fn rank(shape: &Shape, kinds: &mut Vec<Kind>) -> Option<usize> {
    match shape {
        Shape::Scalar(kind) => {
            kinds.push(*kind);
            Some(0)
        }
        Shape::Symmetric(_) => {
            kinds.push(Kind::Number);
            Some(2)
        }
        Shape::Array(items) => {
            let ranks: Vec<Option<usize>> = items.iter().map(|item| rank(item, kinds)).collect();
            Some(1 + ranks.first().copied().flatten()?)
        }
        Shape::Object(_) => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn find(exercise: Exercise, name: &str) -> Function {
        exercise
            .interface()
            .into_iter()
            .find(|function| function.name == name)
            .unwrap()
    }

    #[test]
    fn the_ekf_interface_carries_the_labs_matlab_conventions() {
        let associate = find(Exercise::EkfLocalization, "associate");
        let outputs: Vec<(&str, Option<usize>, bool, bool, bool)> = associate
            .outputs
            .iter()
            .map(|o| (o.name, o.rank, o.index, o.flag, o.stacked))
            .collect();
        assert_eq!(
            outputs,
            [
                ("c", Some(0), true, false, false),
                ("outlier", Some(0), false, true, false),
                ("nu", Some(2), false, false, true),
                ("S", Some(3), false, false, true),
                ("H", Some(3), false, false, true),
            ]
        );
        let m = associate.arguments.iter().find(|a| a.name == "M").unwrap();
        assert_eq!(m.global_variable, Some("map"));

        let observation = find(Exercise::EkfLocalization, "observation_model");
        assert!(observation.arguments[2].index);
        assert_eq!(observation.outputs[0].rank, Some(1));

        let jacobian = find(Exercise::EkfLocalization, "jacobian_observation_model");
        assert_eq!(jacobian.trailing, Some(1.0));

        let predict = find(Exercise::EkfLocalization, "predict");
        assert_eq!(predict.outputs[0].headings, [2]);

        let batch = find(Exercise::EkfLocalization, "batch_associate");
        assert_eq!(
            (batch.outputs[0].rank, batch.outputs[0].index),
            (Some(1), true)
        );
        assert_eq!(
            (batch.outputs[1].rank, batch.outputs[1].flag),
            (Some(1), true)
        );

        let init = find(Exercise::EkfLocalization, "init");
        let names: Vec<&str> = init.outputs.iter().map(|o| o.name).collect();
        assert_eq!(names, ["mu", "sigma", "R", "Q", "Lambda_M"]);
        assert!(init.outputs.iter().all(|o| o.rank.is_none()));
    }

    #[test]
    fn other_exercises_use_matlabs_own_shapes_only() {
        for exercise in [Exercise::Odometry, Exercise::SensorFusion] {
            for function in exercise.interface() {
                assert!(function.trailing.is_none());
                assert!(
                    function
                        .arguments
                        .iter()
                        .all(|a| !a.index && a.global_variable.is_none())
                );
                assert!(function.outputs.iter().all(|o| !o.stacked && !o.index));
            }
        }
        let step = find(Exercise::Odometry, "odometry_step");
        assert_eq!(step.outputs[0].rank, Some(1));
        let jacobian = find(Exercise::Odometry, "pose_jacobian");
        assert_eq!(jacobian.outputs[0].rank, Some(2));
    }
}
