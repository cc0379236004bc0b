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
//! a quadric or a general cone among its `+` bodies; a ray that meets the
//! box of such a `-` body; `-` bodies that would leave three spans.
//!
//! Each lane computes with the same IEEE operations, in the same order, as
//! the scalar tracer does for its ray, so the hits are the same bit for bit
//! (tested against [`Prepared::first_hit_in`] for every lane width).
//!
//! Shadow rays toward a parallel light go in packets too (the `shadow` module): the
//! rays of a packet share their direction, and each lane stops at the first
//! opaque zone that blocks it.
//!
//! Everything the packet tracer calls between its entry points (compiled
//! for an instruction set with `#[target_feature]`) and the intrinsics is
//! `#[inline(always)]` and free of closures: an intrinsic left in a
//! function compiled without its instruction set stays a call, and a call
//! per operation undoes the lanes' gain.

use crate::hit::{Hit, Scratch};
use crate::prepare::{Prepared, PreparedZone};
use std::mem::MaybeUninit;
use sv_geom::boolean::Bound;
use sv_geom::shape::{SegLanes, Shape};
use sv_math::lanes::{along, box_lanes, dot, not, Lanes, MAX_LANES};
use sv_math::simd::Simd;
use sv_math::{DVec3, Ray};

/// What the rays traced together share, to the bit, as their caller
/// knows: the lanes take it from the first ray without reading the rest.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RaysShare {
    /// Nothing known: the lanes compare the rays' directions.
    Unknown,
    /// Every ray has the first ray's direction.
    Direction,
    /// Every ray has the first ray's direction and origin but for the
    /// origin's coordinate along this axis: the rays of a grid's row.
    AllBut(usize),
}

impl RaysShare {
    /// Whether `rays` do share what this says, to the bit (`-0.0` is not
    /// `0.0`: it gives the other infinity as a reciprocal).
    pub fn holds_for(self, rays: &[Ray]) -> bool {
        let Some(first) = rays.first() else {
            return true;
        };
        let bits = |v: DVec3| v.to_array().map(f64::to_bits);
        rays.iter().all(|ray| match self {
            RaysShare::Unknown => true,
            RaysShare::Direction => bits(ray.dir) == bits(first.dir),
            RaysShare::AllBut(varying) => {
                let (mut origin, mut first_origin) = (bits(ray.origin), bits(first.origin));
                (origin[varying], first_origin[varying]) = (0, 0);
                bits(ray.dir) == bits(first.dir) && origin == first_origin
            }
        })
    }
}

/// The entry points of a packet method, one per instruction set:
/// `$avx512` and `$avx2` call `Prepared::$method` with the token, compiled
/// with that instruction set enabled, so that everything inlined into them
/// uses it; `$any` calls the widest this processor has when the packets are
/// on, and answers `None` when there is none (the caller's scalar code then
/// does the work).
macro_rules! compiled_for_each {
    (fn $avx512:ident, $avx2:ident, $any:ident => $method:ident $(::<$($gen:tt),+>)? ($($arg:ident: $ty:ty),* $(,)?)) => {
        compiled_for_each! { fn $avx512, $avx2, $any => $method $(::<$($gen),+>)? ($($arg: $ty),*) -> () }
    };
    (fn $avx512:ident, $avx2:ident, $any:ident => $method:ident $(::<$($gen:tt),+>)? ($($arg:ident: $ty:ty),* $(,)?) -> $ret:ty) => {
        #[doc = concat!("[`Prepared::", stringify!($method), "`] with the widest instruction set here, if any.")]
        #[allow(clippy::too_many_arguments, clippy::unused_unit)]
        #[cfg_attr(not(target_arch = "x86_64"), allow(unused_variables))]
        pub(super) fn $any(p: &Prepared, $($arg: $ty),*) -> Option<$ret> {
            #[cfg(target_arch = "x86_64")]
            if p.packets {
                if let Some(t) = sv_math::simd::Avx512::detect() {
                    // SAFETY: the token proves the processor has AVX-512F.
                    return Some(unsafe { $avx512(p, t, $($arg),*) });
                }
                if let Some(t) = sv_math::simd::Avx2::detect() {
                    // SAFETY: the token proves the processor has AVX2.
                    return Some(unsafe { $avx2(p, t, $($arg),*) });
                }
            }
            None
        }

        #[doc = concat!("[`Prepared::", stringify!($method), "`] compiled for AVX-512.")]
        ///
        /// # Safety
        /// The processor must have AVX-512F (the token's existence proves it).
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx512f")]
        #[allow(clippy::too_many_arguments, clippy::unused_unit)]
        pub(super) unsafe fn $avx512(
            p: &Prepared,
            t: sv_math::simd::Avx512,
            $($arg: $ty),*
        ) -> $ret {
            p.$method $(::<$($gen),+>)? (t, $($arg),*)
        }

        #[doc = concat!("[`Prepared::", stringify!($method), "`] compiled for AVX2.")]
        ///
        /// # Safety
        /// The processor must have AVX2 (the token's existence proves it).
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx2")]
        #[allow(clippy::too_many_arguments, clippy::unused_unit)]
        pub(super) unsafe fn $avx2(
            p: &Prepared,
            t: sv_math::simd::Avx2,
            $($arg: $ty),*
        ) -> $ret {
            p.$method $(::<$($gen),+>)? (t, $($arg),*)
        }
    };
}

