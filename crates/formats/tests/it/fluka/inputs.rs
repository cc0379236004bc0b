//! The pyg4ometry test inputs: counts, body values, transforms, regions and the preprocessor.

use super::*;

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
    // Values that make each body whole (the reader checks the geometry
    // rules too), read back in card order.
    let cards = [
        "RPP a 1 2 3 4 5 6",
        "BOX b 0 0 0 1 0 0 0 2 0 0 0 3",
        "SPH c 1 2 3 4",
        "RCC d 1 2 3 4 5 6 7",
        "REC e 0 0 0 0 0 5 1 0 0 0 2 0",
        "TRC f 1 2 3 4 5 6 7 8",
        "ELL g 0 0 0 0 0 2 4",
        "WED h 0 0 0 1 0 0 0 2 0 0 0 3",
        "RAW i 0 0 0 1 0 0 0 2 0 0 0 3",
        "ARB j 0 0 0 1 0 0 1 1 0 0 1 0 0 0 1 1 0 1 1 1 1 0 1 1 4321 5678 1265 2376 3487 4158",
        "XYP k 1",
        "XZP l 1",
        "YZP m 1",
        "PLA n 1 2 3 4 5 6",
        "XCC o 1 2 3",
        "YCC p 1 2 3",
        "ZCC q 1 2 3",
        "XEC r 1 2 3 4",
        "YEC s 1 2 3 4",
        "ZEC t 1 2 3 4",
        "QUA u 1 2 3 4 5 6 7 8 9 10",
    ];
    let text = geo(
        &cards.join("\n"),
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
    for (b, card) in l.scene.geometry.bodies.iter().zip(cards) {
        let want: Vec<f64> = card
            .split_whitespace()
            .skip(2)
            .map(|v| v.parse().unwrap())
            .collect();
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
fn regions_keep_their_parentheses_as_groups() {
    let Some(l) = input("101_Intersection.inp") else {
        return;
    };
    assert_eq!(zones(&l, "blackhole"), ["+blackhole -(+rpp1 +rpp2)"]);
    assert_eq!(zones(&l, "intreg"), ["+rpp1 +rpp2"]);
    let l = input("102_Difference.inp").unwrap();
    assert_eq!(zones(&l, "blackhole"), ["+blackhole -(+rpp1 -rpp2)"]);
    assert_eq!(zones(&l, "subreg"), ["+rpp1 -rpp2"]);
    let l = input("103_Union.inp").unwrap();
    assert_eq!(zones(&l, "unionreg"), ["+rpp1", "+rpp2"]);
    assert_eq!(zones(&l, "blackhole"), ["+blackhole -rpp1 -rpp2"]);
    // Three subtracted six-plane cubes: one zone, three groups of six
    // terms (216 zones if it were expanded).
    let l = input("310_XYP_transform.inp").unwrap();
    let r = region(&l, "blackhol");
    assert_eq!(r.zones.len(), 1);
    assert_eq!(r.zones[0].groups.len(), 3);
    assert!(r.zones[0]
        .groups
        .iter()
        .all(|g| g.zones.len() == 1 && g.zones[0].terms.len() == 6));
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
    assert_eq!(zones(&l, "r1"), ["+d -(+a | +b -c)"]);
    assert_eq!(zones(&l, "r2"), ["+a +(+b | +c)", "-d"]);
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
    assert_eq!(body_names(&l), ["x", "y"]);
}

#[test]
fn pyramids_become_polyhedra_of_their_corners() {
    // The manual's example: a PYZ truncated to 0.8 of its major base, and a
    // full PYX.
    let l = read_text(&geo(
        "PYZ body3 0.0 0.5 -10.0 +20.0 +40.0 50.0 0.8\nPYX apex 1 0 0 2 3 -4 0",
        "r 5 +body3\nq 5 +apex",
    ))
    .unwrap();
    let b = body(&l, "body3");
    assert_eq!(b.kind, BodyKind::Arb8);
    assert_close(&b.params[..3], &[-20.0, -39.5, -10.0]);
    assert_close(&b.params[18..21], &[16.0, 32.5, 40.0]);
    let a = body(&l, "apex");
    assert_eq!(a.kind, BodyKind::Arb5);
    assert_close(&a.params[..3], &[1.0, -2.0, -3.0]);
    assert_close(&a.params[12..], &[-3.0, 0.0, 0.0]);
    let e = errors(&geo("PYY p 0 0 0 1 1 5 1.5", "r 5 +p"));
    assert_eq!(
        e,
        [(
            5,
            1,
            "PYY `p`: its ratio R = 1.5 must be at least 0 and below 1".to_string()
        )]
    );
}
