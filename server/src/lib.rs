//! estlab's server and command line as a library: the binary (`main.rs`) parses the
//! command line and hands over to `commands`; the tests build the web application
//! in-process from the same modules (with a clock of their own).

pub mod clock;
pub mod commands;
pub mod courses;
pub mod datasets;
pub mod error;
pub mod grading;
pub mod platforms;
pub mod sandbox;
pub mod store;
pub mod web;
