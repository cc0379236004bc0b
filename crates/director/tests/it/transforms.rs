//! Timeline transforms checked against closed-form positions.

use crate::{region, sun_and_lamp};
use sv_director::*;
use sv_geom::{Body, BodyKind};
use sv_math::{DMat3, DVec3};
use sv_scene::{Camera, Lens, LightKind, RegionProps, Scene};

const HELI: usize = 0;
const ROTOR: usize = 1;
/// Static axis: vertical through (5, 0, 0).
const A: usize = 0;
/// Mast: vertical through (10, 0, 0), carried by the helicopter.
const MAST: usize = 1;
/// Static axis along x through the origin.
const X: usize = 2;
/// Vertical through (12, 0, 0), carried by the helicopter.
const OFFSET: usize = 3;

/// hull: sphere at (10,0,5); blade: RCC from (10,0,7) along (4,0,0); ground.
fn base() -> Scene {
    let mut s = Scene::default();
    s.geometry.bodies = vec![
        Body::new("hull", BodyKind::Sph, vec![10.0, 0.0, 5.0, 1.0]),
        Body::new(
            "blade",
            BodyKind::Rcc,
            vec![10.0, 0.0, 7.0, 4.0, 0.0, 0.0, 0.1],
        ),
        Body::new(
            "ground",
            BodyKind::Rpp,
            vec![-50.0, 50.0, -50.0, 50.0, -1.0, 0.0],
        ),
    ];
    for (name, b) in [("hull", 0), ("blade", 1), ("ground", 2)] {
        s.push_region(region(name, &[b]), RegionProps::default());
    }
    s.camera = Some(Camera::looking_at(
        DVec3::new(0.0, -50.0, 10.0),
        DVec3::ZERO,
        DVec3::Z,
        Lens::Fov { vertical_deg: 40.0 },
    ));
    s.lights = sun_and_lamp(DVec3::new(0.0, 0.0, -1.0), 100.0);
    s
}

fn spec(steps: Vec<Step>) -> Spec {
    Spec {
        objects: vec![
            Object {
                name: "HELICOPTER".into(),
                regions: vec![0],
                children: vec![ROTOR],
            },
            Object {
                name: "ROTOR".into(),
                regions: vec![1],
                children: vec![],
            },
        ],
        axes: vec![
            Axis {
                name: "A".into(),
                point: DVec3::new(5.0, 0.0, 0.0),
                dir: DVec3::Z,
                on: None,
            },
            Axis {
                name: "MAST".into(),
                point: DVec3::new(10.0, 0.0, 0.0),
                dir: DVec3::Z,
                on: Some(HELI),
            },
            Axis {
                name: "X".into(),
                point: DVec3::ZERO,
                dir: DVec3::X,
                on: None,
            },
            Axis {
                name: "OFFSET".into(),
                point: DVec3::new(12.0, 0.0, 0.0),
                dir: DVec3::Z,
                on: Some(HELI),
            },
        ],
        steps,
        ..Spec::default()
    }
}

fn timeline(steps: Vec<Step>) -> Timeline {
    Timeline::new(spec(steps), &base()).expect("valid timeline")
}

fn now(c: Change) -> Step {
    Step::Change(Timed::now(c))
}

fn over(c: Change, n: usize) -> Step {
    Step::Change(Timed::over(c, n))
}

fn mv(target: Target, x: f64, y: f64, z: f64) -> Change {
    Change::Move {
        target,
        by: DVec3::new(x, y, z),
    }
}

fn turn(target: Target, axis: usize, degrees: f64) -> Change {
    Change::Turn {
        target,
        axis,
        degrees,
    }
}

fn hull(s: &Scene) -> DVec3 {
    s.geometry.bodies[0].vec3(0)
}

fn blade(s: &Scene) -> (DVec3, DVec3) {
    (s.geometry.bodies[1].vec3(0), s.geometry.bodies[1].vec3(3))
}

fn close(a: DVec3, b: DVec3) {
    assert!((a - b).length() < 1e-9, "{a} != {b}");
}

