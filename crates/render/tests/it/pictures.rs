//! Shading against analytic values, shadows, snapshots and determinism.

use sv_geom::{Body, BodyKind, Geometry, Op, Region, Term, Zone};
use sv_math::DVec3;
use sv_render::{Renderer, Settings};
use sv_scene::{Background, Camera, Lens, Light, LightKind, RegionProps, Scene};

fn one_body_region(g: &mut Geometry, props: &mut Vec<RegionProps>, body: Body, k: f64) {
    let i = g.bodies.len();
    g.bodies.push(body);
    g.regions.push(Region::of_body(format!("r{i}"), i));
    props.push(RegionProps {
        k,
        ..Default::default()
    });
}

/// A slab whose top face is the plane z = 0, seen from straight above.
fn plane_scene(light: Light, ambient: f64) -> Scene {
    let mut s = Scene::default();
    let mut props = vec![];
    one_body_region(
        &mut s.geometry,
        &mut props,
        Body::new(
            "floor",
            BodyKind::Rpp,
            vec![-100.0, 100.0, -100.0, 100.0, -1.0, 0.0],
        ),
        0.8,
    );
    s.regions = props;
    s.camera = Some(Camera {
        eye: DVec3::new(0.0, 0.0, 10.0),
        dir: -DVec3::Z,
        up: DVec3::Y,
        lens: Lens::Ortho { height: 2.0 },
    });
    s.lights = vec![light];
    s.ambient = ambient;
    s.background = Background::Colour([0.0; 3]);
    s
}

fn render(s: &Scene, w: u32, h: u32, shadows: bool) -> sv_render::Frame {
    let (r, _) = Renderer::new(s, w as f64 / h as f64).unwrap();
    r.render(
        &Settings {
            width: w,
            height: h,
            shadows,
            samples: 1,
            aovs: true,
        },
        &|_| {},
    )
}

#[test]
fn lit_plane_has_the_papers_exact_intensity() {
    for deg in [0.0f64, 30.0, 60.0, 89.0] {
        let th = deg.to_radians();
        let sun = Light {
            name: "SUN".into(),
            kind: LightKind::Parallel {
                dir: DVec3::new(th.sin(), 0.0, -th.cos()),
            },
            intensity: 1.0,
            colour: [1.0; 3],
        };
        let f = render(&plane_scene(sun, 0.1), 4, 4, true);
        let want = (0.8 * th.cos() + 0.1) as f32;
        assert!(
            (f.grey(1, 1) - want).abs() < 1e-6,
            "{deg}°: {} vs {want}",
            f.grey(1, 1)
        );
    }
    // A light from below the surface contributes nothing: I = A₀.
    let under = Light {
        name: "U".into(),
        kind: LightKind::Parallel {
            dir: DVec3::new(0.0, 0.0, 1.0),
        },
        intensity: 1.0,
        colour: [1.0; 3],
    };
    assert_eq!(render(&plane_scene(under, 0.1), 2, 2, true).grey(0, 0), 0.1);
}

#[test]
fn point_light_falls_off_as_r_to_the_minus_n() {
    for n in [0.0, 1.0, 2.0] {
        let lamp = Light {
            name: "L".into(),
            kind: LightKind::Point {
                pos: DVec3::new(0.0, 0.0, 4.0),
                decay: n,
            },
            intensity: 50.0,
            colour: [1.0; 3],
        };
        let f = render(&plane_scene(lamp, 0.0), 2, 2, false);
        // Pixel (0,0) looks at (-0.5, 0.5, 0): R² = 0.5 + 16.
        let p = DVec3::new(-0.5, 0.5, 0.0);
        let d = DVec3::new(0.0, 0.0, 4.0) - p;
        let r = d.length();
        let want = 50.0 * 0.8 * (d.z / r) * r.powf(-n);
        assert!(
            (f.grey(0, 0) as f64 - want).abs() < 1e-5 * want.max(1.0),
            "n={n}: {} vs {want}",
            f.grey(0, 0)
        );
    }
}

