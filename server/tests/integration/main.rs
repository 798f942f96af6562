//! The server's integration tests, one binary (each file a module, its tests named after
//! it: `cargo test -p estlab --test integration -- access::`): the real application in
//! this process, the `estlab` binary as a user runs it, and the sandbox's workers. One
//! binary links the server once, where a binary a file linked it thirty times.

mod command;
mod common;
mod student;

mod access;
mod challenge;
mod cli;
mod connections;
mod course_cli;
mod exercises;
mod exports;
mod extensions;
mod fusion_cli;
mod fusion_mistakes;
mod grade;
mod grade_class;
mod handin;
mod hostile_reports;
mod matlab;
mod mistakes;
mod mrclam_cli;
mod objects;
mod odometry_cli;
mod odometry_mistakes;
mod package;
mod python;
mod queue;
mod scores;
mod setup;
mod signin_limits;
mod staff;
mod ukf_particle_mistakes;
mod v8;
