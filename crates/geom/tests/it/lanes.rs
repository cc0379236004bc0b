//! The lane forms of the faceted solid (ARS), the torus and the general
//! cone against their scalar forms, ray by ray and bit for bit: random
//! rays, rays along the axes on grids over their bounds, and for the
//! faceted solid rays aimed exactly at its corners and along its edges'
//! midpoints, where crossings of neighbouring triangles tie or merge.

use crate::conformance::{prepare_one, random_ray, samples};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use sv_geom::shape::{Seg, Shape};
use sv_geom::{ars_triangles, Body, BodyKind};
use sv_math::lanes::Lanes;
use sv_math::simd::{Portable, Simd};
use sv_math::{DVec3, Ray};

/// ARS parameters from closed curves of equal length.
fn ars(curves: &[Vec<DVec3>]) -> Body {
    let mut params = vec![curves.len() as f64, curves[0].len() as f64];
    params.extend(curves.iter().flatten().flat_map(|q| q.to_array()));
    Body::new("ars", BodyKind::Ars, params)
}

/// The sample ARS (a convex bipyramid), an L-shaped prism and a star
/// spindle (neither convex).
fn meshes() -> Vec<Body> {
    let mut out: Vec<Body> = samples()
        .into_iter()
        .filter(|b| b.kind == BodyKind::Ars)
        .collect();
    let l_shape = [
        (-1.0, -1.0),
        (1.0, -1.0),
        (1.0, 0.0),
        (0.0, 0.0),
        (0.0, 1.0),
        (-1.0, 1.0),
    ];
    out.push(ars(
        &[-1.0, 1.0].map(|z| l_shape.map(|(x, y)| DVec3::new(x, y, z)).to_vec())
    ));
    let star = |z: f64, scale: f64| -> Vec<DVec3> {
        (0..6)
            .map(|k| {
                let angle = k as f64 * std::f64::consts::FRAC_PI_3;
                let radius = if k % 2 == 0 { 1.0 } else { 0.35 } * scale;
                DVec3::new(radius * angle.cos(), radius * angle.sin(), z)
            })
            .collect()
    };
    let apex = |z: f64| vec![DVec3::new(0.0, 0.0, z); 6];
    out.push(ars(&[
        apex(-1.0),
        star(-0.3, 1.0),
        star(0.3, 0.6),
        apex(1.0),
    ]));
    out
}

/// Rays at the mesh: random ones, and from random points (and along the
/// axes) exactly through each corner and each edge's midpoint.
fn rays(body: &Body, rng: &mut Pcg64) -> Vec<Ray> {
    let (shape, bounds) = prepare_one(body);
    assert!(matches!(shape, Shape::Mesh(_)));
    let mut out: Vec<Ray> = (0..2000).map(|_| random_ray(rng, bounds)).collect();
    // Grids of rays along each axis, in whole packets: every lane of a
    // packet runs along the same axis, as a check's grid rays do.
    for axis in DVec3::AXES {
        let (u, v) = (
            DVec3::new(axis.z, axis.x, axis.y),
            DVec3::new(axis.y, axis.z, axis.x),
        );
        for i in 0..16 {
            for j in 0..16 {
                let (a, b) = ((i as f64 + 0.37) / 16.0, (j as f64 + 0.61) / 16.0);
                let across = bounds.min + (bounds.max - bounds.min) * (u * a + v * b);
                let from = across * (DVec3::ONE - axis) + (bounds.min - DVec3::ONE) * axis;
                out.push(Ray::new(from, axis));
            }
        }
    }
    let reach = bounds.diagonal() * 2.0;
    for [a, b, c] in ars_triangles(body) {
        for target in [a, b, c, (a + b) * 0.5, (b + c) * 0.5, (c + a) * 0.5] {
            let dir = DVec3::new(
                rng.gen_range(-1.0..1.0),
                rng.gen_range(-1.0..1.0),
                rng.gen_range(-1.0..1.0),
            )
            .normalize();
            out.push(Ray::new(target - dir * reach, dir));
            for axis in [DVec3::X, DVec3::Y, DVec3::Z, -DVec3::Z] {
                out.push(Ray::new(target - axis * reach, axis));
            }
        }
    }
    out
}

