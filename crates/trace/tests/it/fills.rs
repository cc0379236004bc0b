//! Filled regions and lattices against the same models written out in
//! full: a universe moved into a region, a rectangular lattice of pins, a
//! hexagonal one, and a region that holds a moved copy of the root (FLUKA's
//! lattice cells) give the hits, normals and partitions of the model with
//! every copy placed by hand, and packets give what single rays give.

use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use sv_geom::{
    Body, BodyKind, Fill, Geometry, Lattice, LatticeKind, Op, Region, Term, Universe, Zone,
};
use sv_math::{DAffine3, DQuat, DVec3, Ray};
use sv_trace::{Hit, Partition, PrepareOptions, Prepared, Scratch, Tile};

fn plus(body: usize) -> Term {
    Term {
        op: Op::Inside,
        body,
    }
}

fn minus(body: usize) -> Term {
    Term {
        op: Op::Outside,
        body,
    }
}

/// A pin (fuel sphere, clad shell) at `centre`: two bodies pushed onto
/// `bodies`, the regions `fuel` and `clad` of their zones.
fn pin(bodies: &mut Vec<Body>, centre: DVec3) -> (Zone, Zone) {
    let n = bodies.len();
    bodies.push(Body::new(
        format!("f{n}"),
        BodyKind::Sph,
        vec![centre.x, centre.y, centre.z, 0.3],
    ));
    bodies.push(Body::new(
        format!("c{n}"),
        BodyKind::Rcc,
        vec![centre.x, centre.y, centre.z - 0.45, 0.0, 0.0, 0.9, 0.4],
    ));
    (
        Zone::new(vec![plus(n)]),
        Zone::new(vec![plus(n + 1), minus(n)]),
    )
}

/// Rays toward the box `[-2, 2]³` from all around.
fn rays(rng: &mut Pcg64, n: usize) -> Vec<Ray> {
    (0..n)
        .map(|_| {
            let target = DVec3::new(
                rng.gen_range(-1.8..1.8),
                rng.gen_range(-1.8..1.8),
                rng.gen_range(-0.6..0.6),
            );
            let dir = DVec3::new(
                rng.gen_range(-1.0..1.0),
                rng.gen_range(-1.0..1.0),
                rng.gen_range(-0.7..0.7),
            );
            Ray::new(target - dir.normalize() * 9.0, dir)
        })
        .collect()
}

/// The first hits of `a` and `b` agree: the same region at the same
/// distance with the same normal (1e-4 rad: a filled region's normals are
/// carried in 32 bits).
fn same_hits(a: &Prepared, b: &Prepared, rays: &[Ray]) -> usize {
    let (mut sa, mut sb) = (Scratch::new(a), Scratch::new(b));
    let mut hits = 0;
    for ray in rays {
        let (ha, hb) = (
            a.first_hit(ray, 0.0, f64::INFINITY, &mut sa),
            b.first_hit(ray, 0.0, f64::INFINITY, &mut sb),
        );
        match (ha, hb) {
            (None, None) => {}
            (Some(x), Some(y)) => {
                assert_eq!(x.region, y.region, "{ray:?}");
                assert!((x.t - y.t).abs() < 1e-9, "{ray:?}: {} vs {}", x.t, y.t);
                let (nx, ny) = (a.normal(&x, ray), b.normal(&y, ray));
                assert!(nx.angle_between(ny) < 2e-4, "{ray:?}: {nx} vs {ny}");
                hits += 1;
            }
            (x, y) => panic!("{ray:?}: {x:?} vs {y:?}"),
        }
    }
    hits
}

