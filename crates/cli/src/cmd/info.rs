//! `synthavision info`: what a scene or deck holds.

use crate::args::InputArgs;
use crate::error::CliError;
use crate::load::load;
use clap::Args;
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::process::ExitCode;
use sv_scene::Scene;

#[derive(Args, Debug)]
pub struct InfoArgs {
    /// Scene, deck or FLUKA, MCNP or OpenMC input (`-`: standard input).
    pub scene: PathBuf,
    #[command(flatten)]
    pub input: InputArgs,
}

/// Run `info`.
pub fn info(args: InfoArgs) -> Result<ExitCode, CliError> {
    let scene = load(Some(&args.scene), &args.input)?.scene;
    let geometry = &scene.geometry;
    if scene.title.is_empty() {
        outln!("{}", args.scene.display());
    } else {
        outln!("{}", scene.title);
    }
    outln!("units: {}", scene.units.abbrev());
    let mut bodies_by_type: BTreeMap<&str, usize> = BTreeMap::new();
    for body in &geometry.bodies {
        *bodies_by_type.entry(body.kind.name()).or_default() += 1;
    }
    outln!("bodies: {}", geometry.bodies.len());
    for (kind, count) in &bodies_by_type {
        outln!("  {kind:<5} {count}");
    }
    let transparent = scene.regions.iter().filter(|p| p.transparent).count();
    let zones: usize = geometry.regions.iter().map(|r| r.zones.len()).sum();
    outln!(
        "regions: {} ({} zones; {} transparent)",
        geometry.regions.len(),
        zones,
        transparent
    );
    // Warnings about bodies were reported, located, by the reader.
    let (prepared, _) = sv_trace::Prepared::new(geometry, &Default::default())
        .map_err(|e| CliError::Input(format!("error: {e}")))?;
    let bounds = prepared.bounds();
    if bounds.is_empty() {
        outln!("bounds: empty");
    } else {
        let (lower, upper) = (bounds.min, bounds.max);
        outln!(
            "bounds: ({:.4}, {:.4}, {:.4}) to ({:.4}, {:.4}, {:.4})",
            lower.x,
            lower.y,
            lower.z,
            upper.x,
            upper.y,
            upper.z
        );
    }
    print_materials(&scene);
    for note in &scene.notes {
        outln!("note: {note}");
    }
    Ok(ExitCode::SUCCESS)
}

/// Regions by material (`material×count`), and the count of air regions.
fn print_materials(scene: &Scene) {
    let mut regions_by_material: BTreeMap<i64, usize> = BTreeMap::new();
    let mut air = 0;
    for region in &scene.regions {
        *regions_by_material.entry(region.material).or_default() += 1;
        air += usize::from(region.air != 0);
    }
    let materials: Vec<String> = regions_by_material
        .iter()
        .map(|(material, count)| format!("{material}×{count}"))
        .collect();
    outln!("materials: {}", materials.join(" "));
    outln!("air regions: {air}");
}
