//! Cells: operators, complements, LIKE n BUT, TRCL, universes and fills,
//! lattices of both kinds, importance, materials and densities.

use super::*;
use sv_geom::{Fill, LatticeKind};

#[test]
fn operators_lower_to_zones_and_groups_as_written() {
    let l = load(&deck(
        "1 0 -1 (2:3)\n2 0 -1 #1\n3 0 -1 2 3 : -4\n4 0 #(-1 2) -4\n5 0 -4 #(3:(2 1))\n6 0 4 imp:n=0",
        "1 so 5\n2 px 0\n3 py 0\n4 so 10",
        "",
    ));
    assert_eq!(expression(&l, "1"), "+1 +(-2 | -3)");
    assert_eq!(expression(&l, "2"), "+1 -(+1 +(-2 | -3))");
    assert_eq!(expression(&l, "3"), "+1 -2 -3 | +4");
    assert_eq!(expression(&l, "4"), "+4 -(+1 -2)");
    assert_eq!(expression(&l, "5"), "+4 -(-3 | -2 -1)");
    let e = Eval::new(&l.scene);
    let in_cell = |name: &str, p: DVec3| e.region(region(&l, name), p);
    // Cell 1: the ball where x > 0 or y > 0; cell 2 the rest of it.
    assert!(in_cell("1", v(-1.0, 1.0, 0.0)) && !in_cell("1", v(-1.0, -1.0, 0.0)));
    assert!(in_cell("2", v(-1.0, -1.0, 0.0)) && !in_cell("2", v(-1.0, 1.0, 0.0)));
    assert!(in_cell("3", v(1.0, 1.0, 0.0)) && in_cell("3", v(-1.0, 1.0, 0.0)));
    assert!(!in_cell("4", v(1.0, 1.0, 0.0)) && in_cell("4", v(-1.0, 1.0, 0.0)));
    assert!(in_cell("5", v(-1.0, -1.0, 0.0)) && !in_cell("5", v(6.0, -1.0, 0.0)));
}

#[test]
fn like_but_and_trcl_move_copies() {
    let l = load(&deck(
        "1 1 -2.7 -1 imp:n=1 $ the first\n\
         2 like 1 but trcl=(10 0 0) mat=2 rho=0.05\n\
         3 like 1 but *trcl=(0 0 0 90 0 90 180 90 90 90 90 0)\n\
         4 like 1 but trcl=5 mat=0\n\
         5 0 -9 #1 #2 #3 #4\n\
         6 0 9 imp:n=0",
        "1 s 3 0 0 1\n9 so 50",
        "m1 13027 1\nm2 1001 2 8016 1\ntr5 0 0 20",
    ));
    assert_eq!(expression(&l, "2"), "+2001");
    assert_close(&body(&l, "2001").params, &[13.0, 0.0, 0.0, 1.0]);
    assert_close(&body(&l, "3001").params, &[0.0, 3.0, 0.0, 1.0]);
    assert_close(&body(&l, "4001").params, &[3.0, 0.0, 20.0, 1.0]);
    let props = |name: &str| {
        let i = l.scene.geometry.region_index(name).unwrap();
        l.scene.regions[i].clone()
    };
    assert_eq!(
        (props("2").material, props("2").atom_density),
        (2, Some(0.05))
    );
    assert_eq!(props("2").description, "the first");
    assert_eq!((props("3").material, props("3").density), (1, Some(2.7)));
    assert_eq!((props("4").material, props("4").air), (0, 1));
    let e = Eval::new(&l.scene);
    for (p, cell) in [
        (v(3.0, 0.0, 0.0), "1"),
        (v(13.0, 0.0, 0.0), "2"),
        (v(0.0, 3.0, 0.0), "3"),
        (v(3.0, 0.0, 20.0), "4"),
        (v(0.0, 0.0, 0.0), "5"),
        (v(60.0, 0.0, 0.0), "6"),
    ] {
        assert_eq!(e.path(p), [cell], "{p}");
    }
}

