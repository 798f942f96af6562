//! Each exercise's contract is written once, in its `Call` enum: the starter file the
//! students get declares every function of it with the contract's arguments, named and
//! ordered as the call serialises them, which is the order the harness passes them in.

use labs::Exercise;
use labs::exercises::{Graded, Visit, odometry};
use labs::grading::{Case, Contract, Generator};
use serde::Deserialize;
use serde::de::{Deserializer, IgnoredAny, MapAccess, Visitor};
use std::fmt;

/// The names of a JSON object's fields, in the order of the text.
struct Fields(Vec<String>);

impl<'de> Deserialize<'de> for Fields {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct InOrder;
        impl<'de> Visitor<'de> for InOrder {
            type Value = Fields;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("an object")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Fields, A::Error> {
                let mut fields = Vec::new();
                while let Some((name, IgnoredAny)) = map.next_entry::<String, IgnoredAny>()? {
                    fields.push(name);
                }
                Ok(Fields(fields))
            }
        }
        deserializer.deserialize_map(InOrder)
    }
}

/// A call as it serialises: `{"function": ..., "args": {...}}`.
#[derive(Deserialize)]
struct Serialised {
    function: String,
    args: Fields,
}

/// Every `function name(a, b)` line of a file, as (name, parameters).
fn declarations(source: &str) -> Vec<(String, Vec<String>)> {
    source
        .lines()
        .filter_map(|line| line.strip_prefix("function "))
        .filter_map(|rest| {
            let (name, rest) = rest.split_once('(')?;
            let (parameters, _) = rest.split_once(')')?;
            Some((
                name.trim().to_owned(),
                parameters
                    .split(',')
                    .map(|p| p.trim().to_owned())
                    .filter(|p| !p.is_empty())
                    .collect(),
            ))
        })
        .collect()
}

fn check<C: Contract>(generate: Generator<C>, starter: &str) {
    let declared = declarations(starter);
    for &function in C::FUNCTIONS {
        let cases: Vec<Case<C>> = generate(1, 2);
        let case = cases
            .iter()
            .find(|case| case.call.function() == function)
            .unwrap_or_else(|| panic!("{}: no case of {function}", C::EXERCISE));
        let serialised: Serialised =
            serde_json::from_str(&serde_json::to_string(&case.call).unwrap()).unwrap();
        assert_eq!(serialised.function, function);
        let parameters = declared
            .iter()
            .find(|(name, _)| name == function)
            .map(|(_, parameters)| parameters)
            .unwrap_or_else(|| panic!("{}'s starter does not declare {function}", C::EXERCISE));
        // The harness gets the call's fields in the order they serialise
        // (`Contract::arguments`): the starter's parameters must be those, in that order.
        assert_eq!(
            parameters,
            &serialised.args.0,
            "{}: {function}'s parameters in the starter",
            C::EXERCISE
        );
    }
}

/// An exercise's starter file checked against its contract.
struct Starter;

impl Visit for Starter {
    type Output = ();
    fn visit<G: Graded>(self) {
        check(G::GENERATE, G::DECLARATION.starters.javascript);
    }
}

#[test]
fn the_starters_declare_the_contracts() {
    for exercise in Exercise::ALL {
        exercise.visit(Starter);
    }
}

#[test]
fn a_starter_that_renames_a_parameter_is_caught() {
    let starter = odometry::Odometry::DECLARATION.starters.javascript.replace(
        "function wheel_noise(ds_r, ds_l, k_r, k_l)",
        "function wheel_noise(ds_r, ds_l, k_l, k_r)",
    );
    let caught = std::panic::catch_unwind(|| check(odometry::generate, &starter));
    assert!(caught.is_err());
}