mod partitions;
mod primary;
mod shadow;

pub use primary::{Tile, FACING_MISS};
#[cfg(test)]
mod tests;

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
struct NearestHit<S: Simd> {
    tmin: S::F,
    limit: S::F,
    t: S::F,
    region: S::F,
    zone: S::F,
    inside: S::M,
    /// The surface entered.
    a: End<S>,
}

impl<S: Simd> NearestHit<S> {
    #[inline(always)]
    fn new(s: S, tmin: f64, tmax: f64) -> NearestHit<S> {
        let none = s.splat(f64::from(u32::MAX));
        NearestHit {
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

    /// The lanes that hit something.
    #[inline(always)]
    fn hits(&self, s: S) -> u32 {
        s.bits(s.lt(self.region, s.splat(f64::from(u32::MAX))))
    }

    /// Write the lanes' hits to the first places of `out` in lane order,
    /// each with its lane's index from `index`, and, when given, their rays
    /// and the surface normals there ([`Prepared::normal`]) to the same
    /// places of `rays`; the number of hits.
    #[inline(always)]
    fn emit(
        &self,
        p: &Prepared,
        s: S,
        index: &[u32; MAX_LANES],
        out: &mut [(u32, Hit)],
        rays: Option<(&Lanes<S>, &mut [Ray], &mut [DVec3])>,
    ) -> usize {
        let hit = self.hits(s);
        if hit == 0 {
            return 0;
        }
        let lanes = HitLanes::of(s, self);
        let mut n = 0;
        for (j, &at_index) in index.iter().enumerate().take(S::LANES) {
            if hit & (1 << j) != 0 {
                // Written in place, field by field (see `first_hit_in`).
                let slot = &mut out[n];
                slot.0 = at_index;
                slot.1 = lanes.hit(j);
                n += 1;
            }
        }
        if let Some((r, rays, normals)) = rays {
            let lanes = lane_rays(s, r);
            let mut n = 0;
            for (j, ray) in lanes.iter().enumerate().take(S::LANES) {
                if hit & (1 << j) != 0 {
                    rays[n] = *ray;
                    n += 1;
                }
            }
            self.normals(p, s, r, hit, &out[..n], &lanes, normals);
        }
        n
    }

    /// The surface normals of the lanes of `hit` ([`Prepared::normal`] of
    /// their `hits`, in lane order, and `rays`), into the first places of
    /// `normals`: in the lanes for each body that several of them hit, one
    /// by one for the rest.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn normals(
        &self,
        p: &Prepared,
        s: S,
        r: &Lanes<S>,
        hit: u32,
        hits: &[(u32, Hit)],
        rays: &[Ray; MAX_LANES],
        normals: &mut [DVec3],
    ) {
        // Written only for the lanes of `in_lanes`.
        let mut out = [const { MaybeUninit::<LaneValues>::uninit() }; 3];
        let mut in_lanes = 0;
        let (mut groups, mut one_by_one) = self.normal_groups(s, r, hit);
        while let Some((group, lanes)) = groups.next(p, s, &mut one_by_one) {
            if in_lanes == 0 {
                for (o, l) in out.iter_mut().zip(lanes) {
                    o.write(LaneValues::of(s, l));
                }
            } else {
                for (o, l) in out.iter_mut().zip(lanes) {
                    let v = LaneValues::of(s, l);
                    // SAFETY: written when the first group was.
                    let o = unsafe { o.assume_init_mut() };
                    for (k, x) in o.0.iter_mut().enumerate().take(S::LANES) {
                        if group & (1 << k) != 0 {
                            *x = v.0[k];
                        }
                    }
                }
            }
            in_lanes |= group;
        }
        // The hits are in lane order: the n-th hit is the n-th lane of `hit`.
        let mut n = 0;
        for (j, ray) in rays.iter().enumerate().take(S::LANES) {
            if hit & (1 << j) == 0 {
                continue;
            }
            // Written a coordinate at a time: a normal gathered on the
            // stack and copied whole stalls on the stores of its parts.
            let slot = &mut normals[n];
            if in_lanes & (1 << j) != 0 {
                // SAFETY: written for the lanes of `in_lanes`.
                unsafe {
                    slot.x = out[0].assume_init_ref().0[j];
                    slot.y = out[1].assume_init_ref().0[j];
                    slot.z = out[2].assume_init_ref().0[j];
                }
            } else {
                *slot = p.normal(&hits[n].1, ray);
            }
            n += 1;
        }
        debug_assert_eq!(one_by_one | in_lanes, hit);
    }

    /// The lanes of `hit` whose normals the lanes can compute, to be taken
    /// a body at a time from [`NormalGroups::next`], and those that start
    /// inside their region or lie on no body (whose normals face the ray)
    /// or on a surface inside a filled region (whose normal the hit
    /// carries): these go one by one.
    #[inline(always)]
    fn normal_groups(&self, s: S, r: &Lanes<S>, hit: u32) -> (NormalGroups<S>, u32) {
        let facing = s.or(
            self.inside,
            s.ge(self.a.body, s.splat(f64::from(Bound::NESTED))),
        );
        // The face without the flip bit (set for subtracted bodies), and
        // the points hit.
        let flip = s.ge(self.a.face, s.splat(FLIP));
        let groups = NormalGroups {
            todo: hit & !s.bits(facing),
            bodies: LaneValues::of(s, self.a.body),
            body: self.a.body,
            flip,
            face: s.select(flip, s.sub(self.a.face, s.splat(FLIP)), self.a.face),
            at: along(s, r.o, r.d, self.t),
        };
        (groups, hit & s.bits(facing))
    }

    /// For each lane of `hit`, how squarely its surface faces its ray (see
    /// [`Prepared::facing`]), written to `out` at the lane's place in
    /// `index`: in the lanes for each body that several of them hit, one
    /// by one for the rest.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn facing(
        &self,
        p: &Prepared,
        s: S,
        r: &Lanes<S>,
        hit: u32,
        index: &[u32; MAX_LANES],
        out: &mut [f64],
        sc: &mut Scratch,
    ) {
        if hit == 0 {
            return;
        }
        let mut cos = s.splat(0.0);
        let (mut groups, mut one_by_one) = self.normal_groups(s, r, hit);
        while let Some((group, n)) = groups.next(p, s, &mut one_by_one) {
            // `-n·d`, as glam's dot and negation in `Prepared::facing`.
            let c = s.neg(dot(s, n, r.d));
            cos = s.select(s.mask(group), c, cos);
        }
        let cos = LaneValues::of(s, cos);
        if one_by_one == 0 {
            for (j, &at_index) in index.iter().enumerate().take(S::LANES) {
                if hit & (1 << j) != 0 {
                    out[at_index as usize] = cos.0[j].max(0.0);
                }
            }
            return;
        }
        let (rays, hits) = (lane_rays(s, r), HitLanes::of(s, self));
        for (j, &at_index) in index.iter().enumerate().take(S::LANES) {
            if hit & (1 << j) == 0 {
                continue;
            }
            out[at_index as usize] = if one_by_one & (1 << j) != 0 {
                p.facing(&hits.hit(j), &rays[j], sc)
            } else {
                cos.0[j].max(0.0)
            };
        }
    }
}

