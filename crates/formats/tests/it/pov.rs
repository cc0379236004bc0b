//! The POV-Ray writer: the text for every body type, CSG, camera and
//! lights, and — when `povray` is installed — pictures rendered by POV-Ray
//! from the exported scene compared pixel by pixel with ours.

use std::path::PathBuf;
use std::process::Command;
use sv_formats::{pov, LoadOptions, SourceFile};
use sv_geom::{Body, BodyKind, Op, Region, Term, Zone};
use sv_math::DVec3;
use sv_render::{Renderer, Settings};
use sv_scene::{Background, Camera, Lens, Light, LightKind, RegionProps, Scene};

fn camera() -> Camera {
    Camera::looking_at(
        DVec3::new(0.0, -30.0, 0.0),
        DVec3::ZERO,
        DVec3::Z,
        Lens::Fov { vertical_deg: 36.0 },
    )
}

fn sun() -> Light {
    Light {
        name: "SUN".into(),
        kind: LightKind::Parallel {
            dir: DVec3::new(0.6, 1.0, -1.5),
        },
        intensity: 0.85,
        colour: [1.0; 3],
    }
}

fn zone(terms: &[(Op, usize)]) -> Zone {
    Zone::new(terms.iter().map(|&(op, body)| Term { op, body }).collect())
}

/// A scene with the given bodies, one region per entry of `regions`.
fn scene(bodies: Vec<Body>, regions: Vec<Vec<Vec<(Op, usize)>>>) -> Scene {
    let mut s = Scene {
        camera: Some(camera()),
        lights: vec![sun()],
        ..Scene::default()
    };
    s.geometry.bodies = bodies;
    for (i, zones) in regions.into_iter().enumerate() {
        s.push_region(
            Region::new(format!("r{i}"), zones.iter().map(|z| zone(z)).collect()),
            RegionProps {
                k: 0.85,
                ..RegionProps::default()
            },
        );
    }
    s
}

fn one_body(kind: BodyKind, params: &[f64]) -> String {
    let s = scene(
        vec![Body::new("b", kind, params.to_vec())],
        vec![vec![vec![(Op::Inside, 0)]]],
    );
    pov::write(&s, 320, 240).unwrap_or_else(|e| panic!("{kind}: {e}"))
}

const I: Op = Op::Inside;
const O: Op = Op::Outside;

