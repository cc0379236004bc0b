//! The light buffer of a parallel light (Haines and Greenberg 1986, "The
//! light buffer: a shadow-testing accelerator"): the opaque zones binned by
//! where their bounds fall on a plane normal to the light.
//!
//! Every shadow ray toward a parallel light runs along the same direction,
//! so its projection on that plane is a single point: it can only meet the
//! zones whose projected bounds hold that point, which are the zones listed
//! in the point's cell. Each cell's zones are sorted by how far their
//! bounds reach toward the light, so the zones wholly behind the ray's
//! origin are skipped with a binary search. Zones large beside the rest
//! (a ground under a vehicle) are kept apart in one list, so that they do
//! not stretch the grid. A shadow test then looks at a handful of zones
//! instead of walking the hierarchy.

use crate::prepare::Prepared;
use crate::trace::Scratch;
use sv_math::{orthonormal_basis, Aabb, DVec3, Ray};

/// Opaque zones binned on a grid normal to a parallel light's direction.
#[derive(Clone, Debug)]
pub struct LightBuffer {
    /// The direction toward the light as given.
    toward: DVec3,
    /// The same made unit (the shadow rays' direction), and its inverse.
    dir: DVec3,
    inv_dir: DVec3,
    /// The plane's axes.
    u: DVec3,
    v: DVec3,
    /// Grid origin on the plane and cells per unit length along u and v.
    origin: (f64, f64),
    scale: (f64, f64),
    nu: usize,
    nv: usize,
    /// Zones of cell `c` are `items[start[c]..start[c + 1]]`, sorted by
    /// `far`: how far (along `dir`) their bounds reach.
    start: Vec<u32>,
    items: Vec<u32>,
    far: Vec<f64>,
    /// The large zones, left out of the grid, sorted by `big_far`.
    big: Vec<u32>,
    big_far: Vec<f64>,
}

/// Upper bound on the number of cells.
const MAX_CELLS: usize = 1 << 20;
/// Upper bound on the zone references, as a multiple of the zone count (the
/// grid is made coarser until it fits).
const MAX_REFS_PER_ZONE: usize = 32;

