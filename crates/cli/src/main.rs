//! The `synthavision` command.
//!
//! Exit codes: 0 success; 1 problems found (`check`); 2 bad input (a
//! scene, deck or option with errors: nothing is written); 3 failure to
//! write output or another run-time error.

mod args;
mod check_cmd;
mod commands;
mod export_cmd;
mod film_cmd;
mod load;

use std::process::ExitCode;

fn main() -> ExitCode {
    match commands::run() {
        Ok(code) => code,
        Err(e) => {
            e.print();
            e.exit_code()
        }
    }
}
