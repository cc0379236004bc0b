//! FLUKA inputs through the tracer: regions with groups as written, and
//! lattice cells filled with the prototype.

use super::*;
use sv_render::{Renderer, Settings};
use sv_scene::{Camera, Lens};
use sv_trace::{PrepareOptions, Prepared};

/// A field input, read.
fn field(name: &str) -> Option<Loaded> {
    let dir = sv_testdata::shared_decks("fluka/field")?;
    Some(read_path(&dir.join(name)).unwrap_or_else(|d| panic!("{}", d.render_plain())))
}

#[test]
fn the_tokamaks_groups_are_traced_as_written() {
    let Some(l) = field("tt1_runaway.inp") else {
        return;
    };
    let g = &l.scene.geometry;
    let (p, _) = Prepared::new(g, &PrepareOptions::default()).unwrap();
    let world = g.region_index("WORLD").unwrap();
    let coils = g.region_index("TF").unwrap();
    // Inside coil TF1 (between its radii 33.2 and 44 about an axis along
    // (6.88, -1.31, 0) from (8.70, 64.51, 0)), and at the centre.
    let in_coil = sv_math::DVec3::new(12.14, 63.855, 38.0);
    assert!(p.region_contains(coils, in_coil));
    assert!(
        !p.region_contains(world, in_coil),
        "WORLD subtracts the coils"
    );
    assert!(p.region_contains(world, sv_math::DVec3::ZERO));
    assert!(!p.region_contains(coils, sv_math::DVec3::ZERO));
    // nEXO's regions, continued over lines, prepare too.
    let l = field("nexo_2024.inp").unwrap();
    let g = &l.scene.geometry;
    let (p, _) = Prepared::new(g, &PrepareOptions::default()).unwrap();
    let rock = g.region_index("rock").unwrap();
    assert!(p.region_contains(rock, sv_math::DVec3::new(2000.0, 0.0, 0.0)));
    assert!(!p.region_contains(rock, sv_math::DVec3::ZERO));
}

/// Lit pixels of a picture of `scene` looking at `at` from 100 cm away,
/// with the lattice cells' own region left out of the picture (FLUKA gives
/// a cell no material of its own: what it shows is what fills it).
fn lit_pixels(scene: &sv_scene::Scene, at: sv_math::DVec3) -> usize {
    let mut scene = scene.clone();
    for (r, p) in scene.geometry.regions.iter().zip(scene.regions.iter_mut()) {
        if r.name.starts_with("REPLIC") {
            p.transparent = true;
        }
    }
    scene.camera = Some(Camera::looking_at(
        at + sv_math::DVec3::new(30.0, -90.0, 40.0),
        at,
        sv_math::DVec3::Z,
        Lens::Fov { vertical_deg: 40.0 },
    ));
    let (r, _) = Renderer::new(&scene, 4.0 / 3.0).unwrap();
    let st = Settings {
        width: 160,
        height: 120,
        shadows: false,
        ..Settings::default()
    };
    r.render(&st, &|_| {})
        .alpha
        .iter()
        .filter(|a| **a > 0.0)
        .count()
}

#[test]
fn a_lattice_cell_shows_the_prototype_moved_into_it() {
    // 702: the prototype (TARGET around TARGET2) and two cells (REPLICA
    // around REPLIC2) holding its copy.
    let Some(l) = input("702_LATTICE.inp") else {
        return;
    };
    let Some(sv_geom::Fill::Universe {
        region_from_universe,
        ..
    }) = &region(&l, "REPLICA").fill
    else {
        panic!("REPLICA is not filled");
    };
    // Look between the prototype (at the origin) and its copy.
    let at = region_from_universe.transform_point3(sv_math::DVec3::ZERO) / 2.0;
    let filled = lit_pixels(&l.scene, at);
    let mut empty = l.scene.clone();
    for r in &mut empty.geometry.regions {
        r.fill = None;
    }
    let prototype_only = lit_pixels(&empty, at);
    assert!(prototype_only > 100, "{prototype_only} lit pixels");
    assert!(
        filled as f64 > 1.5 * prototype_only as f64,
        "{filled} lit pixels with the cells filled, {prototype_only} without"
    );
}
