//! Includes and every kind of error, with positions and exact text.

use super::*;

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
    let cases: [(&str, (usize, usize, &str)); 10] = [
        ("r 5 +world -bal", (8, 13, "region `r` refers to undefined body `bal`")),
        ("r 5 +world -(+ball", (8, 13, "in region `r`: `(` is never closed")),
        ("r 5 +world )", (8, 12, "in region `r`: unexpected `)` with no `(` open")),
        ("r 5 +world | | +ball", (8, 14, "in region `r`: empty zone: expected `+body` or `-body` before `|`")),
        ("r 5 +world -", (8, 13, "in region `r`: expected a body name, found the end of the region")),
        ("r 5", (8, 1, "region `r` has no expression")),
        ("r 5 +world\nr 5 +ball", (9, 1, "region `r` is defined twice")),
        ("r 5 +world\n-bal", (9, 2, "region `r` refers to undefined body `bal`")),
        ("+world\nr 5 +ball", (8, 1, "region expression outside a region: expected a region name and its NAZ number first")),
        ("world\nr 5 +ball", (8, 1, "expected a region name and its NAZ number, found `world`")),
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
            10,
            1,
            "second GEOBEGIN card: an input holds one geometry".to_string()
        )]
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
            10,
            17,
            "ROT-DEFI axis code j = 5 is not 1 (x), 2 (y) or 3 (z)".to_string()
        )]
    );
    let text = geo("SPH a 0 0 0 1", "r 5 +a") + "ROT-DEFI  , 100., abc, 0, 0, 0, 0, t\n";
    assert_eq!(
        errors(&text),
        [(
            10,
            19,
            "expected a number in ROT-DEFI WHAT(2), found `abc`".to_string()
        )]
    );
}