fn rz(deg: f64) -> DMat3 {
    DMat3::from_rotation_z(deg.to_radians())
}

/// Rotation about the vertical line through `c` by `deg`.
fn about(c: DVec3, deg: f64, p: DVec3) -> DVec3 {
    let r = rz(deg) * DVec3::new(p.x - c.x, p.y - c.y, 0.0);
    DVec3::new(c.x + r.x, c.y + r.y, p.z)
}

#[test]
fn paper_move_and_turn_about_an_axis_off_the_origin() {
    let t = timeline(vec![
        now(mv(Target::Object(HELI), 3.0, 0.0, -1.0)),
        Step::Shoot(1),
        now(turn(Target::Object(HELI), A, 15.0)),
        Step::Shoot(1),
    ]);
    assert_eq!(t.frame_count(), 2);
    let s0 = t.scene_at(&base(), 0);
    close(hull(&s0), DVec3::new(13.0, 0.0, 4.0));
    // The rotor is carried by the helicopter.
    close(blade(&s0).0, DVec3::new(13.0, 0.0, 6.0));
    let s1 = t.scene_at(&base(), 1);
    let c = DVec3::new(5.0, 0.0, 0.0);
    close(hull(&s1), about(c, 15.0, DVec3::new(13.0, 0.0, 4.0)));
    close(blade(&s1).0, about(c, 15.0, DVec3::new(13.0, 0.0, 6.0)));
    close(blade(&s1).1, rz(15.0) * DVec3::new(4.0, 0.0, 0.0));
    // The ground is in no object and stays put, bit for bit.
    assert_eq!(s1.geometry.bodies[2], base().geometry.bodies[2]);
}

#[test]
fn axis_moves_with_its_object() {
    let t = timeline(vec![
        now(mv(Target::Object(HELI), 0.0, 10.0, 0.0)),
        now(turn(Target::Object(HELI), OFFSET, 90.0)),
        Step::Shoot(1),
    ]);
    // OFFSET was carried to (12, 10): the hull at (10, 10) turns about it.
    let s = t.scene_at(&base(), 0);
    close(
        hull(&s),
        about(
            DVec3::new(12.0, 10.0, 0.0),
            90.0,
            DVec3::new(10.0, 10.0, 5.0),
        ),
    );
    close(hull(&s), DVec3::new(12.0, 8.0, 5.0));
    // A second turn uses the axis where the first turn left it (on its own
    // line, so it stays put).
    let t = timeline(vec![
        now(mv(Target::Object(HELI), 0.0, 10.0, 0.0)),
        now(turn(Target::Object(HELI), OFFSET, 90.0)),
        now(turn(Target::Object(HELI), OFFSET, 90.0)),
        Step::Shoot(1),
    ]);
    close(hull(&t.scene_at(&base(), 0)), DVec3::new(14.0, 10.0, 5.0));
}

#[test]
fn rotor_spins_while_the_helicopter_turns() {
    let t = timeline(vec![
        now(Change::Spin {
            object: ROTOR,
            axis: MAST,
            degrees_per_frame: 10.0,
        }),
        over(turn(Target::Object(HELI), A, 90.0), 9),
    ]);
    assert_eq!(t.frame_count(), 9);
    for f in 0..9 {
        let k = (f + 1) as f64;
        let heli = 10.0 * k;
        let s = t.scene_at(&base(), f);
        let c = DVec3::new(5.0, 0.0, 0.0);
        close(hull(&s), about(c, heli, DVec3::new(10.0, 0.0, 5.0)));
        // The mast is carried to the hull's x, y; the blade root sits on it,
        // and the blade points along the sum of both angles.
        let (v, h) = blade(&s);
        close(v, about(c, heli, DVec3::new(10.0, 0.0, 7.0)));
        close(h, rz(heli + 10.0 * k) * DVec3::new(4.0, 0.0, 0.0));
    }
}

