//! COMGEOM / GIFT deck reader and writer: the real decks, every body type
//! they hold, region references, ident metadata, round trips, every error
//! kind with its exact text, and mutation robustness.

use proptest::prelude::*;
use sv_formats::{comgeom, DeckVersion, Diagnostics, LoadOptions, Loaded, Severity, SourceFile};
use sv_geom::{BodyKind, Geometry, Op, Term};
use sv_scene::{Scene, Units};

const DECKS: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../../shared/decks/comgeom/"
);
const VDECK: &str = "vdeck-all-types.cg";
const GIFT: &str = "gift-sample-target-v4.cg";
const GENERATOR: &str = "mep021a-generator-v5.cg";

/// The text of a shared deck, or `None` (with a message) when the shared
/// decks are not next to the repository.
fn deck_text(name: &str) -> Option<String> {
    let path = format!("{DECKS}{name}");
    match std::fs::read(&path) {
        Ok(b) => Some(String::from_utf8_lossy(&b).into_owned()),
        Err(e) => {
            eprintln!("skipping: cannot read {path}: {e}");
            None
        }
    }
}

fn read_text(name: &str, text: &str) -> Result<Loaded, Diagnostics> {
    comgeom::read(&SourceFile::new(name, text), &LoadOptions::default())
}

/// Read a deck that must load, showing the diagnostics (not the whole
/// deck) when it does not.
fn read_ok(name: &str, text: &str) -> Loaded {
    read_text(name, text).unwrap_or_else(|d| panic!("{name} does not load:\n{}", d.render_plain()))
}

fn load(name: &str) -> Option<Loaded> {
    let text = deck_text(name)?;
    match read_text(name, &text) {
        Ok(l) => Some(l),
        Err(d) => panic!("{name} does not load:\n{}", d.render_plain()),
    }
}

/// The error messages of a deck that must fail.
fn errors(text: &str) -> Vec<String> {
    match read_text("bad.cg", text) {
        Ok(_) => panic!("the deck was accepted:\n{text}"),
        Err(d) => d.errors().map(|e| e.message.clone()).collect(),
    }
}

/// A v5 body card: number, type, values right-aligned in 10 columns.
fn v5_body(num: &str, ty: &str, vals: &[&str]) -> String {
    let mut s = format!("{num:>5}{ty:<5}");
    for v in vals {
        s.push_str(&format!("{v:>10}"));
    }
    s
}

/// A v5 region card: number, then (operator, number) fields.
fn v5_region(num: &str, fields: &[(&str, i64)]) -> String {
    let mut s = format!("{num:>5} ");
    for (op, n) in fields {
        s.push_str(&format!("{op:>2}{n:>5}"));
    }
    s
}

/// A v5 deck from body and region cards.
fn v5_deck(nb: usize, nr: usize, bodies: &[String], regions: &[String]) -> String {
    let mut s = format!("in   test deck\n{nb:>5}{nr:>5}\n");
    for b in bodies.iter().chain(regions) {
        s.push_str(b);
        s.push('\n');
    }
    s.push_str("   -1\n");
    s
}

fn sph(num: usize) -> String {
    v5_body(
        &num.to_string(),
        "SPH",
        &["0.", "0.", "0.", &format!("{num}.")],
    )
}

// ---------------------------------------------------------------- real decks

#[test]
fn real_decks_parse_with_the_documented_counts_and_versions() {
    for (name, version, bodies, regions) in [
        (VDECK, DeckVersion::V5, 19, 19),
        (GIFT, DeckVersion::V4, 20, 20),
        (GENERATOR, DeckVersion::V5, 282, 282),
    ] {
        let Some(text) = deck_text(name) else { return };
        assert_eq!(comgeom::detect_version(&text), version, "{name}");
        let l = load(name).unwrap();
        assert_eq!(l.scene.geometry.bodies.len(), bodies, "{name} bodies");
        assert_eq!(l.scene.geometry.regions.len(), regions, "{name} regions");
        assert_eq!(l.scene.regions.len(), regions, "{name} region properties");
        // Forcing the detected version reads the same thing.
        let forced = comgeom::read(
            &SourceFile::new(name, text.as_str()),
            &LoadOptions {
                deck_version: Some(version),
            },
        )
        .unwrap();
        assert_eq!(forced.scene.geometry, l.scene.geometry, "{name}");
        // Body and region names are their numbers.
        assert_eq!(l.scene.geometry.bodies[bodies - 1].name, bodies.to_string());
        assert_eq!(
            l.scene.geometry.regions[regions - 1].name,
            regions.to_string()
        );
    }
}

#[test]
fn real_decks_load_without_errors_and_only_the_gift_deck_warns() {
    for name in [VDECK, GENERATOR] {
        let Some(l) = load(name) else { return };
        assert!(
            l.warnings.is_empty(),
            "{name}: {:?}",
            l.warnings.iter().map(|w| &w.message).collect::<Vec<_>>()
        );
    }
    let Some(l) = load(GIFT) else { return };
    let msgs: Vec<_> = l.warnings.iter().map(|w| w.message.as_str()).collect();
    assert_eq!(
        msgs,
        ["line 85, columns 75–80: 20 v4 ident cards hold text, not material and line-of-sight numbers, in columns 75–80; they are kept in the description, and material 0 and line of sight 100 are used"]
    );
    assert!(l.warnings.iter().all(|w| w.severity == Severity::Warning));
}

#[test]
fn titles_and_units_come_from_the_title_card() {
    for (name, units, title) in [
        (VDECK, Units::Millimetre, "comgeom-g test TGM"),
        (GIFT, Units::Inch, "SAMPLE TARGET INPUT FOR GIFT CODE (V4)"),
        (GENERATOR, Units::Inch, "ADA073408 table"),
    ] {
        let Some(l) = load(name) else { return };
        assert_eq!(l.scene.units, units, "{name}");
        assert_eq!(l.scene.title, title, "{name}");
    }
}

