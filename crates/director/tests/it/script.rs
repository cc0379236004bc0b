//! The director script language: parsing, name look-up, every diagnostic
//! with its exact text, and robustness against any input.

use crate::{region, sun_and_lamp};
use proptest::prelude::*;
use sv_director::*;
use sv_formats::native::{merge, Clash, MergeError};
use sv_formats::script::build_timeline;
use sv_formats::SourceFile;
use sv_geom::{Body, BodyKind};
use sv_math::DVec3;
use sv_scene::{Camera, Lens, RegionProps, Scene};

/// fuselage (sphere at (1,0,2)), hub, blade, ground; SUN and LAMP; a camera.
pub(super) fn scene() -> Scene {
    let mut s = Scene::default();
    s.geometry.bodies = vec![
        Body::new("f", BodyKind::Sph, vec![1.0, 0.0, 2.0, 1.0]),
        Body::new("h", BodyKind::Rcc, vec![0.0, 0.0, 3.0, 0.0, 0.0, 0.5, 0.3]),
        Body::new(
            "b",
            BodyKind::Box,
            vec![0.0, -0.1, 3.2, 4.0, 0.0, 0.0, 0.0, 0.2, 0.0, 0.0, 0.0, 0.05],
        ),
        Body::new(
            "g",
            BodyKind::Rpp,
            vec![-50.0, 50.0, -50.0, 50.0, -1.0, 0.0],
        ),
    ];
    for (n, b) in [("fuselage", 0), ("hub", 1), ("blade", 2), ("ground", 3)] {
        s.push_region(region(n, &[b]), RegionProps::default());
    }
    s.camera = Some(Camera::looking_at(
        DVec3::new(30.0, -30.0, 10.0),
        DVec3::ZERO,
        DVec3::Z,
        Lens::Fov { vertical_deg: 40.0 },
    ));
    s.lights = sun_and_lamp(DVec3::new(1.0, 1.0, -1.0), 50.0);
    s
}

pub(super) const HEADER: &str = "SCENE \"heli.sv\"
OBJECT ROTOR REGIONS hub blade
OBJECT HELICOPTER REGIONS fuselage CONTAINS ROTOR
AXIS 1 POINT (1,0,0) DIR (0,0,1) ON HELICOPTER
AXIS MAST POINT (0,0,0) DIR (0,0,1) ON HELICOPTER
";

pub(super) fn build(text: &str, scene: &Scene) -> Result<Timeline, String> {
    let src = SourceFile::new("film.svs", text);
    build_timeline(&src, scene).map_err(|d| d.render_plain())
}

pub(super) fn errors(text: &str) -> String {
    errors_in(text, &scene())
}

pub(super) fn errors_in(text: &str, scene: &Scene) -> String {
    match build(text, scene) {
        Ok(_) => "no error".into(),
        Err(e) => e,
    }
}

// One test per diagnostic of the language, with its exact text. Each
// script is the standard header (lines 1-5) and the lines shown.

#[test]
fn diagnostic_unknown_command() {
    let text = format!("{HEADER}{}\n", "MOVEE HELICOPTER (1,0,0)");
    assert_eq!(errors(&text), "error: unknown command `MOVEE`\n --> film.svs:6:1\n  |\n6 | MOVEE HELICOPTER (1,0,0)\n  | ^^^^^\n  = hint: did you mean `MOVE`?\n");
}

#[test]
fn diagnostic_expected_number() {
    let text = format!("{HEADER}{}\n", "MOVE HELICOPTER (1,x,0)");
    assert_eq!(errors(&text), "error: expected a number, found `x`\n --> film.svs:6:20\n  |\n6 | MOVE HELICOPTER (1,x,0)\n  |                    ^\n");
}

#[test]
fn diagnostic_number_missing_at_end() {
    let text = format!("{HEADER}{}\n", "MOVE HELICOPTER (1,0");
    assert_eq!(errors(&text), "error: expected a number, found the end of the line\n --> film.svs:6:21\n  |\n6 | MOVE HELICOPTER (1,0\n  |                     ^\n");
}