#[test]
fn spin_continues_through_holds_and_stops() {
    let t = timeline(vec![
        now(Change::Spin {
            object: ROTOR,
            axis: MAST,
            degrees_per_frame: 10.0,
        }),
        Step::Shoot(9),
        now(Change::Stop { object: ROTOR }),
        Step::Shoot(3),
    ]);
    assert_eq!(t.frame_count(), 12);
    close(blade(&t.scene_at(&base(), 8)).1, DVec3::new(0.0, 4.0, 0.0));
    for f in 9..12 {
        close(blade(&t.scene_at(&base(), f)).1, DVec3::new(0.0, 4.0, 0.0));
    }
}

#[test]
fn camera_moves_turns_and_aims() {
    let t = timeline(vec![
        now(mv(Target::Camera, 1.0, 2.0, 3.0)),
        Step::Shoot(1),
        now(turn(Target::Camera, A, 90.0)),
        Step::Shoot(1),
        now(Change::Aim(AimPoint::Object(HELI))),
        Step::Shoot(1),
        now(Change::Aim(AimPoint::Point(DVec3::new(1.0, 1.0, 1.0)))),
        Step::Shoot(1),
    ]);
    let cam = |f| t.scene_at(&base(), f).camera.expect("camera");
    assert_eq!(cam(0).eye, DVec3::new(1.0, -48.0, 13.0));
    let c1 = cam(1);
    let c = DVec3::new(5.0, 0.0, 0.0);
    close(c1.eye, about(c, 90.0, DVec3::new(1.0, -48.0, 13.0)));
    close(c1.dir, rz(90.0) * DVec3::new(0.0, 50.0, -10.0));
    close(c1.up, DVec3::Z);
    // Centre of the helicopter: bounding box of the hull centre (10,0,5),
    // the blade root (10,0,7) and tip (14,0,7).
    close(cam(2).dir, DVec3::new(12.0, 0.0, 6.0) - c1.eye);
    close(cam(3).dir, DVec3::new(1.0, 1.0, 1.0) - c1.eye);
}

#[test]
fn lights_move_turn_and_dim() {
    let t = timeline(vec![
        now(mv(Target::Light(1), 1.0, 0.0, 0.0)),
        now(turn(Target::Light(0), X, 90.0)),
        Step::Shoot(1),
        over(
            Change::Intensity {
                light: 0,
                value: 0.5,
            },
            10,
        ),
    ]);
    let s = t.scene_at(&base(), 0);
    assert_eq!(
        s.lights[1].kind,
        LightKind::Point {
            pos: DVec3::new(1.0, 0.0, 20.0),
            decay: 2.0
        }
    );
    let LightKind::Parallel { dir } = s.lights[0].kind else {
        panic!("parallel light expected")
    };
    close(dir, DVec3::new(0.0, 1.0, 0.0));
    // Frame 5 is the 5th of 10 frames of the dimming.
    assert!((t.scene_at(&base(), 5).lights[0].intensity - 0.75).abs() < 1e-12);
    assert_eq!(t.scene_at(&base(), 10).lights[0].intensity, 0.5);
}

#[test]
fn over_interpolates_moves_and_angles() {
    let t = timeline(vec![
        over(mv(Target::Object(HELI), 30.0, 0.0, 0.0), 48),
        over(turn(Target::Object(HELI), A, 90.0), 3),
    ]);
    assert_eq!(t.frame_count(), 51);
    close(
        hull(&t.scene_at(&base(), 0)),
        DVec3::new(10.0 + 30.0 / 48.0, 0.0, 5.0),
    );
    close(hull(&t.scene_at(&base(), 23)), DVec3::new(25.0, 0.0, 5.0));
    assert_eq!(hull(&t.scene_at(&base(), 47)), DVec3::new(40.0, 0.0, 5.0));
    // The turn goes round the circle, 30 degrees a frame, not along a chord.
    let c = DVec3::new(5.0, 0.0, 0.0);
    for (f, deg) in [(48, 30.0), (49, 60.0), (50, 90.0)] {
        let p = hull(&t.scene_at(&base(), f));
        close(p, about(c, deg, DVec3::new(40.0, 0.0, 5.0)));
        assert!(((p - DVec3::new(5.0, 0.0, 5.0)).length() - 35.0).abs() < 1e-9);
    }
}

