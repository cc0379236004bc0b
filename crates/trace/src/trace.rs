//! Ray queries: the first opaque region hit (front to back, lazily), any
//! hit (shadows), and the full list of region partitions along a ray.

use crate::bvh::{hits, Bvh, Stack};
use crate::prepare::{EnclosureRef, Prepared, PreparedZone};
use crate::raster::{entry_of, rect_of};
use sv_geom::boolean::{flipped, intersect_with, push_merged, subtract_with, Bound, Span};
use sv_geom::shape::Seg;
use sv_math::{Aabb, DVec3, Ray, RayGen};

/// Per-thread working memory. Reused from ray to ray, so tracing allocates
/// nothing once it has warmed up.
#[derive(Clone, Debug)]
pub struct Scratch {
    ray_id: u32,
    /// Per body: the ray it was last cast along and its segments' range in
    /// `segs` for that ray, side by side so that one look-up finds all
    /// three.
    cache: Vec<[u32; 3]>,
    segs: Vec<Seg>,
    pub(crate) cur: Vec<Span>,
    tmp: Vec<Span>,
    tagged: Vec<(u32, Span)>,
    stack: Stack,
    /// Per zone, the packet of shadow rays that last tested it, so that a
    /// packet tests each zone its rays' cells list once.
    pub(crate) tested: Vec<u32>,
    pub(crate) packet: u32,
}

impl Scratch {
    /// Working memory for `p`.
    pub fn new(p: &Prepared) -> Scratch {
        Scratch {
            ray_id: 0,
            cache: vec![[0; 3]; p.shapes.len()],
            segs: Vec::with_capacity(64),
            cur: Vec::with_capacity(16),
            tmp: Vec::with_capacity(16),
            tagged: Vec::new(),
            stack: Stack::new(),
            tested: vec![0; p.zones.len()],
            packet: 0,
        }
    }

    /// Begin a packet of shadow rays: no zone is yet tested for it.
    pub(crate) fn new_packet(&mut self) {
        self.packet = self.packet.wrapping_add(1);
        if self.packet == 0 {
            self.tested.iter_mut().for_each(|t| *t = 0);
            self.packet = 1;
        }
    }

    /// Forget the previous ray's cached body segments.
    pub(crate) fn new_ray(&mut self) {
        self.ray_id = self.ray_id.wrapping_add(1);
        if self.ray_id == 0 {
            self.cache.iter_mut().for_each(|c| c[0] = 0);
            self.ray_id = 1;
        }
        self.segs.clear();
    }
}

/// The first visible surface along a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Distance along the ray.
    pub t: f64,
    /// Region entered.
    pub region: u32,
    /// Surface crossed: body (prepared number, see
    /// [`Prepared::body_index`]), face and whether it was subtracted.
    pub bound: Bound,
    /// True when the ray started inside the region (no surface crossed).
    pub inside: bool,
    /// The zone of the region that was hit.
    pub zone: u32,
}

impl Hit {
    /// No hit: any hit found is better (region `u32::MAX` marks it).
    pub const NONE: Hit = Hit {
        t: f64::INFINITY,
        region: u32::MAX,
        bound: Bound::new(f64::INFINITY, u32::MAX, 0),
        inside: false,
        zone: u32::MAX,
    };

    /// False for [`Hit::NONE`].
    pub fn is_some(&self) -> bool {
        self.region != u32::MAX
    }
}

/// A stretch of the ray inside one region.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Partition {
    /// Region.
    pub region: u32,
    /// Entry and exit.
    pub span: Span,
}

/// One surface crossing along a ray (for `shoot`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossing {
    /// Distance along the ray.
    pub t: f64,
    /// Entering (true) or leaving the region.
    pub entering: bool,
    /// Region entered or left.
    pub region: u32,
    /// Body whose surface is crossed.
    pub body: u32,
    /// Face of that body.
    pub face: u32,
}

/// The order of [`Prepared::by_distance`]: by entry bound, then by zone.
pub fn by_entry(a: &(f64, u32), b: &(f64, u32)) -> std::cmp::Ordering {
    a.0.total_cmp(&b.0).then(a.1.cmp(&b.1))
}

impl Prepared {
    /// Segments of body `b` along the ray, cached for the current ray.
    /// `boxed`: the caller knows the ray meets the body's bounds.
    #[inline]
    fn body_segs(&self, b: u32, ray: &Ray, s: &mut Scratch, boxed: bool) -> (usize, usize) {
        let bi = b as usize;
        let c = s.cache[bi];
        if c[0] != s.ray_id {
            let start = s.segs.len();
            // The (padded) bounds reject most misses for the price of a
            // box test.
            if boxed || hits(&self.body_bounds[bi], ray, f64::NEG_INFINITY, f64::INFINITY).is_some()
            {
                self.shapes[bi].shoot(ray, &mut s.segs);
            }
            let end = s.segs.len();
            s.cache[bi] = [s.ray_id, start as u32, end as u32];
            return (start, end);
        }
        (c[1] as usize, c[2] as usize)
    }

    /// Walk `bvh` along the ray with the scratch's stack, as
    /// [`Bvh::traverse`], handing `visit` each leaf's zones, the limit and
    /// the scratch.
    #[inline]
    fn leaves(
        &self,
        bvh: &Bvh,
        ray: &Ray,
        tmin: f64,
        limit: &mut f64,
        s: &mut Scratch,
        mut visit: impl FnMut(&[u32], &mut f64, &mut Scratch) -> bool,
    ) {
        let mut stack = std::mem::take(&mut s.stack);
        bvh.traverse(ray, tmin, limit, &mut stack, |items, limit| {
            visit(items, limit, s)
        });
        s.stack = stack;
    }

