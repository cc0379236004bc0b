//! The FLUKA reader against the pyg4ometry test inputs and hand-made cases.

use proptest::prelude::*;
use std::path::{Path, PathBuf};
use sv_formats::{fluka, Diagnostics, LoadOptions, Loaded, SourceFile};
use sv_geom::{Body, BodyKind, Op, Region};
use sv_math::DVec3;

const DATA: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../../shared/decks/fluka/pyg4ometry-testdata/"
);

fn data_dir() -> Option<&'static Path> {
    let p = Path::new(DATA);
    if p.is_dir() {
        Some(p)
    } else {
        eprintln!("skipping: FLUKA test inputs not found at {DATA}");
        None
    }
}

fn read_path(path: &Path) -> Result<Loaded, Diagnostics> {
    let text = std::fs::read_to_string(path).expect("test input is readable");
    fluka::read(
        &SourceFile::new(path.display().to_string(), text),
        &LoadOptions::default(),
    )
}

/// Read a test input; `None` when the data set is not there.
fn input(name: &str) -> Option<Loaded> {
    let dir = data_dir()?;
    match read_path(&dir.join(name)) {
        Ok(l) => Some(l),
        Err(d) => panic!("{name} failed:\n{}", d.render_plain()),
    }
}

fn read_text(text: &str) -> Result<Loaded, Diagnostics> {
    fluka::read(&SourceFile::new("test.inp", text), &LoadOptions::default())
}

/// A complete input around a body list and a region list.
fn geo(bodies: &str, regions: &str) -> String {
    format!(
        "TITLE\nhand-made\nGEOBEGIN                                                              COMBNAME\n    0    0          test\n{bodies}\nEND\n{regions}\nEND\nGEOEND\nSTOP\n"
    )
}

/// (line, column, message) of every error.
fn errors(text: &str) -> Vec<(usize, usize, String)> {
    match read_text(text) {
        Ok(_) => panic!("expected errors for:\n{text}"),
        Err(d) => d
            .errors()
            .map(|e| {
                let (l, c) = e.line_col();
                (l, c, e.message.clone())
            })
            .collect(),
    }
}

fn body<'a>(l: &'a Loaded, name: &str) -> &'a Body {
    l.scene
        .geometry
        .bodies
        .iter()
        .find(|b| b.name == name)
        .unwrap_or_else(|| panic!("no body {name}"))
}

fn region<'a>(l: &'a Loaded, name: &str) -> &'a Region {
    l.scene
        .geometry
        .regions
        .iter()
        .find(|r| r.name == name)
        .unwrap_or_else(|| panic!("no region {name}"))
}

/// A region's zones written as `+a -b` strings.
fn zones(l: &Loaded, name: &str) -> Vec<String> {
    let bodies = &l.scene.geometry.bodies;
    region(l, name)
        .zones
        .iter()
        .map(|z| {
            z.terms
                .iter()
                .map(|t| {
                    format!(
                        "{}{}",
                        if t.op == Op::Inside { '+' } else { '-' },
                        bodies[t.body].name
                    )
                })
                .collect::<Vec<_>>()
                .join(" ")
        })
        .collect()
}

fn assert_close(got: &[f64], want: &[f64]) {
    assert_eq!(got.len(), want.len(), "got {got:?}, want {want:?}");
    for (g, w) in got.iter().zip(want) {
        assert!(
            (g - w).abs() < 1e-9 * (1.0 + w.abs()),
            "got {got:?}, want {want:?}"
        );
    }
}

// Body and region counts of every input, counted by reading the files: the
// 90x inputs keep one `bb1` of their #if branches, and 904 takes both bodies
// and regions from preprocessor_fragment.geom.
const COUNTS: [(&str, usize, usize); 84] = [
    ("001_RPP.inp", 2, 2),
    ("002_BOX.inp", 2, 2),
    ("003_SPH.inp", 2, 2),
    ("004_RCC.inp", 2, 2),
    ("005_REC.inp", 2, 2),
    ("006_TRC.inp", 2, 2),
    ("007_ELL.inp", 2, 2),
    ("009_ARB.inp", 2, 2),
    ("009_ARB_cube_anticlockwise.inp", 2, 2),
    ("009_ARB_cube_clockwise.inp", 2, 2),
    ("011_XYP.inp", 7, 2),
    ("012_XZP.inp", 7, 2),
    ("013_YZP.inp", 7, 2),
    ("014_PLA.inp", 7, 2),
    ("015_XCC.inp", 4, 2),
    ("016_YCC.inp", 4, 2),
    ("017_ZCC.inp", 4, 2),
    ("018_XEC.inp", 4, 2),
    ("019_YEC.inp", 4, 2),
    ("020_ZEC.inp", 4, 2),
    ("021_QUA.inp", 5, 2),
    ("050_RPP_Translate.inp", 2, 2),
    ("051_RPP_Expansion.inp", 2, 2),
    ("052_RPP_RotDefi.inp", 2, 2),
    ("053_RPP_RotDefi2.inp", 2, 2),
    ("054_RPP_TranslateExpansionRotDefi.inp", 2, 2),
    ("100_Multiple.inp", 3, 3),
    ("101_Intersection.inp", 3, 2),
    ("102_Difference.inp", 3, 2),
    ("103_Union.inp", 3, 2),
    ("104_shift_cylinders.inp", 3, 2),
    ("301_RPP_transform.inp", 4, 2),
    ("302_BOX_transform.inp", 4, 2),
    ("303_SPH_transform.inp", 4, 2),
    ("304_RCC_transform.inp", 4, 2),
    ("305_REC_transform.inp", 4, 2),
    ("306_TRC_transform.inp", 4, 2),
    ("307_ELL_transform.inp", 4, 2),
    ("308_RAW_transform.inp", 4, 2),
    ("308_WED_transform.inp", 4, 2),
    ("309_ARB_transform.inp", 4, 2),
    ("310_XYP_transform.inp", 19, 4),
    ("310_XZP_transform.inp", 19, 4),
    ("310_YZP_transform.inp", 19, 4),
    ("311_PLA_transform.inp", 19, 4),
    ("312_XCC_transform.inp", 3, 1),
    ("312_YCC_transform.inp", 3, 1),
    ("312_ZCC_transform.inp", 3, 1),
    ("313_XEC_transform.inp", 3, 1),
    ("313_YEC_transform.inp", 3, 1),
    ("313_ZEC_transform.inp", 3, 1),
    ("314_QUA_transform.inp", 5, 2),
    ("320_cube_from_halfspaces_transform.inp", 19, 4),
    ("321_cube_from_plas_transform.inp", 19, 4),
    ("322_cube_from_halfspaces.inp", 7, 2),
    ("323_cube_from_plas.inp", 7, 2),
    ("514_QUA_coplanar.inp", 9, 3),
    ("514_QUA_expansion.inp", 5, 2),
    ("514_QUA_rototranslation.inp", 5, 2),
    ("514_QUA_translation.inp", 5, 2),
    ("601_filter_redundant_halfspaces.inp", 3, 2),
    ("701_LATTICE.inp", 3, 3),
    ("702_LATTICE.inp", 5, 5),
    ("703_LATTICE.inp", 4, 4),
    ("801_nested_expansion.inp", 2, 2),
    ("802_nested_translation.inp", 2, 2),
    ("803_nested_transform.inp", 4, 2),
    ("804_recursive_transform.inp", 3, 3),
    ("805_inverse_transform.inp", 3, 3),
    ("806_combined_translat_transform.inp", 4, 4),
    ("901_preprocessor_if.inp", 2, 2),
    ("902_preprocessor_elif.inp", 2, 2),
    ("903_preprocessor_else.inp", 2, 2),
    ("904_preprocessor_include.inp", 2, 2),
    ("905_preprocessor_nested_if.inp", 2, 2),
    ("906_preprocessor_nested_elif.inp", 2, 2),
    ("907_preprocessor_nested_else.inp", 2, 2),
    ("908_preprocessor_define.inp", 2, 2),
    ("ex-geometry.inp", 16, 12),
    ("ex_Scoring.inp", 7, 5),
    ("example_running.inp", 3, 3),
    ("example_score.inp", 7, 5),
    ("manualSimpleFileFixed.inp", 4, 4),
    ("manualSimpleFileFree.inp", 4, 4),
];

