//! `synthavision regions`: every region with what it is made of and where
//! it is.

use crate::args::InputArgs;
use crate::error::{bad_input, CliError};
use crate::load::load;
use crate::term::round;
use clap::Args;
use std::collections::BTreeSet;
use std::path::PathBuf;
use std::process::ExitCode;
use sv_geom::Zone;
use sv_math::Aabb;
use sv_scene::Scene;

#[derive(Args, Debug)]
pub struct RegionsArgs {
    /// Scene, deck or FLUKA, MCNP or OpenMC input (`-`: standard input).
    pub scene: PathBuf,
    /// Only the regions of this material (its code, or its name as the
    /// input gives it: `WATER`, `m12`).
    #[arg(long, value_name = "MATERIAL")]
    pub material: Option<String>,
    /// Only the regions whose name or description contains this text (any
    /// case).
    #[arg(long, value_name = "TEXT")]
    pub matching: Option<String>,
    /// Print the regions as JSON.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub input: InputArgs,
}

/// One region as listed.
struct Listed {
    number: usize,
    name: String,
    description: String,
    material: String,
    air: i64,
    bounds: Aabb,
    bodies: usize,
}

/// Run `regions`.
pub fn regions(args: RegionsArgs) -> Result<ExitCode, CliError> {
    let scene = load(Some(&args.scene), &args.input)?.scene;
    let (prepared, _) = sv_trace::Prepared::new(&scene.geometry, &Default::default())
        .map_err(|e| CliError::Input(format!("error: {e}")))?;
    let wanted = |listed: &Listed| {
        let material = args.material.as_deref().is_none_or(|m| {
            let region = &scene.regions[listed.number - 1];
            region.material.to_string() == m.trim()
                || region
                    .material_name
                    .as_deref()
                    .is_some_and(|name| name.eq_ignore_ascii_case(m.trim()))
        });
        let text = args.matching.as_deref().is_none_or(|text| {
            let text = text.to_lowercase();
            listed.name.to_lowercase().contains(&text)
                || listed.description.to_lowercase().contains(&text)
        });
        material && text
    };
    let listed: Vec<Listed> = (0..scene.geometry.regions.len())
        .map(|region| listing(&scene, region, prepared.region_bounds(region)))
        .filter(wanted)
        .collect();
    if listed.is_empty() && (args.material.is_some() || args.matching.is_some()) {
        return Err(bad_input("no region matches --material/--matching"));
    }
    if args.json {
        let regions: Vec<_> = listed.iter().map(json).collect();
        let text = serde_json::to_string_pretty(&regions).expect("regions serialise");
        outln!("{text}");
    } else {
        print_table(&listed, scene.units.abbrev());
    }
    Ok(ExitCode::SUCCESS)
}

/// Region `region` of `scene` as listed.
fn listing(scene: &Scene, region: usize, bounds: Aabb) -> Listed {
    let props = &scene.regions[region];
    let material = match &props.material_name {
        Some(name) => name.clone(),
        None => props.material.to_string(),
    };
    let mut bodies = BTreeSet::new();
    for zone in &scene.geometry.regions[region].zones {
        collect_bodies(zone, &mut bodies);
    }
    Listed {
        number: region + 1,
        name: scene.geometry.regions[region].name.clone(),
        description: props.description.clone(),
        material,
        air: props.air,
        bounds,
        bodies: bodies.len(),
    }
}

/// The bodies a zone names, its groups' included.
fn collect_bodies(zone: &Zone, bodies: &mut BTreeSet<usize>) {
    bodies.extend(zone.terms.iter().map(|term| term.body));
    for group in &zone.groups {
        for inner in &group.zones {
            collect_bodies(inner, bodies);
        }
    }
}

/// A region's bounds for people: rounded, `unbounded` or `empty`.
fn bounds_text(bounds: &Aabb) -> String {
    if bounds.is_empty() {
        "empty".into()
    } else if !bounds.is_finite() {
        "unbounded".into()
    } else {
        let (low, high) = (bounds.min, bounds.max);
        format!(
            "({}, {}, {}) to ({}, {}, {})",
            round(low.x),
            round(low.y),
            round(low.z),
            round(high.x),
            round(high.y),
            round(high.z)
        )
    }
}

/// The regions as a table on stdout.
fn print_table(listed: &[Listed], unit: &str) {
    outln!(
        "{:>5} {:<16} {:<12} {:>4} {:>6}  {:<28} bounds ({unit})",
        "#",
        "region",
        "material",
        "air",
        "bodies",
        "description"
    );
    for region in listed {
        outln!(
            "{:>5} {:<16} {:<12} {:>4} {:>6}  {:<28} {}",
            region.number,
            region.name,
            region.material,
            region.air,
            region.bodies,
            region.description,
            bounds_text(&region.bounds)
        );
    }
}

/// A region as JSON (bounds `null` when empty or unbounded).
fn json(region: &Listed) -> serde_json::Value {
    let bounds = (!region.bounds.is_empty() && region.bounds.is_finite())
        .then(|| [region.bounds.min.to_array(), region.bounds.max.to_array()]);
    serde_json::json!({
        "number": region.number,
        "name": region.name,
        "description": region.description,
        "material": region.material,
        "air": region.air,
        "bodies": region.bodies,
        "bounds": bounds,
    })
}