/// Parsed values of one body of a real deck compared with its card text.
macro_rules! body_test {
    ($test:ident, $deck:expr, $number:expr, $kind:ident, [$($v:expr),* $(,)?]) => {
        #[test]
        fn $test() {
            let Some(l) = load($deck) else { return };
            let b = &l.scene.geometry.bodies[$number - 1];
            assert_eq!(b.name, stringify!($number));
            assert_eq!(b.kind, BodyKind::$kind);
            let expect: Vec<f64> = vec![$($v as f64),*];
            assert_eq!(b.params, expect);
        }
    };
}

// GIFT sample target (v4): every body type it holds.
body_test!(
    gift_tor_steering_wheel,
    GIFT,
    1,
    Tor,
    [21.5, 0, 37, 1, 0, 0, 8, 1]
);
body_test!(
    gift_arb4_steering_column,
    GIFT,
    2,
    Arb4,
    [21.5, -6, 33.5, 21.5, 6, 33.5, 21.5, 0, 44, 40, 0, 37]
);
body_test!(
    gift_arb5_body_front,
    GIFT,
    3,
    Arb5,
    [75, -36, 12, 75, 36, 12, 75, 36, 48, 75, -36, 48, 100, 0, 12]
);
body_test!(
    gift_arb8_body_rear,
    GIFT,
    4,
    Arb8,
    [
        -75, -36, 12, -75, 36, 12, -75, 36, 48, -75, -36, 48, -100, -24, 12, -100, 24, 12, -100,
        24, 20, -100, -24, 20
    ]
);
body_test!(
    gift_ell_is_the_foci_form_in_v4,
    GIFT,
    5,
    Ell,
    [20, 0, 48, -20, 0, 48, 50]
);
body_test!(gift_rpp_body, GIFT, 6, Rpp, [-75, 75, -36, 36, 12, 48]);
body_test!(gift_rcc_wheel, GIFT, 7, Rcc, [60, -36, 12, 0, 8, 0, 12]);
body_test!(
    gift_raw_engine_cover,
    GIFT,
    12,
    Raw,
    [-70, 0, 35, 0, -11, 11, 0, 11, 11, 40, 0, 0]
);
body_test!(
    gift_rec_torso,
    GIFT,
    13,
    Rec,
    [0, 0, 24, 0, 0, 28, 0, 7.5, 0, 5, 0, 0]
);
body_test!(gift_sph_head, GIFT, 14, Sph, [0, 0, 52, 5]);
body_test!(
    gift_tec_arm,
    GIFT,
    15,
    Tec,
    [0, -7.5, 49, 20, 0, -12, 0, 0, 3, 0, 2, 0, 2]
);
body_test!(
    gift_trc_leg,
    GIFT,
    17,
    Trc,
    [-2, -4.5, 27, 32, 0, -12, 3, 2]
);
body_test!(
    gift_ell1_inside_air,
    GIFT,
    19,
    Ell1,
    [0, 0, 48, 24, 0, 0, 14]
);
body_test!(
    gift_box_inside_air,
    GIFT,
    20,
    Box,
    [-74, -35, 13, 148, 0, 0, 0, 70, 0, 0, 0, 34]
);

#[test]
fn gift_ars_engine_reads_six_curves_of_five_points() {
    let Some(l) = load(GIFT) else { return };
    let b = &l.scene.geometry.bodies[10];
    assert_eq!(b.kind, BodyKind::Ars);
    assert_eq!(b.params.len(), 2 + 6 * 5 * 3);
    assert_eq!(b.params[..2], [6.0, 5.0]);
    let point = |c: usize, p: usize| b.params[2 + (c * 5 + p) * 3..][..3].to_vec();
    // Curve 1 is the degenerate point (-30,-10,15); the "." in an unused
    // field of card 11-4 is ignored.
    for p in 0..5 {
        assert_eq!(point(0, p), [-30.0, -10.0, 15.0]);
    }
    // Curve 2 (cards 11-5..11-7), curve 4 (cards 11-11..11-13).
    assert_eq!(point(1, 1), [-70.0, -10.0, 15.0]);
    assert_eq!(point(1, 2), [-70.0, 10.0, 15.0]);
    assert_eq!(point(1, 3), [-30.0, 10.0, 15.0]);
    assert_eq!(point(3, 2), [-70.0, 20.0, 35.0]);
    assert_eq!(point(5, 4), [-30.0, -10.0, 45.0]);
}