#[test]
fn a_blocked_light_contributes_nothing_unless_shadows_are_off() {
    let sun = Light {
        name: "SUN".into(),
        kind: LightKind::Parallel { dir: -DVec3::Z },
        intensity: 1.0,
        colour: [1.0; 3],
    };
    let mut s = plane_scene(sun, 0.2);
    let mut props = std::mem::take(&mut s.regions);
    // A small sphere high above the centre, outside the orthographic view.
    one_body_region(
        &mut s.geometry,
        &mut props,
        Body::new("ball", BodyKind::Sph, vec![0.0, 0.0, 20.0, 0.5]),
        0.8,
    );
    s.regions = props;
    let f = render(&s, 3, 3, true);
    assert_eq!(f.grey(1, 1), 0.2, "centre is in the shadow");
    assert!((f.grey(0, 0) - 1.0).abs() < 1e-6, "corner is lit");
    let f = render(&s, 3, 3, false);
    assert!(
        (f.grey(1, 1) - 1.0).abs() < 1e-6,
        "--no-shadows reproduces the paper"
    );
    // A transparent region casts no shadow.
    s.regions[1].transparent = true;
    assert!((render(&s, 3, 3, true).grey(1, 1) - 1.0).abs() < 1e-6);
}

fn figure1_like() -> Scene {
    let mut s = Scene::default();
    let mut props = vec![];
    s.geometry.bodies = vec![
        Body::new("1", BodyKind::Sph, vec![0.0, 0.0, 0.0, 1.0]),
        Body::new(
            "2",
            BodyKind::Rcc,
            vec![0.45, -0.2, -1.4, 0.0, 0.0, 2.8, 0.6],
        ),
    ];
    s.geometry.regions.push(Region::new(
        "D",
        vec![Zone::new(vec![
            Term {
                op: Op::Inside,
                body: 0,
            },
            Term {
                op: Op::Outside,
                body: 1,
            },
        ])],
    ));
    props.push(RegionProps::default());
    s.regions = props;
    s.camera = Some(Camera {
        eye: DVec3::new(0.0, 0.0, 10.0),
        dir: -DVec3::Z,
        up: DVec3::Y,
        lens: Lens::Ortho { height: 3.0 },
    });
    s
}

#[test]
fn sphere_pierced_by_a_cylinder_ascii_snapshot() {
    let f = render(&figure1_like(), 24, 12, true);
    // Looking down the cylinder's axis: the hole (x from -0.15 to 1.05)
    // takes the sphere's right side away.
    let want = "\
........................
........................
..........####..........
.........######.........
........#####.##........
........####............
........###.............
........####............
.........###............
..........####..........
........................
........................
";
    assert_eq!(f.ascii(), want, "got:\n{}", f.ascii());
}

#[test]
fn serial_parallel_and_brute_force_renders_are_bit_identical() {
    let scene = figure1_like();
    let (r, _) = Renderer::new(&scene, 1.0).unwrap();
    let st = Settings {
        width: 64,
        height: 64,
        shadows: true,
        samples: 2,
        aovs: true,
    };
    let one = on_threads(&r, &st, 1);
    assert_eq!(on_threads(&r, &st, 2), one);
    assert_eq!(brute_force(&scene, 1.0).render(&st, &|_| {}), one);
}

/// Render with `threads` worker threads.
fn on_threads(r: &Renderer, st: &Settings, threads: usize) -> sv_render::Frame {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(|| r.render(st, &|_| {}))
}

/// `scene` prepared without hierarchy: every zone is tried by every ray.
fn brute_force(scene: &Scene, aspect: f64) -> Renderer {
    Renderer::with_options(
        scene,
        aspect,
        sv_trace::PrepareOptions {
            brute_force: true,
            ..Default::default()
        },
    )
    .unwrap()
    .0
}

