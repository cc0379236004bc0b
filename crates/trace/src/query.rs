//! Ray queries: the first opaque region hit (front to back, lazily), any
//! hit (shadows), the full list of region partitions along a ray, its
//! surface crossings, and the walk of every body surface (`shoot`).

use crate::bvh::{hits, Bvh};
use crate::hit::{by_entry, Crossing, Hit, Partition, Scratch, Step};
use crate::prepare::Prepared;
use crate::raster::entry_of;
use sv_geom::boolean::{Bound, Span};
use sv_math::{DVec3, Ray};

impl Prepared {
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
    pub(crate) fn consider(
        &self,
        zi: u32,
        ray: &Ray,
        tmin: f64,
        limit: &mut f64,
        best: &mut Hit,
        s: &mut Scratch,
    ) {
        let z = &self.zones[zi as usize];
        if hits(&z.bounds, ray, tmin, *limit).is_none() {
            return;
        }
        if z.is_filled() {
            if let Some(h) = self.fill_hit(z, zi, ray, tmin, *limit, s) {
                self.keep_nearer(h, limit, best);
            }
            return;
        }
        if !self.zone_spans(z, ray, tmin, *limit, s) {
            return;
        }
        let sp = s.cur[0];
        let (t, inside) = if sp.a.t > tmin {
            (sp.a.t, false)
        } else {
            (tmin, true)
        };
        let hit = Hit {
            zone: zi,
            t,
            region: z.region,
            bound: sp.a,
            inside,
        };
        self.keep_nearer(hit, limit, best);
    }

    /// Keep `hit` when it is nearer than `best`. Any hit is better than
    /// none (region `u32::MAX`). At equal `t` the lower region wins, and
    /// within a region the lower zone (two zones of a region may be entered
    /// through the same surface): the hit is then the same in whatever
    /// order the zones are tried.
    #[inline(always)]
    fn keep_nearer(&self, hit: Hit, limit: &mut f64, best: &mut Hit) {
        let t = hit.t;
        if t < best.t
            || (t == best.t
                && (hit.region < best.region
                    || (hit.region == best.region && hit.zone < best.zone)))
        {
            *best = hit;
            // Keep equal-t candidates reachable for the tie rule.
            *limit = t + self.tol.min(t.abs() * 1e-15 + f64::MIN_POSITIVE);
        }
    }

