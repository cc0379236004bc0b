//! The real decks render the same, bit for bit, with the acceleration
//! structures (hierarchy, tile lists, light buffer, shadow cache) and
//! without them, in sunlight and under a lamp, on 1 and 2 threads, and
//! under rt's shading.

use std::path::PathBuf;
use sv_formats::{load_file, LoadOptions};
use sv_render::{Frame, Renderer, Settings, Shading};
use sv_scene::{Light, LightKind};
use sv_trace::PrepareOptions;

/// The shared COMGEOM decks and FLUKA test inputs; `None` only when they
/// are missing and `SV_SKIP_SHARED=1` is set.
fn decks() -> Option<Vec<PathBuf>> {
    let mut files = sv_testdata::shared_files("comgeom", &[".cg"])?;
    files.extend(sv_testdata::shared_files(
        "fluka/pyg4ometry-testdata",
        &[".inp"],
    )?);
    Some(files)
}

fn render(r: &Renderer, threads: usize) -> Frame {
    let st = Settings {
        width: 64,
        height: 48,
        shadows: true,
        samples: 1,
        aovs: true,
    };
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(|| r.render(&st, &|_| {}))
}

/// Pixels whose colour, coverage or auxiliary values differ.
fn differing(a: &Frame, b: &Frame) -> usize {
    (0..a.rgb.len())
        .filter(|&i| {
            a.rgb[i] != b.rgb[i]
                || a.alpha[i] != b.alpha[i]
                || a.region[i] != b.region[i]
                || a.depth[i] != b.depth[i]
                || a.normal[i] != b.normal[i]
        })
        .count()
}

#[test]
fn every_deck_renders_the_same_with_and_without_acceleration() {
    let Some(files) = decks() else {
        return;
    };
    let mut compared = 0;
    for f in &files {
        // The fragment file of the FLUKA set is not a whole input.
        let Ok(loaded) = load_file(f, &LoadOptions::default()) else {
            continue;
        };
        let mut scene = loaded.scene;
        scene.show_air_if_nothing_else();
        let Ok((fast, _)) = Renderer::new(&scene, 4.0 / 3.0) else {
            continue;
        };
        // The same camera for both, and a lamp beside the sun.
        scene.camera = Some(fast.camera);
        // The model's diagonal is 1e7 times the tolerance.
        let diagonal = fast.prepared().tolerance() * 1e7;
        let lamp = fast.camera.eye + fast.camera.up.normalize() * 0.2 * diagonal;
        scene.lights = vec![
            fast.lights[0].clone(),
            Light {
                name: "LAMP".into(),
                kind: LightKind::Point {
                    pos: lamp,
                    decay: 0.0,
                },
                intensity: 0.4,
                colour: [1.0; 3],
            },
        ];
        let (fast, _) = Renderer::new(&scene, 4.0 / 3.0).unwrap();
        let (slow, _) = Renderer::with_options(
            &scene,
            4.0 / 3.0,
            PrepareOptions {
                brute_force: true,
                ..Default::default()
            },
        )
        .unwrap();
        let one = render(&fast, 1);
        let two = render(&fast, 2);
        assert!(
            two == one,
            "{}: 1 and 2 threads differ in {} pixels",
            f.display(),
            differing(&one, &two)
        );
        let brute = render(&slow, 1);
        assert!(
            brute == one,
            "{}: with and without acceleration, {} pixels differ",
            f.display(),
            differing(&one, &brute)
        );
        // rt's shading, traced for how each pixel faces its ray alone.
        let rt = |r: &Renderer| {
            let mut r = r.clone();
            r.lights.clear();
            r.shading = Shading::RtEyeLight;
            render(&r, 1)
        };
        let (one, brute) = (rt(&fast), rt(&slow));
        assert!(
            brute == one,
            "{}: rt's shading with and without acceleration, {} pixels differ",
            f.display(),
            differing(&one, &brute)
        );
        compared += 1;
    }
    assert!(compared >= 80, "only {compared} decks compared");
}