#[test]
fn diagnostic_expected_paren() {
    let text = format!("{HEADER}{}\n", "TURN HELICOPTER AXIS 1 15");
    assert_eq!(errors(&text), "error: expected `(`, found `AXIS`\n --> film.svs:6:17\n  |\n6 | TURN HELICOPTER AXIS 1 15\n  |                 ^^^^\n");
}

#[test]
fn diagnostic_unexpected_after() {
    let text = format!("{HEADER}{}\n", "SHOOT 2 FRAMES");
    assert_eq!(errors(&text), "error: unexpected `FRAMES` at the end of the statement\n --> film.svs:6:9\n  |\n6 | SHOOT 2 FRAMES\n  |         ^^^^^^\n");
}

#[test]
fn diagnostic_end_without_block() {
    let text = format!("{HEADER}{}\n", "END");
    assert_eq!(
        errors(&text),
        "error: END without REPEAT or TOGETHER\n --> film.svs:6:1\n  |\n6 | END\n  | ^^^\n"
    );
}

#[test]
fn diagnostic_repeat_without_end() {
    let text = format!("{HEADER}{}\n", "REPEAT 2\nSHOOT");
    assert_eq!(errors(&text), "error: REPEAT without END\n --> film.svs:6:1\n  |\n6 | REPEAT 2\n  | ^^^^^^\n  = hint: close the block with `END`\n");
}

#[test]
fn diagnostic_together_without_end() {
    let text = format!("{HEADER}{}\n", "TOGETHER\nMOVE HELICOPTER (1,0,0) OVER 4");
    assert_eq!(errors(&text), "error: TOGETHER without END\n --> film.svs:6:1\n  |\n6 | TOGETHER\n  | ^^^^^^^^\n  = hint: close the block with `END`\n");
}

#[test]
fn diagnostic_shoot_inside_together() {
    let text = format!("{HEADER}{}\n", "TOGETHER\nSHOOT\nEND");
    assert_eq!(errors(&text), "error: SHOOT cannot be used inside TOGETHER\n --> film.svs:7:1\n  |\n7 | SHOOT\n  | ^^^^^\n  = hint: TOGETHER holds changes that run over the same frames; put this before or after the block\n");
}

#[test]
fn diagnostic_fps_twice() {
    let text = format!("{HEADER}{}\n", "FPS 24\nFPS 25");
    assert_eq!(
        errors(&text),
        "error: FPS is already set on line 6\n --> film.svs:7:1\n  |\n7 | FPS 25\n  | ^^^\n"
    );
}

#[test]
fn diagnostic_size_twice() {
    let text = format!("{HEADER}{}\n", "SIZE 320 240\nSIZE 640 480");
    assert_eq!(errors(&text), "error: SIZE is already set on line 6\n --> film.svs:7:1\n  |\n7 | SIZE 640 480\n  | ^^^^\n");
}

#[test]
fn diagnostic_camera_twice() {
    let text = format!(
        "{HEADER}{}\n",
        "CAMERA EYE (1,2,3) AT (0,0,0)\nCAMERA EYE (1,2,3) AT (0,0,0)"
    );
    assert_eq!(errors(&text), "error: CAMERA is already set on line 6\n --> film.svs:7:1\n  |\n7 | CAMERA EYE (1,2,3) AT (0,0,0)\n  | ^^^^^^\n");
}

#[test]
fn diagnostic_unterminated_string() {
    let text = format!("{HEADER}{}\n", "SCENE \"other.sv");
    assert_eq!(errors(&text), "error: unterminated string\n --> film.svs:6:7\n  |\n6 | SCENE \"other.sv\n  |       ^^^^^^^^^\n  = hint: close it with `\"`\n");
}