#[test]
fn fills_move_universes_and_trcl_moves_the_fill() {
    let l = load(&deck(
        "1 0 -1 fill=1 (2)\n\
         2 0 -2 fill=1 (0 20 0)\n\
         3 0 -3 *fill=1 (0 -20 0 90 0 90 180 90 90 90 90 0)\n\
         6 0 -1 trcl=(0 0 40) fill=1\n\
         4 0 1 2 3 6001 -9\n\
         5 0 9 imp:n=0\n\
         10 1 -1 -10 u=1\n\
         11 0 10 u=1",
        "1 so 2\n2 s 0 20 0 2\n3 s 0 -20 0 2\n9 so 100\n10 s 1 0 0 0.5",
        "tr2 0 0 1\nm1 1001 1",
    ));
    assert_eq!(l.scene.geometry.universes.len(), 2);
    assert_eq!(region(&l, "10").universe, 1);
    let e = Eval::new(&l.scene);
    assert_eq!(e.path(v(1.0, 0.0, 1.0)), ["1", "10"]);
    assert_eq!(e.path(v(1.0, 0.0, 0.0)), ["1", "11"]);
    assert_eq!(e.path(v(1.0, 20.0, 0.0)), ["2", "10"]);
    assert_eq!(e.path(v(0.0, -19.0, 0.0)), ["3", "10"]);
    assert_eq!(e.path(v(1.0, -20.0, 0.0)), ["3", "11"]);
    assert_eq!(e.path(v(1.0, 0.0, 40.0)), ["6", "10"]);
    let Some(Fill::Universe { universe, .. }) = region(&l, "1").fill else {
        panic!("cell 1 is filled");
    };
    assert_eq!(universe, 1);
    // A filled void is not air; the void left in universe 1 is.
    let i = l.scene.geometry.region_index("1").unwrap();
    assert_eq!(l.scene.regions[i].air, 0);
    let i = l.scene.geometry.region_index("11").unwrap();
    assert_eq!(l.scene.regions[i].air, 1);
}

/// A row of three elements of pitch 2 along x, the lattice cell's planes
/// written `planes`, filled `-1:1 0:0 0:0 {elements}`.
fn row(planes: &str, elements: &str) -> Loaded {
    load(&deck(
        &format!(
            "1 0 -1 fill=5\n2 0 1 imp:n=0\n\
             10 4 -2.5 {planes} u=5 lat=1 fill=-1:1 0:0 0:0 {elements}\n\
             20 1 -1 -99 u=1\n21 2 -1 -99 u=2\n22 3 -1 -99 u=3"
        ),
        "1 rpp -3 3 -1 1 -1 1\n10 px 1\n11 px -1\n12 py 1\n13 py -1\n99 so 1000",
        "",
    ))
}

