//! Primary rays in packets: a tile's rays traced several at once, one ray
//! per vector lane (Wald et al. 2001, "Interactive rendering with
//! coherent ray tracing"), through the tile's sorted list of zones.
//!
//! A packet walks the list once for all its rays: each lane keeps its own
//! limit and stops where its ray alone would stop, the zone's box and
//! bodies are tested for every lane at once, and a zone whose bodies are
//! all convex (spheres, ellipsoids, cones and cylinders, boxes, polyhedra)
//! has its span intersected and subtracted in the lanes, with exactly the
//! comparisons of [`Prepared::zone_spans`]. Every other case goes to the
//! scalar code, one lane at a time: a zone with a torus, a faceted solid,
//! a quadric or a general cone; a `-` body that splits a span in two.
//!
//! Each lane computes with the same IEEE operations, in the same order, as
//! the scalar tracer does for its ray, so the hits are the same bit for bit
//! (tested against [`Prepared::first_hit_in`] for every lane width).

use crate::boolean::Bound;
use crate::bvh::{Child, WideNode, STACK, WIDTH};
use crate::lightbuf::{LightBuffer, Zones};
use crate::prepare::{PZone, Prepared};
use crate::shape::Shape;
use crate::simd::Simd;
use crate::trace::{Hit, Scratch};
use std::mem::MaybeUninit;
use sv_math::{Aabb, DMat3, DVec3, Ray};

/// The widest packet of any instruction set.
pub(crate) const MAX_LANES: usize = 8;

/// The rays of a packet, one vector per coordinate.
pub(crate) struct Lanes<S: Simd> {
    /// Origins.
    pub o: [S::F; 3],
    /// Unit directions.
    pub d: [S::F; 3],
    /// Reciprocals of the directions.
    pub inv: [S::F; 3],
}

/// A convex body's segment along each lane's ray, in the lanes of `hit`:
/// entry and exit, and the faces crossed there (small integers in `f64`).
pub(crate) struct SegLanes<S: Simd> {
    pub t0: S::F,
    pub t1: S::F,
    pub f0: S::F,
    pub f1: S::F,
    pub hit: S::M,
}

/// One end of a span in every lane: a [`Bound`] with its body and its
/// face and flip bits held as `f64` (exact below 2⁵³), so that a lane
/// picks whole ends with one select per field.
#[derive(Clone, Copy)]
struct End<S: Simd> {
    t: S::F,
    body: S::F,
    face: S::F,
}

/// A span in every lane.
#[derive(Clone, Copy)]
struct SpanLanes<S: Simd> {
    a: End<S>,
    b: End<S>,
}

/// Each lane's best hit so far, as [`Prepared::consider`] keeps it for one
/// ray: the lowest entry (ties to the lower region), and the limit past
/// which no zone can do better.
struct Best<S: Simd> {
    tmin: S::F,
    limit: S::F,
    t: S::F,
    region: S::F,
    zone: S::F,
    inside: S::M,
    /// The surface entered.
    a: End<S>,
}

impl<S: Simd> Best<S> {
    #[inline(always)]
    fn new(s: S, tmin: f64, tmax: f64) -> Best<S> {
        let none = s.splat(f64::from(u32::MAX));
        Best {
            tmin: s.splat(tmin),
            limit: s.splat(tmax),
            t: s.splat(f64::INFINITY),
            region: none,
            zone: none,
            inside: s.none(),
            a: End {
                t: s.splat(f64::INFINITY),
                body: none,
                face: s.splat(0.0),
            },
        }
    }

    /// Write the lanes' hits to the first places of `out` in lane order,
    /// with their ray's index (`first` plus the lane); the number of hits.
    #[inline(always)]
    fn emit(&self, s: S, out: &mut [(u32, Hit)], first: u32) -> usize {
        let hit = s.bits(s.lt(self.region, s.splat(f64::from(u32::MAX))));
        if hit == 0 {
            return 0;
        }
        let (t, region, zone) = (
            Spill::of(s, self.t),
            Spill::of(s, self.region),
            Spill::of(s, self.zone),
        );
        let (at, body, face) = (
            Spill::of(s, self.a.t),
            Spill::of(s, self.a.body),
            Spill::of(s, self.a.face),
        );
        let inside = s.bits(self.inside);
        let mut n = 0;
        for j in 0..S::LANES {
            if hit & (1 << j) != 0 {
                // Written in place, field by field (see `first_hit_in`).
                let slot = &mut out[n];
                slot.0 = first + j as u32;
                slot.1 = Hit {
                    t: t.0[j],
                    region: region.0[j] as u32,
                    bound: Bound::from_parts(at.0[j], body.0[j] as u32, face.0[j] as u32),
                    inside: inside & (1 << j) != 0,
                    zone: zone.0[j] as u32,
                };
                n += 1;
            }
        }
        n
    }
}

/// The flip bit of a [`Bound`], as added to a face held in `f64`.
const FLIP: f64 = 2_147_483_648.0;

/// `a · b` as glam computes it: `(x + y) + z`.
#[inline(always)]
pub(crate) fn dot<S: Simd>(s: S, a: [S::F; 3], b: [S::F; 3]) -> S::F {
    s.add(
        s.add(s.mul(a[0], b[0]), s.mul(a[1], b[1])),
        s.mul(a[2], b[2]),
    )
}

/// `m v` as glam computes it: the columns scaled by `v`'s coordinates and
/// added left to right.
///
/// Everything the packet tracer calls between its entry points (compiled
/// for an instruction set) and the intrinsics is `#[inline(always)]` and
/// free of closures: an intrinsic left in a function compiled without its
/// instruction set stays a call.
#[inline(always)]
pub(crate) fn mat_vec<S: Simd>(s: S, m: &DMat3, v: [S::F; 3]) -> [S::F; 3] {
    let (x, y, z) = (m.x_axis, m.y_axis, m.z_axis);
    [
        row(s, x.x, y.x, z.x, v),
        row(s, x.y, y.y, z.y, v),
        row(s, x.z, y.z, z.z, v),
    ]
}

