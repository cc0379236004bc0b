use super::Seg;
use crate::body::Warning;
use crate::Body;
use sv_math::{Aabb, DVec3, Ray};

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
    bounds: Aabb,
    eps: f64,
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
            .collect();
        Mesh { tris, bounds, eps }
    }

    /// Number of (non-degenerate) triangles.
    pub fn triangle_count(&self) -> usize {
        self.tris.len()
    }

    pub(crate) fn shoot(&self, ray: &Ray, out: &mut Vec<Seg>) {
        if self.bounds.ray_range(ray).is_none() {
            return;
        }
        // Collect crossings in the tail of `out` to avoid an allocation.
        let base = out.len();
        for (i, tri) in self.tris.iter().enumerate() {
            // Möller–Trumbore 1997.
            let p = ray.dir.cross(tri.e2);
            let det = tri.e1.dot(p);
            if det.abs() < 1e-300 {
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

    pub(crate) fn normal(&self, face: u32) -> DVec3 {
        self.tris[face as usize].n
    }

    pub(crate) fn contains(&self, p: DVec3) -> bool {
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

    pub(crate) fn bounds(&self) -> Aabb {
        self.bounds
    }
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
