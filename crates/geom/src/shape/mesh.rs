use super::{Seg, SegLanes};
use crate::body::Warning;
use crate::Body;
use std::mem::MaybeUninit;
use sv_math::lanes::{cross, dot, not, splat3, sub_point, Lanes, MAX_LANES};
use sv_math::simd::Simd;
use sv_math::{Aabb, DVec3, Ray};

/// How many triangles' crossings [`Mesh::shoot_lanes`] keeps from its
/// first pass for its second: a packet of rays crosses few of a mesh's
/// triangles.
const KEPT_CROSSINGS: usize = 16;

/// The most triangles a mesh's cut by a plane reads
/// ([`Mesh::bounds_within`]): a grid cuts it once per row.
const MAX_CUT_TRIANGLES: usize = 256;

#[derive(Clone, Debug)]
struct Tri {
    v0: DVec3,
    e1: DVec3,
    e2: DVec3,
    n: DVec3,
}

/// A closed triangle mesh (the ARS faceted solid), possibly non-convex. A
/// ray's crossings are sorted and paired (even–odd rule), so the mesh's
/// winding does not matter.
#[derive(Clone, Debug)]
pub struct Mesh {
    tris: Vec<Tri>,
    /// Per axis, for each triangle a ray along it can cross, what
    /// Möller–Trumbore first works out from a ray's direction alone, for
    /// rays along that axis (a check's grid rays, a view along an axis):
    /// `d × e2`, then `e1 · (d × e2)` and one over it. The lanes read them
    /// for a packet along an axis instead of dividing for every triangle,
    /// and pass over the triangles edge-on to the axis (the walls of a
    /// faceted box), which such a ray never crosses.
    along_axis: [Vec<AxisTerms>; 3],
    bounds: Aabb,
    eps: f64,
}

/// A mesh's `along_axis` terms of one triangle: its index, and `p = d ×
/// e2`, `det` and `inv`, as [`Mesh::shoot`] computes them for `d` the
/// axis.
#[derive(Clone, Copy, Debug)]
struct AxisTerms {
    tri: usize,
    p: DVec3,
    det: f64,
    inv: f64,
}

impl Mesh {
    /// From consistently wound triangles (degenerate ones are dropped).
    /// Normals follow the winding, flipped as a whole if the mesh's signed
    /// volume is negative, so they point outward for any closed mesh.
    pub fn new(tris: &[[DVec3; 3]]) -> Mesh {
        let bounds = Aabb::from_points(tris.iter().flatten().copied());
        let eps = 1e-9 * bounds.diagonal().max(1e-300);
        let c = bounds.center();
        let signed_volume: f64 = tris
            .iter()
            .map(|[a, b, d]| (*a - c).dot((*b - c).cross(*d - c)))
            .sum();
        let flip = if signed_volume < 0.0 { -1.0 } else { 1.0 };
        let tris = tris
            .iter()
            .filter_map(|[a, b, c]| {
                let e1 = *b - *a;
                let e2 = *c - *a;
                let n = e1.cross(e2);
                let len = n.length();
                if len <= eps * eps {
                    return None;
                }
                Some(Tri {
                    v0: *a,
                    e1,
                    e2,
                    n: n / len * flip,
                })
            })
            .collect::<Vec<Tri>>();
        let along_axis = DVec3::AXES.map(|dir| {
            let terms = tris.iter().enumerate().map(|(i, tri)| {
                let p = dir.cross(tri.e2);
                let det = tri.e1.dot(p);
                AxisTerms {
                    tri: i,
                    p,
                    det,
                    inv: 1.0 / det,
                }
            });
            // Those `shoot` passes over as flat to the ray.
            terms.filter(|terms| !is_flat(terms.det)).collect()
        });
        Mesh {
            tris,
            along_axis,
            bounds,
            eps,
        }
    }

    /// Number of (non-degenerate) triangles.
    pub fn triangle_count(&self) -> usize {
        self.tris.len()
    }