    /// Spans of zone `z` that reach into `(lo, hi)`, left in `s.cur`.
    /// Returns false when there are none. The caller has checked that the
    /// ray meets the zone's bounds.
    pub(crate) fn zone_spans(
        &self,
        z: &PreparedZone,
        ray: &Ray,
        lo: f64,
        hi: f64,
        s: &mut Scratch,
    ) -> bool {
        let keep = |sp: &Span| sp.b.t > lo && sp.a.t < hi;
        s.cur.clear();
        if z.plus == 1 && z.minus == 0 {
            // A lone body: its spans are the zone's.
            let b = self.terms[z.first as usize];
            let (a, e) = self.body_segs(b, ray, s, true);
            s.cur.extend(spans(&s.segs[a..e], b).filter(keep));
            return !s.cur.is_empty();
        }
        let terms =
            &self.terms[z.first as usize..(z.first as usize + z.plus as usize + z.minus as usize)];
        let (plus, minus) = terms.split_at(z.plus as usize);
        // The `-` bodies already applied to the spans in `s.cur`, if any.
        let mut done = None;
        if z.convex && !plus.is_empty() {
            match self.convex_spans(plus, minus, ray, lo, hi, s) {
                Convex::Empty => return false,
                Convex::One(sp) => {
                    s.cur.push(sp);
                    return true;
                }
                // On with the lists.
                Convex::Split(k) => done = Some(k),
                Convex::Lists => {}
            }
        }
        if done.is_none() && !self.plus_spans(plus, ray, keep, s) {
            return false;
        }
        for &b in &minus[done.unwrap_or(0)..] {
            let (first, last) = (s.cur[0].a.t, s.cur[s.cur.len() - 1].b.t);
            let Some(range) = self.minus_segs(b, ray, first, last, s) else {
                continue;
            };
            if !self.combine(Combine::Subtract, b, range, s) {
                return false;
            }
        }
        s.cur.retain(keep);
        !s.cur.is_empty()
    }

    /// The spans of the `+` bodies' intersection, the first body's
    /// filtered by `keep` (the whole line when there are no `+` bodies), in
    /// `s.cur`; false when there are none.
    #[inline(always)]
    fn plus_spans(
        &self,
        plus: &[u32],
        ray: &Ray,
        keep: impl Fn(&Span) -> bool,
        s: &mut Scratch,
    ) -> bool {
        if plus.is_empty() {
            s.cur.push(Span {
                a: Bound::new(f64::NEG_INFINITY, u32::MAX, 0),
                b: Bound::new(f64::INFINITY, u32::MAX, 0),
            });
            return true;
        }
        for (i, &b) in plus.iter().enumerate() {
            // A lone `+` body has the zone's bounds, which the ray meets.
            let (a, e) = self.body_segs(b, ray, s, plus.len() == 1);
            // A missed `+` body empties the zone: no copy, no boolean.
            if a == e {
                return false;
            }
            if i == 0 {
                s.cur.extend(spans(&s.segs[a..e], b).filter(&keep));
                if s.cur.is_empty() {
                    return false;
                }
            } else if !self.combine(Combine::Intersect, b, (a, e), s) {
                return false;
            }
        }
        true
    }

    /// `s.cur` intersected with, or less, body `b`'s segments
    /// `s.segs[a..e]`; false when nothing is left.
    #[inline(always)]
    fn combine(&self, op: Combine, b: u32, (a, e): (usize, usize), s: &mut Scratch) -> bool {
        let segs = &s.segs[a..e];
        let y = |j: usize| span(&segs[j], b);
        match op {
            Combine::Intersect => intersect_with(&s.cur, segs.len(), y, &mut s.tmp, self.tol),
            Combine::Subtract => subtract_with(&s.cur, segs.len(), y, &mut s.tmp, self.tol),
        }
        std::mem::swap(&mut s.cur, &mut s.tmp);
        !s.cur.is_empty()
    }

    /// The segments of `-` body `b` when they may cut the spans from
    /// `first` to `last`; `None` when they leave them as they are.
    #[inline(always)]
    fn minus_segs(
        &self,
        b: u32,
        ray: &Ray,
        first: f64,
        last: f64,
        s: &mut Scratch,
    ) -> Option<(usize, usize)> {
        hits(&self.body_bounds[b as usize], ray, first, last)?;
        // A missed `-` body changes nothing.
        let (a, e) = self.body_segs(b, ray, s, true);
        (!(a == e || s.segs[a].t0 >= last || s.segs[e - 1].t1 <= first)).then_some((a, e))
    }