#[test]
fn diagnostic_scene_not_quoted() {
    let text = format!("{HEADER}{}\n", "SCENE other.sv");
    assert_eq!(errors(&text), "error: expected a quoted file name, found `other.sv`\n --> film.svs:6:7\n  |\n6 | SCENE other.sv\n  |       ^^^^^^^^\n");
}

#[test]
fn diagnostic_hold_zero() {
    let text = format!("{HEADER}{}\n", "HOLD 0");
    assert_eq!(errors(&text), "error: expected a whole number of frames from 1 to 1000000, found `0`\n --> film.svs:6:6\n  |\n6 | HOLD 0\n  |      ^\n");
}

#[test]
fn diagnostic_fractional_frames() {
    let text = format!("{HEADER}{}\n", "MOVE HELICOPTER (1,0,0) OVER 2.5 FRAMES");
    assert_eq!(errors(&text), "error: expected a whole number of frames from 1 to 1000000, found `2.5`\n --> film.svs:6:30\n  |\n6 | MOVE HELICOPTER (1,0,0) OVER 2.5 FRAMES\n  |                              ^^^\n");
}

#[test]
fn diagnostic_negative_seconds() {
    let text = format!("{HEADER}{}\n", "MOVE HELICOPTER (1,0,0) OVER -1 SECONDS");
    assert_eq!(errors(&text), "error: expected a number of seconds above 0, found `-1`\n --> film.svs:6:30\n  |\n6 | MOVE HELICOPTER (1,0,0) OVER -1 SECONDS\n  |                              ^^\n");
}

#[test]
fn diagnostic_fps_zero() {
    let text = format!("{HEADER}{}\n", "FPS 0");
    assert_eq!(errors(&text), "error: expected a frame rate above 0, found `0`\n --> film.svs:6:5\n  |\n6 | FPS 0\n  |     ^\n");
}

#[test]
fn diagnostic_size_zero() {
    let text = format!("{HEADER}{}\n", "SIZE 0 10");
    assert_eq!(errors(&text), "error: expected a width in pixels from 1 to 65536, found `0`\n --> film.svs:6:6\n  |\n6 | SIZE 0 10\n  |      ^\n");
}

#[test]
fn diagnostic_axis_zero() {
    let text = format!("{HEADER}{}\n", "AXIS 2 POINT (0,0,0) DIR (0,0,0)");
    assert_eq!(errors(&text), "error: the axis direction must not be zero\n --> film.svs:6:22\n  |\n6 | AXIS 2 POINT (0,0,0) DIR (0,0,0)\n  |                      ^^^\n");
}

#[test]
fn diagnostic_axis_point_missing() {
    let text = format!("{HEADER}{}\n", "AXIS 2 (0,0,0) DIR (0,0,1)");
    assert_eq!(errors(&text), "error: expected `POINT`, found `(`\n --> film.svs:6:8\n  |\n6 | AXIS 2 (0,0,0) DIR (0,0,1)\n  |        ^\n");
}

#[test]
fn diagnostic_zoom_what() {
    let text = format!("{HEADER}{}\n", "ZOOM CAMERA WIDE 3");
    assert_eq!(errors(&text), "error: expected `FOV`, `FOCAL` or `HEIGHT`, found `WIDE`\n --> film.svs:6:13\n  |\n6 | ZOOM CAMERA WIDE 3\n  |             ^^^^\n");
}

#[test]
fn diagnostic_negative_intensity() {
    let text = format!("{HEADER}{}\n", "INTENSITY SUN -1");
    assert_eq!(errors(&text), "error: an intensity cannot be negative\n --> film.svs:6:15\n  |\n6 | INTENSITY SUN -1\n  |               ^^\n");
}

#[test]
fn diagnostic_repeat_count() {
    let text = format!("{HEADER}{}\n", "REPEAT many\nEND");
    assert_eq!(errors(&text), "error: expected a repeat count from 1 to 1000000, found `many`\n --> film.svs:6:8\n  |\n6 | REPEAT many\n  |        ^^^^\n");
}

