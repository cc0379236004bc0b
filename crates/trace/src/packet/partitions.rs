//! Every region's stretches along rays that share a list of zones (the
//! grid rays of a check along one row), several rays at once: each zone's
//! box is tested and its spans made for all the lanes together, and a zone
//! the lanes cannot make, or a lane that would hold more than two spans,
//! goes to the scalar code.

use super::primary::lanes_of;
use super::{within, End, RaysShare, SpanLanes};
use crate::hit::{leave_empty_if_repeat, leave_repeats_empty, Partition, Scratch};
use crate::prepare::Prepared;
use crate::query::{insert_by_entry, insert_spans};
use sv_geom::boolean::{Bound, Span};
use sv_math::lanes::{box_lanes, Lanes, MAX_LANES};
use sv_math::simd::Simd;
use sv_math::Ray;

/// [`partitions_any`] or [`stretches_any`].
type PacketsOfRays = fn(
    &Prepared,
    &[u32],
    (&[Ray], RaysShare),
    f64,
    f64,
    &mut Scratch,
    &mut [Vec<Partition>],
) -> Option<u64>;

impl Prepared {
    /// [`Prepared::partitions_in`] for each of `rays`, into the same
    /// places of `out`: `zones` must hold every zone whose bounds any of
    /// them meets within `(tmin, tmax)`. Several rays at once where the
    /// processor has vector instructions for it; the same stretches, bit
    /// for bit, as the rays give one by one.
    pub fn partitions_of_rays_in(
        &self,
        zones: &[u32],
        rays: &[Ray],
        tmin: f64,
        tmax: f64,
        s: &mut Scratch,
        out: &mut [Vec<Partition>],
    ) {
        // Partitions with their bodies are never left as the ray before's.
        let rays = (rays, RaysShare::Unknown);
        self.partitions_of_rays_with(partitions_any, zones, rays, (tmin, tmax), s, out);
    }

    /// [`Prepared::partitions_of_rays_in`] when only the regions and the
    /// distances matter (a check's classification): the same regions and
    /// distances, bit for bit, but the ends' bodies and faces are not
    /// kept where the lanes made a stretch (they read 0 there), which
    /// spares the packets carrying them.
    ///
    /// Returns the rays (bit `k` for ray `k`, of the first 64) whose
    /// stretches are those of the ray before them, to the bit: their
    /// lists in `out` are left empty. Neighbouring rays of a row often
    /// cross the same faces, square to them, at the same distances. Every
    /// ray but the first is compared with the ray before: in the lanes,
    /// or once made where the lanes cannot (the first of a vector, or
    /// every ray where there are no lanes here).
    ///
    /// `share` says what the rays share, to the bit (a check's rays fired
    /// together share their direction, and a row's all but one
    /// coordinate): the lanes take it from the first ray unread.
    pub fn stretches_of_rays_in(
        &self,
        zones: &[u32],
        (rays, share): (&[Ray], RaysShare),
        tmin: f64,
        tmax: f64,
        s: &mut Scratch,
        out: &mut [Vec<Partition>],
    ) -> u64 {
        debug_assert!(
            share.holds_for(rays),
            "rays do not share what {share:?} says"
        );
        let count = rays.len();
        let rays = (rays, share);
        self.partitions_of_rays_with(stretches_any, zones, rays, (tmin, tmax), s, out)
            .unwrap_or_else(|| leave_repeats_empty(&mut out[..count]))
    }

    /// The partitions of `rays` by `packets` where the processor has
    /// vector instructions for it, and the rays whose stretches were left
    /// as the ray before's (see [`Prepared::stretches_of_rays_in`]); else
    /// ray by ray, and `None`.
    fn partitions_of_rays_with(
        &self,
        packets: PacketsOfRays,
        zones: &[u32],
        (rays, share): (&[Ray], RaysShare),
        (tmin, tmax): (f64, f64),
        s: &mut Scratch,
        out: &mut [Vec<Partition>],
    ) -> Option<u64> {
        assert!(
            out.len() >= rays.len(),
            "a list of partitions for every ray"
        );
        let packets_of = (rays, share);
        if let Some(repeats) = packets(self, zones, packets_of, tmin, tmax, s, out) {
            return Some(repeats);
        }
        for (ray, parts) in rays.iter().zip(out) {
            self.partitions_in(zones, ray, tmin, tmax, s, parts);
        }
        None
    }

