//! Integration tests of the director: the example film, the script
//! language, its CAMERA and ZOOM read as scenes read them, and the timeline's transforms.
mod camera;
mod example_film;
mod script;
mod transforms;

use sv_geom::{Op, Region, Term, Zone};
use sv_math::DVec3;
use sv_scene::{Light, LightKind};

/// A region of one zone intersecting `bodies`.
fn region(name: &str, bodies: &[usize]) -> Region {
    Region::new(
        name,
        vec![Zone::new(
            bodies
                .iter()
                .map(|&b| Term {
                    op: Op::Inside,
                    body: b,
                })
                .collect(),
        )],
    )
}

/// The test scenes' lights: SUN shining along `sun_dir`, and LAMP, a point
/// light of `lamp_intensity` at (0, 0, 20) fading with the square.
fn sun_and_lamp(sun_dir: DVec3, lamp_intensity: f64) -> Vec<Light> {
    vec![
        Light {
            name: "SUN".into(),
            kind: LightKind::Parallel { dir: sun_dir },
            intensity: 1.0,
            colour: [1.0; 3],
        },
        Light {
            name: "LAMP".into(),
            kind: LightKind::Point {
                pos: DVec3::new(0.0, 0.0, 20.0),
                decay: 2.0,
            },
            intensity: lamp_intensity,
            colour: [1.0; 3],
        },
    ]
}
