//! The `synthavision` binary as a user runs it: exit codes, outputs, and
//! no partial files on bad input.

use crate::{examples, sv};
use std::path::{Path, PathBuf};

/// The shared COMGEOM decks; `None` only when they are missing and
/// `SV_SKIP_SHARED=1` is set.
fn decks() -> Option<PathBuf> {
    sv_testdata::shared_decks("comgeom")
}

#[test]
fn render_without_a_scene_draws_the_bundled_helicopter() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("h.png");
    let o = sv(&["render", "--size", "96x72", "-o", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let img = image::open(&out).unwrap().into_rgb8();
    assert_eq!(img.dimensions(), (96, 72));
    // Sky-blue background in the corner, something darker in the middle.
    assert_eq!(img.get_pixel(0, 0).0, [140, 179, 230]);
    assert!(
        img.pixels().filter(|p| p.0[2] < 150).count() > 300,
        "the helicopter covers part of the picture"
    );
}

#[test]
fn bad_input_exits_2_names_the_place_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("bad.sv");
    std::fs::write(
        &scene,
        "BODY 1 SPH 0 0 0 1\nBODY 2 SHP 0 0 0 1\nREGION a = +1\n",
    )
    .unwrap();
    let out = dir.path().join("out.png");
    let o = sv(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("unknown body type `SHP`"), "{err}");
    assert!(err.contains("bad.sv:2:8"), "{err}");
    assert!(err.contains("did you mean `SPH`?"), "{err}");
    assert!(
        err.ends_with("\n1 error found; nothing was written\n"),
        "{err}"
    );
    assert!(
        !out.exists(),
        "no picture may be written from a scene with errors"
    );
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        1,
        "no temporary file is left"
    );
}

#[test]
fn every_error_is_listed_and_counted() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("two.sv");
    std::fs::write(
        &scene,
        "BODY 1 SPH 0 0 0 1\nBODY 2 SHP 0 0 0 1\nBODY 3 SHQ 0 0 0 1\nREGION a = +1\n",
    )
    .unwrap();
    let o = sv(&["info", scene.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("two.sv:2:8") && err.contains("two.sv:3:8"),
        "{err}"
    );
    assert!(
        err.ends_with("\n2 errors found; nothing was written\n"),
        "{err}"
    );
}

#[test]
fn an_invalid_body_is_bad_input_too() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("zero.sv");
    std::fs::write(&scene, "BODY leg RCC (0,0,0) (0,0,0) 1\nREGION a = +leg\n").unwrap();
    let o = sv(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        dir.path().join("x.png").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("RCC `leg`: height vector is zero"));
}

