//! The OpenMC reader against the benchmark models in ../shared/decks and
//! small models written in the tests.

mod boundaries;
mod decks;
mod diagnostics;
mod materials;
mod regions;
mod robustness;
mod surfaces;
mod universes;

use std::path::PathBuf;
use sv_formats::{openmc, Diagnostics, Loaded, SourceFile};
use sv_geom::{Fill, Lattice, LatticeKind, Op, Region, Zone};
use sv_math::DVec3;

/// The MCNP/OpenMC benchmark folder; `None` only when `SV_SKIP_SHARED=1`.
fn decks_dir() -> Option<PathBuf> {
    sv_testdata::shared_decks("mcnp-openmc")
}

/// Two materials for the models written in the tests.
const MATERIALS: &str = r#"<?xml version="1.0"?>
<materials>
  <material id="1" name="fuel">
    <density value="18.7" units="g/cm3"/>
    <nuclide name="U235" ao="0.93"/>
    <nuclide name="U238" ao="0.07"/>
  </material>
  <material id="2" name="water">
    <density units="sum"/>
    <nuclide name="H1" ao="0.0667"/>
    <nuclide name="O16" ao="0.0333"/>
  </material>
</materials>
"#;

/// Read a geometry written in a test, with [`MATERIALS`].
fn read(geometry: &str) -> Result<Loaded, Diagnostics> {
    openmc::read_with_materials(
        &SourceFile::new("geometry.xml", geometry),
        Some(&SourceFile::new("materials.xml", MATERIALS)),
    )
}

/// `<geometry>` around `body`, read; panics with the diagnostics on errors.
fn model(body: &str) -> Loaded {
    match read(&format!("<geometry>\n{body}\n</geometry>\n")) {
        Ok(l) => l,
        Err(d) => panic!("{}", d.render_plain()),
    }
}

/// (line, column, message) of every error of `<geometry>` around `body`.
fn errors(body: &str) -> Vec<(usize, usize, String)> {
    errors_of(read(&format!("<geometry>\n{body}\n</geometry>\n")))
}

fn errors_of(result: Result<Loaded, Diagnostics>) -> Vec<(usize, usize, String)> {
    match result {
        Ok(_) => panic!("expected errors"),
        Err(d) => crate::mutation::located(&d),
    }
}

/// Errors as (line, column, message) with borrowed messages, to compare
/// with a list written in a test.
fn by_place(e: &[(usize, usize, String)]) -> Vec<(usize, usize, &str)> {
    e.iter().map(|(l, c, m)| (*l, *c, m.as_str())).collect()
}

/// The region of cell `name`.
fn region<'a>(l: &'a Loaded, name: &str) -> &'a Region {
    let g = &l.scene.geometry;
    let index = g.region_index(name);
    &g.regions[index.unwrap_or_else(|| panic!("no cell {name}"))]
}

/// A region's expression with bodies named by surface id.
fn expression(l: &Loaded, name: &str) -> String {
    let bodies = &l.scene.geometry.bodies;
    region(l, name).expression(&|b| bodies[b].name.as_str())
}

fn lattice<'a>(l: &'a Loaded, name: &str) -> &'a Lattice {
    match &region(l, name).fill {
        Some(Fill::Lattice(lat)) => lat,
        other => panic!("cell {name} is filled with {other:?}"),
    }
}

fn close(a: DVec3, b: DVec3) -> bool {
    (a - b).length() < 1e-9 * (1.0 + b.length())
}