#[test]
fn smooth_easing_is_half_way_at_the_middle() {
    let t = timeline(vec![Step::Change(Timed {
        change: mv(Target::Object(HELI), 10.0, 0.0, 0.0),
        frames: 4,
        easing: Easing::Smooth,
    })]);
    close(hull(&t.scene_at(&base(), 1)), DVec3::new(15.0, 0.0, 5.0));
    close(
        hull(&t.scene_at(&base(), 0)),
        DVec3::new(10.0 + 10.0 * 0.15625, 0.0, 5.0),
    );
    assert_eq!(hull(&t.scene_at(&base(), 3)), DVec3::new(20.0, 0.0, 5.0));
}

#[test]
fn together_runs_changes_over_the_same_frames() {
    let t = timeline(vec![Step::Together(vec![
        Timed::over(mv(Target::Object(HELI), 10.0, 0.0, 0.0), 10),
        Timed::over(turn(Target::Object(ROTOR), MAST, 90.0), 5),
        Timed::over(Change::Zoom(Zoom::Fov(20.0)), 4),
    ])]);
    assert_eq!(t.frame_count(), 10);
    let s = t.scene_at(&base(), 1);
    close(hull(&s), DVec3::new(12.0, 0.0, 5.0));
    // The rotor turns about the mast where the helicopter has carried it.
    close(blade(&s).0, DVec3::new(12.0, 0.0, 7.0));
    close(blade(&s).1, rz(36.0) * DVec3::new(4.0, 0.0, 0.0));
    assert_eq!(
        s.camera.map(|c| c.lens),
        Some(Lens::Fov { vertical_deg: 30.0 })
    );
    let s = t.scene_at(&base(), 6);
    close(blade(&s).1, DVec3::new(0.0, 4.0, 0.0));
    close(hull(&s), DVec3::new(17.0, 0.0, 5.0));
}

#[test]
fn zoom_converts_a_field_of_view_to_a_focal_length() {
    let t = timeline(vec![over(
        Change::Zoom(Zoom::Focal {
            focal: 50.0,
            film_height: Some(24.0),
        }),
        2,
    )]);
    // 40 degrees on a 24-high film is a focal length of 12 / tan 20°.
    let f0 = 12.0 / 20f64.to_radians().tan();
    match t.scene_at(&base(), 0).camera.map(|c| c.lens) {
        Some(Lens::Focal { focal, film_height }) => {
            assert!((focal - (f0 + 50.0) / 2.0).abs() < 1e-9);
            assert_eq!(film_height, 24.0);
        }
        other => panic!("focal lens expected, got {other:?}"),
    }
}

#[test]
fn tracking_camera_follows_the_object() {
    let t = timeline(vec![
        now(Change::Track(Some(HELI))),
        over(mv(Target::Object(HELI), 0.0, 20.0, 0.0), 4),
    ]);
    for f in 0..4 {
        let s = t.scene_at(&base(), f);
        let cam = s.camera.expect("camera");
        let centre = DVec3::new(12.0, 5.0 * (f + 1) as f64, 6.0);
        close(cam.dir, centre - cam.eye);
    }
}