#[test]
fn diagnostic_not_a_command() {
    let text = format!("{HEADER}{}\n", "(1,2,3)");
    assert_eq!(
        errors(&text),
        "error: expected a command, found `(`\n --> film.svs:6:1\n  |\n6 | (1,2,3)\n  | ^\n"
    );
}

#[test]
fn diagnostic_contains_nothing() {
    let text = format!("{HEADER}{}\n", "OBJECT TAIL REGIONS ground CONTAINS");
    assert_eq!(errors(&text), "error: expected an object name, found the end of the line\n --> film.svs:6:36\n  |\n6 | OBJECT TAIL REGIONS ground CONTAINS\n  |                                    ^\n");
}

#[test]
fn diagnostic_unknown_object() {
    let text = format!("{HEADER}{}\n", "AIM CAMERA AT HELICOPTR");
    assert_eq!(errors(&text), "error: unknown object `HELICOPTR`\n --> film.svs:6:15\n  |\n6 | AIM CAMERA AT HELICOPTR\n  |               ^^^^^^^^^\n  = hint: did you mean `HELICOPTER`?\n");
}

#[test]
fn diagnostic_unknown_target() {
    let text = format!("{HEADER}{}\n", "MOVE HELICOPTR (1,0,0)");
    assert_eq!(errors(&text), "error: unknown object or light `HELICOPTR`\n --> film.svs:6:6\n  |\n6 | MOVE HELICOPTR (1,0,0)\n  |      ^^^^^^^^^\n  = hint: did you mean `HELICOPTER`?\n");
}

#[test]
fn diagnostic_unknown_axis() {
    let text = format!("{HEADER}{}\n", "TURN HELICOPTER (AXIS 2,15)");
    assert_eq!(errors(&text), "error: unknown axis `2`\n --> film.svs:6:23\n  |\n6 | TURN HELICOPTER (AXIS 2,15)\n  |                       ^\n  = hint: did you mean `1`?\n");
}

#[test]
fn diagnostic_unknown_region() {
    let text = format!("{HEADER}{}\n", "OBJECT TAIL REGIONS fuselag");
    assert_eq!(errors(&text), "error: unknown region `fuselag`\n --> film.svs:6:21\n  |\n6 | OBJECT TAIL REGIONS fuselag\n  |                     ^^^^^^^\n  = hint: did you mean `fuselage`?\n");
}

#[test]
fn diagnostic_unknown_light() {
    let text = format!("{HEADER}{}\n", "INTENSITY LIGHT SUNN 0.5");
    assert_eq!(errors(&text), "error: unknown light `SUNN`\n --> film.svs:6:17\n  |\n6 | INTENSITY LIGHT SUNN 0.5\n  |                 ^^^^\n  = hint: did you mean `SUN`?\n");
}

#[test]
fn diagnostic_object_twice() {
    let text = format!("{HEADER}{}\n", "OBJECT ROTOR REGIONS ground");
    assert_eq!(errors(&text), "error: object `ROTOR` is already declared on line 2\n --> film.svs:6:8\n  |\n6 | OBJECT ROTOR REGIONS ground\n  |        ^^^^^\n");
}

#[test]
fn diagnostic_axis_twice() {
    let text = format!("{HEADER}{}\n", "AXIS mast POINT (0,0,0) DIR (1,0,0)");
    assert_eq!(errors(&text), "error: axis `mast` is already declared on line 5\n --> film.svs:6:6\n  |\n6 | AXIS mast POINT (0,0,0) DIR (1,0,0)\n  |      ^^^^\n");
}

#[test]
fn diagnostic_parallel_light_moved() {
    let text = format!("{HEADER}{}\n", "MOVE LIGHT SUN (1,0,0)");
    assert_eq!(errors(&text), "error: light `SUN` is parallel and cannot be moved\n --> film.svs:6:12\n  |\n6 | MOVE LIGHT SUN (1,0,0)\n  |            ^^^\n  = hint: TURN it about an axis to change its direction\n");
}