    /// [`Prepared::partitions_of_rays_in`] in packets of `S::LANES` rays
    /// when `BODIES`, else [`Prepared::stretches_of_rays_in`]: the ends'
    /// bodies and faces are kept only when `BODIES`, and rays' stretches
    /// are left as the ray before's only when not. What `share` says the
    /// rays share is taken from the first ray.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub(crate) fn packet_partitions<S: Simd, const BODIES: bool>(
        &self,
        s: S,
        zones: &[u32],
        (rays, share): (&[Ray], RaysShare),
        tmin: f64,
        tmax: f64,
        sc: &mut Scratch,
        out: &mut [Vec<Partition>],
    ) -> u64 {
        let mut held = HeldSpans::default();
        let mut repeats = 0;
        for (at, (packet, parts)) in rays
            .chunks(S::LANES)
            .zip(out.chunks_mut(S::LANES))
            .enumerate()
        {
            let r = lanes_of(s, packet, share);
            sc.lane_casts.new_packet();
            let active = (1u32 << packet.len()) - 1;
            parts.iter_mut().for_each(Vec::clear);
            // Every lane but the first sees what the lane before it sees
            // until a zone tells them apart (only the first 64 rays can be
            // answered so).
            let answered = (at + 1) * S::LANES <= 64;
            held.alike = if BODIES || !answered { 0 } else { active & !1 };
            held.filling = false;
            for &zi in zones {
                let rays = (&r, packet);
                self.tag_zone_lanes::<S, BODIES>(
                    s,
                    zi,
                    rays,
                    active,
                    (tmin, tmax),
                    sc,
                    parts,
                    &mut held,
                );
            }
            held.hand_out::<BODIES>(parts);
            let mut made = active & !held.alike;
            while made != 0 {
                let j = made.trailing_zeros() as usize;
                made &= made - 1;
                // One stretch or none is its own union.
                if parts[j].len() > 1 {
                    self.union_in_place(&mut parts[j]);
                }
            }
            if held.alike != 0 {
                repeats |= u64::from(held.alike) << (at * S::LANES);
            }
        }
        if !BODIES {
            // The lanes compare rays within a vector: the first of each
            // vector after the first is compared with the ray before once
            // made (with the last one made before it).
            for first in (S::LANES..rays.len().min(64)).step_by(S::LANES) {
                repeats = leave_empty_if_repeat(out, first, repeats);
            }
        }
        repeats
    }

    /// The spans of zone `zi` along the rays of the lanes of `active`
    /// (`r` in lanes, `rays` one by one) that reach into `(tmin, tmax)`,
    /// added to each lane's stretches in `parts` (by
    /// [`insert_by_entry`]) with the zone's region: those made one by one
    /// at once, those made in the lanes held in `held` until the next zone
    /// a lane meets (or the packet's end).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn tag_zone_lanes<S: Simd, const BODIES: bool>(
        &self,
        s: S,
        zi: u32,
        (r, rays): (&Lanes<S>, &[Ray]),
        active: u32,
        (tmin, tmax): (f64, f64),
        sc: &mut Scratch,
        parts: &mut [Vec<Partition>],
        held: &mut HeldSpans,
    ) {
        let z = &self.zones[zi as usize];
        let (lo, hi) = (s.splat(tmin), s.splat(tmax));
        let m = s.and(s.mask(active), box_lanes(s, &z.bounds, r, lo, hi));
        let met = s.bits(m);
        if met == 0 {
            return;
        }
        // The last zone's spans go first, so that each lane's spans stay
        // in the order of the zones.
        held.hand_out::<BODIES>(parts);
        let mut one_by_one = met;
        if z.lanes && !z.is_filled() {
            // Only a zone that shares a body with another looks its
            // bodies up: the look-ups would cost the others.
            let casts = &mut sc.lane_casts;
            let spans = if casts.shares(zi) {
                self.zone_lanes_spans::<S, true>(s, z, r, m, lo, hi, casts)
            } else {
                self.zone_lanes_spans::<S, false>(s, z, r, m, lo, hi, casts)
            };
            one_by_one = s.bits(spans.more);
            // A lane left to the scalar code gets its spans there only.
            let alive = s.andnot(spans.alive, spans.more);
            let first = s.bits(s.and(alive, within(s, &spans.cur, lo, hi)));
            let second = s.bits(s.and(s.and(alive, spans.two), within(s, &spans.next, lo, hi)));
            if first | second != 0 {
                held.hold::<S, BODIES>(s, z.region, (first, &spans.cur), (second, &spans.next));
            }
        }
        if one_by_one == 0 {
            return;
        }
        // The lanes' stretches are all made from here on.
        held.make_alike(parts);
        for (j, (ray, lane)) in rays.iter().zip(parts.iter_mut()).enumerate() {
            if one_by_one & (1 << j) == 0 {
                continue;
            }
            sc.new_ray();
            if z.is_filled() {
                self.fill_partitions(z, ray, tmin, tmax, sc, lane);
            } else if self.zone_spans(z, ray, tmin, tmax, sc) {
                insert_spans(lane, z.region, &sc.cur);
            }
        }
    }
}