// vdeck (v5, lower-case type names): every body type BRL-CAD writes.
body_test!(
    vdeck_arb4,
    VDECK,
    1,
    Arb4,
    [3, 0, -3, 3, 0, 0, 3, -3, -3, 0, 0, -3]
);
body_test!(
    vdeck_arb5,
    VDECK,
    2,
    Arb5,
    [1, 0, 0, 1, 2, 0, 3, 2, 0, 3, 0, 0, 1.5, 1.5, 5]
);
body_test!(
    vdeck_arb6,
    VDECK,
    3,
    Arb6,
    [2, -0.5, -0.5, 2, 0, -0.5, 2, 0, 0, 2, -0.5, 0, 2.5, -0.3, -0.5, 2.5, -0.3, 0]
);
body_test!(
    vdeck_arb7,
    VDECK,
    4,
    Arb7,
    [
        3.25, -1.25, -0.75, 3.25, -0.25, -0.75, 3.25, -0.25, 0.25, 3.25, -1.25, -0.25, 2.25, -1.25,
        -0.75, 2.25, -0.25, -0.75, 2.25, -0.25, -0.25
    ]
);
body_test!(
    vdeck_arb8,
    VDECK,
    5,
    Arb8,
    [10, -9, -8, 10, -1, -8, 10, -1, 0, 10, -9, 0, 3, -9, -8, 3, -1, -8, 3, -1, 0, 3, -9, 0]
);
body_test!(
    vdeck_ars,
    VDECK,
    6,
    Ars,
    [
        3, 3, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 100, 100, 0, 100, 100, 100, 100, 0, 0, 200, 0, 0,
        200, 0, 0, 200
    ]
);
body_test!(
    vdeck_ellg,
    VDECK,
    8,
    Ellg,
    [10, 0, 0, -12, 0, 0, 0, -3, 0, 0, 0, 5]
);
body_test!(vdeck_ell1, VDECK, 9, Ell1, [3, 2, 8, 3, -1, 8, 4]);
body_test!(vdeck_haf, VDECK, 11, Haf, [0.5774, 0.5774, 0.5774, -5]);
body_test!(vdeck_rcc, VDECK, 12, Rcc, [0, 0, 0, 3, 3, 30, 7]);
body_test!(
    vdeck_tec,
    VDECK,
    13,
    Tec,
    [0, 0, 0, 3, 3, 10, 10, 0, 0, 0, 3, 0, 1]
);
body_test!(vdeck_sph, VDECK, 15, Sph, [42, 42, 42, 42]);
body_test!(
    vdeck_tgc,
    VDECK,
    17,
    Tgc,
    [0, 0, 0, 0, 0, 10, 5, 0, 0, 0, 8, 0, 2, 9]
);
body_test!(
    vdeck_tor,
    VDECK,
    18,
    Tor,
    [0, 0, 0, 0.3015, 0.3015, 0.9045, 5, 2]
);
body_test!(vdeck_trc, VDECK, 19, Trc, [0, 0, 0, 0, 0, 10, 4, 7]);

// MEP-021A generator (v5 with left-aligned numbers): its four body types.
body_test!(
    generator_rcc_crankshaft,
    GENERATOR,
    1,
    Rcc,
    [-303.0232, 0, 0, 697.4867, 0, 0, 12.7001]
);
body_test!(
    generator_arb8_block,
    GENERATOR,
    5,
    Arb8,
    [
        -303.0232, -50.6002, -35.5601, -303.0232, -152.4006, -35.5601, -303.0232, -152.4006,
        35.5601, -303.0232, -50.8002, 35.5601, -5.08, -50.8002, -35.5601, -5.08, -152.4006,
        -35.5601, -5.08, -152.4006, 35.5601, -5.08, -50.8002, 35.5601
    ]
);
body_test!(
    generator_trc_fan,
    GENERATOR,
    181,
    Trc,
    [74.7271, 0, 0, -38.1002, 0, 0, 151.1306, 45.5119]
);
body_test!(
    generator_rpp_stiffener,
    GENERATOR,
    277,
    Rpp,
    [-387.1686, 412.5687, 220.4729, 230.1249, -226.4571, -182.007]
);

fn terms(spec: &[i64]) -> Vec<Term> {
    spec.iter()
        .map(|&n| Term {
            op: if n < 0 { Op::Outside } else { Op::Inside },
            body: n.unsigned_abs() as usize - 1,
        })
        .collect()
}

#[test]
fn region_cards_become_zones_with_continuations() {
    let Some(l) = load(GIFT) else { return };
    let g = &l.scene.geometry;
    assert_eq!(g.regions[5].zones.len(), 1);
    assert_eq!(
        g.regions[5].zones[0].terms,
        terms(&[6, -20, -19, -7, -8, -9, -10])
    );
    assert_eq!(
        g.regions[12].zones[0].terms,
        terms(&[13, -15, -16, -17, -18])
    );
    let Some(l) = load(GENERATOR) else { return };
    let g = &l.scene.geometry;
    assert_eq!(
        g.regions[4].zones[0].terms,
        terms(&[5, -6, -7, -8, -28, -29, -30, -148])
    );
    // Line 766 continues the region above it (blank region number).
    assert_eq!(
        g.regions[215].zones[0].terms,
        terms(&[216, -217, -11, -17, -33, -39, -56, -62, -78, -84])
    );
}

#[test]
fn ident_tables_fill_region_metadata_and_air_is_transparent() {
    let Some(l) = load(GIFT) else { return };
    let r = &l.scene.regions;
    assert_eq!(
        (r[0].ident, r[0].air, r[0].material, r[0].los),
        (40, 0, 0, 100)
    );
    assert_eq!(r[0].description, "STEERING WHEEL     1-2              TOR");
    assert_eq!(r[5].description, "BODY-CENTER        6-20-19-7-8-9-10 RPP");
    assert_eq!(r[11].ident, 111);
    assert_eq!(r[11].description, "DUMMY REGION       0                RAW");
    for i in [18, 19] {
        assert_eq!((r[i].ident, r[i].air), (0, 2), "region {}", i + 1);
        assert!(r[i].transparent);
    }
    assert_eq!(r.iter().filter(|p| p.transparent).count(), 2);

    let Some(l) = load(VDECK) else { return };
    let r = &l.scene.regions;
    assert_eq!(
        (r[0].ident, r[0].air, r[0].material, r[0].los),
        (1000, 0, 1, 100)
    );
    assert_eq!(r[18].ident, 1018);
    assert_eq!(r[0].description, "all/arb4.r");
    assert!(r.iter().all(|p| !p.transparent));

    let Some(l) = load(GENERATOR) else { return };
    let r = &l.scene.regions;
    assert_eq!(
        (r[0].ident, r[0].air, r[0].material, r[0].los),
        (1, 0, 3, 100)
    );
    assert_eq!(r[0].description, "CRANKSHAFT");
    assert_eq!(
        (r[5].ident, r[5].air, r[5].material, r[5].los),
        (0, 5, 0, 0)
    );
    assert_eq!(r[5].description, "1AIR C-ROD");
    assert!(r[5].transparent && !r[4].transparent);
    assert_eq!(r[276].los, 60);
    assert_eq!(r[281].material, 25);
}