/// The partitions of `a` and `b` agree region by region.
fn same_partitions(a: &Prepared, b: &Prepared, rays: &[Ray]) -> usize {
    let (mut sa, mut sb) = (Scratch::new(a), Scratch::new(b));
    let (mut pa, mut pb) = (Vec::new(), Vec::new());
    let mut compared = 0;
    let key = |p: &Partition| (p.region, p.span.a.t, p.span.b.t);
    for ray in rays {
        a.partitions(ray, 0.0, f64::INFINITY, &mut sa, &mut pa);
        b.partitions(ray, 0.0, f64::INFINITY, &mut sb, &mut pb);
        let (mut ka, mut kb): (Vec<_>, Vec<_>) =
            (pa.iter().map(key).collect(), pb.iter().map(key).collect());
        ka.sort_by(|x, y| x.partial_cmp(y).unwrap());
        kb.sort_by(|x, y| x.partial_cmp(y).unwrap());
        assert_eq!(ka.len(), kb.len(), "{ray:?}: {ka:?} vs {kb:?}");
        for (x, y) in ka.iter().zip(&kb) {
            assert_eq!(x.0, y.0, "{ray:?}: {ka:?} vs {kb:?}");
            assert!(
                (x.1 - y.1).abs() < 1e-9 && (x.2 - y.2).abs() < 1e-9,
                "{ray:?}: {ka:?} vs {kb:?}"
            );
        }
        compared += ka.len();
    }
    compared
}

/// `g` prepared with a tolerance of its own: the written-out models hold
/// a stand-in body far off, which would change the default.
fn prepared(g: &Geometry) -> Prepared {
    let opts = PrepareOptions {
        tolerance: Some(1e-9),
        ..PrepareOptions::default()
    };
    Prepared::new(g, &opts).unwrap().0
}

#[test]
fn a_universe_moved_into_a_region_is_the_universe_placed_there() {
    // Region 0 (root): a box filled with universe 1 (a pin and the water
    // around it), turned and moved. Written out: the pin's bodies moved,
    // the water less the pin, each clipped to the box.
    let turn = DAffine3::from_rotation_translation(
        DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 0.5).normalize(), 0.7),
        DVec3::new(0.3, -0.2, 0.1),
    );
    let mut bodies = vec![Body::new(
        "box",
        BodyKind::Rpp,
        vec![-1.5, 1.5, -1.2, 1.2, -1.0, 1.0],
    )];
    let (fuel, clad) = pin(&mut bodies, DVec3::ZERO);
    bodies.push(Body::new("water", BodyKind::Sph, vec![0.0, 0.0, 0.0, 5.0]));
    let mut nested = Geometry {
        bodies: bodies.clone(),
        universes: vec![Universe { name: "0".into() }, Universe { name: "1".into() }],
        ..Geometry::default()
    };
    let mut container = Region::of_body("box", 0);
    container.fill = Some(Fill::Universe {
        universe: 1,
        region_from_universe: turn,
    });
    nested.regions.push(container);
    for (name, zone) in [
        ("fuel", fuel.clone()),
        ("clad", clad.clone()),
        ("water", Zone::new(vec![plus(3), minus(2)])),
    ] {
        let mut r = Region::new(name, vec![zone]);
        r.universe = 1;
        nested.regions.push(r);
    }
    let mut flat = Geometry {
        bodies: bodies[..1].to_vec(),
        ..Geometry::default()
    };
    flat.bodies
        .extend(bodies[1..].iter().map(|b| b.transformed(&turn).unwrap()));
    // Region 0 has nothing of its own: keep its index with an empty
    // stand-in far away.
    flat.bodies
        .push(Body::new("far", BodyKind::Sph, vec![1e3, 0.0, 0.0, 1.0]));
    flat.regions.push(Region::of_body("box", 4));
    for zone in [fuel, clad, Zone::new(vec![plus(3), minus(2)])] {
        let mut z = zone;
        z.terms.push(plus(0));
        flat.regions.push(Region::new("r", vec![z]));
    }
    let (a, b) = (prepared(&nested), prepared(&flat));
    let rays = rays(&mut Pcg64::seed_from_u64(1), 3000);
    assert!(same_hits(&a, &b, &rays) > 1500);
    assert!(same_partitions(&a, &b, &rays) > 2000);
    // The point at the pin's centre is in the box and the fuel.
    assert_eq!(a.regions_at(turn.transform_point3(DVec3::ZERO)), [0, 1]);
}