/// The normals of a packet's hits that the lanes compute, a body at a
/// time (see [`NearestHit::normal_groups`]).
struct NormalGroups<S: Simd> {
    /// Lanes not yet taken.
    todo: u32,
    /// Each lane's body, to pick the next body from.
    bodies: LaneValues,
    body: S::F,
    flip: S::M,
    face: S::F,
    at: [S::F; 3],
}

impl<S: Simd> NormalGroups<S> {
    /// The next body's lanes and their normals (reversed for a subtracted
    /// body), or `None` when no lane is left. A body that fewer than three
    /// lanes hit, or with no lane form, adds its lanes to `one_by_one`.
    #[inline(always)]
    fn next(&mut self, p: &Prepared, s: S, one_by_one: &mut u32) -> Option<(u32, [S::F; 3])> {
        while self.todo != 0 {
            let body = self.bodies.0[self.todo.trailing_zeros() as usize];
            let group = self.todo & s.bits(s.eq(self.body, s.splat(body)));
            self.todo &= !group;
            let shape = &p.shapes[body as u32 as usize];
            // Lanes are worth it for three rays or more.
            if group.count_ones() < 3 || !shape.has_lanes() {
                *one_by_one |= group;
                continue;
            }
            let [x, y, z] = shape.normal_lanes(s, self.face, self.at);
            let f = self.flip;
            let n = [
                s.select(f, s.neg(x), x),
                s.select(f, s.neg(y), y),
                s.select(f, s.neg(z), z),
            ];
            return Some((group, n));
        }
        None
    }
}

