//! The `synthavision` command.
//!
//! Exit codes: 0 success; 1 problems found (`check`); 2 bad input (a
//! scene, deck or option with errors: nothing is written); 3 failure to
//! write output or another run-time error.
//!
//! Each subcommand lives in [`cmd`], a thin layer over the library crates;
//! the pieces they share are beside it: the options common to several
//! commands ([`args`]), loading the input ([`load`]), option values
//! ([`parse`]), the view and the worker threads ([`view`]) and the errors
//! ([`error`]).

#[macro_use]
mod term;
mod args;
mod cmd;
mod error;
mod load;
mod parse;
mod view;

use std::process::ExitCode;

fn main() -> ExitCode {
    match cmd::run() {
        Ok(code) => code,
        Err(error) => {
            error.print();
            error.exit_code()
        }
    }
}
