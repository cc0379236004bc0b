use super::Seg;
use super::SegLanes;
use crate::body::{independent, nonzero, perpendicular, Warning};
use crate::table::BodyKind;
use crate::Body;
use sv_math::lanes::{dot, splat3, Lanes};
use sv_math::simd::Simd;
use sv_math::{Aabb, DVec3, Ray};

/// A plane `n·x = d`; the inside is `n·x <= d`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    /// Outward unit normal.
    pub n: DVec3,
    /// Offset.
    pub d: f64,
}

/// A convex polyhedron as an intersection of half-spaces (Haines 1991,
/// "Fast ray-convex polyhedron intersection"). A single plane is a
/// half-space (HAF, PLA, XYP…); bounds may then be infinite.
#[derive(Clone, Debug)]
pub struct Polyhedron {
    planes: Vec<Plane>,
    bounds: Aabb,
}

impl Polyhedron {
    /// From planes with unit outward normals, and precomputed bounds.
    pub fn new(planes: Vec<Plane>, bounds: Aabb) -> Polyhedron {
        Polyhedron { planes, bounds }
    }

    /// The planes.
    pub fn planes(&self) -> &[Plane] {
        &self.planes
    }

    /// Append the segments of the ray inside the body to `out` (see
    /// [`super::Shape::shoot`]).
    #[inline]
    pub fn shoot(&self, ray: &Ray, out: &mut Vec<Seg>) {
        let mut t0 = f64::NEG_INFINITY;
        let mut t1 = f64::INFINITY;
        let (mut f0, mut f1) = (0, 0);
        for (i, pl) in self.planes.iter().enumerate() {
            let denom = pl.n.dot(ray.dir);
            let dist = pl.d - pl.n.dot(ray.origin);
            if denom == 0.0 {
                if dist < 0.0 {
                    return;
                }
                continue;
            }
            let t = dist / denom;
            if denom < 0.0 {
                if t > t0 {
                    t0 = t;
                    f0 = i as u32;
                }
            } else if t < t1 {
                t1 = t;
                f1 = i as u32;
            }
            if t0 > t1 {
                return;
            }
        }
        if t0 < t1 {
            out.push(Seg { t0, t1, f0, f1 });
        }
    }

    /// [`Polyhedron::shoot`] in every lane, operation for operation (a lane
    /// that the scalar code would leave early stays missed).
    #[inline(always)]
    pub fn shoot_lanes<S: Simd>(&self, s: S, r: &Lanes<S>) -> SegLanes<S> {
        let zero = s.splat(0.0);
        let (mut t0, mut t1) = (s.splat(f64::NEG_INFINITY), s.splat(f64::INFINITY));
        let (mut f0, mut f1) = (zero, zero);
        let mut miss = s.none();
        for (i, pl) in self.planes.iter().enumerate() {
            let n = splat3(s, pl.n);
            let denom = dot(s, n, r.d);
            let dist = s.sub(s.splat(pl.d), dot(s, n, r.o));
            let flat = s.eq(denom, zero);
            miss = s.or(miss, s.and(flat, s.lt(dist, zero)));
            if s.all(flat) {
                // Every ray runs along the plane, as a grid's rays do along
                // the sides of a box: it can only miss (the division
                // below would change nothing in a lane parallel to it).
                continue;
            }
            let t = s.div(dist, denom);
            let entering = s.lt(denom, zero);
            let face = s.splat(i as f64);
            let n0 = s.and(entering, s.gt(t, t0));
            let n1 = s.andnot(s.andnot(s.lt(t, t1), entering), flat);
            t0 = s.select(n0, t, t0);
            f0 = s.select(n0, face, f0);
            t1 = s.select(n1, t, t1);
            f1 = s.select(n1, face, f1);
            miss = s.or(miss, s.gt(t0, t1));
        }
        SegLanes {
            t0,
            t1,
            f0,
            f1,
            hit: s.andnot(s.lt(t0, t1), miss),
            scalar: s.none(),
        }
    }

