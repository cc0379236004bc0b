//! The conformance suite every body passes (entry ≤ exit, midpoints inside,
//! points just outside are not, outward unit normals, bounds hold every hit,
//! invariance under rigid transforms, no re-hit from a convex body's own
//! surface): one named test per body type, and a test that every type in
//! the body table has a sample and a test.

use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use sv_geom::shape::{Seg, Shape};
use sv_geom::{Body, BodyKind, BODY_TYPES};
use sv_math::{Aabb, DAffine3, DQuat, DVec3, Ray};

/// One test per body type, each running the suite on every sample of its
/// type; `TESTED` lists the types so that a type without a test is found.
macro_rules! conformance_tests {
    ($($test:ident: $kind:ident,)*) => {
        $(
            #[test]
            fn $test() {
                let bodies: Vec<Body> =
                    samples().into_iter().filter(|b| b.kind == BodyKind::$kind).collect();
                assert!(!bodies.is_empty(), "no sample {}", BodyKind::$kind);
                for body in &bodies {
                    passes_the_conformance_suite(body);
                    is_invariant_under_rigid_transforms(body);
                }
            }
        )*
        const TESTED: &[BodyKind] = &[$(BodyKind::$kind),*];
    };
}

conformance_tests! {
    sph: Sph, rcc: Rcc, rec: Rec, trc: Trc, tec: Tec, ell: Ell, ell1: Ell1, ellg: Ellg,
    rpp: Rpp, box_: Box, raw: Raw, arb4: Arb4, arb5: Arb5, arb6: Arb6, arb7: Arb7,
    arb8: Arb8, tgc: Tgc, tor: Tor, haf: Haf, ars: Ars, xyp: Xyp, xzp: Xzp, yzp: Yzp,
    pla: Pla, xcc: Xcc, ycc: Ycc, zcc: Zcc, xec: Xec, yec: Yec, zec: Zec, qua: Qua,
    arbf: ArbF,
}

#[test]
fn every_type_in_the_body_table_has_a_sample_and_a_test() {
    let sampled: Vec<BodyKind> = samples().iter().map(|b| b.kind).collect();
    for t in BODY_TYPES {
        assert!(sampled.contains(&t.kind), "{} has no sample body", t.name);
        assert!(
            TESTED.contains(&t.kind),
            "{} has no conformance test",
            t.name
        );
    }
}

