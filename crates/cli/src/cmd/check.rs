//! `synthavision check`: overlaps and voids, with an exit status for
//! pipelines (1 when any are found).

use crate::args::{InputArgs, UniverseArgs};
use crate::cmd::check_error;
use crate::error::{bad_input, CliError};
use crate::load::load;
use crate::parse::parse_numbers;
use crate::view::thread_pool;
use clap::Args;
use std::path::PathBuf;
use std::process::ExitCode;
use sv_check::{CheckOptions, Model, UniverseChoice};
use sv_math::{Aabb, DVec3};
use sv_scene::Scene;

#[derive(Args, Debug)]
pub struct CheckArgs {
    /// Scene, deck or FLUKA, MCNP or OpenMC input (`-`: standard input).
    pub scene: PathBuf,
    /// Distance between grid rays (model units; default: about 120 000
    /// rays in all, as a cube with 200 rays per side).
    #[arg(long, value_name = "D", value_parser = crate::parse::positive, allow_hyphen_values = true)]
    pub spacing: Option<f64>,
    /// Add rays between neighbouring grid rays that see different
    /// regions, by halving, down to this distance apart (model units), so
    /// that slivers at the edges of parts thinner than the spacing are
    /// found (default: a sixteenth of the spacing).
    #[arg(long, value_name = "D", value_parser = crate::parse::positive, allow_hyphen_values = true, conflicts_with = "no_refine")]
    pub refine_to: Option<f64>,
    /// Fire the grids only, without refinement.
    #[arg(long)]
    pub no_refine: bool,
    /// Extra rays in random directions.
    #[arg(long, value_name = "N", default_value_t = 0)]
    pub random: u64,
    /// Fire the rays through this box instead of the model's bounds (look
    /// closely at a part; needed when no region is finite).
    #[arg(
        long = "box",
        value_name = "X0,Y0,Z0,X1,Y1,Z1",
        allow_hyphen_values = true
    )]
    pub bounds: Option<String>,
    /// Seed of the random rays.
    #[arg(long, default_value_t = 1971)]
    pub seed: u64,
    /// Print the report as JSON.
    #[arg(long)]
    pub json: bool,
    /// Count overlaps with air regions (non-zero air code) as problems too
    /// (always so for FLUKA and MCNP inputs).
    #[arg(long)]
    pub strict_air: bool,
    /// Exit 0 on a clean report even when some regions were met by no ray
    /// (by default such a check is incomplete and exits 1).
    #[arg(long)]
    pub allow_unsampled: bool,
    #[command(flatten)]
    pub check: UniverseArgs,
    #[command(flatten)]
    pub input: InputArgs,
}

/// The model to check with `--universe`/`--no-universe`, after checking
/// `--tolerance`.
pub fn model(scene: &Scene, universe: &UniverseArgs) -> Result<Model, CliError> {
    let choice = match (&universe.universe, universe.no_universe) {
        (_, true) => UniverseChoice::None,
        (Some(name), false) => UniverseChoice::Named(name.clone()),
        (None, false) => UniverseChoice::Auto,
    };
    if let Some(tolerance) = universe.tolerance {
        if !(tolerance >= 0.0 && tolerance.is_finite()) {
            return Err(bad_input(format!(
                "--tolerance must be zero or more, found {tolerance}"
            )));
        }
    }
    // Warnings about bodies were reported, located, by the reader.
    let (model, _) = Model::new(scene, &choice).map_err(check_error)?;
    Ok(model)
}

/// Run `check`.
pub fn check(args: CheckArgs) -> Result<ExitCode, CliError> {
    let input = load(Some(&args.scene), &args.input)?;
    let model = model(&input.scene, &args.check)?;
    if let Some(spacing) = args.spacing {
        if !(spacing > 0.0 && spacing.is_finite()) {
            return Err(bad_input(format!(
                "--spacing must be positive, found {spacing}"
            )));
        }
    }
    let bounds = args.bounds.as_deref().map(parse_box).transpose()?;
    let opts = CheckOptions {
        bounds,
        spacing: args.spacing,
        tolerance: args.check.tolerance,
        random: args.random,
        seed: args.seed,
        strict_air: args.strict_air || input.strict_air(),
        refine: if args.no_refine {
            0
        } else {
            CheckOptions::default().refine
        },
        refine_to: args.refine_to,
        ..Default::default()
    };
    let spinner = crate::term::Spinner::start("checking for overlaps and voids");
    let report = thread_pool(args.check.threads)?
        .install(|| sv_check::check(&model, &opts))
        .map_err(check_error)?;
    drop(spinner);
    if args.json {
        outln!("{}", report.to_json());
    } else {
        out!("{}", report.to_table());
    }
    Ok(
        if report.is_clean() && (report.met_every_region() || args.allow_unsampled) {
            ExitCode::SUCCESS
        } else {
            ExitCode::from(1)
        },
    )
}

/// `--box X0,Y0,Z0,X1,Y1,Z1`.
pub(crate) fn parse_box(text: &str) -> Result<Aabb, CliError> {
    let bad = || {
        bad_input(format!(
            "--box: expected six numbers X0,Y0,Z0,X1,Y1,Z1 with X0 < X1, Y0 < Y1, Z0 < Z1, found `{text}`"
        ))
    };
    let numbers = parse_numbers(text).ok_or_else(bad)?;
    match numbers[..] {
        [x0, y0, z0, x1, y1, z1]
            if numbers.iter().all(|x| x.is_finite()) && x0 < x1 && y0 < y1 && z0 < z1 =>
        {
            Ok(Aabb::new(DVec3::new(x0, y0, z0), DVec3::new(x1, y1, z1)))
        }
        _ => Err(bad()),
    }
}