    /// [`Prepared::zone_spans`] for a zone whose `+` bodies are convex,
    /// while its spans stay one: held in hand, without the lists and their
    /// booleans. Each step makes exactly what [`intersect_with`] and
    /// [`subtract_with`] make of one span and one segment.
    #[inline(always)]
    fn convex_spans(
        &self,
        plus: &[u32],
        minus: &[u32],
        ray: &Ray,
        lo: f64,
        hi: f64,
        s: &mut Scratch,
    ) -> Convex {
        let tol = self.tol;
        let mut cur = None::<Span>;
        for &b in plus {
            let (a, e) = self.body_segs(b, ray, s, plus.len() == 1);
            match e - a {
                0 => return Convex::Empty,
                1 => {}
                // Convex bodies give one segment; leave anything else to
                // the lists.
                _ => return Convex::Lists,
            }
            let q = span(&s.segs[a], b);
            cur = Some(match cur {
                None if q.b.t > lo && q.a.t < hi => q,
                None => return Convex::Empty,
                Some(p) => {
                    let a = if p.a.t >= q.a.t { p.a } else { q.a };
                    let b = if p.b.t <= q.b.t { p.b } else { q.b };
                    if b.t - a.t > tol {
                        Span { a, b }
                    } else {
                        return Convex::Empty;
                    }
                }
            });
        }
        let Some(mut cur) = cur else {
            return Convex::Lists;
        };
        for (k, &b) in minus.iter().enumerate() {
            let Some((a, e)) = self.minus_segs(b, ray, cur.a.t, cur.b.t, s) else {
                continue;
            };
            if e - a != 1 {
                s.cur.push(cur);
                return Convex::Split(k);
            }
            // The segment reaches past the span's start and begins before
            // its end (`minus_segs`).
            let c = span(&s.segs[a], b);
            let mut start = cur.a;
            let before = (c.a.t > start.t && c.a.t - start.t > tol).then_some(Span {
                a: start,
                b: flipped(c.a),
            });
            if c.b.t > start.t {
                start = flipped(c.b);
            }
            let after = (cur.b.t - start.t > tol).then_some(Span { a: start, b: cur.b });
            cur = match (before, after) {
                (None, None) => return Convex::Empty,
                (Some(p), None) | (None, Some(p)) => p,
                (Some(p), Some(q)) => {
                    s.cur.push(p);
                    s.cur.push(q);
                    return Convex::Split(k + 1);
                }
            };
        }
        if cur.b.t > lo && cur.a.t < hi {
            Convex::One(cur)
        } else {
            Convex::Empty
        }
    }

    /// The first surface of an opaque region met along the ray with
    /// `tmin < t < tmax`. A ray that starts inside an opaque region hits it
    /// at `tmin` with `inside` set. Ties between regions sharing a surface
    /// go to the lower region index, and within a region to the lower zone,
    /// so the answer does not depend on the order in which the hierarchy is
    /// walked.
    pub fn first_hit(&self, ray: &Ray, tmin: f64, tmax: f64, s: &mut Scratch) -> Option<Hit> {
        s.new_ray();
        let mut best = Hit::NONE;
        let mut limit = tmax;
        for &zi in &self.unbounded_opaque {
            self.consider(zi, ray, tmin, &mut limit, &mut best, s);
        }
        self.leaves(
            &self.bvh_opaque,
            ray,
            tmin,
            &mut limit,
            s,
            |items, limit, s| {
                for &zi in items {
                    self.consider(zi, ray, tmin, limit, &mut best, s);
                }
                false
            },
        );
        best.is_some().then_some(best)
    }

    /// As [`Prepared::first_hit`], but looking only at `zones` (from
    /// [`Prepared::frustum_zones`] for a bundle of rays), each given with a
    /// lower bound of the distance at which any ray of the bundle can enter
    /// it, sorted by that bound. Gives exactly the same answer for any ray
    /// of the bundle; stops as soon as no remaining zone can come nearer.
    ///
    /// The hit is written into `out` ([`Hit::NONE`] when there is none),
    /// which may be its final place: a hit built field by field and then
    /// copied whole stalls the processor (the copy's wide loads cannot be
    /// forwarded from the narrow stores still in flight).
    pub fn first_hit_in(
        &self,
        zones: &[(f64, u32)],
        ray: &Ray,
        tmin: f64,
        tmax: f64,
        s: &mut Scratch,
        out: &mut Hit,
    ) -> bool {
        s.new_ray();
        *out = Hit::NONE;
        let mut limit = tmax;
        for &(near, zi) in zones {
            if near > limit {
                break;
            }
            self.consider(zi, ray, tmin, &mut limit, out, s);
        }
        out.is_some()
    }

    /// Order `zones` for [`Prepared::first_hit_in`]: each zone with a lower
    /// bound of the distance at which rays leaving `eye` (perspective), or
    /// rays along `dir` leaving the plane through `eye` normal to `dir`
    /// (orthographic, `dir` unit), can enter its bounds.
    pub fn by_distance(
        &self,
        zones: &[u32],
        eye: DVec3,
        parallel: Option<DVec3>,
        out: &mut Vec<(f64, u32)>,
    ) {
        out.clear();
        out.extend(
            zones
                .iter()
                .map(|&zi| (self.entry_bound(zi, eye, parallel), zi)),
        );
        out.sort_unstable_by(by_entry);
    }

    /// The lower bound of where the rays of [`Prepared::by_distance`] can
    /// enter zone `zi`'s bounds.
    #[inline]
    pub fn entry_bound(&self, zi: u32, eye: DVec3, parallel: Option<DVec3>) -> f64 {
        entry_of(
            &self.zones[zi as usize].bounds,
            self.enclosure(zi),
            eye,
            parallel,
        )
    }

    /// Test one zone for the first hit, keeping the best so far: the lowest
    /// entry, ties to the lower region index.
    #[inline]
    fn consider(
        &self,
        zi: u32,
        ray: &Ray,
        tmin: f64,
        limit: &mut f64,
        best: &mut Hit,
        s: &mut Scratch,
    ) {
        let z = &self.zones[zi as usize];
        if hits(&z.bounds, ray, tmin, *limit).is_none() || !self.zone_spans(z, ray, tmin, *limit, s)
        {
            return;
        }
        let sp = s.cur[0];
        let (t, inside) = if sp.a.t > tmin {
            (sp.a.t, false)
        } else {
            (tmin, true)
        };
        // Any hit is better than none (region `u32::MAX`). At equal `t`
        // the lower region wins, and within a region the lower zone (two
        // zones of a region may be entered through the same surface): the
        // hit is then the same in whatever order the zones are tried.
        if t < best.t
            || (t == best.t
                && (z.region < best.region || (z.region == best.region && zi < best.zone)))
        {
            *best = Hit {
                zone: zi,
                t,
                region: z.region,
                bound: sp.a,
                inside,
            };
            // Keep equal-t candidates reachable for the tie rule.
            *limit = t + self.tol.min(t.abs() * 1e-15 + f64::MIN_POSITIVE);
        }
    }