/// The spans a zone left in the lanes, held lane by lane until they are
/// handed out to the lanes' lists: read back at once, the values just
/// stored from the vectors would wait for the stores to reach the cache.
///
/// A lane that has met the same spans as the lane before it, to the bit,
/// is not handed them: its list is not made (it would be the same) until
/// a zone tells the two apart, when it starts as a copy of the list of the
/// lane it matched, as it stood.
#[derive(Default)]
struct HeldSpans {
    region: u32,
    /// The lanes whose first span, and whose second, are held.
    first: u32,
    second: u32,
    /// The two spans' ends: distance, body and face of each end.
    cur: [[f64; MAX_LANES]; 6],
    next: [[f64; MAX_LANES]; 6],
    /// While lanes are not made: the lanes (from the second on) whose
    /// first span, and whose second, do not end where the lane before's
    /// do, to the bit (whatever each lane holds).
    cur_apart: u32,
    next_apart: u32,
    /// The lanes whose lists are not made: each has met what the lane
    /// before it met.
    alike: u32,
    /// Whether any list of the packet holds something.
    filling: bool,
}

impl HeldSpans {
    /// Hold the spans `cur` of the lanes of `first` and `next` of those
    /// of `second`, of region `region`.
    #[inline(always)]
    fn hold<S: Simd, const BODIES: bool>(
        &mut self,
        s: S,
        region: u32,
        (first, cur): (u32, &SpanLanes<S>),
        (second, next): (u32, &SpanLanes<S>),
    ) {
        self.region = region;
        (self.first, self.second) = (first, second);
        store_span::<S, BODIES>(s, cur, &mut self.cur);
        if second != 0 {
            store_span::<S, BODIES>(s, next, &mut self.next);
        }
        // Compared in the vectors, before they are stored: lanes not made
        // only become fewer until the spans are handed out.
        if self.alike != 0 {
            let apart = |sp: &SpanLanes<S>| {
                s.differ_from_lane_before(sp.a.t) | s.differ_from_lane_before(sp.b.t)
            };
            self.cur_apart = apart(cur);
            if second != 0 {
                self.next_apart = apart(next);
            }
        }
    }

    /// Add the spans held to their lanes' stretches, and hold none.
    #[inline(always)]
    fn hand_out<const BODIES: bool>(&mut self, parts: &mut [Vec<Partition>]) {
        let (first, second) = (self.first, self.second);
        if first | second == 0 {
            return;
        }
        if self.alike != 0 {
            self.part_lanes(parts);
        }
        self.filling |= (first | second) & !self.alike != 0;
        // Each lane's first span before its second (which lie in order).
        for (mut lanes, ends) in [(first, &self.cur), (second, &self.next)] {
            lanes &= !self.alike;
            while lanes != 0 {
                let j = lanes.trailing_zeros() as usize;
                lanes &= lanes - 1;
                let (region, span) = (self.region, lane_span::<BODIES>(ends, j));
                insert_by_entry(&mut parts[j], Partition { region, span });
            }
        }
        (self.first, self.second) = (0, 0);
    }