    /// Points whose convex hull holds the polyhedron: where three of its
    /// planes meet inside all the others (within `eps`, so that rounding
    /// can only add points, never drop a corner). `None` for a polyhedron
    /// with infinite bounds, with too many planes to try every triple, or
    /// whose corners do not pass the checks below.
    pub fn corners(&self, eps: f64) -> Option<Vec<DVec3>> {
        let n = self.planes.len();
        if !self.bounds.is_finite() || n > 12 {
            return None;
        }
        let p = &self.planes;
        let out = plane_corners(p, eps);
        // Checks that no corner was lost to a badly conditioned triple:
        // the corners reach the bounds (made from the vertices) on every
        // side, and every face has at least three of them.
        let reach = Aabb::from_points(out.iter().copied());
        let reaches = (reach.min - self.bounds.min).max_element() <= eps
            && (self.bounds.max - reach.max).max_element() <= eps;
        let faces = p.iter().all(|q| {
            out.iter()
                .filter(|x| (q.n.dot(**x) - q.d).abs() <= eps)
                .count()
                >= 3
        });
        (out.len() >= 4 && reaches && faces).then_some(out)
    }

    /// Outward unit normal at a point of the surface.
    pub fn normal(&self, face: u32) -> DVec3 {
        self.planes[face as usize].n
    }

    /// [`Polyhedron::normal`] in every lane (faces held as `f64`).
    #[inline(always)]
    pub fn normal_lanes<S: Simd>(&self, s: S, face: S::F) -> [S::F; 3] {
        let mut n = [s.splat(0.0); 3];
        for (i, pl) in self.planes.iter().enumerate() {
            let here = s.eq(face, s.splat(i as f64));
            n = [
                s.select(here, s.splat(pl.n.x), n[0]),
                s.select(here, s.splat(pl.n.y), n[1]),
                s.select(here, s.splat(pl.n.z), n[2]),
            ];
        }
        n
    }

    /// True when `p` is strictly inside.
    pub fn contains(&self, p: DVec3) -> bool {
        self.planes.iter().all(|pl| pl.n.dot(p) < pl.d)
    }

    /// Bounds (infinite sides where the body is unbounded).
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// Bounds of the part of the polyhedron inside the finite box
    /// `within`, for a half-space or another unbounded polyhedron, whose
    /// own bounds are infinite: each plane's side of the box (the box's
    /// corners on that side and the plane's crossings of its edges),
    /// bounded, and these intersected. A little larger than the part for
    /// several planes, never smaller but for rounding (pad it).
    pub fn bounds_within(&self, within: &Aabb) -> Aabb {
        let mut out = self.bounds.intersection(within);
        let (lo, hi) = (within.min, within.max);
        let corner = |k: usize| {
            DVec3::new(
                if k & 1 == 0 { lo.x } else { hi.x },
                if k & 2 == 0 { lo.y } else { hi.y },
                if k & 4 == 0 { lo.z } else { hi.z },
            )
        };
        for plane in &self.planes {
            let side = |p: DVec3| plane.n.dot(p) - plane.d;
            let mut part = Aabb::EMPTY;
            for k in 0..8 {
                let a = corner(k);
                if side(a) <= 0.0 {
                    part = part.including(a);
                }
                // The edges from this corner to the corners one bit up.
                for bit in [1, 2, 4].into_iter().filter(|bit| k & bit == 0) {
                    let b = corner(k | bit);
                    let (fa, fb) = (side(a), side(b));
                    if (fa < 0.0) != (fb < 0.0) {
                        part = part.including(super::edge_crossing(a, b, fa, fb));
                    }
                }
            }
            out = out.intersection(&part);
        }
        out
    }
}

/// Outcome of [`convex_hull_planes`].
pub(crate) struct Hull {
    pub planes: Vec<Plane>,
    pub volume: f64,
}