/// A packet's best hits, lane by lane, for the scalar code.
struct HitLanes {
    t: LaneValues,
    region: LaneValues,
    zone: LaneValues,
    at: LaneValues,
    body: LaneValues,
    face: LaneValues,
    inside: u32,
}

impl HitLanes {
    #[inline(always)]
    fn of<S: Simd>(s: S, b: &NearestHit<S>) -> HitLanes {
        HitLanes {
            t: LaneValues::of(s, b.t),
            region: LaneValues::of(s, b.region),
            zone: LaneValues::of(s, b.zone),
            at: LaneValues::of(s, b.a.t),
            body: LaneValues::of(s, b.a.body),
            face: LaneValues::of(s, b.a.face),
            inside: s.bits(b.inside),
        }
    }

    /// Lane `j`'s hit.
    #[inline(always)]
    fn hit(&self, j: usize) -> Hit {
        Hit {
            t: self.t.0[j],
            region: self.region.0[j] as u32,
            bound: Bound::from_parts(self.at.0[j], self.body.0[j] as u32, self.face.0[j] as u32),
            inside: self.inside & (1 << j) != 0,
            zone: self.zone.0[j] as u32,
        }
    }
}

/// The flip bit of a [`Bound`], as added to a face held in `f64`.
const FLIP: f64 = 2_147_483_648.0;

/// Working values of a packet's lanes, one place per lane, for the lanes
/// left to the scalar code.
#[derive(Clone, Copy)]
pub(crate) struct LaneValues(pub [f64; MAX_LANES]);

impl LaneValues {
    #[inline(always)]
    fn of<S: Simd>(s: S, x: S::F) -> LaneValues {
        let mut v = [0.0; MAX_LANES];
        s.store(x, &mut v);
        LaneValues(v)
    }
}

/// The rays of a packet's lanes, one by one, for the scalar code (the
/// values of the lanes, which are those of the rays they were made from).
#[inline(always)]
fn lane_rays<S: Simd>(s: S, r: &Lanes<S>) -> [Ray; MAX_LANES] {
    let c = [
        LaneValues::of(s, r.o[0]),
        LaneValues::of(s, r.o[1]),
        LaneValues::of(s, r.o[2]),
        LaneValues::of(s, r.d[0]),
        LaneValues::of(s, r.d[1]),
        LaneValues::of(s, r.d[2]),
        LaneValues::of(s, r.inv[0]),
        LaneValues::of(s, r.inv[1]),
        LaneValues::of(s, r.inv[2]),
    ];
    std::array::from_fn(|j| Ray {
        origin: DVec3::new(c[0].0[j], c[1].0[j], c[2].0[j]),
        dir: DVec3::new(c[3].0[j], c[4].0[j], c[5].0[j]),
        inv_dir: DVec3::new(c[6].0[j], c[7].0[j], c[8].0[j]),
    })
}

