//! The native scene language: golden diagnostics and round trips.

use sv_formats::{load_source, native, Format, LoadError, LoadOptions, SourceFile};

fn errors(text: &str) -> String {
    let src = SourceFile::new("scene.sv", text);
    match load_source(&src, Format::Native, &LoadOptions::default()) {
        Err(LoadError::Invalid(d)) => d.render_plain(),
        Ok(_) => panic!("expected errors in:\n{text}"),
        Err(e) => panic!("{e}"),
    }
}

#[test]
fn unknown_body_type_suggests_the_nearest() {
    assert_eq!(
        errors("# demo\n\nBODY 1 SHP 0 0 0 1\n"),
        "error: unknown body type `SHP`\n --> scene.sv:3:8\n  |\n3 | BODY 1 SHP 0 0 0 1\n  |        ^^^\n  = hint: did you mean `SPH`?\n"
    );
}

#[test]
fn wrong_value_count_names_the_layout() {
    assert_eq!(
        errors("BODY c RCC (0,0,0) (0,0,1)\n"),
        "error: RCC takes 7 values, found 6\n --> scene.sv:1:13\n  |\n1 | BODY c RCC (0,0,0) (0,0,1)\n  |             ^\n  = hint: RCC: V H R\n"
    );
}

#[test]
fn bad_number_points_at_it() {
    assert_eq!(
        errors("BODY s SPH 0 0 0 12.7O\n"),
        "error: expected a number for SPH parameters, found `12.7O`\n --> scene.sv:1:18\n  |\n1 | BODY s SPH 0 0 0 12.7O\n  |                  ^^^^^\n"
    );
}

#[test]
fn region_with_a_missing_body_names_both() {
    assert_eq!(
        errors("BODY hull SPH 0 0 0 1\nREGION r = +hul -2\n"),
        "error: region `r` refers to body `hul`, which is not defined\n --> scene.sv:2:12\n  |\n2 | REGION r = +hul -2\n  |            ^^^^\n  = hint: did you mean `hull`?\n"
    );
}

#[test]
fn unknown_statement_and_property_are_suggested() {
    assert_eq!(
        errors("CAMRA EYE (0,0,0) AT (1,0,0)\n"),
        "error: unknown statement `CAMRA`\n --> scene.sv:1:1\n  |\n1 | CAMRA EYE (0,0,0) AT (1,0,0)\n  | ^^^^^\n  = hint: did you mean `CAMERA`?\n"
    );
    assert_eq!(
        errors("BODY 1 SPH 0 0 0 1\nREGION a = +1 COLR 1 0 0\n"),
        "error: unknown region property `COLR`\n --> scene.sv:2:15\n  |\n2 | REGION a = +1 COLR 1 0 0\n  |               ^^^^\n  = hint: did you mean `COLOR`?\n"
    );
}

#[test]
fn every_error_of_a_file_is_reported_at_once() {
    let text = "BODY 1 SHP 0 0 0 1\nBODY 2 SPH 0 0 0\nLIGTH SUN PARALLEL DIR (0,0,-1)\nCAMERA AT (0,0,0)\n";
    let out = errors(text);
    for want in [
        "scene.sv:1:8",
        "scene.sv:2:12",
        "scene.sv:3:1",
        "scene.sv:4:",
    ] {
        assert!(out.contains(want), "{want} missing from:\n{out}");
    }
    assert_eq!(out.matches("error:").count(), 4);
}

#[test]
fn camera_and_light_rules() {
    assert!(
        errors("CAMERA EYE (0,0,0) AT (0,0,0)\n").contains("the aim point coincides with the eye")
    );
    assert!(
        errors("CAMERA ORTHO EYE (0,0,5) AT (0,0,0)\n").contains("an ORTHO camera needs HEIGHT")
    );
    assert!(errors("LIGHT L POINT INTENSITY 3\n").contains("a POINT light needs AT (its position)"));
    // As a script's INTENSITY command says.
    assert!(errors("LIGHT L POINT AT (0,0,1) INTENSITY -3\n")
        .contains("an intensity cannot be negative"));
    assert!(
        errors("REGION x = +1\n").contains("region `x` refers to body `1`, which is not defined")
    );
    assert!(errors("BODY 1 SPH 0 0 0 1\nREGION a = +1 K 1.5\n")
        .contains("reflectivity k must lie between 0 and 1 (is 1.5)"));
}