/// Planes of the convex hull of a few points (an ARB's ≤ 8 vertices),
/// by testing every triple: a triple spans a hull face when all points lie
/// on one side of its plane. Duplicate planes are merged. `eps` is the
/// distance below which a point counts as on the plane.
pub(crate) fn convex_hull_planes(pts: &[DVec3], eps: f64) -> Hull {
    let mut planes: Vec<Plane> = Vec::new();
    let n = pts.len();
    let centroid = pts.iter().copied().sum::<DVec3>() / n as f64;
    for i in 0..n {
        for j in i + 1..n {
            for k in j + 1..n {
                let nrm = (pts[j] - pts[i]).cross(pts[k] - pts[i]);
                let len = nrm.length();
                if len <= eps * eps {
                    continue;
                }
                let mut nrm = nrm / len;
                let mut d = nrm.dot(pts[i]);
                let (mut above, mut below) = (false, false);
                for p in pts {
                    let s = nrm.dot(*p) - d;
                    above |= s > eps;
                    below |= s < -eps;
                }
                if above && below {
                    continue;
                }
                if above || nrm.dot(centroid) > d {
                    nrm = -nrm;
                    d = -d;
                }
                if !planes
                    .iter()
                    .any(|q| q.n.dot(nrm) > 1.0 - 1e-12 && (q.d - d).abs() <= eps)
                {
                    planes.push(Plane { n: nrm, d });
                }
            }
        }
    }
    // Volume as the sum of pyramids from the centroid over the hull faces;
    // each face's area comes from the points lying on it.
    let mut volume = 0.0;
    for pl in &planes {
        let on: Vec<DVec3> = pts
            .iter()
            .copied()
            .filter(|p| (pl.n.dot(*p) - pl.d).abs() <= eps)
            .collect();
        volume += face_area(&on, pl.n) * (pl.d - pl.n.dot(centroid)) / 3.0;
    }
    Hull { planes, volume }
}

/// Area of the convex polygon spanned by coplanar points with normal `n`.
fn face_area(pts: &[DVec3], n: DVec3) -> f64 {
    if pts.len() < 3 {
        return 0.0;
    }
    let c = pts.iter().copied().sum::<DVec3>() / pts.len() as f64;
    let (u, v) = sv_math::orthonormal_basis(n);
    let mut ang: Vec<(f64, DVec3)> = pts
        .iter()
        .map(|p| ((p - c).dot(v).atan2((p - c).dot(u)), *p))
        .collect();
    ang.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut area = 0.0;
    for i in 0..ang.len() {
        let a = ang[i].1 - c;
        let b = ang[(i + 1) % ang.len()].1 - c;
        area += a.cross(b).dot(n);
    }
    0.5 * area.abs()
}

/// BOX: vertex V and three perpendicular edge vectors A, B, C.
pub(crate) fn prepare_box(b: &Body, warnings: &mut Vec<Warning>) -> Prepared {
    let (a, bb, c) = (
        nonzero(b.vec3(3), "edge A")?,
        nonzero(b.vec3(6), "edge B")?,
        nonzero(b.vec3(9), "edge C")?,
    );
    perpendicular(a, bb, "edges A and B")?;
    perpendicular(a, c, "edges A and C")?;
    perpendicular(bb, c, "edges B and C")?;
    let o = b.vec3(0);
    let corners: Vec<DVec3> = (0..8)
        .map(|i| o + a * (i & 1) as f64 + bb * ((i >> 1) & 1) as f64 + c * ((i >> 2) & 1) as f64)
        .collect();
    polyhedron_from_points(b, &corners, warnings, false)
}

/// RAW (WED): the right triangle V, V+A, V+B swept along C.
pub(crate) fn prepare_raw(b: &Body, warnings: &mut Vec<Warning>) -> Prepared {
    let (a, bb, c) = (
        nonzero(b.vec3(3), "leg A")?,
        nonzero(b.vec3(6), "leg B")?,
        nonzero(b.vec3(9), "sweep C")?,
    );
    independent(a, bb, c, "A, B and C")?;
    let o = b.vec3(0);
    let corners = [o, o + a, o + bb, o + c, o + a + c, o + bb + c];
    polyhedron_from_points(b, &corners, warnings, false)
}