#[test]
fn repeat_and_hold_count_frames() {
    let t = timeline(vec![
        Step::Repeat(
            3,
            vec![over(turn(Target::Object(HELI), A, 90.0), 4), Step::Shoot(2)],
        ),
        Step::Shoot(1),
    ]);
    assert_eq!(t.frame_count(), 3 * (4 + 2) + 1);
    let t2 = timeline(vec![
        Step::Repeat(2, vec![Step::Repeat(3, vec![Step::Shoot(1)])]),
        Step::Shoot(24),
    ]);
    assert_eq!(t2.frame_count(), 30);
    // Changes that shoot nothing add no frames; an empty block repeated
    // without end costs nothing, a change repeated without end is refused.
    let t3 = timeline(vec![Step::Repeat(
        1000,
        vec![now(mv(Target::Camera, 0.0, 0.0, 0.0))],
    )]);
    assert_eq!(t3.frame_count(), 0);
    assert_eq!(
        timeline(vec![Step::Repeat(
            usize::MAX,
            vec![Step::Repeat(usize::MAX, vec![])]
        )])
        .frame_count(),
        0
    );
    let r = Timeline::new(
        spec(vec![Step::Repeat(
            usize::MAX,
            vec![now(mv(Target::Camera, 0.0, 0.0, 0.0))],
        )]),
        &base(),
    );
    assert_eq!(r.err(), Some(vec![DirectorError::TooLong]));
    // Four quarter turns bring the helicopter back.
    let t4 = timeline(vec![Step::Repeat(
        4,
        vec![over(turn(Target::Object(HELI), A, 90.0), 2)],
    )]);
    assert_eq!(t4.frame_count(), 8);
    close(hull(&t4.scene_at(&base(), 7)), DVec3::new(10.0, 0.0, 5.0));
    close(hull(&t4.scene_at(&base(), 1)), DVec3::new(5.0, 5.0, 5.0));
}

#[test]
fn too_long_a_film_is_refused() {
    let r = Timeline::new(
        spec(vec![Step::Repeat(2_000_000, vec![Step::Shoot(1)])]),
        &base(),
    );
    assert_eq!(r.err(), Some(vec![DirectorError::TooLong]));
}

#[test]
fn many_small_turns_do_not_drift() {
    let t = timeline(vec![Step::Repeat(
        3600,
        vec![now(turn(Target::Object(HELI), A, 0.1)), Step::Shoot(1)],
    )]);
    assert_eq!(t.frame_count(), 3600);
    let s = t.scene_at(&base(), 3599);
    close(hull(&s), DVec3::new(10.0, 0.0, 5.0));
    assert!(
        (s.geometry.bodies[0].params[3] - 1.0).abs() < 1e-12,
        "radius kept"
    );
}

fn everything() -> Vec<Step> {
    vec![
        now(Change::Spin {
            object: ROTOR,
            axis: MAST,
            degrees_per_frame: 17.0,
        }),
        Step::Shoot(2),
        Step::Repeat(
            3,
            vec![
                Step::Together(vec![
                    Timed::over(mv(Target::Object(HELI), 1.5, 2.25, 0.3), 7),
                    Timed {
                        change: turn(Target::Object(HELI), OFFSET, 33.0),
                        frames: 5,
                        easing: Easing::Smooth,
                    },
                    Timed::over(turn(Target::Camera, X, -3.0), 6),
                    Timed::now(Change::Aim(AimPoint::Object(ROTOR))),
                ]),
                over(
                    Change::Intensity {
                        light: 1,
                        value: 40.0,
                    },
                    3,
                ),
                Step::Shoot(2),
            ],
        ),
        now(Change::Track(Some(HELI))),
        over(turn(Target::Light(1), A, 45.0), 5),
        over(Change::Zoom(Zoom::Fov(25.0)), 4),
    ]
}

#[test]
fn frame_alone_equals_frame_of_a_sequential_run_bit_for_bit() {
    let t = timeline(everything());
    let b = base();
    let seq: Vec<Scene> = t.states().map(|s| t.scene_from_state(&b, &s)).collect();
    assert_eq!(seq.len(), t.frame_count());
    assert_eq!(t.frame_count(), 2 + 3 * (7 + 3 + 2) + 5 + 4);
    let bits = |s: &Scene| -> Vec<u64> {
        let mut v: Vec<u64> = s
            .geometry
            .bodies
            .iter()
            .flat_map(|b| b.params.iter().map(|x| x.to_bits()))
            .collect();
        let c = s.camera.expect("camera");
        v.extend(
            [c.eye, c.dir, c.up]
                .iter()
                .flat_map(|p| p.to_array())
                .map(f64::to_bits),
        );
        v.extend(s.lights.iter().map(|l| l.intensity.to_bits()));
        v
    };
    // In reverse, and each from a fresh timeline, and twice.
    for f in (0..t.frame_count()).rev() {
        let alone = timeline(everything()).scene_at(&b, f);
        assert_eq!(bits(&alone), bits(&seq[f]), "frame {f}");
        assert_eq!(alone, seq[f]);
        assert_eq!(bits(&t.scene_at(&b, f)), bits(&seq[f]));
    }
    // Consecutive frames differ: the film moves.
    assert_ne!(bits(&seq[0]), bits(&seq[1]));
}