// ---------------------------------------------------------------- round trip

fn round_trip(scene: &Scene) -> Scene {
    let w = comgeom::write(scene).unwrap();
    assert_eq!(comgeom::detect_version(&w.text), DeckVersion::V5);
    match read_text("written.cg", &w.text) {
        Ok(l) => {
            assert!(l.warnings.is_empty(), "{:?}", l.warnings);
            l.scene
        }
        Err(d) => panic!(
            "written deck does not read:\n{}\n{}",
            d.render_plain(),
            w.text
        ),
    }
}

fn assert_same_props(a: &Scene, b: &Scene) {
    assert_eq!(a.title, b.title);
    assert_eq!(a.units, b.units);
    assert_eq!(a.regions.len(), b.regions.len());
    for (x, y) in a.regions.iter().zip(&b.regions) {
        assert_eq!(
            (x.ident, x.air, x.material, x.los, x.transparent),
            (y.ident, y.air, y.material, y.los, y.transparent)
        );
        assert_eq!(x.description, y.description);
    }
}

#[test]
fn written_v5_decks_read_back_to_the_same_geometry() {
    for name in [VDECK, GENERATOR] {
        let Some(l) = load(name) else { return };
        let w = comgeom::write(&l.scene).unwrap();
        assert!(w.notes.is_empty(), "{name}: {:?}", w.notes);
        let again = round_trip(&l.scene);
        assert_eq!(again.geometry, l.scene.geometry, "{name}");
        assert_same_props(&l.scene, &again);
        // Writing is stable.
        assert_eq!(comgeom::write(&again).unwrap().text, w.text);
    }
}

#[test]
fn written_gift_deck_reads_back_with_the_foci_ell_in_centre_form() {
    let Some(l) = load(GIFT) else { return };
    let w = comgeom::write(&l.scene).unwrap();
    assert_eq!(
        w.notes,
        ["body 5: ELL given by its foci is written as ELL1 (centre, semi-major axis, radius)"]
    );
    let again = round_trip(&l.scene);
    let mut expect: Geometry = l.scene.geometry.clone();
    let ell = &mut expect.bodies[4];
    ell.kind = BodyKind::Ell1;
    ell.params = comgeom::ell_foci_to_centre(&ell.params).to_vec();
    assert_eq!(ell.params, [0.0, 0.0, 48.0, -25.0, 0.0, 0.0, 15.0]);
    assert_eq!(again.geometry, expect);
    assert_same_props(&l.scene, &again);
}

#[test]
fn writer_keeps_full_precision_and_says_when_it_cannot() {
    let text = v5_deck(
        1,
        1,
        &[v5_body("1", "SPH", &["1.5e-7", "-2.25", "1e20", "0.1"])],
        &[v5_region("1", &[("", 1)])],
    );
    let mut scene = read_ok("p.cg", &text).scene;
    scene.geometry.bodies[0].params[3] = 0.1 + 0.2;
    let w = comgeom::write(&scene).unwrap();
    let again = read_ok("w.cg", &w.text).scene;
    assert_eq!(again.geometry.bodies[0].params[..3], [1.5e-7, -2.25, 1e20]);
    assert!((again.geometry.bodies[0].params[3] - 0.3).abs() < 1e-9);
    assert_eq!(
        w.notes,
        ["body 1 (SPH): value 4 (0.30000000000000004) written as 0.30000000 to fit 10 columns"]
    );
}

#[test]
fn writer_refuses_bodies_comgeom_cannot_express() {
    let mut scene = Scene::default();
    scene.geometry.bodies.push(sv_geom::Body::new(
        "wall",
        BodyKind::Xcc,
        vec![0.0, 0.0, 1.0],
    ));
    let e = comgeom::write(&scene).unwrap_err();
    assert_eq!(
        e.to_string(),
        "body wall is a XCC, which a COMGEOM deck cannot express"
    );
}

// ---------------------------------------------------------------- versions

#[test]
fn v1_decks_have_no_control_card_and_end_cards() {
    // Type in columns 3-5, number in 6-9, region fields from column 11.
    let deck = [
        "OLD MAGI STYLE DECK",
        "  RPP   1      -10.0      10.0     -10.0      10.0     -10.0      10.0",
        "  ELL   2        1.0       0.0       0.0      -1.0       0.0       0.0",
        "               3.0",
        "  END",
        "    1      +    1     -2",
        "    2      +    2",
        "  end",
        "",
    ]
    .join("\n");
    let deck = deck.as_str();
    assert_eq!(comgeom::detect_version(deck), DeckVersion::V1);
    let l = read_ok("v1.cg", deck);
    let g = &l.scene.geometry;
    assert_eq!(l.scene.units, Units::Inch);
    assert_eq!(l.scene.title, "OLD MAGI STYLE DECK");
    assert_eq!(g.bodies.len(), 2);
    assert_eq!(g.bodies[1].kind, BodyKind::Ell);
    assert_eq!(g.bodies[1].params, [1.0, 0.0, 0.0, -1.0, 0.0, 0.0, 3.0]);
    assert_eq!(g.regions[0].zones[0].terms, terms(&[1, -2]));
    assert_eq!(g.regions[1].zones[0].terms, terms(&[2]));
}