    /// Append the segments of the ray inside the body to `out` (see
    /// [`super::Shape::shoot`]). Every triangle is tried: the callers have
    /// tested the ray against the mesh's box, and a second box test here
    /// would be one the lane form ([`Mesh::shoot_lanes`]) must repeat
    /// operation for operation.
    pub fn shoot(&self, ray: &Ray, out: &mut Vec<Seg>) {
        // Collect crossings in the tail of `out` to avoid an allocation.
        let base = out.len();
        for (i, tri) in self.tris.iter().enumerate() {
            // Möller–Trumbore 1997.
            let p = ray.dir.cross(tri.e2);
            let det = tri.e1.dot(p);
            if is_flat(det) {
                continue;
            }
            let inv = 1.0 / det;
            let s = ray.origin - tri.v0;
            let u = s.dot(p) * inv;
            if !(0.0..=1.0).contains(&u) {
                continue;
            }
            let q = s.cross(tri.e1);
            let v = ray.dir.dot(q) * inv;
            if v < 0.0 || u + v > 1.0 {
                continue;
            }
            let t = tri.e2.dot(q) * inv;
            out.push(Seg {
                t0: t,
                t1: t,
                f0: i as u32,
                f1: i as u32,
            });
        }
        let hits = &mut out[base..];
        hits.sort_by(|a, b| a.t0.total_cmp(&b.t0));
        // Merge crossings through a shared edge or vertex (same t).
        let mut n = 0;
        for i in 0..hits.len() {
            if n > 0 && hits[i].t0 - hits[n - 1].t0 <= self.eps {
                continue;
            }
            hits[n] = hits[i];
            n += 1;
        }
        let pairs = n / 2;
        for k in 0..pairs {
            let (a, b) = (out[base + 2 * k], out[base + 2 * k + 1]);
            out[base + k] = Seg {
                t0: a.t0,
                t1: b.t0,
                f0: a.f0,
                f1: b.f0,
            };
        }
        out.truncate(base + pairs);
    }

    /// [`Mesh::shoot`] in every lane, operation for operation, for the
    /// lanes whose ray crosses the surface twice (after merging crossings
    /// through a shared edge): their one segment. A lane with more
    /// crossings, or one that is not a finite number, is marked `scalar`.
    ///
    /// The sorted, merged crossings are found without sorting: the first
    /// is the nearest (the lowest triangle among equal distances, as the
    /// stable sort keeps it), the second the nearest farther than `eps`
    /// beyond it, and there is a third exactly when the farthest lies more
    /// than `eps` beyond the second.
    #[inline(always)]
    pub fn shoot_lanes<S: Simd>(&self, s: S, r: &Lanes<S>) -> SegLanes<S> {
        let (zero, inf, eps) = (s.splat(0.0), s.splat(f64::INFINITY), s.splat(self.eps));
        let (mut t0, mut f0, mut farthest) = (inf, zero, s.neg(inf));
        let mut not_finite = s.none();
        // The crossings found, in the order of the triangles, for the
        // second pass (which otherwise tests every triangle again); only
        // the first `kept` places are written, and none are kept once
        // there are more than it holds.
        let mut crossings =
            [const { MaybeUninit::<(usize, S::F, S::M)>::uninit() }; KEPT_CROSSINGS];
        let mut kept = 0;
        let along = self.terms_along(s, r);
        for k in 0..self.tried(along) {
            let (i, terms) = self.triangle(along, k);
            let Some((t, hit)) = crossing_lanes(s, &self.tris[i], r, terms) else {
                continue;
            };
            if kept < KEPT_CROSSINGS {
                crossings[kept].write((i, t, hit));
            }
            kept += 1;
            // `t - t` is zero for a finite `t`, not a number otherwise.
            not_finite = s.or(not_finite, s.andnot(hit, s.eq(s.sub(t, t), zero)));
            let nearer = s.and(hit, s.lt(t, t0));
            t0 = s.select(nearer, t, t0);
            f0 = s.select(nearer, s.splat(i as f64), f0);
            farthest = s.select(s.and(hit, s.gt(t, farthest)), t, farthest);
        }
        let (mut t1, mut f1) = (inf, zero);
        let beyond_first = s.andnot(s.gt(s.sub(farthest, t0), eps), not_finite);
        // The nearest crossing more than `eps` beyond the first: a triangle
        // no lane crosses changes nothing, so the kept crossings, in the
        // same order, give what testing every triangle again gives.
        let past_first = (t0, beyond_first, eps);
        if s.any(beyond_first) && kept <= KEPT_CROSSINGS {
            for c in &crossings[..kept] {
                // SAFETY: the first `kept` places were written.
                let (i, t, hit) = unsafe { c.assume_init() };
                nearer_beyond(s, past_first, (i, t, hit), &mut t1, &mut f1);
            }
        } else if s.any(beyond_first) {
            for k in 0..self.tried(along) {
                let (i, terms) = self.triangle(along, k);
                if let Some((t, hit)) = crossing_lanes(s, &self.tris[i], r, terms) {
                    nearer_beyond(s, past_first, (i, t, hit), &mut t1, &mut f1);
                }
            }
        }
        let two = s.lt(t1, inf);
        let scalar = s.or(not_finite, s.and(two, s.gt(s.sub(farthest, t1), eps)));
        SegLanes {
            t0,
            t1,
            f0,
            f1,
            hit: s.andnot(two, scalar),
            scalar,
        }
    }

