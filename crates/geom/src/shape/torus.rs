use super::poly::{quartic_roots_lanes, roots_in};
use super::{segments_by_classification, Seg, SegLanes};
use crate::body::{nonzero, positive, Warning};
use crate::Body;
use sv_math::lanes::{
    along, clamp, dot, mat_vec, max_num, min_num, nan, ray_range_lanes, sub_point, Lanes,
};
use sv_math::simd::Simd;
use sv_math::{Aabb, DMat3, DVec3, Ray};

/// A torus: centre, unit axis, major radius `r1`, minor radius `r2 < r1`.
/// A ray may cross it four times, so it can give two segments.
#[derive(Clone, Debug)]
pub struct Torus {
    c: DVec3,
    /// Rows are the local x, y, z (= axis) directions: local = rot·(p − c).
    rot: DMat3,
    r1: f64,
    r2: f64,
    axis: DVec3,
}

impl Torus {
    /// A torus about the line through `c` along `axis`.
    pub fn new(c: DVec3, axis: DVec3, r1: f64, r2: f64) -> Torus {
        let n = axis.normalize();
        let (u, v) = sv_math::orthonormal_basis(n);
        let rot = DMat3::from_cols(u, v, n).transpose();
        Torus {
            c,
            rot,
            r1,
            r2,
            axis: n,
        }
    }

    fn inside_local(&self, q: DVec3) -> bool {
        let rho = (q.x * q.x + q.y * q.y).sqrt() - self.r1;
        rho * rho + q.z * q.z < self.r2 * self.r2
    }

    /// Append the segments of the ray inside the body to `out` (see
    /// [`super::Shape::shoot`]).
    pub fn shoot(&self, ray: &Ray, out: &mut Vec<Seg>) {
        let Some((o, d, range)) = self.local_range(ray) else {
            return;
        };
        if self.misses_clearly(o, d, range) {
            return;
        }
        self.shoot_quartic(ray, (o, d), range, out);
    }

    /// The box around the tube in the torus's own frame.
    fn local_box(&self) -> Aabb {
        let e = self.r1 + self.r2;
        Aabb::new(DVec3::new(-e, -e, -self.r2), DVec3::new(e, e, self.r2))
    }

    /// `ray` in local space (origin and direction) and its range in the
    /// torus's box, if it crosses the box.
    fn local_range(&self, ray: &Ray) -> Option<(DVec3, DVec3, (f64, f64))> {
        let o = self.rot * (ray.origin - self.c);
        let d = self.rot * ray.dir;
        let range = self.local_box().ray_range(&Ray {
            origin: o,
            dir: d,
            inv_dir: d.recip(),
        })?;
        Some((o, d, range))
    }

    /// The segments of `ray` (`o + t·d` in local space) within `(lo, hi)`
    /// from the roots of the torus's quartic.
    fn shoot_quartic(
        &self,
        ray: &Ray,
        (o, d): (DVec3, DVec3),
        (lo, hi): (f64, f64),
        out: &mut Vec<Seg>,
    ) {
        // Shift the origin to the box entry so the quartic is well scaled.
        let o = o + d * lo;
        let (a2, b2) = (self.r1 * self.r1, self.r2 * self.r2);
        let f = o.dot(d);
        let g = o.length_squared() - a2 - b2;
        let coef = [
            g * g - 4.0 * a2 * (b2 - o.z * o.z),
            4.0 * f * g + 8.0 * a2 * o.z * d.z,
            2.0 * g + 4.0 * f * f + 4.0 * a2 * d.z * d.z,
            4.0 * f,
            1.0,
        ];
        let mut roots = [0.0; 4];
        let n = roots_in(&coef, 0.0, hi - lo, &mut roots);
        if n == 0 {
            return;
        }
        let mut cands = [(0.0, 0u32); 4];
        for i in 0..n {
            cands[i] = (roots[i] + lo, 0);
        }
        let inside = |p: DVec3| self.inside_local(self.rot * (p - self.c));
        segments_by_classification(&mut cands[..n], ray, inside, out);
    }