/// ARB4 … ARB8: the convex hull of the vertices. An ARB8's faces are
/// checked for planarity; when one is not flat, a warning names it and the
/// solid is bounded by each face's plane as BRL-CAD makes it (see
/// [`ARB_FACE_ORDER`]), so that pictures and checks agree with rt's and
/// gqa's.
pub(crate) fn prepare_arb(b: &Body, warnings: &mut Vec<Warning>) -> Prepared {
    let corners = arb_points(b);
    polyhedron_from_points(b, &corners, warnings, b.kind == BodyKind::Arb8)
}

/// FLUKA's ARB: eight vertices and six face codes such as 1234; the hull of
/// the vertices the codes use.
pub(crate) fn prepare_arbf(b: &Body, warnings: &mut Vec<Warning>) -> Prepared {
    let vertices: Vec<DVec3> = (0..8).map(|i| b.vec3(3 * i)).collect();
    let mut used = [false; 8];
    for code in &b.params[24..30] {
        let mut digits = code.abs().round() as u64;
        while digits > 0 {
            let d = (digits % 10) as usize;
            if d == 0 || d > 8 {
                return Err(format!(
                    "face code {code} names vertex {d}, which does not exist"
                ));
            }
            used[d - 1] = true;
            digits /= 10;
        }
    }
    let corners: Vec<DVec3> = vertices
        .iter()
        .zip(used)
        .filter(|(_, u)| *u)
        .map(|(p, _)| *p)
        .collect();
    if corners.len() < 4 {
        return Err("face codes use fewer than 4 vertices".into());
    }
    polyhedron_from_points(b, &corners, warnings, false)
}

/// HAF: the half-space N·x <= D.
pub(crate) fn prepare_haf(b: &Body, _: &mut Vec<Warning>) -> Prepared {
    half_space(b.vec3(0), b.params[3])
}

/// XYP, XZP, YZP: the half-space below a plane normal to an axis.
pub(crate) fn prepare_axis_plane(b: &Body, _: &mut Vec<Warning>) -> Prepared {
    let normal = match b.kind {
        BodyKind::Xyp => DVec3::Z,
        BodyKind::Xzp => DVec3::Y,
        _ => DVec3::X,
    };
    half_space(normal, b.params[0])
}

/// PLA: the half-space behind the plane through V with outward normal N.
pub(crate) fn prepare_pla(b: &Body, _: &mut Vec<Warning>) -> Prepared {
    let n = nonzero(b.vec3(0), "normal")?;
    half_space(n, n.dot(b.vec3(3)))
}

/// What a body family's preparation gives.
type Prepared = Result<(super::Shape, Aabb), String>;

/// ARB4…ARB7 as the eight points of an ARB8 (BRL-CAD's conventions).
pub fn arb_points(b: &Body) -> Vec<DVec3> {
    let n = b.params.len() / 3;
    let p: Vec<DVec3> = (0..n).map(|i| b.vec3(3 * i)).collect();
    match b.kind {
        BodyKind::Arb4 => vec![p[0], p[1], p[2], p[0], p[3], p[3], p[3], p[3]],
        BodyKind::Arb5 => vec![p[0], p[1], p[2], p[3], p[4], p[4], p[4], p[4]],
        BodyKind::Arb6 => vec![p[0], p[1], p[2], p[3], p[4], p[4], p[5], p[5]],
        BodyKind::Arb7 => vec![p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[4]],
        _ => p,
    }
}

/// The six faces of an ARB8 by vertex numbers (1-based), as BRL-CAD names them.
const ARB_FACES: [[usize; 4]; 6] = [
    [1, 2, 3, 4],
    [5, 6, 7, 8],
    [1, 4, 8, 5],
    [2, 3, 7, 6],
    [1, 2, 6, 5],
    [4, 3, 7, 8],
];

/// The same six faces, each with its corners in the order BRL-CAD's librt
/// takes them (`rt_arb_info`): a face's plane is that of its first three
/// distinct corners that are not in line, whatever the fourth.
const ARB_FACE_ORDER: [[usize; 4]; 6] = [
    [4, 3, 2, 1],
    [5, 6, 7, 8],
    [5, 8, 4, 1],
    [3, 7, 6, 2],
    [2, 6, 5, 1],
    [8, 7, 3, 4],
];

