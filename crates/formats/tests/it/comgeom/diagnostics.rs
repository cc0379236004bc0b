//! Every kind of error and warning, with its exact text.

use super::*;

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
    let all = read_text("bad.cg", &deck).unwrap_err();
    assert_eq!(all.error_count(), 1000);
    assert_eq!(all.to_string(), "1000 errors");
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
    let msgs: Vec<_> = l
        .warnings
        .iter()
        .filter(|w| !is_non_planar(w))
        .map(|w| w.message.as_str())
        .collect();
    assert_eq!(
        msgs,
        ["line 2: the control card declares 290 bodies, but the deck defines 282"]
    );
}
