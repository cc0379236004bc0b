//! The packet tracer held to the scalar tracer, bit for bit.

use super::primary::*;
use super::shadow::*;
use super::*;
use crate::{LightBuffer, PrepareOptions};
use rand::{Rng, SeedableRng};
use sv_geom::{Body, BodyKind, Geometry, Op, Region, Term, Zone};
use sv_math::simd::Portable;
use sv_math::{DVec3, RayGen};

/// Bodies of every kind the lanes cast, about the origin, and a few
/// they do not (a torus, a general cone), with flush faces among them.
fn bodies(rng: &mut impl Rng) -> Vec<Body> {
    let mut out = Vec::new();
    let v = |r: &mut dyn FnMut() -> f64| [r(), r(), r()];
    for i in 0..48 {
        let mut u = || rng.gen_range(-1.0..1.0);
        let p = v(&mut u);
        let (kind, params): (BodyKind, Vec<f64>) = match i % 16 {
            0 => (BodyKind::Sph, vec![p[0], p[1], p[2], 0.3 + 0.5 * u().abs()]),
            1 => (
                BodyKind::Rcc,
                [p.to_vec(), v(&mut u).to_vec(), vec![0.25]].concat(),
            ),
            // Along an axis: rays parallel to it and through its ends.
            2 => (BodyKind::Rcc, vec![0.0, 0.0, -1.0, 0.0, 0.0, 2.0, 0.4]),
            3 => (
                BodyKind::Trc,
                [p.to_vec(), v(&mut u).to_vec(), vec![0.5, 0.1]].concat(),
            ),
            4 => (
                BodyKind::Trc,
                [p.to_vec(), v(&mut u).to_vec(), vec![0.1, 0.6]].concat(),
            ),
            5 => (BodyKind::Rpp, vec![-0.5, 0.5, -0.5, 0.5, -0.5, 0.5]),
            6 => {
                let q = v(&mut u);
                (
                    BodyKind::Rpp,
                    vec![
                        q[0].min(p[0]),
                        q[0].max(p[0]),
                        q[1].min(p[1]),
                        q[1].max(p[1]),
                        -0.5,
                        0.5,
                    ],
                )
            }
            7 => (
                BodyKind::Ell1,
                [p.to_vec(), v(&mut u).to_vec(), vec![0.3]].concat(),
            ),
            8 => (
                BodyKind::Box,
                [
                    p.to_vec(),
                    vec![0.6, 0.3, 0.0, -0.3, 0.6, 0.0, 0.0, 0.0, 0.7],
                ]
                .concat(),
            ),
            9 => (
                BodyKind::Raw,
                [
                    p.to_vec(),
                    vec![0.8, 0.0, 0.0, 0.0, 0.6, 0.0, 0.0, 0.0, 0.5],
                ]
                .concat(),
            ),
            10 => (BodyKind::Haf, vec![0.0, 0.0, 1.0, -0.2]),
            11 => (
                BodyKind::Arb8,
                vec![
                    -0.6, -0.6, -0.6, 0.6, -0.6, -0.6, 0.6, 0.6, -0.6, -0.6, 0.6, -0.6, -0.3, -0.3,
                    0.6, 0.3, -0.3, 0.6, 0.3, 0.3, 0.6, -0.3, 0.3, 0.6,
                ],
            ),
            12 => (
                BodyKind::Tor,
                vec![p[0], p[1], p[2], 0.0, 0.0, 1.0, 0.5, 0.15],
            ),
            13 => (
                BodyKind::Tgc,
                [
                    p.to_vec(),
                    vec![0.0, 0.0, 0.8, 0.5, 0.0, 0.0, 0.0, 0.3, 0.0, 0.2, 0.25],
                ]
                .concat(),
            ),
            14 => (
                BodyKind::Tec,
                [
                    p.to_vec(),
                    vec![0.0, 0.1, 0.9, 0.4, 0.0, 0.0, 0.0, 0.25, 0.0, 1.5],
                ]
                .concat(),
            ),
            _ => (
                BodyKind::Rec,
                [
                    p.to_vec(),
                    vec![0.9, 0.0, 0.0, 0.0, 0.3, 0.0, 0.0, 0.0, 0.2],
                ]
                .concat(),
            ),
        };
        out.push(Body::new(format!("b{i}"), kind, params));
    }
    out
}

