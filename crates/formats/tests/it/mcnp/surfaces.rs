//! Every surface type and macrobody, its facets, transformations and
//! boundary marks: each surface's negative side checked at points inside
//! and outside it.

use super::*;
use sv_geom::BodyKind;

/// Cell 1 is the negative side of the surface on `card` (numbered 1),
/// cell 2 the positive side.
fn sides(card: &str, data: &str) -> Loaded {
    load(&deck("1 0 -1\n2 0 1", card, data))
}

/// Check `inside` points are in cell 1 and `outside` ones in cell 2.
fn check(card: &str, data: &str, inside: &[DVec3], outside: &[DVec3]) -> Loaded {
    let l = sides(card, data);
    let e = Eval::new(&l.scene);
    for p in inside {
        assert_eq!(
            e.cell(*p),
            "1",
            "{card}: {p} should be on the negative side"
        );
    }
    for p in outside {
        assert_eq!(
            e.cell(*p),
            "2",
            "{card}: {p} should be on the positive side"
        );
    }
    l
}

fn kinds(l: &Loaded) -> Vec<BodyKind> {
    l.scene.geometry.bodies.iter().map(|b| b.kind).collect()
}

#[test]
fn planes() {
    let l = check("1 p 1 1 0 1", "", &[v(0.0, 0.0, 0.0)], &[v(1.0, 1.0, 0.0)]);
    assert_eq!(kinds(&l), [BodyKind::Haf]);
    // By three points: the origin on the negative side...
    check(
        "1 p 0 0 1  1 0 1  0 1 1",
        "",
        &[v(0.0, 0.0, 0.0)],
        &[v(0.0, 0.0, 2.0)],
    );
    check(
        "1 p 0 1 1  1 0 1  0 0 1",
        "",
        &[v(0.0, 0.0, 0.0)],
        &[v(0.0, 0.0, 2.0)],
    );
    // ... or when the plane holds it, (0, 0, ∞) on the positive side.
    check(
        "1 p 0 0 0  1 0 0  0 1 0",
        "",
        &[v(0.0, 0.0, -1.0)],
        &[v(0.0, 0.0, 1.0)],
    );
    for (m, axis) in [("px", 0), ("py", 1), ("pz", 2)] {
        let mut lo = DVec3::ZERO;
        let mut hi = DVec3::ZERO;
        lo[axis] = 1.0;
        hi[axis] = 3.0;
        let l = check(&format!("1 {m} 2"), "", &[lo], &[hi]);
        assert_eq!(
            kinds(&l),
            [[BodyKind::Yzp, BodyKind::Xzp, BodyKind::Xyp][axis]]
        );
    }
}

#[test]
fn spheres_and_cylinders() {
    check("1 so 2", "", &[v(0.0, 0.0, 1.9)], &[v(0.0, 0.0, 2.1)]);
    check("1 s 1 2 3 1", "", &[v(1.0, 2.0, 3.9)], &[v(1.0, 2.0, 4.1)]);
    check("1 sx 4 1", "", &[v(4.9, 0.0, 0.0)], &[v(5.1, 0.0, 0.0)]);
    check("1 sy 4 1", "", &[v(0.0, 4.9, 0.0)], &[v(0.0, 5.1, 0.0)]);
    check("1 sz 4 1", "", &[v(0.0, 0.0, 4.9)], &[v(0.0, 0.0, 5.1)]);
    let l = check(
        "1 c/x 1 2 0.5",
        "",
        &[v(7.0, 1.0, 2.4)],
        &[v(7.0, 1.0, 2.6), v(7.0, 1.6, 2.0)],
    );
    assert_eq!(kinds(&l), [BodyKind::Xcc]);
    check(
        "1 c/y 1 2 0.5",
        "",
        &[v(1.4, 7.0, 2.0)],
        &[v(1.6, 7.0, 2.0), v(1.0, 7.0, 2.6)],
    );
    check(
        "1 c/z 1 2 0.5",
        "",
        &[v(1.0, 2.4, 7.0)],
        &[v(1.0, 2.6, 7.0), v(1.6, 2.0, 7.0)],
    );
    check("1 cx 1", "", &[v(50.0, 0.0, 0.9)], &[v(50.0, 0.0, 1.1)]);
    check("1 cy 1", "", &[v(0.9, 50.0, 0.0)], &[v(1.1, 50.0, 0.0)]);
    check("1 cz 1", "", &[v(0.0, 0.9, 50.0)], &[v(0.0, 1.1, 50.0)]);
}

