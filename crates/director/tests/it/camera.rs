//! CAMERA, LIGHT and the lens of ZOOM: one grammar, read alike by scenes
//! and scripts, with the same diagnostics.

use super::script::{build, errors, errors_in, scene, HEADER};
use sv_formats::{load_source, Format, LoadError, LoadOptions, SourceFile};
use sv_math::DVec3;
use sv_scene::{Camera, Lens};

/// A scene made of `line` (after a region, since a scene without one is
/// refused): its camera, or the message and hint of its first error
/// (`error: …` and `= hint: …` lines).
fn in_scene(line: &str) -> Result<Option<Camera>, Vec<String>> {
    let text = format!("BODY a SPH (0,0,0) 1\nREGION r = +a\n{line}\n");
    let src = SourceFile::new("scene.sv", text);
    match load_source(&src, Format::Native, &LoadOptions::default()) {
        Ok(loaded) => Ok(loaded.scene.camera),
        Err(LoadError::Invalid(d)) => Err(message_and_hint(&d.render_plain())),
        Err(e) => panic!("{e}"),
    }
}

/// A script with `line` after the standard header: its camera, or the
/// message and hint of its first error.
fn in_script(line: &str) -> Result<Option<Camera>, Vec<String>> {
    let s = scene();
    match build(&format!("{HEADER}{line}\nSHOOT\n"), &s) {
        Ok(t) => Ok(t.scene_at(&s, 0).camera),
        Err(text) => Err(message_and_hint(&text)),
    }
}

fn message_and_hint(rendered: &str) -> Vec<String> {
    rendered
        .lines()
        .filter(|l| l.starts_with("error") || l.contains("= hint"))
        .take(2)
        .map(|l| l.trim().to_string())
        .collect()
}

/// Both readers give the same result for `line`.
fn alike(line: &str) -> Result<Option<Camera>, Vec<String>> {
    let scene = in_scene(line);
    assert_eq!(scene, in_script(line), "{line}");
    scene
}

#[test]
fn a_field_of_view_past_180_degrees_is_refused_in_both() {
    assert_eq!(
        alike("CAMERA EYE (0,-10,2) AT (0,0,2) FOV 200"),
        Err(vec![
            "error: field of view must lie between 0 and 180 degrees (is 200)".to_string(),
            "= hint: FOV is the vertical angle the picture spans, in degrees".to_string(),
        ])
    );
    // Located at the value.
    assert_eq!(
        errors(&format!("{HEADER}CAMERA EYE (0,-10,2) AT (0,0,2) FOV 200\n")),
        "error: field of view must lie between 0 and 180 degrees (is 200)\n --> film.svs:6:37\n  |\n6 | CAMERA EYE (0,-10,2) AT (0,0,2) FOV 200\n  |                                     ^^^\n  = hint: FOV is the vertical angle the picture spans, in degrees\n"
    );
}

#[test]
fn the_readme_orthographic_camera_reads_in_both() {
    let camera = alike("CAMERA ORTHO EYE (10,10,10) AT (0,0,0) HEIGHT 12")
        .unwrap()
        .unwrap();
    assert_eq!(camera.lens, Lens::Ortho { height: 12.0 });
    assert_eq!(camera.dir, DVec3::splat(-10.0));
    // The short form scripts used, `ORTHO height`, is the same camera.
    assert_eq!(
        alike("CAMERA EYE (10,10,10) AT (0,0,0) ORTHO 12"),
        Ok(Some(camera))
    );
}

#[test]
fn a_focal_length_needs_a_film_height_in_both() {
    let hint =
        "= hint: write both, in the same units: `FOCAL 50 FILM 24` is a 50 mm lens on 35 mm film";
    assert_eq!(
        alike("CAMERA EYE (0,-10,2) AT (0,0,2) FOCAL 50"),
        Err(vec![
            "error: FOCAL needs FILM (the film height) and FILM needs FOCAL".to_string(),
            hint.to_string(),
        ])
    );
    let camera = alike("CAMERA EYE (0,-10,2) DIR (0,1,0) FOCAL 50 FILM 36")
        .unwrap()
        .unwrap();
    assert_eq!(
        camera.lens,
        Lens::Focal {
            focal: 50.0,
            film_height: 36.0
        }
    );
}