/// Zones of random bodies, or zones made to sit on the tolerances
/// (apart, so that the random ones do not hide them; `only` one of them,
/// so that none hides another): `+` and `-` bodies flush with each other,
/// a body less itself, cones whose generators the rays below run along,
/// slabs that cut a span into two or three.
fn geometry(rng: &mut impl Rng, made_only: bool, only: Option<usize>) -> Geometry {
    let mut g = Geometry {
        bodies: bodies(rng),
        ..Default::default()
    };
    let n = g.bodies.len();
    let edge: [(BodyKind, Vec<f64>); 12] = [
        (BodyKind::Rpp, vec![0.5, 1.5, -0.5, 0.5, -0.5, 0.5]),
        (BodyKind::Rpp, vec![-0.5, 0.0, -0.5, 0.5, -0.5, 0.5]),
        (BodyKind::Trc, vec![0.0, 0.0, -1.0, 0.0, 0.0, 2.0, 0.6, 0.2]),
        (BodyKind::Trc, vec![0.0, 0.0, -1.0, 0.0, 0.0, 2.0, 0.2, 0.6]),
        (BodyKind::Rcc, vec![0.0, 0.0, -0.5, 0.0, 0.0, 1.0, 0.5]),
        (BodyKind::Sph, vec![0.0, 0.0, 0.0, 0.5]),
        // The cube's halves as polyhedra: their faces' distances come
        // out a few units in the last place off the box's.
        (
            BodyKind::Box,
            vec![
                -0.5, -0.5, -0.5, 0.5, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0,
            ],
        ),
        (
            BodyKind::Box,
            vec![0.0, -0.5, -0.5, 0.5, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
        ),
        // Slabs across the cube: one splits a span in two, the other makes
        // three pieces.
        (BodyKind::Rpp, vec![-0.1, 0.1, -2.0, 2.0, -2.0, 2.0]),
        (BodyKind::Rpp, vec![0.25, 0.3, -2.0, 2.0, -2.0, 2.0]),
        // Bodies the lanes cannot cast, cutting visible surfaces: a ring
        // groove in the cube's top, a general cone through the ball.
        (BodyKind::Tor, vec![0.0, 0.0, 0.5, 0.0, 0.0, 1.0, 0.3, 0.12]),
        (
            BodyKind::Tgc,
            vec![
                -1.0, 0.1, 0.0, 2.0, 0.0, 0.0, 0.0, 0.3, 0.0, 0.0, 0.0, 0.2, 0.1, 0.3,
            ],
        ),
    ];
    for (i, (kind, params)) in edge.into_iter().enumerate() {
        g.bodies.push(Body::new(format!("e{i}"), kind, params));
    }
    let (cube, flush, half, cone, cup, cyl, ball) = (5, n, n + 1, n + 2, n + 3, n + 4, n + 5);
    let (low, high, slab, slab2, ring, tgc) = (n + 6, n + 7, n + 8, n + 9, n + 10, n + 11);
    let zone = |plus: &[usize], minus: &[usize]| Zone {
        terms: plus
            .iter()
            .map(|&body| Term {
                op: Op::Inside,
                body,
            })
            .chain(minus.iter().map(|&body| Term {
                op: Op::Outside,
                body,
            }))
            .collect(),
    };
    let made = [
        zone(&[cube, flush], &[]),
        zone(&[cube], &[flush]),
        zone(&[cube], &[half]),
        zone(&[cube, half], &[]),
        zone(&[cube], &[cube]),
        zone(&[cone], &[]),
        zone(&[cup], &[cyl]),
        zone(&[cyl], &[ball]),
        zone(&[ball], &[cyl]),
        zone(&[cube], &[cone, ball]),
        zone(&[cube], &[low]),
        zone(&[cube], &[high]),
        zone(&[cube, low], &[]),
        zone(&[low], &[half]),
        zone(&[cube], &[high, low]),
        zone(&[cube], &[slab]),
        zone(&[cube], &[slab, half]),
        zone(&[cube], &[slab, slab2]),
        zone(&[cube], &[slab, slab2, half]),
        zone(&[ball], &[slab, cyl]),
        zone(&[cube], &[ring]),
        zone(&[ball], &[tgc]),
        zone(&[cube], &[slab, ring]),
    ];
    let count = made.len();
    for (r, z) in made.into_iter().enumerate() {
        if only.is_none_or(|i| i % count == r) {
            g.regions.push(Region {
                name: format!("m{r}"),
                zones: vec![z],
            });
        }
    }
    if made_only {
        return g;
    }
    for r in 0..60 {
        let zones = (0..1 + usize::from(r % 7 == 0))
            .map(|_| {
                let plus: Vec<usize> = (0..1 + usize::from(rng.gen_bool(0.3)))
                    .map(|_| rng.gen_range(0..n))
                    .collect();
                let minus: Vec<usize> = (0..rng.gen_range(0..4))
                    .map(|_| rng.gen_range(0..n))
                    .collect();
                zone(&plus, &minus)
            })
            .collect();
        g.regions.push(Region {
            name: format!("r{r}"),
            zones,
        });
    }
    g
}

/// Rays for one batch: a pinhole's from one eye, or an orthographic
/// view's; some along the axes from points on the faces of the boxes
/// (rays in face planes, infinite reciprocals), some along a
/// generator of the cones.
fn rays(rng: &mut impl Rng, batch: usize) -> (Vec<Ray>, DVec3, Option<DVec3>) {
    let mut u = |a: f64| rng.gen_range(-a..a);
    let eye = DVec3::new(u(3.0), u(3.0), u(3.0));
    let on_face = [-0.5, 0.0, 0.5, 1.5];
    let axis = [DVec3::X, DVec3::Y, DVec3::Z, -DVec3::Z][batch % 4];
    let rays: Vec<Ray> = match batch % 5 {
        // Parallel rays along an axis, from points on the boxes' faces.
        0 => (0..37)
            .map(|i| {
                let mut p = DVec3::new(on_face[i % 4], on_face[(i / 4) % 4], on_face[(i / 3) % 4]);
                if i % 5 == 4 {
                    p += DVec3::new(u(0.7), u(0.7), u(0.7));
                }
                // Through the boxes' edges, entering two faces at once.
                if i % 5 == 3 {
                    let c = on_face[i % 4];
                    let diagonal = [DVec3::new(1.0, 1.0, 0.0), DVec3::ONE][i % 2];
                    return Ray::new(DVec3::new(c, c, c * diagonal.z) - diagonal * 2.0, diagonal);
                }
                // On the plane 4 behind the origin.
                Ray::new(p - axis * (axis.dot(p) + 4.0), axis)
            })
            .collect(),
        // Along the generators of the two cones, x = ±0.4 per 2 up.
        1 => (0..37)
            .map(|i| {
                let dir = DVec3::new(if i % 2 == 0 { -0.4 } else { 0.4 }, 0.0, 2.0);
                let o = DVec3::new(u(0.8), u(0.8), -3.0);
                Ray::new(o, dir)
            })
            .collect(),
        2 => {
            let view = (DVec3::ZERO - eye).normalize();
            (0..37)
                .map(|_| {
                    let j = DVec3::new(u(1.0), u(1.0), u(1.0));
                    Ray::new(eye + (j - view * j.dot(view)) * 1.5, view)
                })
                .collect()
        }
        _ => {
            let view = (DVec3::ZERO - eye).normalize();
            (0..37)
                .map(|_| Ray::new(eye, view + DVec3::new(u(0.6), u(0.6), u(0.6))))
                .collect()
        }
    };
    // An orthographic view's entry bounds are measured from the plane of
    // its rays' origins.
    let ortho = batch % 5 < 3;
    let dir = rays[0].dir;
    let eye = if ortho { rays[0].origin } else { eye };
    (rays, eye, ortho.then_some(dir))
}

/// One way of tracing a batch of rays into a list of hits.
type Tracer<'a> = dyn FnMut(&mut [(u32, Hit)]) -> usize + 'a;

/// Bit-for-bit equality of two hit lists.
fn same(a: &[(u32, Hit)], b: &[(u32, Hit)]) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|((ka, x), (kb, y))| {
            ka == kb
                && x.t.to_bits() == y.t.to_bits()
                && x.bound.t.to_bits() == y.bound.t.to_bits()
                && x.bound.body == y.bound.body
                && x.bound.face_flip() == y.bound.face_flip()
                && (x.region, x.zone, x.inside) == (y.region, y.zone, y.inside)
        })
}