impl LightBuffer {
    /// The buffer of `p`'s opaque zones for shadow rays along `to_light`
    /// (need not be unit).
    pub fn new(p: &Prepared, to_light: DVec3) -> LightBuffer {
        let dir = to_light.normalize();
        let (u, v) = orthonormal_basis(dir);
        // Each zone's bounds on the plane, padded so that rounding in the
        // projection of a shadow ray's origin cannot lose a zone.
        let pad = 4.0 * p.tol;
        let mut rects: Vec<(u32, [f64; 4], f64)> = p
            .bvh_opaque
            .items
            .iter()
            .map(|&zi| {
                let b = &p.zones[zi as usize].bounds;
                (zi, project(b, u, v, pad), reach(b, dir, pad))
            })
            .collect();
        rects.sort_by(|a, b| a.2.total_cmp(&b.2).then(a.0.cmp(&b.0)));
        // Zones more than a quarter as wide as everything go apart.
        let all = extent(&rects);
        let (aw, ah) = (all[2] - all[0], all[3] - all[1]);
        let (big, rects): (Vec<_>, Vec<_>) = rects.into_iter().partition(|(_, r, _)| {
            !(aw.is_finite() && ah.is_finite())
                || is_large(r[2] - r[0], aw)
                || is_large(r[3] - r[1], ah)
        });
        let ext = extent(&rects);
        let mut lb = LightBuffer {
            toward: to_light,
            dir,
            inv_dir: dir.recip(),
            u,
            v,
            origin: (0.0, 0.0),
            scale: (0.0, 0.0),
            nu: 1,
            nv: 1,
            start: vec![0, 0],
            items: Vec::new(),
            far: Vec::new(),
            big: big.iter().map(|r| r.0).collect(),
            big_far: big.iter().map(|r| r.2).collect(),
        };
        let (wu, wv) = (ext[2] - ext[0], ext[3] - ext[1]);
        if rects.is_empty() || !(wu.is_finite() && wv.is_finite()) {
            // No zone to grid: one empty cell.
            return lb;
        }
        lb.origin = (ext[0], ext[1]);
        // About four cells per zone (at least 64 × 64), shaped like the
        // extent.
        let mut cells = (4 * rects.len()).clamp(4096, MAX_CELLS) as f64;
        loop {
            let aspect = (wu / wv.max(f64::MIN_POSITIVE)).clamp(1e-3, 1e3);
            let nu = ((cells * aspect).sqrt().round() as usize).clamp(1, 4096);
            let nv = ((cells / nu as f64).round() as usize).clamp(1, 4096);
            let scale = (
                nu as f64 / wu.max(f64::MIN_POSITIVE),
                nv as f64 / wv.max(f64::MIN_POSITIVE),
            );
            lb.nu = nu;
            lb.nv = nv;
            lb.scale = scale;
            let refs: usize = rects
                .iter()
                .map(|(_, r, _)| {
                    let (a, b) = lb.span(r);
                    (a.1 - a.0 + 1) * (b.1 - b.0 + 1)
                })
                .sum();
            if refs <= MAX_REFS_PER_ZONE * rects.len() || nu * nv == 1 {
                break;
            }
            cells = (nu * nv) as f64 / 4.0;
        }
        // Counting sort of the references by cell.
        let mut count = vec![0u32; lb.nu * lb.nv + 1];
        for (_, r, _) in &rects {
            let ((u0, u1), (v0, v1)) = lb.span(r);
            for j in v0..=v1 {
                for i in u0..=u1 {
                    count[j * lb.nu + i + 1] += 1;
                }
            }
        }
        for c in 1..count.len() {
            count[c] += count[c - 1];
        }
        let mut fill = count.clone();
        let total = *count.last().unwrap_or(&0) as usize;
        let (mut items, mut far) = (vec![0u32; total], vec![0.0; total]);
        // In order of reach, so every cell's list comes out sorted.
        for (zi, r, f) in &rects {
            let ((u0, u1), (v0, v1)) = lb.span(r);
            for j in v0..=v1 {
                for i in u0..=u1 {
                    let c = j * lb.nu + i;
                    items[fill[c] as usize] = *zi;
                    far[fill[c] as usize] = *f;
                    fill[c] += 1;
                }
            }
        }
        lb.start = count;
        lb.items = items;
        lb.far = far;
        lb
    }

    /// The direction toward the light, as given to [`LightBuffer::new`].
    pub fn toward(&self) -> DVec3 {
        self.toward
    }

    /// The shadow ray from `p` toward the light: exactly
    /// `Ray::new(p, self.toward())`, without its divisions.
    pub fn shadow_ray(&self, p: DVec3) -> Ray {
        Ray {
            origin: p,
            dir: self.dir,
            inv_dir: self.inv_dir,
        }
    }

    /// The cells (inclusive ranges along u and v) covered by a rectangle.
    fn span(&self, r: &[f64; 4]) -> ((usize, usize), (usize, usize)) {
        let (i0, j0) = self.cell_of(r[0], r[1]);
        let (i1, j1) = self.cell_of(r[2], r[3]);
        ((i0, i1), (j0, j1))
    }

    /// The cell holding plane point `(a, b)`, clamped to the grid.
    fn cell_of(&self, a: f64, b: f64) -> (usize, usize) {
        let i = ((a - self.origin.0) * self.scale.0).floor();
        let j = ((b - self.origin.1) * self.scale.1).floor();
        (
            (i.max(0.0) as usize).min(self.nu - 1),
            (j.max(0.0) as usize).min(self.nv - 1),
        )
    }

