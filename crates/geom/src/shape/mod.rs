//! Prepared bodies: the form `prepare` computes once (inverse matrices,
//! squared radii, plane sets), and where a ray enters and leaves them.
//!
//! Every shape reports *segments* on the whole line of the ray
//! (`-inf < t < +inf`), each tagged with the face crossed at either end, so
//! that results can be cached per ray and reused by every region that
//! mentions the body. Convex bodies give at most one segment; the torus, the
//! general TGC, quadrics and faceted ARS solids may give several.
//!
//! One file per body family holds everything about it: the checks of a
//! body's values and its preparation (`prepare_…`, named in the body
//! table, [`crate::table`]), the prepared form, where a ray enters and
//! leaves it, its normal and bounds, and its lane form for the packet
//! tracer. A new body type of an existing family is one function there and
//! one table entry; a new family is one file and a [`Shape`] variant.

pub(crate) mod cone;
pub(crate) mod ellipsoid;
pub(crate) mod mesh;
mod poly;
pub(crate) mod polyhedron;
pub(crate) mod quadric;
pub(crate) mod rpp;
pub(crate) mod sphere;
pub(crate) mod torus;

pub use cone::{Cone, GeneralCone};
pub use ellipsoid::Ellipsoid;
pub use mesh::{ars_triangles, Mesh};
pub use polyhedron::{arb_points, Plane, Polyhedron};
pub use quadric::Quadric;
pub use rpp::Rpp;
pub use sphere::Sphere;
pub use torus::Torus;

use sv_math::lanes::Lanes;
use sv_math::simd::Simd;
use sv_math::{Aabb, DVec3, Ray};

/// The corners `c ± a ± b` of two parallelograms, given as `(c, a, b)`:
/// their convex hull holds a prism or a truncated cone whose ends lie in
/// them.
fn ends(p: (DVec3, DVec3, DVec3), q: (DVec3, DVec3, DVec3)) -> Vec<DVec3> {
    [p, q]
        .iter()
        .flat_map(|&(c, a, b)| [c - a - b, c + a - b, c + a + b, c - a + b])
        .collect()
}

/// Where the segment from `a` to `b` crosses the plane whose signed
/// distances at `a` and `b` are `fa` and `fb` (of opposite signs): the
/// cut of an edge, for the bodies' parts within a box.
fn edge_crossing(a: DVec3, b: DVec3, fa: f64, fb: f64) -> DVec3 {
    a + (b - a) * (fa / (fa - fb))
}

/// A stretch of the ray inside a body, with the faces crossed at its ends.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Seg {
    /// Entry parameter (may be `-inf`).
    pub t0: f64,
    /// Exit parameter (may be `+inf`).
    pub t1: f64,
    /// Face crossed on entry.
    pub f0: u32,
    /// Face crossed on exit.
    pub f1: u32,
}

/// A body ready for ray casting.
#[derive(Clone, Debug)]
pub enum Shape {
    /// Sphere.
    Sphere(Sphere),
    /// Ellipsoid (ELL, ELL1, ELLG).
    Ellipsoid(Ellipsoid),
    /// Cylinder or truncated cone with similar end ellipses (RCC, REC, TRC,
    /// TEC, and TGC with equal axis ratios).
    Cone(Cone),
    /// TGC whose top ellipse is not similar to the base (quartic surface).
    GeneralCone(GeneralCone),
    /// Axis-aligned box (RPP).
    Rpp(Rpp),
    /// Convex polyhedron or half-space (BOX, RAW, ARB*, HAF, PLA, XYP…).
    Polyhedron(Polyhedron),
    /// General quadric (QUA, infinite cylinders).
    Quadric(Quadric),
    /// Torus.
    Torus(Torus),
    /// Closed triangle mesh (ARS).
    Mesh(Mesh),
}

impl Shape {
    /// Append the segments of the ray's line inside the body to `out`,
    /// sorted and disjoint.
    #[inline]
    pub fn shoot(&self, ray: &Ray, out: &mut Vec<Seg>) {
        match self {
            Shape::Sphere(s) => s.shoot(ray, out),
            Shape::Ellipsoid(s) => s.shoot(ray, out),
            Shape::Cone(s) => s.shoot(ray, out),
            Shape::GeneralCone(s) => s.shoot(ray, out),
            Shape::Rpp(s) => s.shoot(ray, out),
            Shape::Polyhedron(s) => s.shoot(ray, out),
            Shape::Quadric(s) => s.shoot(ray, out),
            Shape::Torus(s) => s.shoot(ray, out),
            Shape::Mesh(s) => s.shoot(ray, out),
        }
    }

