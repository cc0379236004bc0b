//! `synthavision completions` and `synthavision man`: made from the same
//! argument definitions as the commands themselves.

use crate::error::{runtime, CliError};
use clap::Args;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Args, Debug)]
pub struct CompletionsArgs {
    /// The shell: bash, zsh, fish, elvish or powershell.
    pub shell: clap_complete::Shell,
}

#[derive(Args, Debug)]
pub struct ManArgs {
    /// Write synthavision.1 and a page per command
    /// (synthavision-render.1, …) into this folder instead.
    #[arg(long, value_name = "DIR")]
    pub dir: Option<PathBuf>,
}

/// Run `completions`.
pub fn completions(args: CompletionsArgs) -> Result<ExitCode, CliError> {
    let mut command = crate::args::definition();
    let mut script = Vec::new();
    clap_complete::generate(args.shell, &mut command, "synthavision", &mut script);
    crate::term::out_bytes(&script);
    Ok(ExitCode::SUCCESS)
}

/// Run `man`.
pub fn man(args: ManArgs) -> Result<ExitCode, CliError> {
    let command = crate::args::definition();
    match args.dir {
        None => {
            let mut page = Vec::new();
            clap_mangen::Man::new(command)
                .render(&mut page)
                .map_err(runtime)?;
            crate::term::out_bytes(&page);
        }
        Some(dir) => {
            std::fs::create_dir_all(&dir).map_err(runtime)?;
            clap_mangen::generate_to(command, &dir).map_err(runtime)?;
            noteln!("manual pages written to {}", dir.display());
        }
    }
    Ok(ExitCode::SUCCESS)
}