impl Prepared {
    /// [`Prepared::consider`] of zone `zi` for the lanes of `m`.
    #[inline(always)]
    fn consider_lanes<S: Simd>(
        &self,
        s: S,
        zi: u32,
        r: &Lanes<S>,
        m: S::M,
        b: &mut NearestHit<S>,
        sc: &mut Scratch,
    ) {
        let z = &self.zones[zi as usize];
        let m = s.and(m, box_lanes(s, &z.bounds, r, b.tmin, b.limit));
        if !s.any(m) {
            return;
        }
        if z.is_filled() {
            self.consider_filled_lanes(s, zi, r, m, b, sc);
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
            // The scalar code's answers written over the lanes'.
            let mut ends = [
                LaneValues::of(s, sp.a.t),
                LaneValues::of(s, sp.a.body),
                LaneValues::of(s, sp.a.face),
            ];
            let found = self.spans_one_by_one(
                z,
                &lane_rays(s, r),
                left,
                &LaneValues::of(s, b.limit),
                LaneValues::of(s, b.tmin).0[0],
                sc,
                &mut ends,
            );
            sp.a = End {
                t: s.load(&ends[0].0),
                body: s.load(&ends[1].0),
                face: s.load(&ends[2].0),
            };
            valid = s.or(valid, s.mask(found));
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

    /// [`Prepared::consider_lanes`] of filled zone `zi` for the lanes of
    /// `m`, one ray at a time by the scalar code: what fills a region is
    /// traced in its own frame.
    #[inline(never)]
    fn consider_filled_lanes<S: Simd>(
        &self,
        s: S,
        zi: u32,
        r: &Lanes<S>,
        m: S::M,
        b: &mut NearestHit<S>,
        sc: &mut Scratch,
    ) {
        let rays = lane_rays(s, r);
        let tmin = LaneValues::of(s, b.tmin).0[0];
        let [mut t, mut region, mut zone, mut limit] =
            [b.t, b.region, b.zone, b.limit].map(|x| LaneValues::of(s, x));
        let [mut at, mut body, mut face] =
            [b.a.t, b.a.body, b.a.face].map(|x| LaneValues::of(s, x));
        let (lanes, mut inside) = (s.bits(m), s.bits(b.inside));
        for (j, ray) in rays.iter().enumerate().take(S::LANES) {
            if lanes & (1 << j) == 0 {
                continue;
            }
            let mut best = Hit {
                t: t.0[j],
                region: region.0[j] as u32,
                bound: Bound::from_parts(at.0[j], body.0[j] as u32, face.0[j] as u32),
                inside: inside & (1 << j) != 0,
                zone: zone.0[j] as u32,
            };
            sc.new_ray();
            self.consider(zi, ray, tmin, &mut limit.0[j], &mut best, sc);
            t.0[j] = best.t;
            region.0[j] = f64::from(best.region);
            zone.0[j] = f64::from(best.zone);
            at.0[j] = best.bound.t;
            body.0[j] = f64::from(best.bound.body);
            face.0[j] = f64::from(best.bound.face_flip());
            inside = (inside & !(1 << j)) | (u32::from(best.inside) << j);
        }
        (b.t, b.region, b.zone, b.limit) = (
            s.load(&t.0),
            s.load(&region.0),
            s.load(&zone.0),
            s.load(&limit.0),
        );
        b.a = End {
            t: s.load(&at.0),
            body: s.load(&body.0),
            face: s.load(&face.0),
        };
        b.inside = s.mask(inside);
    }

    /// The zone's first span (its entry: distance, body, face) for the rays
    /// of `lanes` by the scalar code, one ray at a time, written into those
    /// lanes of `ends`; the lanes that have one.
    #[allow(clippy::too_many_arguments)]
    #[inline(never)]
    fn spans_one_by_one(
        &self,
        z: &PreparedZone,
        rays: &[Ray; MAX_LANES],
        lanes: u32,
        limit: &LaneValues,
        tmin: f64,
        sc: &mut Scratch,
        ends: &mut [LaneValues; 3],
    ) -> u32 {
        let mut found = 0;
        for (j, ray) in rays.iter().enumerate() {
            if lanes & (1 << j) == 0 {
                continue;
            }
            sc.new_ray();
            if self.zone_spans(z, ray, tmin, limit.0[j], sc) {
                let e = sc.cur[0].a;
                ends[0].0[j] = e.t;
                ends[1].0[j] = f64::from(e.body);
                ends[2].0[j] = f64::from(e.face_flip());
                found |= 1 << j;
            }
        }
        found
    }

    /// [`Prepared::zone_spans`]' first span for the lanes of `m`, for a
    /// zone of [`PreparedZone::lanes`]: the span, the lanes that have one, and the
    /// lanes left to the scalar code (where the `-` bodies would leave more
    /// than two spans, or a faceted body more than one segment).
    #[inline(always)]
    fn zone_lanes<S: Simd>(
        &self,
        s: S,
        z: &PreparedZone,
        r: &Lanes<S>,
        m: S::M,
        lo: S::F,
        hi: S::F,
    ) -> (SpanLanes<S>, S::M, S::M) {
        let mut none = LaneCasts::NONE;
        let spans = self.zone_lanes_spans::<S, false>(s, z, r, m, lo, hi, &mut none);
        let (in_cur, in_next) = spans.within(s, lo, hi);
        (
            pick_span(s, in_next, spans.next, spans.cur),
            s.or(in_cur, in_next),
            spans.more,
        )
    }

    /// [`Prepared::zone_spans`]' spans for the lanes of `m`, for a zone of
    /// [`PreparedZone::lanes`], before they are cut to `(lo, hi)`: one or
    /// two in each lane, and the lanes left to the scalar code (where the
    /// `-` bodies would leave more than two, or a faceted body more than
    /// one segment). Each step is
    /// [`Prepared::convex_spans`]' for one span and one segment, or the
    /// lists' for two spans and one segment. When `KEEP`, a body already
    /// cast for the packet under way is taken from `held`, and one cast
    /// is kept there.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn zone_lanes_spans<S: Simd, const KEEP: bool>(
        &self,
        s: S,
        z: &PreparedZone,
        r: &Lanes<S>,
        m: S::M,
        lo: S::F,
        hi: S::F,
        held: &mut LaneCasts,
    ) -> ZoneLanes<S> {
        let (plus, minus) = self.zone_terms(z).split_at(z.plus as usize);
        let tol = s.splat(self.tol);
        let mut alive = m;
        // The lanes left to the scalar code.
        let mut more = s.none();
        let mut cur: Option<SpanLanes<S>> = None;
        // A lane may hold two spans, as the lists would: `cur`, and `next`
        // in the lanes of `two`. A third goes to the scalar code.
        let (mut two, mut next) = (s.none(), None);
        let first_shape = plus.first().map(|&b| &self.shapes[b as usize]);
        if let ([b], Some(Shape::Torus(torus))) = (plus, first_shape) {
            // A lone torus: its two segments, where a ray crosses the
            // tube twice, are the zone's two spans before the `-` bodies.
            let [g, h] = torus.shoot_lanes_both(s, r, alive);
            let (first, second) = (span(s, &g, *b), span(s, &h, *b));
            let in_first = s.and(s.and(alive, g.hit), within(s, &first, lo, hi));
            let in_second = s.and(s.and(alive, h.hit), within(s, &second, lo, hi));
            alive = s.or(in_first, in_second);
            two = s.and(in_first, in_second);
            cur = Some(pick_span(s, in_first, first, second));
            next = Some(second);
        }
        // The `+` bodies of one segment a lane, intersected one by one.
        for &b in plus.iter().filter(|_| next.is_none()) {
            // A lone `+` body has the zone's bounds, which the rays meet.
            if plus.len() > 1 {
                let inf = s.splat(f64::INFINITY);
                let bounds = &self.body_bounds[b as usize];
                alive = s.and(alive, box_lanes(s, bounds, r, s.neg(inf), inf));
            }
            let g = cast_lanes::<S, KEEP>(s, held, b, &self.shapes[b as usize], r);
            more = s.or(more, s.and(alive, g.scalar));
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
            let none = SpanLanes { a: z0, b: z0 };
            return ZoneLanes {
                cur: none,
                next: none,
                alive: s.none(),
                two: s.none(),
                more,
            };
        };
        let mut next = next.unwrap_or(cur);
        for &b in minus {
            // The reach of the lane's spans, as the lists see it.
            let last = s.select(two, next.b.t, cur.b.t);
            let mm = s.and(
                alive,
                box_lanes(s, &self.body_bounds[b as usize], r, cur.a.t, last),
            );
            if !s.any(mm) {
                continue;
            }
            let shape = &self.shapes[b as usize];
            if !shape.has_lanes() {
                // A body the lanes cannot cast (a torus, say): the rays
                // that meet its box go to the scalar code.
                more = s.or(more, mm);
                alive = s.andnot(alive, mm);
                if !s.any(alive) {
                    break;
                }
                continue;
            }
            let g = cast_lanes::<S, KEEP>(s, held, b, shape, r);
            let scalar = s.and(mm, g.scalar);
            if s.any(scalar) {
                more = s.or(more, scalar);
                alive = s.andnot(alive, scalar);
                if !s.any(alive) {
                    break;
                }
            }
            // The segment reaches past the spans' start and begins before
            // their end.
            let mm = s.andnot(
                s.and(mm, g.hit),
                s.or(s.ge(g.t0, last), s.le(g.t1, cur.a.t)),
            );
            if !s.any(mm) {
                continue;
            }
            let c = span(s, &g, b);
            let first = subtract_span(s, cur, c, mm, tol);
            if !s.any(two) {
                alive = s.and(alive, first.some);
                (cur, next, two) = (first.one, first.other, first.both);
            } else {
                let second = subtract_span(s, next, c, s.and(mm, two), tol);
                let (some2, both2) = (s.and(two, second.some), s.and(two, second.both));
                // The spans left, in order: the first's, then the second's.
                let three = s.or(s.and(first.both, some2), s.and(first.some, both2));
                more = s.or(more, s.and(alive, three));
                alive = s.andnot(s.and(alive, s.or(first.some, some2)), three);
                let one_and_one = s.and(s.andnot(first.some, first.both), s.andnot(some2, both2));
                two = s.and(
                    alive,
                    s.or(
                        s.or(s.andnot(first.both, some2), one_and_one),
                        s.andnot(both2, first.some),
                    ),
                );
                next = pick_span(
                    s,
                    first.both,
                    first.other,
                    pick_span(s, first.some, second.one, second.other),
                );
                cur = pick_span(s, first.some, first.one, second.one);
            }
            if !s.any(alive) {
                break;
            }
        }
        ZoneLanes {
            cur,
            next,
            alive,
            two,
            more,
        }
    }
}

/// Body `b` (shape `shape`) cast along the rays `r` of the packet under
/// way: when `KEEP`, taken from `held` if it was cast for the packet
/// already.
#[inline(always)]
fn cast_lanes<S: Simd, const KEEP: bool>(
    s: S,
    held: &mut LaneCasts,
    b: u32,
    shape: &Shape,
    r: &Lanes<S>,
) -> SegLanes<S> {
    if KEEP {
        held.cast(s, b, shape, r)
    } else {
        shape.shoot_lanes(s, r)
    }
}

/// The bodies cast in the lanes for the packet under way, kept until the
/// next: a body that several zones share (one region's `+` body is often
/// subtracted from its neighbours) is cast once a packet, not once a zone.
/// The same operations on the same rays, so the same segments to the bit.
#[derive(Clone, Debug)]
pub(crate) struct LaneCasts {
    /// The packet under way, counted from 1 (0 marks a body cast for
    /// none yet).
    packet: u32,
    /// Per body: the packet it was last cast for, and where in `casts`
    /// ([`LaneCasts::ALONE`] for a body only one zone casts).
    of_body: Vec<[u32; 2]>,
    /// Per zone: whether it casts a body that another zone casts too.
    shares: Vec<bool>,
    casts: Vec<HeldCast>,
    /// How many of `casts` the packet under way holds.
    used: usize,
}

/// One body's segments in the lanes: entry, exit and their faces, and the
/// lanes that meet it and those left to the scalar code.
#[derive(Clone, Debug)]
struct HeldCast {
    ends: [[f64; MAX_LANES]; 4],
    hit: u32,
    scalar: u32,
}

impl LaneCasts {
    /// Room for the casts of the bodies of `p` that zones cast in the
    /// lanes share; the others are cast as they come.
    pub(crate) fn new(p: &Prepared) -> LaneCasts {
        let mut zones_of_body = vec![0u32; p.shapes.len()];
        for z in p.zones.iter().filter(|z| z.lanes) {
            for &b in p.zone_terms(z) {
                zones_of_body[b as usize] += 1;
            }
        }
        let of_body: Vec<[u32; 2]> = zones_of_body
            .iter()
            .map(|&zones| [if zones > 1 { 0 } else { Self::ALONE }, 0])
            .collect();
        let shares = p
            .zones
            .iter()
            .map(|z| {
                let shared = |&b: &u32| of_body[b as usize][0] != Self::ALONE;
                z.lanes && p.zone_terms(z).iter().any(shared)
            })
            .collect();
        LaneCasts {
            packet: 1,
            of_body,
            shares,
            casts: Vec::new(),
            used: 0,
        }
    }