/// The cells found at `p`, from the root down through fills and lattices,
/// by ENGINE.md's rules evaluated in the test: in each universe the region
/// whose zones hold the point (body insides, zones and groups), then the
/// fill's universe at the point moved by the fill's transform, or the
/// lattice element's universe (the nearest centre of a hexagonal lattice).
/// The engine's own walk through the fills
/// ([`sv_trace::Prepared::regions_at`]) must find the same cells, the
/// engine's [`sv_trace::Prepared::region_contains`] the root cell, and no
/// two cells of a universe may hold the point.
fn cells_at(l: &Loaded, p: DVec3) -> Vec<String> {
    let g = &l.scene.geometry;
    let (prepared, _) = sv_trace::Prepared::new(g, &sv_trace::PrepareOptions::default())
        .unwrap_or_else(|e| panic!("the engine refuses the model: {e}"));
    let walked = walk(l, p);
    let mut engine: Vec<&str> = prepared
        .regions_at(p)
        .iter()
        .map(|r| g.regions[*r as usize].name.as_str())
        .collect();
    let mut ours: Vec<&str> = walked.iter().map(String::as_str).collect();
    engine.sort_unstable();
    ours.sort_unstable();
    assert_eq!(ours, engine, "the engine finds other cells at {p}");
    if let Some(root) = walked.first() {
        let index = g.region_index(root).expect("a cell of the model");
        assert!(prepared.region_contains(index, p));
    }
    walked
}

/// [`cells_at`] as the test walks the fills.
fn walk(l: &Loaded, p: DVec3) -> Vec<String> {
    let g = &l.scene.geometry;
    let shapes: Vec<_> = g
        .bodies
        .iter()
        .map(|b| {
            sv_geom::prepare(b, &mut Vec::new())
                .expect("body prepares")
                .0
        })
        .collect();
    let mut out = Vec::new();
    let (mut universe, mut point) = (0, p);
    for _ in 0..16 {
        let holding: Vec<&Region> = g
            .regions
            .iter()
            .filter(|r| {
                r.universe == universe && r.zones.iter().any(|z| in_zone(&shapes, z, point))
            })
            .collect();
        let r = match holding[..] {
            [] => break,
            [r] => r,
            _ => panic!("cells overlap at {point}"),
        };
        out.push(r.name.clone());
        match &r.fill {
            None => break,
            Some(Fill::Universe {
                universe: u,
                region_from_universe,
            }) => {
                universe = *u;
                point = region_from_universe.inverse().transform_point3(point);
            }
            Some(Fill::Lattice(lat)) => {
                let q = lat.region_from_lattice.inverse().transform_point3(point);
                let index = element_at(lat, q);
                let Some(u) = lat.element(index) else { break };
                let [a, b, c] = lat.steps;
                let moved = lat.origin
                    + a * f64::from(index[0])
                    + b * f64::from(index[1])
                    + c * f64::from(index[2]);
                universe = u;
                point = q - moved;
            }
        }
    }
    out
}

fn in_zone(shapes: &[sv_geom::shape::Shape], z: &Zone, p: DVec3) -> bool {
    z.terms
        .iter()
        .all(|t| shapes[t.body].contains(p) == (t.op == Op::Inside))
        && z.groups
            .iter()
            .all(|g| g.zones.iter().any(|inner| in_zone(shapes, inner, p)) == (g.op == Op::Inside))
}

/// The lattice element holding `q` (lattice coordinates).
fn element_at(lat: &Lattice, q: DVec3) -> [i32; 3] {
    let [a, b, c] = lat.steps;
    let m = sv_math::DMat3::from_cols(a, b, c);
    match lat.kind {
        LatticeKind::Rectangular => {
            let f = m.inverse() * (q - lat.base);
            [f.x.floor() as i32, f.y.floor() as i32, f.z.floor() as i32]
        }
        LatticeKind::Hexagonal => {
            let f = m.inverse() * (q - lat.base);
            let k = (f.z + 0.5).floor() as i32;
            let (i0, j0) = (f.x.round() as i32, f.y.round() as i32);
            let mut best = (f64::INFINITY, [i0, j0, k]);
            for di in -1..=1 {
                for dj in -1..=1 {
                    let (i, j) = (i0 + di, j0 + dj);
                    let centre = lat.base + a * f64::from(i) + b * f64::from(j);
                    let d = (q - centre).truncate().length();
                    if d < best.0 {
                        best = (d, [i, j, k]);
                    }
                }
            }
            best.1
        }
    }
}
