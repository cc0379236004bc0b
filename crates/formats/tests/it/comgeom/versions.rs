//! The v1, v4 and v5 layouts and how a deck's version is told.

use super::*;

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