#[test]
fn body_shared_by_objects_that_move_differently_is_refused() {
    let mut b = base();
    // The blade region also uses the hull body.
    b.geometry.regions[1] = region("blade", &[1, 0]);
    let e = Timeline::new(
        spec(vec![now(Change::Spin {
            object: ROTOR,
            axis: MAST,
            degrees_per_frame: 1.0,
        })]),
        &b,
    )
    .unwrap_err();
    assert_eq!(
        e,
        vec![DirectorError::SharedBody {
            body: 0,
            body_name: "hull".into(),
            first: Owner::Object("HELICOPTER".into()),
            second: Owner::Object("ROTOR".into()),
        }]
    );
    assert_eq!(
        e[0].to_string(),
        "body `hull` is shared by objects `HELICOPTER` and `ROTOR`, which move differently"
    );
    // When only the helicopter moves, both move together: allowed.
    assert!(Timeline::new(spec(vec![now(mv(Target::Object(HELI), 1.0, 0.0, 0.0))]), &b).is_ok());
    // A static region sharing a moving body.
    let mut b = base();
    b.geometry.regions[2] = region("ground", &[2, 0]);
    let e =
        Timeline::new(spec(vec![now(mv(Target::Object(HELI), 1.0, 0.0, 0.0))]), &b).unwrap_err();
    assert_eq!(
        e[0].to_string(),
        "body `hull` is shared by object `HELICOPTER`, which moves, and region `ground`, which is in no object"
    );
}

#[test]
fn containment_errors() {
    let mut s = spec(vec![]);
    s.objects[1].children = vec![HELI];
    assert_eq!(
        Timeline::new(s, &base()).unwrap_err(),
        vec![
            DirectorError::Cycle {
                object: 0,
                name: "HELICOPTER".into()
            },
            DirectorError::Cycle {
                object: 1,
                name: "ROTOR".into()
            }
        ]
    );
    let mut s = spec(vec![]);
    s.objects.push(Object {
        name: "OTHER".into(),
        regions: vec![],
        children: vec![ROTOR],
    });
    assert_eq!(
        Timeline::new(s, &base()).unwrap_err()[0].to_string(),
        "object `ROTOR` is contained in both `HELICOPTER` and `OTHER`"
    );
    let mut s = spec(vec![now(turn(Target::Object(7), 9, 1.0))]);
    s.axes[0].dir = DVec3::ZERO;
    let e = Timeline::new(s, &base()).unwrap_err();
    assert!(e.contains(&DirectorError::BadIndex {
        what: "object",
        index: 7
    }));
    assert!(e.contains(&DirectorError::BadIndex {
        what: "axis",
        index: 9
    }));
    assert!(e.contains(&DirectorError::BadAxis {
        axis: 0,
        name: "A".into()
    }));
}

#[test]
fn fingerprint_follows_the_film_and_the_scene() {
    let b = base();
    let a = timeline(everything()).fingerprint(&b);
    assert_eq!(a.len(), 64);
    assert_eq!(a, timeline(everything()).fingerprint(&b));
    let mut steps = everything();
    steps.push(Step::Shoot(1));
    assert_ne!(a, timeline(steps).fingerprint(&b));
    let mut b2 = base();
    b2.ambient = 0.3;
    assert_ne!(
        a,
        Timeline::new(spec(everything()), &b2)
            .expect("valid")
            .fingerprint(&b2)
    );
}