    /// True when the ray `o + t·d` (local), `t` in `range`, passes the
    /// tube by more than a billionth of the torus's size: its distance
    /// from the axis stays beyond the tube's reach wherever it is level
    /// with the tube. Exact for rays along the axis and across it
    /// (the grids' rays through a torus turned to an axis); a ray that
    /// passes closer goes to the quartic, which finds no root for a ray
    /// that misses, so the segments are the same either way.
    fn misses_clearly(&self, o: DVec3, d: DVec3, (lo, hi): (f64, f64)) -> bool {
        let margin = 1e-9 * (self.r1 + self.r2);
        // Where the ray is level with the tube, and how far the tube
        // reaches from its core circle there.
        let top = self.r2 + margin;
        let (ta, tb, reach) = if d.z == 0.0 {
            if o.z.abs() > top {
                return true;
            }
            (lo, hi, (self.r2 * self.r2 - o.z * o.z).max(0.0).sqrt())
        } else {
            let (za, zb) = ((-top - o.z) / d.z, (top - o.z) / d.z);
            (lo.max(za.min(zb)), hi.min(za.max(zb)), self.r2)
        };
        if ta.is_nan() || tb.is_nan() {
            return false;
        }
        if ta > tb {
            return true;
        }
        // Squared distance from the axis: convex in t, so largest at an
        // end of the stretch and smallest at its vertex or an end.
        let across = |t: f64| (o.x + t * d.x).powi(2) + (o.y + t * d.y).powi(2);
        let flat = d.x * d.x + d.y * d.y;
        let nearest = if flat > 0.0 {
            (-(o.x * d.x + o.y * d.y) / flat).clamp(ta, tb)
        } else {
            ta
        };
        let (closest, farthest) = (across(nearest), across(ta).max(across(tb)));
        let outer = self.r1 + reach + margin;
        let inner = self.r1 - reach - margin;
        closest > outer * outer || (inner > 0.0 && farthest < inner * inner)
    }

    /// [`Torus::shoot`] in every lane of `m`, operation for operation:
    /// each lane's first segment, and its second (the `hit` of the second
    /// is the lanes whose ray crosses the tube twice).
    ///
    /// Inlined into the packets' entry points where optimised, as all the
    /// lanes' code is. Unoptimised, every value of an inlined function
    /// keeps its own place on the stack, and the quartic's many, with the
    /// bodies' casts at every place a zone casts one, grew the render
    /// packets' entry point's frame past a worker thread's 2 MiB stack
    /// (2.6 MB): there the casts stay calls.
    #[cfg_attr(not(debug_assertions), inline(always))]
    #[cfg_attr(debug_assertions, inline(never))]
    pub fn shoot_lanes_both<S: Simd>(&self, s: S, r: &Lanes<S>, m: S::M) -> [SegLanes<S>; 2] {
        let zero = s.splat(0.0);
        let mut first = SegLanes {
            t0: zero,
            t1: zero,
            f0: zero,
            f1: zero,
            hit: s.none(),
            scalar: s.none(),
        };
        let mut second = SegLanes { ..first };
        let o = mat_vec(s, &self.rot, sub_point(s, r.o, self.c));
        let d = mat_vec(s, &self.rot, r.d);
        let (lo, hi, in_box) = ray_range_lanes(s, &self.local_box(), o, d);
        let m = s.and(m, in_box);
        let m = s.andnot(m, self.misses_clearly_lanes(s, o, d, (lo, hi)));
        if !s.any(m) {
            return [first, second];
        }
        let o = along(s, o, d, lo);
        let (a2, b2) = (self.r1 * self.r1, self.r2 * self.r2);
        let f = dot(s, o, d);
        let g = s.sub(s.sub(dot(s, o, o), s.splat(a2)), s.splat(b2));
        let four_f = s.mul(s.splat(4.0), f);
        let coef = [
            s.sub(
                s.mul(g, g),
                s.mul(s.splat(4.0 * a2), s.sub(s.splat(b2), s.mul(o[2], o[2]))),
            ),
            s.add(
                s.mul(four_f, g),
                s.mul(s.mul(s.splat(8.0 * a2), o[2]), d[2]),
            ),
            s.add(
                s.add(s.mul(s.splat(2.0), g), s.mul(four_f, f)),
                s.mul(s.mul(s.splat(4.0 * a2), d[2]), d[2]),
            ),
            four_f,
            s.splat(1.0),
        ];
        let (roots, n) = quartic_roots_lanes(s, coef, s.sub(hi, lo), m);
        // As `segments_by_classification`: the roots come in order, and
        // each stretch between two whose midpoint is inside joins the
        // segment before if it ends there. Two stretches that do not
        // follow one another make two segments; four roots make no more.
        let mut cands = roots;
        for cand in &mut cands {
            *cand = s.add(*cand, lo);
        }
        let (mut open, mut two) = (s.none(), s.none());
        let (mut cur, mut done) = ([zero; 2], [zero; 2]);
        for w in 0..3 {
            let (ta, tb) = (cands[w], cands[w + 1]);
            let valid = s.and(m, s.lt(s.splat((w + 1) as f64), n));
            let mid = along(s, r.o, r.d, s.mul(s.splat(0.5), s.add(ta, tb)));
            let inside = s.and(s.andnot(valid, s.le(tb, ta)), self.inside_lanes(s, mid));
            if !s.any(inside) {
                continue;
            }
            let join = s.and(s.and(inside, open), s.eq(cur[1], ta));
            let start = s.andnot(inside, join);
            let close = s.and(start, open);
            done = [
                s.select(close, cur[0], done[0]),
                s.select(close, cur[1], done[1]),
            ];
            two = s.or(two, close);
            cur = [s.select(start, ta, cur[0]), s.select(inside, tb, cur[1])];
            open = s.or(open, inside);
        }
        (first.t0, first.t1, first.hit) = (
            s.select(two, done[0], cur[0]),
            s.select(two, done[1], cur[1]),
            open,
        );
        (second.t0, second.t1, second.hit) = (cur[0], cur[1], two);
        [first, second]
    }