#[test]
fn keywords_ignore_case_and_vectors_may_be_grouped() {
    let src = SourceFile::new(
        "ok.sv",
        "body 1 sph (1, 2, 3) 4\nregion a = +1 colour 1 0.5 0 k 0.5 transparent\ncamera eye (0,-10,0) at (0,0,0) fov 30\nlight sun parallel dir (0,1,-1)\n",
    );
    let s = load_source(&src, Format::Native, &LoadOptions::default())
        .unwrap()
        .scene;
    assert_eq!(s.geometry.bodies[0].params, vec![1.0, 2.0, 3.0, 4.0]);
    assert!(s.regions[0].transparent);
    assert_eq!(s.regions[0].colour, Some([1.0, 0.5, 0.0]));
    assert_eq!(s.lights.len(), 1);
}

#[test]
fn examples_round_trip_through_the_writer() {
    let ex = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    for f in [
        "figure1/figure1.sv",
        "figure3/figure3.sv",
        "helicopter/helicopter.sv",
    ] {
        let a = sv_formats::load_file(&ex.join(f), &LoadOptions::default())
            .unwrap()
            .scene;
        let text = native::write(&a);
        let b = load_source(
            &SourceFile::new("rt.sv", text.clone()),
            Format::Native,
            &LoadOptions::default(),
        )
        .unwrap_or_else(|e| panic!("{f}: {e}\n{text}"))
        .scene;
        assert_eq!(a.geometry, b.geometry, "{f}");
        assert_eq!(a.regions, b.regions, "{f}");
        assert_eq!(a.camera, b.camera, "{f}");
        assert_eq!(a.lights, b.lights, "{f}");
    }
}

#[test]
fn a_deck_included_in_other_units_is_scaled_into_the_scene() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("a.sv"),
        "UNITS mm\nBODY s SPH 0 0 0 25.4\nREGION r = +s\n",
    )
    .unwrap();
    std::fs::write(dir.path().join("main.sv"), "UNITS in\nINCLUDE \"a.sv\"\n").unwrap();
    let s = sv_formats::load_file(&dir.path().join("main.sv"), &LoadOptions::default())
        .unwrap()
        .scene;
    // The 25.4 mm sphere is one inch in the including scene.
    assert_eq!(s.units, sv_scene::Units::Inch);
    assert!(
        (s.geometry.bodies[0].params[3] - 1.0).abs() < 1e-12,
        "{:?}",
        s.geometry.bodies[0]
    );
}

#[test]
fn two_decks_in_different_units_share_one_scene() {
    let Some(decks) = sv_testdata::shared_decks("comgeom") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let main = dir.path().join("both.sv");
    std::fs::write(
        &main,
        format!(
            "UNITS in\nINCLUDE \"{}\"\nINCLUDE \"{}\"\n",
            decks.join("gift-sample-target-v4.cg").display(),
            decks.join("vdeck-all-types.cg").display()
        ),
    )
    .unwrap();
    let s = sv_formats::load_file(&main, &LoadOptions::default())
        .unwrap()
        .scene;
    assert_eq!(s.geometry.bodies.len(), 39);
    // Body 15 of the mm deck (a sphere of radius 42 mm) keeps its place
    // under a tagged name and is scaled to inches.
    let i = s
        .geometry
        .body_index("vdeck-all-types/15")
        .expect("renamed body");
    let sph = &s.geometry.bodies[i];
    assert!((sph.params[3] - 42.0 / 25.4).abs() < 1e-12, "{sph:?}");
    assert_eq!(s.geometry.regions.len(), 20 + 19, "regions of both decks");
    assert!(
        s.geometry.region_index("vdeck-all-types/1").is_some(),
        "clashing region names are tagged"
    );
}