    /// How many triangles the lanes try: every triangle, or along an axis
    /// (`along`, from [`Mesh::terms_along`]) those not flat to it.
    #[inline(always)]
    fn tried(&self, along: Option<&[AxisTerms]>) -> usize {
        along.map_or(self.tris.len(), <[AxisTerms]>::len)
    }

    /// The `k`-th triangle the lanes try (in the order of the triangles):
    /// its index and its terms along the axis of `along`. Not a closure
    /// handed each: a closure's body would stay a call outside the
    /// instruction set the lanes are compiled for.
    #[inline(always)]
    fn triangle<'a>(
        &self,
        along: Option<&'a [AxisTerms]>,
        k: usize,
    ) -> (usize, Option<&'a AxisTerms>) {
        match along {
            Some(not_flat) => (not_flat[k].tri, Some(&not_flat[k])),
            None => (k, None),
        }
    }

    /// The triangles' [`AxisTerms`] for the rays `r` when every lane's
    /// direction is the same axis (`+x`, `+y` or `+z`).
    #[inline(always)]
    fn terms_along<S: Simd>(&self, s: S, r: &Lanes<S>) -> Option<&[AxisTerms]> {
        let (zero, one) = (s.splat(0.0), s.splat(1.0));
        for (k, terms) in self.along_axis.iter().enumerate() {
            let along = s.eq(r.d[k], one);
            let level = s.and(s.eq(r.d[(k + 1) % 3], zero), s.eq(r.d[(k + 2) % 3], zero));
            if s.all(s.and(along, level)) {
                return Some(terms);
            }
        }
        None
    }

    /// Outward unit normal at a point of the surface.
    pub fn normal(&self, face: u32) -> DVec3 {
        self.tris[face as usize].n
    }

    /// [`Mesh::normal`] in every lane, of faces `face` (as `f64`).
    #[inline(always)]
    pub fn normal_lanes<S: Simd>(&self, s: S, face: S::F) -> [S::F; 3] {
        let mut faces = [0.0; MAX_LANES];
        s.store(face, &mut faces);
        let mut n = [[0.0; MAX_LANES]; 3];
        for (j, &f) in faces.iter().enumerate().take(S::LANES) {
            // Lanes on other bodies carry their faces: any number.
            let normal = self.tris.get(f as usize).map_or(DVec3::ZERO, |tri| tri.n);
            (n[0][j], n[1][j], n[2][j]) = (normal.x, normal.y, normal.z);
        }
        n.map(|c| s.load(&c))
    }

    /// True when `p` is strictly inside.
    pub fn contains(&self, p: DVec3) -> bool {
        let ray = Ray::new(
            p,
            DVec3::new(
                0.577_350_269_189_625_8,
                0.577_350_269_189_625_7,
                0.577_350_269_189_626,
            ),
        );
        let mut segs = Vec::new();
        self.shoot(&ray, &mut segs);
        segs.iter().any(|s| s.t0 < 0.0 && s.t1 > 0.0)
    }

    /// Bounds (infinite sides where the body is unbounded).
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// Whether [`Mesh::bounds_within`] cuts the mesh by a plane: not a
    /// mesh of more than `MAX_CUT_TRIANGLES` (256) triangles.
    pub fn cuts(&self) -> bool {
        self.tris.len() <= MAX_CUT_TRIANGLES
    }

    /// Bounds of the mesh's part of the box `within` (see
    /// [`super::Shape::bounds_within`]). Where the box is flat across an
    /// axis, the part is the mesh's cut by that plane, which its surface
    /// bounds: the triangles' edges' crossings of the plane, within the
    /// box. A larger mesh, or a box not flat, gets the mesh's bounds
    /// within the box: the cut reads every triangle.
    pub fn bounds_within(&self, within: &Aabb) -> Aabb {
        let near = self.bounds.intersection(within);
        let flat = (0..3).find(|&a| within.min[a] == within.max[a]);
        let (Some(axis), true) = (flat, self.cuts() && !near.is_empty()) else {
            return near;
        };
        let plane = within.min[axis];
        let mut cut = Aabb::EMPTY;
        for tri in &self.tris {
            let corners = [tri.v0, tri.v0 + tri.e1, tri.v0 + tri.e2];
            for (k, &p) in corners.iter().enumerate() {
                let q = corners[(k + 1) % 3];
                let (side_p, side_q) = (p[axis] - plane, q[axis] - plane);
                let crossing = if side_p == 0.0 {
                    p
                } else if (side_p < 0.0) != (side_q < 0.0) && side_q != 0.0 {
                    super::edge_crossing(p, q, side_p, side_q)
                } else {
                    continue;
                };
                // On the plane exactly, whatever the rounding.
                let mut on_plane = crossing;
                on_plane[axis] = plane;
                cut = cut.including(on_plane);
            }
        }
        cut.intersection(&near)
    }
}

