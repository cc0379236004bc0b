//! `synthavision diff A B`: do two models of one experiment hold the same
//! materials in the same places? Exit 0 when they agree within the
//! tolerance, 1 when not.

use crate::args::InputArgs;
use crate::cmd::check::parse_box;
use crate::cmd::check_error;
use crate::error::{bad_input, runtime, CliError};
use crate::load::load;
use crate::view::thread_pool;
use clap::Args;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use sv_check::{DiffOptions, DiffSide, Model, UniverseChoice};
use sv_output::{write_image, ImageFormat, Pixels, WriteOptions};

#[derive(Args, Debug)]
pub struct DiffArgs {
    /// The first model (any readable format: MCNP, OpenMC, FLUKA, COMGEOM, .sv).
    pub a: PathBuf,
    /// The second model.
    pub b: PathBuf,
    /// Write a picture of where they differ (.png or .ppm): sections across
    /// x, y and z through the middle (top) and views along x, y and z
    /// adding up the disagreement (bottom).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Pixels on a side of each of the picture's six panels.
    #[arg(long, default_value_t = 320)]
    pub panel: u32,
    /// Pairs of materials that are the same whatever their compositions
    /// say: a file of lines `A-material B-material` (names or numbers,
    /// `#` comments).
    #[arg(long, value_name = "FILE")]
    pub map: Option<PathBuf>,
    /// Agree when the volume where they differ is at most this fraction of
    /// the volume holding material.
    #[arg(long, default_value_t = 1e-3)]
    pub tolerance: f64,
    /// Materials are the same when their atom fractions differ by at most
    /// this much in all.
    #[arg(long, default_value_t = 0.01)]
    pub composition_tolerance: f64,
    /// … and their atom densities by at most this relative amount.
    #[arg(long, default_value_t = 0.01)]
    pub density_tolerance: f64,
    /// Rays per side of each batch's grid, along each axis.
    #[arg(long, default_value_t = 64)]
    pub rays: u32,
    /// Batches (their spread gives the errors).
    #[arg(long, default_value_t = 8)]
    pub batches: u32,
    /// Compare inside this box instead of where the models' bounds overlap
    /// (needed when a model is unbounded).
    #[arg(
        long = "box",
        value_name = "X0,Y0,Z0,X1,Y1,Z1",
        allow_hyphen_values = true
    )]
    pub bounds: Option<String>,
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

/// The pairs of a `--map` file.
fn read_map(path: &Path) -> Result<Vec<(String, String)>, CliError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| bad_input(format!("cannot read {}: {e}", path.display())))?;
    let mut pairs = Vec::new();
    for (number, line) in text.lines().enumerate() {
        let content = line.split('#').next().unwrap_or("");
        let words: Vec<&str> = content.split_whitespace().collect();
        match words[..] {
            [] => {}
            [a, b] => pairs.push((a.to_string(), b.to_string())),
            _ => {
                return Err(bad_input(format!(
                    "{}:{}:1: expected two material names (A's, then B's), found `{}`\n  hint: write one pair per line, e.g. `m12 UO2`",
                    path.display(),
                    number + 1,
                    content.trim()
                )))
            }
        }
    }
    Ok(pairs)
}

fn check_fraction(name: &str, value: f64) -> Result<(), CliError> {
    if (0.0..1.0).contains(&value) {
        Ok(())
    } else {
        Err(bad_input(format!(
            "--{name} must lie in [0, 1), found {value}"
        )))
    }
}

/// Run `diff`.
pub fn diff(args: DiffArgs) -> Result<ExitCode, CliError> {
    check_fraction("tolerance", args.tolerance)?;
    check_fraction("composition-tolerance", args.composition_tolerance)?;
    check_fraction("density-tolerance", args.density_tolerance)?;
    let format = match &args.output {
        Some(out) => match ImageFormat::from_path(out) {
            Some(format @ (ImageFormat::Png | ImageFormat::Pnm)) => Some(format),
            _ => {
                return Err(bad_input(format!(
                    "cannot tell the picture format of `{}`: use .png or .ppm",
                    out.display()
                )))
            }
        },
        None => None,
    };
    let map = args.map.as_deref().map(read_map).transpose()?;
    let scenes = [
        load(Some(&args.a), &args.input)?.scene,
        load(Some(&args.b), &args.input)?.scene,
    ];
    let models = scenes
        .iter()
        .map(|scene| {
            let (model, warnings) =
                Model::new(scene, &UniverseChoice::None).map_err(check_error)?;
            for warning in warnings {
                errln!("warning: {warning}");
            }
            Ok(model)
        })
        .collect::<Result<Vec<Model>, CliError>>()?;
    let side = |i: usize| DiffSide {
        scene: &scenes[i],
        model: &models[i],
    };
    let opts = DiffOptions {
        rays_per_side: args.rays,
        batches: args.batches,
        seed: args.seed,
        tolerance: args.tolerance,
        composition_tolerance: args.composition_tolerance,
        density_tolerance: args.density_tolerance,
        map: map.unwrap_or_default(),
        region: args.bounds.as_deref().map(parse_box).transpose()?,
        ..DiffOptions::default()
    };
    let pool = thread_pool(args.threads)?;
    let report = pool
        .install(|| sv_check::diff(side(0), side(1), &opts))
        .map_err(check_error)?;
    if let (Some(out), Some(format)) = (&args.output, format) {
        let picture = pool
            .install(|| sv_check::diff_picture(side(0), side(1), &opts, args.panel))
            .map_err(check_error)?;
        let pixels = Pixels {
            width: picture.width,
            height: picture.height,
            rgb: &picture.rgb,
            alpha: None,
        };
        write_image(out, format, &pixels, &WriteOptions::default()).map_err(runtime)?;
        noteln!(
            "wrote {}: sections (top) and views (bottom) across x, y, z; magenta: different materials, orange: material only in A, cyan: only in B, red (views): rays that cross a difference",
            out.display()
        );
    }
    if args.json {
        outln!("{}", report.to_json());
    } else {
        out!(
            "A: {}\nB: {}\n{}",
            args.a.display(),
            args.b.display(),
            report.to_table()
        );
    }
    Ok(if report.agree {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}