#[test]
fn every_body_type_is_written_as_its_primitive() {
    use BodyKind::*;
    // y and z are swapped on the way out.
    let cases: Vec<(BodyKind, Vec<f64>, &str)> =
        vec![
        (Sph, vec![1.0, 2.0, 3.0, 0.5], "sphere { <1, 3, 2>, 0.5 }"),
        (
            Rcc,
            vec![0.0, 0.0, 0.0, 0.0, 0.0, 2.0, 1.0],
            "cylinder { <0, 0, 0>, <0, 2, 0>, 1 }",
        ),
        (
            Trc,
            vec![0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.5],
            "cone { <0, 0, 0>, 1, <1, 0, 0>, 0.5 }",
        ),
        (
            Rec,
            vec![1.0, 2.0, 3.0, 0.0, 0.0, 2.0, 1.0, 0.0, 0.0, 0.0, 0.5, 0.0],
            "cylinder { <0, 0, 0>, <0, 0, 1>, 1 matrix <1, 0, 0, 0, 0, 0.5, 0, 2, 0, 1, 3, 2> }",
        ),
        (
            Tec,
            vec![0.0, 0.0, 0.0, 0.0, 0.0, 2.0, 1.0, 0.0, 0.0, 0.0, 0.5, 0.0, 2.0],
            "cone { <0, 0, 0>, 1, <0, 0, 1>, 0.5 matrix",
        ),
        (
            Tgc,
            vec![
                0.0, 0.0, 0.0, 0.0, 0.0, 2.0, 1.0, 0.0, 0.0, 0.0, 0.5, 0.0, 0.5, 0.25,
            ],
            "cone { <0, 0, 0>, 1, <0, 0, 1>, 0.5 matrix",
        ),
        (
            Tgc,
            vec![
                0.0, 0.0, 0.0, 0.0, 0.0, 2.0, 1.0, 0.0, 0.0, 0.0, 0.5, 0.0, 0.3, 0.5,
            ],
            "poly { 4, <",
        ),
        (
            Ell,
            vec![-1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 4.0],
            "sphere { <0, 0, 0>, 1 matrix <2, 0, 0,",
        ),
        (
            Ell,
            vec![1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 4.0],
            "sphere { <1, 1, 1>, 2 }",
        ),
        (
            Ell1,
            vec![0.0, 0.0, 0.0, 0.0, 0.0, 2.0, 1.0],
            "sphere { <0, 0, 0>, 1 matrix <",
        ),
        (
            Ellg,
            vec![0.0, 0.0, 0.0, 3.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0, 1.0],
            "sphere { <0, 0, 0>, 1 matrix <3, 0, 0, 0, 0, 2, 0, 1, 0, 0, 0, 0> }",
        ),
        (
            Rpp,
            vec![0.0, 1.0, 0.0, 2.0, 0.0, 3.0],
            "box { <0, 0, 0>, <1, 3, 2> }",
        ),
        (
            Box,
            vec![0.0, 0.0, 0.0, 1.0, 1.0, 0.0, -1.0, 1.0, 0.0, 0.0, 0.0, 2.0],
            "box { <0, 0, 0>, <1, 1, 1> matrix <1, 0, 1, -1, 0, 1, 0, 2, 0, 0, 0, 0> }",
        ),
        (
            Tor,
            vec![0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 2.0, 0.5],
            "torus { 2, 0.5 matrix <",
        ),
        (Haf, vec![0.0, 0.0, 2.0, 4.0], "plane { <0, 1, 0>, 2 }"),
        (Xyp, vec![3.0], "plane { <0, 1, 0>, 3 }"),
        (Xzp, vec![3.0], "plane { <0, 0, 1>, 3 }"),
        (Yzp, vec![3.0], "plane { <1, 0, 0>, 3 }"),
        (
            Pla,
            vec![0.0, 3.0, 0.0, 5.0, 2.0, 7.0],
            "plane { <0, 0, 1>, 2 }",
        ),
        (
            Qua,
            vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, -10.0],
            "quadric { <1, 3, 2>, <5, 4, 6>, <7, 9, 8>, -10 }",
        ),
        // XCC: (y-1)² + (z-2)² - 1 = y² + z² - 2y - 4z + 4.
        (
            Xcc,
            vec![1.0, 2.0, 1.0],
            "quadric { <0, 1, 1>, <0, 0, 0>, <0, -4, -2>, 4 }",
        ),
    ];
    for (kind, params, expect) in cases {
        let text = one_body(kind, &params);
        assert!(
            text.contains(expect),
            "{kind}: expected `{expect}` in\n{text}"
        );
    }
}