#[test]
fn diagnostic_zoom_height_on_perspective() {
    let text = format!("{HEADER}{}\n", "ZOOM HEIGHT 20");
    assert_eq!(errors(&text), "error: ZOOM HEIGHT needs an orthographic camera\n --> film.svs:6:1\n  |\n6 | ZOOM HEIGHT 20\n  | ^^^^\n");
}

#[test]
fn diagnostic_contained_twice() {
    let text = format!("{HEADER}{}\n", "OBJECT OTHER REGIONS ground CONTAINS ROTOR");
    assert_eq!(errors(&text), "error: object `ROTOR` is contained in both `HELICOPTER` and `OTHER`\n --> film.svs:6:38\n  |\n6 | OBJECT OTHER REGIONS ground CONTAINS ROTOR\n  |                                      ^^^^^\n");
}

#[test]
fn diagnostic_contains_itself() {
    let text = format!("{HEADER}{}\n", "OBJECT A CONTAINS B\nOBJECT B CONTAINS A");
    assert_eq!(errors(&text), "error: object `A` contains itself\n --> film.svs:6:8\n  |\n6 | OBJECT A CONTAINS B\n  |        ^\n\nerror: object `B` contains itself\n --> film.svs:7:8\n  |\n7 | OBJECT B CONTAINS A\n  |        ^\n");
}

#[test]
fn diagnostic_shared_body() {
    let text = format!(
        "{HEADER}{}\n",
        "OBJECT HULL REGIONS fuselage\nMOVE HELICOPTER (1,0,0)"
    );
    assert_eq!(errors(&text), "error: body `f` is shared by objects `HELICOPTER` and `HULL`, which move differently\n --> film.svs:6:8\n  |\n6 | OBJECT HULL REGIONS fuselage\n  |        ^^^^\n  = hint: give each object its own copy of the body\n");
}
#[test]
fn diagnostic_no_scene() {
    assert_eq!(
        errors("FPS 24\n"),
        "error: the script names no scene\n --> film.svs:1:1\n  |\n1 | FPS 24\n  | ^\n  = hint: start the script with `SCENE \"file.sv\"`\n"
    );
}

#[test]
fn diagnostic_camera_not_set() {
    let mut s = scene();
    s.camera = None;
    let text = format!("{HEADER}AIM CAMERA AT HELICOPTER\nMOVE CAMERA (1,0,0)\n");
    // Reported once, at the first command that needs the camera.
    assert_eq!(
        errors_in(&text, &s),
        "error: the camera is not set: the scene has no CAMERA and the script none\n --> film.svs:6:1\n  |\n6 | AIM CAMERA AT HELICOPTER\n  | ^^^\n  = hint: add `CAMERA EYE (x,y,z) AT (x,y,z)` to the script\n"
    );
    // A CAMERA line in the script provides it.
    let text = format!("{HEADER}CAMERA EYE (0,-10,2) AT (0,0,2) FOCAL 35 FILM 24\nAIM CAMERA AT HELICOPTER\nSHOOT\n");
    let t = build(&text, &s).expect("valid");
    let cam = t.scene_at(&s, 0).camera.expect("camera");
    assert_eq!(cam.eye, DVec3::new(0.0, -10.0, 2.0));
    assert_eq!(
        cam.lens,
        Lens::Focal {
            focal: 35.0,
            film_height: 24.0
        }
    );
}

#[test]
fn diagnostic_zoom_fov_on_orthographic_camera() {
    let mut s = scene();
    s.camera = Some(Camera::looking_at(
        DVec3::new(0.0, -10.0, 0.0),
        DVec3::ZERO,
        DVec3::Z,
        Lens::Ortho { height: 10.0 },
    ));
    assert_eq!(
        errors_in(&format!("{HEADER}ZOOM FOV 20 OVER 4\nZOOM CAMERA HEIGHT 5 OVER 4\n"), &s),
        "error: ZOOM FOV needs a perspective camera\n --> film.svs:6:1\n  |\n6 | ZOOM FOV 20 OVER 4\n  | ^^^^\n"
    );
}