/// One coordinate of [`mat_vec`].
#[inline(always)]
fn row<S: Simd>(s: S, a: f64, b: f64, c: f64, v: [S::F; 3]) -> S::F {
    s.add(
        s.add(s.mul(s.splat(a), v[0]), s.mul(s.splat(b), v[1])),
        s.mul(s.splat(c), v[2]),
    )
}

/// `p - c` in every lane.
#[inline(always)]
pub(crate) fn sub_point<S: Simd>(s: S, p: [S::F; 3], c: DVec3) -> [S::F; 3] {
    [
        s.sub(p[0], s.splat(c.x)),
        s.sub(p[1], s.splat(c.y)),
        s.sub(p[2], s.splat(c.z)),
    ]
}

/// `a + b t` in every lane.
#[inline(always)]
pub(crate) fn along<S: Simd>(s: S, a: [S::F; 3], b: [S::F; 3], t: S::F) -> [S::F; 3] {
    [
        s.add(a[0], s.mul(b[0], t)),
        s.add(a[1], s.mul(b[1], t)),
        s.add(a[2], s.mul(b[2], t)),
    ]
}

/// `a - b t` in every lane.
#[inline(always)]
pub(crate) fn back<S: Simd>(s: S, a: [S::F; 3], b: [S::F; 3], t: S::F) -> [S::F; 3] {
    [
        s.sub(a[0], s.mul(b[0], t)),
        s.sub(a[1], s.mul(b[1], t)),
        s.sub(a[2], s.mul(b[2], t)),
    ]
}

/// A point or vector in every lane.
#[inline(always)]
pub(crate) fn splat3<S: Simd>(s: S, v: DVec3) -> [S::F; 3] {
    [s.splat(v.x), s.splat(v.y), s.splat(v.z)]
}

/// Lanes not set in `m`.
#[inline(always)]
pub(crate) fn not<S: Simd>(s: S, m: S::M) -> S::M {
    s.andnot(s.mask(u32::MAX), m)
}

/// A packet of rays in lanes. A short packet repeats its last ray in the
/// lanes left.
#[inline(always)]
fn lanes_of<S: Simd>(s: S, rays: &[Ray]) -> Lanes<S> {
    if rays.len() < S::LANES {
        let mut full = [rays[rays.len() - 1]; MAX_LANES];
        full[..rays.len()].copy_from_slice(rays);
        return gather_lanes(s, Ray::coordinates(&full[..S::LANES]));
    }
    gather_lanes(s, Ray::coordinates(&rays[..S::LANES]))
}

/// The rays of [`Ray::coordinates`] `v` in lanes, each coordinate read
/// across the rays at once. (Written lane by lane into arrays first, they
/// were loaded back whole before the writes could be forwarded, which
/// stalled every packet.)
#[inline(always)]
fn gather_lanes<S: Simd>(s: S, v: &[f64]) -> Lanes<S> {
    Lanes {
        o: [s.gather(v, 0, 9), s.gather(v, 1, 9), s.gather(v, 2, 9)],
        d: [s.gather(v, 3, 9), s.gather(v, 4, 9), s.gather(v, 5, 9)],
        inv: [s.gather(v, 6, 9), s.gather(v, 7, 9), s.gather(v, 8, 9)],
    }
}

/// The entry of each lane's ray into child `k` of wide node `n`, and the
/// lanes that meet it within `[tmin, tmax]`: [`crate::bvh`]'s slab test of
/// a wide node's child.
#[inline(always)]
fn child_lanes<S: Simd>(
    s: S,
    n: &WideNode,
    k: usize,
    r: &Lanes<S>,
    tmin: S::F,
    tmax: S::F,
) -> (S::F, S::M) {
    let mut t0 = tmin;
    let mut t1 = tmax;
    for a in 0..3 {
        let x0 = s.mul(s.sub(s.splat(n.lo[a][k]), r.o[a]), r.inv[a]);
        let x1 = s.mul(s.sub(s.splat(n.hi[a][k]), r.o[a]), r.inv[a]);
        t0 = s.max(s.min(x0, x1), t0);
        t1 = s.min(s.max(x0, x1), t1);
    }
    (t0, s.le(t0, t1))
}

/// The lanes whose rays meet `b` within `[tmin, tmax]`: the slab test of
/// [`crate::bvh`]'s `hits`, operation for operation.
#[inline(always)]
fn box_lanes<S: Simd>(s: S, b: &Aabb, r: &Lanes<S>, tmin: S::F, tmax: S::F) -> S::M {
    let mut t0 = tmin;
    let mut t1 = tmax;
    for a in 0..3 {
        let x0 = s.mul(s.sub(s.splat(b.min[a]), r.o[a]), r.inv[a]);
        let x1 = s.mul(s.sub(s.splat(b.max[a]), r.o[a]), r.inv[a]);
        t0 = s.max(s.min(x0, x1), t0);
        t1 = s.min(s.max(x0, x1), t1);
    }
    s.le(t0, t1)
}

impl Shape {
    /// True for the shapes [`Shape::shoot_lanes`] casts.
    pub(crate) fn has_lanes(&self) -> bool {
        matches!(
            self,
            Shape::Sphere(_)
                | Shape::Ellipsoid(_)
                | Shape::Cone(_)
                | Shape::Rpp(_)
                | Shape::Polyhedron(_)
        )
    }