#[test]
fn polyhedra_are_intersections_of_their_hull_planes_with_a_bound() {
    use BodyKind::*;
    let unit_cube: Vec<f64> = [
        [0, 0, 0],
        [1, 0, 0],
        [1, 1, 0],
        [0, 1, 0],
        [0, 0, 1],
        [1, 0, 1],
        [1, 1, 1],
        [0, 1, 1],
    ]
    .iter()
    .flatten()
    .map(|&v| v as f64)
    .collect();
    let mut arbf = unit_cube.clone();
    arbf.extend([1234.0, 5678.0, 1265.0, 2376.0, 3487.0, 4158.0]);
    let cases: Vec<(BodyKind, Vec<f64>, usize)> = vec![
        (
            Raw,
            vec![0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
            5,
        ),
        (Arb8, unit_cube.clone(), 6),
        (
            Arb4,
            vec![0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
            4,
        ),
        (ArbF, arbf, 6),
    ];
    for (kind, params, planes) in cases {
        let text = one_body(kind, &params);
        let obj = text.lines().find(|l| l.contains("intersection")).unwrap();
        assert_eq!(obj.matches("plane {").count(), planes, "{kind}: {obj}");
        assert!(obj.contains("bounded_by { box {"), "{kind}: {obj}");
    }
}

#[test]
fn ars_is_a_closed_mesh_that_can_take_part_in_csg() {
    // A square frustum closed by an apex: 3 curves of 4 points.
    let mut p = vec![3.0, 4.0];
    for (z, s) in [(0.0, 1.0), (1.0, 0.5), (2.0, 0.0)] {
        for (x, y) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            p.extend([x * s, y * s, z]);
        }
    }
    let text = one_body(BodyKind::Ars, &p);
    assert!(text.contains("mesh { triangle {"), "{text}");
    assert!(text.contains("inside_vector"), "{text}");
    // 8 side triangles on the lower band, 4 on the upper (the others
    // collapse at the apex) and 2 closing the base.
    let mesh = text.lines().find(|l| l.contains("mesh {")).unwrap();
    assert_eq!(mesh.matches("triangle {").count(), 14, "{mesh}");
}

#[test]
fn regions_become_csg_and_transparent_ones_are_left_out() {
    let sph = |x: f64| Body::new(format!("s{x}"), BodyKind::Sph, vec![x, 0.0, 0.0, 1.0]);
    let mut s = scene(
        vec![sph(0.0), sph(0.5), sph(5.0), sph(9.0)],
        vec![
            // r0 = +0 -1 OR +2 ; body 0 is also used by r1.
            vec![vec![(I, 0), (O, 1)], vec![(I, 2)]],
            vec![vec![(I, 0), (I, 1)]],
            vec![vec![(I, 3)]],
        ],
    );
    s.regions[2].transparent = true;
    s.regions[0].colour = Some([0.25, 0.5, 0.75]);
    let text = pov::write(&s, 320, 240).unwrap();
    // Bodies used twice are declared once; those used once are inlined.
    assert!(
        text.contains("#declare B0 = sphere { <0, 0, 0>, 1 }"),
        "{text}"
    );
    assert!(
        text.contains("#declare B1 = sphere { <0.5, 0, 0>, 1 }"),
        "{text}"
    );
    assert!(!text.contains("#declare B2"), "{text}");
    assert!(text.contains(
        "union {\n  difference { object { B0 } object { B1 } }\n  sphere { <5, 0, 0>, 1 }\n  pigment { rgb <0.25, 0.5, 0.75> }"
    ), "{text}");
    assert!(
        text.contains("object { intersection { object { B0 } object { B1 } }\n  pigment { rgb <1, 1, 1> } finish { ambient 0.15 diffuse 0.85"),
        "{text}"
    );
    // The transparent region and its body are not written.
    assert!(!text.contains("// region r2"), "{text}");
    assert!(!text.contains("<9, 0, 0>"), "{text}");
}

#[test]
fn camera_lights_and_settings() {
    let mut s = scene(
        vec![Body::new("s", BodyKind::Sph, vec![0.0, 0.0, 0.0, 1.0])],
        vec![vec![vec![(I, 0)]]],
    );
    s.camera = Some(Camera::looking_at(
        DVec3::new(0.0, -15.0, 4.0),
        DVec3::ZERO,
        DVec3::Z,
        Lens::Fov { vertical_deg: 41.8 },
    ));
    s.background = Background::Colour([0.1, 0.2, 0.3]);
    let text = pov::write(&s, 960, 720).unwrap();
    // Horizontal angle from the vertical field of view at 4:3.
    let angle: f64 = text
        .lines()
        .find_map(|l| l.trim().strip_prefix("angle "))
        .and_then(|l| l.split_whitespace().next())
        .unwrap()
        .parse()
        .unwrap();
    let expect = 2.0
        * ((41.8f64.to_radians() / 2.0).tan() * 4.0 / 3.0)
            .atan()
            .to_degrees();
    assert!((angle - expect).abs() < 1e-9, "{angle} vs {expect}");
    assert!(text.contains("location <0, 4, -15>"), "{text}");
    assert!(text.contains("right x*1.3333333333333333"), "{text}");
    assert!(
        text.contains("background { rgb <0.1, 0.2, 0.3> }"),
        "{text}"
    );
    assert!(text.contains("assumed_gamma 1.0"), "{text}");
    assert!(text.contains("parallel point_at"), "{text}");
    assert!(!text.contains("shadowless"), "{text}");

    s.shadows = false;
    s.lights.push(Light {
        name: "LAMP".into(),
        kind: LightKind::Point {
            pos: DVec3::new(1.0, 2.0, 3.0),
            decay: 2.0,
        },
        intensity: 1.0,
        colour: [1.0; 3],
    });
    s.camera = Some(Camera {
        lens: Lens::Ortho { height: 6.0 },
        ..s.camera.unwrap()
    });
    let text = pov::write(&s, 960, 720).unwrap();
    assert_eq!(text.matches("shadowless").count(), 2, "{text}");
    assert!(text.contains("light_source { <1, 3, 2>"), "{text}");
    assert!(text.contains("fade_power 2"), "{text}");
    assert!(text.contains("orthographic"), "{text}");
    assert!(text.contains("right x*8\n  up y*6\n"), "{text}");
}

#[test]
fn refuses_scenes_it_cannot_write_and_names_the_body() {
    let mut s = scene(
        vec![Body::new("ball", BodyKind::Sph, vec![0.0, 0.0, 0.0, -1.0])],
        vec![vec![vec![(I, 0)]]],
    );
    let e = pov::write(&s, 320, 240).unwrap_err();
    assert!(e.contains("ball"), "{e}");
    s.geometry.bodies[0].params[3] = 1.0;
    assert!(pov::write(&s, 320, 240).is_ok());
    s.camera = None;
    assert!(pov::write(&s, 320, 240).unwrap_err().contains("camera"));
    s.camera = Some(camera());
    s.lights.clear();
    assert!(pov::write(&s, 320, 240).unwrap_err().contains("light"));
    s.lights.push(sun());
    assert!(pov::write(&s, 0, 240).is_err());
}

// ------------------------------------------------------------ POV-Ray itself

fn povray_installed() -> bool {
    Command::new("povray")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success() || !o.stderr.is_empty())
}

