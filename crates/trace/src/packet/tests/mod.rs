//! The packet tracer against the rays traced one by one: every path, every
//! lane width, bit for bit.

mod partitions;
mod primary;
mod shadow;
mod tiles;

use super::partitions::*;
use super::primary::*;
use super::shadow::*;
use super::*;
use crate::LightBuffer;
use rand::Rng;
use sv_geom::{Body, BodyKind, Geometry, Group, Op, Region, Term, Zone};
use sv_math::simd::Portable;
use sv_math::{DVec3, RayGen};

/// Bodies of every kind the lanes cast, about the origin, and a few
/// they do not (a torus, a general cone), with flush faces among them.
pub(super) fn bodies(rng: &mut impl Rng) -> Vec<Body> {
    let mut out = Vec::new();
    let v = |r: &mut dyn FnMut() -> f64| [r(), r(), r()];
    for i in 0..54 {
        let mut u = || rng.gen_range(-1.0..1.0);
        let p = v(&mut u);
        let (kind, params): (BodyKind, Vec<f64>) = match i % 18 {
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
            16 => (BodyKind::Ars, bipyramid(DVec3::from(p), 0.5)),
            17 => (BodyKind::Ars, star_spindle(DVec3::from(p), 0.6)),
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

/// An ARS's parameters from its curves (each of the same number of
/// points).
fn ars(curves: &[Vec<DVec3>]) -> Vec<f64> {
    let mut params = vec![curves.len() as f64, curves[0].len() as f64];
    params.extend(curves.iter().flatten().flat_map(|q| q.to_array()));
    params
}

/// A convex ARS: a triangle between two apexes (curves of one point
/// repeated), as the COMGEOM test deck has.
fn bipyramid(c: DVec3, r: f64) -> Vec<f64> {
    let apex = |z: f64| vec![c + DVec3::new(0.0, 0.0, z); 3];
    let ring = vec![
        c + DVec3::new(-r, -r, 0.0),
        c + DVec3::new(r, -r, 0.1 * r),
        c + DVec3::new(r, r, -0.1 * r),
    ];
    ars(&[apex(-1.5 * r), ring, apex(2.0 * r)])
}

/// A non-convex ARS: two six-pointed stars, one narrower, between two
/// apexes (rays cross it four times or more).
fn star_spindle(c: DVec3, r: f64) -> Vec<f64> {
    let star = |z: f64, scale: f64| -> Vec<DVec3> {
        (0..6)
            .map(|k| {
                let angle = k as f64 * std::f64::consts::FRAC_PI_3;
                let radius = if k % 2 == 0 { r } else { 0.35 * r } * scale;
                c + DVec3::new(radius * angle.cos(), radius * angle.sin(), z)
            })
            .collect()
    };
    let apex = |z: f64| vec![c + DVec3::new(0.0, 0.0, z); 6];
    ars(&[apex(-r), star(-0.3 * r, 1.0), star(0.3 * r, 0.6), apex(r)])
}

/// Zones of random bodies, or zones made to sit on the tolerances
/// (apart, so that the random ones do not hide them; `only` one of them,
/// so that none hides another): `+` and `-` bodies flush with each other,
/// a body less itself, cones whose generators the rays below run along,
/// slabs that cut a span into two or three.
pub(super) fn geometry(rng: &mut impl Rng, made_only: bool, only: Option<usize>) -> Geometry {
    let mut g = Geometry {
        bodies: bodies(rng),
        ..Default::default()
    };
    let n = g.bodies.len();
    let edge: [(BodyKind, Vec<f64>); 14] = [
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
        // Faceted solids flush with the cube: an L-shaped prism (not
        // convex), and a star less the cube.
        (
            BodyKind::Ars,
            ars(&[-0.5, 0.5].map(|z| {
                [
                    (-0.5, -0.5),
                    (0.5, -0.5),
                    (0.5, 0.0),
                    (0.0, 0.0),
                    (0.0, 0.5),
                    (-0.5, 0.5),
                ]
                .map(|(x, y)| DVec3::new(x, y, z))
                .to_vec()
            })),
        ),
        (BodyKind::Ars, star_spindle(DVec3::new(0.3, 0.0, 0.5), 0.7)),
    ];
    for (i, (kind, params)) in edge.into_iter().enumerate() {
        g.bodies.push(Body::new(format!("e{i}"), kind, params));
    }
    let (cube, flush, half, cone, cup, cyl, ball) = (5, n, n + 1, n + 2, n + 3, n + 4, n + 5);
    let (low, high, slab, slab2, ring, tgc) = (n + 6, n + 7, n + 8, n + 9, n + 10, n + 11);
    let (ell, star) = (n + 12, n + 13);
    let zone = |plus: &[usize], minus: &[usize]| {
        Zone::new(
            plus.iter()
                .map(|&body| Term {
                    op: Op::Inside,
                    body,
                })
                .chain(minus.iter().map(|&body| Term {
                    op: Op::Outside,
                    body,
                }))
                .collect(),
        )
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
        zone(&[ell], &[]),
        zone(&[cube], &[ell]),
        zone(&[cube, ell], &[slab]),
        zone(&[star], &[cube]),
        zone(&[cube], &[star, ball]),
        zone(&[ball, star], &[]),
        // Groups: the cube less the union of the ball and the slab; the
        // ball and the cube's low half, whichever is nearer.
        Zone {
            groups: vec![Group {
                op: Op::Outside,
                zones: vec![zone(&[ball], &[]), zone(&[slab], &[])],
            }],
            ..zone(&[cube], &[])
        },
        Zone {
            groups: vec![Group {
                op: Op::Inside,
                zones: vec![zone(&[ball], &[ring]), zone(&[low], &[])],
            }],
            ..zone(&[], &[cyl])
        },
    ];
    let count = made.len();
    for (r, z) in made.into_iter().enumerate() {
        if only.is_none_or(|i| i % count == r) {
            g.regions.push(Region::new(format!("m{r}"), vec![z]));
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
        g.regions.push(Region::new(format!("r{r}"), zones));
    }
    g
}

/// Rays for one batch: a pinhole's from one eye, or an orthographic
/// view's; some along the axes from points on the faces of the boxes
/// (rays in face planes, infinite reciprocals), some along a
/// generator of the cones.
pub(super) fn rays(rng: &mut impl Rng, batch: usize) -> (Vec<Ray>, DVec3, Option<DVec3>) {
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
pub(super) type Tracer<'a> = dyn FnMut(&mut [(u32, Hit)]) -> usize + 'a;

/// Bit-for-bit equality of two hit lists.
pub(super) fn same(a: &[(u32, Hit)], b: &[(u32, Hit)]) -> bool {
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

/// Surfaces of subtracted bodies in view: a cube with a ball cut from its
/// corner, a tube, a box with a slot.
pub(super) fn hollows() -> Geometry {
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
        g.regions.push(Region::new(
            format!("hollow{r}"),
            vec![Zone::new(vec![
                Term {
                    op: Op::Inside,
                    body: plus,
                },
                Term {
                    op: Op::Outside,
                    body: minus,
                },
            ])],
        ));
    }
    g
}

/// What a tile's tracing gives: hits, their rays and their normals.
pub(super) struct Traced {
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
pub(super) fn same_bits(a: &[DVec3], b: &[DVec3]) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|(x, y)| {
            x.to_array()
                .iter()
                .zip(y.to_array())
                .all(|(u, v)| u.to_bits() == v.to_bits())
        })
}

/// Shadow rays from `from` toward the light of `lb` tested by every packet
/// path this processor has, each path's answers starting from `wrong`.
pub(super) fn shadow_paths(
    p: &Prepared,
    lb: &LightBuffer,
    from: &[(DVec3, Option<u32>)],
    tmin: f64,
    s: &mut Scratch,
    wrong: &[bool],
) -> Vec<(&'static str, Vec<bool>)> {
    let mut last = None;
    let mut out = Vec::new();
    let mut answers = wrong.to_vec();
    p.occluded_in_packets(Portable::<4>, lb, from, tmin, &mut last, s, &mut answers);
    out.push(("four portable lanes", answers));
    let mut answers = wrong.to_vec();
    p.occluded_in_packets(Portable::<8>, lb, from, tmin, &mut last, s, &mut answers);
    out.push(("eight portable lanes", answers));
    #[cfg(target_arch = "x86_64")]
    {
        if let Some(t) = sv_math::simd::Avx512::detect() {
            let mut answers = wrong.to_vec();
            // SAFETY: the token proves the instructions are there.
            unsafe { occluded_avx512(p, t, lb, from, tmin, &mut last, s, &mut answers) };
            out.push(("AVX-512", answers));
        }
        if let Some(t) = sv_math::simd::Avx2::detect() {
            let mut answers = wrong.to_vec();
            // SAFETY: as above.
            unsafe { occluded_avx2(p, t, lb, from, tmin, &mut last, s, &mut answers) };
            out.push(("AVX2", answers));
        }
    }
    out
}

/// A tile traced by every packet path this processor has, each into fresh
/// buffers: the path, what it gave and how many hits.
pub(super) fn tile_paths(
    p: &Prepared,
    gen: &RayGen,
    tile: Tile,
    zones: Option<&[(f64, u32)]>,
    s: &mut Scratch,
) -> Vec<(&'static str, Traced, usize)> {
    let fresh = || Traced::new(tile.len());
    each_tile_path(p, gen, tile, zones, s, fresh, |t| {
        PacketOut::Hits(&mut t.hits, Some((&mut t.rays, &mut t.normals)))
    })
}

/// As [`tile_paths`], for how each pixel faces its ray
/// ([`Prepared::tile_facing`]), every place first [`FACING_MISS`].
pub(super) fn facing_paths(
    p: &Prepared,
    gen: &RayGen,
    tile: Tile,
    zones: Option<&[(f64, u32)]>,
    s: &mut Scratch,
) -> Vec<(&'static str, Vec<f64>, usize)> {
    let fresh = || vec![FACING_MISS; tile.len()];
    each_tile_path(p, gen, tile, zones, s, fresh, |f| PacketOut::Facing(f))
}

/// A tile traced by every packet path this processor has, each into what
/// `fresh` makes, written as `out_of` asks.
fn each_tile_path<T>(
    p: &Prepared,
    gen: &RayGen,
    tile: Tile,
    zones: Option<&[(f64, u32)]>,
    s: &mut Scratch,
    fresh: impl Fn() -> T,
    out_of: for<'a> fn(&'a mut T) -> PacketOut<'a>,
) -> Vec<(&'static str, T, usize)> {
    let inf = f64::INFINITY;
    let mut out = Vec::new();
    let mut got = fresh();
    let m = p.tile_in_packets(
        Portable::<4>,
        gen,
        tile,
        zones,
        0.0,
        inf,
        s,
        out_of(&mut got),
    );
    out.push(("four portable lanes", got, m));
    let mut got = fresh();
    let m = p.tile_in_packets(
        Portable::<8>,
        gen,
        tile,
        zones,
        0.0,
        inf,
        s,
        out_of(&mut got),
    );
    out.push(("eight portable lanes", got, m));
    #[cfg(target_arch = "x86_64")]
    {
        // SAFETY (both): the tokens prove the instructions are there.
        if let Some(t) = sv_math::simd::Avx512::detect() {
            let mut got = fresh();
            let m = unsafe { tile_avx512(p, t, gen, tile, zones, 0.0, inf, s, out_of(&mut got)) };
            out.push(("AVX-512", got, m));
        }
        if let Some(t) = sv_math::simd::Avx2::detect() {
            let mut got = fresh();
            let m = unsafe { tile_avx2(p, t, gen, tile, zones, 0.0, inf, s, out_of(&mut got)) };
            out.push(("AVX2", got, m));
        }
    }
    out
}