/// Below this, a triangle's Möller–Trumbore determinant for a ray says it
/// lies flat to the ray: the ray is not taken to cross it.
const FLAT_DETERMINANT: f64 = 1e-300;

/// Whether a triangle whose determinant for a ray is `det` lies flat to it.
#[inline(always)]
fn is_flat(det: f64) -> bool {
    det.abs() < FLAT_DETERMINANT
}

/// [`Mesh::shoot_lanes`]' second pass for crossing `(i, t, hit)` of
/// triangle `i`: kept as `(t1, f1)` in the lanes of `beyond` where it lies
/// more than `eps` beyond `t0` and nearer than `t1`.
#[inline(always)]
fn nearer_beyond<S: Simd>(
    s: S,
    (t0, beyond, eps): (S::F, S::M, S::F),
    (i, t, hit): (usize, S::F, S::M),
    t1: &mut S::F,
    f1: &mut S::F,
) {
    let next = s.and(
        s.and(hit, beyond),
        s.and(s.gt(s.sub(t, t0), eps), s.lt(t, *t1)),
    );
    *t1 = s.select(next, t, *t1);
    *f1 = s.select(next, s.splat(i as f64), *f1);
}

/// A ray's crossing of triangle `tri` in every lane, as [`Mesh::shoot`]
/// computes it (Möller–Trumbore, the same operations in the same order,
/// those of the direction alone taken from `along` where the lanes run
/// along an axis): its distance, and the lanes that cross; `None` when no
/// lane does. The rest is left undone once no lane's `u` is in range:
/// most triangles of a mesh lie beside a packet's rays.
#[inline(always)]
fn crossing_lanes<S: Simd>(
    s: S,
    tri: &Tri,
    r: &Lanes<S>,
    along: Option<&AxisTerms>,
) -> Option<(S::F, S::M)> {
    let (e1, e2) = (splat3(s, tri.e1), splat3(s, tri.e2));
    let (zero, one) = (s.splat(0.0), s.splat(1.0));
    let (p, det, inv) = match along {
        // The same values, for the direction they were worked out for.
        Some(terms) => (splat3(s, terms.p), s.splat(terms.det), s.splat(terms.inv)),
        None => {
            let p = cross(s, r.d, e2);
            let det = dot(s, e1, p);
            (p, det, s.div(one, det))
        }
    };
    let from_corner = sub_point(s, r.o, tri.v0);
    let u = s.mul(dot(s, from_corner, p), inv);
    let flat = s.lt(s.abs(det), s.splat(FLAT_DETERMINANT));
    let outside_u = not(s, s.and(s.ge(u, zero), s.le(u, one)));
    let in_u = not(s, s.or(flat, outside_u));
    if !s.any(in_u) {
        return None;
    }
    let q = cross(s, from_corner, e1);
    let v = s.mul(dot(s, r.d, q), inv);
    let outside_v = s.or(s.lt(v, zero), s.gt(s.add(u, v), one));
    let hit = s.andnot(in_u, outside_v);
    if !s.any(hit) {
        return None;
    }
    Some((s.mul(dot(s, e2, q), inv), hit))
}

/// ARS: curves of points joined into a closed faceted surface.
pub(crate) fn prepare_ars(b: &Body, _: &mut Vec<Warning>) -> Result<(super::Shape, Aabb), String> {
    let mesh = Mesh::new(&ars_triangles(b));
    if mesh.triangle_count() < 4 {
        return Err("the curves span no surface (degenerate ARS)".into());
    }
    let bounds = mesh.bounds();
    Ok((super::Shape::Mesh(mesh), bounds))
}

/// An ARS's counts: at least 2 curves of at least 3 points, and three
/// values for each point.
pub(crate) fn check_ars_counts(b: &Body) -> Result<(), String> {
    if b.params.len() < 2 {
        return Err("missing curve and point counts".into());
    }
    let (nc, np) = (b.params[0], b.params[1]);
    if nc.fract() != 0.0 || np.fract() != 0.0 || nc < 2.0 || np < 3.0 {
        return Err(format!(
            "needs at least 2 curves of at least 3 points (has {nc} curves of {np})"
        ));
    }
    if b.params.len() != 2 + 3 * (nc as usize) * (np as usize) {
        return Err(format!(
            "{nc} curves of {np} points need {} values, found {}",
            3.0 * nc * np,
            b.params.len() - 2
        ));
    }
    Ok(())
}