#[test]
fn rectangular_lattices_follow_the_order_of_their_surfaces() {
    let l = row("-10 11 -12 13", "1 2 3");
    let e = Eval::new(&l.scene);
    assert_eq!(e.path(v(-2.0, 0.0, 0.0)), ["1", "10", "[-1,0,0]", "20"]);
    assert_eq!(e.path(v(0.0, 0.0, 0.0)), ["1", "10", "[0,0,0]", "21"]);
    assert_eq!(e.path(v(2.0, 0.0, 0.0)), ["1", "10", "[1,0,0]", "22"]);
    let Some(Fill::Lattice(lat)) = &region(&l, "10").fill else {
        panic!("cell 10 is a lattice");
    };
    assert_eq!(lat.kind, LatticeKind::Rectangular);
    assert_close(&lat.steps[0].to_array(), &[2.0, 0.0, 0.0]);
    assert_close(&lat.base.to_array()[..2], &[-1.0, -1.0]);
    assert_eq!((lat.lowest, lat.counts), ([-1, 0, 0], [3, 1, 1]));
    // The first surface at -x: element (1,0,0) lies toward -x.
    let l = row("11 -10 13 -12", "1 2 3");
    assert_eq!(
        Eval::new(&l.scene).path(v(2.0, 0.0, 0.0)),
        ["1", "10", "[-1,0,0]", "20"]
    );
    // The lattice's own universe, or 0, leaves the element to the cell's
    // material; shorthand repeats.
    let l = row("-10 11 -12 13", "5 0 1R");
    let e = Eval::new(&l.scene);
    assert_eq!(e.path(v(0.0, 0.0, 0.0)), ["1", "10", "[0,0,0]"]);
    assert_eq!(e.path(v(2.0, 0.0, 0.0)), ["1", "10", "[1,0,0]"]);
    let i = l.scene.geometry.region_index("10").unwrap();
    assert_eq!(
        (l.scene.regions[i].material, l.scene.regions[i].density),
        (4, Some(2.5))
    );
    // An element moved by its own transformation.
    let l = row("-10 11 -12 13", "1 2(0 0.5 0) 3");
    assert_eq!(
        Eval::new(&l.scene).path(v(0.0, 0.4, 0.0)),
        ["1", "10", "[0,0,0]", "10:2(0 0.5 0)", "21"]
    );
}

#[test]
fn an_infinite_lattice_repeats_one_universe() {
    let l = load(&deck(
        "1 0 -1 fill=5\n2 0 1 imp:n=0\n10 0 -10 11 -12 13 u=5 lat=1 fill=1\n20 1 -1 -98 u=1\n21 0 98 u=1",
        "1 rpp -9 9 -9 9 -1 1\n10 px 1\n11 px -1\n12 py 1\n13 py -1\n98 cz 0.5",
        "",
    ));
    let e = Eval::new(&l.scene);
    assert_eq!(e.path(v(6.0, -4.0, 0.0)), ["1", "10", "[3,-2,0]", "20"]);
    assert_eq!(e.path(v(6.7, -4.0, 0.0)), ["1", "10", "[3,-2,0]", "21"]);
}

#[test]
fn hexagonal_lattices_by_rhp_or_by_planes() {
    let cells = |lattice: &str| {
        format!(
            "1 0 -1 fill=5\n2 0 1 imp:n=0\n10 0 {lattice} u=5 lat=2 fill=-1:1 -1:1 0:0 1 1 1 1 2 1 1 1 3\n\
             20 1 -1 -99 u=1\n21 2 -1 -99 u=2\n22 3 -1 -99 u=3"
        )
    };
    let s60 = "0.5 0.8660254037844386 0";
    let s120 = "-0.5 0.8660254037844386 0";
    let planes = format!(
        "11 px 1\n12 px -1\n13 p {s60} 1\n14 p {s60} -1\n15 p {s120} 1\n16 p {s120} -1\n17 pz 1\n18 pz -1"
    );
    for (lattice, surfaces) in [
        ("-10", "10 rhp 0 0 -1 0 0 2 1 0 0".to_string()),
        ("-11 12 -13 14 -15 16 -17 18", planes),
    ] {
        let l = load(&deck(
            &cells(lattice),
            &format!("1 rcc 0 0 -1 0 0 2 10\n99 so 1000\n{surfaces}"),
            "",
        ));
        let e = Eval::new(&l.scene);
        assert_eq!(
            e.path(v(0.1, 0.1, 0.0)),
            ["1", "10", "[0,0,0]", "21"],
            "{lattice}"
        );
        assert_eq!(
            e.path(v(3.0, 1.7, 0.0)),
            ["1", "10", "[1,1,0]", "22"],
            "{lattice}"
        );
        assert_eq!(
            e.path(v(2.0, 0.0, 0.0)),
            ["1", "10", "[1,0,0]", "20"],
            "{lattice}"
        );
        assert_eq!(
            e.path(v(-1.0, 1.7, 0.5)),
            ["1", "10", "[-1,1,0]", "20"],
            "{lattice}"
        );
        let Some(Fill::Lattice(lat)) = &region(&l, "10").fill else {
            panic!("cell 10 is a lattice");
        };
        assert_eq!(lat.kind, LatticeKind::Hexagonal);
        assert_close(&lat.steps[1].to_array(), &[1.0, 3f64.sqrt(), 0.0]);
        assert_close(&lat.steps[2].to_array(), &[0.0, 0.0, 2.0]);
    }
}