    /// [`Torus::misses_clearly`] in every lane.
    #[inline(always)]
    fn misses_clearly_lanes<S: Simd>(
        &self,
        s: S,
        o: [S::F; 3],
        d: [S::F; 3],
        (lo, hi): (S::F, S::F),
    ) -> S::M {
        let zero = s.splat(0.0);
        let margin = 1e-9 * (self.r1 + self.r2);
        let top = s.splat(self.r2 + margin);
        let level = s.eq(d[2], zero);
        let above = s.and(level, s.gt(s.abs(o[2]), top));
        let level_reach = s.sqrt(max_num(
            s,
            s.sub(s.splat(self.r2 * self.r2), s.mul(o[2], o[2])),
            zero,
        ));
        let za = s.div(s.sub(s.neg(top), o[2]), d[2]);
        let zb = s.div(s.sub(top, o[2]), d[2]);
        let ta = s.select(level, lo, max_num(s, lo, min_num(s, za, zb)));
        let tb = s.select(level, hi, min_num(s, hi, max_num(s, za, zb)));
        let reach = s.select(level, level_reach, s.splat(self.r2));
        let unknown = s.or(nan(s, ta), nan(s, tb));
        let past = s.gt(ta, tb);

        let flat = s.add(s.mul(d[0], d[0]), s.mul(d[1], d[1]));
        let vertex = s.div(s.neg(s.add(s.mul(o[0], d[0]), s.mul(o[1], d[1]))), flat);
        let nearest = s.select(s.gt(flat, zero), clamp(s, vertex, ta, tb), ta);
        let closest = across_lanes(s, o, d, nearest);
        let farthest = max_num(s, across_lanes(s, o, d, ta), across_lanes(s, o, d, tb));
        let margin = s.splat(margin);
        let outer = s.add(s.add(s.splat(self.r1), reach), margin);
        let inner = s.sub(s.sub(s.splat(self.r1), reach), margin);
        let clear = s.or(
            s.gt(closest, s.mul(outer, outer)),
            s.and(s.gt(inner, zero), s.lt(farthest, s.mul(inner, inner))),
        );
        s.or(above, s.andnot(s.or(past, clear), s.or(unknown, above)))
    }

    /// [`Torus::inside_local`] of the points `p` in every lane.
    #[inline(always)]
    fn inside_lanes<S: Simd>(&self, s: S, p: [S::F; 3]) -> S::M {
        let q = mat_vec(s, &self.rot, sub_point(s, p, self.c));
        let rho = s.sub(
            s.sqrt(s.add(s.mul(q[0], q[0]), s.mul(q[1], q[1]))),
            s.splat(self.r1),
        );
        s.lt(
            s.add(s.mul(rho, rho), s.mul(q[2], q[2])),
            s.splat(self.r2 * self.r2),
        )
    }

    /// Outward unit normal at a point of the surface.
    pub fn normal(&self, p: DVec3) -> DVec3 {
        let q = self.rot * (p - self.c);
        let ring = DVec3::new(q.x, q.y, 0.0).normalize_or_zero() * self.r1;
        (self.rot.transpose() * (q - ring)).normalize()
    }

    /// True when `p` is strictly inside.
    pub fn contains(&self, p: DVec3) -> bool {
        self.inside_local(self.rot * (p - self.c))
    }

    /// Bounds (infinite sides where the body is unbounded).
    pub fn bounds(&self) -> Aabb {
        // Extent along world axis i: r1·sqrt(1 − n_i²) + r2.
        let n = self.axis;
        let e = DVec3::new(
            self.r1 * (1.0 - n.x * n.x).max(0.0).sqrt() + self.r2,
            self.r1 * (1.0 - n.y * n.y).max(0.0).sqrt() + self.r2,
            self.r1 * (1.0 - n.z * n.z).max(0.0).sqrt() + self.r2,
        );
        Aabb::new(self.c - e, self.c + e)
    }
}