    /// The opaque zones that the frustum may meet (their bounds, and the
    /// ball or hull points found for each when prepared), in hierarchy order
    /// (unbounded zones first). Gives up and returns false as soon as there
    /// are more than `max`: the rays had better walk the hierarchy then.
    pub fn frustum_zones(&self, f: &Frustum, max: usize, out: &mut Vec<u32>) -> bool {
        self.zones_meeting(
            max,
            out,
            |b| f.may_meet(b),
            // A zone whose box the frustum meets may still lie beside it:
            // the frustum can pass a box's corner and miss the ball inside,
            // or a rotor blade set at an angle across its box. Only the
            // zones left count toward `max`.
            |zi| self.enclosure_meets(zi, f),
        )
    }

    /// True when [`Prepared::frustum_zones`] would list bounded zone `zi`
    /// for frustum `f`: its box, then its ball or hull points, may meet it.
    pub fn frustum_keeps(&self, zi: u32, f: &Frustum) -> bool {
        f.may_meet(&self.zones[zi as usize].bounds) && self.enclosure_meets(zi, f)
    }

    /// The test of a zone's ball or hull points against a frustum.
    fn enclosure_meets(&self, zi: u32, f: &Frustum) -> bool {
        match self.enclosure(zi) {
            EnclosureRef::Box => true,
            EnclosureRef::Ball(c, r) => f.may_meet_ball(c, r),
            EnclosureRef::Points(pts) => f.may_meet_points(pts),
        }
    }

    /// Where bounded zone `zi` may be seen on the raster of `gen`: within
    /// the rectangle around its box, narrowed to that around its ball or
    /// hull points where it has them (up to rounding: pad it); nowhere when
    /// it lies wholly behind the plane of the eye (or, orthographic, of the
    /// rays' origins); anywhere when neither its box nor its ball or hull
    /// lies wholly in front of a perspective camera's eye. For a zone in
    /// front of the eye this is [`Prepared::frustum_zones`]' test of a
    /// tile's frustum, plane by plane, turned around: a box, ball or hull
    /// lies wholly outside a plane through the eye and a tile's edge
    /// exactly when its rectangle lies beyond that edge.
    pub fn zone_rect(&self, zi: u32, gen: &RayGen) -> RasterExtent {
        rect_of(&self.zones[zi as usize].bounds, self.enclosure(zi), gen)
    }

    /// The zones of opaque regions that have no finite bounds (they lead
    /// every list of [`Prepared::frustum_zones`], untested).
    pub fn unbounded_opaque(&self) -> &[u32] {
        &self.unbounded_opaque
    }

    /// The opaque zones whose bounds pass `meets` and that then pass `keep`
    /// (unbounded zones always), walking the hierarchy through the nodes
    /// whose bounds pass `meets`; false (and given up) past `max`.
    fn zones_meeting(
        &self,
        max: usize,
        out: &mut Vec<u32>,
        meets: impl Fn(&Aabb) -> bool,
        keep: impl Fn(u32) -> bool,
    ) -> bool {
        out.clear();
        out.extend_from_slice(&self.unbounded_opaque);
        let nodes = &self.bvh_opaque.nodes;
        let mut stack = [0u32; 64];
        let mut sp = usize::from(!nodes.is_empty());
        while sp > 0 {
            sp -= 1;
            let node = nodes[stack[sp] as usize];
            if !meets(&node.bounds) {
                continue;
            }
            if node.count > 0 {
                let items =
                    &self.bvh_opaque.items[node.first as usize..(node.first + node.count) as usize];
                out.extend(
                    items
                        .iter()
                        .copied()
                        .filter(|&zi| meets(&self.zones[zi as usize].bounds) && keep(zi)),
                );
            } else if sp + 2 <= stack.len() {
                stack[sp] = node.first + 1;
                stack[sp + 1] = node.first;
                sp += 2;
            } else {
                // Deeper than the stack: let the rays walk the hierarchy.
                return false;
            }
            if out.len() > max {
                return false;
            }
        }
        out.len() <= max
    }

    /// True when an opaque region lies on the ray within `(tmin, tmax)`
    /// (shadow rays: any hit will do), never looking at zone `skip` (see
    /// [`Prepared::shadow_skip`]).
    pub fn occluded(
        &self,
        ray: &Ray,
        tmin: f64,
        tmax: f64,
        skip: Option<u32>,
        s: &mut Scratch,
    ) -> bool {
        s.new_ray();
        let unbounded = self.unbounded_opaque.iter().copied();
        if self
            .any_opaque(unbounded, skip, ray, tmin, tmax, s)
            .is_some()
        {
            return true;
        }
        let mut limit = tmax;
        let mut found = false;
        self.leaves(&self.bvh_opaque, ray, tmin, &mut limit, s, |items, _, s| {
            found = self
                .any_opaque(items.iter().copied(), skip, ray, tmin, tmax, s)
                .is_some();
            found
        });
        found
    }