fn polyhedron_from_points(
    b: &Body,
    pts: &[DVec3],
    warnings: &mut Vec<Warning>,
    check_faces: bool,
) -> Result<(super::Shape, Aabb), String> {
    let bounds = Aabb::from_points(pts.iter().copied());
    let size = bounds.diagonal();
    if size == 0.0 {
        return Err("all vertices coincide".into());
    }
    let eps = 1e-9 * size;
    if check_faces {
        let faces = arb_face_planes(pts, eps);
        let mut flat = true;
        for (face, plane) in ARB_FACES.iter().zip(&faces) {
            let Some(FacePlane { corners, off, .. }) = plane else {
                continue;
            };
            if let Some((vertex, off)) = off.filter(|&(_, off)| off > 1e-6 * size) {
                flat = false;
                let [first, second, third] = corners;
                warnings.push(Warning {
                    body: b.name.clone(),
                    kind: b.kind,
                    message: format!(
                        "face {}{}{}{} is not planar (vertex {vertex} is {off:.4} off the plane of vertices {first}, {second} and {third}); using that plane, as BRL-CAD does",
                        face[0], face[1], face[2], face[3]
                    ),
                });
            }
        }
        if !flat {
            return polyhedron_from_face_planes(pts, &faces, eps);
        }
    }
    let h = convex_hull_planes(pts, eps);
    if h.volume <= 1e-12 * size * size * size || h.planes.len() < 4 {
        return Err("the vertices span no volume (degenerate polyhedron)".into());
    }
    Ok((
        super::Shape::Polyhedron(Polyhedron::new(h.planes, bounds)),
        bounds,
    ))
}

/// The plane of one of an ARB8's faces as librt makes it: through
/// `corners` (vertex numbers, 1-based), facing away from the mean of the
/// eight vertices, and how far the face's other distinct vertex lies off
/// it, if it has one.
struct FacePlane {
    plane: Plane,
    corners: [usize; 3],
    off: Option<(usize, f64)>,
}

/// Each face's [`FacePlane`] in the order of [`ARB_FACES`]; `None` for a
/// face with fewer than three distinct corners out of line (librt drops
/// such a face). Corners within `eps` of one another count as one.
fn arb_face_planes(pts: &[DVec3], eps: f64) -> Vec<Option<FacePlane>> {
    let centre = pts.iter().copied().sum::<DVec3>() / pts.len() as f64;
    ARB_FACE_ORDER
        .iter()
        .map(|order| {
            let mut chosen: Vec<usize> = Vec::new();
            let mut rest: Vec<usize> = Vec::new();
            for &v in order {
                let p = pts[v - 1];
                let same = |&w: &usize| (pts[w - 1] - p).length() <= eps;
                if chosen.iter().any(same) || rest.iter().any(same) {
                    continue;
                }
                let in_line = chosen.len() == 2 && {
                    let (a, b) = (pts[chosen[0] - 1], pts[chosen[1] - 1]);
                    (p - a).cross((b - a).normalize()).length() <= eps
                };
                if chosen.len() < 3 && !in_line {
                    chosen.push(v);
                } else {
                    rest.push(v);
                }
            }
            let [a, b, c] = <[usize; 3]>::try_from(chosen).ok()?;
            let (pa, pb, pc) = (pts[a - 1], pts[b - 1], pts[c - 1]);
            let mut n = (pc - pa).cross(pb - pa).normalize();
            if (pa - centre).dot(n) < 0.0 {
                n = -n;
            }
            let plane = Plane { n, d: n.dot(pa) };
            let off = rest
                .first()
                .map(|&v| (v, (plane.n.dot(pts[v - 1]) - plane.d).abs()));
            Some(FacePlane {
                plane,
                corners: [a, b, c],
                off,
            })
        })
        .collect()
}