#[test]
fn ell_means_foci_in_v4_and_centre_in_v5() {
    let v4 = "in   v4\n                   1         1\n1  ELL       0.        0.        0.        2.        0.        0.\n1             4.\n  1       1\n-1\n\n  1         100\n";
    assert_eq!(comgeom::detect_version(v4), DeckVersion::V4);
    let b = &read_ok("v4.cg", v4).scene.geometry.bodies[0];
    assert_eq!(
        (b.kind, b.params.as_slice()),
        (BodyKind::Ell, &[0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 4.0][..])
    );
    let v5 = v5_deck(
        1,
        1,
        &[
            v5_body("1", "ell", &["0.", "0.", "0.", "2.", "0.", "0."]),
            v5_body("", "", &["4."]),
        ],
        &[v5_region("1", &[("", 1)])],
    );
    let b = &read_ok("v5.cg", &v5).scene.geometry.bodies[0];
    assert_eq!(
        (b.kind, b.params.as_slice()),
        (BodyKind::Ell1, &[0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 4.0][..])
    );
}

#[test]
fn a_blank_card_after_minus_one_means_v4() {
    // No body card to tell (an unknown type), so the blank card decides.
    let deck = "in   t\n    1    1\n    1XYZ       1.\n    1       1\n   -1\n\n    1  100\n";
    assert_eq!(comgeom::detect_version(deck), DeckVersion::V4);
    assert_eq!(
        comgeom::detect_version(&deck.replace("\n\n", "\n")),
        DeckVersion::V5
    );
}

#[test]
fn units_are_case_blind_and_unknown_units_warn_and_mean_inches() {
    let body = [sph(1)];
    let region = [v5_region("1", &[("", 1)])];
    for (card, units) in [
        ("MM", Units::Millimetre),
        ("ft", Units::Foot),
        ("Cm", Units::Centimetre),
        ("m ", Units::Metre),
    ] {
        let deck = v5_deck(1, 1, &body, &region).replacen("in ", card, 1);
        assert_eq!(read_ok("u.cg", &deck).scene.units, units, "{card}");
    }
    let deck = v5_deck(1, 1, &body, &region).replacen("in ", "yd ", 1);
    let l = read_ok("u.cg", &deck);
    assert_eq!(l.scene.units, Units::Inch);
    assert_eq!(
        l.warnings[0].message,
        "line 1, columns 1–2: unknown units \"yd\"; inches assumed"
    );
}

#[test]
fn region_fields_that_straddle_column_7_are_read_from_the_column_that_fits() {
    // MEP-021A style (left-aligned numbers from column 10) with a 4-digit
    // body number: "-1000" in columns 17-21 crosses the documented fields.
    let bodies: Vec<String> = (1..=1000).map(sph).collect();
    let region = format!("{:<9}{:<7}{:<7}", "  1", "1", "-1000");
    let l = read_text("wide.cg", &v5_deck(1000, 1, &bodies, &[region])).unwrap();
    assert_eq!(
        l.scene.geometry.regions[0].zones[0].terms,
        terms(&[1, -1000])
    );
    let msgs: Vec<_> = l.warnings.iter().map(|w| w.message.as_str()).collect();
    assert_eq!(
        msgs,
        ["line 1003, columns 7–69: the region fields do not fit the columns from 7 (first on this card); every region card reads with fields from column 8, so that is used"]
    );

    // GIFT style (right-aligned numbers ending in columns 11, 18, ...).
    let mut deck = String::from("in   gift style\n                1001         1\n");
    for n in 1..=1001 {
        deck.push_str(&format!(
            "{:<3}{:<7}{:>10}{:>10}{:>10}{:>10}\n",
            n % 1000,
            "SPH",
            "0.",
            "0.",
            "0.",
            "1."
        ));
    }
    deck.push_str(&format!(
        "{:>3}{:>8}{:>7}\n-1\n\n  1         100\n",
        "1", "1000", "-1001"
    ));
    assert_eq!(comgeom::detect_version(&deck), DeckVersion::V4);
    let l = read_ok("gift.cg", &deck);
    assert_eq!(l.scene.geometry.bodies.len(), 1001);
    assert_eq!(
        l.scene.geometry.regions[0].zones[0].terms,
        terms(&[1000, -1001])
    );
    assert_eq!(l.warnings.len(), 1);
    assert!(
        l.warnings[0]
            .message
            .ends_with("fields from column 6, so that is used"),
        "{}",
        l.warnings[0].message
    );
}

// ---------------------------------------------------------------- region references

/// Membership of a point described by which bodies contain it.
fn in_zones(zones: &[sv_geom::Zone], inside: &dyn Fn(usize) -> bool) -> bool {
    zones.iter().any(|z| {
        z.terms
            .iter()
            .all(|t| inside(t.body) == (t.op == Op::Inside))
    })
}

#[test]
fn region_references_expand_to_the_same_point_sets() {
    // Region 1 = (1 - 2) OR 3; region 2 = 4 OR (5 - 6);
    // region 3 = 5 + region 1 - region 2; region 4 = 6 - region 3 OR 1.
    let bodies: Vec<String> = (1..=6).map(sph).collect();
    let regions = [
        v5_region("1", &[("", 1), ("", -2), ("OR", 3)]),
        v5_region("2", &[("", 4), ("OR", 5), ("", -6)]),
        v5_region("3", &[("", 5), (" G", 1), (" G", -2)]),
        v5_region("4", &[("", 6), ("G", -3), ("OR", 1)]),
    ];
    let l = read_text("refs.cg", &v5_deck(6, 4, &bodies, &regions)).unwrap();
    let g = &l.scene.geometry;
    for bits in 0u32..64 {
        let b = |i: usize| bits & (1 << i) != 0; // body index i
        let r1 = (b(0) && !b(1)) || b(2);
        let r2 = b(3) || (b(4) && !b(5));
        let r3 = b(4) && r1 && !r2;
        let r4 = (b(5) && !r3) || b(0);
        for (i, want) in [r1, r2, r3, r4].into_iter().enumerate() {
            assert_eq!(
                in_zones(&g.regions[i].zones, &b),
                want,
                "region {} bodies {bits:06b}",
                i + 1
            );
        }
    }
    // The expansion is plain body terms, so it writes and reads back.
    assert_eq!(round_trip(&l.scene).geometry, *g);
}

