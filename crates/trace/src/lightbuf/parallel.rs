//! The buffer of a parallel light: zones binned on a grid normal to it.

use super::binning::*;
use super::{sealed, Candidates};
use crate::prepare::Prepared;
use sv_math::{orthonormal_basis, DVec3, Ray};

/// Opaque zones binned on a grid normal to a parallel light's direction.
#[derive(Clone, Debug)]
pub struct LightBuffer {
    /// The direction toward the light as given.
    pub(super) toward: DVec3,
    /// The same made unit (the shadow rays' direction), and its inverse.
    pub(super) dir: DVec3,
    pub(super) inv_dir: DVec3,
    /// The plane's axes.
    pub(super) u: DVec3,
    pub(super) v: DVec3,
    /// Grid origin on the plane and cells per unit length along u and v.
    pub(super) origin: (f64, f64),
    pub(super) scale: (f64, f64),
    pub(super) nu: usize,
    pub(super) nv: usize,
    /// Zones of cell `c` are `items[start[c]..start[c + 1]]`, sorted by
    /// `short`: how far (along `dir`) their bounds reach, negated (so the
    /// zones that reach past a point come first).
    pub(super) start: Vec<u32>,
    pub(super) items: Vec<u32>,
    pub(super) short: Vec<f64>,
    /// The large zones, left out of the grid's extent, sorted by
    /// `big_far`: tested by shadow rays from off the grid.
    pub(super) big: Vec<u32>,
    pub(super) big_far: Vec<f64>,
    /// Those of them not also listed in the cells they cover, sorted by
    /// `loose_far`: tested by every shadow ray from the grid.
    pub(super) loose: Vec<u32>,
    pub(super) loose_far: Vec<f64>,
}

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
            short: Vec::new(),
            big: big.iter().map(|r| r.0).collect(),
            big_far: big.iter().map(|r| r.2).collect(),
            loose: big.iter().map(|r| r.0).collect(),
            loose_far: big.iter().map(|r| r.2).collect(),
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
            let refs: usize = rects.iter().map(|(_, r, _)| lb.cells_in(r)).sum();
            if refs <= MAX_REFS_PER_ZONE * rects.len() || nu * nv == 1 {
                break;
            }
            cells = (nu * nv) as f64 / 4.0;
        }
        // The large zones are listed in the cells they cover as well, when
        // that adds no more references than the grid was sized for (or
        // than it has cells): a shadow ray from the grid then meets only
        // those over its cell. (Nine of the helicopter's 24 zones are large
        // beside the rest, its rotor blades among them, and every shadow
        // ray tested them all.)
        type Rect<'a> = &'a (u32, [f64; 4], f64);
        let (gridded, loose): (Vec<Rect>, Vec<Rect>) = big
            .iter()
            .partition(|(_, r, f)| r.iter().all(|x| x.is_finite()) && f.is_finite());
        let own: usize = rects.iter().map(|(_, r, _)| lb.cells_in(r)).sum();
        let extra: usize = gridded.iter().map(|(_, r, _)| lb.cells_in(r)).sum();
        let budget = own.max(MAX_REFS_PER_ZONE * rects.len()) + lb.nu * lb.nv;
        let (gridded, loose) = if extra <= budget {
            (gridded, loose)
        } else {
            (Vec::new(), big.iter().collect())
        };
        lb.loose = loose.iter().map(|r| r.0).collect();
        lb.loose_far = loose.iter().map(|r| r.2).collect();
        let mut listed: Vec<Rect> = rects.iter().chain(gridded).collect();
        listed.sort_by(|a, b| a.2.total_cmp(&b.2).then(a.0.cmp(&b.0)));
        // A zone is listed in the cells its outline meets, when it has one,
        // else in every cell its rectangle covers.
        let outlines: Vec<Option<Vec<[f64; 2]>>> = listed
            .iter()
            .map(|(zi, _, _)| outline(p, *zi, u, v))
            .collect();
        // In order of reach, farthest first, so every cell's list comes out
        // sorted.
        (lb.start, lb.items, lb.short) = bin_by_cell(lb.nu * lb.nv, |visit| {
            for ((zi, r, f), hull) in listed.iter().zip(&outlines).rev() {
                let ((u0, u1), (v0, v1)) = lb.span(r);
                for j in v0..=v1 {
                    for i in u0..=u1 {
                        if hull.as_ref().is_none_or(|h| lb.cell_meets(i, j, h, pad)) {
                            visit(j * lb.nu + i, *zi, -f);
                        }
                    }
                }
            }
        });
        lb
    }

    /// Whether cell (`i`, `j`) meets the convex polygon `hull`
    /// (counter-clockwise) grown by `slack`: false only when one of the
    /// polygon's edges has the whole cell clearly outside.
    pub(super) fn cell_meets(&self, i: usize, j: usize, hull: &[[f64; 2]], slack: f64) -> bool {
        let (a0, b0) = (
            self.origin.0 + i as f64 / self.scale.0,
            self.origin.1 + j as f64 / self.scale.1,
        );
        let (a1, b1) = (
            self.origin.0 + (i + 1) as f64 / self.scale.0,
            self.origin.1 + (j + 1) as f64 / self.scale.1,
        );
        // Rounding in the cell's corners and in a shadow ray's projection.
        let slack = slack + 1e-9 * (a0.abs().max(a1.abs()) + b0.abs().max(b1.abs()));
        let corners = [[a0, b0], [a1, b0], [a1, b1], [a0, b1]];
        (0..hull.len()).all(|k| {
            let (p, q) = (hull[k], hull[(k + 1) % hull.len()]);
            // Outward normal of edge p → q of a counter-clockwise polygon.
            let (nx, ny) = (q[1] - p[1], p[0] - q[0]);
            let limit = slack * nx.hypot(ny);
            corners
                .iter()
                .any(|c| nx * (c[0] - p[0]) + ny * (c[1] - p[1]) <= limit)
        })
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
    pub(super) fn span(&self, r: &[f64; 4]) -> ((usize, usize), (usize, usize)) {
        let (i0, j0) = self.cell_of(r[0], r[1]);
        let (i1, j1) = self.cell_of(r[2], r[3]);
        ((i0, i1), (j0, j1))
    }

    /// How many cells a rectangle covers.
    pub(super) fn cells_in(&self, r: &[f64; 4]) -> usize {
        let ((u0, u1), (v0, v1)) = self.span(r);
        (u1 - u0 + 1) * (v1 - v0 + 1)
    }

    /// The cell holding plane point `(a, b)`, clamped to the grid.
    pub(super) fn cell_of(&self, a: f64, b: f64) -> (usize, usize) {
        (
            clamped_cell(a, self.origin.0, self.scale.0, self.nu),
            clamped_cell(b, self.origin.1, self.scale.1, self.nv),
        )
    }
}