/// A 4 × 3 lattice of pins in water, pitch 1, filling the box
/// [-2, 2] × [-1.5, 1.5] × [-1, 1] (the lattice's frame moved by `move_`),
/// and the same written out; universe 1 is the pin cell.
fn pin_lattice(move_: DAffine3) -> (Geometry, Geometry) {
    let mut bodies = vec![Body::new(
        "box",
        BodyKind::Rpp,
        vec![-2.0, 2.0, -1.5, 1.5, -1.0, 1.0],
    )];
    let (fuel, clad) = pin(&mut bodies, DVec3::ZERO);
    bodies.push(Body::new(
        "cell",
        BodyKind::Rpp,
        vec![-0.5, 0.5, -0.5, 0.5, -5.0, 5.0],
    ));
    let mut nested = Geometry {
        bodies: bodies.clone(),
        universes: vec![
            Universe { name: "0".into() },
            Universe { name: "pin".into() },
        ],
        ..Geometry::default()
    };
    nested.bodies[0] = nested.bodies[0].transformed(&move_).unwrap();
    let mut container = Region::of_body("box", 0);
    container.fill = Some(Fill::Lattice(Lattice {
        kind: LatticeKind::Rectangular,
        region_from_lattice: move_,
        steps: [DVec3::X, DVec3::Y, DVec3::Z * 10.0],
        base: DVec3::new(-2.0, -1.5, -5.0),
        origin: DVec3::new(-1.5, -1.0, 0.0),
        lowest: [0, 0, 0],
        counts: [4, 3, 1],
        elements: vec![Some(1); 12],
        outer: None,
    }));
    nested.regions.push(container);
    // Everything but the pin is water: the water region fills all of the
    // pin universe's space.
    for (name, zone) in [
        ("fuel", fuel.clone()),
        ("clad", clad.clone()),
        ("water", Zone::new(vec![minus(1), minus(2)])),
    ] {
        let mut r = Region::new(name, vec![zone]);
        r.universe = 1;
        nested.regions.push(r);
    }
    let mut flat = Geometry {
        bodies: bodies[..1].to_vec(),
        ..Geometry::default()
    };
    flat.bodies[0] = flat.bodies[0].transformed(&move_).unwrap();
    flat.bodies
        .push(Body::new("far", BodyKind::Sph, vec![1e3, 0.0, 0.0, 1.0]));
    flat.regions.push(Region::of_body("box", 1));
    let (mut fuels, mut clads, mut waters) = (Vec::new(), Vec::new(), Vec::new());
    for j in 0..3 {
        for i in 0..4 {
            let centre = DVec3::new(-1.5 + i as f64, -1.0 + j as f64, 0.0);
            let cell = flat.bodies.len();
            let c = centre;
            flat.bodies.push(
                Body::new(
                    "cell",
                    BodyKind::Rpp,
                    vec![c.x - 0.5, c.x + 0.5, c.y - 0.5, c.y + 0.5, -5.0, 5.0],
                )
                .transformed(&move_)
                .unwrap(),
            );
            let mut placed = Vec::new();
            let (f, cl) = pin(&mut placed, centre);
            let base = flat.bodies.len();
            flat.bodies
                .extend(placed.iter().map(|b| b.transformed(&move_).unwrap()));
            let shift = |z: &Zone| {
                let mut z = z.clone();
                for t in &mut z.terms {
                    t.body += base;
                }
                z.terms.push(plus(0));
                z.terms.push(plus(cell));
                z
            };
            fuels.push(shift(&f));
            clads.push(shift(&cl));
            waters.push(Zone::new(vec![
                plus(0),
                plus(cell),
                minus(base),
                minus(base + 1),
            ]));
        }
    }
    flat.regions.push(Region::new("fuel", fuels));
    flat.regions.push(Region::new("clad", clads));
    flat.regions.push(Region::new("water", waters));
    (nested, flat)
}

