//! `synthavision shoot`: every surface crossing along one ray.

use crate::args::InputArgs;
use crate::error::{bad_input, CliError};
use crate::load::load;
use crate::parse::parse_vec3;
use clap::Args;
use std::path::PathBuf;
use std::process::ExitCode;
use sv_math::Ray;
use sv_trace::Scratch;

#[derive(Args, Debug)]
pub struct ShootArgs {
    /// Scene, deck or FLUKA, MCNP or OpenMC input (`-`: standard input).
    pub scene: PathBuf,
    /// Ray origin X,Y,Z.
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub from: String,
    /// Ray direction DX,DY,DZ.
    #[arg(long, value_name = "DX,DY,DZ", allow_hyphen_values = true)]
    pub dir: String,
    #[command(flatten)]
    pub input: InputArgs,
}

/// Run `shoot`.
pub fn shoot(args: ShootArgs) -> Result<ExitCode, CliError> {
    let scene = load(Some(&args.scene), &args.input)?.scene;
    let from = parse_vec3(&args.from, "--from")?;
    let dir = parse_vec3(&args.dir, "--dir")?;
    if dir.length_squared() == 0.0 {
        return Err(bad_input("--dir must not be zero"));
    }
    let geometry = &scene.geometry;
    let (prepared, _) = sv_trace::Prepared::new(geometry, &Default::default())
        .map_err(|e| CliError::Input(format!("error: {e}")))?;
    let mut scratch = Scratch::new(&prepared);
    let region_name = |region: usize| geometry.regions[region].name.clone();
    let start: Vec<String> = (0..geometry.regions.len())
        .filter(|&region| prepared.region_contains(region, from))
        .map(region_name)
        .collect();
    let start = if start.is_empty() {
        "no region".into()
    } else {
        start.join(", ")
    };
    outln!("start ({}, {}, {}) in {start}", from.x, from.y, from.z);
    outln!(
        "{:>12}  {:<8} {:<10} {:<10} region after",
        "t",
        "",
        "body",
        "type"
    );
    for step in prepared.walk(&Ray::new(from, dir), 0.0, &mut scratch) {
        let body = &geometry.bodies[step.body as usize];
        let after = if step.regions_after.is_empty() {
            "(outside the geometry)".to_string()
        } else {
            let names: Vec<String> = step
                .regions_after
                .iter()
                .map(|r| region_name(*r as usize))
                .collect();
            let mut after = names.join(" + ");
            if step.regions_after.len() > 1 {
                after.push_str("  (overlap)");
            }
            after
        };
        outln!(
            "{:>12.6}  {:<8} {:<10} {:<10} {}",
            step.t,
            if step.entering { "enters" } else { "leaves" },
            body.name,
            body.kind.name(),
            after
        );
    }
    Ok(ExitCode::SUCCESS)
}