/// A lattice of 9 × 9 × 6 spheres (486 zones), every other one pierced by
/// a cylinder, seen in perspective from a corner: at 96 × 72 a tile meets
/// up to about a hundred zones and its rays walk the tile's list; in one
/// tile of 16 × 12 pixels it meets them all, more than a tile lists, and
/// the rays walk the hierarchy. The shadow rays toward the sun use its
/// light buffer and those toward the lamp the per-tile zone lists.
fn crowded() -> Scene {
    let mut s = Scene::default();
    let mut props = vec![];
    for i in 0..9 {
        for j in 0..9 {
            for k in 0..6 {
                let c = [i as f64 * 1.1, j as f64 * 1.1, k as f64 * 1.1];
                let b = s.geometry.bodies.len();
                s.geometry.bodies.push(Body::new(
                    format!("s{b}"),
                    BodyKind::Sph,
                    vec![c[0], c[1], c[2], 0.5 + 0.01 * ((i + j + k) % 5) as f64],
                ));
                let mut terms = vec![Term {
                    op: Op::Inside,
                    body: b,
                }];
                if (i + j + k) % 2 == 0 {
                    s.geometry.bodies.push(Body::new(
                        format!("c{b}"),
                        BodyKind::Rcc,
                        vec![c[0] - 0.7, c[1] + 0.1, c[2], 1.4, 0.3, 0.2, 0.22],
                    ));
                    terms.push(Term {
                        op: Op::Outside,
                        body: b + 1,
                    });
                }
                s.geometry
                    .regions
                    .push(Region::new(format!("r{b}"), vec![Zone::new(terms)]));
                props.push(RegionProps::default());
            }
        }
    }
    s.regions = props;
    s.camera = Some(Camera::looking_at(
        DVec3::new(-3.0, -2.5, 7.0),
        DVec3::new(4.4, 4.4, 2.7),
        DVec3::Z,
        Lens::Fov { vertical_deg: 45.0 },
    ));
    s.lights = vec![
        Light {
            kind: LightKind::Parallel {
                dir: DVec3::new(-0.3, 0.5, -1.0),
            },
            intensity: 0.7,
            colour: [1.0; 3],
            name: "SUN".into(),
        },
        Light {
            kind: LightKind::Point {
                pos: DVec3::new(12.0, -2.0, 8.0),
                decay: 0.0,
            },
            intensity: 0.3,
            colour: [1.0; 3],
            name: "LAMP".into(),
        },
    ];
    s
}

/// The crowded lattice rendered at `width` × `height` with shadows: checks
/// that one thread, two threads and no hierarchy give the same picture, and
/// that the lattice fills most of it; returns the renderer, the settings
/// and the picture.
fn crowded_the_same_every_way(width: u32, height: u32) -> (Renderer, Settings, sv_render::Frame) {
    let scene = crowded();
    let (r, _) = Renderer::new(&scene, 4.0 / 3.0).unwrap();
    let st = Settings {
        width,
        height,
        shadows: true,
        samples: 1,
        aovs: true,
    };
    let one = on_threads(&r, &st, 1);
    assert_eq!(on_threads(&r, &st, 2), one);
    assert_eq!(brute_force(&scene, 4.0 / 3.0).render(&st, &|_| {}), one);
    let cover = one.alpha.iter().filter(|&&a| a > 0.0).count();
    assert!(cover > one.alpha.len() / 2, "coverage {cover}");
    (r, st, one)
}

#[test]
fn crowded_scene_renders_bit_identically_with_any_threads_and_without_hierarchy() {
    let (r, st, one) = crowded_the_same_every_way(96, 72);
    // The picture is worth comparing: many spheres are in shadow.
    let unshadowed = r.render(
        &Settings {
            shadows: false,
            ..st.clone()
        },
        &|_| {},
    );
    let shaded = (0..one.rgb.len())
        .filter(|&i| one.rgb[i] != unshadowed.rgb[i])
        .count();
    assert!(shaded > one.rgb.len() / 10, "{shaded} pixels in shadow");
}

#[test]
fn crowded_scene_seen_orthographically_renders_as_without_hierarchy() {
    // Orthographic rays start on a plane, not at the eye: the tile lists'
    // entry bounds (boxes, and the spheres' balls) are measured from it.
    let mut scene = crowded();
    let (r, _) = Renderer::new(&scene, 4.0 / 3.0).unwrap();
    scene.camera = Some(Camera {
        lens: Lens::Ortho { height: 10.0 },
        ..r.camera
    });
    let st = Settings {
        width: 96,
        height: 72,
        shadows: true,
        samples: 1,
        aovs: true,
    };
    let (r, _) = Renderer::new(&scene, 4.0 / 3.0).unwrap();
    let one = on_threads(&r, &st, 1);
    assert_eq!(brute_force(&scene, 4.0 / 3.0).render(&st, &|_| {}), one);
    let cover = one.alpha.iter().filter(|&&a| a > 0.0).count();
    assert!(cover > one.alpha.len() / 4, "coverage {cover}");
}

