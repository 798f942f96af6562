//! `estlab`: the estlab server and command line.

fn main() -> std::process::ExitCode {
    estlab::commands::main()
}