    /// True when zone `zi` holds opaque material on the ray within
    /// `(tmin, tmax)`: any of its stretches, or, filled, any of its
    /// content's. The caller has checked that the ray meets its bounds.
    #[inline]
    pub(crate) fn zone_blocks(
        &self,
        zi: u32,
        ray: &Ray,
        tmin: f64,
        tmax: f64,
        s: &mut Scratch,
    ) -> bool {
        let z = &self.zones[zi as usize];
        if z.is_filled() {
            self.fill_hit(z, zi, ray, tmin, tmax, s).is_some()
        } else {
            self.zone_spans(z, ray, tmin, tmax, s)
        }
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
                && self.zone_blocks(zi, ray, tmin, tmax, s)
        })
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
        self.gather_partitions(ray, tmin, tmax, s, out, |collect, s| {
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
        });
    }

    /// [`Prepared::partitions`] looking only at `zones`, which must hold
    /// every zone whose bounds the ray meets within `(tmin, tmax)` (as
    /// [`Prepared::all_zones_in_box`] lists them for a box the ray crosses
    /// there): the same stretches, without walking the hierarchy. For
    /// bundles of rays that share one list, such as a grid's.
    pub fn partitions_in(
        &self,
        zones: &[u32],
        ray: &Ray,
        tmin: f64,
        tmax: f64,
        s: &mut Scratch,
        out: &mut Vec<Partition>,
    ) {
        self.gather_partitions(ray, tmin, tmax, s, out, |collect, s| {
            for &zi in zones {
                collect(zi, s);
            }
        });
    }

    /// The partitions of the zones `walk` hands to its `collect` whose
    /// bounds the ray meets, each region's zones unioned, sorted by entry
    /// then region.
    fn gather_partitions(
        &self,
        ray: &Ray,
        tmin: f64,
        tmax: f64,
        s: &mut Scratch,
        out: &mut Vec<Partition>,
        walk: impl FnOnce(&mut dyn FnMut(u32, &mut Scratch), &mut Scratch),
    ) {
        s.new_ray();
        out.clear();
        let mut collect = |zi: u32, s: &mut Scratch| {
            let z = &self.zones[zi as usize];
            if hits(&z.bounds, ray, tmin, tmax).is_none() {
                return;
            }
            if z.is_filled() {
                self.fill_partitions(z, ray, tmin, tmax, s, out);
            } else if self.zone_spans(z, ray, tmin, tmax, s) {
                insert_spans(out, z.region, &s.cur);
            }
        };
        walk(&mut collect, s);
        self.union_in_place(out);
    }

    /// Each region's stretches in `parts`, sorted by
    /// [`insert_by_entry`], unioned in place. Taken in order, each
    /// stretch extends the region's last one kept when it starts within
    /// the tolerance of its end, or is kept: the stretches stay in order,
    /// and each region's are unioned in the order of their entries, ties
    /// in the order they were inserted.
    pub(crate) fn union_in_place(&self, parts: &mut Vec<Partition>) {
        // Regions already kept, by their number modulo 64: most come
        // once, and need no search for a stretch to extend.
        let mut kept_already = 0u64;
        // Most lists hold no region twice: they are read, not rewritten.
        // Up to the first stretch whose region may come before, each
        // stretch is kept where it is.
        let mut first_repeat = parts.len();
        for (at, part) in parts.iter().enumerate() {
            let bit = 1u64 << (part.region % 64);
            if kept_already & bit != 0 {
                first_repeat = at;
                break;
            }
            kept_already |= bit;
        }
        let mut kept = first_repeat;
        for at in first_repeat..parts.len() {
            let Partition { region, span } = parts[at];
            let bit = 1u64 << (region % 64);
            let searched = kept_already & bit != 0;
            kept_already |= bit;
            let last = if searched {
                parts[..kept].iter_mut().rev().find(|p| p.region == region)
            } else {
                None
            };
            match last {
                Some(last) if span.a.t <= last.span.b.t + self.tol => {
                    if span.b.t > last.span.b.t {
                        last.span.b = span.b;
                    }
                }
                _ => {
                    // Until a stretch is merged, each stays where it is.
                    if kept != at {
                        parts[kept] = parts[at];
                    }
                    kept += 1;
                }
            }
        }
        parts.truncate(kept);
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
        self.surface_normal(&hit.bound, ray.at(hit.t))
    }

    /// How squarely the surface at `hit` faces its ray: `max(0, −n·d)`,
    /// where `n` is the normal BRL-CAD's `rt` shades with,
    /// [`Prepared::normal`] or, for a ray that starts inside its region,
    /// [`Prepared::normal_behind`]. Zero for a surface seen edge on or from
    /// behind (and for a normal that is not a number).
    pub fn facing(&self, hit: &Hit, ray: &Ray, s: &mut Scratch) -> f64 {
        // The cosine in each branch: a normal chosen first and read back
        // whole from the stack stalls on the store of its parts.
        let cos = if hit.inside {
            -self.normal_behind(hit, ray, s).dot(ray.dir)
        } else {
            -self.normal(hit, ray).dot(ray.dir)
        };
        cos.max(0.0)
    }

    /// For a hit whose ray starts inside its region: the outward normal of
    /// the surface where the ray, followed backwards, entered that region,
    /// at the point of entry (anywhere on a plane met at −∞). BRL-CAD's
    /// `rt` shades such a hit with this normal; [`Prepared::normal`]
    /// gives `-dir` instead, a face toward the viewer. `-dir` too when the
    /// region has no such surface (all space).
    pub fn normal_behind(&self, hit: &Hit, ray: &Ray, s: &mut Scratch) -> DVec3 {
        let mut parts = Vec::new();
        self.partitions(ray, f64::NEG_INFINITY, f64::INFINITY, s, &mut parts);
        let entry = parts
            .iter()
            .find(|p| p.region == hit.region && p.span.a.t <= hit.t && hit.t < p.span.b.t)
            .map(|p| p.span.a);
        match entry {
            Some(a) if a.body != u32::MAX => {
                let at = if a.t.is_finite() {
                    ray.at(a.t)
                } else {
                    ray.origin
                };
                self.surface_normal(&a, at)
            }
            _ => -ray.dir,
        }
    }

    /// Outward unit normal of the surface `bound` crosses, at point `at`
    /// of it: carried in the bound for a nested universe's surface,
    /// reversed for a subtracted body.
    #[inline(always)]
    fn surface_normal(&self, bound: &Bound, at: DVec3) -> DVec3 {
        if let Some(n) = bound.nested_normal() {
            return n;
        }
        let n = self.shapes[bound.body as usize].normal(bound.face(), at);
        if bound.flip() {
            -n
        } else {
            n
        }
    }
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

/// Add each of `spans`, of region `region`, to `parts` by
/// [`insert_by_entry`].
#[inline(always)]
pub(crate) fn insert_spans(parts: &mut Vec<Partition>, region: u32, spans: &[Span]) {
    for &span in spans {
        insert_by_entry(parts, Partition { region, span });
    }
}

/// Add `part` to `parts`, which stay sorted by entry, then region, and
/// after those equal to it: a stable sort of the stretches as they come,
/// which are few and nearly in order (the zones are listed by where the
/// rays enter their bounds).
#[inline(always)]
pub(crate) fn insert_by_entry(parts: &mut Vec<Partition>, part: Partition) {
    let after = |p: &Partition| {
        p.span
            .a
            .t
            .total_cmp(&part.span.a.t)
            .then(p.region.cmp(&part.region))
            .is_gt()
    };
    // Most come after the last: entered later (a comparison that NaN
    // and a signed zero fail, to be ordered below).
    if parts
        .last()
        .is_none_or(|last| part.span.a.t > last.span.a.t)
    {
        parts.push(part);
        return;
    }
    let mut at = parts.len();
    parts.push(part);
    while at > 0 && after(&parts[at - 1]) {
        parts[at] = parts[at - 1];
        at -= 1;
    }
    parts[at] = part;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::PrepareOptions;
    use sv_geom::{Body, BodyKind, Geometry, Region};

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
}
