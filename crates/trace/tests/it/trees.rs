//! Regions as expression trees: along any ray, a region's stretches are
//! those of the same region expanded into sums of products, and the points
//! between its surfaces are inside it exactly where its expression says.

use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use sv_geom::{Body, BodyKind, Geometry, Group, Op, Region, Term, Zone};
use sv_math::{DVec3, Ray};
use sv_trace::{Partition, PrepareOptions, Prepared, Scratch};

/// Bodies about the origin: spheres, boxes, cylinders, a torus and a
/// half-space, overlapping one another.
fn bodies(rng: &mut Pcg64) -> Vec<Body> {
    let mut v = Vec::new();
    let mut c = || {
        DVec3::new(
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
        )
    };
    for i in 0..4 {
        let p = c();
        v.push(Body::new(
            format!("s{i}"),
            BodyKind::Sph,
            vec![p.x, p.y, p.z, 0.8 + 0.1 * i as f64],
        ));
    }
    for i in 0..3 {
        let p = c();
        v.push(Body::new(
            format!("b{i}"),
            BodyKind::Rpp,
            vec![
                p.x - 0.7,
                p.x + 0.6,
                p.y - 0.5,
                p.y + 0.9,
                p.z - 0.8,
                p.z + 0.4,
            ],
        ));
    }
    let (p, h) = (c(), c());
    v.push(Body::new(
        "c",
        BodyKind::Rcc,
        vec![p.x, p.y, p.z - 1.5, h.x, h.y, 3.0, 0.4],
    ));
    v.push(Body::new(
        "t",
        BodyKind::Tor,
        vec![0.1, 0.0, 0.2, 0.3, 0.2, 1.0, 0.9, 0.3],
    ));
    v.push(Body::new("h", BodyKind::Haf, vec![0.2, 0.1, 1.0, 0.3]));
    v
}

/// A random zone over `n` bodies, with groups down to `depth` levels.
fn zone(rng: &mut Pcg64, n: usize, depth: usize) -> Zone {
    let mut z = Zone::default();
    let sign = |rng: &mut Pcg64| {
        if rng.gen_bool(0.6) {
            Op::Inside
        } else {
            Op::Outside
        }
    };
    for _ in 0..rng.gen_range(1..3) {
        z.terms.push(Term {
            op: sign(rng),
            body: rng.gen_range(0..n),
        });
    }
    if depth > 0 {
        for _ in 0..rng.gen_range(0..3) {
            let zones = (0..rng.gen_range(1..4))
                .map(|_| zone(rng, n, depth - 1))
                .collect();
            z.groups.push(Group {
                op: sign(rng),
                zones,
            });
        }
    }
    z
}

/// A region's stretches along the ray, from its partitions.
fn stretches(parts: &[Partition], r: u32) -> Vec<(f64, f64)> {
    parts
        .iter()
        .filter(|p| p.region == r)
        .map(|p| (p.span.a.t, p.span.b.t))
        .collect()
}