#[test]
fn units_come_from_the_scene_or_its_first_model() {
    let dir = tempfile::tempdir().unwrap();
    // A scene file without UNITS of its own is in its includer's units.
    std::fs::write(
        dir.path().join("part.sv"),
        "BODY s SPH 0 0 0 2\nREGION r = +s\n",
    )
    .unwrap();
    std::fs::write(
        dir.path().join("metres.sv"),
        "UNITS m\nINCLUDE \"part.sv\"\n",
    )
    .unwrap();
    let s = sv_formats::load_file(&dir.path().join("metres.sv"), &LoadOptions::default())
        .unwrap()
        .scene;
    assert_eq!(s.units, sv_scene::Units::Metre);
    assert_eq!(
        s.geometry.bodies[0].params[3], 2.0,
        "not scaled: the part is in metres too"
    );
    // A scene that never says its units takes the first model's.
    std::fs::write(
        dir.path().join("mm.sv"),
        "UNITS mm\nBODY t SPH 0 0 0 5\nREGION q = +t\n",
    )
    .unwrap();
    std::fs::write(
        dir.path().join("wrap.sv"),
        "INCLUDE \"mm.sv\"\nINCLUDE \"part.sv\"\n",
    )
    .unwrap();
    let s = sv_formats::load_file(&dir.path().join("wrap.sv"), &LoadOptions::default())
        .unwrap()
        .scene;
    assert_eq!(s.units, sv_scene::Units::Millimetre);
    assert_eq!(s.geometry.bodies[0].params[3], 5.0);
    assert_eq!(
        s.geometry.bodies[1].params[3], 2.0,
        "part.sv has no units: it takes the scene's (mm)"
    );
}

#[test]
fn regions_nest_with_parentheses_and_bars_and_read_back_as_written() {
    let text = "BODY a SPH (0,0,0) 2\nBODY b SPH (1,0,0) 1\nBODY c SPH (-1,0,0) 1\n\
                BODY d RPP -3 3 -3 3 -0.1 0.1\n\
                REGION R = +a -(+b | +c -d) OR +d -a COLOR (1,0,0)\n";
    let src = SourceFile::new("scene.sv", text);
    let scene = load_source(&src, Format::Native, &LoadOptions::default())
        .unwrap()
        .scene;
    let region = &scene.geometry.regions[0];
    let names: Vec<&str> = scene
        .geometry
        .bodies
        .iter()
        .map(|b| b.name.as_str())
        .collect();
    assert_eq!(region.expression(&|b| names[b]), "+a -(+b | +c -d) | +d -a");
    assert_eq!(scene.regions[0].colour, Some([1.0, 0.0, 0.0]));
    // Written with its groups, it reads back the same.
    let written = native::write(&scene);
    let again = load_source(
        &SourceFile::new("again.sv", written.clone()),
        Format::Native,
        &LoadOptions::default(),
    )
    .unwrap_or_else(|e| panic!("{e}\n{written}"))
    .scene;
    assert_eq!(again.geometry.regions, scene.geometry.regions, "{written}");
}

#[test]
fn nested_region_errors_point_into_the_parentheses() {
    assert_eq!(
        errors("BODY a SPH (0,0,0) 2\nBODY b SPH (1,0,0) 1\nREGION R = +a -(+b | +x)\n"),
        "error: region `R` refers to body `x`, which is not defined\n --> scene.sv:3:23\n  |\n3 | REGION R = +a -(+b | +x)\n  |                       ^\n  = hint: did you mean `a`?\n"
    );
    let unclosed = errors("BODY a SPH (0,0,0) 2\nBODY b SPH (1,0,0) 1\nREGION R = +a -(+b\n");
    assert!(unclosed.contains("scene.sv:3:"), "{unclosed}");
    assert!(unclosed.contains("region `R`"), "{unclosed}");
}
