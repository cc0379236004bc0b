//! `synthavision convert`: a scene or deck as a v5 COMGEOM deck or in the
//! scene language.

use crate::args::InputArgs;
use crate::error::{bad_input, runtime, CliError};
use crate::load::load;
use clap::Args;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Args, Debug)]
pub struct ConvertArgs {
    /// Scene, deck or FLUKA, MCNP or OpenMC input (`-`: standard input).
    pub input: PathBuf,
    /// Output: `.cg` for a v5 COMGEOM deck, `.sv` for the scene language.
    #[arg(short, long)]
    pub output: PathBuf,
    #[command(flatten)]
    pub input_args: InputArgs,
}

/// Run `convert`: the output's extension chooses the format.
pub fn convert(args: ConvertArgs) -> Result<ExitCode, CliError> {
    let scene = load(Some(&args.input), &args.input_args)?.scene;
    let extension = args
        .output
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let text = match extension.as_deref() {
        Some("cg") => {
            let deck = sv_formats::comgeom::write(&scene).map_err(|e| bad_input(e.to_string()))?;
            for note in &deck.notes {
                noteln!("note: {note}");
            }
            deck.text
        }
        Some("sv") => sv_formats::native::write(&scene),
        _ => {
            return Err(bad_input(format!(
                "cannot tell the format of `{}`: use .cg or .sv",
                args.output.display()
            )))
        }
    };
    sv_output::write_atomic(&args.output, |w| w.write_all(text.as_bytes())).map_err(runtime)?;
    Ok(ExitCode::SUCCESS)
}
