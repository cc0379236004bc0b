//! `synthavision volume`: volume, centroid and mass of every region.

use crate::args::InputArgs;
use crate::cmd::{check_error, emit};
use crate::error::{bad_input, CliError};
use crate::load::load;
use crate::view::thread_pool;
use clap::Args;
use std::path::PathBuf;
use std::process::ExitCode;
use sv_check::{Model, UniverseChoice, VolumeOptions};

#[derive(Args, Debug)]
pub struct VolumeArgs {
    /// Scene, deck or FLUKA input.
    pub scene: PathBuf,
    /// Target relative (one sigma) error of every region's volume.
    #[arg(long, default_value_t = 0.001)]
    pub rel_error: f64,
    /// Stop after about this many rays.
    #[arg(long, default_value_t = 20_000_000)]
    pub max_rays: u64,
    /// Seed of the sampling.
    #[arg(long, default_value_t = 1971)]
    pub seed: u64,
    /// Print the report as JSON.
    #[arg(long)]
    pub json: bool,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    #[command(flatten)]
    pub input: InputArgs,
}

/// Run `volume`.
pub fn volume(args: VolumeArgs) -> Result<ExitCode, CliError> {
    if !(args.rel_error > 0.0 && args.rel_error < 1.0) {
        return Err(bad_input(format!(
            "--rel-error must lie between 0 and 1, found {}",
            args.rel_error
        )));
    }
    let scene = load(Some(&args.scene), &args.input)?.scene;
    let (model, warnings) = Model::new(&scene, &UniverseChoice::None).map_err(check_error)?;
    for warning in warnings {
        eprintln!("warning: {warning}");
    }
    let opts = VolumeOptions {
        rel_error: args.rel_error,
        max_rays: args.max_rays,
        seed: args.seed,
        ..Default::default()
    };
    let report = thread_pool(args.threads)?
        .install(|| sv_check::volumes(&model, &opts))
        .map_err(check_error)?;
    if args.json {
        emit(&format!("{}\n", report.to_json()));
    } else {
        emit(&report.to_table());
    }
    Ok(ExitCode::SUCCESS)
}