/// The squared distance from the axis of the points `o + t·d` in every
/// lane ([`Torus::misses_clearly`]'s `across`).
#[inline(always)]
fn across_lanes<S: Simd>(s: S, o: [S::F; 3], d: [S::F; 3], t: S::F) -> S::F {
    let x = s.add(o[0], s.mul(t, d[0]));
    let y = s.add(o[1], s.mul(t, d[1]));
    s.add(s.mul(x, x), s.mul(y, y))
}

/// TOR: centre V, normal N, major radius R1 and a smaller minor radius R2.
pub(crate) fn prepare_tor(b: &Body, _: &mut Vec<Warning>) -> Result<(super::Shape, Aabb), String> {
    let n = nonzero(b.vec3(3), "normal")?;
    let (r1, r2) = (
        positive(b.params[6], "major radius")?,
        positive(b.params[7], "minor radius")?,
    );
    if r2 >= r1 {
        return Err(format!(
            "minor radius {r2} must be smaller than major radius {r1}"
        ));
    }
    let torus = Torus::new(b.vec3(0), n, r1, r2);
    let bounds = torus.bounds();
    Ok((super::Shape::Torus(torus), bounds))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The ray from `from` along `dir`, and it in the frame of `torus`
    /// (origin, direction, range in the torus's box).
    fn local_ray(
        torus: &Torus,
        from: DVec3,
        dir: DVec3,
    ) -> Option<(Ray, DVec3, DVec3, (f64, f64))> {
        let ray = Ray::new(from, dir.normalize());
        let (o, d, range) = torus.local_range(&ray)?;
        Some((ray, o, d, range))
    }

    proptest! {
        /// Every ray the quick test passes over gets no segment from the
        /// quartic either: grid rays (along the world's axes, through tori
        /// turned to an axis or leaning) and rays in any direction.
        #[test]
        fn rays_passed_over_meet_no_tube(
            axis in prop::sample::select(vec![DVec3::X, DVec3::Y, DVec3::Z, DVec3::new(0.3015, 0.3015, 0.9045)]),
            (r1, r2) in (1.0f64..10.0, 0.05f64..0.95).prop_map(|(r1, k)| (r1, r1 * k)),
            from in prop::array::uniform3(-12.0f64..12.0),
            along in 0usize..4,
            dir in prop::array::uniform3(-1.0f64..1.0),
        ) {
            let torus = Torus::new(DVec3::new(0.5, -0.25, 1.0), axis, r1, r2);
            let dir = match along {
                3 => DVec3::from(dir),
                k => DVec3::AXES[k],
            };
            prop_assume!(dir.length() > 0.1);
            let from = DVec3::from(from) - dir.normalize() * 30.0;
            if let Some((ray, o, d, range)) = local_ray(&torus, from, dir) {
                if torus.misses_clearly(o, d, range) {
                    let mut segs = Vec::new();
                    torus.shoot_quartic(&ray, (o, d), range, &mut segs);
                    prop_assert!(segs.is_empty(), "{segs:?}");
                }
            }
        }
    }

    #[test]
    fn rays_through_the_hole_and_beside_the_rim_are_passed_over() {
        let torus = Torus::new(DVec3::ZERO, DVec3::X, 5.0, 2.0);
        // Along the axis through the hole, and across it (in the box)
        // beside the rim of the tube where they pass.
        for (from, dir) in [
            (DVec3::new(-20.0, 1.0, 0.5), DVec3::X),
            (DVec3::new(1.5, -20.0, 6.6), DVec3::Y),
            (DVec3::new(1.0, 6.9, -20.0), DVec3::Z),
        ] {
            let (_, o, d, range) = local_ray(&torus, from, dir).unwrap();
            assert!(torus.misses_clearly(o, d, range), "{from} {dir}");
        }
        // Rays that meet the tube are not.
        for (from, dir) in [
            (DVec3::new(-20.0, 5.0, 0.0), DVec3::X),
            (DVec3::new(0.0, -20.0, 0.0), DVec3::Y),
            (DVec3::new(1.9, -20.0, 5.0), DVec3::Y),
        ] {
            let (_, o, d, range) = local_ray(&torus, from, dir).unwrap();
            assert!(!torus.misses_clearly(o, d, range), "{from} {dir}");
            let mut segs = Vec::new();
            torus.shoot(&Ray::new(from, dir), &mut segs);
            assert!(!segs.is_empty(), "{from} {dir}");
        }
    }
}
