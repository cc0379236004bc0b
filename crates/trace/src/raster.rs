//! Zones as a camera's raster sees them, from a small copy of what that
//! needs of each: a renderer places every bounded zone on the raster once a
//! frame ([`Prepared::place_proxy`]), and 100,000 zones' boxes and balls are
//! 10 MB in double precision, read anew in every frame after the rays have
//! pushed them out of the caches.

use crate::frustum::RasterExtent;
use crate::prepare::{Enclosure, EnclosureRef, Prepared};
use sv_math::{Aabb, DVec3, RayGen};

/// A bounded opaque zone's box, and the ball of a sphere among its `+`
/// bodies, in single precision, rounded outward: a box and a ball that
/// hold the zone's. 48 bytes where the zone and its [`Enclosure`] are 104.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RasterProxy {
    lo: [f32; 3],
    hi: [f32; 3],
    enclosure: ProxyEnclosure,
    zi: u32,
}

/// A [`RasterProxy`]'s [`Enclosure`].
#[derive(Clone, Copy, Debug)]
enum ProxyEnclosure {
    Box,
    /// Centre and radius.
    Ball([f32; 4]),
    /// Hull points: the zone's own, read where it is placed.
    Hull,
}

/// The greatest `f32` not above `v`.
fn down(v: f64) -> f32 {
    let f = v as f32;
    if f64::from(f) > v {
        f.next_down()
    } else {
        f
    }
}

/// The least `f32` not below `v`.
fn up(v: f64) -> f32 {
    let f = v as f32;
    if f64::from(f) < v {
        f.next_up()
    } else {
        f
    }
}

impl RasterProxy {
    /// Zone `zi`'s, from its box and [`Enclosure`].
    pub(crate) fn new(zi: u32, b: &Aabb, t: &Enclosure) -> RasterProxy {
        let enclosure = match *t {
            Enclosure::Box => ProxyEnclosure::Box,
            Enclosure::Points(..) => ProxyEnclosure::Hull,
            Enclosure::Ball(c, r) => {
                let c32 = c.to_array().map(|v| v as f32);
                // The radius grown by how far the centre moved.
                let moved = (c - DVec3::from(c32.map(f64::from))).length();
                ProxyEnclosure::Ball([c32[0], c32[1], c32[2], up((r + moved) * (1.0 + 1e-15))])
            }
        };
        RasterProxy {
            lo: b.min.to_array().map(down),
            hi: b.max.to_array().map(up),
            enclosure,
            zi,
        }
    }
}

impl Prepared {
    /// The bounded zones of opaque regions ([`Prepared::place_proxy`] takes
    /// their places in this order, that of the zones).
    pub fn raster_proxy_count(&self) -> usize {
        self.raster_proxies.len()
    }

    /// The `k`th bounded zone of an opaque region (counting in the order of
    /// the zones), where it may be seen on the raster of `gen`, and a lower
    /// bound of where the raster's rays can enter it: a rectangle that
    /// holds [`Prepared::zone_rect`]'s (nowhere only when that is nowhere
    /// too), and a bound not above [`Prepared::entry_bound`]'s, in single
    /// precision (sorted by a radix sort in half the passes). Both are
    /// those of a box and ball grown by single precision's rounding, a
    /// ten-millionth of their coordinates (a small part of a pixel but
    /// close to the eye); this reads 48 bytes of the zone, not 104.
    pub fn place_proxy(&self, k: usize, gen: &RayGen) -> (u32, RasterExtent, f32) {
        let s = &self.raster_proxies[k];
        let b = Aabb {
            min: DVec3::from(s.lo.map(f64::from)),
            max: DVec3::from(s.hi.map(f64::from)),
        };
        let enclosure = match s.enclosure {
            ProxyEnclosure::Box => EnclosureRef::Box,
            ProxyEnclosure::Ball(v) => {
                let [x, y, z, r] = v.map(f64::from);
                EnclosureRef::Ball(DVec3::new(x, y, z), r)
            }
            ProxyEnclosure::Hull => self.enclosure(s.zi),
        };
        let (eye, parallel) = (gen.eye, gen.ortho.then_some(gen.forward));
        (
            s.zi,
            rect_of(&b, enclosure, gen),
            down(entry_of(&b, enclosure, eye, parallel)),
        )
    }
}