#[test]
fn a_rectangular_lattice_is_its_elements_placed_one_by_one() {
    for move_ in [
        DAffine3::IDENTITY,
        DAffine3::from_rotation_translation(
            DQuat::from_rotation_z(0.4),
            DVec3::new(0.25, 0.1, 0.0),
        ),
    ] {
        let (nested, flat) = pin_lattice(move_);
        let (a, b) = (prepared(&nested), prepared(&flat));
        let rays = rays(&mut Pcg64::seed_from_u64(2), 3000);
        assert!(same_hits(&a, &b, &rays) > 1500);
        assert!(same_partitions(&a, &b, &rays) > 4000);
    }
}

#[test]
fn packets_and_single_rays_agree_through_a_lattice() {
    let (nested, _) = pin_lattice(DAffine3::IDENTITY);
    let with = prepared(&nested);
    let without = Prepared::new(
        &nested,
        &PrepareOptions {
            brute_force: true,
            ..PrepareOptions::default()
        },
    )
    .unwrap()
    .0;
    let eye = DVec3::new(4.0, -5.0, 3.0);
    let forward = (-eye).normalize();
    let (right, up) = sv_math::orthonormal_basis(forward);
    let gen = sv_math::RayGen::new(eye, right * 0.5, up * 0.4, forward, false, 40, 32);
    let tile = Tile {
        x0: 0,
        x1: 40,
        y0: 0,
        y1: 32,
    };
    // Per tracer, its hits and their normals, in pixel order.
    type Traced = (Vec<(u32, Hit)>, Vec<DVec3>);
    let mut outputs: Vec<Traced> = Vec::new();
    for p in [&with, &without] {
        let mut s = Scratch::new(p);
        let (mut hits, mut rays, mut normals) = (Vec::new(), Vec::new(), Vec::new());
        let n = p.tile_hits(
            &gen,
            tile,
            None,
            0.0,
            f64::INFINITY,
            &mut s,
            &mut hits,
            &mut rays,
            &mut normals,
        );
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by_key(|&i| hits[i].0);
        outputs.push((
            order.iter().map(|&i| hits[i]).collect(),
            order.iter().map(|&i| normals[i]).collect(),
        ));
    }
    let (a, b) = (&outputs[0], &outputs[1]);
    assert!(a.0.len() > 400, "{} hits", a.0.len());
    assert_eq!(a.0.len(), b.0.len());
    for ((x, y), (nx, ny)) in a.0.iter().zip(&b.0).zip(a.1.iter().zip(&b.1)) {
        assert_eq!(x.0, y.0);
        assert_eq!((x.1.t.to_bits(), x.1.region), (y.1.t.to_bits(), y.1.region));
        assert_eq!(
            nx.to_array().map(f64::to_bits),
            ny.to_array().map(f64::to_bits)
        );
    }
}

