//! FLUKA inputs as physicists write them, end to end: a thin layer in a
//! huge world, a cylinder cut by a negated half-space, several black holes.

use sv_check::{check, CheckOptions, Model, UniverseChoice};
use sv_formats::{load_source, Format, LoadOptions, SourceFile};
use sv_math::{DVec3, Ray};
use sv_render::{frame_bounds, Renderer, Settings};
use sv_scene::Scene;
use sv_trace::Scratch;

/// A FLUKA input of free-format `bodies` and `regions` (name, NAZ,
/// expression) with BLCKHOLE on `blackholes`, VACUUM on `voids`, and
/// IRON on everything else.
fn fluka(bodies: &str, regions: &str, blackholes: &[&str], voids: &[&str]) -> Scene {
    let mut text = String::from("TITLE\nthin layers\nGEOBEGIN                                                              COMBNAME\n    0    0          \n");
    text += bodies;
    text += "END\n";
    text += regions;
    text += "END\nGEOEND\n";
    let names: Vec<&str> = regions
        .lines()
        .filter_map(|l| l.split_whitespace().next())
        .collect();
    for name in names {
        let material = if blackholes.contains(&name) {
            "BLCKHOLE"
        } else if voids.contains(&name) {
            "VACUUM"
        } else {
            "IRON"
        };
        text += &format!("ASSIGNMA  {material:>10}{name:>10}\n");
    }
    text += "STOP\n";
    let src = SourceFile::new("thin.inp", text);
    load_source(&src, Format::Fluka, &LoadOptions::default())
        .unwrap_or_else(|e| panic!("{e}"))
        .scene
}

/// The regions a ray along +x through the middle of the slab passes,
/// with their lengths.
fn along_x(scene: &Scene, r: &Renderer) -> Vec<(String, f64)> {
    let ray = Ray::new(DVec3::new(-50.0, 0.01, 0.02), DVec3::X);
    let mut parts = Vec::new();
    let p = r.prepared();
    p.partitions(&ray, 0.0, 100.0, &mut Scratch::new(p), &mut parts);
    parts
        .iter()
        .map(|p| {
            (
                scene.geometry.regions[p.region as usize].name.clone(),
                p.span.len(),
            )
        })
        .collect()
}

#[test]
fn a_thin_layer_survives_a_huge_world() {
    for (world, hole) in [("1e6", "2e6"), ("1e10", "2e10")] {
        // A 0.16 cm iron slab in a 50 cm void sphere in a world sphere of
        // `world` cm inside a black hole twice that.
        let scene = fluka(
            &format!(
                "SPH blkbody    0.0 0.0 0.0 {hole}\nSPH world      0.0 0.0 0.0 {world}\n\
                 SPH void       0.0 0.0 0.0 50.0\nRPP slab       0.0 0.16 -10.0 10.0 -10.0 10.0\n"
            ),
            "BLKHOLE      5 +blkbody -world\nOUTER        5 +world -void\n\
             VOID         5 +void -slab\nSLAB         5 +slab\n",
            &["BLKHOLE"],
            &["VOID", "OUTER"],
        );
        let (r, _) = Renderer::new(&scene, 4.0 / 3.0).unwrap();
        let tol = r.prepared().tolerance();
        assert!(tol < 1e-4, "world {world}: tolerance {tol} cm");
        let crossed = along_x(&scene, &r);
        let slab: Vec<f64> = crossed
            .iter()
            .filter(|(name, _)| name == "SLAB")
            .map(|p| p.1)
            .collect();
        assert_eq!(slab.len(), 1, "world {world}: {crossed:?}");
        assert!((slab[0] - 0.16).abs() < 1e-6, "world {world}: {crossed:?}");

        // Drawn: the default view frames the slab, not the world, and the
        // slab covers much of the picture.
        let b = frame_bounds(r.prepared());
        assert!(b.diagonal() < 100.0, "world {world}: framed {b:?}");
        let frame = r.render(
            &Settings {
                width: 64,
                height: 48,
                shadows: false,
                samples: 1,
                aovs: true,
            },
            &|_| {},
        );
        // The region image holds region index + 1.
        let slab_index = scene.geometry.region_index("SLAB").unwrap() as u32 + 1;
        let covered = frame.region.iter().filter(|&&g| g == slab_index).count();
        assert!(
            covered > 64 * 48 / 10,
            "world {world}: slab on {covered} pixels"
        );

        // Checked: no false voids between the slab and its void.
        let model = Model::new(&scene, &UniverseChoice::Auto).unwrap().0;
        let report = check(&model, &CheckOptions::default()).unwrap();
        assert!(report.is_clean(), "world {world}: {}", report.to_table());
        assert!(
            !report.unseen.contains(&"SLAB".to_string()),
            "{}",
            report.to_table()
        );
    }
}

#[test]
fn a_negated_half_space_bounds_nothing_and_the_cylinder_is_framed() {
    // A cylinder of radius 5 between z = 0 and z = 20, made as FLUKA users
    // write it: `+ZCC +XYP -XYP`.
    let scene = fluka(
        "SPH blkbody    0.0 0.0 0.0 1e6\nSPH world      0.0 0.0 0.0 1e5\n\
         ZCC pipe       0.0 0.0 5.0\nXYP top        20.0\nXYP bottom     0.0\n",
        "BLKHOLE      5 +blkbody -world\nAIR          5 +world -(+pipe +top -bottom)\n\
         CYL          5 +pipe +top -bottom\n",
        &["BLKHOLE"],
        &["AIR"],
    );
    let (r, _) = Renderer::new(&scene, 1.0).unwrap();
    let b = frame_bounds(r.prepared());
    assert!(
        (b.min - DVec3::new(-5.0, -5.0, 0.0)).abs().max_element() < 0.01
            && (b.max - DVec3::new(5.0, 5.0, 20.0)).abs().max_element() < 0.01,
        "{b:?}"
    );
}

#[test]
fn the_universe_is_the_black_hole_that_encloses_the_others() {
    // An inner black hole (a beam dump's) and the outer one.
    let scene = fluka(
        "SPH blkbody    0.0 0.0 0.0 1e4\nSPH world      0.0 0.0 0.0 1e3\n\
         RPP dump       -1.0 1.0 -1.0 1.0 -1.0 1.0\nRPP shield     -5.0 5.0 -5.0 5.0 -5.0 5.0\n",
        "BLKHOLE      5 +blkbody -world\nAIR          5 +world -shield\n\
         SHIELD       5 +shield -dump\nDUMPHOLE     5 +dump\n",
        &["BLKHOLE", "DUMPHOLE"],
        &["AIR"],
    );
    let (model, _) = Model::new(&scene, &UniverseChoice::Auto).unwrap();
    let note = model.universe_note.clone().unwrap_or_default();
    assert!(note.contains("BLKHOLE"), "{note}");
    let report = check(&model, &CheckOptions::default()).unwrap();
    assert!(
        report.outside.is_empty(),
        "the inner black hole was taken for the universe: {}",
        report.to_table()
    );
    assert!(report.is_clean(), "{}", report.to_table());
}