    /// Outward unit normal of `face` at point `p` (on that face).
    #[inline(always)]
    pub fn normal(&self, face: u32, p: DVec3) -> DVec3 {
        match self {
            Shape::Sphere(s) => s.normal(p),
            Shape::Ellipsoid(s) => s.normal(p),
            Shape::Cone(s) => s.normal(face, p),
            Shape::GeneralCone(s) => s.normal(face, p),
            Shape::Rpp(s) => s.normal(face),
            Shape::Polyhedron(s) => s.normal(face),
            Shape::Quadric(s) => s.normal(p),
            Shape::Torus(s) => s.normal(p),
            Shape::Mesh(s) => s.normal(face),
        }
    }

    /// True when `p` is strictly inside (used by tests, checks and volume
    /// sampling; the tracer never needs it).
    pub fn contains(&self, p: DVec3) -> bool {
        match self {
            Shape::Sphere(s) => s.contains(p),
            Shape::Ellipsoid(s) => s.contains(p),
            Shape::Cone(s) => s.contains(p),
            Shape::GeneralCone(s) => s.contains(p),
            Shape::Rpp(s) => s.contains(p),
            Shape::Polyhedron(s) => s.contains(p),
            Shape::Quadric(s) => s.contains(p),
            Shape::Torus(s) => s.contains(p),
            Shape::Mesh(s) => s.contains(p),
        }
    }

    /// Bounds (infinite sides for unbounded bodies).
    pub fn bounds(&self) -> Aabb {
        match self {
            Shape::Sphere(s) => s.bounds(),
            Shape::Ellipsoid(s) => s.bounds(),
            Shape::Cone(s) => s.bounds(),
            Shape::GeneralCone(s) => s.bounds(),
            Shape::Rpp(s) => s.bounds(),
            Shape::Polyhedron(s) => s.bounds(),
            Shape::Quadric(_) => Aabb::INFINITE,
            Shape::Torus(s) => s.bounds(),
            Shape::Mesh(s) => s.bounds(),
        }
    }

    /// Bounds of the body's part of the box `within`, never smaller than
    /// that part but for rounding (pad them by a tolerance): a
    /// polyhedron's planes' parts of the box
    /// ([`Polyhedron::bounds_within`]), a sphere's part worked out axis by
    /// axis, and where the box is flat across an axis (the plane a grid
    /// row's rays lie in) a mesh's crossings of that plane; the body's
    /// bounds within the box for the other shapes.
    pub fn bounds_within(&self, within: &Aabb) -> Aabb {
        match self {
            Shape::Polyhedron(s) => s.bounds_within(within),
            Shape::Sphere(s) => s.bounds_within(within),
            Shape::Mesh(s) => s.bounds_within(within),
            _ => self.bounds().intersection(within),
        }
    }

    /// Whether [`Shape::bounds_within`] can give less than the body's
    /// bounds within a box: not for a polyhedron square to the axes, nor
    /// the shapes it gives the bounds of.
    pub fn narrows_within(&self) -> bool {
        match self {
            Shape::Polyhedron(s) => s
                .planes()
                .iter()
                .any(|plane| plane.n.abs().max_element() != 1.0),
            Shape::Sphere(_) => true,
            Shape::Mesh(s) => s.cuts(),
            _ => false,
        }
    }

    /// A few points whose convex hull holds the body, tighter than its
    /// bounds' corners for a body turned to the axes, where it has such a
    /// set: a bounded polyhedron's corners (see [`Polyhedron::corners`],
    /// `eps`), or the corners of the parallelograms around a cone's two
    /// ends or of the parallelepiped around an ellipsoid's axes.
    pub fn hull_points(&self, eps: f64) -> Option<Vec<DVec3>> {
        match self {
            Shape::Polyhedron(s) => s.corners(eps),
            Shape::Cone(s) => Some(s.corners()),
            Shape::Ellipsoid(s) => Some(s.corners()),
            _ => None,
        }
    }