/// Render `scene` with POV-Ray (linear 8-bit PPM) and return its pixels.
fn povray_render(scene: &Scene, w: u32, h: u32, tag: &str) -> Vec<[u8; 3]> {
    let dir = std::env::temp_dir().join(format!("sv-pov-test-{}-{tag}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let src = dir.join("scene.pov");
    let out = dir.join("out.ppm");
    std::fs::write(&src, pov::write(scene, w, h).unwrap()).unwrap();
    let o = Command::new("povray")
        .arg(format!("+I{}", src.display()))
        .arg(format!("+O{}", out.display()))
        .args(["+FP", "-A", "-D", "-V", "-P", "File_Gamma=1.0"])
        .arg(format!("+W{w}"))
        .arg(format!("+H{h}"))
        .output()
        .expect("run povray");
    assert!(
        o.status.success(),
        "povray failed:\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let px = read_ppm(&std::fs::read(&out).unwrap(), w, h);
    let _ = std::fs::remove_dir_all(&dir);
    px
}

fn read_ppm(d: &[u8], w: u32, h: u32) -> Vec<[u8; 3]> {
    // Header: P6, then width, height, maxval, separated by white space and
    // comments.
    let mut fields = Vec::new();
    let mut i = 0;
    while fields.len() < 4 {
        while d[i].is_ascii_whitespace() {
            i += 1;
        }
        if d[i] == b'#' {
            while d[i] != b'\n' {
                i += 1;
            }
            continue;
        }
        let j = i + d[i..].iter().position(|c| c.is_ascii_whitespace()).unwrap();
        fields.push(String::from_utf8_lossy(&d[i..j]).into_owned());
        i = j;
    }
    assert_eq!(fields, ["P6", &w.to_string(), &h.to_string(), "255"]);
    d[i + 1..]
        .chunks(3)
        .take((w * h) as usize)
        .map(|c| [c[0], c[1], c[2]])
        .collect()
}

/// Fractions of pixels that are geometry in only one picture, and that
/// differ by more than one code in some channel.
fn compare(scene: &Scene, w: u32, h: u32, tag: &str) -> (f64, f64, f64) {
    let theirs = povray_render(scene, w, h, tag);
    let (r, _) = Renderer::new(scene, w as f64 / h as f64).unwrap();
    let st = Settings {
        width: w,
        height: h,
        shadows: scene.shadows,
        ..Settings::default()
    };
    let ours = r.render(&st, &|_| {});
    let Background::Colour(bg) = scene.background;
    let bg = bg.map(|c| (c * 255.0).round() as i32);
    let (mut mask, mut differ, mut cover) = (0, 0, 0);
    for (i, t) in theirs.iter().enumerate() {
        let o = ours.rgb[i].map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as i32);
        let t = t.map(i32::from);
        let hit_t = (0..3).any(|c| (t[c] - bg[c]).abs() > 1);
        let hit_o = ours.alpha[i] > 0.0;
        cover += usize::from(hit_o);
        mask += usize::from(hit_t != hit_o);
        differ += usize::from((0..3).any(|c| (t[c] - o[c]).abs() > 1));
    }
    let n = theirs.len() as f64;
    (cover as f64 / n, mask as f64 / n, differ as f64 / n)
}

#[test]
fn figure1_matches_povray_when_installed() {
    if !povray_installed() {
        eprintln!("skipped: povray is not installed (apt-get install povray)");
        return;
    }
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/figure1/figure1.sv");
    let src = SourceFile::new(
        path.display().to_string(),
        std::fs::read_to_string(&path).unwrap(),
    );
    let scene = sv_formats::native::read(&src, &LoadOptions::default())
        .unwrap()
        .scene;
    let (cover, mask, differ) = compare(&scene, 320, 240, "figure1");
    assert!(cover > 0.05, "coverage {cover}");
    assert!(
        mask < 0.002,
        "{mask} of the pixels are hit in one picture only"
    );
    assert!(differ < 0.005, "{differ} of the pixels differ");
}

/// One item of the wall: bodies intersected into one region.
type Item = Vec<(BodyKind, Vec<f64>)>;

/// An item of one body.
fn one(kind: BodyKind, params: Vec<f64>) -> Item {
    vec![(kind, params)]
}

/// The corners of a box `2s` wide, `1.4s` deep and `2s` high, for ARB8.
fn cube(s: f64) -> Vec<f64> {
    let mut v = Vec::new();
    for (x, y, z) in [
        (-1, -1, -1),
        (1, -1, -1),
        (1, 1, -1),
        (-1, 1, -1),
        (-1, -1, 1),
        (1, -1, 1),
        (1, 1, 1),
        (-1, 1, 1),
    ] {
        v.extend([x as f64 * s, y as f64 * s * 0.7, z as f64 * s]);
    }
    v
}

/// Spheres, cylinders, cones and ellipsoids.
fn quadric_solids() -> Vec<Item> {
    use BodyKind::*;
    vec![
        one(Sph, vec![0.0, 0.0, 0.0, 1.0]),
        one(Rcc, vec![0.0, 0.0, -1.0, 0.3, 0.2, 2.0, 0.7]),
        one(
            Rec,
            vec![0.0, 0.0, -1.0, 0.0, 0.3, 2.0, 0.9, 0.0, 0.0, 0.0, 0.5, 0.1],
        ),
        one(Trc, vec![0.0, 0.0, -1.0, 0.0, 0.0, 2.0, 1.0, 0.4]),
        one(
            Tec,
            vec![
                0.0, 0.0, -1.0, 0.0, 0.0, 2.0, 1.0, 0.0, 0.0, 0.0, 0.6, 0.0, 2.0,
            ],
        ),
        one(
            Tgc,
            vec![
                0.0, 0.0, -1.0, 0.0, 0.0, 2.0, 1.0, 0.0, 0.0, 0.0, 0.6, 0.0, 0.5, 0.3,
            ],
        ),
        one(
            Tgc,
            vec![
                0.0, 0.0, -1.0, 0.2, 0.0, 2.0, 1.0, 0.0, 0.0, 0.0, 0.6, 0.0, 0.3, 0.6,
            ],
        ),
        one(Ell, vec![-0.6, 0.0, -0.3, 0.6, 0.0, 0.3, 2.2]),
        one(Ell1, vec![0.0, 0.0, 0.0, 1.0, 0.0, 0.5, 0.6]),
        one(
            Ellg,
            vec![0.0, 0.0, 0.0, 0.8, 0.0, 0.8, 0.0, 0.5, 0.0, -0.5, 0.0, 0.5],
        ),
    ]
}

/// Bodies with flat faces.
fn polyhedra() -> Vec<Item> {
    use BodyKind::*;
    let mut items = Vec::new();
    items.push(one(Rpp, vec![-0.8, 0.8, -0.6, 0.6, -1.0, 1.0]));
    {
        let a = DVec3::new(1.0, 0.0, 1.0) * 0.8;
        let b = DVec3::new(-1.0, 0.3, 1.0) * 0.6;
        let c = a.cross(b).normalize() * 0.5;
        let v = -(a + b + c) * 0.5;
        let mut p = v.to_array().to_vec();
        for e in [a, b, c] {
            p.extend(e.to_array());
        }
        items.push(one(Box, p));
    }
    items.push(one(
        Raw,
        vec![
            -0.7, -0.3, -0.8, 1.5, 0.0, 0.0, 0.0, 0.0, 1.5, 0.0, 0.8, 0.3,
        ],
    ));
    items.push(one(
        Arb4,
        vec![
            -1.0, 0.0, -0.8, 1.0, -0.3, -0.8, 0.0, 0.5, -0.6, 0.1, 0.0, 1.0,
        ],
    ));
    items.push(one(
        Arb5,
        vec![
            -1.0, -0.6, -0.8, 1.0, -0.6, -0.8, 1.0, 0.6, -0.8, -1.0, 0.6, -0.8, 0.2, 0.0, 1.0,
        ],
    ));
    items.push(one(
        Arb6,
        vec![
            -1.0, -0.6, -0.8, 1.0, -0.6, -0.8, 1.0, 0.6, -0.8, -1.0, 0.6, -0.8, 0.0, -0.6, 0.9,
            0.0, 0.6, 0.9,
        ],
    ));
    items.push(one(
        Arb7,
        vec![
            -1.0, -0.6, -0.8, 1.0, -0.6, -0.8, 1.0, 0.6, -0.8, -1.0, 0.6, -0.8, -1.0, -0.6, 0.9,
            1.0, -0.6, 0.5, 1.0, 0.6, 0.5,
        ],
    ));
    items.push(one(Arb8, cube(0.8)));
    {
        let mut p = cube(0.7);
        p.extend([1234.0, 5678.0, 1265.0, 2376.0, 3487.0, 4158.0]);
        items.push(one(ArbF, p));
    }
    items
}

/// The torus and an ARS of three curves.
fn torus_and_ars() -> Vec<Item> {
    use BodyKind::*;
    let mut items = Vec::new();
    items.push(one(Tor, vec![0.0, 0.0, 0.0, 0.0, -1.0, 1.0, 0.8, 0.3]));
    {
        let mut p = vec![3.0, 4.0];
        for (z, s) in [(-1.0, 1.0), (0.2, 0.6), (1.0, 0.0)] {
            for (x, y) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                p.extend([x * s, y * s * 0.8, z]);
            }
        }
        items.push(one(Ars, p));
    }
    items
}

/// Infinite bodies, each cut by a unit sphere.
fn infinite_bodies_cut() -> Vec<Item> {
    use BodyKind::*;
    let unit_sphere = (Sph, vec![0.0, 0.0, 0.0, 1.0]);
    let mut items = Vec::new();
    for inf in [
        (Haf, vec![1.0, -0.5, 1.0, 0.2]),
        (Xyp, vec![0.3]),
        (Xzp, vec![-0.2]),
        (Yzp, vec![0.4]),
        (Pla, vec![-1.0, 0.0, 1.0, 0.0, 0.0, 0.3]),
        (Xcc, vec![0.0, 0.2, 0.5]),
        (Zec, vec![0.2, 0.0, 0.5, 0.8]),
        (
            Qua,
            vec![1.0, 1.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -0.1],
        ),
    ] {
        items.push(vec![unit_sphere.clone(), inf]);
    }
    items
}

/// Every body type, side by side in a wall facing the camera; the
/// infinite ones are cut by a sphere.
fn all_bodies() -> Scene {
    let mut items = quadric_solids();
    items.extend(polyhedra());
    items.extend(torus_and_ars());
    items.extend(infinite_bodies_cut());
    // Lay the items out on a 7-wide grid in the x-z plane.
    let mut s = Scene {
        camera: Some(Camera::looking_at(
            DVec3::new(0.0, -40.0, 8.0),
            DVec3::ZERO,
            DVec3::Z,
            Lens::Fov { vertical_deg: 24.0 },
        )),
        lights: vec![sun()],
        ..Scene::default()
    };
    for (n, item) in items.into_iter().enumerate() {
        let centre = DVec3::new(-8.4 + 2.8 * (n % 7) as f64, 0.0, 4.2 - 2.8 * (n / 7) as f64);
        let mut terms = Vec::new();
        for (kind, p) in item {
            let b = Body::new(format!("b{}", s.geometry.bodies.len()), kind, p);
            let b = b
                .transformed(&sv_math::DAffine3::from_translation(centre))
                .unwrap();
            terms.push(Term {
                op: Op::Inside,
                body: s.geometry.bodies.len(),
            });
            s.geometry.bodies.push(b);
        }
        s.push_region(
            Region::new(format!("r{n}"), vec![Zone::new(terms)]),
            RegionProps {
                k: 0.85,
                colour: Some([0.9, 0.8 - 0.02 * n as f64, 0.5 + 0.015 * n as f64]),
                ..RegionProps::default()
            },
        );
    }
    s
}

#[test]
fn the_wall_of_every_body_type_is_written_whole() {
    // The scene the POV-Ray comparison renders, checked without POV-Ray:
    // every type is in it (XCC and ZEC stand for the other infinite
    // cylinders) and every region is written.
    let scene = all_bodies();
    let kinds: std::collections::HashSet<BodyKind> =
        scene.geometry.bodies.iter().map(|b| b.kind).collect();
    let missing: Vec<&str> = sv_geom::BODY_TYPES
        .iter()
        .map(|t| t.name)
        .filter(|n| !kinds.iter().any(|k| k.name() == *n))
        .collect();
    assert_eq!(missing, ["YCC", "ZCC", "XEC", "YEC"]);
    let text = pov::write(&scene, 320, 240).unwrap();
    assert_eq!(
        text.matches("// region r").count(),
        scene.geometry.regions.len()
    );
}

#[test]
fn every_body_type_matches_povray_when_installed() {
    if !povray_installed() {
        eprintln!("skipped: povray is not installed (apt-get install povray)");
        return;
    }
    let mut scene = all_bodies();
    // Every item is in the picture (so the comparison covers every type).
    let (r, _) = Renderer::new(&scene, 4.0 / 3.0).unwrap();
    let f = r.render(
        &Settings {
            width: 448,
            height: 336,
            aovs: true,
            ..Settings::default()
        },
        &|_| {},
    );
    for reg in 1..=scene.geometry.regions.len() as u32 {
        let n = f.region.iter().filter(|&&x| x == reg).count();
        assert!(n > 100, "region {} covers only {n} pixels", reg - 1);
    }
    for shadows in [false, true] {
        scene.shadows = shadows;
        let (cover, mask, differ) = compare(&scene, 448, 336, &format!("all{shadows}"));
        eprintln!(
            "shadows {shadows}: coverage {cover}, hit in one only {mask}, differing {differ}"
        );
        assert!(cover > 0.1, "coverage {cover}");
        assert!(
            mask < 0.003,
            "shadows {shadows}: {mask} of the pixels are hit in one picture only"
        );
        assert!(
            differ < 0.01,
            "shadows {shadows}: {differ} of the pixels differ"
        );
    }
}