#[test]
fn every_error_is_reported_at_once_in_file_order() {
    let text = format!("{HEADER}MOVE HELICOPTR (1,0,0)\nSPIN ROTOR (AXIS 9, 10)\nSHOOT 0\nTURN HELICOPTER (MAST 15)\nFLY HELICOPTER\n");
    let e = errors(&text);
    let heads: Vec<&str> = e.lines().filter(|l| l.starts_with("error")).collect();
    assert_eq!(
        heads,
        [
            "error: unknown object or light `HELICOPTR`",
            "error: unknown axis `9`",
            "error: expected a whole number of frames from 1 to 1000000, found `0`",
            "error: unknown command `FLY`",
        ]
    );
}

#[test]
fn a_broken_declaration_is_reported_once() {
    let text = format!("{HEADER}AXIS 7 POINT (0,0,x) DIR (0,0,1)\nTURN HELICOPTER (AXIS 7, 10)\nOBJECT TAIL REGIONS ground CONTAINS\nMOVE TAIL (1,0,0)\n");
    let e = errors(&text);
    let heads: Vec<&str> = e.lines().filter(|l| l.starts_with("error")).collect();
    assert_eq!(
        heads,
        [
            "error: expected a number, found `x`",
            "error: expected an object name, found the end of the line"
        ]
    );
}

#[test]
fn missing_scene_file_is_reported_at_its_name() {
    let dir = tempfile::tempdir().expect("temp dir");
    let text = "SCENE \"nowhere.sv\"\nOBJECT X REGIONS a\nSHOOT\n";
    let src = SourceFile::new("film.svs", text);
    let r = sv_formats::script::load_source(&src, dir.path(), &Default::default());
    match r {
        Err(sv_formats::script::ScriptError::Invalid(d)) => assert_eq!(
            d.render_plain(),
            "error: cannot read scene `nowhere.sv`: No such file or directory (os error 2)\n --> film.svs:1:7\n  |\n1 | SCENE \"nowhere.sv\"\n  |       ^^^^^^^^^^^^\n"
        ),
        other => panic!("expected diagnostics, got {other:?}"),
    }
    let r = sv_formats::script::load_script(&dir.path().join("none.svs"), &Default::default());
    assert!(matches!(r, Err(sv_formats::script::ScriptError::Io { .. })));
}

#[test]
fn scenes_merge_with_shifted_body_references() {
    let mut m = scene();
    let mut b = Scene::default();
    b.geometry.bodies = vec![Body::new("gun", BodyKind::Sph, vec![5.0, 5.0, 0.5, 0.5])];
    b.push_region(region("gun_base", &[0]), RegionProps::default());
    merge(&mut m, b.clone(), "b", Clash::Refuse).expect("merge");
    assert_eq!(m.geometry.bodies.len(), 5);
    let r = m.geometry.region_index("gun_base").expect("region");
    assert_eq!(m.geometry.regions[r].zones[0].terms[0].body, 4);
    assert_eq!(m.regions.len(), m.geometry.regions.len());
    assert!(m.camera.is_some());
    b.geometry.regions[0].name = "hub".into();
    let mut a = scene();
    assert_eq!(
        merge(&mut a, b, "b", Clash::Refuse),
        Err(MergeError::Region("hub".to_string()))
    );
    assert_eq!(a, scene());
}

const FILM: &str = r#"* A film of the test scene.
SCENE "heli.sv"   # the scene
fps 12
Size 320 240
object rotor regions HUB, blade
OBJECT helicopter REGIONS fuselage CONTAINS rotor
AXIS 1 POINT (1,0,0) DIR (0,0,1) ON HELICOPTER
axis MAST point (0 0 0) dir (0 0 1) on helicopter
AXIS X POINT (0,0,0) DIR (1,0,0)