    /// None held, for the callers that keep no casts.
    const NONE: LaneCasts = LaneCasts {
        packet: 0,
        of_body: Vec::new(),
        shares: Vec::new(),
        casts: Vec::new(),
        used: 0,
    };

    /// The packet that marks a body only one zone casts in the lanes:
    /// never kept.
    const ALONE: u32 = u32::MAX;

    /// Whether zone `zi` casts a body that another zone casts too.
    #[inline(always)]
    pub(crate) fn shares(&self, zi: u32) -> bool {
        self.shares[zi as usize]
    }

    /// Forget the last packet's casts.
    pub(crate) fn new_packet(&mut self) {
        self.packet += 1;
        if self.packet == Self::ALONE {
            for of in &mut self.of_body {
                if of[0] != Self::ALONE {
                    of[0] = 0;
                }
            }
            self.packet = 1;
        }
        self.used = 0;
    }

    /// [`Shape::shoot_lanes`] of body `b` (shape `shape`) along `r`, the
    /// rays of the packet under way.
    #[inline(always)]
    fn cast<S: Simd>(&mut self, s: S, b: u32, shape: &Shape, r: &Lanes<S>) -> SegLanes<S> {
        let [packet, at] = self.of_body[b as usize];
        if packet == self.packet {
            let held = &self.casts[at as usize];
            return SegLanes {
                t0: s.load(&held.ends[0]),
                t1: s.load(&held.ends[1]),
                f0: s.load(&held.ends[2]),
                f1: s.load(&held.ends[3]),
                hit: s.mask(held.hit),
                scalar: s.mask(held.scalar),
            };
        }
        let g = shape.shoot_lanes(s, r);
        if packet == Self::ALONE {
            return g;
        }
        if self.used == self.casts.len() {
            self.casts.push(HeldCast {
                ends: [[0.0; MAX_LANES]; 4],
                hit: 0,
                scalar: 0,
            });
        }
        let held = &mut self.casts[self.used];
        s.store(g.t0, &mut held.ends[0]);
        s.store(g.t1, &mut held.ends[1]);
        s.store(g.f0, &mut held.ends[2]);
        s.store(g.f1, &mut held.ends[3]);
        (held.hit, held.scalar) = (s.bits(g.hit), s.bits(g.scalar));
        self.of_body[b as usize] = [self.packet, self.used as u32];
        self.used += 1;
        g
    }
}

/// A zone's spans in every lane ([`Prepared::zone_lanes_spans`]): `cur`
/// in the lanes of `alive`, then `next` in those of `two`; the lanes of
/// `more` are left to the scalar code.
struct ZoneLanes<S: Simd> {
    cur: SpanLanes<S>,
    next: SpanLanes<S>,
    alive: S::M,
    two: S::M,
    more: S::M,
}

impl<S: Simd> ZoneLanes<S> {
    /// The lanes where the first span reaches into `(lo, hi)`, and those
    /// where the second does and the first does not.
    #[inline(always)]
    fn within(&self, s: S, lo: S::F, hi: S::F) -> (S::M, S::M) {
        let in_cur = s.and(self.alive, within(s, &self.cur, lo, hi));
        let in_next = s.andnot(
            s.and(s.and(self.alive, self.two), within(s, &self.next, lo, hi)),
            in_cur,
        );
        (in_cur, in_next)
    }
}

/// What is left of span `p` less span `c` in the lanes of `m` (elsewhere
/// `p` as it was): [`sv_geom::boolean::subtract_with`]'s step for one span and
/// one segment that meets it.
#[inline(always)]
fn subtract_span<S: Simd>(
    s: S,
    p: SpanLanes<S>,
    c: SpanLanes<S>,
    m: S::M,
    tol: S::F,
) -> SpanRemainder<S> {
    // Only where the segment reaches into the span.
    let m = s.and(m, s.and(s.gt(c.b.t, p.a.t), s.lt(c.a.t, p.b.t)));
    let start = p.a;
    let before = s.and(s.gt(c.a.t, start.t), s.gt(s.sub(c.a.t, start.t), tol));
    let after_start = pick(s, s.gt(c.b.t, start.t), flip(s, c.b), start);
    let after = s.gt(s.sub(p.b.t, after_start.t), tol);
    let (before_span, after_span) = (
        SpanLanes {
            a: start,
            b: flip(s, c.a),
        },
        SpanLanes {
            a: after_start,
            b: p.b,
        },
    );
    SpanRemainder {
        one: pick_span(s, m, pick_span(s, before, before_span, after_span), p),
        other: after_span,
        some: s.or(not(s, m), s.or(before, after)),
        both: s.and(m, s.and(before, after)),
    }
}

/// A span less a segment, in every lane: none, one (`one`) or two (`one`
/// then `other`) spans.
struct SpanRemainder<S: Simd> {
    one: SpanLanes<S>,
    other: SpanLanes<S>,
    /// Lanes with one span or two.
    some: S::M,
    /// Lanes with two.
    both: S::M,
}

/// The lanes where span `sp` reaches into `(lo, hi)`.
#[inline(always)]
fn within<S: Simd>(s: S, sp: &SpanLanes<S>, lo: S::F, hi: S::F) -> S::M {
    s.and(s.gt(sp.b.t, lo), s.lt(sp.a.t, hi))
}

/// `if c { x } else { y }` of whole spans, lane by lane.
#[inline(always)]
fn pick_span<S: Simd>(s: S, c: S::M, x: SpanLanes<S>, y: SpanLanes<S>) -> SpanLanes<S> {
    SpanLanes {
        a: pick(s, c, x.a, y.a),
        b: pick(s, c, x.b, y.b),
    }
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

/// The end of a subtracted body ([`sv_geom::boolean::flipped`] of an end
/// from a shot, which has no flip bit).
#[inline(always)]
fn flip<S: Simd>(s: S, e: End<S>) -> End<S> {
    End {
        face: s.add(e.face, s.splat(FLIP)),
        ..e
    }
}