#[test]
fn cones_with_both_sheets_or_one() {
    // Apex at z = 1, half-angle tangent 0.5.
    let l = check(
        "1 k/z 0 0 1 0.25",
        "",
        &[v(0.4, 0.0, 2.0), v(0.4, 0.0, 0.0)],
        &[v(0.6, 0.0, 2.0)],
    );
    assert_eq!(kinds(&l), [BodyKind::Qua]);
    let l = check(
        "1 k/z 0 0 1 0.25 1",
        "",
        &[v(0.4, 0.0, 2.0)],
        &[v(0.4, 0.0, 0.0), v(0.6, 0.0, 2.0)],
    );
    assert_eq!(kinds(&l), [BodyKind::Qua, BodyKind::Xyp]);
    assert_eq!(body(&l, "1:sheet").params, [1.0]);
    check(
        "1 k/z 0 0 1 0.25 -1",
        "",
        &[v(0.4, 0.0, 0.0)],
        &[v(0.4, 0.0, 2.0)],
    );
    check(
        "1 kx 1 0.25 -1",
        "",
        &[v(0.0, 0.4, 0.0)],
        &[v(2.0, 0.4, 0.0), v(0.0, 0.6, 0.0)],
    );
    check(
        "1 k/y 0 1 0 1 1",
        "",
        &[v(0.0, 3.0, 1.0)],
        &[v(0.0, -1.0, 0.5)],
    );
    check(
        "1 ky 1 1",
        "",
        &[v(0.0, 3.0, 1.0), v(0.0, -1.0, 0.5)],
        &[v(0.0, 3.0, 2.5)],
    );
    check("1 kz -1 1", "", &[v(0.0, 1.0, 0.5)], &[v(0.0, 1.0, -0.5)]);
    let e = errors(&deck("1 0 -1\n2 0 1", "1 kz 0 1 2", ""));
    assert_eq!(
        e[0].2,
        "surface 1 (KZ): the sheet entry must be 1 or -1, not 2"
    );
}

#[test]
fn quadrics_and_tori() {
    // A sphere of radius 2 about (1, 2, 3), and an ellipsoid.
    check(
        "1 sq 1 1 1 0 0 0 -4 1 2 3",
        "",
        &[v(1.0, 2.0, 4.9)],
        &[v(1.0, 2.0, 5.1)],
    );
    check(
        "1 sq 1 0.25 1 0 0 0 -1 0 0 0",
        "",
        &[v(0.0, 1.9, 0.0)],
        &[v(0.0, 0.0, 1.1)],
    );
    // SQ's linear terms: (x-1)² + 2·1·(x-1) - 3 = x² - 4 < 0.
    check(
        "1 sq 1 1 1 1 0 0 -3 1 0 0",
        "",
        &[v(1.9, 0.0, 0.0)],
        &[v(2.1, 0.0, 0.0)],
    );
    check(
        "1 gq 1 1 0 0 0 0 0 0 0 -1",
        "",
        &[v(0.5, 0.0, 9.0)],
        &[v(1.5, 0.0, 9.0)],
    );
    // GQ's cross terms: D xy, E yz, F zx.
    check(
        "1 gq 0 0 0 1 0 0 0 0 0 -1",
        "",
        &[v(0.5, 0.5, 9.0)],
        &[v(2.0, 2.0, 0.0)],
    );
    check(
        "1 gq 0 0 0 0 1 0 0 0 0 -1",
        "",
        &[v(9.0, 0.5, 0.5)],
        &[v(0.0, 2.0, 2.0)],
    );
    check(
        "1 gq 0 0 0 0 0 1 0 0 0 -1",
        "",
        &[v(0.5, 9.0, 0.5)],
        &[v(2.0, 0.0, 2.0)],
    );
    let l = check(
        "1 tz 0 0 1 5 1 1",
        "",
        &[v(5.0, 0.0, 1.0)],
        &[v(0.0, 0.0, 1.0), v(5.0, 0.0, 2.1)],
    );
    assert_eq!(kinds(&l), [BodyKind::Tor]);
    check(
        "1 tx 1 0 0 5 1 1",
        "",
        &[v(1.0, 5.0, 0.0)],
        &[v(1.0, 0.0, 0.0)],
    );
    check(
        "1 ty 0 1 0 5 1 1",
        "",
        &[v(0.0, 1.0, 5.0)],
        &[v(0.0, 1.0, 0.0)],
    );
    let e = errors(&deck("1 0 -1\n2 0 1", "1 tz 0 0 0 5 1 2", ""));
    assert_eq!(e.len(), 1);
    assert_eq!((e[0].0, e[0].1), (5, 3));
    assert!(
        e[0].2.contains("elliptic") && e[0].2.contains("TOR"),
        "{}",
        e[0].2
    );
}

