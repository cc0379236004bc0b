//! One zone along one ray: the `+` bodies' segments intersected, the `-`
//! bodies' subtracted (BRL-CAD's booleans, held in hand while a convex
//! zone's spans stay one), with each body cast once a ray.

use crate::bvh::hits;
use crate::hit::Scratch;
use crate::prepare::{Prepared, PreparedGroup, PreparedZone};
use sv_geom::boolean::{flipped, intersect, intersect_with, subtract, subtract_with, Bound, Span};
use sv_geom::shape::Seg;
use sv_math::Ray;

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
        if z.plus == 1 && z.minus == 0 && z.group_count() == 0 {
            // A lone body: its spans are the zone's.
            let b = self.terms[z.first as usize];
            let (a, e) = self.body_segs(b, ray, s, true);
            s.cur.extend(spans(&s.segs[a..e], b).filter(keep));
            return !s.cur.is_empty();
        }
        let (plus, minus) = self.zone_terms(z).split_at(z.plus as usize);
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
        if z.group_count() > 0 && !self.apply_groups(z, ray, s) {
            return false;
        }
        s.cur.retain(keep);
        !s.cur.is_empty()
    }

    /// `s.cur` intersected with, or less, each group of zone `z`, each
    /// group's zones evaluated along the stretch `s.cur` covers and
    /// unioned; false when nothing is left. Each body is still cast once a
    /// ray (the cache holds its segments), so the cost follows the size of
    /// the expression, whatever its nesting.
    #[inline(never)]
    fn apply_groups(&self, z: &PreparedZone, ray: &Ray, s: &mut Scratch) -> bool {
        for g in self.zone_groups(z) {
            let (first, last) = (s.cur[0].a.t, s.cur[s.cur.len() - 1].b.t);
            let met = hits(&g.bounds, ray, first, last).is_some();
            if !met && g.subtract {
                continue;
            }
            let union = if met {
                self.group_spans(g, ray, first, last, s)
            } else {
                s.spare()
            };
            let mut out = s.spare();
            if g.subtract {
                subtract(&s.cur, &union, &mut out, self.tol);
            } else {
                intersect(&s.cur, &union, &mut out, self.tol);
            }
            s.give_back(union);
            let before = std::mem::replace(&mut s.cur, out);
            s.give_back(before);
            if s.cur.is_empty() {
                return false;
            }
        }
        true
    }

    /// The union of the zones of group `g` that reach into `(lo, hi)`.
    fn group_spans(
        &self,
        g: &PreparedGroup,
        ray: &Ray,
        lo: f64,
        hi: f64,
        s: &mut Scratch,
    ) -> Vec<Span> {
        // The nested zones work in a spare list of the pool, handed back
        // below: a fresh one would be allocated for every group a ray
        // meets, and the pool would grow by one a call.
        let nested_cur = s.spare();
        let outer = std::mem::replace(&mut s.cur, nested_cur);
        let (mut union, mut merged) = (s.spare(), s.spare());
        let zones = &self.nested[g.first as usize..(g.first + g.count) as usize];
        for inner in zones {
            if hits(&inner.bounds, ray, lo, hi).is_some() && self.zone_spans(inner, ray, lo, hi, s)
            {
                sv_geom::boolean::union(&union, &s.cur, &mut merged, self.tol);
                std::mem::swap(&mut union, &mut merged);
            }
        }
        s.give_back(merged);
        let inner_cur = std::mem::replace(&mut s.cur, outer);
        s.give_back(inner_cur);
        union
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::PrepareOptions;
    use sv_geom::{Body, BodyKind, Geometry, Op, Region, Term, Zone};
    use sv_math::DVec3;
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
            g.regions
                .push(Region::new(format!("r{i}"), vec![Zone::new(terms)]));
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
}