/// One body of every type, with awkward orientations.
pub fn samples() -> Vec<Body> {
    use BodyKind::*;
    let b = |k: BodyKind, p: &[f64]| Body::new(k.to_string(), k, p.to_vec());
    vec![
        b(Sph, &[1.0, 2.0, 3.0, 1.5]),
        b(Rcc, &[0.0, 0.0, 0.0, 1.0, 2.0, 3.0, 0.7]),
        b(
            Rec,
            &[0.0, 0.0, 0.0, 0.0, 0.0, 3.0, 2.0, 0.0, 0.0, 0.0, 1.0, 0.0],
        ),
        b(Trc, &[0.0, 0.0, 0.0, 0.0, 1.0, 4.0, 2.0, 0.5]),
        b(Trc, &[0.0, 0.0, 0.0, 0.0, 0.0, 2.0, 0.0, 1.0]),
        b(
            Tec,
            &[
                0.0, 0.0, 0.0, 0.0, 0.0, 10.0, 5.0, 0.0, 0.0, 0.0, 3.0, 0.0, 0.6,
            ],
        ),
        b(
            Tgc,
            &[
                0.0, 0.0, 0.0, 0.0, 0.0, 10.0, 5.0, 0.0, 0.0, 0.0, 8.0, 0.0, 2.0, 9.0,
            ],
        ),
        b(
            Tgc,
            &[
                0.0, 0.0, 0.0, 0.0, 0.0, 10.0, 5.0, 0.0, 0.0, 0.0, 8.0, 0.0, 2.5, 4.0,
            ],
        ),
        b(Ell, &[0.0, 0.0, 0.0, 4.0, 1.0, 0.0, 6.0]),
        b(Ell1, &[3.0, 2.0, 8.0, 3.0, -1.0, 8.0, 4.0]),
        b(
            Ellg,
            &[
                10.0, 0.0, 0.0, -12.0, 0.0, 0.0, 0.0, -3.0, 0.0, 0.0, 0.0, 5.0,
            ],
        ),
        b(Rpp, &[-1.0, 2.0, -3.0, 4.0, 0.5, 1.5]),
        b(
            Box,
            &[0.0, 0.0, 0.0, 1.0, 1.0, 0.0, -2.0, 2.0, 0.0, 0.0, 0.0, 3.0],
        ),
        b(
            Raw,
            &[
                -70.0, 0.0, 35.0, 0.0, -11.0, 11.0, 0.0, 11.0, 11.0, 40.0, 0.0, 0.0,
            ],
        ),
        b(
            Arb4,
            &[
                3.0, 0.0, -3.0, 3.0, 0.0, 0.0, 3.0, -3.0, -3.0, 0.0, 0.0, -3.0,
            ],
        ),
        b(
            Arb5,
            &[
                1.0, 0.0, 0.0, 1.0, 2.0, 0.0, 3.0, 2.0, 0.0, 3.0, 0.0, 0.0, 1.5, 1.5, 5.0,
            ],
        ),
        b(
            Arb6,
            &[
                2.0, -0.5, -0.5, 2.0, 0.0, -0.5, 2.0, 0.0, 0.0, 2.0, -0.5, 0.0, 2.5, -0.3, -0.5,
                2.5, -0.3, 0.0,
            ],
        ),
        b(
            Arb7,
            &[
                3.25, -1.25, -0.75, 3.25, -0.25, -0.75, 3.25, -0.25, 0.25, 3.25, -1.25, -0.25,
                2.25, -1.25, -0.75, 2.25, -0.25, -0.75, 2.25, -0.25, -0.25,
            ],
        ),
        b(
            Arb8,
            &[
                10.0, -9.0, -8.0, 10.0, -1.0, -8.0, 10.0, -1.0, 0.0, 10.0, -9.0, 0.0, 3.0, -9.0,
                -8.0, 3.0, -1.0, -8.0, 3.0, -1.0, 0.0, 3.0, -9.0, 0.0,
            ],
        ),
        b(Tor, &[0.0, 0.0, 0.0, 0.3015, 0.3015, 0.9045, 5.0, 2.0]),
        b(
            Ars,
            &[
                3.0, 3.0, 0., 0., 0., 0., 0., 0., 0., 0., 0., 0., 0., 100., 100., 0., 100., 100.,
                100., 100., 0., 0., 200., 0., 0., 200., 0., 0., 200.,
            ],
        ),
        b(
            ArbF,
            &[
                0., 0., 0., 1., 0., 0., 1., 1., 0., 0., 1., 0., 0., 0., 1., 1., 0., 1., 1., 1., 1.,
                0., 1., 1., 4321., 5678., 2376., 1485., 1265., 4378.,
            ],
        ),
        b(Haf, &[0.5774, 0.5774, 0.5774, -5.0]),
        b(Xyp, &[2.0]),
        b(Xzp, &[-1.5]),
        b(Yzp, &[0.25]),
        b(Pla, &[1.0, 1.0, 0.0, 0.0, 0.0, 1.0]),
        b(Xcc, &[1.0, 2.0, 0.5]),
        b(Ycc, &[-3.0, 0.5, 2.0]),
        b(Zcc, &[0.0, 0.0, 7.5]),
        b(Xec, &[1.0, -2.0, 3.0, 0.5]),
        b(Yec, &[1.0, 2.0, 0.5, 1.5]),
        b(Zec, &[4.0, 4.0, 0.1, 2.5]),
        b(Qua, &[1.0, 1.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0]),
    ]
}

pub fn prepare_one(b: &Body) -> (Shape, Aabb) {
    sv_geom::prepare(b, &mut Vec::new()).expect("sample body prepares")
}

pub fn random_ray(rng: &mut Pcg64, bb: Aabb) -> Ray {
    let (lo, hi) = if bb.is_finite() {
        (bb.min, bb.max)
    } else {
        (DVec3::splat(-10.0), DVec3::splat(10.0))
    };
    let target = DVec3::new(
        rng.gen_range(lo.x..=hi.x),
        rng.gen_range(lo.y..=hi.y),
        rng.gen_range(lo.z..=hi.z),
    );
    let dir = DVec3::new(
        rng.gen_range(-1.0..1.0),
        rng.gen_range(-1.0..1.0),
        rng.gen_range(-1.0..1.0),
    )
    .normalize();
    let dist = (hi - lo).length().clamp(1.0, 1e6) * 2.0;
    Ray::new(target - dir * dist, dir)
}

fn shoot(s: &Shape, r: &Ray) -> Vec<Seg> {
    let mut v = Vec::new();
    s.shoot(r, &mut v);
    v
}