#[test]
fn every_test_input_parses_with_its_body_and_region_counts() {
    let Some(dir) = data_dir() else { return };
    let mut on_disk: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".inp"))
        .collect();
    on_disk.sort();
    let mut listed: Vec<String> = COUNTS.iter().map(|c| c.0.to_string()).collect();
    listed.sort();
    assert_eq!(on_disk, listed, "the table must list every input");
    for (name, bodies, regions) in COUNTS {
        let l = input(name).unwrap();
        let g = &l.scene.geometry;
        assert_eq!(
            (g.bodies.len(), g.regions.len()),
            (bodies, regions),
            "{name}"
        );
        assert_eq!(
            l.scene.regions.len(),
            regions,
            "{name}: one RegionProps per region"
        );
        assert_eq!(l.scene.units, sv_scene::Units::Centimetre);
        for r in &g.regions {
            assert!(!r.zones.is_empty(), "{name}: region {} has zones", r.name);
        }
    }
}

#[test]
fn the_include_fragment_alone_is_refused_for_lack_of_a_geometry() {
    let Some(dir) = data_dir() else { return };
    let e = read_path(&dir.join("preprocessor_fragment.geom")).unwrap_err();
    let msgs: Vec<_> = e.errors().map(|d| d.message.as_str()).collect();
    assert_eq!(msgs, ["no GEOBEGIN card: this input has no geometry"]);
}

#[test]
fn body_parameters_match_the_card_text() {
    let cases: [(&str, &str, BodyKind, &[f64]); 21] = [
        (
            "001_RPP.inp",
            "rpp",
            BodyKind::Rpp,
            &[-50., 50., -50., 50., -50., 50.],
        ),
        (
            "002_BOX.inp",
            "box",
            BodyKind::Box,
            &[0., 0., 0., 100., 0., 0., 0., 100., 0., 0., 0., 100.],
        ),
        ("003_SPH.inp", "sph", BodyKind::Sph, &[0., 0., 0., 100.]),
        (
            "004_RCC.inp",
            "rcc",
            BodyKind::Rcc,
            &[50., -50., 0., -100., 100., 0., 25.],
        ),
        (
            "005_REC.inp",
            "rec",
            BodyKind::Rec,
            &[50., -50., 0., -100., 100., 0., 25., 25., 0., 0., 0., 100.],
        ),
        (
            "006_TRC.inp",
            "trc",
            BodyKind::Trc,
            &[0., 0., 0., 0., 100., 0., 100., 50.],
        ),
        (
            "007_ELL.inp",
            "ell",
            BodyKind::Ell,
            &[50., 0., 0., -50., 0., 0., 150.],
        ),
        (
            "009_ARB.inp",
            "arb",
            BodyKind::ArbF,
            &[
                -44.2, -36.5, 3572., -44.2, -33.5, 3572., -37.1, -31., 3572., -37.1, -39., 3572.,
                -44.2, -36.5, 0., -44.2, -33.5, 0., -37.1, -31., 0., -37.1, -39., 0., 1234., 1562.,
                5876., 1485., 4378., 6732.,
            ],
        ),
        (
            "009_ARB_cube_clockwise.inp",
            "arb",
            BodyKind::ArbF,
            &[
                0., 0., 0., 20., 0., 0., 20., 20., 0., 0., 20., 0., 0., 0., 20., 20., 0., 20., 20.,
                20., 20., 0., 20., 20., 4321., 5678., 2376., 1584., 3487., 1265.,
            ],
        ),
        ("011_XYP.inp", "xyphig1", BodyKind::Xyp, &[10.]),
        ("012_XZP.inp", "xzphig1", BodyKind::Xzp, &[10.]),
        ("013_YZP.inp", "yzphig1", BodyKind::Yzp, &[10.]),
        (
            "014_PLA.inp",
            "xyphig1",
            BodyKind::Pla,
            &[0., 0., 1., 0., 0., 10.],
        ),
        ("015_XCC.inp", "xcc", BodyKind::Xcc, &[0., 0., 50.]),
        ("016_YCC.inp", "ycc", BodyKind::Ycc, &[0., 0., 50.]),
        ("017_ZCC.inp", "zcc", BodyKind::Zcc, &[0., 0., 50.]),
        ("018_XEC.inp", "xec", BodyKind::Xec, &[0., 0., 50., 100.]),
        ("019_YEC.inp", "yec", BodyKind::Yec, &[0., 0., 50., 100.]),
        ("020_ZEC.inp", "zec", BodyKind::Zec, &[0., 0., 50., 100.]),
        (
            "021_QUA.inp",
            "parab",
            BodyKind::Qua,
            &[0.06, 0., 0., 0., 0., 0., 0., 1., 0., -20.],
        ),
        ("015_XCC.inp", "cut1", BodyKind::Yzp, &[100.]),
    ];
    for (file, name, kind, params) in cases {
        let Some(l) = input(file) else { return };
        let b = body(&l, name);
        assert_eq!(b.kind, kind, "{file} {name}");
        assert_close(&b.params, params);
    }
}