#[test]
fn a_hexagonal_lattice_puts_each_point_in_its_nearest_element() {
    // Elements of flat-to-flat pitch 1 (a along x, b at 60°), three rings
    // listed, each element's universe a marker ball at its centre.
    let a = DVec3::X;
    let b = DVec3::new(0.5, 3f64.sqrt() / 2.0, 0.0);
    let mut g = Geometry {
        bodies: vec![
            Body::new("world", BodyKind::Sph, vec![0.0, 0.0, 0.0, 20.0]),
            Body::new("marker", BodyKind::Sph, vec![0.0, 0.0, 0.0, 0.2]),
        ],
        // Beyond the listed elements, an empty outer universe (without
        // one, the lattice region's own material would fill it).
        universes: vec![
            Universe { name: "0".into() },
            Universe { name: "m".into() },
            Universe {
                name: "empty".into(),
            },
        ],
        ..Geometry::default()
    };
    let mut container = Region::of_body("world", 0);
    container.fill = Some(Fill::Lattice(Lattice {
        kind: LatticeKind::Hexagonal,
        region_from_lattice: DAffine3::IDENTITY,
        steps: [a, b, DVec3::Z * 4.0],
        base: DVec3::ZERO,
        origin: DVec3::ZERO,
        lowest: [-3, -3, 0],
        counts: [7, 7, 1],
        elements: vec![Some(1); 49],
        outer: Some(2),
    }));
    g.regions.push(container);
    let mut marker = Region::of_body("marker", 1);
    marker.universe = 1;
    g.regions.push(marker);
    let p = prepared(&g);
    let mut rng = Pcg64::seed_from_u64(4);
    let (mut inside, mut outside) = (0, 0);
    for _ in 0..4000 {
        let q = DVec3::new(
            rng.gen_range(-2.0..2.0),
            rng.gen_range(-2.0..2.0),
            rng.gen_range(-1.0..1.0),
        );
        // The nearest centre i a + j b, searched.
        let mut nearest = f64::INFINITY;
        for i in -5..=5 {
            for j in -5..=5 {
                let c = a * i as f64 + b * j as f64;
                nearest = nearest.min((DVec3::new(q.x, q.y, 0.0) - c).length());
            }
        }
        let want_marker = (nearest * nearest + q.z * q.z).sqrt() < 0.2;
        if ((nearest * nearest + q.z * q.z).sqrt() - 0.2).abs() < 1e-6 {
            continue;
        }
        let got = p.regions_at(q);
        assert_eq!(got.contains(&1), want_marker, "{q}: {got:?}");
        if want_marker {
            inside += 1;
        } else {
            outside += 1;
        }
    }
    assert!(inside > 20 && outside > 1000, "{inside} {outside}");
    // Rays across the plane meet the markers they pass within 0.2 of.
    let mut s = Scratch::new(&p);
    for k in 0..200 {
        let y = -1.5 + k as f64 * 0.015;
        let ray = Ray::new(DVec3::new(-6.0, y, 0.0), DVec3::X);
        let hit = p.first_hit(&ray, 0.0, f64::INFINITY, &mut s);
        let passes = (-5..=5)
            .flat_map(|i| (-5..=5).map(move |j| (i, j)))
            .any(|(i, j)| {
                let c = a * i as f64 + b * j as f64;
                (c.y - y).abs() < 0.2 - 1e-9 && c.x.abs() < 5.5
            });
        assert_eq!(hit.is_some(), passes, "y = {y}");
        if let Some(h) = hit {
            assert_eq!(h.region, 1);
        }
    }
}

#[test]
fn a_region_may_hold_a_moved_copy_of_the_root() {
    // FLUKA's lattice cells: the prototype (a box holding a ball) stays
    // where it is; the cell, a box further along x, holds the root moved
    // so that the prototype's contents appear inside it.
    let mut g = Geometry {
        bodies: vec![
            Body::new(
                "proto",
                BodyKind::Rpp,
                vec![-1.0, 1.0, -1.0, 1.0, -1.0, 1.0],
            ),
            Body::new("ball", BodyKind::Sph, vec![0.0, 0.0, 0.0, 0.5]),
            Body::new("cell", BodyKind::Rpp, vec![4.0, 6.0, -1.0, 1.0, -1.0, 1.0]),
        ],
        ..Geometry::default()
    };
    g.regions.push(Region::new(
        "fill",
        vec![Zone::new(vec![plus(0), minus(1)])],
    ));
    g.regions.push(Region::of_body("ball", 1));
    let mut cell = Region::of_body("cell", 2);
    cell.fill = Some(Fill::Universe {
        universe: 0,
        region_from_universe: DAffine3::from_translation(DVec3::new(5.0, 0.0, 0.0)),
    });
    g.regions.push(cell);
    // Only the ball is opaque: seen through the prototype and the cell.
    let opts = PrepareOptions {
        opaque: Some(vec![false, true, false]),
        ..PrepareOptions::default()
    };
    let p = Prepared::new(&g, &opts).unwrap().0;
    let mut s = Scratch::new(&p);
    for (x, want) in [(0.0, Some(4.5)), (5.0, Some(4.5)), (2.5, None), (5.7, None)] {
        let ray = Ray::new(DVec3::new(x, 0.0, -5.0), DVec3::Z);
        let hit = p.first_hit(&ray, 0.0, f64::INFINITY, &mut s);
        assert_eq!(
            hit.map(|h| (h.region, h.t)),
            want.map(|t| (1, t)),
            "x = {x}"
        );
    }
    assert_eq!(p.regions_at(DVec3::new(5.1, 0.0, 0.0)), [1, 2]);
}