/// The triangles of an ARS: each pair of neighbouring curves joined by two
/// triangles per point (curves are closed), and the first and last curves
/// closed by fans (which vanish where a curve is a single point). The
/// winding is consistent, so the mesh orients itself (see [`Mesh::new`]).
/// `b` must be a well-formed ARS (checked by `prepare`).
pub fn ars_triangles(b: &Body) -> Vec<[DVec3; 3]> {
    let (nc, np) = (b.params[0] as usize, b.params[1] as usize);
    let curve = |i: usize, j: usize| b.vec3(2 + 3 * (i * np + j % np));
    let mut tris = Vec::with_capacity(2 * nc * np + 2 * np);
    for i in 0..nc.saturating_sub(1) {
        for j in 0..np {
            let (a, bq, c, d) = (
                curve(i, j),
                curve(i, j + 1),
                curve(i + 1, j + 1),
                curve(i + 1, j),
            );
            tris.push([a, bq, c]);
            tris.push([a, c, d]);
        }
    }
    for j in 1..np.saturating_sub(1) {
        tris.push([curve(0, 0), curve(0, j + 1), curve(0, j)]);
        tris.push([curve(nc - 1, 0), curve(nc - 1, j), curve(nc - 1, j + 1)]);
    }
    tris
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The octahedron `|x| + |y| + |z| <= 1` as a mesh.
    fn octahedron() -> Mesh {
        let tris: Vec<[DVec3; 3]> = (0..8)
            .map(|k| {
                let sign = |bit: usize| if k & bit == 0 { 1.0 } else { -1.0 };
                let (x, y, z) = (DVec3::X * sign(1), DVec3::Y * sign(2), DVec3::Z * sign(4));
                // Wound outward whatever the octant: the mesh orients
                // itself, but keep the winding consistent.
                if sign(1) * sign(2) * sign(4) > 0.0 {
                    [x, y, z]
                } else {
                    [x, z, y]
                }
            })
            .collect();
        Mesh::new(&tris)
    }

    #[test]
    fn a_plane_cuts_the_mesh_across_its_section() {
        let mesh = octahedron();
        let plane = Aabb::new(DVec3::new(-5.0, -5.0, 0.5), DVec3::new(5.0, 5.0, 0.5));
        let cut = mesh.bounds_within(&plane);
        // |x| + |y| <= 0.5 at z = 0.5.
        assert!(
            (cut.min - DVec3::new(-0.5, -0.5, 0.5)).length() < 1e-12,
            "{cut:?}"
        );
        assert!(
            (cut.max - DVec3::new(0.5, 0.5, 0.5)).length() < 1e-12,
            "{cut:?}"
        );
        let beside = Aabb::new(DVec3::new(-5.0, -5.0, 1.5), DVec3::new(5.0, 5.0, 1.5));
        assert!(mesh.bounds_within(&beside).is_empty());
        // A box not flat gets the mesh's bounds within it.
        let thick = Aabb::new(DVec3::new(-5.0, -5.0, 0.5), DVec3::new(5.0, 5.0, 0.6));
        assert_eq!(
            mesh.bounds_within(&thick),
            mesh.bounds().intersection(&thick)
        );
    }

    proptest! {
        /// Every point of the mesh on a plane across an axis, within the
        /// box, lies in the cut: a point of the octahedron, and a box
        /// about it flat across one axis.
        #[test]
        fn the_cut_holds_every_point_of_the_section(
            axis in 0usize..3,
            towards in prop::array::uniform3(-1.0..1.0f64),
            depth in 0.0..1.0f64,
            below in prop::array::uniform3(0.0..1.5f64),
            above in prop::array::uniform3(0.0..1.5f64),
        ) {
            let mesh = octahedron();
            let towards = DVec3::from(towards);
            prop_assume!(towards.abs().element_sum() > 1e-3);
            let p = towards * (depth / towards.abs().element_sum());
            let mut within = Aabb::new(p - DVec3::from(below), p + DVec3::from(above));
            (within.min[axis], within.max[axis]) = (p[axis], p[axis]);
            let cut = mesh.bounds_within(&within);
            prop_assert!(cut.padded(1e-12).contains(p), "{p} outside {cut:?}");
        }
    }
}