#[test]
fn region_expansion_is_capped() {
    // Region 1 is the union of 9 one-term zones; intersecting it three times
    // gives 9^3 = 729 zones. Region 2 is one zone of 9 terms, so subtracting
    // it splits each zone in 9: 6561 zones, over the cap.
    let bodies: Vec<String> = (1..=18).map(sph).collect();
    let wide: Vec<(&str, i64)> = (1..=9)
        .map(|n| if n == 1 { ("", n) } else { ("OR", n) })
        .collect();
    let pairs: Vec<(&str, i64)> = (1..=9).map(|n| ("", n)).collect();
    let regions = [
        v5_region("1", &wide),
        v5_region(
            "2",
            &pairs.iter().map(|&(o, n)| (o, n + 9)).collect::<Vec<_>>(),
        ),
        v5_region("3", &[("G", 1), ("G", 1), ("G", 1), ("G", -2)]),
    ];
    let errs = errors(&v5_deck(18, 3, &bodies, &regions));
    assert_eq!(errs, ["line 23, columns 30–34: region 3: subtracting region 2 expands to more than 4096 zones"]);
}

#[test]
fn missing_and_cyclic_region_references_are_errors() {
    let bodies = [sph(1)];
    let regions = [
        v5_region("1", &[("", 1), ("G", -2)]),
        v5_region("2", &[("G", 3)]),
        v5_region("3", &[("G", 2)]),
        v5_region("4", &[("G", 9)]),
    ];
    assert_eq!(
        errors(&v5_deck(1, 4, &bodies, &regions)),
        [
            "line 6, columns 9–13: region 3 refers to region 2, which leads back to region 3 (a cycle)",
            "line 7, columns 9–13: region 4 refers to region 9, which is not defined",
        ]
    );
}

#[test]
fn a_first_region_card_may_start_with_an_operator() {
    // Columns 6-10 of "    1 OR    1" hold letters, but it is a region card.
    let bodies = [sph(1), sph(2)];
    let regions = [
        v5_region("1", &[("OR", 1), ("", -2)]),
        v5_region("2", &[(" G", 1), ("", 1)]),
    ];
    let l = read_text("op.cg", &v5_deck(2, 2, &bodies, &regions)).unwrap();
    assert_eq!(l.scene.geometry.regions[0].zones[0].terms, terms(&[1, -2]));
    // Region 1 intersected with body 1 again: the repeated term is dropped.
    assert_eq!(l.scene.geometry.regions[1].zones[0].terms, terms(&[1, -2]));
    // Without the control card's count it is still not read as a body.
    let deck = v5_deck(2, 2, &bodies, &regions).replacen("    2    2", "    0    0", 1);
    let l = read_ok("op.cg", &deck);
    assert_eq!(l.scene.geometry.bodies.len(), 2);
    assert_eq!(l.scene.geometry.regions.len(), 2);
}

// ---------------------------------------------------------------- errors

#[test]
fn a_malformed_number_names_line_columns_field_and_text() {
    let deck = v5_deck(
        1,
        1,
        &[
            v5_body("1", "RCC", &["0.", "0.", "0.", "0.", "0.", "10."]),
            v5_body("", "", &["12.7O"]),
        ],
        &[v5_region("1", &[("", 1)])],
    );
    let d = read_text("bad.cg", &deck).unwrap_err();
    assert_eq!(d.items.len(), 1);
    let e = &d.items[0];
    assert_eq!(
        e.message,
        "line 4, columns 11–20: expected a number for RCC radius (R), found \"12.7O\""
    );
    assert_eq!(
        e.hint.as_deref(),
        Some("numbers are plain decimals such as 12.5, -3., .75 or 1.5E-3")
    );
    assert_eq!(
        e.render_plain(),
        "error: line 4, columns 11–20: expected a number for RCC radius (R), found \"12.7O\"\n --> bad.cg:4:11\n  |\n4 |                12.7O\n  |           ^^^^^^^^^^\n  = hint: numbers are plain decimals such as 12.5, -3., .75 or 1.5E-3\n"
    );
    // A vector component is named too.
    let deck = v5_deck(
        1,
        1,
        &[
            v5_body("1", "RCC", &["0.", "0.", "0.", "0.", "1D3", "10."]),
            v5_body("", "", &["1."]),
        ],
        &[v5_region("1", &[("", 1)])],
    );
    assert_eq!(
        errors(&deck),
        ["line 3, columns 51–60: expected a number for RCC height vector (H.y), found \"1D3\""]
    );
}

