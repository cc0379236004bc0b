//! `synthavision volume`: volume, centroid and mass of every region.

use crate::args::InputArgs;
use crate::cmd::check_error;
use crate::error::{bad_input, CliError};
use crate::load::load;
use crate::view::thread_pool;
use clap::Args;
use std::path::PathBuf;
use std::process::ExitCode;
use sv_check::{Model, UniverseChoice, VolumeOptions};

#[derive(Args, Debug)]
pub struct VolumeArgs {
    /// Scene, deck or FLUKA, MCNP or OpenMC input (`-`: standard input).
    pub scene: PathBuf,
    /// Target relative (one sigma) error of every region's volume.
    #[arg(long, default_value_t = 0.001, value_parser = crate::parse::positive, allow_hyphen_values = true)]
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
    #[arg(long, value_parser = crate::parse::threads)]
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
    let opts = VolumeOptions {
        rel_error: args.rel_error,
        max_rays: args.max_rays,
        seed: args.seed,
        ..Default::default()
    };
    if opts.max_rays < opts.min_rays() {
        return Err(bad_input(format!(
            "--max-rays {} is too few to estimate any volume: give at least {}",
            opts.max_rays,
            opts.min_rays()
        )));
    }
    let scene = load(Some(&args.scene), &args.input)?.scene;
    // Warnings about bodies were reported, located, by the reader.
    let (model, _) = Model::new(&scene, &UniverseChoice::None).map_err(volume_error)?;
    let spinner = crate::term::Spinner::start("measuring volumes");
    let report = thread_pool(args.threads)?
        .install(|| sv_check::volumes(&model, &opts))
        .map_err(volume_error)?;
    drop(spinner);
    if args.json {
        outln!("{}", report.to_json());
    } else {
        out!("{}", report.to_table());
    }
    Ok(ExitCode::SUCCESS)
}

/// A measurement that could not run; `volume` has no box to give, so the
/// hint of `check` and `slice` does not apply.
fn volume_error(error: sv_check::CheckError) -> CliError {
    match error {
        sv_check::CheckError::Unbounded => bad_input(
            "the model has no finite region, so no volume can be measured \
             (a deck whose every region is infinite, such as a lone half-space)",
        ),
        other => check_error(other),
    }
}