    /// The zone that a ray leaving `hit` toward the outside of its surface
    /// (a shadow ray with `cos θ > 0`) cannot meet again, if any: the hit
    /// zone itself when the surface belongs to one of its `+` bodies and
    /// all of them are convex. Their intersection is convex, so the ray
    /// leaves it for good, and `-` bodies only take material away.
    pub fn shadow_skip(&self, hit: &Hit) -> Option<u32> {
        let z = &self.zones[hit.zone as usize];
        (!hit.inside && !hit.bound.flip() && z.convex).then_some(hit.zone)
    }

    /// As [`Prepared::occluded`], looking only at `zones` (from
    /// [`Prepared::zones_in_box`] for a bundle of shadow rays): the same
    /// answer for any ray of the bundle.
    pub fn occluded_in(
        &self,
        zones: &[u32],
        skip: Option<u32>,
        ray: &Ray,
        tmin: f64,
        tmax: f64,
        s: &mut Scratch,
    ) -> bool {
        s.new_ray();
        self.any_opaque(zones.iter().copied(), skip, ray, tmin, tmax, s)
            .is_some()
    }

    /// The first of `zones` (other than `skip`) found on the ray within
    /// `(tmin, tmax)`. The body cache is the caller's: `s.new_ray()` first
    /// for a new ray.
    pub(crate) fn any_opaque(
        &self,
        zones: impl IntoIterator<Item = u32>,
        skip: Option<u32>,
        ray: &Ray,
        tmin: f64,
        tmax: f64,
        s: &mut Scratch,
    ) -> Option<u32> {
        zones.into_iter().find(|&zi| {
            let z = &self.zones[zi as usize];
            Some(zi) != skip
                && hits(&z.bounds, ray, tmin, tmax).is_some()
                && self.zone_spans(z, ray, tmin, tmax, s)
        })
    }

    /// The opaque zones whose bounds meet the box `from`. A shadow ray
    /// toward a point light from any point of `from` can only meet these
    /// when `from` holds both the points and the light. Gives up past
    /// `max`. (Shadow rays toward parallel lights use a
    /// [`crate::LightBuffer`].)
    pub fn zones_in_box(&self, from: &Aabb, max: usize, out: &mut Vec<u32>) -> bool {
        let near = from.padded(self.tol);
        self.zones_meeting(max, out, |b| !b.intersection(&near).is_empty(), |_| true)
    }

    /// Every region's stretches along the ray within `(tmin, tmax)`,
    /// transparent regions included, sorted by entry then region.
    pub fn partitions(
        &self,
        ray: &Ray,
        tmin: f64,
        tmax: f64,
        s: &mut Scratch,
        out: &mut Vec<Partition>,
    ) {
        s.new_ray();
        out.clear();
        let mut tagged = std::mem::take(&mut s.tagged);
        tagged.clear();
        let mut collect = |zi: u32, s: &mut Scratch| {
            let z = &self.zones[zi as usize];
            if hits(&z.bounds, ray, tmin, tmax).is_some() && self.zone_spans(z, ray, tmin, tmax, s)
            {
                tagged.extend(s.cur.iter().map(|sp| (z.region, *sp)));
            }
        };
        for &zi in &self.unbounded_all {
            collect(zi, s);
        }
        let mut limit = tmax;
        self.leaves(&self.bvh_all, ray, tmin, &mut limit, s, |items, _, s| {
            for &zi in items {
                collect(zi, s);
            }
            false
        });
        // Union the zones of each region.
        tagged.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.a.t.total_cmp(&b.1.a.t)));
        let mut i = 0;
        while i < tagged.len() {
            let r = tagged[i].0;
            s.tmp.clear();
            while i < tagged.len() && tagged[i].0 == r {
                push_merged(&mut s.tmp, tagged[i].1, self.tol);
                i += 1;
            }
            out.extend(s.tmp.iter().map(|sp| Partition {
                region: r,
                span: *sp,
            }));
        }
        out.sort_by(|a, b| {
            a.span
                .a
                .t
                .total_cmp(&b.span.a.t)
                .then(a.region.cmp(&b.region))
        });
        s.tagged = tagged;
    }

    /// Every surface crossing along the ray for `t > tmin`, in order: where
    /// the ray enters and leaves each region, and through which body.
    pub fn crossings(&self, ray: &Ray, tmin: f64, s: &mut Scratch) -> Vec<Crossing> {
        let mut parts = Vec::new();
        self.partitions(ray, tmin, f64::INFINITY, s, &mut parts);
        let mut out = Vec::new();
        for p in &parts {
            for (b, entering) in [(p.span.a, true), (p.span.b, false)] {
                if b.t.is_finite() && b.t > tmin {
                    out.push(Crossing {
                        t: b.t,
                        entering,
                        region: p.region,
                        body: if b.body == u32::MAX {
                            b.body
                        } else {
                            self.body_index(b.body) as u32
                        },
                        face: b.face(),
                    });
                }
            }
        }
        out.sort_by(|a, b| {
            a.t.total_cmp(&b.t)
                .then(a.entering.cmp(&b.entering))
                .then(a.region.cmp(&b.region))
        });
        out
    }

    /// Outward unit normal of the surface at a hit (reversed for a
    /// subtracted body; facing the ray when it started inside).
    #[inline(always)]
    pub fn normal(&self, hit: &Hit, ray: &Ray) -> DVec3 {
        if hit.inside || hit.bound.body == u32::MAX {
            return -ray.dir;
        }
        let n = self.shapes[hit.bound.body as usize].normal(hit.bound.face(), ray.at(hit.t));
        if hit.bound.flip() {
            -n
        } else {
            n
        }
    }
}

