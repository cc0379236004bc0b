//! The real decks: counts, versions, every body type they hold, regions and idents.

use super::*;

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
        let other: Vec<_> = l.warnings.iter().filter(|w| !is_non_planar(w)).collect();
        assert!(
            other.is_empty(),
            "{name}: {:?}",
            other.iter().map(|w| &w.message).collect::<Vec<_>>()
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
// The card says `.5774 .5774 .5774 -5`: comgeom-g's N·x ≤ −d, so the
// half-space holds the points with N·x ≤ 5 (the body's own distance).
body_test!(vdeck_haf, VDECK, 11, Haf, [0.5774, 0.5774, 0.5774, 5]);
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