/// The rays of `chunk` (at most `P`) in `P` portable lanes, the last
/// repeated in the lanes left.
fn lanes_of<const P: usize>(chunk: &[Ray]) -> Lanes<Portable<P>> {
    let ray = |j: usize| chunk[j.min(chunk.len() - 1)];
    Lanes {
        o: [0, 1, 2].map(|c| std::array::from_fn(|j| ray(j).origin[c])),
        d: [0, 1, 2].map(|c| std::array::from_fn(|j| ray(j).dir[c])),
        inv: [0, 1, 2].map(|c| std::array::from_fn(|j| ray(j).inv_dir[c])),
    }
}

/// How many lanes of [`agree`]'s rays had a segment, and how many were
/// left to the scalar code.
#[derive(Debug, PartialEq)]
struct Agreed {
    with_segment: usize,
    left: usize,
}

/// Checks each lane of `Shape::shoot_lanes` for `rays` against the scalar
/// segments: a lane left to the scalar code only where it must or may be,
/// a lane's segment equal bit for bit to the scalar one.
fn agree<const P: usize>(shape: &Shape, rays: &[Ray]) -> Agreed {
    let s = Portable::<P>;
    let (mut with_segment, mut left) = (0, 0);
    for chunk in rays.chunks(P) {
        let got = shape.shoot_lanes(s, &lanes_of(chunk));
        let (hit, scalar) = (s.bits(got.hit), s.bits(got.scalar));
        for (j, r) in chunk.iter().enumerate() {
            let mut segs: Vec<Seg> = Vec::new();
            shape.shoot(r, &mut segs);
            let why = format!("ray {r:?}: scalar {segs:?}");
            assert_eq!(
                hit & scalar & (1 << j),
                0,
                "{why}: a lane both hit and left"
            );
            if scalar & (1 << j) != 0 {
                left += 1;
                continue;
            }
            assert!(
                segs.len() <= 1,
                "{why}: more than one segment, in the lanes"
            );
            assert_eq!(hit & (1 << j) != 0, segs.len() == 1, "{why}: hit or not");
            if let [seg] = segs[..] {
                let lane = (got.t0[j], got.t1[j], got.f0[j], got.f1[j]);
                let want = (seg.t0, seg.t1, f64::from(seg.f0), f64::from(seg.f1));
                assert_eq!(lane.0.to_bits(), want.0.to_bits(), "{why}: entry");
                assert_eq!(lane.1.to_bits(), want.1.to_bits(), "{why}: exit");
                assert_eq!((lane.2, lane.3), (want.2, want.3), "{why}: faces");
                with_segment += 1;
            }
        }
    }
    Agreed { with_segment, left }
}

/// [`agree`] in packets of four and of eight rays, the same rays meeting
/// the shape in both, and more than a tenth of them; what four lanes
/// agreed on.
fn agree_in_four_and_eight_lanes(shape: &Shape, rays: &[Ray]) -> Agreed {
    let (four, eight) = (agree::<4>(shape, rays), agree::<8>(shape, rays));
    assert_eq!(four.with_segment, eight.with_segment);
    assert!(
        four.with_segment > rays.len() / 10,
        "{four:?} of {} rays met it",
        rays.len()
    );
    four
}

#[test]
fn faceted_solids_in_lanes_agree_with_the_scalar_code() {
    let mut rng = Pcg64::seed_from_u64(1971);
    for body in meshes() {
        let rays = rays(&body, &mut rng);
        let shape = prepare_one(&body).0;
        agree_in_four_and_eight_lanes(&shape, &rays);
    }
}

/// A bellows: an ARS of twenty folds between its two apexes, each curve
/// eight points round, of radius 1 and 0.4 in turn. A ray along its axis
/// between the two radii crosses every fold.
fn bellows() -> Body {
    let folds = 20;
    let ring = |z: f64, radius: f64| -> Vec<DVec3> {
        (0..8)
            .map(|k| {
                let angle = k as f64 * std::f64::consts::FRAC_PI_4;
                DVec3::new(radius * angle.cos(), radius * angle.sin(), z)
            })
            .collect()
    };
    let mut curves = vec![ring(-1.0, 0.0)];
    for k in 1..=folds {
        let z = -1.0 + 2.0 * k as f64 / (folds + 1) as f64;
        curves.push(ring(z, if k % 2 == 1 { 1.0 } else { 0.4 }));
    }
    curves.push(ring(1.0, 0.0));
    ars(&curves)
}