mod random_films {
    use super::*;
    use proptest::prelude::*;

    fn change() -> impl Strategy<Value = Change> {
        let v =
            || (-5.0..5.0f64, -5.0..5.0f64, -5.0..5.0f64).prop_map(|(x, y, z)| DVec3::new(x, y, z));
        let target = prop_oneof![
            Just(Target::Object(HELI)),
            Just(Target::Object(ROTOR)),
            Just(Target::Camera),
            Just(Target::Light(0)),
            Just(Target::Light(1))
        ];
        prop_oneof![
            (target.clone(), v()).prop_map(|(target, by)| Change::Move { target, by }),
            (target, 0..4usize, -200.0..200.0f64).prop_map(|(target, axis, degrees)| {
                Change::Turn {
                    target,
                    axis,
                    degrees,
                }
            }),
            (0..2usize, 0..4usize, -30.0..30.0f64).prop_map(|(object, axis, d)| Change::Spin {
                object,
                axis,
                degrees_per_frame: d
            }),
            (0..2usize).prop_map(|object| Change::Stop { object }),
            v().prop_map(|p| Change::Aim(AimPoint::Point(p))),
            (0..2usize).prop_map(|o| Change::Aim(AimPoint::Object(o))),
            (5.0..80.0f64).prop_map(|d| Change::Zoom(Zoom::Fov(d))),
            (0..2usize, 0.0..10.0f64).prop_map(|(light, value)| Change::Intensity { light, value }),
            prop_oneof![Just(None), Just(Some(HELI)), Just(Some(ROTOR))].prop_map(Change::Track),
        ]
    }

    fn timed() -> impl Strategy<Value = Timed> {
        (change(), 0..5usize, any::<bool>()).prop_map(|(change, frames, smooth)| Timed {
            change,
            frames,
            easing: if smooth {
                Easing::Smooth
            } else {
                Easing::Linear
            },
        })
    }

    fn step() -> impl Strategy<Value = Step> {
        let leaf = prop_oneof![
            timed().prop_map(Step::Change),
            (1..4usize).prop_map(Step::Shoot),
            proptest::collection::vec(timed(), 1..4).prop_map(Step::Together),
        ];
        leaf.prop_recursive(2, 16, 4, |inner| {
            (1..4usize, proptest::collection::vec(inner, 1..4))
                .prop_map(|(n, b)| Step::Repeat(n, b))
        })
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 128, .. ProptestConfig::default() })]

        /// Any film: every frame computed alone equals the same frame of a
        /// sequential run, bit for bit.
        #[test]
        fn any_frame_alone_equals_the_sequential_run(steps in proptest::collection::vec(step(), 1..8), order in any::<u64>()) {
            let t = timeline(steps);
            let b = base();
            let seq: Vec<Scene> = t.states().map(|s| t.scene_from_state(&b, &s)).collect();
            prop_assert_eq!(seq.len(), t.frame_count());
            let n = seq.len();
            for i in 0..n {
                // Visit the frames in a scrambled order.
                let f = (i.wrapping_mul(7919) + order as usize) % n;
                let alone = t.scene_at(&b, f);
                let same = alone.geometry.bodies.iter().zip(&seq[f].geometry.bodies).all(|(a, s)| {
                    a.kind == s.kind && a.params.iter().map(|x| x.to_bits()).eq(s.params.iter().map(|x| x.to_bits()))
                });
                prop_assert!(same, "bodies of frame {} differ", f);
                let bits = |c: &Option<Camera>| c.map(|c| [c.eye, c.dir, c.up].map(|p| p.to_array().map(f64::to_bits)));
                prop_assert_eq!(bits(&alone.camera), bits(&seq[f].camera));
                prop_assert_eq!(format!("{:?}", alone.camera.map(|c| c.lens)), format!("{:?}", seq[f].camera.map(|c| c.lens)));
                let lights = |s: &Scene| format!("{:?}", s.lights);
                prop_assert_eq!(lights(&alone), lights(&seq[f]));
            }
        }
    }
}