#[test]
fn packets_find_the_hits_of_rays_traced_one_by_one() {
    let mut rng = rand_pcg::Pcg64::seed_from_u64(5);
    let (mut lanes_zones, mut other_zones, mut hits, mut rays_cast) = (0, 0, 0, 0);
    for i in 0..31 {
        let g = geometry(&mut rng, i % 2 == 0 || i >= 8, (i >= 8).then(|| i - 8));
        let p = Prepared::new(&g, &PrepareOptions::default()).unwrap().0;
        lanes_zones += p.zones.iter().filter(|z| z.lanes).count();
        other_zones += p.zones.iter().filter(|z| !z.lanes).count();
        let all: Vec<u32> = (0..p.zones.len() as u32).collect();
        let mut s = Scratch::new(&p);
        let (mut sorted, mut one, mut many) = (Vec::new(), Vec::new(), Vec::new());
        for batch in 0..100 {
            let (rays, eye, parallel) = rays(&mut rng, batch);
            // The rays along the axes, through edges and along the
            // generators share no plane of origins: their list is every
            // zone from the lowest entry.
            if batch % 5 < 2 {
                sorted.clear();
                sorted.extend(all.iter().map(|&z| (f64::NEG_INFINITY, z)));
            } else {
                p.by_distance(&all, eye, parallel, &mut sorted);
            }
            let tmin = if batch % 7 == 3 { 0.5 } else { 0.0 };
            one.clear();
            one.resize(rays.len(), (0, Hit::NONE));
            let n = p.hits_one_by_one(&sorted, &rays, tmin, f64::INFINITY, &mut s, &mut one);
            one.truncate(n);
            hits += n;
            rays_cast += rays.len();
            // Every way of tracing them: the tile's list and the
            // hierarchy, ray by ray and in packets of every width.
            let inf = f64::INFINITY;
            let mut check = |how: &str, trace: &mut Tracer| {
                many.clear();
                many.resize(rays.len(), (0, Hit::NONE));
                let m = trace(&mut many);
                assert!(same(&one, &many[..m]), "{how}, batch {batch}");
            };
            check("list, four portable lanes", &mut |o| {
                p.rays_in_packets(Portable::<4>, Some(&sorted), &rays, tmin, inf, &mut s, o)
            });
            check("list, eight portable lanes", &mut |o| {
                p.rays_in_packets(Portable::<8>, Some(&sorted), &rays, tmin, inf, &mut s, o)
            });
            check("walk, ray by ray", &mut |o| {
                p.walk_one_by_one(&rays, tmin, inf, &mut s, o)
            });
            check("walk, four portable lanes", &mut |o| {
                p.rays_in_packets(Portable::<4>, None, &rays, tmin, inf, &mut s, o)
            });
            check("walk, eight portable lanes", &mut |o| {
                p.rays_in_packets(Portable::<8>, None, &rays, tmin, inf, &mut s, o)
            });
            #[cfg(target_arch = "x86_64")]
            {
                // SAFETY (all four): the tokens prove the instructions
                // are there.
                if let Some(t) = sv_math::simd::Avx512::detect() {
                    check("list, AVX-512", &mut |o| unsafe {
                        rays_avx512(&p, t, Some(&sorted), &rays, tmin, inf, &mut s, o)
                    });
                    check("walk, AVX-512", &mut |o| unsafe {
                        rays_avx512(&p, t, None, &rays, tmin, inf, &mut s, o)
                    });
                }
                if let Some(t) = sv_math::simd::Avx2::detect() {
                    check("list, AVX2", &mut |o| unsafe {
                        rays_avx2(&p, t, Some(&sorted), &rays, tmin, inf, &mut s, o)
                    });
                    check("walk, AVX2", &mut |o| unsafe {
                        rays_avx2(&p, t, None, &rays, tmin, inf, &mut s, o)
                    });
                }
            }
        }
    }
    // Zones in lanes and zones left to the scalar code were both met,
    // and many rays hit.
    assert!(
        lanes_zones > 100 && other_zones > 20,
        "{lanes_zones} {other_zones}"
    );
    assert!(hits * 4 > rays_cast, "{hits} of {rays_cast}");
}

