//! Shadow rays toward a parallel light, in packets.

use super::LaneValues;
use crate::hit::Scratch;
use crate::lightbuf::{Grid, LightBuffer, Place};
use crate::prepare::Prepared;
use sv_math::lanes::{box_lanes, dot, splat3, Lanes, MAX_LANES};
use sv_math::simd::Simd;
use sv_math::{DVec3, Ray};

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
    /// changes nothing; the rays that start in one cell ask for its list
    /// once, for the one of them farthest from the light, whose list holds the
    /// others'.
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
        if occluded_any(self, buf, from, tmin, last, s, out).is_some() {
            return;
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
        let grid = buf.grid();
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
            sc.new_packet();
            let active = (1u32 << chunk.len()) - 1;
            let (mut blocked, mut blocker) = (0, None);
            // The zone that blocked the last shadow ray first: neighbouring
            // points are mostly shadowed by the same zone. (No closure for
            // the zone's test: its intrinsics would stay calls.)
            if let Some(zi) = *last {
                sc.tested[zi as usize] = sc.packet;
                let b = self.blocks(s, zi, &r, &along, chunk, active, skip, tmin, sc);
                if b != 0 {
                    (blocked, blocker) = (b, Some(zi));
                }
            }
            // The lanes in a cell together: the cell's zones, listed for
            // the lane farthest from the light (the longest list), tried once.
            // Each lane's place as `LightBuffer::place` finds it, operation
            // for operation: the cell's number (or -1 off the grid, -2 for a
            // point that is not a number) and the depth.
            let (cell, depth) = places(s, &grid, &r);
            // A depth that is not a number (an origin far off at infinity)
            // lists every zone, as it does for the ray alone.
            let depth = s.select(s.eq(depth, depth), depth, s.splat(f64::NEG_INFINITY));
            let cells = LaneValues::of(s, cell);
            let mut todo = active;
            while todo != 0 {
                let j = todo.trailing_zeros() as usize;
                let c = cells.0[j];
                let group = todo & s.bits(s.eq(cell, s.splat(c)));
                todo &= !group;
                if group & !blocked == 0 {
                    continue;
                }
                if c == NOWHERE {
                    // A point that is not a number: the full search decides.
                    for (k, &(p, skip_k)) in chunk.iter().enumerate() {
                        if group & !blocked & (1 << k) != 0
                            && self.occluded(&buf.shadow_ray(p), tmin, f64::INFINITY, skip_k, sc)
                        {
                            blocked |= 1 << k;
                        }
                    }
                    continue;
                }
                let place = if c == OFF {
                    Place::Off
                } else {
                    Place::Cell(c as u32)
                };
                let farthest = s.min_lane(s.select(s.mask(group), depth, s.splat(f64::INFINITY)));
                let cands = buf.candidates(place, farthest);
                for zi in self.unbounded_opaque.iter().copied().chain(cands.all()) {
                    if sc.tested[zi as usize] == sc.packet {
                        continue;
                    }
                    sc.tested[zi as usize] = sc.packet;
                    let b =
                        self.blocks(s, zi, &r, &along, chunk, active & !blocked, skip, tmin, sc);
                    if b != 0 {
                        (blocked, blocker) = (blocked | b, Some(zi));
                        if group & !blocked == 0 {
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
    /// zone, in the lanes where the zone allows it, else by the scalar code
    /// (the rays `along` from each point of `from`).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn blocks<S: Simd>(
        &self,
        s: S,
        zi: u32,
        r: &Lanes<S>,
        along: &Ray,
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
            found |= self.blocks_one_by_one(zi, from, along, scalar, tmin, sc);
        }
        found
    }

    /// [`Prepared::blocks`] for the lanes of `lanes`, one ray at a time.
    #[inline(never)]
    fn blocks_one_by_one(
        &self,
        zi: u32,
        from: &[(DVec3, Option<u32>)],
        along: &Ray,
        lanes: u32,
        tmin: f64,
        sc: &mut Scratch,
    ) -> u32 {
        let mut found = 0;
        for (j, &(origin, _)) in from.iter().enumerate() {
            if lanes & (1 << j) == 0 {
                continue;
            }
            let ray = Ray { origin, ..*along };
            sc.new_ray();
            if self.zone_blocks(zi, &ray, tmin, f64::INFINITY, sc) {
                found |= 1 << j;
            }
        }
        found
    }
}

/// The cell number of a point off a light buffer's grid, in [`places`].
const OFF: f64 = -1.0;
/// The cell number of a point that is not a number, in [`places`].
const NOWHERE: f64 = -2.0;

/// Where the rays of `r` start on a light buffer's grid: each lane's cell
/// number ([`OFF`] or [`NOWHERE`] else) and depth, as
/// [`LightBuffer::place`] finds them, operation for operation.
#[inline(always)]
fn places<S: Simd>(s: S, g: &Grid, r: &Lanes<S>) -> (S::F, S::F) {
    let depth = dot(s, r.o, splat3(s, g.dir));
    let (a, b) = (dot(s, r.o, splat3(s, g.u)), dot(s, r.o, splat3(s, g.v)));
    let fa = s.mul(s.sub(a, s.splat(g.origin.0)), s.splat(g.scale.0));
    let fb = s.mul(s.sub(b, s.splat(g.origin.1)), s.splat(g.scale.1));
    let zero = s.splat(0.0);
    let on = s.and(
        s.and(s.ge(fa, zero), s.ge(fb, zero)),
        s.and(s.lt(fa, s.splat(g.cells.0)), s.lt(fb, s.splat(g.cells.1))),
    );
    // The cell's number: whole numbers below 2²⁴, exact in `f64`.
    let cell = s.add(s.mul(s.floor(fb), s.splat(g.cells.0)), s.floor(fa));
    let number = s.and(
        s.and(s.eq(r.o[0], r.o[0]), s.eq(r.o[1], r.o[1])),
        s.eq(r.o[2], r.o[2]),
    );
    let cell = s.select(on, cell, s.splat(OFF));
    (s.select(number, cell, s.splat(NOWHERE)), depth)
}

compiled_for_each! {
    fn occluded_avx512, occluded_avx2, occluded_any => occluded_in_packets(
        buf: &LightBuffer,
        from: &[(DVec3, Option<u32>)],
        tmin: f64,
        last: &mut Option<u32>,
        s: &mut Scratch,
        out: &mut [bool],
    )
}