/// The conformance suite for one body: entry <= exit, sorted segments,
/// midpoints inside, points just outside not, hits within the bounds, unit
/// outward normals, and no re-hit after leaving a convex body.
fn passes_the_conformance_suite(body: &Body) {
    let mut rng = Pcg64::seed_from_u64(7);
    let (shape, bb) = prepare_one(body);
    let shape = &shape;
    let scale = if bb.is_finite() { bb.diagonal() } else { 20.0 };
    let eps = 1e-6 * scale;
    let mut hits = 0;
    let mut wrong_way = 0;
    for _ in 0..400 {
        let ray = random_ray(&mut rng, bb);
        let segs = shoot(shape, &ray);
        for (i, s) in segs.iter().enumerate() {
            assert!(s.t0 <= s.t1, "{}: entry after exit {s:?}", body.kind);
            if i > 0 {
                assert!(
                    segs[i - 1].t1 <= s.t0,
                    "{}: segments overlap or unsorted",
                    body.kind
                );
            }
            let (a, b) = (s.t0.max(-1e3 * scale), s.t1.min(1e3 * scale));
            if b - a > 10.0 * eps {
                let mid = ray.at(0.5 * (a + b));
                assert!(
                    shape.contains(mid),
                    "{}: midpoint {mid} of {s:?} not inside",
                    body.kind
                );
            }
            for (t, face, sign) in [(s.t0, s.f0, -1.0), (s.t1, s.f1, 1.0)] {
                if !t.is_finite() {
                    continue;
                }
                hits += 1;
                let pt = ray.at(t);
                assert!(
                    !shape.contains(ray.at(t + sign * 10.0 * eps))
                        || segs
                            .iter()
                            .any(|o| o != s && o.t0 <= t + 20.0 * eps && o.t1 >= t - 20.0 * eps),
                    "{}: point just outside {pt} is inside",
                    body.kind
                );
                assert!(
                    bb.padded(eps).contains(pt),
                    "{}: hit {pt} outside bounds {bb:?}",
                    body.kind
                );
                let n = shape.normal(face, pt);
                assert!(
                    (n.length() - 1.0).abs() < 1e-9,
                    "{}: normal not unit",
                    body.kind
                );
                // A ray through an edge (a cone's rim) may be given either
                // face; such hits are rare, systematic errors are not.
                if n.dot(ray.dir) * sign < -1e-6 {
                    wrong_way += 1;
                }
                let probe = 1e-4 * scale;
                if shape.is_convex() {
                    assert!(
                        !shape.contains(pt + n * probe),
                        "{}: outward normal points inside",
                        body.kind
                    );
                    // A ray leaving the surface outward never re-hits a convex body.
                    let out = Ray::new(pt + n * eps, (n + ray.dir * sign).normalize());
                    assert!(
                        shoot(shape, &out).iter().all(|s| s.t1 <= 10.0 * eps),
                        "{}: re-hit after leaving",
                        body.kind
                    );
                }
            }
        }
    }
    assert!(
        hits > 20,
        "{}: only {hits} surface hits in 400 rays",
        body.kind
    );
    assert!(
        wrong_way * 100 <= hits,
        "{}: {wrong_way} of {hits} normals face the wrong way",
        body.kind
    );
}

/// A body turned and moved gives the segments of the ray turned and moved
/// with it.
fn is_invariant_under_rigid_transforms(body: &Body) {
    let mut rng = Pcg64::seed_from_u64(11);
    let (shape, bounds) = prepare_one(body);
    for _ in 0..5 {
        let q = DQuat::from_axis_angle(
            DVec3::new(
                rng.gen_range(-1.0..1.0),
                rng.gen_range(-1.0..1.0),
                rng.gen_range(-1.0..1.0),
            )
            .normalize(),
            rng.gen_range(0.0..std::f64::consts::TAU),
        );
        let xf = DAffine3::from_rotation_translation(
            q,
            DVec3::new(rng.gen_range(-50.0..50.0), 3.0, -7.0),
        );
        let moved = body.transformed(&xf).unwrap();
        let (moved_shape, _) = prepare_one(&moved);
        let scale = bounds.diagonal().clamp(1.0, 100.0);
        for _ in 0..60 {
            let r = random_ray(&mut rng, bounds);
            let rm = Ray::new(xf.transform_point3(r.origin), xf.transform_vector3(r.dir));
            let (a, b) = (shoot(&shape, &r), shoot(&moved_shape, &rm));
            let fin = |s: &[Seg]| -> Vec<f64> {
                s.iter()
                    .flat_map(|s| [s.t0, s.t1])
                    .filter(|t| t.is_finite())
                    .collect()
            };
            let (fa, fb) = (fin(&a), fin(&b));
            if fa.len() == fb.len() {
                for (x, y) in fa.iter().zip(&fb) {
                    assert!(
                        (x - y).abs() < 1e-6 * scale.max(x.abs()),
                        "{}: {x} vs {y}",
                        body.kind
                    );
                }
            } else {
                // Only grazing rays may differ in the number of crossings.
                let graze = fa.iter().chain(&fb).any(|t| {
                    let n = shape.normal(0, r.at(*t));
                    n.dot(r.dir).abs() < 1e-3
                }) || (fa.len() as i64 - fb.len() as i64).abs() <= 2
                    && a.iter().chain(&b).any(|s| s.t1 - s.t0 < 1e-3 * scale);
                assert!(graze, "{}: {fa:?} vs {fb:?}", body.kind);
            }
        }
    }
}