    /// Bounds of the space outside the body (the closure of its
    /// complement): all space, but for a half-space whose plane is normal
    /// to an axis, whose outside is the other half-space. A zone that
    /// subtracts such a body is bounded by it (`+ZCC +XYP -XYP` is a finite
    /// cylinder).
    pub fn outside_bounds(&self) -> Aabb {
        let mut bounds = Aabb::INFINITE;
        if let Shape::Polyhedron(p) = self {
            if let [plane] = p.planes() {
                for a in 0..3 {
                    if plane.n[a] == 1.0 {
                        bounds.min[a] = plane.d;
                    } else if plane.n[a] == -1.0 {
                        bounds.max[a] = -plane.d;
                    }
                }
            }
        }
        bounds
    }

    /// True for shapes whose segments are always a single convex stretch.
    pub fn is_convex(&self) -> bool {
        !matches!(
            self,
            Shape::GeneralCone(_) | Shape::Quadric(_) | Shape::Torus(_) | Shape::Mesh(_)
        )
    }
}

/// A body's segment along each lane's ray, in the lanes of `hit`: entry
/// and exit, and the faces crossed there (small integers in `f64`). A lane
/// of `scalar` is one whose answer the lanes cannot give (a faceted solid
/// crossed more than twice, a general cone met at a slant): the caller
/// leaves it to the scalar code.
pub struct SegLanes<S: Simd> {
    /// Entry.
    pub t0: S::F,
    /// Exit.
    pub t1: S::F,
    /// Face crossed on entry.
    pub f0: S::F,
    /// Face crossed on exit.
    pub f1: S::F,
    /// The lanes whose ray meets the body.
    pub hit: S::M,
    /// The lanes left to [`Shape::shoot`] (never in `hit`).
    pub scalar: S::M,
}

impl Shape {
    /// True for the shapes [`Shape::shoot_lanes`] casts.
    pub fn has_lanes(&self) -> bool {
        matches!(
            self,
            Shape::Sphere(_)
                | Shape::Ellipsoid(_)
                | Shape::Cone(_)
                | Shape::GeneralCone(_)
                | Shape::Rpp(_)
                | Shape::Polyhedron(_)
                | Shape::Mesh(_)
        )
    }

    /// [`Shape::normal`] in every lane, at points `p` on faces `face` (as
    /// `f64`), for the shapes of [`Shape::has_lanes`] only.
    #[inline(always)]
    pub fn normal_lanes<S: Simd>(&self, s: S, face: S::F, p: [S::F; 3]) -> [S::F; 3] {
        match self {
            Shape::Sphere(b) => b.normal_lanes(s, p),
            Shape::Ellipsoid(b) => b.normal_lanes(s, p),
            Shape::Cone(b) => b.normal_lanes(s, face, p),
            Shape::GeneralCone(b) => b.normal_lanes(s, face, p),
            Shape::Rpp(b) => b.normal_lanes(s, face),
            Shape::Polyhedron(b) => b.normal_lanes(s, face),
            Shape::Mesh(b) => b.normal_lanes(s, face),
            _ => unreachable!("normals in lanes asked of a shape without them"),
        }
    }

    /// [`Shape::shoot`] for every lane, for the shapes of
    /// [`Shape::has_lanes`] only (one segment at most: the lanes whose ray
    /// a faceted solid would give more, or whose ray meets a general cone
    /// at a slant, are marked `scalar`); the callers leave the other
    /// shapes to the scalar code.
    ///
    /// Inlined where optimised, as all the lanes' code is (see
    /// [`Torus::shoot_lanes_both`] for why not otherwise).
    #[cfg_attr(not(debug_assertions), inline(always))]
    #[cfg_attr(debug_assertions, inline(never))]
    pub fn shoot_lanes<S: Simd>(&self, s: S, r: &Lanes<S>) -> SegLanes<S> {
        match self {
            Shape::Sphere(b) => b.shoot_lanes(s, r),
            Shape::Ellipsoid(b) => b.shoot_lanes(s, r),
            Shape::Cone(b) => b.shoot_lanes(s, r),
            Shape::GeneralCone(b) => b.shoot_lanes(s, r),
            Shape::Rpp(b) => b.shoot_lanes(s, r),
            Shape::Polyhedron(b) => b.shoot_lanes(s, r),
            Shape::Mesh(b) => b.shoot_lanes(s, r),
            _ => unreachable!("lanes asked to cast a shape they cannot"),
        }
    }
}