/// A body's segments as spans bounded by its faces (not flipped:
/// `subtract` flips the bounds it takes from a subtracted body).
fn spans(segs: &[Seg], body: u32) -> impl Iterator<Item = Span> + '_ {
    segs.iter().map(move |g| span(g, body))
}

/// The boolean of [`Prepared::combine`].
#[derive(Clone, Copy)]
enum Combine {
    Intersect,
    Subtract,
}

/// What [`Prepared::convex_spans`] made of a zone.
enum Convex {
    /// No spans.
    Empty,
    /// One span.
    One(Span),
    /// The spans so far, in `s.cur`, when they are two or a `-` body gave
    /// more than one segment: the `-` bodies before the given index are
    /// applied.
    Split(usize),
    /// Nothing: a body gave more than one segment.
    Lists,
}

/// One segment of `body` as a span (see [`spans`]).
#[inline(always)]
fn span(g: &Seg, body: u32) -> Span {
    Span {
        a: Bound::new(g.t0, body, g.f0),
        b: Bound::new(g.t1, body, g.f1),
    }
}

/// Where a zone may be seen on a camera's raster
/// ([`Prepared::zone_rect`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RasterExtent {
    /// Nowhere: it lies behind the rays.
    Nowhere,
    /// Anywhere: it reaches behind a perspective camera's eye.
    Anywhere,
    /// Within the rectangle `[x0, y0, x1, y1]` of the raster, in pixels
    /// from its top-left corner (up to rounding).
    Within([f64; 4]),
}

/// The volume swept by a bundle of rays (a tile of pixels): the
/// intersection of half-spaces `n·x >= d`. Used only to rule zones out, so
/// it must contain every ray of the bundle.
#[derive(Clone, Copy, Debug)]
pub struct Frustum {
    /// Normal `n`, offset `d`, the rounding slack `1e-9 (|d| + |n|)` and
    /// `|n|`.
    planes: [(DVec3, f64, f64, f64); 4],
}

impl Frustum {
    /// The frustum bounded by four corner rays given in order around the
    /// bundle (their origins may differ, as for an orthographic view; the
    /// rays must diverge or stay parallel).
    pub fn from_corners(c: [Ray; 4]) -> Frustum {
        let centre_o = (c[0].origin + c[1].origin + c[2].origin + c[3].origin) * 0.25;
        let centre_d = (c[0].dir + c[1].dir + c[2].dir + c[3].dir).normalize();
        let probe = centre_o + centre_d;
        let planes = std::array::from_fn(|i| {
            let (a, b) = (&c[i], &c[(i + 1) % 4]);
            // The plane holds ray a and the point where ray b starts.
            let mut n = a.dir.cross(b.dir + (b.origin - a.origin));
            if n.dot(probe - a.origin) < 0.0 {
                n = -n;
            }
            let d = n.dot(a.origin);
            (n, d, 1e-9 * (d.abs() + n.length()), n.length())
        });
        Frustum { planes }
    }

    /// False only when the box lies wholly outside.
    pub fn may_meet(&self, b: &sv_math::Aabb) -> bool {
        self.planes.iter().all(|&(n, d, slack, _)| {
            let p = DVec3::new(
                if n.x > 0.0 { b.max.x } else { b.min.x },
                if n.y > 0.0 { b.max.y } else { b.min.y },
                if n.z > 0.0 { b.max.z } else { b.min.z },
            );
            let v = n.dot(p);
            // Rounding slack: rule a box out only when clearly outside.
            // (A NaN compares as unordered and keeps the box.)
            v.partial_cmp(&(d - slack - 1e-9 * v.abs())) != Some(std::cmp::Ordering::Less)
        })
    }

    /// False only when the convex hull of `pts` lies wholly outside.
    pub fn may_meet_points(&self, pts: &[DVec3]) -> bool {
        self.planes.iter().all(|&(n, d, slack, _)| {
            pts.iter().any(|&p| {
                let v = n.dot(p);
                v.partial_cmp(&(d - slack - 1e-9 * v.abs())) != Some(std::cmp::Ordering::Less)
            })
        })
    }

    /// False only when the ball of centre `c` and radius `r` lies wholly
    /// outside.
    pub fn may_meet_ball(&self, c: DVec3, r: f64) -> bool {
        self.planes.iter().all(|&(n, d, slack, len)| {
            let v = n.dot(c) + r * len;
            v.partial_cmp(&(d - slack - 1e-9 * (v.abs() + r * len)))
                != Some(std::cmp::Ordering::Less)
        })
    }
}

/// One body-surface crossing along a ray, with the regions the ray is in
/// just after it (for `shoot`, the paper's Figure 3 walk-through).
#[derive(Clone, Debug, PartialEq)]
pub struct Step {
    /// Distance along the ray.
    pub t: f64,
    /// Body crossed.
    pub body: u32,
    /// Face of the body.
    pub face: u32,
    /// True when the ray enters the body here.
    pub entering: bool,
    /// Regions containing the ray just past this point (empty: outside
    /// the geometry; more than one: an overlap).
    pub regions_after: Vec<u32>,
}

