//! Booleans on sorted lists of spans along one ray (BRL-CAD's `bool.c` in
//! spirit): intersection, subtraction and union.
//!
//! Each end of a span remembers the body and face that bound it and whether
//! that body was subtracted (`flip`): the surface normal at a region's entry
//! comes from that body, reversed for a subtracted one.
//!
//! **Tolerance.** Spans no longer than `tol` are dropped and gaps no longer
//! than `tol` are closed. This is what keeps coincident faces (a body
//! subtracted flush with a face of another, two regions sharing a face)
//! free of speckles: rounding leaves slivers of 1e-15 relative size that
//! would otherwise be seen as surfaces. sv-trace's `Prepared` sets `tol` to
//! 1e-7 of the model's bounding-box diagonal unless told otherwise.

use sv_math::DVec3;

/// One end of a span.
///
/// Sixteen bytes without padding: spans are copied whole all through the
/// booleans, and a copy that carries padding bytes reads back the narrow
/// store of the flag beside them, which the processor cannot forward.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bound {
    /// Ray parameter (distance along the ray).
    pub t: f64,
    /// Body whose surface is crossed. In the bounds of hits and partitions
    /// this is the prepared body number, which
    /// `Prepared::body_index` (sv-trace) turns into the
    /// body's index in the geometry.
    pub body: u32,
    /// The face of that body in the low bits, [`Bound::FLIP`] when the body
    /// was subtracted.
    face_flip: u32,
}

impl Bound {
    /// The bit of `face_flip` set for a subtracted body.
    pub const FLIP: u32 = 1 << 31;

    /// The end at `t` on `face` of `body` (faces below 2³¹), not flipped.
    pub const fn new(t: f64, body: u32, face: u32) -> Bound {
        debug_assert!(face < Self::FLIP, "face number too large");
        Bound {
            t,
            body,
            face_flip: face & !Self::FLIP,
        }
    }

    /// Face of the body.
    pub fn face(&self) -> u32 {
        self.face_flip & !Self::FLIP
    }

    /// True when the body was subtracted, so its normal is reversed.
    pub fn flip(&self) -> bool {
        self.face_flip & Self::FLIP != 0
    }

    /// The face with the flip bit ([`Bound::FLIP`] when subtracted).
    pub fn face_flip(&self) -> u32 {
        self.face_flip
    }

    /// The body number that marks the end of a surface inside a filled
    /// region (a universe or lattice element moved into it): such an end
    /// carries the surface's normal, in the filled region's frame, instead
    /// of a face ([`Bound::nested`]).
    pub const NESTED: u32 = u32::MAX - 1;

    /// The end at `t` on a surface inside a filled region whose outward
    /// unit normal there is `normal`: the normal is held in the face field,
    /// each of its octahedral coordinates in 16 bits (Cigolle et al. 2014,
    /// "A survey of efficient representations for independent unit
    /// vectors"), some 1e-4 radians from the true one at most.
    pub fn nested(t: f64, normal: DVec3) -> Bound {
        let n = normal / (normal.x.abs() + normal.y.abs() + normal.z.abs());
        let (mut u, mut v) = (n.x, n.y);
        if n.z < 0.0 {
            (u, v) = (
                (1.0 - n.y.abs()) * n.x.signum(),
                (1.0 - n.x.abs()) * n.y.signum(),
            );
        }
        let q = |c: f64| (((c.clamp(-1.0, 1.0) + 1.0) * 0.5 * 65535.0).round() as u32) & 0xffff;
        Bound {
            t,
            body: Self::NESTED,
            face_flip: q(u) | q(v) << 16,
        }
    }

    /// The normal of a [`Bound::nested`] end, `None` for other ends.
    pub fn nested_normal(&self) -> Option<DVec3> {
        if self.body != Self::NESTED {
            return None;
        }
        let d = |bits: u32| f64::from(bits & 0xffff) / 65535.0 * 2.0 - 1.0;
        let (u, v) = (d(self.face_flip), d(self.face_flip >> 16));
        let z = 1.0 - u.abs() - v.abs();
        let (x, y) = if z < 0.0 {
            ((1.0 - v.abs()) * u.signum(), (1.0 - u.abs()) * v.signum())
        } else {
            (u, v)
        };
        Some(DVec3::new(x, y, z).normalize())
    }