#[test]
fn shadow_packets_agree_with_shadow_rays_one_by_one() {
    let mut rng = rand_pcg::Pcg64::seed_from_u64(9);
    let (mut blocked, mut tested) = (0, 0);
    for i in 0..8 {
        let g = geometry(&mut rng, i % 2 == 0, None);
        let p = Prepared::new(&g, &PrepareOptions::default()).unwrap().0;
        let all: Vec<u32> = (0..p.zones.len() as u32).collect();
        let mut s = Scratch::new(&p);
        let (mut sorted, mut hits, mut one, mut many) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for batch in 0..40 {
            // Points on surfaces (with the zones their shadow rays
            // skip), from the first hits of a batch of rays, and a few
            // points in the open.
            let (rays, eye, parallel) = rays(&mut rng, batch + 2);
            p.by_distance(&all, eye, parallel, &mut sorted);
            hits.clear();
            hits.resize(rays.len(), (0, Hit::NONE));
            let n = p.hits_one_by_one(&sorted, &rays, 0.0, f64::INFINITY, &mut s, &mut hits);
            let mut from: Vec<(DVec3, Option<u32>)> = hits[..n]
                .iter()
                .map(|(k, h)| (rays[*k as usize].at(h.t), p.shadow_skip(h)))
                .collect();
            from.extend((0..5).map(|_| {
                (
                    DVec3::new(
                        rng.gen_range(-1.5..1.5),
                        rng.gen_range(-1.5..1.5),
                        rng.gen_range(-1.5..1.5),
                    ),
                    None,
                )
            }));
            // Origins that are not numbers or lie at infinity, and one far
            // off the light buffer's grid.
            from.extend([
                (DVec3::new(f64::NAN, 0.1, 0.2), None),
                (DVec3::new(0.3, f64::INFINITY, -0.2), None),
                (DVec3::new(f64::NEG_INFINITY, 0.0, 0.0), None),
                (DVec3::splat(1e30), None),
            ]);
            // The sun along an axis now and then: shadow rays in face
            // planes, infinite reciprocals.
            let toward = if batch % 4 == 0 {
                [DVec3::X, DVec3::Y, DVec3::Z, -DVec3::Z][batch / 4 % 4]
            } else {
                DVec3::new(
                    rng.gen_range(-1.0..1.0),
                    rng.gen_range(-1.0..1.0),
                    rng.gen_range(-1.0..1.0),
                )
            };
            let lb = LightBuffer::new(&p, toward);
            let tmin = 10.0 * p.tol;
            let mut last = None;
            one.clear();
            one.extend(from.iter().map(|&(o, skip)| {
                p.occluded_by(
                    &lb,
                    &lb.shadow_ray(o),
                    tmin,
                    f64::INFINITY,
                    skip,
                    &mut last,
                    &mut s,
                )
            }));
            blocked += one.iter().filter(|&&b| b).count();
            tested += one.len();
            // Each path starts from the wrong answers: one that leaves a
            // ray alone fails.
            let wrong = |many: &mut Vec<bool>| {
                many.clear();
                many.extend(one.iter().map(|b| !b));
            };
            wrong(&mut many);
            p.occluded_in_packets(
                Portable::<4>,
                &lb,
                &from,
                tmin,
                &mut last,
                &mut s,
                &mut many,
            );
            assert_eq!(one, many, "four portable lanes, batch {batch}");
            wrong(&mut many);
            p.occluded_in_packets(
                Portable::<8>,
                &lb,
                &from,
                tmin,
                &mut last,
                &mut s,
                &mut many,
            );
            assert_eq!(one, many, "eight portable lanes, batch {batch}");
            #[cfg(target_arch = "x86_64")]
            {
                if let Some(t) = sv_math::simd::Avx512::detect() {
                    wrong(&mut many);
                    // SAFETY: the token proves the instructions are there.
                    unsafe {
                        occluded_avx512(&p, t, &lb, &from, tmin, &mut last, &mut s, &mut many)
                    };
                    assert_eq!(one, many, "AVX-512, batch {batch}");
                }
                if let Some(t) = sv_math::simd::Avx2::detect() {
                    wrong(&mut many);
                    // SAFETY: as above.
                    unsafe { occluded_avx2(&p, t, &lb, &from, tmin, &mut last, &mut s, &mut many) };
                    assert_eq!(one, many, "AVX2, batch {batch}");
                }
            }
        }
    }
    // Both answers were common.
    assert!(
        blocked * 5 > tested && blocked * 5 < 4 * tested,
        "{blocked} of {tested}"
    );
}