#[test]
fn an_unknown_body_type_is_an_error_with_a_suggestion() {
    let deck = v5_deck(
        2,
        1,
        &[v5_body("1", "SHP", &["0.", "0.", "0.", "1."]), sph(2)],
        &[v5_region("1", &[("", 2)])],
    );
    let d = read_text("bad.cg", &deck).unwrap_err();
    let e = d.errors().next().unwrap();
    assert_eq!(
        e.message,
        "line 3, columns 6–10: unknown body type \"SHP\" (body 1)"
    );
    assert_eq!(e.hint.as_deref(), Some("did you mean \"SPH\"?"));
    assert_eq!(d.errors().count(), 1);
    // FLUKA bodies are not COMGEOM bodies.
    let deck = v5_deck(
        1,
        1,
        &[v5_body("1", "XYZZY", &["1."])],
        &[v5_region("1", &[("", 1)])],
    );
    let d = read_text("bad.cg", &deck).unwrap_err();
    let e = d.errors().next().unwrap();
    assert_eq!(
        e.message,
        "line 3, columns 6–10: unknown body type \"XYZZY\" (body 1)"
    );
    assert!(e
        .hint
        .as_deref()
        .unwrap()
        .starts_with("COMGEOM body types are ARB4, ARB5"));
}

#[test]
fn a_missing_body_names_the_region_and_the_body() {
    let deck = v5_deck(
        1,
        2,
        &[sph(1)],
        &[
            v5_region("1", &[("", 1)]),
            v5_region("2", &[("", 1), ("", -23)]),
        ],
    );
    assert_eq!(errors(&deck), ["line 5, columns 16–20: region 2 refers to body 23, which is not defined (the deck has 1 bodies)"]);
}

#[test]
fn an_operator_without_a_number_is_an_error() {
    let deck = v5_deck(1, 1, &[sph(1)], &["    1       1OR".to_string()]);
    assert_eq!(
        errors(&deck),
        ["line 4, columns 14–20: expected an operator and a body number in region 1, found \"OR\" with no number"]
    );
}

#[test]
fn truncated_bodies_are_errors() {
    // The RCC's second card is missing: the next card is a body.
    let deck = v5_deck(
        2,
        1,
        &[
            v5_body("1", "RCC", &["0.", "0.", "0.", "0.", "0.", "1."]),
            sph(2),
        ],
        &[v5_region("1", &[("", 2)])],
    );
    assert_eq!(
        errors(&deck),
        ["line 4, columns 6–10: expected continuation card 2 of 2 for body 1 (RCC), a card with a blank type field, found \"SPH\""]
    );
    // The deck ends inside a body.
    let deck =
        "in   t\n    1    1\n    1ARB8      0.        0.        0.        1.        0.        0.\n";
    assert_eq!(
        errors(deck),
        [
            "line 3: the deck ends inside body 1 (ARB8): expected continuation card 2 of 4",
            "line 3: the deck ends before the region table"
        ]
    );
}

#[test]
fn an_ars_claiming_more_points_than_the_deck_holds_is_refused_without_allocating() {
    let deck = v5_deck(
        2,
        1,
        &[v5_body("1", "ARS", &["1000000", "1000000000"]), sph(2)],
        &[v5_region("1", &[("", 2)])],
    );
    assert_eq!(
        errors(&deck),
        ["line 3, columns 11–30: ARS body 1 claims 1000000 curves of 1000000000 points (500000000000000 cards), but only 3 cards follow"]
    );
    let deck = v5_deck(
        1,
        1,
        &[v5_body("1", "ARS", &["0", "x"])],
        &[v5_region("1", &[("", 1)])],
    );
    assert_eq!(
        errors(&deck),
        [
            "line 3, columns 11–20: expected the ARS curve count (a positive integer), found \"0\"",
            "line 3, columns 21–30: expected the ARS number of points per curve (a positive integer), found \"x\""
        ]
    );
}

#[test]
fn every_error_of_a_deck_is_reported_at_once_in_file_order() {
    let deck = v5_deck(
        4,
        3,
        &[
            v5_body("1", "SPH", &["0.", "x", "0.", "1."]),
            v5_body("2", "SPG", &["0.", "0.", "0.", "1."]),
            v5_body("3", "RPP", &["0.", "1.", "0.", "1.", "0.", "?"]),
            sph(4),
        ],
        &[
            v5_region("1", &[("", 1)]),
            v5_region("2", &[("", 9)]),
            v5_region("3", &[("XX", 4)]),
            v5_region("2", &[("", 4)]),
        ],
    ) + "    7    1    0    0  100\n";
    assert_eq!(
        errors(&deck),
        [
            "line 3, columns 21–30: expected a number for SPH centre (V.y), found \"x\"",
            "line 4, columns 6–10: unknown body type \"SPG\" (body 2)",
            "line 5, columns 61–70: expected a number for RPP z max (ZMAX), found \"?\"",
            "line 8, columns 9–13: region 2 refers to body 9, which is not defined (the deck has 4 bodies)",
            "line 9, columns 7–8: expected an operator (blank, OR, G or OG), found \"XX\"",
            "line 10, columns 1–5: region 2 is defined twice (first on line 8)",
            "line 12, columns 1–5: ident card for region 7, which the region table does not define",
        ]
    );
}

#[test]
fn bad_control_region_and_ident_fields_are_errors() {
    let deck = v5_deck(
        1,
        1,
        &[sph(1)],
        &[v5_region("1", &[("", 1)]), "   x1      1".into()],
    )
    .replacen("    1    1\n", "    one\n", 1)
        + "    1  1x0\n";
    assert_eq!(
        errors(&deck),
        [
            "line 2: expected the control card (body count, region count), found \"one\"",
            "line 5, columns 1–5: expected a region number, found \"x1\"",
            "line 7, columns 6–10: expected the ident code of region 1 (an integer), found \"1x0\"",
        ]
    );
}

#[test]
fn body_numbers_must_count_up_in_v5() {
    let deck = v5_deck(
        2,
        1,
        &[sph(1), v5_body("3", "SPH", &["0.", "0.", "0.", "1."])],
        &[v5_region("1", &[("", 1)])],
    );
    assert_eq!(
        errors(&deck),
        ["line 4, columns 1–5: expected body number 2, found \"3\""]
    );
}