impl Prepared {
    /// Every body surface the ray crosses for `t > tmin`, in order, and the
    /// regions it is in after each crossing.
    pub fn walk(&self, ray: &Ray, tmin: f64, s: &mut Scratch) -> Vec<Step> {
        let mut steps = Vec::new();
        let mut segs = Vec::new();
        for (i, sh) in self.shapes.iter().enumerate() {
            if self.body_bounds[i].ray_range(ray).is_none() {
                continue;
            }
            segs.clear();
            sh.shoot(ray, &mut segs);
            for g in &segs {
                for (t, face, entering) in [(g.t0, g.f0, true), (g.t1, g.f1, false)] {
                    if t.is_finite() && t > tmin {
                        steps.push(Step {
                            t,
                            body: self.body_index(i as u32) as u32,
                            face,
                            entering,
                            regions_after: Vec::new(),
                        });
                    }
                }
            }
        }
        steps.sort_by(|a, b| a.t.total_cmp(&b.t).then(a.body.cmp(&b.body)));
        let mut parts = Vec::new();
        self.partitions(ray, tmin, f64::INFINITY, s, &mut parts);
        for i in 0..steps.len() {
            let t = steps[i].t;
            let next = steps.get(i + 1).map_or(t + 1.0, |n| n.t);
            let probe = if next > t { 0.5 * (t + next) } else { t };
            steps[i].regions_after = parts
                .iter()
                .filter(|p| p.span.a.t <= probe && probe < p.span.b.t)
                .map(|p| p.region)
                .collect();
        }
        steps
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::PrepareOptions;
    use sv_geom::{Body, BodyKind, Geometry, Op, Region, Term, Zone};

    #[test]
    fn convex_zones_held_in_hand_give_the_spans_of_the_lists() {
        // Convex bodies about the origin, flush faces among them, and a
        // torus (two segments) to subtract.
        let mut g = Geometry::default();
        let bodies: [(BodyKind, Vec<f64>); 8] = [
            (BodyKind::Sph, vec![0.0, 0.0, 0.0, 1.0]),
            (BodyKind::Rpp, vec![-0.8, 0.8, -0.8, 0.8, -0.8, 0.8]),
            (BodyKind::Rpp, vec![0.0, 2.0, -0.5, 0.5, -0.5, 0.5]),
            (BodyKind::Rcc, vec![0.0, 0.0, -2.0, 0.0, 0.0, 4.0, 0.3]),
            (BodyKind::Sph, vec![0.6, 0.2, 0.0, 0.5]),
            (BodyKind::Rpp, vec![-0.8, 0.8, -0.8, 0.8, 0.2, 0.3]),
            (BodyKind::Tor, vec![0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.7, 0.2]),
            (BodyKind::Rcc, vec![-2.0, 0.0, 0.0, 4.0, 0.0, 0.0, 0.25]),
        ];
        for (i, (kind, params)) in bodies.into_iter().enumerate() {
            g.bodies.push(Body::new(format!("b{i}"), kind, params));
        }
        let convex = [0, 1, 2, 3, 4, 5, 7];
        let mut seed = 11u64;
        let mut rnd = move |n: usize| {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 33) as usize) % n
        };
        for i in 0..40 {
            let mut terms = vec![Term {
                op: Op::Inside,
                body: convex[rnd(convex.len())],
            }];
            if rnd(3) == 0 {
                terms.push(Term {
                    op: Op::Inside,
                    body: convex[rnd(convex.len())],
                });
            }
            for _ in 0..rnd(4) {
                terms.push(Term {
                    op: Op::Outside,
                    body: rnd(8),
                });
            }
            g.regions.push(Region {
                name: format!("r{i}"),
                zones: vec![Zone { terms }],
            });
        }
        let p = Prepared::new(&g, &PrepareOptions::default()).unwrap().0;
        let mut lists = p.clone();
        lists.zones.iter_mut().for_each(|z| z.convex = false);
        let (mut s, mut t) = (Scratch::new(&p), Scratch::new(&lists));
        let mut spans_seen = [0usize; 3];
        for k in 0..3000 {
            let f = |m: usize| ((k * m) % 1000) as f64 / 1000.0 * 2.0 - 1.0;
            // Rays through the middle, along the axes among them (flush
            // faces), from outside and from inside.
            let dir = if k % 5 == 0 {
                [DVec3::X, DVec3::Y, DVec3::Z][k % 3]
            } else {
                DVec3::new(f(7), f(13), f(29))
            };
            let target = DVec3::new(f(31), f(37), f(41)) * 0.9;
            let origin = target - dir.normalize() * if k % 4 == 0 { 0.1 } else { 5.0 };
            let ray = Ray::new(origin, dir);
            s.new_ray();
            t.new_ray();
            for (z, zl) in p.zones.iter().zip(&lists.zones) {
                let lo = if k % 3 == 0 { 0.0 } else { f64::NEG_INFINITY };
                let a = p.zone_spans(z, &ray, lo, f64::INFINITY, &mut s);
                let b = lists.zone_spans(zl, &ray, lo, f64::INFINITY, &mut t);
                // The spans count only when there are some.
                assert_eq!(a, b, "ray {k}, zone {z:?}");
                if a {
                    assert_eq!(s.cur, t.cur, "ray {k}, zone {z:?}");
                }
                spans_seen[if a { s.cur.len().min(2) } else { 0 }] += 1;
            }
        }
        // Both empty, single and split zones were met.
        assert!(spans_seen.iter().all(|&n| n > 100), "{spans_seen:?}");
    }

    #[test]
    fn entry_bounds_are_never_past_where_a_ray_enters() {
        // Overlapping spheres, one zone each, and boxes turned to the axes.
        let mut g = Geometry::default();
        let mut rnd = crate::test_numbers(7);
        for i in 0..60 {
            let (x, y, z) = (rnd() * 6.0, rnd() * 6.0, rnd() * 6.0);
            let (kind, params) = if i % 3 == 0 {
                let (a, b) = (rnd() * 2.0 - 1.0, rnd() * 2.0 - 1.0);
                (BodyKind::Box, crate::turned_box([x, y, z], a, b))
            } else {
                (BodyKind::Sph, vec![x, y, z, 0.3 + rnd()])
            };
            g.bodies.push(Body::new(format!("b{i}"), kind, params));
            g.regions.push(Region::of_body(format!("r{i}"), i));
        }
        let p = Prepared::new(&g, &PrepareOptions::default()).unwrap().0;
        let mut s = Scratch::new(&p);
        let zones: Vec<u32> = (0..p.zones.len() as u32).collect();
        let mut near = Vec::new();
        let mut checked = 0;
        for eye in [DVec3::new(-8.0, 3.0, 2.0), DVec3::new(3.0, 3.0, 3.0)] {
            for parallel in [None, Some(DVec3::new(1.0, 0.2, 0.1).normalize())] {
                p.by_distance(&zones, eye, parallel, &mut near);
                for _ in 0..400 {
                    let ray = match parallel {
                        None => Ray::new(
                            eye,
                            DVec3::new(rnd() * 2.0 - 1.0, rnd() * 2.0 - 1.0, rnd() * 2.0 - 1.0),
                        ),
                        // From the plane through the eye across `d`.
                        Some(d) => {
                            let (u, v) = sv_math::orthonormal_basis(d);
                            let o = eye + u * (rnd() * 8.0 - 1.0) + v * (rnd() * 8.0 - 1.0);
                            Ray::new(o, d)
                        }
                    };
                    s.new_ray();
                    for &(bound, zi) in &near {
                        let z = &p.zones[zi as usize];
                        if p.zone_spans(z, &ray, 0.0, f64::INFINITY, &mut s) {
                            let t = s.cur[0].a.t.max(0.0);
                            assert!(bound <= t, "zone {zi}: bound {bound} past entry {t}");
                            checked += 1;
                        }
                    }
                }
            }
        }
        assert!(checked > 1000, "{checked} entries checked");
    }

    #[test]
    fn a_frustum_rules_out_a_ball_whose_box_it_meets() {
        // Rays from the origin through the square |x|, |y| <= 1 at z = 1.
        let f = Frustum::from_corners(
            [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
                .map(|(x, y)| Ray::new(DVec3::ZERO, DVec3::new(x, y, 1.0))),
        );
        let ball = |c: DVec3, r: f64| (f.may_meet(&Aabb::new(c - r, c + r)), f.may_meet_ball(c, r));
        // 0.71 beyond the side x = z: its box reaches over the side.
        assert_eq!(ball(DVec3::new(2.0, 0.0, 1.0), 0.6), (true, false));
        // 0.57 beyond it: the ball reaches over too.
        assert_eq!(ball(DVec3::new(1.8, 0.0, 1.0), 0.6), (true, true));
        assert_eq!(ball(DVec3::new(0.0, 0.0, 5.0), 0.1), (true, true));
        assert_eq!(ball(DVec3::new(9.0, 0.0, 1.0), 0.6), (false, false));
        // Grazing: kept.
        let graze = DVec3::new(2.0, 0.0, 1.0);
        let r = (2.0 - 1.0) / 2f64.sqrt();
        assert!(f.may_meet_ball(graze, r));
        // A rod running parallel to the side x = z, 0.28 beyond it: its
        // box reaches over the side, its ends (and so the rod) do not.
        let rod = [DVec3::new(1.2, 0.0, 0.8), DVec3::new(2.0, 0.0, 1.6)];
        assert!(f.may_meet(&Aabb::from_points(rod)));
        assert!(!f.may_meet_points(&rod));
        assert!(f.may_meet_points(&[rod[0], DVec3::new(0.5, 0.0, 1.6)]));
    }

    #[test]
    fn a_tile_lists_its_zones_when_only_their_boxes_crowd_it() {
        // Rays from the origin through the square |x|, |y| <= 1 at z = 1
        // (as above). Three small spheres sit on the z axis; twelve beside
        // the four sides, like the ball 0.71 beyond the side x = z above,
        // have boxes that reach over the sides and balls that do not.
        let mut g = Geometry::default();
        let mut add = |c: DVec3, r: f64| {
            let i = g.bodies.len();
            g.bodies.push(Body::new(
                format!("s{i}"),
                BodyKind::Sph,
                vec![c.x, c.y, c.z, r],
            ));
            g.regions.push(Region::of_body(format!("r{i}"), i));
        };
        for z in [2.0, 8.0, 30.0] {
            add(DVec3::new(0.0, 0.0, z), 0.1);
        }
        for z in [1.0, 4.0, 16.0] {
            for (x, y) in [(2.0, 0.0), (-2.0, 0.0), (0.0, 2.0), (0.0, -2.0)] {
                add(DVec3::new(x * z, y * z, z), 0.6 * z);
            }
        }
        let p = Prepared::new(&g, &PrepareOptions::default()).unwrap().0;
        let f = Frustum::from_corners(
            [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
                .map(|(x, y)| Ray::new(DVec3::ZERO, DVec3::new(x, y, 1.0))),
        );
        let mut out = Vec::new();
        // Fifteen boxes meet the frustum, three balls: within a limit of
        // five, the tile keeps a list, of those three.
        assert!(p.frustum_zones(&f, 5, &mut out));
        out.sort_unstable();
        let regions: Vec<u32> = out.iter().map(|&zi| p.zones[zi as usize].region).collect();
        assert_eq!(regions, [0, 1, 2]);
        assert!(!p.frustum_zones(&f, 2, &mut out));
    }
}