    /// The bounded zones a shadow ray from `p` may meet: the large ones
    /// and those of `p`'s cell (none off the grid), or `None` when `p` is
    /// not a number.
    fn zones_at(&self, p: DVec3) -> Option<(&[u32], &[u32])> {
        if p.is_nan() {
            return None;
        }
        let depth = p.dot(self.dir);
        // Zones that do not reach past the origin lie behind the ray.
        let big = &self.big[self.big_far.partition_point(|&f| f < depth)..];
        let (a, b) = (p.dot(self.u), p.dot(self.v));
        let (fa, fb) = (
            (a - self.origin.0) * self.scale.0,
            (b - self.origin.1) * self.scale.1,
        );
        // The grid has at most 4096 cells a side: the comparisons and casts
        // go through `u32`, which converts in one or two instructions
        // where `usize` takes a dozen.
        let (nu, nv) = (self.nu as u32, self.nv as u32);
        if !(fa >= 0.0 && fb >= 0.0 && fa < f64::from(nu) && fb < f64::from(nv)) {
            return Some((big, &[]));
        }
        let c = (fb as u32 * nu + fa as u32) as usize;
        let cell = self.start[c] as usize..self.start[c + 1] as usize;
        let behind = self.far[cell.clone()].partition_point(|&f| f < depth);
        Some((big, &self.items[cell.start + behind..cell.end]))
    }
}

/// True when a rectangle side of length `side` is large beside the whole
/// extent `whole` along the same axis.
fn is_large(side: f64, whole: f64) -> bool {
    side > 0.25 * whole
}

/// The extent `[u0, v0, u1, v1]` of projected rectangles.
fn extent(rects: &[(u32, [f64; 4], f64)]) -> [f64; 4] {
    rects.iter().fold(
        [
            f64::INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        ],
        |e, (_, r, _)| {
            [
                e[0].min(r[0]),
                e[1].min(r[1]),
                e[2].max(r[2]),
                e[3].max(r[3]),
            ]
        },
    )
}

/// How far a box reaches along unit `dir` (the largest `x · dir` over
/// it), rounded up.
fn reach(b: &Aabb, dir: DVec3, pad: f64) -> f64 {
    let (c, h) = (b.center().dot(dir), (b.size() * 0.5).dot(dir.abs()));
    c + h + pad + 1e-12 * (c.abs() + h)
}

/// A box's extent on the plane spanned by `u` and `v`: `[u0, v0, u1, v1]`.
fn project(b: &Aabb, u: DVec3, v: DVec3, pad: f64) -> [f64; 4] {
    let c = b.center();
    let h = b.size() * 0.5;
    let (cu, cv) = (c.dot(u), c.dot(v));
    // Half-widths of the projected box; grown by a relative slack for the
    // rounding of the dot products.
    let (hu, hv) = (h.dot(u.abs()), h.dot(v.abs()));
    let su = pad + 1e-12 * (cu.abs() + hu);
    let sv = pad + 1e-12 * (cv.abs() + hv);
    [cu - hu - su, cv - hv - sv, cu + hu + su, cv + hv + sv]
}

impl Prepared {
    /// As [`Prepared::occluded`] for a shadow ray along the direction of
    /// `lb` (a ray from [`LightBuffer::shadow_ray`]): the same answer,
    /// looking only at the zones of the ray origin's cell.
    ///
    /// `last` is the light buffer's shadow cache: the zone that blocked the
    /// previous shadow ray (`None` if it was not blocked). Neighbouring
    /// points are mostly shadowed by the same zone, so it is tried first;
    /// the answer does not depend on it.
    #[allow(clippy::too_many_arguments)]
    pub fn occluded_along(
        &self,
        lb: &LightBuffer,
        ray: &Ray,
        tmin: f64,
        tmax: f64,
        skip: Option<u32>,
        last: &mut Option<u32>,
        s: &mut Scratch,
    ) -> bool {
        debug_assert!((ray.dir - lb.dir).length() < 1e-12);
        let Some((big, cell)) = lb.zones_at(ray.origin) else {
            // A point that is not a number: let the full search decide.
            return self.occluded(ray, tmin, tmax, skip, s);
        };
        s.new_ray();
        if let Some(z) = *last {
            if self.any_opaque(&[z], skip, ray, tmin, tmax, s).is_some() {
                return true;
            }
        }
        *last = self
            .any_opaque(&self.unbounded_opaque, skip, ray, tmin, tmax, s)
            .or_else(|| self.any_opaque(big, skip, ray, tmin, tmax, s))
            .or_else(|| self.any_opaque(cell, skip, ray, tmin, tmax, s));
        last.is_some()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Body, BodyKind, Geometry, Op, PrepareOptions, Region, Term, Zone};