/// The solid bounded by the planes of `faces` (librt's ARB8 when a face is
/// not flat), cut to the box of the vertices `pts`: librt finds the body
/// only along rays that meet that box, and no more than a bent corner's
/// sliver reaches past it.
fn polyhedron_from_face_planes(
    pts: &[DVec3],
    faces: &[Option<FacePlane>],
    eps: f64,
) -> Result<(super::Shape, Aabb), String> {
    let mut planes: Vec<Plane> = faces.iter().flatten().map(|f| f.plane).collect();
    if planes.len() < 4 {
        return Err(format!(
            "only {} faces have three distinct corners out of line",
            planes.len()
        ));
    }
    // Cut by the box's sides the face planes reach past, or by all six
    // when the planes alone leave the solid open (their normals do not
    // surround the origin); the other sides would only repeat the faces.
    let vertex_box = Aabb::from_points(pts.iter().copied());
    let normals: Vec<DVec3> = planes.iter().map(|p| p.n).collect();
    let around = convex_hull_planes(&normals, 1e-12);
    let closed = around.volume > 1e-12 && around.planes.iter().all(|p| p.d > 1e-9);
    // Corners met by nearly parallel planes carry more rounding than the
    // vertices' own tolerance.
    let corner_eps = 1e3 * eps;
    let reach = if closed {
        Aabb::from_points(plane_corners(&planes, corner_eps))
    } else {
        Aabb::INFINITE
    };
    for axis in 0..3 {
        let mut n = DVec3::ZERO;
        n[axis] = 1.0;
        if reach.max[axis] > vertex_box.max[axis] + eps {
            planes.push(Plane {
                n,
                d: vertex_box.max[axis],
            });
        }
        if reach.min[axis] < vertex_box.min[axis] - eps {
            planes.push(Plane {
                n: -n,
                d: -vertex_box.min[axis],
            });
        }
    }
    let corners = plane_corners(&planes, corner_eps);
    let size = vertex_box.diagonal();
    if corners.len() < 4 || convex_hull_planes(&corners, eps).volume <= 1e-12 * size * size * size {
        return Err("the planes of the faces enclose no volume".into());
    }
    let bounds = Aabb::from_points(corners.iter().copied());
    Ok((
        super::Shape::Polyhedron(Polyhedron::new(planes, bounds)),
        bounds,
    ))
}

/// The points where three of `planes` meet inside all the others (within
/// `eps`, so that rounding can only add points): the corners of the solid
/// they bound, when it is bounded.
fn plane_corners(p: &[Plane], eps: f64) -> Vec<DVec3> {
    let n = p.len();
    let mut out = Vec::new();
    for i in 0..n {
        for j in i + 1..n {
            for k in j + 1..n {
                // Cramer's rule on n_i·x = d_i, n_j·x = d_j, n_k·x = d_k.
                let (a, b, c) = (p[i].n, p[j].n, p[k].n);
                let bc = b.cross(c);
                let det = a.dot(bc);
                if det.abs() < 1e-9 {
                    continue;
                }
                let x = (bc * p[i].d + c.cross(a) * p[j].d + a.cross(b) * p[k].d) / det;
                if x.is_finite() && p.iter().all(|q| q.n.dot(x) <= q.d + eps) {
                    out.push(x);
                }
            }
        }
    }
    out
}

