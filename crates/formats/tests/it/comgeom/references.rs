//! Region references become groups of the same point sets.

use super::*;

/// Membership of a point described by which bodies contain it.
fn in_zones(zones: &[sv_geom::Zone], inside: &dyn Fn(usize) -> bool) -> bool {
    zones.iter().any(|z| {
        z.terms
            .iter()
            .all(|t| inside(t.body) == (t.op == Op::Inside))
            && z.groups
                .iter()
                .all(|g| in_zones(&g.zones, inside) == (g.op == Op::Inside))
    })
}

#[test]
fn region_references_hold_the_same_point_sets() {
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
    // A deck cannot nest: written, the groups are expanded into zones of
    // body terms, which read back to the same point sets.
    let back = round_trip(&l.scene).geometry;
    for bits in 0u32..64 {
        let b = |i: usize| bits & (1 << i) != 0;
        for (i, region) in back.regions.iter().enumerate() {
            assert!(region.zones.iter().all(|z| z.groups.is_empty()));
            assert_eq!(
                in_zones(&region.zones, &b),
                in_zones(&g.regions[i].zones, &b),
                "region {} bodies {bits:06b}",
                i + 1
            );
        }
    }
}

#[test]
fn region_references_are_not_expanded() {
    // Region 1 is the union of 9 one-term zones; region 3 intersects it
    // three times and subtracts region 2, one zone of 9 terms: 6561 zones
    // if expanded, three groups and a group here.
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
    let l = read_text("wide.cg", &v5_deck(18, 3, &bodies, &regions)).unwrap();
    let region = &l.scene.geometry.regions[2];
    assert_eq!(region.zones.len(), 1);
    let groups: Vec<(Op, usize)> = region.zones[0]
        .groups
        .iter()
        .map(|g| (g.op, g.zones.len()))
        .collect();
    assert_eq!(
        groups,
        [
            (Op::Inside, 9),
            (Op::Inside, 9),
            (Op::Inside, 9),
            (Op::Outside, 1)
        ]
    );
}

#[test]
fn copies_of_referenced_regions_are_capped() {
    // Each region refers to the one before twice: copying region 40 would
    // take 2^40 terms.
    let bodies = [sph(1)];
    let mut regions = vec![v5_region("1", &[("", 1)])];
    for n in 2..=40 {
        regions.push(v5_region(&n.to_string(), &[("G", n - 1), ("G", n - 1)]));
    }
    let errs = errors(&v5_deck(1, 40, &bodies, &regions));
    assert!(
        errs.iter()
            .any(|e| e.contains("region references copy more than")),
        "{errs:?}"
    );
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
    // Region 2 is body 1 and region 1, a group.
    let zone = &l.scene.geometry.regions[1].zones[0];
    assert_eq!(zone.terms, terms(&[1]));
    assert_eq!(zone.groups.len(), 1);
    assert_eq!(zone.groups[0].zones[0].terms, terms(&[1, -2]));
    // Without the control card's count it is still not read as a body.
    let deck = v5_deck(2, 2, &bodies, &regions).replacen("    2    2", "    0    0", 1);
    let l = read_ok("op.cg", &deck);
    assert_eq!(l.scene.geometry.bodies.len(), 2);
    assert_eq!(l.scene.geometry.regions.len(), 2);
}