    /// [`Shape::shoot`] for every lane, for the shapes of
    /// [`Shape::has_lanes`] (convex: one segment at most); others hit
    /// nothing here and are left to the scalar code by the caller.
    #[inline(always)]
    fn shoot_lanes<S: Simd>(&self, s: S, r: &Lanes<S>) -> SegLanes<S> {
        match self {
            Shape::Sphere(b) => b.shoot_lanes(s, r),
            Shape::Ellipsoid(b) => b.shoot_lanes(s, r),
            Shape::Cone(b) => b.shoot_lanes(s, r),
            Shape::Rpp(b) => b.shoot_lanes(s, r),
            Shape::Polyhedron(b) => b.shoot_lanes(s, r),
            _ => {
                let z = s.splat(0.0);
                SegLanes {
                    t0: z,
                    t1: z,
                    f0: z,
                    f1: z,
                    hit: s.none(),
                }
            }
        }
    }
}

/// Working values of a packet's lanes, one place per lane, for the lanes
/// left to the scalar code.
#[derive(Clone, Copy)]
struct Spill([f64; MAX_LANES]);

impl Spill {
    #[inline(always)]
    fn of<S: Simd>(s: S, x: S::F) -> Spill {
        let mut v = [0.0; MAX_LANES];
        s.store(x, &mut v);
        Spill(v)
    }
}

impl Prepared {
    /// [`Prepared::first_hit_in`] for each of `rays` (a tile's, in the
    /// order they are given), several rays at once where the processor has
    /// vector instructions for it. The hits go to the first places of
    /// `out`, with the index of their ray, in the order of the rays; the
    /// number of hits is returned. `out` is only ever grown: its places
    /// past the hits are kept for the next call.
    pub fn first_hits_in(
        &self,
        zones: &[(f64, u32)],
        rays: &[Ray],
        tmin: f64,
        tmax: f64,
        s: &mut Scratch,
        out: &mut Vec<(u32, Hit)>,
    ) -> usize {
        if out.len() < rays.len() {
            out.resize(rays.len(), (0, Hit::NONE));
        }
        #[cfg(target_arch = "x86_64")]
        if self.packets {
            use crate::simd::{Avx2, Avx512};
            if let Some(t) = Avx512::detect() {
                // SAFETY: the token proves the processor has AVX-512F.
                return unsafe { hits_avx512(self, t, zones, rays, tmin, tmax, s, out) };
            }
            if let Some(t) = Avx2::detect() {
                // SAFETY: the token proves the processor has AVX2.
                return unsafe { hits_avx2(self, t, zones, rays, tmin, tmax, s, out) };
            }
        }
        self.hits_one_by_one(zones, rays, tmin, tmax, s, out)
    }

    /// [`Prepared::first_hits_in`] ray by ray.
    pub(crate) fn hits_one_by_one(
        &self,
        zones: &[(f64, u32)],
        rays: &[Ray],
        tmin: f64,
        tmax: f64,
        s: &mut Scratch,
        out: &mut [(u32, Hit)],
    ) -> usize {
        let mut found = 0;
        for (k, ray) in rays.iter().enumerate() {
            let slot = &mut out[found];
            if self.first_hit_in(zones, ray, tmin, tmax, s, &mut slot.1) {
                slot.0 = k as u32;
                found += 1;
            }
        }
        found
    }