/// [`Prepared::entry_bound`] of a zone of box `b` and [`EnclosureRef`] `t`.
#[inline]
pub(crate) fn entry_of(b: &Aabb, t: EnclosureRef<'_>, eye: DVec3, parallel: Option<DVec3>) -> f64 {
    let base = parallel.map_or(0.0, |d| eye.dot(d));
    let mut near = match parallel {
        None => (b.min - eye).max(eye - b.max).max(DVec3::ZERO).length(),
        Some(d) => {
            // The box corner furthest against `d`, axis by axis: an axis
            // the rays run across adds nothing, even where the box is
            // unbounded along it (0 · ∞ would be not a number, and a zone
            // whose bound is not a number was never tried: a half-space
            // across the view hid nothing).
            (0..3)
                .map(|a| match d[a] {
                    x if x > 0.0 => b.min[a] * x,
                    x if x < 0.0 => b.max[a] * x,
                    _ => 0.0,
                })
                .sum::<f64>()
                - base
        }
    };
    // A ball inside the box may lie farther off than the box.
    if let EnclosureRef::Ball(c, r) = t {
        let ball = match parallel {
            None => (c - eye).length() - r,
            Some(d) => c.dot(d) - r - base,
        };
        near = near.max(ball);
    }
    // Rounding slack keeps the bound a bound.
    near - 1e-9 * (near.abs() + base.abs())
}

/// [`Prepared::zone_rect`] of a zone of box `b` and [`EnclosureRef`] `t`.
#[inline]
pub(crate) fn rect_of(b: &Aabb, t: EnclosureRef<'_>, gen: &RayGen) -> RasterExtent {
    let corner = |i: usize| {
        DVec3::new(
            if i & 1 == 0 { b.min.x } else { b.max.x },
            if i & 2 == 0 { b.min.y } else { b.max.y },
            if i & 4 == 0 { b.min.z } else { b.max.z },
        )
    };
    // Rays meet only points ahead of where they start. The corner
    // farthest ahead, term by term: rounding keeps each term's order, so
    // this is the greatest of the corners' `(corner - eye)·forward`.
    let (e, f) = (gen.eye, gen.forward);
    let ahead = |lo: f64, hi: f64, e: f64, f: f64| ((lo - e) * f).max((hi - e) * f);
    if ahead(b.min.x, b.max.x, e.x, f.x)
        + ahead(b.min.y, b.max.y, e.y, f.y)
        + ahead(b.min.z, b.max.z, e.z, f.z)
        < 0.0
    {
        return RasterExtent::Nowhere;
    }
    let boxed = || gen.raster_rect((0..8).map(corner));
    let rect = match t {
        // The ball lies in the box.
        EnclosureRef::Ball(c, r) => gen.ball_rect(c, r).or_else(boxed),
        EnclosureRef::Points(pts) => match (boxed(), gen.raster_rect(pts.iter().copied())) {
            (Some(a), Some(h)) => Some([
                a[0].max(h[0]),
                a[1].max(h[1]),
                a[2].min(h[2]),
                a[3].min(h[3]),
            ]),
            (a, h) => a.or(h),
        },
        EnclosureRef::Box => boxed(),
    };
    rect.map_or(RasterExtent::Anywhere, RasterExtent::Within)
}

#[cfg(test)]
mod tests {
    use crate::{PrepareOptions, Prepared, RasterExtent};
    use sv_geom::{Body, BodyKind, Geometry, Op, Region, Term, Zone};
    use sv_math::{DVec3, RayGen};