#[test]
fn every_body_code_maps_to_its_kind_in_card_order() {
    let text = geo(
        "RPP a 1 2 3 4 5 6\nBOX b 1 2 3 4 5 6 7 8 9 10 11 12\nSPH c 1 2 3 4\nRCC d 1 2 3 4 5 6 7\n\
         REC e 1 2 3 4 5 6 7 8 9 10 11 12\nTRC f 1 2 3 4 5 6 7 8\nELL g 1 2 3 4 5 6 7\n\
         WED h 1 2 3 4 5 6 7 8 9 10 11 12\nRAW i 1 2 3 4 5 6 7 8 9 10 11 12\n\
         ARB j 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20 21 22 23 24 1234 5678 1265 2376 3487 4158\n\
         XYP k 1\nXZP l 1\nYZP m 1\nPLA n 1 2 3 4 5 6\nXCC o 1 2 3\nYCC p 1 2 3\nZCC q 1 2 3\n\
         XEC r 1 2 3 4\nYEC s 1 2 3 4\nZEC t 1 2 3 4\nQUA u 1 2 3 4 5 6 7 8 9 10",
        "all 5 +a +b +c +d +e +f +g +h +i +j +k +l +m +n +o +p +q +r +s +t +u",
    );
    let l = read_text(&text).unwrap();
    use BodyKind::*;
    let kinds = [
        Rpp, Box, Sph, Rcc, Rec, Trc, Ell, Raw, Raw, ArbF, Xyp, Xzp, Yzp, Pla, Xcc, Ycc, Zcc, Xec,
        Yec, Zec, Qua,
    ];
    let got: Vec<_> = l.scene.geometry.bodies.iter().map(|b| b.kind).collect();
    assert_eq!(got, kinds);
    for b in &l.scene.geometry.bodies {
        let n = b.params.len();
        let want: Vec<f64> = if b.kind == ArbF {
            (1..=24)
                .map(f64::from)
                .chain([1234., 5678., 1265., 2376., 3487., 4158.])
                .collect()
        } else {
            (1..=n).map(|i| i as f64).collect()
        };
        assert_eq!(b.params, want, "{}", b.name);
    }
}

#[test]
fn numbers_may_use_commas_exponents_and_continuation_lines() {
    let text = geo("RCC c 0.0,1.5E1 -2.d0\n   0 0 1.e2\n\t25.", "r 5 +c");
    let l = read_text(&text).unwrap();
    assert_eq!(
        body(&l, "c").params,
        vec![0.0, 15.0, -2.0, 0.0, 0.0, 100.0, 25.0]
    );
}

#[test]
fn translation_and_expansion_move_an_rpp() {
    let Some(t) = input("050_RPP_Translate.inp") else {
        return;
    };
    assert_eq!(body(&t, "rpp").kind, BodyKind::Rpp);
    assert_close(&body(&t, "rpp").params, &[0., 100., 0., 100., 0., 100.]);
    assert_close(
        &body(&t, "blackhole").params,
        &[-200., 200., -200., 200., -200., 200.],
    );
    let e = input("051_RPP_Expansion.inp").unwrap();
    assert_close(
        &body(&e, "rpp").params,
        &[-150., 150., -150., 150., -150., 150.],
    );
    // 2 × 2 × 5.
    let n = input("801_nested_expansion.inp").unwrap();
    assert_close(
        &body(&n, "rpp").params,
        &[-1000., 1000., -1000., 1000., -1000., 1000.],
    );
    // (10,10,10) + (0,20,0) + (-10,-10,-10).
    let s = input("802_nested_translation.inp").unwrap();
    assert_close(&body(&s, "rpp").params, &[-50., 50., -30., 70., -50., 50.]);
    // Moving an infinite z cylinder along z leaves it unchanged.
    let c = input("104_shift_cylinders.inp").unwrap();
    assert_eq!(body(&c, "bp").kind, BodyKind::Zec);
    assert_close(&body(&c, "bp").params, &[0., 0., 3., 1.5]);
    assert_close(
        &body(&c, "yoke").params,
        &[-10., 10., -10., 10., -3008.5, -2991.5],
    );
}

const H: f64 = std::f64::consts::FRAC_1_SQRT_2;

#[test]
fn rot_defi_about_z_turns_an_rpp_into_a_box() {
    // ROT-DEFI WHAT(1)=0 (z), θ=45°, φ=45°, offset (50,50,50): a point r goes
    // to Rθ·Rφ·(r + t). The corner (-50,-50,-50) goes to the origin; the edges
    // are 100 times the columns of Rθ·Rφ: (½,−½√2,½), (½,½√2,½), (−½√2,0,½√2).
    let Some(l) = input("052_RPP_RotDefi.inp") else {
        return;
    };
    let b = body(&l, "rpp");
    assert_eq!(b.kind, BodyKind::Box);
    assert_close(&b.params[..3], &[0.0, 0.0, 0.0]);
    let p = &b.params;
    for (got, want) in [
        (&p[3..6], [50.0, -100.0 * H, 50.0]),
        (&p[6..9], [50.0, 100.0 * H, 50.0]),
        (&p[9..12], [-100.0 * H, 0.0, 100.0 * H]),
    ] {
        for (g, w) in got.iter().zip(want) {
            assert!((g - w).abs() < 1e-9, "{p:?}");
        }
    }
}

#[test]
fn expansion_then_translation_then_rotation() {
    // 054: RPP ±50, expanded ×3, moved by 25, then the 052 rotation: the
    // corner (-125,-125,-125) + (50,50,50) = -75·(1,1,1) goes to −75 times the
    // sum of the rotation's columns (½+½−½√2, 0, ½+½+½√2).
    let Some(l) = input("054_RPP_TranslateExpansionRotDefi.inp") else {
        return;
    };
    let b = body(&l, "rpp");
    assert_eq!(b.kind, BodyKind::Box);
    let v = b.vec3(0);
    let want = DVec3::new(-75.0 * (1.0 - H), 0.0, -75.0 * (1.0 + H));
    assert!((v - want).length() < 1e-9, "{v}");
    assert!((b.vec3(3) - DVec3::new(150.0, -300.0 * H, 150.0)).length() < 1e-9);
}

#[test]
fn cards_with_one_name_apply_in_order() {
    // `trans` = azimuth 90° about y (x,y,z → −z,y,x), then +10 in z.
    let Some(l) = input("804_recursive_transform.inp") else {
        return;
    };
    let b = body(&l, "rpptrans");
    assert_eq!(b.kind, BodyKind::Box);
    let p = &b.params;
    let want = [0., 0., 10., 0., 0., 10., 0., 10., 0., -10., 0., 0.];
    for (g, w) in p.iter().zip(want) {
        assert!((g - w).abs() < 1e-9, "{p:?}");
    }
    assert_close(&body(&l, "rpp0").params, &[0., 10., 0., 10., 0., 10.]);
}

