//! The subcommands, one file each: its options and a thin layer over the
//! library crates.

pub mod bench;
pub mod bodies;
pub mod check;
mod colour_by;
pub mod convert;
pub mod diff;
pub mod export;
pub mod film;
pub mod info;
pub mod regions;
pub mod render;
pub mod shell;
pub mod shoot;
pub mod slice;
pub mod studio;
pub mod volume;

use crate::args::{Cli, Command};
use crate::error::CliError;
use clap::FromArgMatches;
use std::process::ExitCode;

/// Parse the command line and run the command.
pub fn run() -> Result<ExitCode, CliError> {
    let matches = crate::args::definition().get_matches();
    let cli = Cli::from_arg_matches(&matches).unwrap_or_else(|error| error.exit());
    crate::term::set_quiet(cli.quiet);
    match cli.command {
        Command::Render(args) => render::render(args),
        Command::Info(args) => info::info(args),
        Command::Shoot(args) => shoot::shoot(args),
        Command::Bodies => bodies::bodies(),
        Command::Bench(args) => bench::bench(args),
        Command::Film(args) => film::film(args),
        Command::Convert(args) => convert::convert(args),
        Command::Check(args) => check::check(args),
        Command::Slice(args) => slice::slice(args),
        Command::Volume(args) => volume::volume(args),
        Command::Export(args) => export::export(args),
        Command::Regions(args) => regions::regions(args),
        Command::Completions(args) => shell::completions(args),
        Command::Man(args) => shell::man(args),
        Command::Studio(args) => studio::studio(args),
        Command::Diff(args) => diff::diff(args),
    }
}

/// A check that could not run, with a hint where one helps.
fn check_error(error: sv_check::CheckError) -> CliError {
    let hint = match &error {
        sv_check::CheckError::UnknownUniverse(_) => "; name a region or body of the deck",
        _ => "",
    };
    CliError::Input(format!("error: {error}{hint}"))
}

/// The file name beside `out` with `suffix` for its extension
/// (`a.png` → `a.legend.json`); `fallback` when `out` has no stem.
fn beside(out: &std::path::Path, suffix: &str, fallback: &str) -> std::path::PathBuf {
    let stem = out
        .file_stem()
        .map_or(fallback.into(), |s| s.to_string_lossy().into_owned());
    out.with_file_name(format!("{stem}.{suffix}"))
}
