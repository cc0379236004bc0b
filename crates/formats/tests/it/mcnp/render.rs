//! MCNP models through the tracer: the regions it finds at points agree
//! with the test's own evaluator, and a picture of the Hoogenboom–Martin
//! core shows its pins through two levels of lattices.

use super::*;
use sv_render::{Renderer, Settings};
use sv_scene::{Camera, Lens};
use sv_trace::{PrepareOptions, Prepared};

/// Points spread over `lo..hi` by a fixed sequence (no two runs differ).
fn points(lo: DVec3, hi: DVec3, n: usize) -> Vec<DVec3> {
    // Additive recurrence on the plastic number's powers (R3 sequence).
    let g = 1.220_744_084_605_759_5_f64;
    let step = DVec3::new(1.0 / g, 1.0 / (g * g), 1.0 / (g * g * g));
    (1..=n)
        .map(|i| {
            let f = (step * i as f64 + 0.5).fract();
            lo + (hi - lo) * f
        })
        .collect()
}

#[test]
fn the_tracer_finds_the_regions_the_evaluator_finds() {
    let inputs = decks::inputs();
    for path in inputs.iter().filter(|p| {
        let s = p.display().to_string();
        [
            "mc-performance",
            "pu-met-fast-003",
            "u233-comp",
            "leu-comp-therm-008/mcnp/case-11",
            "heu-met-inter-006/mcnp/case-4",
        ]
        .iter()
        .any(|k| s.contains(k))
    }) {
        let l = read_named(
            &path.display().to_string(),
            &std::fs::read_to_string(path).unwrap(),
        )
        .unwrap();
        let g = &l.scene.geometry;
        let (p, _) = Prepared::new(g, &PrepareOptions::default())
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let e = Eval::new(&l.scene);
        let bounds = p.opaque_bounds();
        assert!(bounds.is_finite(), "{}: {bounds:?}", path.display());
        for q in points(bounds.min, bounds.max, 300) {
            let mut want = e.regions(q);
            want.sort_unstable();
            let got: Vec<usize> = p.regions_at(q).into_iter().map(|r| r as usize).collect();
            assert_eq!(got, want, "{} at {q}", path.display());
        }
    }
}

#[test]
fn a_picture_of_the_core_shows_pins_through_two_lattices() {
    let Some(root) = sv_testdata::shared_decks("mcnp-openmc") else {
        return;
    };
    let path = root.join("mc-performance/mcnp/input");
    let l = read_named(
        &path.display().to_string(),
        &std::fs::read_to_string(&path).unwrap(),
    )
    .unwrap();
    let mut scene = l.scene.clone();
    // Everything above and around the core made transparent: the view
    // from above meets the top of the upper lattice (z = 183).
    for (r, p) in scene.geometry.regions.iter().zip(scene.regions.iter_mut()) {
        if r.universe == 0 && r.name != "200" {
            p.transparent = true;
        }
    }
    scene.camera = Some(Camera::looking_at(
        v(0.0, 0.0, 600.0),
        v(0.0, 0.0, 0.0),
        DVec3::Y,
        Lens::Fov { vertical_deg: 40.0 },
    ));
    let (r, _) = Renderer::new(&scene, 1.0).unwrap();
    let st = Settings {
        width: 201,
        height: 201,
        shadows: false,
        aovs: true,
        ..Settings::default()
    };
    let frame = r.render(&st, &|_| {});
    let g = &scene.geometry;
    let seen = |name: &str| {
        let i = g.region_index(name).unwrap() as u32 + 1;
        frame.region.iter().filter(|r| **r == i).count()
    };
    // The centre pixel looks down the central instrumentation tube.
    assert_eq!(
        frame.region[100 * 201 + 100],
        g.region_index("30").unwrap() as u32 + 1
    );
    for name in ["27", "29", "70"] {
        assert!(
            seen(name) > 50,
            "cell {name} is seen on {} pixels",
            seen(name)
        );
    }
}