#[test]
fn count_mismatches_and_a_missing_end_card_are_warnings() {
    let deck = v5_deck(3, 2, &[sph(1)], &[v5_region("1", &[("", 1)])]).replace("   -1\n", "");
    let l = read_ok("w.cg", &deck);
    let msgs: Vec<_> = l.warnings.iter().map(|w| w.message.as_str()).collect();
    assert_eq!(
        msgs,
        [
            "line 4: the region table has no -1 end card",
            "line 2: the control card declares 3 bodies, but the deck defines 1",
            "line 2: the control card declares 2 regions, but the deck defines 1",
        ]
    );
}

#[test]
fn a_deck_with_thousands_of_errors_reports_the_first_200_and_counts_the_rest() {
    let bodies: Vec<String> = (1..=1000)
        .map(|n| v5_body(&n.to_string(), "SPH", &["x", "0.", "0.", "1."]))
        .collect();
    let deck = v5_deck(1000, 1, &bodies, &[v5_region("1", &[("", 1)])]);
    let msgs = errors(&deck);
    assert_eq!(msgs.len(), 201);
    assert_eq!(
        msgs[0],
        "line 3, columns 11–20: expected a number for SPH centre (V.x), found \"x\""
    );
    assert_eq!(
        msgs[199],
        "line 202, columns 11–20: expected a number for SPH centre (V.x), found \"x\""
    );
    assert_eq!(msgs[200], "800 more errors and warnings are not shown");
}

#[test]
fn a_control_card_claiming_too_many_bodies_only_warns() {
    let Some(text) = deck_text(GENERATOR) else {
        return;
    };
    let text = text.replacen("282  282", "290  282", 1);
    let l = read_ok(GENERATOR, &text);
    assert_eq!(l.scene.geometry.bodies.len(), 282);
    assert_eq!(l.scene.geometry.regions.len(), 282);
    let msgs: Vec<_> = l.warnings.iter().map(|w| w.message.as_str()).collect();
    assert_eq!(
        msgs,
        ["line 2: the control card declares 290 bodies, but the deck defines 282"]
    );
}

// ---------------------------------------------------------------- robustness

#[derive(Clone, Debug)]
enum Mutation {
    Flip(usize, u8),
    DeleteLine(usize),
    DuplicateLine(usize),
    Truncate(usize),
    InsertLine(usize, String),
}

fn mutate(text: &str, muts: &[Mutation]) -> String {
    let mut bytes = text.as_bytes().to_vec();
    for m in muts {
        let lines = |b: &[u8]| {
            b.split(|&c| c == b'\n')
                .map(<[u8]>::to_vec)
                .collect::<Vec<_>>()
        };
        match m {
            Mutation::Flip(i, v) if !bytes.is_empty() => {
                let n = bytes.len();
                bytes[i % n] = *v;
            }
            Mutation::DeleteLine(i) => {
                let mut l = lines(&bytes);
                let n = l.len();
                l.remove(i % n);
                bytes = l.join(&b'\n');
            }
            Mutation::DuplicateLine(i) => {
                let mut l = lines(&bytes);
                let n = l.len();
                let dup = l[i % n].clone();
                l.insert(i % n, dup);
                bytes = l.join(&b'\n');
            }
            Mutation::Truncate(i) => {
                let n = bytes.len().max(1);
                bytes.truncate(i % n);
            }
            Mutation::InsertLine(i, s) => {
                let mut l = lines(&bytes);
                let n = l.len();
                l.insert(i % (n + 1), s.clone().into_bytes());
                bytes = l.join(&b'\n');
            }
            _ => {}
        }
    }
    String::from_utf8_lossy(&bytes).into_owned()
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let nasty = prop_oneof![
        Just("    1ARS  1000000000 999999999".to_string()),
        Just("    6ars           3    100000".to_string()),
        Just("    1      G    1 G    1 G   -1".to_string()),
        Just("   -1".to_string()),
        Just("  end".to_string()),
        Just("99999999999999999999 -9".to_string()),
        "[ -~]{0,90}",
        "\\PC{0,40}",
    ];
    prop_oneof![
        (any::<usize>(), any::<u8>()).prop_map(|(i, v)| Mutation::Flip(i, v)),
        any::<usize>().prop_map(Mutation::DeleteLine),
        any::<usize>().prop_map(Mutation::DuplicateLine),
        any::<usize>().prop_map(Mutation::Truncate),
        (any::<usize>(), nasty).prop_map(|(i, s)| Mutation::InsertLine(i, s)),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]

    #[test]
    fn mutated_real_decks_never_panic(deck in 0usize..3, muts in proptest::collection::vec(mutation(), 1..8), version in 0usize..4) {
        let name = [VDECK, GIFT, GENERATOR][deck];
        let Some(text) = deck_text(name) else { return Ok(()) };
        let text = mutate(&text, &muts);
        let deck_version = [None, Some(DeckVersion::V1), Some(DeckVersion::V4), Some(DeckVersion::V5)][version];
        let src = SourceFile::new(name, text.as_str());
        match comgeom::read(&src, &LoadOptions { deck_version }) {
            Ok(l) => {
                // Whatever reads must write, and what is written must read.
                if let Ok(w) = comgeom::write(&l.scene) {
                    let again = read_text("again.cg", &w.text);
                    prop_assert!(again.is_ok(), "{}", again.unwrap_err().render_plain());
                }
            }
            Err(d) => {
                prop_assert!(d.has_errors());
                for e in d.items {
                    let _ = e.render_plain();
                }
            }
        }
    }
}