#[test]
fn a_tile_too_crowded_to_list_renders_the_same_through_the_hierarchy() {
    // One tile for the whole lattice: more zones than a tile lists, so
    // every primary ray walks the hierarchy.
    crowded_the_same_every_way(16, 12);
}

#[test]
fn a_reused_frame_holds_exactly_the_new_picture() {
    let st = Settings {
        width: 40,
        height: 30,
        shadows: true,
        samples: 1,
        aovs: true,
    };
    let (first, _) = Renderer::new(&crowded(), 4.0 / 3.0).unwrap();
    let (second, _) = Renderer::new(&figure1_like(), 4.0 / 3.0).unwrap();
    let mut frame = first.render(&st, &|_| {});
    second.render_into(&st, &mut frame, &|_| {});
    let fresh = second.render(&st, &|_| {});
    assert_eq!(frame, fresh);
    // Background is left where the crowded scene had geometry.
    assert!(fresh.region.contains(&0));
    // A frame of another size is remade.
    let small = Settings {
        width: 8,
        height: 6,
        aovs: false,
        ..st
    };
    second.render_into(&small, &mut frame, &|_| {});
    assert_eq!(frame, second.render(&small, &|_| {}));
}

#[test]
fn moving_the_lamp_between_renders_moves_its_shadows() {
    // The lamp's buffer is kept too, and remade when the lamp moves. One
    // tile for the lattice: its shadow rays toward the lamp may meet more
    // zones than a tile lists, so they use the lamp's buffer.
    let st = Settings {
        width: 16,
        height: 12,
        shadows: true,
        samples: 1,
        aovs: false,
    };
    let mut scene = crowded();
    // The lamp alone, so that its shadows are all there is to see.
    scene
        .lights
        .retain(|l| matches!(l.kind, LightKind::Point { .. }));
    let (mut r, _) = Renderer::new(&scene, 4.0 / 3.0).unwrap();
    let first = r.render(&st, &|_| {});
    assert_eq!(r.render(&st, &|_| {}), first, "same lamp, same picture");
    let LightKind::Point { pos, decay } = r.lights[0].kind else {
        panic!("the crowded scene has a lamp");
    };
    let moved_to = LightKind::Point {
        pos: DVec3::new(pos.y, -pos.x, pos.z),
        decay,
    };
    r.lights[0].kind = moved_to;
    let again = r.render(&st, &|_| {});
    let mut moved = scene.clone();
    moved.lights[0].kind = moved_to;
    let (fresh, _) = Renderer::new(&moved, 4.0 / 3.0).unwrap();
    assert_eq!(again, fresh.render(&st, &|_| {}));
    assert_eq!(again, brute_force(&moved, 4.0 / 3.0).render(&st, &|_| {}));
    let changed = (0..first.rgb.len())
        .filter(|&i| first.rgb[i] != again.rgb[i])
        .count();
    assert!(changed > first.rgb.len() / 20, "{changed} pixels changed");
}

#[test]
fn turning_the_sun_between_renders_moves_the_shadows() {
    // The light buffers of one render are kept for the next: they must be
    // remade when a parallel light turns, and only then.
    let st = Settings {
        width: 48,
        height: 36,
        shadows: true,
        samples: 1,
        aovs: false,
    };
    let scene = crowded();
    let (mut r, _) = Renderer::new(&scene, 4.0 / 3.0).unwrap();
    let first = r.render(&st, &|_| {});
    assert_eq!(r.render(&st, &|_| {}), first, "same lights, same picture");
    let LightKind::Parallel { dir } = r.lights[0].kind else {
        panic!("the crowded scene has a sun first");
    };
    let turned = DVec3::new(dir.y, -dir.x, dir.z);
    r.lights[0].kind = LightKind::Parallel { dir: turned };
    let again = r.render(&st, &|_| {});
    let mut moved = scene.clone();
    moved.lights[0].kind = LightKind::Parallel { dir: turned };
    let (fresh, _) = Renderer::new(&moved, 4.0 / 3.0).unwrap();
    assert_eq!(again, fresh.render(&st, &|_| {}));
    let changed = (0..first.rgb.len())
        .filter(|&i| first.rgb[i] != again.rgb[i])
        .count();
    assert!(changed > first.rgb.len() / 20, "{changed} pixels changed");
}