#[test]
fn trees_trace_as_their_sums_of_products_and_their_points_classify() {
    let mut rng = Pcg64::seed_from_u64(17);
    let (mut compared, mut nested_stretches) = (0, 0);
    for _ in 0..12 {
        let bodies = bodies(&mut rng);
        let n = bodies.len();
        let mut tree = Geometry {
            bodies,
            ..Geometry::default()
        };
        while tree.regions.len() < 8 {
            let zones: Vec<Zone> = (0..rng.gen_range(1..3))
                .map(|_| zone(&mut rng, n, 3))
                .collect();
            let region = Region::new(format!("r{}", tree.regions.len()), zones);
            // Keep regions whose expansion stays small enough to compare.
            if region.flattened(2000).is_some_and(|f| !f.is_empty()) {
                tree.regions.push(region);
            }
        }
        let mut flat = tree.clone();
        for r in &mut flat.regions {
            r.zones = r.flattened(2000).expect("checked");
        }
        let opts = PrepareOptions::default();
        let p_tree = Prepared::new(&tree, &opts).unwrap().0;
        let p_flat = Prepared::new(&flat, &opts).unwrap().0;
        let tol = p_tree.tolerance();
        let (mut s, mut sf) = (Scratch::new(&p_tree), Scratch::new(&p_flat));
        let (mut parts, mut flat_parts) = (Vec::new(), Vec::new());
        for _ in 0..200 {
            let dir = DVec3::new(
                rng.gen_range(-1.0..1.0),
                rng.gen_range(-1.0..1.0),
                rng.gen_range(-1.0..1.0),
            );
            let through = DVec3::new(
                rng.gen_range(-1.0..1.0),
                rng.gen_range(-1.0..1.0),
                rng.gen_range(-1.0..1.0),
            );
            let ray = Ray::new(through - dir.normalize() * 6.0, dir);
            p_tree.partitions(&ray, 0.0, f64::INFINITY, &mut s, &mut parts);
            p_flat.partitions(&ray, 0.0, f64::INFINITY, &mut sf, &mut flat_parts);
            for (ri, region) in tree.regions.iter().enumerate() {
                let (a, b) = (
                    stretches(&parts, ri as u32),
                    stretches(&flat_parts, ri as u32),
                );
                assert_eq!(a.len(), b.len(), "region {ri}: {a:?} vs {b:?}");
                let near = |u: f64, v: f64| u == v || (u - v).abs() <= 2.0 * tol;
                for (x, y) in a.iter().zip(&b) {
                    assert!(
                        near(x.0, y.0) && near(x.1, y.1),
                        "region {ri}: {a:?} vs {b:?}"
                    );
                }
                if region.is_nested() {
                    nested_stretches += a.len();
                }
                // Midway along each stretch the point is inside, and midway
                // between stretches it is not.
                for w in a.windows(2) {
                    let gap = 0.5 * (w[0].1 + w[1].0);
                    if w[1].0 - w[0].1 > 10.0 * tol {
                        assert!(!p_tree.region_contains(ri, ray.at(gap)), "region {ri} gap");
                    }
                }
                for &(t0, t1) in &a {
                    if t1 - t0 > 10.0 * tol && t0.is_finite() && t1.is_finite() {
                        let m = ray.at(0.5 * (t0 + t1));
                        assert!(
                            p_tree.region_contains(ri, m),
                            "region {ri} stretch {t0} {t1} flat says {} expr {}",
                            p_flat.region_contains(ri, m),
                            region.expression(&|b| tree.bodies[b].name.as_str())
                        );
                    }
                }
                compared += 1;
            }
        }
    }
    assert!(
        nested_stretches > 1000,
        "{nested_stretches} stretches of nested regions"
    );
    assert!(compared > 10_000);
}

#[test]
fn a_region_of_eighteen_alternatives_stays_the_size_of_its_expression() {
    // +sph -( +(+a1 -b1) | +(+a2 -b2) | … 18 terms ): 2^18 zones if it were
    // expanded into sums of products; here one zone, one group of 18.
    let mut g = Geometry::default();
    g.bodies
        .push(Body::new("sph", BodyKind::Sph, vec![0.0, 0.0, 0.0, 10.0]));
    let mut alternatives = Vec::new();
    for i in 0..18 {
        let angle = i as f64 * std::f64::consts::TAU / 18.0;
        let (x, y) = (6.0 * angle.cos(), 6.0 * angle.sin());
        let a = g.bodies.len();
        g.bodies.push(Body::new(
            format!("a{i}"),
            BodyKind::Sph,
            vec![x, y, 0.0, 1.5],
        ));
        g.bodies.push(Body::new(
            format!("b{i}"),
            BodyKind::Sph,
            vec![x, y, 0.0, 1.0],
        ));
        alternatives.push(Zone::new(vec![
            Term {
                op: Op::Inside,
                body: a,
            },
            Term {
                op: Op::Outside,
                body: a + 1,
            },
        ]));
    }
    let region = Region::new(
        "coils",
        vec![Zone {
            terms: vec![Term {
                op: Op::Inside,
                body: 0,
            }],
            groups: vec![Group {
                op: Op::Outside,
                zones: alternatives,
            }],
        }],
    );
    assert!(region.flattened(1 << 17).is_none());
    g.regions.push(region);
    let p = Prepared::new(&g, &PrepareOptions::default()).unwrap().0;
    let mut s = Scratch::new(&p);
    // Up through the middle of coil 0: sphere, the shell's wall, the
    // hole (inside the region again), the other wall, then the sphere.
    let ray = Ray::new(DVec3::new(6.0, 0.0, -20.0), DVec3::Z);
    let mut parts = Vec::new();
    p.partitions(&ray, 0.0, f64::INFINITY, &mut s, &mut parts);
    let ends: Vec<(f64, f64)> = parts.iter().map(|q| (q.span.a.t, q.span.b.t)).collect();
    let want = [(20.0 - 8.0, 18.5), (19.0, 21.0), (21.5, 28.0)];
    assert_eq!(ends.len(), want.len(), "{ends:?}");
    for (got, w) in ends.iter().zip(want) {
        assert!(
            (got.0 - w.0).abs() < 1e-9 && (got.1 - w.1).abs() < 1e-9,
            "{ends:?}"
        );
    }
}