MOVE HELICOPTER (3,0,-1)
TURN HELICOPTER (AXIS 1,15)
SHOOT
spin Rotor (mast, 30) per frame
MOVE HELICOPTER (30,0,0) OVER 2 SECONDS SMOOTH
TOGETHER
  TURN CAMERA (AXIS X, 10) OVER 6
  MOVE LAMP (0,0,-5) OVER 12 FRAMES
  INTENSITY SUN 0.5 OVER 3
  ZOOM FOV 30 OVER 4
  AIM CAMERA AT HELICOPTER
END
REPEAT 2 TIMES
  TURN HELICOPTER (MAST, 90) OVER 3
  HOLD 2
END
TRACK CAMERA HELICOPTER
STOP ROTOR
FRAME 2
STOP CAMERA
AIM AT (0,0,0) OVER 2
"#;

#[test]
fn a_script_declares_its_rate_size_objects_and_axes() {
    let s = scene();
    let t = build(FILM, &s).expect("valid script");
    assert_eq!(t.fps(), 12.0);
    assert_eq!(t.size(), Some((320, 240)));
    assert_eq!(t.frame_count(), 1 + 24 + 12 + 2 * (3 + 2) + 2 + 2);
    let spec = t.spec();
    assert_eq!(
        spec.objects[0],
        Object {
            name: "rotor".into(),
            regions: vec![1, 2],
            children: vec![]
        }
    );
    assert_eq!(
        spec.objects[1],
        Object {
            name: "helicopter".into(),
            regions: vec![0],
            children: vec![0]
        }
    );
    assert_eq!(
        spec.axes[1],
        Axis {
            name: "MAST".into(),
            point: DVec3::ZERO,
            dir: DVec3::Z,
            on: Some(1)
        }
    );
}

#[test]
fn a_script_lists_its_steps_in_order() {
    let s = scene();
    let t = build(FILM, &s).expect("valid script");
    let spec = t.spec();
    let m = |x, y, z| Change::Move {
        target: Target::Object(1),
        by: DVec3::new(x, y, z),
    };
    assert_eq!(spec.steps[0], Step::Change(Timed::now(m(3.0, 0.0, -1.0))));
    assert_eq!(
        spec.steps[1],
        Step::Change(Timed::now(Change::Turn {
            target: Target::Object(1),
            axis: 0,
            degrees: 15.0
        }))
    );
    assert_eq!(spec.steps[2], Step::Shoot(1));
    assert_eq!(
        spec.steps[3],
        Step::Change(Timed::now(Change::Spin {
            object: 0,
            axis: 1,
            degrees_per_frame: 30.0
        }))
    );
    assert_eq!(
        spec.steps[4],
        Step::Change(Timed {
            change: m(30.0, 0.0, 0.0),
            frames: 24,
            easing: Easing::Smooth
        })
    );
    assert_eq!(
        spec.steps[5],
        Step::Together(vec![
            Timed::over(
                Change::Turn {
                    target: Target::Camera,
                    axis: 2,
                    degrees: 10.0
                },
                6
            ),
            Timed::over(
                Change::Move {
                    target: Target::Light(1),
                    by: DVec3::new(0.0, 0.0, -5.0)
                },
                12
            ),
            Timed::over(
                Change::Intensity {
                    light: 0,
                    value: 0.5
                },
                3
            ),
            Timed::over(Change::Zoom(Zoom::Fov(30.0)), 4),
            Timed::now(Change::Aim(AimPoint::Object(1))),
        ])
    );
    assert_eq!(
        spec.steps[6],
        Step::Repeat(
            2,
            vec![
                Step::Change(Timed::over(
                    Change::Turn {
                        target: Target::Object(1),
                        axis: 1,
                        degrees: 90.0
                    },
                    3
                )),
                Step::Shoot(2)
            ]
        )
    );
    assert_eq!(
        spec.steps[7..],
        [
            Step::Change(Timed::now(Change::Track(Some(1)))),
            Step::Change(Timed::now(Change::Stop { object: 0 })),
            Step::Shoot(2),
            Step::Change(Timed::now(Change::Track(None))),
            Step::Change(Timed::over(Change::Aim(AimPoint::Point(DVec3::ZERO)), 2)),
        ]
    );
}

