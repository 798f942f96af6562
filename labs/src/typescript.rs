//! The browser's names for the types ts-rs cannot derive: those serialised by hand as one
//! of a known set of names.

use ts_rs::{Config, TS};

/// `"a" | "b" | ...`: a string that is one of `names`.
fn one_of<'a>(names: impl Iterator<Item = &'a str>) -> String {
    names
        .map(|name| format!("{name:?}"))
        .collect::<Vec<_>>()
        .join(" | ")
}

impl TS for crate::Exercise {
    type WithoutGenerics = Self;
    type OptionInnerType = Self;

    fn name(_: &Config) -> String {
        one_of(crate::Exercise::ALL.iter().map(|e| e.name()))
    }

    fn inline(cfg: &Config) -> String {
        <Self as TS>::name(cfg)
    }
}

impl TS for crate::grading::HintKind {
    type WithoutGenerics = Self;
    type OptionInnerType = Self;

    fn name(_: &Config) -> String {
        one_of(crate::grading::HintKind::every().iter().map(|k| k.name()))
    }

    fn inline(cfg: &Config) -> String {
        <Self as TS>::name(cfg)
    }
}