#[test]
fn surfaces_given_by_points() {
    check("1 x 2 3", "", &[v(1.0, 0.0, 0.0)], &[v(3.0, 0.0, 0.0)]);
    check("1 y 2 3 2 5", "", &[v(0.0, 1.0, 0.0)], &[v(0.0, 3.0, 0.0)]);
    check("1 x 1 2 3 2", "", &[v(0.0, 1.9, 0.0)], &[v(0.0, 2.1, 0.0)]);
    // Through (1, 1) and (3, 2): a cone with its apex at x = -1, one sheet.
    check(
        "1 x 1 1 3 2",
        "",
        &[v(2.0, 1.4, 0.0)],
        &[v(2.0, 1.6, 0.0), v(-3.0, 0.5, 0.0)],
    );
    // r² = 4 - 3x² through (0, 2), (1, 1), (-1, 1).
    check(
        "1 z 0 2 1 1 -1 1",
        "",
        &[v(0.0, 1.9, 0.0)],
        &[v(0.0, 2.1, 0.0), v(0.0, 0.0, 1.2)],
    );
}

#[test]
fn macrobodies_whole() {
    let l = check(
        "1 rpp -1 1 -2 2 -3 3",
        "",
        &[v(0.9, 1.9, 2.9)],
        &[v(1.1, 0.0, 0.0), v(0.0, 0.0, -3.1)],
    );
    assert_eq!(kinds(&l), [BodyKind::Rpp]);
    check(
        "1 box -1 -1 -1 2 0 0 0 2 0 0 0 2",
        "",
        &[v(0.9, 0.9, 0.9)],
        &[v(1.1, 0.0, 0.0)],
    );
    check(
        "1 sph 1 1 1 2",
        "",
        &[v(1.0, 1.0, 2.9)],
        &[v(1.0, 1.0, 3.1)],
    );
    check(
        "1 rcc 0 0 0 0 0 5 1",
        "",
        &[v(0.9, 0.0, 4.9)],
        &[v(0.0, 0.0, 5.1), v(1.1, 0.0, 1.0)],
    );
    let hex = check(
        "1 rhp 0 0 0 0 0 4 1 0 0",
        "",
        &[v(0.99, 0.0, 1.0), v(0.5, 0.85, 1.0), v(0.0, 1.1, 1.0)],
        &[v(1.01, 0.0, 1.0), v(0.0, 1.2, 1.0), v(0.0, 0.0, 4.1)],
    );
    assert_eq!(kinds(&hex), [BodyKind::Pla; 8]);
    check(
        "1 hex 0 0 0 0 0 4 0 1 0 -0.866025403784 0.5 0 -0.866025403784 -0.5 0",
        "",
        &[v(0.0, 0.99, 1.0), v(1.1, 0.0, 1.0)],
        &[v(0.0, 1.01, 1.0), v(1.2, 0.0, 1.0)],
    );
    check(
        "1 rec 0 0 0 0 0 3 2 0 0 1",
        "",
        &[v(1.9, 0.0, 1.0), v(0.0, 0.9, 1.0)],
        &[v(0.0, 1.1, 1.0)],
    );
    check(
        "1 rec 0 0 0 0 0 3 2 0 0 0 1 0",
        "",
        &[v(0.0, 0.9, 1.0)],
        &[v(0.0, 1.1, 1.0)],
    );
    check(
        "1 trc 0 0 0 0 0 4 2 1",
        "",
        &[v(1.4, 0.0, 2.0)],
        &[v(1.6, 0.0, 2.0), v(0.0, 0.0, 4.1)],
    );
    // ELL by foci: MCNP's semi-minor axis is √(R² − (R − c)²) = √20.
    check(
        "1 ell 0 0 -2 0 0 2 6",
        "",
        &[v(0.0, 0.0, 5.9), v(4.4, 0.0, 0.0)],
        &[v(0.0, 0.0, 6.1), v(4.5, 0.0, 0.0)],
    );
    check(
        "1 ell 0 0 0 0 0 3 -2",
        "",
        &[v(0.0, 0.0, 2.9), v(1.9, 0.0, 0.0)],
        &[v(0.0, 0.0, 3.1), v(2.1, 0.0, 0.0)],
    );
    check(
        "1 wed 0 0 0 2 0 0 0 1 0 0 0 3",
        "",
        &[v(0.5, 0.2, 1.0)],
        &[v(1.5, 0.5, 1.0), v(0.5, 0.2, 3.1)],
    );
    let cube = "1 arb -1 -1 -1  1 -1 -1  1 1 -1  -1 1 -1  -1 -1 1  1 -1 1  1 1 1  -1 1 1 1234 5678 1265 2376 3487 4158";
    check(cube, "", &[v(0.9, 0.9, 0.9)], &[v(1.1, 0.0, 0.0)]);
    let tetra = "1 arb 0 0 0 1 0 0 0 1 0 0 0 1 0 0 0 0 0 0 0 0 0 0 0 0 1230 1240 1340 2340 0 0";
    check(tetra, "", &[v(0.2, 0.2, 0.2)], &[v(0.5, 0.5, 0.5)]);
}