    /// [`Prepared::first_hits_in`] in packets of `S::LANES` rays.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub(crate) fn hits_in_packets<S: Simd>(
        &self,
        s: S,
        zones: &[(f64, u32)],
        rays: &[Ray],
        tmin: f64,
        tmax: f64,
        sc: &mut Scratch,
        out: &mut [(u32, Hit)],
    ) -> usize {
        let mut found = 0;
        for (p, chunk) in rays.chunks(S::LANES).enumerate() {
            let lanes = lanes_of(s, chunk);
            let active = (1u32 << chunk.len()) - 1;
            let (base, at) = (p * S::LANES, found);
            found += self.packet_first_hits(
                s,
                zones,
                &lanes,
                chunk,
                active,
                tmin,
                tmax,
                sc,
                &mut out[at..],
                base as u32,
            );
        }
        found
    }

    /// The first hits of one packet's rays (`rays`, the lanes of `active`)
    /// among the sorted `zones`, written to the first places of `out` in
    /// lane order with their ray's index (`first` plus the lane); returns
    /// the number of hits.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn packet_first_hits<S: Simd>(
        &self,
        s: S,
        zones: &[(f64, u32)],
        r: &Lanes<S>,
        rays: &[Ray],
        active: u32,
        tmin: f64,
        tmax: f64,
        sc: &mut Scratch,
        out: &mut [(u32, Hit)],
        first: u32,
    ) -> usize {
        let mut b = Best::new(s, tmin, tmax);
        let mut alive = s.mask(active);
        for &(near, zi) in zones {
            // A lane stops at the first zone that cannot come nearer than
            // its best hit, as the ray alone would.
            alive = s.andnot(alive, s.gt(s.splat(near), b.limit));
            if !s.any(alive) {
                break;
            }
            self.consider_lanes(s, zi, r, rays, alive, &mut b, sc);
        }
        b.emit(s, out, first)
    }

    /// [`Prepared::first_hit`] for each of `rays`, several rays at once
    /// where the processor has vector instructions for it: a packet walks
    /// the hierarchy together, each lane into the boxes its ray meets
    /// before its best hit. Output as [`Prepared::first_hits_in`].
    pub fn first_hits(
        &self,
        rays: &[Ray],
        tmin: f64,
        tmax: f64,
        s: &mut Scratch,
        out: &mut Vec<(u32, Hit)>,
    ) -> usize {
        if out.len() < rays.len() {
            out.resize(rays.len(), (0, Hit::NONE));
        }
        #[cfg(target_arch = "x86_64")]
        if self.packets {
            use crate::simd::{Avx2, Avx512};
            if let Some(t) = Avx512::detect() {
                // SAFETY: the token proves the processor has AVX-512F.
                return unsafe { walk_avx512(self, t, rays, tmin, tmax, s, out) };
            }
            if let Some(t) = Avx2::detect() {
                // SAFETY: the token proves the processor has AVX2.
                return unsafe { walk_avx2(self, t, rays, tmin, tmax, s, out) };
            }
        }
        self.walk_one_by_one(rays, tmin, tmax, s, out)
    }

    /// [`Prepared::first_hits`] ray by ray.
    pub(crate) fn walk_one_by_one(
        &self,
        rays: &[Ray],
        tmin: f64,
        tmax: f64,
        s: &mut Scratch,
        out: &mut [(u32, Hit)],
    ) -> usize {
        let mut found = 0;
        for (k, ray) in rays.iter().enumerate() {
            if let Some(h) = self.first_hit(ray, tmin, tmax, s) {
                out[found] = (k as u32, h);
                found += 1;
            }
        }
        found
    }

    /// [`Prepared::first_hits`] in packets of `S::LANES` rays.
    #[inline(always)]
    pub(crate) fn walk_in_packets<S: Simd>(
        &self,
        s: S,
        rays: &[Ray],
        tmin: f64,
        tmax: f64,
        sc: &mut Scratch,
        out: &mut [(u32, Hit)],
    ) -> usize {
        let mut found = 0;
        for (p, chunk) in rays.chunks(S::LANES).enumerate() {
            let lanes = lanes_of(s, chunk);
            let active = (1u32 << chunk.len()) - 1;
            let first = (p * S::LANES) as u32;
            found += match self.packet_walk(s, &lanes, chunk, active, tmin, tmax, sc) {
                Some(b) => b.emit(s, &mut out[found..], first),
                // A tree deeper than the stack: ray by ray.
                None => {
                    let n = self.walk_one_by_one(chunk, tmin, tmax, sc, &mut out[found..]);
                    out[found..found + n].iter_mut().for_each(|h| h.0 += first);
                    n
                }
            };
        }
        found
    }

    /// The best hits of one packet's rays (the lanes of `active`): the
    /// unbounded zones, then the hierarchy's, walked together, nearer boxes
    /// first; `None` for a tree deeper than the walk's stack.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn packet_walk<S: Simd>(
        &self,
        s: S,
        r: &Lanes<S>,
        rays: &[Ray],
        active: u32,
        tmin: f64,
        tmax: f64,
        sc: &mut Scratch,
    ) -> Option<Best<S>> {
        let mut b = Best::new(s, tmin, tmax);
        let act = s.mask(active);
        for &zi in &self.unbounded_opaque {
            self.consider_lanes(s, zi, r, rays, act, &mut b, sc);
        }
        let bvh = &self.bvh_opaque;
        if bvh.wide.is_empty() {
            return Some(b);
        }
        // Entries to visit, with each lane's entry into their box: not a
        // number for a lane that misses it, which no limit lets through
        // (infinity would pass an infinite limit).
        let (miss, inf) = (s.splat(f64::NAN), s.splat(f64::INFINITY));
        // Not filled beforehand: a packet of a crowded tile would spend a
        // tenth of its walk on it. Only the entries below `sp` are read.
        let mut stack = [const { MaybeUninit::<(Child, S::F)>::uninit() }; STACK];
        stack[0].write((Child::Node(0), s.select(act, b.tmin, miss)));
        let mut sp = 1;
        while sp > 0 {
            sp -= 1;
            // SAFETY: every entry below `sp` was written before `sp` passed
            // it.
            let (c, near) = unsafe { stack[sp].assume_init() };
            let m = s.le(near, b.limit);
            if !s.any(m) {
                continue;
            }
            match c {
                Child::Leaf { first, count } => {
                    for &zi in &bvh.items[first as usize..(first + count) as usize] {
                        self.consider_lanes(s, zi, r, rays, m, &mut b, sc);
                    }
                }
                Child::Node(i) => {
                    let n = &bvh.wide[i as usize];
                    // The children met, pushed farthest first (by the
                    // nearest entry of any lane).
                    let mut order = [(0.0f64, 0usize, miss); WIDTH];
                    let mut k_met = 0;
                    for k in 0..WIDTH {
                        if n.child[k] == Child::None {
                            continue;
                        }
                        let (t0, hit) = child_lanes(s, n, k, r, b.tmin, b.limit);
                        let hit = s.and(hit, m);
                        if !s.any(hit) {
                            continue;
                        }
                        let first = s.min_lane(s.select(hit, t0, inf));
                        let t0 = s.select(hit, t0, miss);
                        let mut j = k_met;
                        while j > 0 && order[j - 1].0 < first {
                            order[j] = order[j - 1];
                            j -= 1;
                        }
                        order[j] = (first, k, t0);
                        k_met += 1;
                    }
                    if sp + k_met > STACK {
                        return None;
                    }
                    for &(_, k, t0) in &order[..k_met] {
                        stack[sp].write((n.child[k], t0));
                        sp += 1;
                    }
                }
                Child::None => {}
            }
        }
        Some(b)
    }

    /// [`Prepared::consider`] of zone `zi` for the lanes of `m`.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn consider_lanes<S: Simd>(
        &self,
        s: S,
        zi: u32,
        r: &Lanes<S>,
        rays: &[Ray],
        m: S::M,
        b: &mut Best<S>,
        sc: &mut Scratch,
    ) {
        let z = &self.zones[zi as usize];
        let m = s.and(m, box_lanes(s, &z.bounds, r, b.tmin, b.limit));
        if !s.any(m) {
            return;
        }
        let (mut sp, mut valid, scalar) = if z.lanes {
            self.zone_lanes(s, z, r, m, b.tmin, b.limit)
        } else {
            let z0 = End {
                t: b.tmin,
                body: b.tmin,
                face: b.tmin,
            };
            (SpanLanes { a: z0, b: z0 }, s.none(), m)
        };
        let left = s.bits(scalar);
        if left != 0 {
            let tmin = Spill::of(s, b.tmin).0[0];
            (sp.a, valid) = self.spans_one_by_one(s, z, rays, left, b.limit, tmin, sc, sp.a, valid);
        }
        if !s.any(valid) {
            return;
        }
        // The best so far: the lowest entry, ties to the lower region, then
        // to the lower zone.
        let inside = s.andnot(valid, s.gt(sp.a.t, b.tmin));
        let t = s.select(inside, b.tmin, sp.a.t);
        let (region, zone) = (s.splat(f64::from(z.region)), s.splat(f64::from(zi)));
        let lower = s.or(
            s.lt(region, b.region),
            s.and(s.eq(region, b.region), s.lt(zone, b.zone)),
        );
        let better = s.and(valid, s.or(s.lt(t, b.t), s.and(s.eq(t, b.t), lower)));
        if !s.any(better) {
            return;
        }
        b.t = s.select(better, t, b.t);
        b.region = s.select(better, region, b.region);
        b.zone = s.select(better, zone, b.zone);
        b.inside = s.or(s.and(better, inside), s.andnot(b.inside, better));
        b.a = pick(s, better, sp.a, b.a);
        // Keep equal-t candidates reachable for the tie rule.
        let slack = s.min(
            s.add(s.mul(s.abs(t), s.splat(1e-15)), s.splat(f64::MIN_POSITIVE)),
            s.splat(self.tol),
        );
        b.limit = s.select(better, s.add(t, slack), b.limit);
    }

    /// The zone's first span (entry) for the lanes in `lanes` by the
    /// scalar code, one ray at a time, written over `a` and `valid`.
    #[allow(clippy::too_many_arguments)]
    #[inline(never)]
    fn spans_one_by_one<S: Simd>(
        &self,
        s: S,
        z: &PZone,
        rays: &[Ray],
        lanes: u32,
        limit: S::F,
        tmin: f64,
        sc: &mut Scratch,
        a: End<S>,
        valid: S::M,
    ) -> (End<S>, S::M) {
        let limit = Spill::of(s, limit);
        let (mut t, mut body, mut face) = (
            Spill::of(s, a.t),
            Spill::of(s, a.body),
            Spill::of(s, a.face),
        );
        let mut valid = s.bits(valid);
        for j in 0..S::LANES {
            if lanes & (1 << j) == 0 {
                continue;
            }
            let ray = &rays[j.min(rays.len() - 1)];
            sc.new_ray();
            if self.zone_spans(z, ray, tmin, limit.0[j], sc) {
                let e = sc.cur[0].a;
                t.0[j] = e.t;
                body.0[j] = f64::from(e.body);
                face.0[j] = f64::from(e.face_flip());
                valid |= 1 << j;
            }
        }
        (
            End {
                t: s.load(&t.0),
                body: s.load(&body.0),
                face: s.load(&face.0),
            },
            s.mask(valid),
        )
    }

    /// [`Prepared::zone_spans`]' first span for the lanes of `m`, for a
    /// zone of [`PZone::lanes`]: the span, the lanes that have one, and the
    /// lanes left to the scalar code (where a `-` body split the span and
    /// its first piece did not last). Each step is
    /// [`Prepared::convex_spans`]' for one span and one segment.
    #[inline(always)]
    fn zone_lanes<S: Simd>(
        &self,
        s: S,
        z: &PZone,
        r: &Lanes<S>,
        m: S::M,
        lo: S::F,
        hi: S::F,
    ) -> (SpanLanes<S>, S::M, S::M) {
        let first = z.first as usize;
        let terms = &self.terms[first..first + z.plus as usize + z.minus as usize];
        let (plus, minus) = terms.split_at(z.plus as usize);
        let tol = s.splat(self.tol);
        let mut alive = m;
        let mut cur: Option<SpanLanes<S>> = None;
        for &b in plus {
            // A lone `+` body has the zone's bounds, which the rays meet.
            if plus.len() > 1 {
                let inf = s.splat(f64::INFINITY);
                let bounds = &self.body_bounds[b as usize];
                alive = s.and(alive, box_lanes(s, bounds, r, s.neg(inf), inf));
            }
            let g = self.shapes[b as usize].shoot_lanes(s, r);
            alive = s.and(alive, g.hit);
            let q = span(s, &g, b);
            cur = Some(match cur {
                None => {
                    alive = s.and(alive, s.and(s.gt(q.b.t, lo), s.lt(q.a.t, hi)));
                    q
                }
                Some(p) => {
                    let a = pick(s, s.ge(p.a.t, q.a.t), p.a, q.a);
                    let b = pick(s, s.le(p.b.t, q.b.t), p.b, q.b);
                    alive = s.and(alive, s.gt(s.sub(b.t, a.t), tol));
                    SpanLanes { a, b }
                }
            });
            if !s.any(alive) {
                break;
            }
        }
        let (Some(mut cur), true) = (cur, s.any(alive)) else {
            let z0 = End {
                t: lo,
                body: lo,
                face: lo,
            };
            return (SpanLanes { a: z0, b: z0 }, s.none(), s.none());
        };
        let mut split = s.none();
        for &b in minus {
            let mm = s.and(
                alive,
                box_lanes(s, &self.body_bounds[b as usize], r, cur.a.t, cur.b.t),
            );
            if !s.any(mm) {
                continue;
            }
            let g = self.shapes[b as usize].shoot_lanes(s, r);
            // The segment reaches past the span's start and begins before
            // its end.
            let mm = s.andnot(
                s.and(mm, g.hit),
                s.or(s.ge(g.t0, cur.b.t), s.le(g.t1, cur.a.t)),
            );
            if !s.any(mm) {
                continue;
            }
            let c = span(s, &g, b);
            let start = cur.a;
            let before = s.and(s.gt(c.a.t, start.t), s.gt(s.sub(c.a.t, start.t), tol));
            let new_start = pick(s, s.gt(c.b.t, start.t), flip(s, c.b), start);
            let after = s.gt(s.sub(cur.b.t, new_start.t), tol);
            // Two spans: the lanes follow the first, which stays the
            // zone's first span while anything of it is left (the lists
            // would cut it by the same steps; it is longer than `tol`, so
            // the lists never drop it untouched).
            split = s.or(split, s.and(mm, s.and(before, after)));
            alive = s.andnot(alive, s.andnot(s.andnot(mm, before), after));
            cur.b = pick(s, s.and(mm, before), flip(s, c.a), cur.b);
            cur.a = pick(s, s.andnot(s.and(mm, after), before), new_start, cur.a);
            if !s.any(alive) {
                break;
            }
        }
        let valid = s.and(alive, s.and(s.gt(cur.b.t, lo), s.lt(cur.a.t, hi)));
        // Where the first of two spans went, or lies before `lo`, the first
        // span is another: the scalar code finds it.
        (cur, valid, s.andnot(split, valid))
    }
}