#[test]
fn a_mesh_crossed_more_often_than_the_lanes_keep_agrees_too() {
    let body = bellows();
    let shape = prepare_one(&body).0;
    let mut rng = Pcg64::seed_from_u64(1972);
    // Along the axis between the folds' radii, mixed with random rays and
    // rays at the corners: packets whose rays cross more than the 16
    // triangles `Mesh::shoot_lanes` keeps from its first pass.
    let mut rays = rays(&body, &mut rng);
    for k in 0..64 {
        let angle = rng.gen_range(0.0..std::f64::consts::TAU);
        let dir = if k % 2 == 0 { DVec3::Z } else { -DVec3::Z };
        let at = DVec3::new(0.6 * angle.cos(), 0.6 * angle.sin(), 0.0);
        rays.insert(k * 7 % rays.len(), Ray::new(at - dir * 3.0, dir));
    }
    let most = rays
        .iter()
        .map(|r| {
            let mut segs: Vec<Seg> = Vec::new();
            shape.shoot(r, &mut segs);
            segs.len()
        })
        .max()
        .unwrap_or(0);
    // Nine segments: at least eighteen triangles crossed by one ray.
    assert!(most >= 9, "at most {most} segments");
    agree_in_four_and_eight_lanes(&shape, &rays);
}

/// Tori turned to each axis and leaning, fat and thin.
fn tori() -> Vec<Shape> {
    let tor = |c: [f64; 3], n: [f64; 3], r1: f64, r2: f64| {
        let params = [c.as_slice(), n.as_slice(), &[r1, r2]].concat();
        prepare_one(&Body::new("tor", BodyKind::Tor, params)).0
    };
    vec![
        tor([21.5, 0.0, 37.0], [1.0, 0.0, 0.0], 8.0, 1.0),
        tor([0.0, 0.0, 0.0], [0.3015, 0.3015, 0.9045], 5.0, 2.0),
        tor([1.0, -2.0, 0.5], [0.0, 1.0, 0.0], 3.0, 2.5),
        tor([0.0, 0.0, 0.0], [0.0, 0.0, -1.0], 1.0, 0.05),
    ]
}

/// Rays at a body of bounds `bounds`: random ones, and rays along each
/// axis on a grid over the bounds that takes in the planes of its
/// extremes, as a check's grid and its refinement would fire them.
fn grid_rays(bounds: sv_math::Aabb, rng: &mut Pcg64) -> Vec<Ray> {
    let mut out: Vec<Ray> = (0..3000).map(|_| random_ray(rng, bounds)).collect();
    let (lo, size) = (bounds.min, bounds.size());
    for axis in 0..3 {
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        for i in 0..=24 {
            for j in 0..=24 {
                let mut from = lo - DVec3::splat(1.0);
                from[u] = lo[u] + size[u] * i as f64 / 24.0;
                from[v] = lo[v] + size[v] * j as f64 / 24.0;
                let mut dir = DVec3::ZERO;
                dir[axis] = if (i + j) % 2 == 0 { 1.0 } else { -1.0 };
                from[axis] = if dir[axis] > 0.0 {
                    lo[axis] - 1.0
                } else {
                    lo[axis] + size[axis] + 1.0
                };
                out.push(Ray::new(from, dir));
            }
        }
    }
    out
}

/// `Torus::shoot_lanes_both` in packets of `P` rays against the scalar
/// segments, bit for bit; how many lanes have one segment, and how many
/// two.
fn torus_agrees<const P: usize>(shape: &Shape, rays: &[Ray]) -> (usize, usize) {
    let Shape::Torus(torus) = shape else {
        panic!("not a torus: {shape:?}");
    };
    let s = Portable::<P>;
    let mut counts = (0, 0);
    for chunk in rays.chunks(P) {
        let [first, second] = torus.shoot_lanes_both(s, &lanes_of(chunk), s.mask(u32::MAX));
        for (j, r) in chunk.iter().enumerate() {
            let mut segs: Vec<Seg> = Vec::new();
            shape.shoot(r, &mut segs);
            let lane = |g: &sv_geom::shape::SegLanes<Portable<P>>| Seg {
                t0: g.t0[j],
                t1: g.t1[j],
                f0: g.f0[j] as u32,
                f1: g.f1[j] as u32,
            };
            let mut got = Vec::new();
            if s.bits(first.hit) & 1 << j != 0 {
                got.push(lane(&first));
            }
            if s.bits(second.hit) & 1 << j != 0 {
                got.push(lane(&second));
            }
            let bits = |v: &[Seg]| -> Vec<(u64, u64, u32, u32)> {
                v.iter()
                    .map(|g| (g.t0.to_bits(), g.t1.to_bits(), g.f0, g.f1))
                    .collect()
            };
            assert_eq!(bits(&got), bits(&segs), "ray {r:?}: {got:?} for {segs:?}");
            match segs.len() {
                1 => counts.0 += 1,
                2 => counts.1 += 1,
                _ => {}
            }
        }
    }
    counts
}