/// Surfaces of subtracted bodies in view: a cube with a ball cut from its
/// corner, a tube, a box with a slot.
fn hollows() -> Geometry {
    let bodies: [(BodyKind, Vec<f64>); 6] = [
        (BodyKind::Rpp, vec![-0.5, 0.5, -0.5, 0.5, -0.5, 0.5]),
        (BodyKind::Sph, vec![0.5, 0.5, 0.5, 0.6]),
        (BodyKind::Rcc, vec![-0.8, 0.0, 0.0, 1.0, 0.0, 0.0, 0.4]),
        (BodyKind::Rcc, vec![-0.9, 0.0, 0.0, 1.2, 0.0, 0.0, 0.3]),
        (BodyKind::Rpp, vec![0.2, 0.9, -0.9, 0.9, -0.2, 0.2]),
        (
            BodyKind::Box,
            vec![0.4, -0.1, -0.5, 0.3, 0.0, 0.0, 0.0, 0.2, 0.0, 0.0, 0.0, 1.0],
        ),
    ];
    let mut g = Geometry::default();
    for (i, (kind, params)) in bodies.into_iter().enumerate() {
        g.bodies.push(Body::new(format!("h{i}"), kind, params));
    }
    for (r, (plus, minus)) in [(0, 1), (2, 3), (4, 5)].into_iter().enumerate() {
        g.regions.push(Region {
            name: format!("hollow{r}"),
            zones: vec![Zone {
                terms: vec![
                    Term {
                        op: Op::Inside,
                        body: plus,
                    },
                    Term {
                        op: Op::Outside,
                        body: minus,
                    },
                ],
            }],
        });
    }
    g
}