fn half_space(n: DVec3, d: f64) -> Result<(super::Shape, Aabb), String> {
    let len = n.length();
    if len == 0.0 {
        return Err("normal vector is zero".into());
    }
    let n = n / len;
    let d = d / len;
    // Axis-aligned half-spaces have bounds open on one side only.
    let mut bounds = Aabb::INFINITE;
    for a in 0..3 {
        if n[a].abs() == 1.0 {
            if n[a] > 0.0 {
                bounds.max[a] = d;
            } else {
                bounds.min[a] = -d;
            }
        }
    }
    Ok((
        super::Shape::Polyhedron(Polyhedron::new(vec![Plane { n, d }], bounds)),
        bounds,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_half_space_is_bounded_by_its_side_of_a_box() {
        let within = Aabb::new(DVec3::splat(-1.0), DVec3::splat(1.0));
        // x + y + z <= -2: the corner at (-1, -1, -1) up to where the
        // plane crosses its three edges, one unit along each.
        let n = DVec3::splat(1.0).normalize();
        let corner = Polyhedron::new(vec![Plane { n, d: -2.0 * n.x }], Aabb::INFINITE);
        let part = corner.bounds_within(&within);
        assert!(
            (part.min - DVec3::splat(-1.0)).abs().max_element() < 1e-12,
            "{part:?}"
        );
        assert!(
            (part.max - DVec3::splat(0.0)).abs().max_element() < 1e-12,
            "{part:?}"
        );
        // Every point of the box on the plane's side lies in the part,
        // for planes every way.
        for k in 0..200 {
            let a = k as f64 * 0.731;
            let n = DVec3::new(
                a.cos() * (1.3 * a).sin(),
                a.sin() * (1.3 * a).sin(),
                (1.3 * a).cos(),
            );
            let plane = Plane {
                n,
                d: (k as f64 * 0.37).sin(),
            };
            let part = Polyhedron::new(vec![plane], Aabb::INFINITE).bounds_within(&within);
            for i in 0..9 {
                for j in 0..9 {
                    for l in 0..9 {
                        let p = DVec3::new(i as f64, j as f64, l as f64) / 4.0 - DVec3::splat(1.0);
                        if n.dot(p) <= plane.d {
                            assert!(
                                part.padded(1e-12).contains(p),
                                "{p} outside {part:?} for {plane:?}"
                            );
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn hull_of_unit_cube_has_six_planes_and_unit_volume() {
        let mut pts = vec![];
        for i in 0..8 {
            pts.push(DVec3::new(
                (i & 1) as f64,
                ((i >> 1) & 1) as f64,
                ((i >> 2) & 1) as f64,
            ));
        }
        let h = convex_hull_planes(&pts, 1e-9);
        assert_eq!(h.planes.len(), 6);
        assert!((h.volume - 1.0).abs() < 1e-12);
        // Its corners come back from its planes.
        let bounds = Aabb::new(DVec3::ZERO, DVec3::ONE);
        let mut corners = Polyhedron::new(h.planes, bounds).corners(1e-9).unwrap();
        corners.sort_by(|a, b| a.to_array().partial_cmp(&b.to_array()).unwrap());
        pts.sort_by(|a, b| a.to_array().partial_cmp(&b.to_array()).unwrap());
        assert_eq!(corners.len(), 8);
        for (c, p) in corners.iter().zip(&pts) {
            assert!((*c - *p).length() < 1e-12, "{c} against {p}");
        }
        // A half-space has no corners to give.
        let half = Polyhedron::new(
            vec![Plane {
                n: DVec3::Z,
                d: 1.0,
            }],
            Aabb::new(DVec3::splat(f64::NEG_INFINITY), DVec3::splat(f64::INFINITY)),
        );
        assert!(half.corners(1e-9).is_none());
    }

    #[test]
    fn bent_arb8_planes_that_leave_it_open_are_closed_by_the_corners_box() {
        // Four side planes whose normals all lie in z = 0 bound no solid;
        // the corners' box closes it at z = 0 and z = 5.
        let pts: Vec<DVec3> = (0..8)
            .map(|i| {
                let (x, y) = ([-1.0, 1.0][i & 1], [-1.0, 1.0][(i >> 1) & 1]);
                DVec3::new(x, y, 5.0 * (i >> 2) as f64)
            })
            .collect();
        let side = |n: DVec3| {
            Some(FacePlane {
                plane: Plane { n, d: 1.0 },
                corners: [1, 2, 3],
                off: None,
            })
        };
        let faces = [
            side(DVec3::X),
            side(-DVec3::X),
            side(DVec3::Y),
            side(-DVec3::Y),
        ];
        let (shape, bounds) = polyhedron_from_face_planes(&pts, &faces, 1e-9).unwrap();
        assert_eq!(
            bounds,
            Aabb::new(DVec3::new(-1.0, -1.0, 0.0), DVec3::new(1.0, 1.0, 5.0))
        );
        let super::super::Shape::Polyhedron(solid) = shape else {
            panic!("a polyhedron");
        };
        let mut segs = Vec::new();
        solid.shoot(&Ray::new(DVec3::new(0.0, 0.0, -10.0), DVec3::Z), &mut segs);
        assert_eq!(segs.len(), 1);
        assert_eq!((segs[0].t0, segs[0].t1), (10.0, 15.0));
    }
}