#[test]
fn the_first_frame_of_a_script_is_the_papers() {
    let s = scene();
    let t = build(FILM, &s).expect("valid script");
    // The paper's first frame: moved by (3,0,-1), then turned 15 degrees
    // about AXIS 1, which the move carried to the vertical through (4, 0).
    let f0 = t.scene_at(&s, 0);
    let v = f0.geometry.bodies[2].vec3(0);
    let rel =
        sv_math::DMat3::from_rotation_z(15f64.to_radians()) * DVec3::new(3.0 - 4.0, -0.1, 0.0);
    let expect = DVec3::new(4.0 + rel.x, rel.y, 2.2);
    assert!((v - expect).length() < 1e-12, "{v} != {expect}");
    assert!((f0.geometry.bodies[0].vec3(0) - DVec3::new(4.0, 0.0, 1.0)).length() < 1e-12);
}

#[test]
fn over_seconds_uses_the_frame_rate_declared_anywhere() {
    let s = scene();
    let t = build(
        &format!("{HEADER}MOVE HELICOPTER (1,0,0) OVER 1.5 SECONDS\nFPS 10\n"),
        &s,
    )
    .expect("valid");
    assert_eq!(t.frame_count(), 15);
}

/// Random edits of a valid script: dropped, doubled, swapped and cut
/// characters, spliced keywords and junk. The reader must never panic and
/// must either build a timeline or report at least one error.
fn mutate(text: &str, edits: &[(usize, u8, u8)]) -> String {
    const JUNK: &[&str] = &[
        "(",
        ")",
        ",",
        "\"",
        "#",
        "*",
        "END",
        "REPEAT 3",
        "TOGETHER",
        "OVER",
        "0",
        "-1",
        "1e309",
        "NaN",
        "inf",
        "AXIS",
        "\n",
        "é",
        "CONTAINS",
        "99999999999999999999",
    ];
    let mut chars: Vec<char> = text.chars().collect();
    for &(pos, kind, pick) in edits {
        if chars.is_empty() {
            break;
        }
        let i = pos % chars.len();
        match kind % 5 {
            0 => {
                chars.remove(i);
            }
            1 => {
                let c = chars[i];
                chars.insert(i, c);
            }
            2 => {
                let j = (i + pick as usize) % chars.len();
                chars.swap(i, j);
            }
            3 => chars.truncate(i),
            _ => {
                let junk = JUNK[pick as usize % JUNK.len()];
                for (k, c) in junk.chars().enumerate() {
                    chars.insert(i + k, c);
                }
            }
        }
    }
    chars.into_iter().collect()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, .. ProptestConfig::default() })]

    #[test]
    fn mutated_scripts_never_panic(edits in proptest::collection::vec((0usize..4096, 0u8..255, 0u8..255), 1..8)) {
        let text = mutate(FILM, &edits);
        let s = scene();
        match build(&text, &s) {
            Ok(t) => {
                // Whatever was built can be evaluated.
                let n = t.frame_count();
                for f in [0, n / 2, n.saturating_sub(1), n] {
                    let _ = t.scene_at(&s, f);
                }
            }
            Err(e) => prop_assert!(e.starts_with("error: "), "{}", e),
        }
    }

    #[test]
    fn arbitrary_text_never_panics(text in "\\PC{0,200}") {
        let _ = build(&text, &scene());
    }
}