#[test]
fn unwritable_output_exits_3() {
    let o = sv(&["render", "--size", "8x8", "-o", "/nonexistent-dir/x.png"]);
    assert_eq!(
        o.status.code(),
        Some(3),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

#[test]
fn shoot_walks_figure3_as_the_paper_does() {
    let f = examples().join("figure3/figure3.sv");
    let o = sv(&[
        "shoot",
        f.to_str().unwrap(),
        "--from",
        "-9,0,0",
        "--dir",
        "1,0,0",
    ]);
    assert!(o.status.success());
    let text = String::from_utf8_lossy(&o.stdout);
    let rows: Vec<Vec<&str>> = text
        .lines()
        .skip(2)
        .map(|l| l.split_whitespace().collect())
        .collect();
    let walk: Vec<(&str, &str, &str)> = rows.iter().map(|r| (r[1], r[2], r[4])).collect();
    assert!(text.starts_with("start (-9, 0, 0) in C"), "{text}");
    // E3 into B, E2 (still B), L3 into A, L2 back into C, L1 out.
    assert_eq!(
        walk,
        vec![
            ("enters", "3", "B"),
            ("enters", "2", "B"),
            ("leaves", "3", "A"),
            ("leaves", "2", "C"),
            ("leaves", "1", "(outside")
        ]
    );
}

#[test]
fn aux_images_keep_exact_region_ids() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("f.png");
    let f = examples().join("figure1/figure1.sv");
    let o = sv(&[
        "render",
        f.to_str().unwrap(),
        "--size",
        "96x72",
        "--aov",
        "region,depth,normal",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let ids = image::open(dir.path().join("f.region.png"))
        .unwrap()
        .into_luma16();
    let mut seen: Vec<u16> = ids.pixels().map(|p| p.0[0]).collect();
    seen.sort();
    seen.dedup();
    assert_eq!(
        seen,
        vec![0, 1, 2, 3, 4, 5],
        "background and the five regions of Figure 1"
    );
    assert!(dir.path().join("f.depth.pfm").is_file() && dir.path().join("f.normal.pfm").is_file());
}

#[test]
fn the_generator_deck_renders_with_no_options() {
    let Some(d) = decks() else { return };
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("gen.png");
    let o = sv(&[
        "render",
        d.join("mep021a-generator-v5.cg").to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let img = image::open(&out).unwrap().into_luma8();
    assert_eq!(img.dimensions(), (960, 720));
    let lit = img.pixels().filter(|p| p.0[0] > 0).count();
    assert!(
        lit > 960 * 720 / 5,
        "the generator fills a good part of the frame ({lit} pixels)"
    );
    // The non-planar ARB8 faces are reported, not refused.
    assert!(String::from_utf8_lossy(&o.stderr).contains("face 2376 is not planar"));
}

#[test]
fn convert_writes_decks_that_read_back_the_same() {
    let Some(d) = decks() else { return };
    let dir = tempfile::tempdir().unwrap();
    for deck in [
        "gift-sample-target-v4.cg",
        "vdeck-all-types.cg",
        "mep021a-generator-v5.cg",
    ] {
        let a = dir.path().join("a.cg");
        let o = sv(&[
            "convert",
            d.join(deck).to_str().unwrap(),
            "-o",
            a.to_str().unwrap(),
        ]);
        assert!(
            o.status.success(),
            "{deck}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        // v5 has no foci form: an ELL comes back as the same ellipsoid
        // written as ELL1, so compare what must survive, not type names.
        let info = |p: &Path| {
            String::from_utf8_lossy(&sv(&["info", p.to_str().unwrap()]).stdout)
                .lines()
                .filter(|l| {
                    ["units:", "bodies:", "regions:", "bounds:", "air regions:"]
                        .iter()
                        .any(|k| l.starts_with(k))
                })
                .collect::<Vec<_>>()
                .join("\n")
        };
        assert_eq!(
            info(&a),
            info(&d.join(deck)),
            "{deck}: counts and bounds survive the round trip"
        );
    }
}

#[test]
fn alpha_channel_and_background_plate() {
    let dir = tempfile::tempdir().unwrap();
    let f = examples().join("figure1/figure1.sv");
    let out = dir.path().join("a.png");
    let o = sv(&[
        "render",
        f.to_str().unwrap(),
        "--size",
        "64x48",
        "--alpha",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let img = image::open(&out).unwrap().into_rgba8();
    assert_eq!(img.get_pixel(0, 0).0[3], 0, "background is transparent");
    assert!(img.pixels().any(|p| p.0[3] == 255), "geometry is opaque");
    // A plate of pure red shows wherever no region is hit.
    let plate = dir.path().join("plate.png");
    image::RgbImage::from_pixel(32, 24, image::Rgb([255, 0, 0]))
        .save(&plate)
        .unwrap();
    let out2 = dir.path().join("b.png");
    let o = sv(&[
        "render",
        f.to_str().unwrap(),
        "--size",
        "64x48",
        "--background",
        plate.to_str().unwrap(),
        "-o",
        out2.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let img = image::open(&out2).unwrap().into_rgb8();
    assert_eq!(img.get_pixel(0, 0).0, [255, 0, 0]);
    let geometry: Vec<_> = img.pixels().filter(|p| p.0 != [255, 0, 0]).collect();
    assert!(
        geometry.iter().any(|p| p.0[1] > 0),
        "grey geometry is drawn over the plate"
    );
}