impl Prepared {
    /// For each of `from` (a point, and the zone its shadow ray cannot
    /// meet: [`Prepared::shadow_skip`]), whether an opaque region blocks
    /// the ray from it toward the parallel light of `buf` beyond `tmin`:
    /// [`Prepared::occluded_by`]'s answer for each, several rays at once
    /// where the processor has vector instructions for it. `last` is the
    /// buffer's shadow cache, as there.
    ///
    /// The rays of a packet share their direction. Each ray's answer is
    /// whether any zone blocks it, which does not depend on the order the
    /// zones are tried in: the packet tries every zone listed for any of
    /// its rays once, on all its rays not yet blocked. A zone that the
    /// buffer does not list for a ray cannot block it, so trying it there
    /// changes nothing.
    pub fn occluded_toward(
        &self,
        buf: &LightBuffer,
        from: &[(DVec3, Option<u32>)],
        tmin: f64,
        last: &mut Option<u32>,
        s: &mut Scratch,
        out: &mut Vec<bool>,
    ) {
        out.clear();
        out.resize(from.len(), false);
        #[cfg(target_arch = "x86_64")]
        if self.packets {
            use crate::simd::{Avx2, Avx512};
            if let Some(t) = Avx512::detect() {
                // SAFETY: the token proves the processor has AVX-512F.
                return unsafe { occluded_avx512(self, t, buf, from, tmin, last, s, out) };
            }
            if let Some(t) = Avx2::detect() {
                // SAFETY: the token proves the processor has AVX2.
                return unsafe { occluded_avx2(self, t, buf, from, tmin, last, s, out) };
            }
        }
        for (o, &(p, skip)) in out.iter_mut().zip(from) {
            let ray = buf.shadow_ray(p);
            *o = self.occluded_by(buf, &ray, tmin, f64::INFINITY, skip, last, s);
        }
    }