    /// Make the lists of the lanes not made whose spans held differ from
    /// the lane before's, before those are handed out: a lane holding
    /// more or fewer spans than the lane before, or spans whose ends are
    /// not the same to the bit. Worked out for all lanes at once, as
    /// masks: lane by lane, which lanes part is not predictable.
    #[inline(always)]
    fn part_lanes(&mut self, parts: &mut [Vec<Partition>]) {
        let (first, second) = (self.first, self.second);
        let mut apart = self.alike & ((first ^ first << 1) | (second ^ second << 1));
        // The rest hold as many spans as the lane before.
        let left = self.alike & !apart;
        apart |= left & (first & self.cur_apart | second & self.next_apart);
        self.make(apart, parts);
    }

    /// Make the lists of the lanes of `lanes` (of those not made): each a
    /// copy of the list of the nearest lane before it that is made.
    #[inline(always)]
    fn make(&mut self, mut lanes: u32, parts: &mut [Vec<Partition>]) {
        if !self.filling {
            self.alike &= !lanes;
            return;
        }
        while lanes != 0 {
            let j = lanes.trailing_zeros() as usize;
            lanes &= lanes - 1;
            let made_before = !self.alike & ((1 << j) - 1);
            let from = 31 - made_before.leading_zeros() as usize;
            // A lane not made holds nothing: only a list with something
            // in it is copied.
            let (before, after) = parts.split_at_mut(j);
            if !before[from].is_empty() {
                after[0].extend_from_slice(&before[from]);
            }
            self.alike &= !(1 << j);
        }
    }

    /// Make every lane's list as it stands: spans made one by one are
    /// about to be added to some.
    #[inline(always)]
    fn make_alike(&mut self, parts: &mut [Vec<Partition>]) {
        self.make(self.alike, parts);
    }
}

/// Store the ends of span `sp` of every lane into `out`: distance, and
/// when `BODIES`, body and face of each end. Written out, without a
/// closure: one would stay a call outside the instruction set the packet
/// is compiled for.
#[inline(always)]
fn store_span<S: Simd, const BODIES: bool>(
    s: S,
    sp: &SpanLanes<S>,
    out: &mut [[f64; MAX_LANES]; 6],
) {
    let (End { t, body, face }, b) = (sp.a, sp.b);
    s.store(t, &mut out[0]);
    s.store(b.t, &mut out[3]);
    if BODIES {
        s.store(body, &mut out[1]);
        s.store(face, &mut out[2]);
        s.store(b.body, &mut out[4]);
        s.store(b.face, &mut out[5]);
    }
}

/// The span of lane `j` of the ends stored by [`store_span`] (bodies and
/// faces 0 unless `BODIES`).
#[inline(always)]
fn lane_span<const BODIES: bool>(ends: &[[f64; MAX_LANES]; 6], j: usize) -> Span {
    let v = |k: usize| ends[k][j];
    let id = |k: usize| if BODIES { v(k) as u32 } else { 0 };
    Span {
        a: Bound::from_parts(v(0), id(1), id(2)),
        b: Bound::from_parts(v(3), id(4), id(5)),
    }
}

compiled_for_each! {
    fn partitions_avx512, partitions_avx2, partitions_any => packet_partitions::<_, true>(
        zones: &[u32],
        rays: (&[Ray], RaysShare),
        tmin: f64,
        tmax: f64,
        s: &mut Scratch,
        out: &mut [Vec<Partition>],
    ) -> u64
}

compiled_for_each! {
    fn stretches_avx512, stretches_avx2, stretches_any => packet_partitions::<_, false>(
        zones: &[u32],
        rays: (&[Ray], RaysShare),
        tmin: f64,
        tmax: f64,
        s: &mut Scratch,
        out: &mut [Vec<Partition>],
    ) -> u64
}
