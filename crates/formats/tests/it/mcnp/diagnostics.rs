//! Bad input: every error located, all of them reported at once; what does
//! not concern the geometry skipped with a note.

use super::*;
use sv_formats::mcnp::MAX_ERRORS;

#[test]
fn the_four_kinds_of_broken_geometry_are_reported_together() {
    let text = deck(
        "1 0 -1 -7\n\
         2 0 -1 #2\n\
         3 0 -1 fill=6\n\
         6 0 -1 u=6 fill=7\n\
         7 0 -1 u=7 fill=6\n\
         8 0 -2 3 -4 5 u=9 lat=1 fill=0:1 0:0 0:0 9 9 9\n\
         9 0 1 imp:n=0",
        "1 so 10\n2 px 1\n3 px -1\n4 py 1\n5 py -1",
        "",
    );
    let e = errors(&text);
    assert_eq!(
        e,
        vec![
            (2, 8, "surface 7 is not defined".to_string()),
            (3, 8, "cell 2 refers to itself through `#2`".to_string()),
            (
                6,
                17,
                "this fill makes universes fill each other in a loop".to_string()
            ),
            (
                7,
                25,
                "lattice cell 8 lists 3 elements; its ranges 0:1 0:0 0:0 need 2".to_string()
            ),
        ]
    );
    let d = read_text(&text).unwrap_err();
    let plain = d.render_plain();
    assert!(plain.contains("--> test.i:2:8"), "{plain}");
    assert!(plain.contains("2 | 1 0 -1 -7\n  |        ^^"), "{plain}");
    assert_eq!(d.items[1].len, 2, "the caret covers `#2`");
}

#[test]
fn complements_that_loop_and_cells_that_are_missing() {
    let e = errors(&deck(
        "1 0 -1 #2\n2 0 -1 #1\n3 0 #12\n4 like 9 but u=1\n5 like 6 but u=2\n6 like 5 but u=3",
        "1 so 1",
        "",
    ));
    assert_eq!(
        e,
        vec![
            (
                3,
                8,
                "cell 2 and cell 1 refer to each other through `#`".to_string()
            ),
            (4, 5, "cell 12 is not defined".to_string()),
            (5, 8, "cell 9 is not defined".to_string()),
            (
                7,
                8,
                "cell 6 is LIKE cell 5, which leads back to it".to_string()
            ),
        ]
    );
}

#[test]
fn geometry_syntax_errors() {
    let cases = [
        ("1 0 -1 (2", (2, 8), "this `(` is never closed"),
        ("1 0 -1 )", (2, 8), "unexpected `)`: no parenthesis is open"),
        (
            "1 0 -1 : : 2",
            (2, 10),
            "expected a surface, `#` or `(` here",
        ),
        (
            "1 0 -1 2x",
            (2, 9),
            "unexpected `x` in the geometry of a cell",
        ),
        (
            "1 0 -1.0",
            (2, 5),
            "`-1.0` names no facet: facets are `.1` to `.8`",
        ),
        ("1 0 imp:n=1", (2, 5), "cell 1 has no geometry"),
        ("1 1", (2, 3), "cell 1 has a material but no density"),
        (
            "1 0 -1 lat=1 fill=1",
            (2, 12),
            "lattice cell 1 belongs to no universe",
        ),
        ("1 x -1", (2, 3), "expected a material number, found `x`"),
        (
            "0 0 -1",
            (2, 1),
            "a cell number must be 1 to 99999999, not 0",
        ),
    ];
    for (cell, (line, col), msg) in cases {
        let e = errors(&deck(cell, "1 so 1\n2 so 2", ""));
        assert_eq!(e[0], (line, col, msg.to_string()), "{cell}");
    }
}