/// Cell 1 is the negative side of facet `k` of surface 1.
fn facet(card: &str, k: usize, inside: &[DVec3], outside: &[DVec3]) {
    let l = load(&deck(&format!("1 0 -1.{k}\n2 0 1.{k}"), card, ""));
    let e = Eval::new(&l.scene);
    for p in inside {
        assert_eq!(e.cell(*p), "1", "{card} facet {k}: {p} should be inside");
    }
    for p in outside {
        assert_eq!(e.cell(*p), "2", "{card} facet {k}: {p} should be outside");
    }
}

#[test]
fn facets_are_the_surfaces_they_lie_on() {
    let rpp = "1 rpp -1 1 -2 2 -3 3";
    for (k, inside, outside) in [
        (1, v(0.9, 50.0, 50.0), v(1.1, 0.0, 0.0)),
        (2, v(-0.9, 50.0, 50.0), v(-1.1, 0.0, 0.0)),
        (3, v(50.0, 1.9, 50.0), v(0.0, 2.1, 0.0)),
        (4, v(50.0, -1.9, 50.0), v(0.0, -2.1, 0.0)),
        (5, v(50.0, 50.0, 2.9), v(0.0, 0.0, 3.1)),
        (6, v(50.0, 50.0, -2.9), v(0.0, 0.0, -3.1)),
    ] {
        facet(rpp, k, &[inside], &[outside]);
    }
    let bx = "1 box -1 -1 -1 2 0 0 0 2 0 0 0 2";
    facet(bx, 1, &[v(0.9, 50.0, 0.0)], &[v(1.1, 0.0, 0.0)]);
    facet(bx, 2, &[v(-0.9, 50.0, 0.0)], &[v(-1.1, 0.0, 0.0)]);
    facet(bx, 6, &[v(0.0, 50.0, -0.9)], &[v(0.0, 0.0, -1.1)]);
    let rcc = "1 rcc 0 0 0 0 0 5 1";
    facet(rcc, 1, &[v(0.9, 0.0, 100.0)], &[v(1.1, 0.0, 100.0)]);
    facet(rcc, 2, &[v(50.0, 50.0, 4.9)], &[v(0.0, 0.0, 5.1)]);
    facet(rcc, 3, &[v(50.0, 50.0, 0.1)], &[v(0.0, 0.0, -0.1)]);
    facet(
        "1 rcc 0 0 0 3 4 0 1",
        1,
        &[v(30.0, 40.0, 0.9)],
        &[v(30.0, 40.0, 1.1)],
    );
    // The cone's sheet holding the frustum (apex at z = 8).
    let trc = "1 trc 0 0 0 0 0 4 2 1";
    facet(
        trc,
        1,
        &[v(2.9, 0.0, -4.0)],
        &[v(3.1, 0.0, -4.0), v(0.1, 0.0, 12.0)],
    );
    facet(trc, 2, &[v(9.0, 0.0, 3.9)], &[v(0.0, 0.0, 4.1)]);
    facet(
        "1 rec 0 0 0 0 0 3 2 0 0 1",
        1,
        &[v(0.0, 0.9, -50.0)],
        &[v(0.0, 1.1, -50.0)],
    );
    let hex = "1 rhp 0 0 0 0 0 4 1 0 0";
    facet(hex, 1, &[v(0.9, 50.0, 50.0)], &[v(1.1, 0.0, 0.0)]);
    facet(hex, 4, &[v(-0.4, -0.8, 50.0)], &[v(-0.6, -0.9, 0.0)]);
    facet(hex, 7, &[v(50.0, 0.0, 3.9)], &[v(0.0, 0.0, 4.1)]);
    let wed = "1 wed 0 0 0 2 0 0 0 1 0 0 0 3";
    facet(wed, 1, &[v(0.5, 0.2, 50.0)], &[v(1.5, 0.5, 1.0)]);
    facet(wed, 2, &[v(0.1, 50.0, 50.0)], &[v(-0.1, 0.0, 0.0)]);
    facet(wed, 3, &[v(50.0, 0.1, 50.0)], &[v(0.0, -0.1, 0.0)]);
    facet(wed, 4, &[v(50.0, 50.0, 2.9)], &[v(0.0, 0.0, 3.1)]);
    let cube = "1 arb -1 -1 -1  1 -1 -1  1 1 -1  -1 1 -1  -1 -1 1  1 -1 1  1 1 1  -1 1 1 1234 5678 1265 2376 3487 4158";
    facet(cube, 1, &[v(50.0, 50.0, -0.9)], &[v(0.0, 0.0, -1.1)]);
    facet(cube, 4, &[v(0.9, 50.0, 50.0)], &[v(1.1, 0.0, 0.0)]);
    facet("1 sph 0 0 0 2", 1, &[v(0.0, 0.0, 1.9)], &[v(0.0, 0.0, 2.1)]);
    // Facets of what has none, or beyond the last.
    let e = errors(&deck(
        "1 0 -1.1 -2.7\n2 0 1",
        "1 so 2\n2 rcc 0 0 0 0 0 1 1",
        "",
    ));
    assert_eq!(
        e[0],
        (
            2,
            5,
            "surface 1 is a SO surface, not a macrobody: it has no facets".to_string()
        )
    );
    assert_eq!(
        e[1],
        (2, 10, "surface 2: RCC has facets 1 to 3, not 7".to_string())
    );
}