    /// A grid of spheres, each its own region, on a much larger ground
    /// slab (region 0).
    fn spheres(n: usize) -> Prepared {
        let mut g = Geometry::default();
        g.bodies.push(Body::new(
            "ground",
            BodyKind::Rpp,
            vec![-500.0, 500.0, -500.0, 500.0, -3.0, -2.5],
        ));
        g.regions.push(Region {
            name: "ground".into(),
            zones: vec![Zone {
                terms: vec![Term {
                    op: Op::Inside,
                    body: 0,
                }],
            }],
        });
        for i in 0..n {
            for j in 0..n {
                let b = g.bodies.len();
                g.bodies.push(Body::new(
                    format!("s{i}_{j}"),
                    BodyKind::Sph,
                    vec![i as f64 * 3.0, j as f64 * 3.0, (i + j) as f64 * 0.5, 1.0],
                ));
                g.regions.push(Region {
                    name: format!("r{b}"),
                    zones: vec![Zone {
                        terms: vec![Term {
                            op: Op::Inside,
                            body: b,
                        }],
                    }],
                });
            }
        }
        Prepared::new(&g, &PrepareOptions::default()).unwrap().0
    }

    #[test]
    fn agrees_with_the_full_search_on_many_shadow_rays() {
        let p = spheres(6);
        let mut s = Scratch::new(&p);
        let mut met = 0;
        for (k, to_light) in [
            DVec3::new(0.3, 0.2, 1.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(0.0, 0.0, -1.0),
            DVec3::new(-1.0, 1.0, 0.01),
        ]
        .into_iter()
        .enumerate()
        {
            let lb = LightBuffer::new(&p, to_light);
            let mut last = None;
            // Origins on a lattice through and around the spheres.
            for a in 0..40 {
                for b in 0..40 {
                    for c in 0..3 {
                        let o = DVec3::new(
                            -3.0 + a as f64 * 0.61,
                            -3.0 + b as f64 * 0.59 + k as f64 * 0.01,
                            -2.0 + c as f64 * 2.7,
                        );
                        let ray = lb.shadow_ray(o);
                        assert_eq!(ray, Ray::new(o, to_light));
                        let want = p.occluded(&ray, 1e-6, f64::INFINITY, None, &mut s);
                        let got = p.occluded_along(
                            &lb,
                            &ray,
                            1e-6,
                            f64::INFINITY,
                            None,
                            &mut last,
                            &mut s,
                        );
                        assert_eq!(got, want, "origin {o:?} toward {to_light:?}");
                        met += usize::from(want);
                    }
                }
            }
        }
        assert!(met > 500, "the lattice should be shadowed often: {met}");
    }

    #[test]
    fn a_cell_lists_few_zones_and_the_ground_stays_apart() {
        let p = spheres(20);
        let lb = LightBuffer::new(&p, DVec3::new(0.1, 0.2, 1.0));
        assert_eq!(lb.big, [0], "the ground is kept apart");
        let cells = lb.start.len() - 1;
        let longest = (0..cells)
            .map(|c| lb.start[c + 1] - lb.start[c])
            .max()
            .unwrap();
        assert!(cells >= 400, "{cells} cells");
        assert!(longest <= 8, "a cell lists {longest} of 400 zones");
    }
}