#[test]
fn importance_materials_and_densities() {
    let l = load(&deck(
        "1 1 -7.9 -1\n2 2 0.08 1 -2\n3 9 -1 2 -3\n4 0 3 -4\n5 0 4",
        "1 so 1\n2 so 2\n3 so 3\n4 so 4",
        "imp:n 1 3r 0\n\
         m1 26056.80c -0.9 6000 -0.1 nlib=80c\n\
         m2 1001.70c 2 8016.70c 1 gas = 1 95642 1e-6\n\
         mt2 lwtr.10t",
    ));
    let r = &l.scene.regions;
    assert_eq!(r[0].material_name.as_deref(), Some("m1"));
    assert_eq!(
        (r[0].density, r[0].atom_density, r[0].material_index),
        (Some(7.9), None, Some(0))
    );
    assert_eq!(
        (r[1].density, r[1].atom_density, r[1].material_index),
        (None, Some(0.08), Some(1))
    );
    assert_eq!((r[2].material, r[2].material_index), (9, None));
    assert!(r[3].air == 1 && r[3].transparent && !r[3].outside);
    assert!(r[4].outside && !r[0].outside);
    let m1 = &l.scene.materials[0];
    assert_eq!(m1.name, "m1");
    assert_eq!(m1.components.len(), 2);
    assert_eq!(
        (
            m1.components[1].zam,
            m1.components[1].fraction,
            m1.components[1].by_weight
        ),
        ((6, 0, 0), 0.1, true)
    );
    let m2 = &l.scene.materials[1];
    let zams: Vec<_> = m2.components.iter().map(|c| c.zam).collect();
    assert_eq!(zams, [(1, 1, 0), (8, 16, 0), (95, 242, 1)]);
    assert!(!m2.components[0].by_weight);
    assert_eq!(l.warnings.len(), 1);
    assert_eq!(l.warnings[0].message, "material 9 has no M card");
    assert_eq!(l.warnings[0].line_col(), (4, 3));
}

#[test]
fn zero_importance_for_neutrons_or_for_the_one_particle_given() {
    let l = load(&deck(
        "1 0 -1 imp:n,p=1\n2 0 1 -2 imp:p=0\n3 0 2 -3 imp:n=1 imp:p=0\n4 0 3 imp:n,p=0",
        "1 so 1\n2 so 2\n3 so 3",
        "",
    ));
    let outside: Vec<bool> = l.scene.regions.iter().map(|r| r.outside).collect();
    assert_eq!(outside, [false, true, false, true]);
}

#[test]
fn cell_parameters_as_data_cards() {
    let l = load(&deck(
        "1 0 -1\n2 0 1 -2\n3 0 2\n4 1 -1 -3\n5 0 3",
        "1 so 5\n2 so 10\n3 so 1",
        "imp:n 1 1 0 1 1\nu 0 0 0 7 7\nfill 7 0 0 0 0\nm1 1001 1",
    ));
    assert!(l.scene.regions[2].outside);
    assert_eq!(region(&l, "4").universe, 1);
    assert!(matches!(
        region(&l, "1").fill,
        Some(Fill::Universe { universe: 1, .. })
    ));
    assert_eq!(Eval::new(&l.scene).path(v(0.0, 0.0, 0.5)), ["1", "4"]);
}