    /// [`Prepared::occluded_toward`] in packets of `S::LANES` rays.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub(crate) fn occluded_in_packets<S: Simd>(
        &self,
        s: S,
        buf: &LightBuffer,
        from: &[(DVec3, Option<u32>)],
        tmin: f64,
        last: &mut Option<u32>,
        sc: &mut Scratch,
        out: &mut [bool],
    ) {
        let along = buf.shadow_ray(DVec3::ZERO);
        let (d, inv) = (splat3(s, along.dir), splat3(s, along.inv_dir));
        for (chunk, out) in from.chunks(S::LANES).zip(out.chunks_mut(S::LANES)) {
            // A short last packet repeats its last ray in the lanes left.
            let mut v = [[0.0; MAX_LANES]; 4];
            for j in 0..S::LANES {
                let (p, skip) = chunk[j.min(chunk.len() - 1)];
                v[0][j] = p.x;
                v[1][j] = p.y;
                v[2][j] = p.z;
                v[3][j] = skip.map_or(-1.0, f64::from);
            }
            let r = Lanes::<S> {
                o: [s.load(&v[0]), s.load(&v[1]), s.load(&v[2])],
                d,
                inv,
            };
            let skip = s.load(&v[3]);
            sc.packet = sc.packet.wrapping_add(1);
            if sc.packet == 0 {
                sc.tested.iter_mut().for_each(|t| *t = 0);
                sc.packet = 1;
            }
            let active = (1u32 << chunk.len()) - 1;
            let (mut blocked, mut blocker) = (0, None);
            // The zone that blocked the last shadow ray first: neighbouring
            // points are mostly shadowed by the same zone. (No closure for
            // the zone's test: its intrinsics would stay calls.)
            if let Some(zi) = *last {
                sc.tested[zi as usize] = sc.packet;
                let b = self.blocks(s, zi, &r, chunk, active, skip, tmin, sc);
                if b != 0 {
                    (blocked, blocker) = (b, Some(zi));
                }
            }
            for (j, &(p, skip_j)) in chunk.iter().enumerate() {
                if blocked & (1 << j) != 0 {
                    continue;
                }
                let Some(cands) = buf.zones_at(p) else {
                    // A point that is not a number: the full search decides.
                    if self.occluded(&buf.shadow_ray(p), tmin, f64::INFINITY, skip_j, sc) {
                        blocked |= 1 << j;
                    }
                    continue;
                };
                for zi in self.unbounded_opaque.iter().copied().chain(cands.all()) {
                    if sc.tested[zi as usize] == sc.packet {
                        continue;
                    }
                    sc.tested[zi as usize] = sc.packet;
                    let b = self.blocks(s, zi, &r, chunk, active & !blocked, skip, tmin, sc);
                    if b != 0 {
                        (blocked, blocker) = (blocked | b, Some(zi));
                        if b & (1 << j) != 0 {
                            break;
                        }
                    }
                }
            }
            *last = if blocked != 0 { blocker } else { None };
            for (j, o) in out.iter_mut().enumerate() {
                *o = blocked & (1 << j) != 0;
            }
        }
    }

    /// The lanes of `mask` whose shadow rays zone `zi` blocks beyond `tmin`
    /// (not those that skip it): [`Prepared::any_opaque`]'s test of one
    /// zone, in the lanes where the zone allows it, else by the scalar code.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn blocks<S: Simd>(
        &self,
        s: S,
        zi: u32,
        r: &Lanes<S>,
        from: &[(DVec3, Option<u32>)],
        mask: u32,
        skip: S::F,
        tmin: f64,
        sc: &mut Scratch,
    ) -> u32 {
        if mask == 0 {
            return 0;
        }
        let z = &self.zones[zi as usize];
        let (lo, hi) = (s.splat(tmin), s.splat(f64::INFINITY));
        let m = s.andnot(s.mask(mask), s.eq(skip, s.splat(f64::from(zi))));
        let m = s.and(m, box_lanes(s, &z.bounds, r, lo, hi));
        if !s.any(m) {
            return 0;
        }
        let (mut found, scalar) = if z.lanes {
            let (_, valid, scalar) = self.zone_lanes(s, z, r, m, lo, hi);
            (s.bits(valid), s.bits(scalar))
        } else {
            (0, s.bits(m))
        };
        if scalar != 0 {
            found |= self.blocks_one_by_one(z, from, scalar, tmin, r_dir(s, r), sc);
        }
        found
    }

    /// [`Prepared::blocks`] for the lanes of `lanes`, one ray at a time.
    #[inline(never)]
    fn blocks_one_by_one(
        &self,
        z: &PZone,
        from: &[(DVec3, Option<u32>)],
        lanes: u32,
        tmin: f64,
        (dir, inv_dir): (DVec3, DVec3),
        sc: &mut Scratch,
    ) -> u32 {
        let mut found = 0;
        for (j, &(origin, _)) in from.iter().enumerate() {
            if lanes & (1 << j) == 0 {
                continue;
            }
            let ray = Ray {
                origin,
                dir,
                inv_dir,
            };
            sc.new_ray();
            if self.zone_spans(z, &ray, tmin, f64::INFINITY, sc) {
                found |= 1 << j;
            }
        }
        found
    }
}