#[test]
fn a_leading_minus_applies_the_inverse() {
    let Some(l) = input("805_inverse_transform.inp") else {
        return;
    };
    let b = body(&l, "rpptrans");
    assert_eq!(b.kind, BodyKind::Rpp);
    assert_close(&b.params, &[0., 10., 0., 10., -10., 0.]);
    // 701: Rotdefi1 = shift (0,−2,−30), then φ=−45° about x; the replica gets
    // its inverse: V' = Rxᵀ(0,0,−5) − t, H' = Rxᵀ(0,0,10).
    let l = input("701_LATTICE.inp").unwrap();
    let r = body(&l, "targRepl");
    assert_eq!(r.kind, BodyKind::Rcc);
    let want = [
        0.0,
        -5.0 * H + 2.0,
        -5.0 * H + 30.0,
        0.0,
        10.0 * H,
        10.0 * H,
        5.0,
    ];
    for (g, w) in r.params.iter().zip(want) {
        assert!((g - w).abs() < 1e-9, "{:?}", r.params);
    }
}

#[test]
fn nested_transforms_apply_the_inner_one_first() {
    // 803: t1 (azimuth 90° about y) around t2 (+10 in z): r' = t1(t2(r)).
    let Some(l) = input("803_nested_transform.inp") else {
        return;
    };
    let b = body(&l, "rppt1t2");
    let want = [40., -50., -50., 0., 0., 100., 0., 100., 0., -100., 0., 0.];
    for (g, w) in b.params.iter().zip(want) {
        assert!((g - w).abs() < 1e-9, "{:?}", b.params);
    }
    // 806: a recursive transform and a translation inside a transform agree.
    let l = input("806_combined_translat_transform.inp").unwrap();
    let (a, b) = (body(&l, "rpptrf"), body(&l, "rpptrflt"));
    assert_eq!(a.kind, b.kind);
    for (x, y) in a.params.iter().zip(&b.params) {
        assert!((x - y).abs() < 1e-9, "{:?} vs {:?}", a.params, b.params);
    }
    assert!((a.vec3(0) - DVec3::new(-10.0, 0.0, 0.0)).length() < 1e-9);
}

#[test]
fn turned_infinite_bodies_take_their_general_forms() {
    let Some(l) = input("312_XCC_transform.inp") else {
        return;
    };
    assert!(l
        .scene
        .geometry
        .bodies
        .iter()
        .all(|b| b.kind == BodyKind::Qua));
    let l = input("310_XYP_transform.inp").unwrap();
    assert!(l
        .scene
        .geometry
        .bodies
        .iter()
        .filter(|b| b.name != "blackhole")
        .all(|b| b.kind == BodyKind::Pla));
}

#[test]
fn regions_become_unions_of_zones() {
    let Some(l) = input("101_Intersection.inp") else {
        return;
    };
    assert_eq!(
        zones(&l, "blackhole"),
        ["+blackhole -rpp1", "+blackhole -rpp2"]
    );
    assert_eq!(zones(&l, "intreg"), ["+rpp1 +rpp2"]);
    let l = input("102_Difference.inp").unwrap();
    assert_eq!(
        zones(&l, "blackhole"),
        ["+blackhole -rpp1", "+blackhole +rpp2"]
    );
    assert_eq!(zones(&l, "subreg"), ["+rpp1 -rpp2"]);
    let l = input("103_Union.inp").unwrap();
    assert_eq!(zones(&l, "unionreg"), ["+rpp1", "+rpp2"]);
    assert_eq!(zones(&l, "blackhole"), ["+blackhole -rpp1 -rpp2"]);
    // Three subtracted six-plane cubes: 6 × 6 × 6 zones.
    let l = input("310_XYP_transform.inp").unwrap();
    assert_eq!(region(&l, "blackhol").zones.len(), 216);
    let l = input("ex-geometry.inp").unwrap();
    assert_eq!(
        zones(&l, "DIP_OUT_"),
        ["+dipyoke -dipyokeo", "+dipyoke +dipyokei"]
    );
}

#[test]
fn nested_parentheses_and_unions_inside_them() {
    let text = geo(
        "SPH a 0 0 0 1\nSPH b 0 0 0 2\nSPH c 0 0 0 3\nSPH d 0 0 0 4",
        "r1 5 +d -(+a | +b -(+c))\nr2 5 | +a +(+b | +c)\n       | -d\nr3 5 (+a -b) c",
    );
    let l = read_text(&text).unwrap();
    assert_eq!(zones(&l, "r1"), ["+d -a -b", "+d -a +c"]);
    assert_eq!(zones(&l, "r2"), ["+a +b", "+a +c", "-d"]);
    assert_eq!(zones(&l, "r3"), ["+a -b +c"]);
}

#[test]
fn preprocessor_branches_pick_one_body() {
    let cases = [
        ("901_preprocessor_if.inp", BodyKind::Trc),
        ("902_preprocessor_elif.inp", BodyKind::Rpp),
        ("903_preprocessor_else.inp", BodyKind::Rcc),
        ("904_preprocessor_include.inp", BodyKind::Rcc),
        ("905_preprocessor_nested_if.inp", BodyKind::Trc),
        ("906_preprocessor_nested_elif.inp", BodyKind::Rpp),
        ("907_preprocessor_nested_else.inp", BodyKind::Rpp),
    ];
    for (file, kind) in cases {
        let Some(l) = input(file) else { return };
        assert_eq!(body(&l, "bb1").kind, kind, "{file}");
    }
    let l = input("904_preprocessor_include.inp").unwrap();
    assert_close(&body(&l, "bb1").params, &[0., -85., 0., 0., 190., 0., 100.]);
    assert_eq!(l.scene.title, "there will be a cylinder if this works.");
}

#[test]
fn ifdef_ifndef_undef() {
    let text = geo(
        "#define A\n#define B some value\n#undef B\n#ifdef A\nSPH x 0 0 0 1\n#endif\n#ifndef B\nSPH y 0 0 0 1\n#else\nSPH z 0 0 0 1\n#endif\n#if B\nSPH w 0 0 0 1\n#endif",
        "r 5 +x +y",
    );
    let l = read_text(&text).unwrap();
    let names: Vec<_> = l
        .scene
        .geometry
        .bodies
        .iter()
        .map(|b| b.name.as_str())
        .collect();
    assert_eq!(names, ["x", "y"]);
}