    #[test]
    fn raster_proxies_hold_the_zones_and_stay_within_a_pixel_of_them() {
        // Far from the origin, where single precision rounds by a
        // thousandth: spheres (balls), axis-aligned boxes (a box only),
        // turned boxes (hull points), and spheres cut by boxes (a ball and a
        // smaller box).
        let mut g = Geometry::default();
        let mut rnd = crate::test_numbers(11);
        let far = DVec3::new(12345.678, -9876.543, 4321.0);
        for i in 0..80 {
            let c = far + DVec3::new(rnd(), rnd(), rnd()) * 6.0;
            let r = 0.2 + rnd();
            let (kind, params) = match i % 4 {
                0 | 3 => (BodyKind::Sph, vec![c.x, c.y, c.z, r]),
                1 => (
                    BodyKind::Rpp,
                    vec![c.x, c.x + r, c.y, c.y + r, c.z, c.z + 2.0 * r],
                ),
                _ => {
                    let (a, b) = (rnd() - 0.5, rnd() - 0.5);
                    (BodyKind::Box, crate::turned_box(c.to_array(), a, b))
                }
            };
            g.bodies.push(Body::new(format!("b{i}"), kind, params));
            let mut terms = vec![Term {
                op: Op::Inside,
                body: g.bodies.len() - 1,
            }];
            if i % 4 == 3 {
                // The box of the lower half of the sphere.
                let p = vec![c.x - r, c.x + r, c.y - r, c.y + r, c.z - r, c.z];
                g.bodies.push(Body::new(format!("h{i}"), BodyKind::Rpp, p));
                terms.push(Term {
                    op: Op::Inside,
                    body: g.bodies.len() - 1,
                });
            }
            g.regions
                .push(Region::new(format!("r{i}"), vec![Zone::new(terms)]));
        }
        let p = Prepared::new(&g, &PrepareOptions::default()).unwrap().0;
        assert_eq!(p.raster_proxy_count(), g.regions.len());
        let centre = far + DVec3::splat(3.0);
        let views = [
            // Outside, perspective and orthographic; inside the crowd.
            (centre + DVec3::new(-20.0, 6.0, 4.0), false),
            (centre + DVec3::new(-20.0, 6.0, 4.0), true),
            (centre + DVec3::new(0.5, -0.2, 0.1), false),
        ];
        let (mut within, mut nowhere, mut anywhere) = (0, 0, 0);
        for (view, (eye, ortho)) in views.into_iter().enumerate() {
            let forward = (centre - eye).normalize_or(DVec3::X);
            let right = forward.cross(DVec3::Z).normalize() * if ortho { 5.0 } else { 0.6 };
            let up = right.cross(forward).normalize() * if ortho { 3.75 } else { 0.45 };
            let gen = RayGen::new(eye, right, up, forward, ortho, 640, 480);
            let parallel = ortho.then_some(forward);
            let mut last = None;
            for k in 0..p.raster_proxy_count() {
                let (zi, seen, near) = p.place_proxy(k, &gen);
                assert!(last < Some(zi), "zones in their order");
                last = Some(zi);
                let exact = p.entry_bound(zi, eye, parallel);
                assert!(f64::from(near) <= exact, "zone {zi}: {near} past {exact}");
                assert!(
                    exact - f64::from(near) < 0.01,
                    "zone {zi}: {near} for {exact}"
                );
                match (p.zone_rect(zi, &gen), seen) {
                    (RasterExtent::Nowhere, s) => {
                        nowhere += usize::from(s == RasterExtent::Nowhere);
                    }
                    (RasterExtent::Within(a), RasterExtent::Within(b)) => {
                        // Holds it; seen from 20 units off, by less than a
                        // tenth of a pixel (close to the eye, a thousandth
                        // of a unit can be a pixel).
                        let most = if view < 2 { 0.1 } else { f64::INFINITY };
                        for i in 0..4 {
                            let grown = if i < 2 { a[i] - b[i] } else { b[i] - a[i] };
                            assert!(grown >= -1e-9 && grown < most, "zone {zi}: {b:?} for {a:?}");
                        }
                        within += 1;
                    }
                    (RasterExtent::Anywhere, RasterExtent::Anywhere) => anywhere += 1,
                    (a, b) => panic!("zone {zi}: {b:?} for {a:?}"),
                }
            }
        }
        assert!(
            within > 100 && nowhere > 5 && anywhere > 5,
            "{within} {nowhere} {anywhere}"
        );
    }
}