/// What a tile's tracing gives: hits, their rays and their normals.
struct Traced {
    hits: Vec<(u32, Hit)>,
    rays: Vec<Ray>,
    normals: Vec<DVec3>,
}

impl Traced {
    fn new(n: usize) -> Traced {
        Traced {
            hits: vec![(0, Hit::NONE); n],
            rays: vec![Ray::new(DVec3::ZERO, DVec3::Z); n],
            normals: vec![DVec3::ZERO; n],
        }
    }

    /// The first `n`, in the order of the pixels.
    fn sorted(&self, n: usize) -> Traced {
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by_key(|&i| self.hits[i].0);
        Traced {
            hits: order.iter().map(|&i| self.hits[i]).collect(),
            rays: order.iter().map(|&i| self.rays[i]).collect(),
            normals: order.iter().map(|&i| self.normals[i]).collect(),
        }
    }
}

/// Bit-for-bit equality of vectors.
fn same_bits(a: &[DVec3], b: &[DVec3]) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|(x, y)| {
            x.to_array()
                .iter()
                .zip(y.to_array())
                .all(|(u, v)| u.to_bits() == v.to_bits())
        })
}

#[test]
fn tiles_of_the_raster_find_the_hits_rays_and_normals_of_pixels_traced_one_by_one() {
    let mut rng = rand_pcg::Pcg64::seed_from_u64(21);
    let (mut hits_seen, mut pixels) = (0, 0);
    let inf = f64::INFINITY;
    for i in 0..6 {
        let g = if i < 4 {
            geometry(&mut rng, i % 2 == 0, None)
        } else {
            hollows()
        };
        let p = Prepared::new(&g, &PrepareOptions::default()).unwrap().0;
        let all: Vec<u32> = (0..p.zones.len() as u32).collect();
        let mut s = Scratch::new(&p);
        let mut sorted = Vec::new();
        for view in 0..12 {
            // A camera from outside the model or inside it, perspective or
            // orthographic, on a raster whose tiles end short at the edges.
            let eye = DVec3::new(
                rng.gen_range(-3.0..3.0),
                rng.gen_range(-3.0..3.0),
                rng.gen_range(-3.0..3.0),
            );
            let forward = (DVec3::new(0.1, -0.2, 0.05) - eye).normalize();
            let (r, u) = sv_math::orthonormal_basis(forward);
            let ortho = view % 3 == 0;
            let half = if ortho { 1.5 } else { 0.6 };
            let gen = RayGen::new(eye, r * half * 1.2, u * half, forward, ortho, 37, 29);
            p.by_distance(&all, eye, ortho.then_some(forward), &mut sorted);
            let tile = |x0, x1, y0, y1| Tile { x0, x1, y0, y1 };
            for tile in [
                tile(0, 16, 0, 16),
                tile(32, 37, 16, 29),
                tile(16, 32, 27, 29),
                tile(3, 4, 5, 6),
            ] {
                for zones in [Some(&sorted[..]), None] {
                    let mut want = Traced::new(tile.len());
                    let n = p.tile_one_by_one(
                        &gen,
                        tile,
                        zones,
                        0.0,
                        inf,
                        &mut s,
                        &mut want.hits,
                        &mut want.rays,
                        &mut want.normals,
                    );
                    let want = want.sorted(n);
                    hits_seen += n;
                    pixels += tile.len();
                    // Each hit's ray is `gen.ray` through its pixel's centre,
                    // and its normal the scalar tracer's.
                    for (((k, h), ray), normal) in
                        want.hits.iter().zip(&want.rays).zip(&want.normals)
                    {
                        let w = tile.x1 - tile.x0;
                        let (x, y) = (tile.x0 + *k as usize % w, tile.y0 + *k as usize / w);
                        assert_eq!(*ray, gen.ray(x as f64 + 0.5, y as f64 + 0.5));
                        assert!(same_bits(&[*normal], &[p.normal(h, ray)]));
                    }
                    let check = |how: &str, got: &Traced, m: usize| {
                        let got = got.sorted(m);
                        assert!(same(&want.hits, &got.hits), "{how}, view {view}, {tile:?}");
                        let (a, b): (Vec<f64>, Vec<f64>) = (
                            Ray::coordinates(&want.rays).to_vec(),
                            Ray::coordinates(&got.rays).to_vec(),
                        );
                        assert!(
                            a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits()),
                            "{how} rays, view {view}, {tile:?}"
                        );
                        assert!(
                            same_bits(&want.normals, &got.normals),
                            "{how} normals, view {view}, {tile:?}"
                        );
                    };
                    // Each path into fresh buffers: none sees another's.
                    let mut got = Traced::new(tile.len());
                    let m = p.tile_in_packets(
                        Portable::<4>,
                        &gen,
                        tile,
                        zones,
                        0.0,
                        inf,
                        &mut s,
                        &mut got.hits,
                        &mut got.rays,
                        &mut got.normals,
                    );
                    check("four portable lanes", &got, m);
                    let mut got = Traced::new(tile.len());
                    let m = p.tile_in_packets(
                        Portable::<8>,
                        &gen,
                        tile,
                        zones,
                        0.0,
                        inf,
                        &mut s,
                        &mut got.hits,
                        &mut got.rays,
                        &mut got.normals,
                    );
                    check("eight portable lanes", &got, m);
                    #[cfg(target_arch = "x86_64")]
                    {
                        // SAFETY (both): the tokens prove the instructions
                        // are there.
                        if let Some(t) = sv_math::simd::Avx512::detect() {
                            let mut got = Traced::new(tile.len());
                            let m = unsafe {
                                tile_avx512(
                                    &p,
                                    t,
                                    &gen,
                                    tile,
                                    zones,
                                    0.0,
                                    inf,
                                    &mut s,
                                    &mut got.hits,
                                    &mut got.rays,
                                    &mut got.normals,
                                )
                            };
                            check("AVX-512", &got, m);
                        }
                        if let Some(t) = sv_math::simd::Avx2::detect() {
                            let mut got = Traced::new(tile.len());
                            let m = unsafe {
                                tile_avx2(
                                    &p,
                                    t,
                                    &gen,
                                    tile,
                                    zones,
                                    0.0,
                                    inf,
                                    &mut s,
                                    &mut got.hits,
                                    &mut got.rays,
                                    &mut got.normals,
                                )
                            };
                            check("AVX2", &got, m);
                        }
                    }
                }
            }
        }
    }
    assert!(
        hits_seen * 5 > pixels,
        "{hits_seen} hits of {pixels} pixels"
    );
}

