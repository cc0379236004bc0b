//! The example film script (examples/helicopter-film/film.svs) against a
//! stand-in scene with the region names it uses: it must read without
//! error, last 30 seconds, and fly the plan its comments describe.

use sv_director::Timeline;
use sv_formats::script::build_timeline;
use sv_formats::SourceFile;
use sv_geom::{Body, BodyKind, Region};
use sv_math::DVec3;
use sv_scene::{RegionProps, Scene};

/// One small body per region, placed roughly where the real model has it.
fn stand_in() -> Scene {
    let sph = |x: f64, y: f64, z: f64| (BodyKind::Sph, vec![x, y, z, 0.3]);
    let rcc =
        |v: [f64; 3], h: [f64; 3]| (BodyKind::Rcc, vec![v[0], v[1], v[2], h[0], h[1], h[2], 0.1]);
    let parts: Vec<(&str, (BodyKind, Vec<f64>))> = vec![
        ("fuselage", sph(0.0, 0.0, 2.0)),
        ("canopy", sph(2.0, 0.0, 2.5)),
        ("tailboom", rcc([-1.0, 0.0, 2.5], [-8.0, 0.0, 0.5])),
        ("fin", sph(-9.4, 0.0, 3.5)),
        ("stabilizer", sph(-8.0, 0.0, 2.8)),
        ("stab_root", sph(-8.0, 0.0, 2.8)),
        ("mast", rcc([0.0, 0.0, 3.0], [0.0, 0.0, 1.0])),
        ("hub", sph(0.0, 0.0, 4.1)),
        ("blade_a", rcc([0.0, 0.0, 4.2], [6.0, 0.0, 0.0])),
        ("blade_b", rcc([0.0, 0.0, 4.2], [-6.0, 0.0, 0.0])),
        ("tailhub", sph(-9.45, 0.3, 3.1)),
        ("tailblade_a", rcc([-9.45, 0.35, 3.1], [0.0, 0.0, 1.0])),
        ("tailblade_b", rcc([-9.45, 0.35, 3.1], [0.0, 0.0, -1.0])),
        ("skid_l", rcc([-2.0, 1.2, 0.1], [4.0, 0.0, 0.0])),
        ("skid_r", rcc([-2.0, -1.2, 0.1], [4.0, 0.0, 0.0])),
        ("strut_fl", rcc([1.0, 1.2, 0.1], [0.0, -0.4, 1.0])),
        ("strut_fr", rcc([1.0, -1.2, 0.1], [0.0, 0.4, 1.0])),
        ("strut_rl", rcc([-1.0, 1.2, 0.1], [0.0, -0.4, 1.0])),
        ("strut_rr", rcc([-1.0, -1.2, 0.1], [0.0, 0.4, 1.0])),
        ("cowling", sph(-0.5, 0.0, 3.0)),
        ("exhaust", sph(-1.5, 0.5, 3.0)),
        ("door", sph(0.5, 1.0, 2.0)),
        ("window", sph(0.5, 1.05, 2.4)),
        ("fairing", sph(-0.5, 0.0, 3.3)),
        (
            "gun_base",
            (BodyKind::Rpp, vec![59.0, 61.0, 29.0, 31.0, 0.0, 1.0]),
        ),
        ("gun_barrel", rcc([60.0, 30.0, 1.5], [-3.0, 0.0, 0.0])),
        (
            "ground",
            (BodyKind::Rpp, vec![-200.0, 200.0, -200.0, 200.0, -1.0, 0.0]),
        ),
    ];
    let mut s = Scene::default();
    for (i, (name, (kind, params))) in parts.into_iter().enumerate() {
        s.geometry.bodies.push(Body::new(name, kind, params));
        s.push_region(Region::of_body(name, i), RegionProps::default());
    }
    s
}

fn film() -> (Timeline, Scene) {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/helicopter-film/film.svs"
    );
    let text = std::fs::read_to_string(path).expect("film.svs");
    let scene = stand_in();
    match build_timeline(&SourceFile::new("film.svs", text), &scene) {
        Ok(t) => (t, scene),
        Err(d) => panic!("{}", d.render_plain()),
    }
}

fn body(s: &Scene, name: &str) -> DVec3 {
    let i = s.geometry.body_index(name).expect("body");
    s.geometry.bodies[i].vec3(0)
}

#[test]
fn example_film_lasts_thirty_seconds_at_24_fps() {
    let (t, _) = film();
    assert_eq!(t.frame_count(), 720);
    assert_eq!(t.fps(), 24.0);
    assert_eq!(t.size(), Some((960, 720)));
}

#[test]
fn example_film_flies_its_flight_plan() {
    let (t, base) = film();
    let at = |f: usize| t.scene_at(&base, f);
    let mast = |f: usize| body(&at(f), "mast");
    let near = |a: DVec3, b: DVec3| (a - b).length() < 1e-6;
    // On the ground, then up to 12, then forward flight.
    assert!(near(mast(0), DVec3::new(0.0, 0.0, 3.0)));
    assert!(near(mast(119), DVec3::new(0.0, 0.0, 15.0)));
    // Landed at (10, 50) after the turn, level again.
    for f in 431..456 {
        assert!(
            near(mast(f), DVec3::new(10.0, 50.0, 3.0)),
            "frame {f}: {}",
            mast(f)
        );
    }
    // The rotor turns on the ground: the blade points elsewhere each frame.
    let blade = |f: usize| {
        let s = at(f);
        s.geometry.bodies[s.geometry.body_index("blade_a").expect("blade")].vec3(3)
    };
    assert!((blade(440) - blade(441)).length() > 1.0);
    // The gun has swung round towards the helicopter's run-in.
    let barrel = |f: usize| {
        let s = at(f);
        s.geometry.bodies[s.geometry.body_index("gun_barrel").expect("barrel")].vec3(3)
    };
    let b = barrel(600);
    assert!(
        b.z > 0.5 && b.y > 0.5,
        "barrel raised and turned towards the helicopter: {b}"
    );
    // Crashed: the wreck is down, away from the gun, and still at the end.
    let end = at(719);
    let fus = body(&end, "fuselage");
    assert!(fus.z < 3.0, "fuselage at {fus}");
    assert!((fus - DVec3::new(60.0, 30.0, 0.0)).length() > 8.0);
    assert_eq!(body(&at(700), "fuselage"), fus);
    assert_eq!(blade(700), blade(719));
}

#[test]
fn example_film_keeps_the_helicopter_in_view() {
    let (t, base) = film();
    for f in (0..720).step_by(6) {
        let s = t.scene_at(&base, f);
        let cam = s.camera.expect("camera");
        let c = t.object_centre(
            t.spec()
                .objects
                .iter()
                .position(|o| o.name == "AIRFRAME")
                .expect("AIRFRAME"),
            &t.state_at(f),
        );
        let d = (c - cam.eye).length();
        let fov = match cam.lens {
            sv_scene::Lens::Fov { vertical_deg } => vertical_deg,
            _ => panic!("field of view expected"),
        };
        // The 13-unit airframe spans a quarter to four fifths of the height.
        let visible = 2.0 * d * (fov.to_radians() / 2.0).tan();
        let share = 13.0 / visible;
        assert!(
            (0.25..0.8).contains(&share),
            "frame {f}: distance {d:.1}, fov {fov:.1}, share {share:.2}"
        );
        // Tracked: the camera looks straight at it.
        assert!(
            cam.dir.normalize().dot((c - cam.eye).normalize()) > 0.999_999,
            "frame {f}"
        );
    }
}