/// What [`LightBuffer::place`] computes with.
pub(crate) struct Grid {
    /// Toward the light.
    pub dir: DVec3,
    /// The plane's axes.
    pub u: DVec3,
    pub v: DVec3,
    /// Origin on the plane, cells per unit length, and cells along each
    /// axis.
    pub origin: (f64, f64),
    pub scale: (f64, f64),
    pub cells: (f64, f64),
}

/// Where a shadow ray toward a parallel light starts, on its buffer's grid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Place {
    /// Its origin is not a number.
    Nowhere,
    /// Off the grid.
    Off,
    /// In this cell.
    Cell(u32),
}

impl LightBuffer {
    /// The place of the shadow ray from `p`, and how far `p` lies along the
    /// light's direction.
    #[inline]
    pub(crate) fn place(&self, p: DVec3) -> (Place, f64) {
        if p.is_nan() {
            return (Place::Nowhere, f64::NAN);
        }
        let depth = p.dot(self.dir);
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
            return (Place::Off, depth);
        }
        (Place::Cell(fb as u32 * nu + fa as u32), depth)
    }

    /// The grid's frame, for locating many points at once as
    /// [`LightBuffer::place`] locates one.
    pub(crate) fn grid(&self) -> Grid {
        Grid {
            dir: self.dir,
            u: self.u,
            v: self.v,
            origin: self.origin,
            scale: self.scale,
            cells: (self.nu as f64, self.nv as f64),
        }
    }

    /// The bounded zones that shadow rays from `place` may meet when they
    /// start no nearer the light than `depth`: the large ones and those of
    /// the cell (none off the grid) that reach past it. (A zone that does
    /// not reach past a ray's origin lies behind the ray.)
    #[inline]
    pub(crate) fn candidates(&self, place: Place, depth: f64) -> Candidates<'_> {
        let Place::Cell(c) = place else {
            return Candidates::only(&self.big[prefix(&self.big_far, |f| f < depth)..]);
        };
        let cell = self.start[c as usize] as usize..self.start[c as usize + 1] as usize;
        Candidates {
            big: &self.loose[prefix(&self.loose_far, |f| f < depth)..],
            cell: &self.items[cell.clone()],
            keys: &self.short[cell],
            bound: -depth,
        }
    }
}

impl sealed::Zones for LightBuffer {
    /// The bounded zones a shadow ray from `p` may meet
    /// ([`LightBuffer::candidates`]), or `None` when `p` is not a number.
    fn zones_at(&self, p: DVec3) -> Option<Candidates<'_>> {
        match self.place(p) {
            (Place::Nowhere, _) => None,
            (place, depth) => Some(self.candidates(place, depth)),
        }
    }

    fn check(&self, ray: &Ray) {
        debug_assert!((ray.dir - self.dir).length() < 1e-12);
    }
}