#[test]
fn the_public_calls_answer_as_the_rays_one_by_one_with_packets_or_without() {
    // Whatever lanes this processor has: each call as the renderer makes
    // it, against the same geometry with packets turned off.
    let mut rng = rand_pcg::Pcg64::seed_from_u64(33);
    let inf = f64::INFINITY;
    let (mut hits_seen, mut blocked) = (0, 0);
    for i in 0..6 {
        let g = geometry(&mut rng, i % 2 == 0, None);
        let with = Prepared::new(&g, &PrepareOptions::default()).unwrap().0;
        let mut without = with.clone();
        without.packets = false;
        let all: Vec<u32> = (0..with.zones.len() as u32).collect();
        let mut s = Scratch::new(&with);
        let mut sorted = Vec::new();
        let (mut a, mut b) = (Traced::new(0), Traced::new(0));
        for batch in 0..30 {
            let (rays, eye, parallel) = rays(&mut rng, batch);
            if batch % 5 < 2 {
                sorted.clear();
                sorted.extend(all.iter().map(|&z| (f64::NEG_INFINITY, z)));
            } else {
                with.by_distance(&all, eye, parallel, &mut sorted);
            }
            let n = with.first_hits_in(&sorted, &rays, 0.0, inf, &mut s, &mut a.hits);
            let m = without.first_hits_in(&sorted, &rays, 0.0, inf, &mut s, &mut b.hits);
            assert!(same(&a.hits[..n], &b.hits[..m]), "list, batch {batch}");
            let n = with.first_hits(&rays, 0.0, inf, &mut s, &mut a.hits);
            let m = without.first_hits(&rays, 0.0, inf, &mut s, &mut b.hits);
            assert!(same(&a.hits[..n], &b.hits[..m]), "walk, batch {batch}");
            hits_seen += n;

            let from: Vec<(DVec3, Option<u32>)> = b.hits[..m]
                .iter()
                .map(|(k, h)| (rays[*k as usize].at(h.t), with.shadow_skip(h)))
                .collect();
            let lb = LightBuffer::new(&with, DVec3::new(0.3, -0.5, 0.8));
            let (mut x, mut y) = (Vec::new(), Vec::new());
            let tmin = 10.0 * with.tol;
            with.occluded_toward(&lb, &from, tmin, &mut None, &mut s, &mut x);
            without.occluded_toward(&lb, &from, tmin, &mut None, &mut s, &mut y);
            assert_eq!(x, y, "shadows, batch {batch}");
            blocked += x.iter().filter(|&&b| b).count();

            let forward = (DVec3::new(0.1, -0.2, 0.05) - eye).normalize();
            let (r, u) = sv_math::orthonormal_basis(forward);
            let ortho = batch % 2 == 0;
            let gen = RayGen::new(eye, r * 1.2, u, forward, ortho, 21, 19);
            let tile = Tile {
                x0: 3,
                x1: 21,
                y0: 2,
                y1: 19,
            };
            for zones in [Some(&sorted[..]), None] {
                let n = with.tile_hits(
                    &gen,
                    tile,
                    zones,
                    0.0,
                    inf,
                    &mut s,
                    &mut a.hits,
                    &mut a.rays,
                    &mut a.normals,
                );
                let m = without.tile_hits(
                    &gen,
                    tile,
                    zones,
                    0.0,
                    inf,
                    &mut s,
                    &mut b.hits,
                    &mut b.rays,
                    &mut b.normals,
                );
                let (x, y) = (a.sorted(n), b.sorted(m));
                assert!(same(&x.hits, &y.hits), "tile, batch {batch}");
                assert!(
                    same_bits(&x.normals, &y.normals),
                    "tile normals, batch {batch}"
                );
                assert!(
                    x.rays.iter().zip(&y.rays).all(|(p, q)| same_bits(
                        &[p.origin, p.dir, p.inv_dir],
                        &[q.origin, q.dir, q.inv_dir]
                    )),
                    "tile rays, batch {batch}"
                );
            }
        }
    }
    assert!(
        hits_seen > 1000 && blocked > 100,
        "{hits_seen} hits, {blocked} blocked"
    );
}