/// The direction shared by a packet's lanes (shadow rays toward a
/// parallel light), and its reciprocal, from the first lane.
#[inline(always)]
fn r_dir<S: Simd>(s: S, r: &Lanes<S>) -> (DVec3, DVec3) {
    let (d, inv) = (
        [
            Spill::of(s, r.d[0]),
            Spill::of(s, r.d[1]),
            Spill::of(s, r.d[2]),
        ],
        [
            Spill::of(s, r.inv[0]),
            Spill::of(s, r.inv[1]),
            Spill::of(s, r.inv[2]),
        ],
    );
    (
        DVec3::new(d[0].0[0], d[1].0[0], d[2].0[0]),
        DVec3::new(inv[0].0[0], inv[1].0[0], inv[2].0[0]),
    )
}

/// A body's segment in every lane as a span bounded by its faces.
#[inline(always)]
fn span<S: Simd>(s: S, g: &SegLanes<S>, b: u32) -> SpanLanes<S> {
    let body = s.splat(f64::from(b));
    SpanLanes {
        a: End {
            t: g.t0,
            body,
            face: g.f0,
        },
        b: End {
            t: g.t1,
            body,
            face: g.f1,
        },
    }
}

/// `if c { x } else { y }`, lane by lane.
#[inline(always)]
fn pick<S: Simd>(s: S, c: S::M, x: End<S>, y: End<S>) -> End<S> {
    End {
        t: s.select(c, x.t, y.t),
        body: s.select(c, x.body, y.body),
        face: s.select(c, x.face, y.face),
    }
}

/// The end of a subtracted body ([`crate::boolean::flipped`] of an end
/// from a shot, which has no flip bit).
#[inline(always)]
fn flip<S: Simd>(s: S, e: End<S>) -> End<S> {
    End {
        face: s.add(e.face, s.splat(FLIP)),
        ..e
    }
}

/// [`Prepared::hits_in_packets`] compiled for AVX-512.
///
/// # Safety
/// The processor must have AVX-512F (the token's existence proves it).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
#[allow(clippy::too_many_arguments)]
unsafe fn hits_avx512(
    p: &Prepared,
    t: crate::simd::Avx512,
    zones: &[(f64, u32)],
    rays: &[Ray],
    tmin: f64,
    tmax: f64,
    s: &mut Scratch,
    out: &mut [(u32, Hit)],
) -> usize {
    p.hits_in_packets(t, zones, rays, tmin, tmax, s, out)
}

/// [`Prepared::occluded_in_packets`] compiled for AVX-512.
///
/// # Safety
/// The processor must have AVX-512F (the token's existence proves it).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
#[allow(clippy::too_many_arguments)]
unsafe fn occluded_avx512(
    p: &Prepared,
    t: crate::simd::Avx512,
    buf: &LightBuffer,
    from: &[(DVec3, Option<u32>)],
    tmin: f64,
    last: &mut Option<u32>,
    s: &mut Scratch,
    out: &mut [bool],
) {
    p.occluded_in_packets(t, buf, from, tmin, last, s, out)
}

/// [`Prepared::occluded_in_packets`] compiled for AVX2.
///
/// # Safety
/// The processor must have AVX2 (the token's existence proves it).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[allow(clippy::too_many_arguments)]
unsafe fn occluded_avx2(
    p: &Prepared,
    t: crate::simd::Avx2,
    buf: &LightBuffer,
    from: &[(DVec3, Option<u32>)],
    tmin: f64,
    last: &mut Option<u32>,
    s: &mut Scratch,
    out: &mut [bool],
) {
    p.occluded_in_packets(t, buf, from, tmin, last, s, out)
}

/// [`Prepared::walk_in_packets`] compiled for AVX-512.
///
/// # Safety
/// The processor must have AVX-512F (the token's existence proves it).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
unsafe fn walk_avx512(
    p: &Prepared,
    t: crate::simd::Avx512,
    rays: &[Ray],
    tmin: f64,
    tmax: f64,
    s: &mut Scratch,
    out: &mut [(u32, Hit)],
) -> usize {
    p.walk_in_packets(t, rays, tmin, tmax, s, out)
}