/// A fresh directory under the system temp dir.
fn temp_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("sv-fluka-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn include_is_relative_to_the_including_file_and_nests() {
    let d = temp_dir("inc");
    std::fs::create_dir_all(d.join("sub")).unwrap();
    std::fs::write(d.join("sub/a.geom"), "SPH a 0 0 0 1\n#include \"b.geom\"\n").unwrap();
    std::fs::write(d.join("sub/b.geom"), "SPH b 0 0 0 2\n").unwrap();
    let main = d.join("main.inp");
    std::fs::write(&main, geo("#include sub/a.geom", "r 5 +b -a")).unwrap();
    let l = read_path(&main).unwrap();
    assert_eq!(l.scene.geometry.bodies.len(), 2);
    assert_eq!(zones(&l, "r"), ["+b -a"]);
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn recursive_and_too_deep_includes_are_errors() {
    let d = temp_dir("rec");
    std::fs::write(d.join("loop.geom"), "#include loop.geom\n").unwrap();
    let main = d.join("main.inp");
    std::fs::write(&main, geo("SPH a 0 0 0 1\n#include loop.geom", "r 5 +a")).unwrap();
    let e = read_path(&main).unwrap_err();
    let msgs: Vec<_> = e.errors().map(|d| d.message.clone()).collect();
    assert_eq!(msgs.len(), 1, "{msgs:?}");
    assert!(
        msgs[0].ends_with("loop.geom` includes itself (recursive #include)"),
        "{msgs:?}"
    );
    // A chain of distinct files deeper than the limit.
    for i in 0..20 {
        std::fs::write(
            d.join(format!("c{i}.geom")),
            format!("#include c{}.geom\n", i + 1),
        )
        .unwrap();
    }
    std::fs::write(d.join("c20.geom"), "\n").unwrap();
    std::fs::write(&main, geo("SPH a 0 0 0 1\n#include c0.geom", "r 5 +a")).unwrap();
    let e = read_path(&main).unwrap_err();
    let msgs: Vec<_> = e.errors().map(|d| d.message.clone()).collect();
    assert_eq!(
        msgs,
        [format!(
            "`#include` nested more than {} levels deep",
            fluka::MAX_INCLUDE_DEPTH
        )]
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn preprocessor_errors() {
    let cases: [(&str, (usize, usize, &str)); 7] = [
        ("#endif", (6, 1, "`#endif` without `#if`")),
        ("#else", (6, 1, "`#else` without `#if`")),
        ("#elif X", (6, 1, "`#elif` without `#if`")),
        (
            "#if X\n#else\n#else\n#endif",
            (8, 1, "second `#else` for the same `#if`"),
        ),
        (
            "#if X\n#else\n#elif Y\n#endif",
            (8, 1, "`#elif` after `#else`"),
        ),
        ("#ifx X", (6, 1, "unknown preprocessor directive `#ifx`")),
        (
            "#include nowhere.geom",
            (
                6,
                10,
                "cannot include `nowhere.geom`: No such file or directory (os error 2)",
            ),
        ),
    ];
    for (lines, (l, c, msg)) in cases {
        let text = geo(&format!("SPH a 0 0 0 1\n{lines}"), "r 5 +a");
        assert_eq!(errors(&text), [(l, c, msg.to_string())], "{lines}");
    }
    // An #if left open hides the rest of the input, GEOEND included.
    let text = geo("SPH a 0 0 0 1\n#ifdef X\n#endif\n#if X", "r 5 +a");
    assert_eq!(
        errors(&text),
        [
            (3, 1, "GEOBEGIN without GEOEND".to_string()),
            (8, 1, "`#if` is never closed by `#endif`".to_string())
        ]
    );
}

#[test]
fn body_errors_are_all_reported_with_positions() {
    let text = geo("SHP a 0 0 0 1\nRCC b 0 0 0 0 0 1\nRCC c 0 0 0 0 0 1 12.7O\nSPH d 0 0 0 1\nSPH d 0 0 0 2\n  1 2 3", "r 5 +a +b +c +d");
    assert_eq!(
        errors(&text),
        [
            (5, 1, "unknown body type `SHP`".to_string()),
            (6, 1, "RCC `b` needs 7 values, found 6".to_string()),
            (
                7,
                19,
                "expected a number for RCC `c` value 7 (R), found `12.7O`".to_string()
            ),
            (9, 5, "body `d` is defined twice".to_string()),
        ]
    );
    let e = read_text(&text).unwrap_err();
    let first = e.errors().next().unwrap();
    assert_eq!(first.hint.as_deref(), Some("did you mean `SPH`?"));
    assert_eq!(
        e.errors().nth(3).unwrap().hint.as_deref(),
        Some("the first definition is on line 8")
    );
    assert_eq!(
        e.errors().nth(1).unwrap().render_plain(),
        "error: RCC `b` needs 7 values, found 6\n --> test.inp:6:1\n  |\n6 | RCC b 0 0 0 0 0 1\n  | ^^^\n  = hint: RCC values: V(3) H(3) R\n"
    );
    assert_eq!(
        errors(&geo("RPP\nSPH a 0 0 0 1", "r 5 +a")),
        [(5, 1, "`RPP` body has no name".to_string())]
    );
    assert_eq!(
        errors(&geo("SPH 1 0 0 0 1", "r 5 +a")).first().unwrap().2,
        "expected a body name after `SPH`, found `1`"
    );
    assert_eq!(
        errors(&geo("1 2 3\nSPH a 0 0 0 1", "r 5 +a")),
        [(5, 1, "expected a body type, found `1`".to_string())]
    );
}

#[test]
fn directive_errors() {
    let cases: [(&str, (usize, usize, &str)); 8] = [
        (
            "$start_rotate x\nSPH a 0 0 0 1",
            (5, 1, "unknown geometry directive `$start_rotate`"),
        ),
        (
            "$end_translat\nSPH a 0 0 0 1",
            (5, 1, "`$end_translat` without a matching `$start_translat`"),
        ),
        (
            "$start_translat 1 2 3\nSPH a 0 0 0 1",
            (5, 1, "`$start_translat` is never closed"),
        ),
        (
            "$start_translat 1 2\nSPH a 0 0 0 1\n$end_translat",
            (5, 1, "`$start_translat` needs three numbers dx dy dz"),
        ),
        (
            "$start_translat 1 2 x\nSPH a 0 0 0 1\n$end_translat",
            (5, 21, "expected a number for `$start_translat`, found `x`"),
        ),
        (
            "$start_expansion -2\nSPH a 0 0 0 1\n$end_expansion",
            (
                5,
                18,
                "`$start_expansion` needs a positive factor, found `-2`",
            ),
        ),
        (
            "$start_transform nope\nSPH a 0 0 0 1\n$end_transform",
            (
                5,
                18,
                "undefined transformation `nope`: no ROT-DEFI card has this name",
            ),
        ),
        (
            "$start_translat 1 2 3 4\nSPH a 0 0 0 1\n$end_translat",
            (5, 23, "unexpected `4` after `$start_translat`"),
        ),
    ];
    for (lines, (l, c, msg)) in cases {
        assert_eq!(
            errors(&geo(lines, "r 5 +a")),
            [(l, c, msg.to_string())],
            "{lines}"
        );
    }
    let e = read_text(&geo("$start_tranlsat 1 2 3\nSPH a 0 0 0 1", "r 5 +a")).unwrap_err();
    assert_eq!(
        e.errors().next().unwrap().hint.as_deref(),
        Some("did you mean `$start_translat`?")
    );
}

#[test]
fn region_errors() {
    let bodies = "SPH ball 0 0 0 1\nSPH world 0 0 0 9";
    let cases: [(&str, (usize, usize, &str)); 9] = [
        ("r 5 +world -bal", (8, 13, "region `r` refers to undefined body `bal`")),
        ("r 5 +world -(+ball", (8, 13, "in region `r`: `(` is never closed")),
        ("r 5 +world )", (8, 12, "in region `r`: unexpected `)` with no `(` open")),
        ("r 5 +world | | +ball", (8, 14, "in region `r`: empty zone: expected `+body` or `-body` before `|`")),
        ("r 5 +world -", (8, 13, "in region `r`: expected a body name, found the end of the region")),
        ("r 5", (8, 1, "region `r` has no expression")),
        ("r 5 +world\nr 5 +ball", (9, 1, "region `r` is defined twice")),
        ("r 5 +world\nworld -ball", (9, 1, "expected a region name and its NAZ number, or a line continuing a region with `+`, `-`, `|` or `(`; found `world`")),
        ("+world\nr 5 +ball", (8, 1, "region expression outside a region: expected a region name and its NAZ number first")),
    ];
    for (regions, (l, c, msg)) in cases {
        assert_eq!(
            errors(&geo(bodies, regions)),
            [(l, c, msg.to_string())],
            "{regions}"
        );
    }
    let e = read_text(&geo(bodies, "r 5 +world -bal")).unwrap_err();
    assert_eq!(
        e.errors().next().unwrap().hint.as_deref(),
        Some("did you mean `ball`?")
    );
    let deep = format!("r 5 {}+ball{}", "+(".repeat(70), ")".repeat(70));
    assert_eq!(
        errors(&geo(bodies, &deep))[0].2,
        "in region `r`: parentheses nested more than 64 levels deep"
    );
}

#[test]
fn zone_blow_up_is_an_error() {
    let bodies: String = (0..40).map(|i| format!("SPH s{i} 0 0 0 1\n")).collect();
    // −(a₁ b₁) −(a₂ b₂) … : 2²⁰ zones.
    let expr: String = (0..20)
        .map(|i| format!("-(+s{} +s{}) ", 2 * i, 2 * i + 1))
        .collect();
    let e = errors(&geo(&bodies, &format!("r 5 {expr}")));
    assert_eq!(
        e,
        [(
            47,
            1,
            "region `r` expands to more than 100000 zones".to_string()
        )]
    );
}

#[test]
fn names_are_letters_digits_and_underscores() {
    assert_eq!(
        errors(&geo("SPH beam-pipe 0 0 0 1", "r 5 +a")),
        [
            (5, 5, "body name `beam-pipe` must start with a letter and hold only letters, digits and `_`".to_string()),
            (7, 6, "region `r` refers to undefined body `a`".to_string()),
        ]
    );
    assert_eq!(
        errors(&geo("SPH a 0 0 0 1", "r.1 5 +a")),
        [(
            7,
            1,
            "region name `r.1` must start with a letter and hold only letters, digits and `_`"
                .to_string()
        )]
    );
}

#[test]
fn a_turned_quadric_keeps_its_surface() {
    // 314: ROT-DEFI WHAT(1)=3 (index 3, z axis), φ=−45°: (x,y,z) goes to
    // ((x−y)/√2, (x+y)/√2, z). The form 0.06x² + y − 20 must take the same
    // values at the moved points.
    let Some(l) = input("314_QUA_transform.inp") else {
        return;
    };
    let q = &body(&l, "parab").params;
    let value = |p: DVec3| {
        q[0] * p.x * p.x
            + q[1] * p.y * p.y
            + q[2] * p.z * p.z
            + q[3] * p.x * p.y
            + q[4] * p.x * p.z
            + q[5] * p.y * p.z
            + q[6] * p.x
            + q[7] * p.y
            + q[8] * p.z
            + q[9]
    };
    let turn = |x: f64, y: f64, z: f64| DVec3::new((x - y) * H, (x + y) * H, z);
    for (p, want) in [
        ((0.0, 20.0, 5.0), 0.0),
        ((0.0, 0.0, 0.0), -20.0),
        ((10.0, 0.0, 0.0), -14.0),
        ((3.0, -4.0, 7.0), -23.46),
    ] {
        let got = value(turn(p.0, p.1, p.2));
        assert!((got - want).abs() < 1e-9, "{p:?}: {got}");
    }
    // The plane XYP end1 (z < 100) is unchanged by a turn about z.
    assert_eq!(body(&l, "end1").kind, BodyKind::Pla);
    assert_close(&body(&l, "end1").params[..3], &[0.0, 0.0, 1.0]);
}

#[test]
fn structure_errors() {
    assert_eq!(
        errors("TITLE\nno geometry\nSTOP\n"),
        [(
            1,
            1,
            "no GEOBEGIN card: this input has no geometry".to_string()
        )]
    );
    assert_eq!(
        errors("GEOBEGIN                                                              COMBNAME\n  0 0\nSPH a 0 0 0 1\nEND\n"),
        [(1, 1, "GEOBEGIN without GEOEND".to_string())]
    );
    assert_eq!(
        errors("GEOBEGIN                                                              COMBNAME\n  0 0\nSPH a 0 0 0 1\nGEOEND\n"),
        [(4, 1, "missing END after the bodies".to_string())]
    );
    assert_eq!(
        errors("GEOBEGIN                                                              COMBNAME\n  0 0\nSPH a 0 0 0 1\nEND\nr 5 +a\nGEOEND\n"),
        [(6, 1, "missing END after the regions".to_string())]
    );
    let text = geo("SPH a 0 0 0 1", "r 5 +a").replace(
        "END\nGEOEND",
        "END\nROT-DEFI  , 0, 0, 0, 0, 0, 0, x\nGEOEND",
    );
    assert_eq!(
        errors(&text),
        [(
            9,
            1,
            "expected LATTICE or GEOEND after the regions, found `ROT-DEFI`".to_string()
        )]
    );
    let text = geo("SPH a 0 0 0 1", "r 5 +a")
        + "GEOBEGIN                                                              COMBNAME\n";
    assert_eq!(
        errors(&text),
        [(
            11,
            1,
            "second GEOBEGIN card: an input holds one geometry".to_string()
        )]
    );
}

#[test]
fn fixed_format_numbered_geometry_is_refused_by_name() {
    let text = "GEOBEGIN                                                              COMBINAT\n    0    0\n  SPH    1       0.0       0.0       0.0       1.0\n  END\n  001    5 +1\n  END\nGEOEND\n";
    let e = read_text(text).unwrap_err();
    let d = e.errors().next().unwrap();
    assert_eq!(
        d.message,
        "the fixed-format numbered geometry (GEOBEGIN SDUM `COMBINAT`) is not supported"
    );
    assert_eq!(d.line_col(), (1, 71));
    assert_eq!(
        d.hint.as_deref(),
        Some("write the geometry in free format with names: GEOBEGIN with SDUM COMBNAME")
    );
    let blank = "GEOBEGIN\n    0    0\nEND\nEND\nGEOEND\n";
    assert_eq!(errors(blank)[0].2, "the fixed-format numbered geometry (GEOBEGIN blank SDUM, which means COMBINAT) is not supported");
    let unit = "GEOBEGIN                      21.                                     COMBNAME\n";
    let unit = format!("{unit}    0    0\nEND\nEND\nGEOEND\n");
    assert_eq!(
        errors(&unit)[0].2,
        "geometry read from a separate logical unit (GEOBEGIN WHAT(3) = 21.) is not supported"
    );
}

#[test]
fn rot_defi_errors() {
    let card = format!(
        "{:<10}{:>10}{:>10}{:>10}{:>10}{:>10}{:>10}t\n",
        "ROT-DEFI", "500.", "0.", "0.", "0.", "0.", "0."
    );
    let text = geo("SPH a 0 0 0 1", "r 5 +a") + &card;
    assert_eq!(
        errors(&text),
        [(
            11,
            17,
            "ROT-DEFI axis code j = 5 is not 1 (x), 2 (y) or 3 (z)".to_string()
        )]
    );
    let text = geo("SPH a 0 0 0 1", "r 5 +a") + "ROT-DEFI  , 100., abc, 0, 0, 0, 0, t\n";
    assert_eq!(
        errors(&text),
        [(
            11,
            19,
            "expected a number in ROT-DEFI WHAT(2), found `abc`".to_string()
        )]
    );
}

#[test]
fn materials_and_black_holes() {
    let Some(l) = input("001_RPP.inp") else {
        return;
    };
    let i = l.scene.geometry.region_index("blackhole").unwrap();
    assert!(l.scene.regions[i].transparent);
    assert_eq!(l.scene.regions[i].description, "material: BLCKHOLE");
    let j = l.scene.geometry.region_index("rppreg").unwrap();
    assert!(!l.scene.regions[j].transparent);
    assert_eq!(l.scene.regions[j].description, "material: BERYLLIU");
    // `ASSIGNMA BLCKHOLE bbr` names a region that does not exist.
    let w: Vec<_> = l
        .warnings
        .iter()
        .map(|w| (w.line_col(), w.message.as_str()))
        .collect();
    assert_eq!(w, [((18, 28), "ASSIGNMA refers to undefined region `bbr`")]);
    // A range: ASSIGNMA , BERYLLIU, BE3, BE4 (free format).
    let l = input("manualSimpleFileFixed.inp").unwrap();
    let d: Vec<_> = l
        .scene
        .regions
        .iter()
        .map(|p| p.description.as_str())
        .collect();
    assert_eq!(
        d,
        [
            "material: BLCKHOLE",
            "material: VACUUM",
            "material: BERYLLIU",
            "material: BERYLLIU"
        ]
    );
    assert_eq!(l.scene.regions[1].air, 1);
    assert!(
        l.scene.regions[1].transparent,
        "vacuum is air: hidden unless --show-air"
    );
    assert_eq!(
        l.scene.title,
        "Charged pion fluence inside and around a proton-irradiated Be target"
    );
    // No ASSIGNMA at all.
    let l = read_text(&geo("SPH a 0 0 0 1", "r 5 +a")).unwrap();
    assert!(!l.scene.regions[0].transparent);
    assert_eq!(
        l.scene.notes,
        ["no ASSIGNMA cards: every region is drawn opaque"]
    );
}

#[test]
fn titles() {
    let Some(l) = input("104_shift_cylinders.inp") else {
        return;
    };
    assert_eq!(l.scene.title, "Correctly shift the cylinder alon its axis.");
    // With an empty TITLE the geometry title line is used.
    let l = input("601_filter_redundant_halfspaces.inp").unwrap();
    assert_eq!(l.scene.title, "MC-CAD");
    let l = input("manualSimpleFileFree.inp").unwrap();
    assert_eq!(
        l.scene
            .regions
            .iter()
            .map(|p| p.description.as_str())
            .collect::<Vec<_>>(),
        [
            "material: BLCKHOLE",
            "material: VACUUM",
            "material: BERYLLIU",
            "material: BERYLLIU"
        ]
    );
}

#[test]
fn lattice_containers_are_kept_and_noted() {
    let Some(l) = input("701_LATTICE.inp") else {
        return;
    };
    assert_eq!(
        l.scene.notes,
        ["LATTICE replicas are not drawn: lattice cell REPLICA is drawn as a plain region (its container only)"]
    );
    let l = input("702_LATTICE.inp").unwrap();
    assert!(l.scene.geometry.region_index("REPLICA").is_some());
    assert_eq!(zones(&l, "REPLICA"), ["+repl -repl2"]);
    assert_eq!(l.scene.notes, ["LATTICE replicas are not drawn: lattice cells REPLICA, REPLIC2 are drawn as plain regions (their containers only)"]);
    let text =
        geo("SPH a 0 0 0 1", "r 5 +a").replace("END\nGEOEND", "END\nLATTICE      cell\nGEOEND");
    assert_eq!(
        errors(&text),
        [(
            9,
            14,
            "LATTICE refers to undefined region `cell`".to_string()
        )]
    );
}

#[test]
fn a_comment_before_the_geometry_title_is_skipped() {
    let text = geo("SPH a 0 0 0 1", "r 5 +a").replace("COMBNAME\n", "COMBNAME\n* note\n");
    let l = read_text(&text.replace("TITLE\nhand-made\n", "")).unwrap();
    assert_eq!(l.scene.title, "test");
}

#[test]
fn comments_are_skipped() {
    let text = geo(
        "* a comment\nSPH a 0 0 0 1 ! trailing\n!whole line",
        "* note\nr 5 +a ! comment -b",
    );
    let l = read_text(&text).unwrap();
    assert_eq!(zones(&l, "r"), ["+a"]);
}

/// Every input of the data set, for mutation.
fn corpus() -> Vec<String> {
    let Some(dir) = data_dir() else {
        return vec![geo("SPH a 0 0 0 1", "r 5 +a -(+a | -a)")];
    };
    let mut names: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    names.sort();
    names
        .iter()
        .map(|p| std::fs::read_to_string(p).unwrap())
        .collect()
}

#[derive(Clone, Debug)]
enum Edit {
    Insert(usize, String),
    Delete(usize, usize),
    DuplicateLine(usize),
    SwapLines(usize, usize),
}

fn edit() -> impl Strategy<Value = Edit> {
    let snippet = prop_oneof![
        Just("(".to_string()),
        Just(")".to_string()),
        Just("-(".to_string()),
        Just("|".to_string()),
        Just("\n".to_string()),
        Just("#if X\n".to_string()),
        Just("#endif\n".to_string()),
        Just("#include 904_preprocessor_include.inp\n".to_string()),
        Just("$start_transform -x\n".to_string()),
        Just("$end_expansion\n".to_string()),
        Just("END\n".to_string()),
        Just("GEOEND\n".to_string()),
        Just("1e308 ".to_string()),
        Just("é".to_string()),
        "[ -~]{0,8}",
    ];
    prop_oneof![
        (any::<usize>(), snippet).prop_map(|(p, s)| Edit::Insert(p, s)),
        (any::<usize>(), 0usize..40).prop_map(|(p, n)| Edit::Delete(p, n)),
        any::<usize>().prop_map(Edit::DuplicateLine),
        (any::<usize>(), any::<usize>()).prop_map(|(a, b)| Edit::SwapLines(a, b)),
    ]
}

fn apply(text: &str, edits: &[Edit]) -> String {
    let mut chars: Vec<char> = text.chars().collect();
    for e in edits {
        match e {
            Edit::Insert(p, s) => {
                let at = p % (chars.len() + 1);
                chars.splice(at..at, s.chars());
            }
            Edit::Delete(p, n) => {
                let at = p % (chars.len() + 1);
                let end = (at + n).min(chars.len());
                chars.drain(at..end);
            }
            Edit::DuplicateLine(i) | Edit::SwapLines(i, _) => {
                let s: String = chars.iter().collect();
                let mut lines: Vec<&str> = s.split('\n').collect();
                let a = i % lines.len();
                if let Edit::SwapLines(_, j) = e {
                    let b = j % lines.len();
                    lines.swap(a, b);
                } else {
                    lines.insert(a, lines[a]);
                }
                chars = lines.join("\n").chars().collect();
            }
        }
    }
    chars.into_iter().collect()
}

proptest! {
    // 400 cases by default; PROPTEST_CASES=N runs more.
    #![proptest_config(ProptestConfig {
        cases: std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(400),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn mutated_inputs_never_panic(pick in any::<usize>(), edits in prop::collection::vec(edit(), 1..8)) {
        let corpus = corpus();
        let text = apply(&corpus[pick % corpus.len()], &edits);
        // Named inside the data folder so #include resolves against it.
        let name = format!("{DATA}mutated.inp");
        let result = fluka::read(&SourceFile::new(name, text), &LoadOptions::default());
        if let Err(d) = result {
            prop_assert!(d.has_errors());
            for e in &d.items {
                let _ = e.render_plain();
            }
        }
    }
}

#[test]
fn errors_past_the_limit_are_counted() {
    let bodies: String = (0..150).map(|i| format!("SHP s{i} 0 0 0 1\n")).collect();
    let e = read_text(&geo(&bodies, "r 5 +s0")).unwrap_err();
    assert_eq!(e.items.len(), fluka::MAX_ERRORS + 1);
    assert_eq!(e.items.last().unwrap().message, "… and 50 more errors");
}

#[test]
fn values_driven_out_of_range_by_directives_are_errors() {
    let text = geo(
        "$start_expansion 1e100\nSPH big 0 0 0 1e300\n$end_expansion",
        "r 5 +big",
    );
    assert_eq!(
        errors(&text),
        [(
            6,
            1,
            "body `big` has a value out of range after its transformation".to_string()
        )]
    );
    let text = geo(
        "$start_expansion 1e200\n$start_expansion 1e200\nSPH big 0 0 0 1\n$end_expansion\n$end_expansion",
        "r 5 +big",
    );
    assert_eq!(
        errors(&text),
        [(
            7,
            1,
            "the directives around body `big` make a transformation out of range".to_string()
        )]
    );
}

#[test]
fn free_format_cards_after_free() {
    let text = "FREE\nTITLE\nfree cards\nGEOBEGIN COMBNAME\n0 0 geometry\nSPH a 0 0 0 1\nRPP w -2 2 -2 2 -2 2\nEND\nvoid 5 +w -a\nball 5 +a\nEND\nGEOEND\nASSIGNMA BLCKHOLE void\nASSIGNMA LEAD ball\nROT-DEFI 100 0 90 0 0 0 unused\n";
    let l = read_text(text).unwrap();
    assert_eq!(l.scene.title, "free cards");
    assert!(l.scene.regions[0].transparent);
    assert_eq!(l.scene.regions[1].description, "material: LEAD");
}

#[test]
fn lattice_ranges_cover_every_region_between() {
    let text = geo(
        "SPH a 0 0 0 1\nSPH b 0 0 0 2\nSPH c 0 0 0 3",
        "r1 5 +a\nr2 5 +b -a\nr3 5 +c -b",
    )
    .replace("END\nGEOEND", "END\nLATTICE   , r1, r3, , , , , t\nGEOEND");
    let l = read_text(&text).unwrap();
    assert_eq!(
        l.scene.notes.last().unwrap(),
        "LATTICE replicas are not drawn: lattice cells r1, r2, r3 are drawn as plain regions (their containers only)"
    );
    assert_eq!(
        l.warnings[0].message,
        "LATTICE transformation `t` has no ROT-DEFI card"
    );
}

#[test]
fn large_inputs_stay_cheap() {
    // 20 000 bodies, regions and ASSIGNMA ranges, and 20 000 references to
    // missing bodies (only the first errors are kept, without hints).
    let n = 20_000;
    let bodies: String = (0..n)
        .map(|i| format!("SPH b{i} 0 0 0 {}\n", i + 1))
        .collect();
    let regions: String = (0..n)
        .map(|i| format!("r{i} 5 +b{i} -missing{i}\n"))
        .collect();
    let mut text = geo(&bodies, &regions);
    for _ in 0..100 {
        text.push_str(&format!("ASSIGNMA  , LEAD, r0, r{}\n", n - 1));
    }
    let e = read_text(&text).unwrap_err();
    assert_eq!(e.items.len(), fluka::MAX_ERRORS + 1);
    assert_eq!(e.items[0].hint, None);
    let fine: String = (0..n).map(|i| format!("r{i} 5 +b{i}\n")).collect();
    let mut text = geo(&bodies, &fine);
    for _ in 0..100 {
        text.push_str(&format!("ASSIGNMA  , LEAD, r0, r{}\n", n - 1));
    }
    let l = read_text(&text).unwrap();
    assert_eq!(l.scene.geometry.regions.len(), n);
    assert!(l
        .scene
        .regions
        .iter()
        .all(|p| p.description == "material: LEAD"));
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(400),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn arbitrary_geometry_text_never_panics(text in "([ -~\t]{0,30}\n){0,30}") {
        let input = format!("GEOBEGIN                                                              COMBNAME\n{text}");
        let _ = read_text(&input);
        let _ = read_text(&format!("{input}\nEND\nr 5 +a\nEND\nGEOEND\n"));
    }
}