#[test]
fn transformations_move_surfaces() {
    // TR1 moves by (10, 0, 0); *TR2 turns x' onto main y (angles).
    let data = "tr1 10 0 0\n*tr2 0 0 0 90 0 90 180 90 90 90 90 0";
    check("1 1 px 2", data, &[v(11.0, 0.0, 0.0)], &[v(13.0, 0.0, 0.0)]);
    check("1 2 cx 1", data, &[v(0.5, 50.0, 0.0)], &[v(50.0, 0.0, 0.5)]);
    check(
        "1 2 rcc 0 0 0 5 0 0 1",
        data,
        &[v(0.0, 4.9, 0.0)],
        &[v(4.9, 0.0, 0.0)],
    );
    // M = -1: the main origin given in the auxiliary system.
    check(
        "1 3 so 1",
        "tr3 5 0 0 1 0 0 0 1 0 0 0 1 -1",
        &[v(-5.0, 0.0, 0.5)],
        &[v(5.0, 0.0, 0.0)],
    );
    let e = errors(&deck("1 0 -1\n2 0 1", "1 7 so 1", ""));
    assert_eq!(
        e,
        vec![(5, 3, "transformation TR7 is not defined".to_string())]
    );
    let e = errors(&deck(
        "1 0 -1\n2 0 1",
        "1 so 1",
        "tr1 0 0 0 1 0 0 0 1 0 0 0 2",
    ));
    assert!(
        e[0].2
            .starts_with("TR1: the rotation matrix is not orthonormal"),
        "{}",
        e[0].2
    );
}

#[test]
fn reflecting_white_and_periodic_surfaces_are_ordinary_with_a_note() {
    let l = load(&deck(
        "1 0 -1 -2 -3\n2 0 1:2:3",
        "*1 so 5\n+2 px 1\n3 -2 px 4",
        "",
    ));
    assert_eq!(expression(&l, "1"), "+1 +2 +3");
    let notes = l.scene.notes.join("\n");
    assert!(
        notes.contains("reflecting (`*`) surfaces are read as ordinary surfaces: 1"),
        "{notes}"
    );
    assert!(
        notes.contains("white (`+`) surfaces are read as ordinary surfaces: 2"),
        "{notes}"
    );
    assert!(
        notes.contains("periodic surfaces are read as ordinary surfaces: 3"),
        "{notes}"
    );
}

#[test]
fn bad_surface_cards_are_located() {
    let e = errors(&deck(
        "1 0 -1\n2 0 1",
        "1 pxx 2\n2 so 1 2\n3 rcc 0 0 0 0 0 0 1",
        "",
    ));
    assert_eq!(e[0], (5, 3, "unknown surface type `pxx`".to_string()));
    assert_eq!(
        e[1],
        (6, 3, "surface 2 (SO) takes 1 values, not 2".to_string())
    );
    assert_eq!(
        e[2],
        (7, 3, "surface 3 (RCC): height vector is zero".to_string())
    );
    let d = read_text(&deck("1 0 -1\n2 0 1", "1 pxx 2", "")).unwrap_err();
    assert_eq!(d.items[0].hint.as_deref(), Some("did you mean `PX`?"));
}