/// Roots of `a t² + 2 b t + c = 0`, ascending, computed without
/// cancellation (Numerical Recipes §5.6). `None` when there is no real root
/// or `a == 0`.
#[inline]
pub(crate) fn quadratic(a: f64, b: f64, c: f64) -> Option<(f64, f64)> {
    if a == 0.0 {
        return None;
    }
    let disc = b * b - a * c;
    if disc < 0.0 {
        return None;
    }
    let q = -(b + b.signum() * disc.sqrt());
    if q == 0.0 {
        // b == 0 and disc == 0: double root at 0.
        return Some((0.0, 0.0));
    }
    let r0 = q / a;
    let r1 = c / q;
    Some(if r0 < r1 { (r0, r1) } else { (r1, r0) })
}

/// Build sorted segments for a non-convex body from candidate crossings by
/// classifying the midpoint of each gap. `cands` holds (t, face) pairs.
pub(crate) fn segments_by_classification(
    cands: &mut [(f64, u32)],
    ray: &Ray,
    inside: impl Fn(DVec3) -> bool,
    out: &mut Vec<Seg>,
) {
    cands.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut cur: Option<Seg> = None;
    for w in 0..cands.len().saturating_sub(1) {
        let (ta, fa) = cands[w];
        let (tb, fb) = cands[w + 1];
        if tb <= ta || !inside(ray.at(0.5 * (ta + tb))) {
            continue;
        }
        match &mut cur {
            Some(s) if s.t1 == ta => {
                s.t1 = tb;
                s.f1 = fb;
            }
            _ => {
                out.extend(cur.take());
                cur = Some(Seg {
                    t0: ta,
                    t1: tb,
                    f0: fa,
                    f1: fb,
                });
            }
        }
    }
    out.extend(cur);
}

#[cfg(test)]
mod tests {
    use super::polyhedron::convex_hull_planes;
    use super::*;
    use sv_math::DMat3;

    /// Points on the surface of `s`, where rays from `inside` in many
    /// directions leave it.
    fn surface(s: &Shape, inside: DVec3) -> Vec<DVec3> {
        let mut out = Vec::new();
        let mut segs = Vec::new();
        for i in 0..40 {
            for j in 0..20 {
                let (az, el) = (i as f64 * 0.157, -1.5 + j as f64 * 0.157);
                let d = DVec3::new(el.cos() * az.cos(), el.cos() * az.sin(), el.sin());
                let ray = Ray::new(inside, d);
                segs.clear();
                s.shoot(&ray, &mut segs);
                out.extend(segs.iter().map(|g| ray.at(g.t1)));
            }
        }
        out
    }

    #[test]
    fn hull_points_hold_turned_bodies() {
        let (a, b, h) = (
            DVec3::new(0.8, 0.6, 0.0) * 0.3,
            DVec3::new(-0.6, 0.8, 0.2).normalize() * 0.2,
            DVec3::new(4.0, 1.0, 2.0),
        );
        let v = DVec3::new(1.0, -2.0, 0.5);
        let shapes = [
            (Shape::Cone(Cone::new(v, a, b, h, 0.4)), v + h * 0.3),
            (
                Shape::Ellipsoid(Ellipsoid::new(v, DMat3::from_cols(h * 0.5, a, b))),
                v,
            ),
        ];
        for (s, inside) in &shapes {
            let pts = s.hull_points(1e-9).expect("a bounded convex body");
            let hull = convex_hull_planes(&pts, 1e-12);
            let on = surface(s, *inside);
            assert!(on.len() > 700, "{s:?}");
            for p in on {
                for pl in &hull.planes {
                    assert!(pl.n.dot(p) <= pl.d + 1e-9, "{p} outside the hull of {s:?}");
                }
            }
            // Tighter than the bounds' box for these turned bodies.
            let b = s.bounds().size();
            assert!(hull.volume < 0.9 * b.x * b.y * b.z);
        }
    }
}