    /// The end at `t` on `body` with `face_flip` as [`Bound::face_flip`]
    /// gives it.
    pub fn from_parts(t: f64, body: u32, face_flip: u32) -> Bound {
        Bound { t, body, face_flip }
    }
}

/// A stretch `[a.t, b.t]` of the ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Span {
    /// Entry.
    pub a: Bound,
    /// Exit.
    pub b: Bound,
}

impl Span {
    /// Length of the span.
    pub fn len(&self) -> f64 {
        self.b.t - self.a.t
    }

    /// True when the span has no length.
    pub fn is_empty(&self) -> bool {
        self.b.t <= self.a.t
    }
}

/// `b` as the end of a subtracted body: its flip bit turned over.
pub fn flipped(mut b: Bound) -> Bound {
    b.face_flip ^= Bound::FLIP;
    b
}

/// `out = x ∩ y`.
pub fn intersect(x: &[Span], y: &[Span], out: &mut Vec<Span>, tol: f64) {
    intersect_with(x, y.len(), |j| y[j], out, tol);
}

/// As [`intersect`], with `y`'s `n` spans made by `y(j)` (from a body's
/// segments, without copying them into a list first).
#[inline]
pub fn intersect_with(
    x: &[Span],
    n: usize,
    y: impl Fn(usize) -> Span,
    out: &mut Vec<Span>,
    tol: f64,
) {
    out.clear();
    let (mut i, mut j) = (0, 0);
    while i < x.len() && j < n {
        let (p, q) = (&x[i], &y(j));
        let a = if p.a.t >= q.a.t { p.a } else { q.a };
        let b = if p.b.t <= q.b.t { p.b } else { q.b };
        if b.t - a.t > tol {
            out.push(Span { a, b });
        }
        if p.b.t < q.b.t {
            i += 1;
        } else {
            j += 1;
        }
    }
}

/// `out = x − y`.
pub fn subtract(x: &[Span], y: &[Span], out: &mut Vec<Span>, tol: f64) {
    subtract_with(x, y.len(), |j| y[j], out, tol);
}

/// As [`subtract`], with `y`'s `n` spans made by `y(j)` (as for
/// [`intersect_with`]).
#[inline]
pub fn subtract_with(
    x: &[Span],
    n: usize,
    y: impl Fn(usize) -> Span,
    out: &mut Vec<Span>,
    tol: f64,
) {
    out.clear();
    let mut j = 0;
    for s in x {
        let mut start = s.a;
        while j < n && y(j).b.t <= start.t {
            j += 1;
        }
        let mut k = j;
        while k < n && y(k).a.t < s.b.t {
            let c = &y(k);
            if c.a.t > start.t && c.a.t - start.t > tol {
                out.push(Span {
                    a: start,
                    b: flipped(c.a),
                });
            }
            if c.b.t > start.t {
                start = flipped(c.b);
            }
            if start.t >= s.b.t {
                break;
            }
            k += 1;
        }
        if s.b.t - start.t > tol {
            out.push(Span { a: start, b: s.b });
        }
    }
}

/// `out = x ∪ y`; spans closer than `tol` are merged.
pub fn union(x: &[Span], y: &[Span], out: &mut Vec<Span>, tol: f64) {
    out.clear();
    let (mut i, mut j) = (0, 0);
    while i < x.len() || j < y.len() {
        let next = if j >= y.len() || (i < x.len() && x[i].a.t <= y[j].a.t) {
            i += 1;
            x[i - 1]
        } else {
            j += 1;
            y[j - 1]
        };
        push_merged(out, next, tol);
    }
}