#[test]
fn the_other_rules_are_the_same_in_both() {
    for (line, outcome) in [
        ("CAMERA EYE 1 2 3 AT 0 0 0 UP 0 1 0 FOV 30", ""),
        ("CAMERA PERSPECTIVE EYE (1,1,1) AT (0,0,0)", ""),
        (
            "CAMERA AT (0,0,0) FOV 30",
            "error: the camera needs an EYE point",
        ),
        (
            "CAMERA EYE (1,1,1) AT (1,1,1)",
            "error: the aim point coincides with the eye",
        ),
        (
            "CAMERA EYE (1,1,1) AT (0,0,0) DIR (1,0,0)",
            "error: the camera needs exactly one of AT (aim point) or DIR (direction)",
        ),
        (
            "CAMERA EYE (1,1,1) AT (0,0,0) FOV 30 FOCAL 50 FILM 24",
            "error: the camera has two lenses, FOV and FOCAL",
        ),
        (
            "CAMERA EYE (1,1,1) AT (0,0,0) EYE (2,2,2)",
            "error: `EYE` is given twice",
        ),
        (
            "CAMERA EYE (1,1,1) AT (0,0,0) HEIGHT 4",
            "error: HEIGHT belongs to ORTHO cameras; use FOV or FOCAL/FILM",
        ),
        (
            "CAMERA ORTHO EYE (1,1,1) AT (0,0,0) FOV 30",
            "error: an ORTHO camera needs HEIGHT (the visible height in model units)",
        ),
        (
            "CAMERA EYE (1,1,1) AT (0,0,0) FOCAL 0 FILM 24",
            "error: expected a focal length above 0, found `0`",
        ),
        (
            "CAMERA EYE (1,1,x) AT (0,0,0)",
            "error: expected a number for the eye point, found `x`",
        ),
        (
            "CAMERA EYE (1,1,1) AT (0,0,0) FOVV 30",
            "error: unknown camera setting `FOVV`",
        ),
    ] {
        match alike(line) {
            Ok(camera) => assert!(outcome.is_empty() && camera.is_some(), "{line}"),
            Err(lines) => assert_eq!(lines[0], outcome, "{line}"),
        }
    }
}

#[test]
fn zoom_reads_its_lens_values_as_camera_does() {
    assert_eq!(
        message_and_hint(&errors(&format!("{HEADER}ZOOM FOV 200 OVER 4\n"))),
        [
            "error: field of view must lie between 0 and 180 degrees (is 200)",
            "= hint: FOV is the vertical angle the picture spans, in degrees"
        ]
    );
    // FOCAL without FILM keeps the camera's film: a camera with a field of
    // view has none.
    assert_eq!(
        errors(&format!("{HEADER}ZOOM FOCAL 50 OVER 4\n")),
        "error: FOCAL needs FILM here: the camera has a field of view, not a film\n --> film.svs:6:6\n  |\n6 | ZOOM FOCAL 50 OVER 4\n  |      ^^^^^\n  = hint: write both, in the same units: `FOCAL 50 FILM 24` is a 50 mm lens on 35 mm film\n"
    );
    let s = scene();
    let zoomed = |script: &str| {
        let t = build(&format!("{HEADER}{script}"), &s).expect("valid");
        t.scene_at(&s, t.frame_count() - 1).camera.map(|c| c.lens)
    };
    let focal = |focal, film_height| Some(Lens::Focal { focal, film_height });
    assert_eq!(zoomed("ZOOM FOCAL 50 FILM 36 OVER 2\n"), focal(50.0, 36.0));
    // Once the lens has a film, FOCAL alone keeps it.
    assert_eq!(
        zoomed("ZOOM FOCAL 50 FILM 36 OVER 2\nZOOM FOCAL 80 OVER 2\n"),
        focal(80.0, 36.0)
    );
    // A second round of a REPEAT starts from where the first ended.
    assert_eq!(
        errors(&format!("{HEADER}REPEAT 2\nZOOM FOCAL 50 FILM 36 OVER 2\nZOOM FOCAL 80 OVER 2\nZOOM FOV 30 OVER 2\nEND\n")),
        "no error"
    );
    assert!(errors_in(
        &format!("{HEADER}ZOOM FOCAL 50 FILM 36 OVER 2\nREPEAT 2\nZOOM FOCAL 80 OVER 2\nZOOM FOV 30 OVER 2\nEND\n"),
        &s
    )
    .starts_with("error: FOCAL needs FILM here"));
}