/// [`Prepared::walk_in_packets`] compiled for AVX2.
///
/// # Safety
/// The processor must have AVX2 (the token's existence proves it).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn walk_avx2(
    p: &Prepared,
    t: crate::simd::Avx2,
    rays: &[Ray],
    tmin: f64,
    tmax: f64,
    s: &mut Scratch,
    out: &mut [(u32, Hit)],
) -> usize {
    p.walk_in_packets(t, rays, tmin, tmax, s, out)
}

/// [`Prepared::hits_in_packets`] compiled for AVX2.
///
/// # Safety
/// The processor must have AVX2 (the token's existence proves it).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[allow(clippy::too_many_arguments)]
unsafe fn hits_avx2(
    p: &Prepared,
    t: crate::simd::Avx2,
    zones: &[(f64, u32)],
    rays: &[Ray],
    tmin: f64,
    tmax: f64,
    s: &mut Scratch,
    out: &mut [(u32, Hit)],
) -> usize {
    p.hits_in_packets(t, zones, rays, tmin, tmax, s, out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simd::Portable;
    use crate::{Body, BodyKind, Geometry, Op, PrepareOptions, Region, Term, Zone};
    use rand::{Rng, SeedableRng};
    use sv_math::DVec3;

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
                        -0.6, -0.6, -0.6, 0.6, -0.6, -0.6, 0.6, 0.6, -0.6, -0.6, 0.6, -0.6, -0.3,
                        -0.3, 0.6, 0.3, -0.3, 0.6, 0.3, 0.3, 0.6, -0.3, 0.3, 0.6,
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
    /// (apart, so that the random ones do not hide them): `+` and `-`
    /// bodies flush with each other, a body less itself, cones whose
    /// generators the rays below run along.
    fn geometry(rng: &mut impl Rng, made_only: bool) -> Geometry {
        let mut g = Geometry {
            bodies: bodies(rng),
            ..Default::default()
        };
        let n = g.bodies.len();
        let edge: [(BodyKind, Vec<f64>); 8] = [
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
        ];
        for (i, (kind, params)) in edge.into_iter().enumerate() {
            g.bodies.push(Body::new(format!("e{i}"), kind, params));
        }
        let (cube, flush, half, cone, cup, cyl, ball) = (5, n, n + 1, n + 2, n + 3, n + 4, n + 5);
        let (low, high) = (n + 6, n + 7);
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
        ];
        for (r, z) in made.into_iter().enumerate() {
            g.regions.push(Region {
                name: format!("m{r}"),
                zones: vec![z],
            });
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
                    let mut p =
                        DVec3::new(on_face[i % 4], on_face[(i / 4) % 4], on_face[(i / 3) % 4]);
                    if i % 5 == 4 {
                        p += DVec3::new(u(0.7), u(0.7), u(0.7));
                    }
                    // Through the boxes' edges, entering two faces at once.
                    if i % 5 == 3 {
                        let c = on_face[i % 4];
                        let diagonal = [DVec3::new(1.0, 1.0, 0.0), DVec3::ONE][i % 2];
                        return Ray::new(
                            DVec3::new(c, c, c * diagonal.z) - diagonal * 2.0,
                            diagonal,
                        );
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
        for i in 0..8 {
            let g = geometry(&mut rng, i % 2 == 0);
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
                    p.hits_in_packets(Portable, &sorted, &rays, tmin, inf, &mut s, o)
                });
                check("walk, ray by ray", &mut |o| {
                    p.walk_one_by_one(&rays, tmin, inf, &mut s, o)
                });
                check("walk, four portable lanes", &mut |o| {
                    p.walk_in_packets(Portable, &rays, tmin, inf, &mut s, o)
                });
                #[cfg(target_arch = "x86_64")]
                {
                    // SAFETY (all four): the tokens prove the instructions
                    // are there.
                    if let Some(t) = crate::simd::Avx512::detect() {
                        check("list, AVX-512", &mut |o| unsafe {
                            hits_avx512(&p, t, &sorted, &rays, tmin, inf, &mut s, o)
                        });
                        check("walk, AVX-512", &mut |o| unsafe {
                            walk_avx512(&p, t, &rays, tmin, inf, &mut s, o)
                        });
                    }
                    if let Some(t) = crate::simd::Avx2::detect() {
                        check("list, AVX2", &mut |o| unsafe {
                            hits_avx2(&p, t, &sorted, &rays, tmin, inf, &mut s, o)
                        });
                        check("walk, AVX2", &mut |o| unsafe {
                            walk_avx2(&p, t, &rays, tmin, inf, &mut s, o)
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
        assert!(hits * 3 > rays_cast, "{hits} of {rays_cast}");
    }

    #[test]
    fn shadow_packets_agree_with_shadow_rays_one_by_one() {
        let mut rng = rand_pcg::Pcg64::seed_from_u64(9);
        let (mut blocked, mut tested) = (0, 0);
        for i in 0..8 {
            let g = geometry(&mut rng, i % 2 == 0);
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
                many.clear();
                many.resize(from.len(), false);
                p.occluded_in_packets(Portable, &lb, &from, tmin, &mut last, &mut s, &mut many);
                assert_eq!(one, many, "four portable lanes, batch {batch}");
                #[cfg(target_arch = "x86_64")]
                {
                    if let Some(t) = crate::simd::Avx512::detect() {
                        // SAFETY: the token proves the instructions are there.
                        unsafe {
                            occluded_avx512(&p, t, &lb, &from, tmin, &mut last, &mut s, &mut many)
                        };
                        assert_eq!(one, many, "AVX-512, batch {batch}");
                    }
                    if let Some(t) = crate::simd::Avx2::detect() {
                        // SAFETY: as above.
                        unsafe {
                            occluded_avx2(&p, t, &lb, &from, tmin, &mut last, &mut s, &mut many)
                        };
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
}