#[test]
fn tori_in_lanes_agree_with_the_scalar_code() {
    let mut rng = Pcg64::seed_from_u64(1973);
    for shape in tori() {
        let rays = grid_rays(shape.bounds(), &mut rng);
        let (four, eight) = (
            torus_agrees::<4>(&shape, &rays),
            torus_agrees::<8>(&shape, &rays),
        );
        assert_eq!(four, eight);
        // Many rays cross the tube once, and many twice.
        assert!(
            four.0 > rays.len() / 20 && four.1 > rays.len() / 50,
            "{four:?} of {}",
            rays.len()
        );
    }
}

/// General cones (TGCs whose top is not like their base): standing on
/// each axis, one with its top pinched to a line, and one leaning.
fn general_cones() -> Vec<(Shape, bool)> {
    // V, H, A, B, and the top's semi-axes C and D; the first three stand
    // on an axis.
    let cones: [[f64; 14]; 4] = [
        [0., 0., 0., 0., 0., 10., 5., 0., 0., 0., 8., 0., 2.0, 9.0],
        [21.5, 0., 37., 4., 0., 0., 0., 1., 0., 0., 0., 3., 2.5, 0.0],
        [1., -2., 0.5, 0., -6., 0., 0., 0., 2., 3., 0., 0., 0.5, 4.0],
        [0., 0., 0., 3., 2., 9., 2., 0., 0., 0., 3., 0., 1.0, 0.5],
    ];
    (cones.iter().enumerate())
        .map(|(k, params)| {
            let shape = prepare_one(&Body::new("tgc", BodyKind::Tgc, params.to_vec())).0;
            assert!(matches!(shape, Shape::GeneralCone(_)), "{shape:?}");
            (shape, k < 3)
        })
        .collect()
}

#[test]
fn general_cones_in_lanes_agree_with_the_scalar_code() {
    let mut rng = Pcg64::seed_from_u64(1974);
    for (shape, upright) in general_cones() {
        let rays = grid_rays(shape.bounds(), &mut rng);
        let agreed = agree_in_four_and_eight_lanes(&shape, &rays);
        // The 3000 random rays meet it at a slant, and go to the scalar
        // code; a grid's rays through one standing on an axis do not.
        if upright {
            assert_eq!(agreed.left, 3000, "{agreed:?} of {}", rays.len());
        } else {
            assert!(agreed.left >= 3000, "{agreed:?} of {}", rays.len());
        }
    }
}

/// `Shape::normal_lanes` of a general cone, four points at a time, equals
/// its scalar normal to the bit at every point where a ray of
/// [`grid_rays`] enters or leaves it: on both caps and the lateral
/// surface.
#[test]
fn general_cones_normals_in_lanes_agree_with_the_scalar_code() {
    let s = Portable::<4>;
    let mut rng = Pcg64::seed_from_u64(1975);
    for (shape, _) in general_cones() {
        let mut points: Vec<(u32, DVec3)> = Vec::new();
        for ray in grid_rays(shape.bounds(), &mut rng) {
            let mut segs: Vec<Seg> = Vec::new();
            shape.shoot(&ray, &mut segs);
            for seg in segs {
                points.push((seg.f0, ray.at(seg.t0)));
                points.push((seg.f1, ray.at(seg.t1)));
            }
        }
        let faces: std::collections::BTreeSet<u32> = points.iter().map(|p| p.0).collect();
        assert_eq!(faces.len(), 3, "{faces:?} of {shape:?}");
        for chunk in points.chunks(4) {
            let at = |j: usize| chunk[j.min(chunk.len() - 1)];
            let face = std::array::from_fn(|j| f64::from(at(j).0));
            let p = [0, 1, 2].map(|c| std::array::from_fn(|j| at(j).1[c]));
            let got = shape.normal_lanes(s, face, p);
            for (j, &(face, point)) in chunk.iter().enumerate() {
                let want = shape.normal(face, point);
                let lane = DVec3::new(got[0][j], got[1][j], got[2][j]);
                // Where the top is pinched to a line, the normal there is
                // not a number either way; which of its bits a not-a-number
                // carries, the compiler does not promise.
                let bits = |v: DVec3| {
                    v.to_array()
                        .map(|c| if c.is_nan() { 0 } else { c.to_bits() })
                };
                assert_eq!(
                    bits(lane),
                    bits(want),
                    "face {face} at {point}: {lane} for {want}"
                );
            }
        }
    }
}