#[test]
fn lattice_and_fill_errors() {
    let lattice = |planes: &str, lat: &str| {
        errors(&deck(
            &format!(
                "1 0 -9 fill=5\n2 0 9 imp:n=0\n10 0 {planes} u=5 lat={lat} fill=1\n11 0 -9 u=1"
            ),
            "9 so 100\n1 px 1\n2 px -1\n3 py 1\n4 py -1\n5 so 1\n6 pz 1",
            "",
        ))
    };
    for (planes, lat, msg) in [
        (
            "-1 2 -3 4",
            "3",
            "LAT must be 1 (hexahedra) or 2 (hexagonal prisms), not 3",
        ),
        (
            "-1 2 -3 -5",
            "1",
            "surface 5 of lattice cell 10 is not a plane",
        ),
        (
            "-1 2 -3",
            "1",
            "a LAT=1 cell is bounded by 4 or 6 planes, not 3 (cell 10)",
        ),
        (
            "-1 2 -3 6",
            "1",
            "lattice cell 10: surfaces 3 and 4 of the cell are not parallel",
        ),
        (
            "-1 2 -3 4 : 6",
            "1",
            "lattice cell 10 must be an intersection of planes, written in MCNP's order",
        ),
    ] {
        assert_eq!(lattice(planes, lat)[0].2, msg, "{planes}");
    }
    let e = errors(&deck("1 0 -1 fill=4\n2 0 1 imp:n=0", "1 so 1", ""));
    assert_eq!(
        e,
        vec![(
            2,
            13,
            "universe 4 is not defined: no cell has U=4".to_string()
        )]
    );
    let e = errors(&deck(
        "1 0 -1 fill=0:1 0:0 0:0 2 2\n2 0 1 imp:n=0\n3 0 -1 u=2",
        "1 so 1",
        "",
    ));
    assert_eq!(e[0].2, "cell 1 has a FILL array but no LAT");
    let e = errors(&deck(
        "1 0 -1 fill=2 (9)\n2 0 1 imp:n=0\n3 0 -1 u=2",
        "1 so 1",
        "",
    ));
    assert_eq!(
        e,
        vec![(2, 16, "transformation TR9 is not defined".to_string())]
    );
}

#[test]
fn data_cards_that_do_not_concern_the_geometry_are_noted() {
    let l = load(&deck(
        "1 0 -1 imp:n=1 vol=3 tmp=2.5e-8 unknown=4\n2 0 1 imp:n=0",
        "1 so 1",
        "kcode 1000 1 10 100\nksrc 0 0 0\nsdef pos=0 0 0\nf4:n 1\nprint\n#  imp:n\n   1  1",
    ));
    assert!(
        l.scene.notes.iter().any(|n| n == "data cards that do not concern the geometry were skipped: KCODE, KSRC, SDEF, F4:N, PRINT"),
        "{:?}",
        l.scene.notes
    );
    let warnings: Vec<&str> = l.warnings.iter().map(|w| w.message.as_str()).collect();
    assert_eq!(
        warnings,
        [
            "unknown cell parameter `unknown` is skipped",
            "cards in vertical format (`#` in columns 1–5) are not read"
        ]
    );
}

#[test]
fn duplicates_are_warned_about_and_read() {
    let l = load(&deck(
        "1 0 -1\n1 0 1 -2\n2 0 2",
        "1 so 1\n2 so 2\n2 so 3",
        "",
    ));
    assert_eq!(l.scene.geometry.regions.len(), 3);
    assert_close(&body(&l, "2").params, &[0.0, 0.0, 0.0, 2.0]);
    let w: Vec<_> = l
        .warnings
        .iter()
        .map(|w| (w.line_col(), w.message.clone()))
        .collect();
    assert_eq!(
        w[0],
        (
            (3, 1),
            "cell 1 is defined again (first on line 2); MCNP refuses this".to_string()
        )
    );
    assert_eq!(
        w[1],
        (
            (8, 1),
            "surface 2 is defined again (first on line 7); MCNP refuses this".to_string()
        )
    );
}

#[test]
fn errors_past_the_limit_are_counted() {
    let surfaces: String = (1..=150).map(|i| format!("{i} sx 1\n")).collect();
    let d = read_text(&deck("1 0 -1\n2 0 1", &surfaces, "")).unwrap_err();
    assert_eq!(d.items.len(), MAX_ERRORS + 1);
    assert_eq!(d.error_count(), 150);
    assert!(d
        .items
        .last()
        .unwrap()
        .message
        .starts_with("… and 50 more errors"));
}

#[test]
fn an_empty_input_has_no_cells() {
    assert_eq!(errors("")[0].2, "the input has no cell cards");
    assert_eq!(errors("title only\n")[0].2, "the input has no cell cards");
}