/// Append `s` to sorted `out`, merging it with the last span if they
/// overlap or nearly touch.
pub fn push_merged(out: &mut Vec<Span>, s: Span, tol: f64) {
    if let Some(last) = out.last_mut() {
        if s.a.t <= last.b.t + tol {
            if s.b.t > last.b.t {
                last.b = s.b;
            }
            return;
        }
    }
    out.push(s);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sp(a: f64, b: f64, body: u32) -> Span {
        Span {
            a: Bound::new(a, body, 0),
            b: Bound::new(b, body, 1),
        }
    }

    /// Reference answer by classifying the midpoint of every sub-interval.
    fn reference(x: &[Span], y: &[Span], op: fn(bool, bool) -> bool) -> Vec<(f64, f64)> {
        let inside = |l: &[Span], t: f64| l.iter().any(|s| s.a.t < t && t < s.b.t);
        let mut ts: Vec<f64> = x.iter().chain(y).flat_map(|s| [s.a.t, s.b.t]).collect();
        ts.sort_by(f64::total_cmp);
        ts.dedup();
        let mut out: Vec<(f64, f64)> = vec![];
        for w in ts.windows(2) {
            let m = 0.5 * (w[0] + w[1]);
            if op(inside(x, m), inside(y, m)) {
                match out.last_mut() {
                    Some(l) if l.1 == w[0] => l.1 = w[1],
                    _ => out.push((w[0], w[1])),
                }
            }
        }
        out
    }

    /// Interval cases: disjoint, touching, overlapping, containing, equal,
    /// in both orders, and lists of two spans.
    fn cases() -> Vec<Vec<Span>> {
        let mut v = vec![vec![]];
        for (a, b) in [
            (0.0, 1.0),
            (0.5, 1.5),
            (1.0, 2.0),
            (-1.0, 3.0),
            (2.0, 3.0),
            (0.25, 0.75),
        ] {
            v.push(vec![sp(a, b, 1)]);
        }
        v.push(vec![sp(0.0, 1.0, 1), sp(2.0, 3.0, 1)]);
        v.push(vec![sp(-0.5, 0.5, 1), sp(0.8, 2.5, 1)]);
        v
    }

    #[test]
    fn operators_match_midpoint_classification_in_both_orders() {
        type Op = (
            fn(&[Span], &[Span], &mut Vec<Span>, f64),
            fn(bool, bool) -> bool,
            &'static str,
        );
        let ops: [Op; 3] = [
            (intersect, |a, b| a && b, "and"),
            (subtract, |a, b| a && !b, "minus"),
            (union, |a, b| a || b, "or"),
        ];
        for x in cases() {
            for y in cases() {
                for (f, r, name) in ops {
                    for (p, q) in [(&x, &y), (&y, &x)] {
                        let mut out = vec![];
                        f(p, q, &mut out, 0.0);
                        let got: Vec<(f64, f64)> = out.iter().map(|s| (s.a.t, s.b.t)).collect();
                        assert_eq!(got, reference(p, q, r), "{name} of {p:?} and {q:?}");
                    }
                }
            }
        }
    }

    #[test]
    fn nested_ends_carry_their_normal() {
        let mut worst: f64 = 0.0;
        for i in 0..2000 {
            let (a, b) = (i as f64 * 0.618, i as f64 * 0.37);
            let n = DVec3::new(a.cos() * b.sin(), a.sin() * b.sin(), b.cos());
            let back = Bound::nested(3.5, n).nested_normal().unwrap();
            worst = worst.max(back.angle_between(n));
            assert!((back.length() - 1.0).abs() < 1e-12);
        }
        assert!(worst < 1e-4, "{worst}");
        for n in [
            DVec3::X,
            -DVec3::X,
            DVec3::Y,
            -DVec3::Y,
            DVec3::Z,
            -DVec3::Z,
        ] {
            assert!(
                Bound::nested(0.0, n)
                    .nested_normal()
                    .unwrap()
                    .angle_between(n)
                    < 1e-4
            );
        }
        assert_eq!(Bound::new(1.0, 3, 2).nested_normal(), None);
    }

    #[test]
    fn subtracted_bounds_are_flipped_and_slivers_dropped() {
        let mut out = vec![];
        subtract(&[sp(0.0, 4.0, 1)], &[sp(1.0, 2.0, 2)], &mut out, 1e-9);
        assert_eq!(out.len(), 2);
        assert!(out[0].b.flip() && out[0].b.body == 2);
        assert!(out[1].a.flip() && out[1].a.body == 2);
        // A body subtracted flush with the entry face leaves no sliver.
        subtract(&[sp(0.0, 4.0, 1)], &[sp(1e-15, 2.0, 2)], &mut out, 1e-9);
        assert_eq!(out.len(), 1);
        assert_eq!(out[0].a.t, 2.0);
    }
}