#[test]
fn shadows_through_a_lattice_agree_with_or_without_packets() {
    let (nested, flat) = pin_lattice(DAffine3::IDENTITY);
    let with = prepared(&nested);
    let without = Prepared::new(
        &nested,
        &PrepareOptions {
            brute_force: true,
            tolerance: Some(1e-9),
            ..PrepareOptions::default()
        },
    )
    .unwrap()
    .0;
    let written = prepared(&flat);
    let toward = DVec3::new(0.3, -0.5, 0.8).normalize();
    let (lb, lb_written) = (
        sv_trace::LightBuffer::new(&with, toward),
        sv_trace::LightBuffer::new(&written, toward),
    );
    let mut rng = Pcg64::seed_from_u64(6);
    let from: Vec<(DVec3, Option<u32>)> = (0..2000)
        .map(|_| {
            let p = DVec3::new(
                rng.gen_range(-2.5..2.5),
                rng.gen_range(-2.0..2.0),
                rng.gen_range(-1.5..1.5),
            );
            (p, None)
        })
        .collect();
    let (mut a, mut b, mut c) = (Vec::new(), Vec::new(), Vec::new());
    let mut s = Scratch::new(&with);
    with.occluded_toward(&lb, &from, 0.0, &mut None, &mut s, &mut a);
    let mut s = Scratch::new(&without);
    without.occluded_toward(&lb, &from, 0.0, &mut None, &mut s, &mut b);
    let mut s = Scratch::new(&written);
    written.occluded_toward(&lb_written, &from, 0.0, &mut None, &mut s, &mut c);
    assert_eq!(a, b);
    assert_eq!(a, c);
    let blocked = a.iter().filter(|&&x| x).count();
    assert!(blocked > 200 && blocked < 1900, "{blocked}");
}

#[test]
fn an_element_with_no_universe_is_the_lattice_regions_own_material() {
    // Two elements name no universe: there the lattice region's own
    // material fills the element (MCNP's element of the lattice's own
    // universe), and a ray is stopped where it enters them, as the
    // partitions say.
    let (mut nested, _) = pin_lattice(DAffine3::IDENTITY);
    if let Some(Fill::Lattice(lattice)) = &mut nested.regions[0].fill {
        lattice.elements[5] = None;
        lattice.elements[6] = None;
    }
    let p = prepared(&nested);
    let mut s = Scratch::new(&p);
    let mut parts = Vec::new();
    let (mut own, mut compared) = (0, 0);
    for ray in rays(&mut Pcg64::seed_from_u64(7), 3000) {
        p.partitions(&ray, 0.0, f64::INFINITY, &mut s, &mut parts);
        let first = parts
            .iter()
            .filter(|q| q.span.b.t > 0.0)
            .min_by(|x, y| x.span.a.t.total_cmp(&y.span.a.t));
        let hit = p.first_hit(&ray, 0.0, f64::INFINITY, &mut s);
        match (first, hit) {
            (None, None) => {}
            (Some(q), Some(h)) => {
                assert!(
                    (q.span.a.t.max(0.0) - h.t).abs() < 1e-9,
                    "{ray:?}: {q:?} vs {h:?}"
                );
                assert_eq!(q.region, h.region, "{ray:?}");
                own += usize::from(h.region == 0);
                compared += 1;
            }
            (q, h) => panic!("{ray:?}: {q:?} vs {h:?}"),
        }
    }
    assert!(
        compared > 1000 && own > 20,
        "{compared} hits, {own} of the lattice region"
    );
}
