//! The buffer of a point light: zones binned by direction on the faces of
//! a cube around it.

use super::binning::*;
use super::{sealed, Candidates};
use crate::prepare::Prepared;
use sv_math::DVec3;

/// The light buffer of a point light (Haines and Greenberg's original
/// form): the opaque zones binned by the directions in which the light
/// sees their bounds, on a grid over each face of a cube around it.
///
/// A shadow ray from `p` toward the light runs along the line from the
/// light to `p`, so it can only meet the zones listed in the cell of that
/// direction; each cell's zones are sorted by how near the light their
/// bounds come, so a shadow ray stops at the first zone farther from it
/// than `p`. Zones whose bounds hold the light are kept apart in one list.
#[derive(Clone, Debug)]
pub struct PointBuffer {
    /// The light.
    pub(super) pos: DVec3,
    /// Each face's grid.
    pub(super) faces: [FaceGrid; 6],
    /// Zones of cell `c` (face-major, then rows, then columns) are
    /// `items[start[c]..start[c + 1]]`, sorted by `near`: how close to the
    /// light their bounds come.
    pub(super) start: Vec<u32>,
    pub(super) items: Vec<u32>,
    pub(super) near: Vec<f64>,
    /// Zones whose bounds hold the light (or come within rounding of it).
    pub(super) big: Vec<u32>,
}

/// A zone seen from a point light through one face of its cube: the
/// zone, how near the light its bounds come, the face, and the zone's
/// rectangle on it.
type ZoneOnFace = (u32, f64, usize, [f64; 4]);

/// The grid over one face of a point light's cube: `n` × `n` cells over the
/// extent from `(u0, v0)` (face coordinates) of the zones seen through the
/// face, `su` and `sv` cells per unit; its cells start at `first`.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct FaceGrid {
    u0: f64,
    v0: f64,
    pub(super) su: f64,
    pub(super) sv: f64,
    pub(super) n: usize,
    pub(super) first: usize,
}

impl FaceGrid {
    /// The grid over `rects`: about four cells a rectangle, no finer than
    /// half the typical rectangle's side and at most `n` a side, its cells
    /// numbered from `first`.
    pub(super) fn new<'r>(
        rects: impl Iterator<Item = &'r [f64; 4]> + Clone,
        n: usize,
        first: usize,
    ) -> Self {
        let e = rects.clone().fold([1.0f64, 1.0, -1.0, -1.0], |e, r| {
            [
                e[0].min(r[0]),
                e[1].min(r[1]),
                e[2].max(r[2]),
                e[3].max(r[3]),
            ]
        });
        let count = rects.clone().count();
        if count == 0 {
            return FaceGrid {
                first,
                ..FaceGrid::default()
            };
        }
        let (u0, v0) = (e[0].max(-1.0), e[1].max(-1.0));
        let (w, h) = (
            (e[2].min(1.0) - u0).max(1e-9),
            (e[3].min(1.0) - v0).max(1e-9),
        );
        // About four cells a zone, but no finer than half the typical
        // zone's width: finer cells would list each zone many times over.
        let mut sides: Vec<f64> = rects.map(|r| (r[2] - r[0]).max(r[3] - r[1])).collect();
        let typical = *sides.select_nth_unstable_by(count / 2, f64::total_cmp).1;
        let fine = (2.0 * w.max(h) / typical.max(1e-9)).ceil().min(1e6) as usize;
        let n = (((4 * count) as f64).sqrt().ceil() as usize)
            .min(fine)
            .clamp(1, n);
        FaceGrid {
            u0,
            v0,
            su: n as f64 / w,
            sv: n as f64 / h,
            n,
            first,
        }
    }

    /// The column (or row) of face coordinate `u`, `None` off the grid
    /// (its far edge belongs to the last cell, as in [`FaceGrid::span`]).
    pub(super) fn index(u: f64, origin: f64, scale: f64, n: usize) -> Option<usize> {
        let x = (u - origin) * scale;
        (x >= 0.0 && x <= n as f64).then(|| (x.floor() as usize).min(n - 1))
    }

    /// The cell of direction `(u, v)`, `None` off the grid (or when the
    /// face has none: no zone is seen through it).
    pub(super) fn cell(&self, u: f64, v: f64) -> Option<usize> {
        if self.n == 0 {
            return None;
        }
        let i = Self::index(u, self.u0, self.su, self.n)?;
        let j = Self::index(v, self.v0, self.sv, self.n)?;
        Some(self.first + j * self.n + i)
    }

    /// The cells (inclusive ranges of columns and rows) a rectangle covers.
    pub(super) fn span(&self, r: &[f64; 4]) -> (usize, usize, usize, usize) {
        (
            clamped_cell(r[0], self.u0, self.su, self.n),
            clamped_cell(r[2], self.u0, self.su, self.n),
            clamped_cell(r[1], self.v0, self.sv, self.n),
            clamped_cell(r[3], self.v0, self.sv, self.n),
        )
    }
}

impl PointBuffer {
    /// The buffer of `p`'s opaque zones for shadow rays toward a light at
    /// `pos`.
    pub fn new(p: &Prepared, pos: DVec3) -> PointBuffer {
        let pad = 4.0 * p.tol;
        let mut big = Vec::new();
        // Each zone with the distance from the light to its bounds (rounded
        // down), once for each face it shows on with its rectangle there.
        let mut seen: Vec<ZoneOnFace> = Vec::new();
        for &zi in &p.bvh_opaque.items {
            let b = p.zones[zi as usize].bounds.padded(pad);
            let (lo, hi) = (b.min - pos, b.max - pos);
            let gap = lo.max(-hi).max(DVec3::ZERO);
            let near = gap.length();
            let near = near - 1e-12 * (near + pos.abs().max_element());
            if near <= 0.0 || near.is_nan() {
                big.push(zi);
                continue;
            }
            // A sideways shift of `pad` at distance `near` turns the
            // direction by at most `pad / near`, which moves a face
            // coordinate by at most twice that.
            let slack = 2.0 * pad / near + 1e-12;
            seen.extend((0..6).filter_map(|f| Some((zi, near, f, face_rect(lo, hi, f, slack)?))));
        }
        let zones = p.bvh_opaque.items.len() - big.len();
        seen.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)).then(a.2.cmp(&b.2)));
        // Each face's grid over the zones seen through it: about four cells
        // a zone, coarser until the references fit.
        let mut most = 1024;
        let faces = loop {
            let mut first = 0;
            let faces: [FaceGrid; 6] = std::array::from_fn(|f| {
                let on_face = seen.iter().filter(|z| z.2 == f).map(|z| &z.3);
                let g = FaceGrid::new(on_face, most, first);
                first += g.n * g.n;
                g
            });
            let refs: usize = seen
                .iter()
                .map(|z| faces[z.2].span(&z.3))
                .map(|(i0, i1, j0, j1)| (i1 - i0 + 1) * (j1 - j0 + 1))
                .sum();
            if refs <= MAX_REFS_PER_ZONE * zones.max(1) || most <= 8 {
                break faces;
            }
            most /= 2;
        };
        let cells: usize = faces.iter().map(|g| g.n * g.n).sum();
        // In order of distance, so every cell's list comes out sorted.
        let (start, items, near) = bin_by_cell(cells, |visit| {
            for &(zi, near, f, r) in &seen {
                let g = &faces[f];
                let (i0, i1, j0, j1) = g.span(&r);
                for j in j0..=j1 {
                    for i in i0..=i1 {
                        visit(g.first + j * g.n + i, zi, near);
                    }
                }
            }
        });
        PointBuffer {
            pos,
            faces,
            start,
            items,
            near,
            big,
        }
    }

    /// The light's position, as given to [`PointBuffer::new`].
    pub fn position(&self) -> DVec3 {
        self.pos
    }
}

impl sealed::Zones for PointBuffer {
    /// The bounded zones a shadow ray from `p` toward the light may meet:
    /// those holding the light and those of the cell of `p`'s direction
    /// that come nearer the light than `p`, or `None` when `p` is the
    /// light or not a number.
    fn zones_at(&self, p: DVec3) -> Option<Candidates<'_>> {
        let d = p - self.pos;
        let ad = d.abs();
        let a = if ad.x >= ad.y && ad.x >= ad.z {
            0
        } else if ad.y >= ad.z {
            1
        } else {
            2
        };
        let m = ad[a];
        if !(m > 0.0 && m.is_finite()) {
            return None;
        }
        let f = 2 * a + usize::from(d[a] < 0.0);
        let (b, c) = others(a);
        let Some(cell) = self.faces[f].cell(d[b] / m, d[c] / m) else {
            // No zone is seen in that direction.
            return Some(Candidates::only(&self.big));
        };
        let range = self.start[cell] as usize..self.start[cell + 1] as usize;
        Some(Candidates {
            big: &self.big,
            cell: &self.items[range.clone()],
            keys: &self.near[range],
            bound: d.length(),
        })
    }
}

/// The two axes other than `a`, in order.
fn others(a: usize) -> (usize, usize) {
    match a {
        0 => (1, 2),
        1 => (0, 2),
        _ => (0, 1),
    }
}

/// The rectangle `[u0, v0, u1, v1]` on cube face `f` (axis `f / 2`, the
/// positive side for even `f`) of the directions from the light toward the
/// box `lo..hi` (relative to the light), grown by `slack`; `None` when no
/// such direction falls on the face.
fn face_rect(lo: DVec3, hi: DVec3, f: usize, slack: f64) -> Option<[f64; 4]> {
    let a = f / 2;
    let s = if f.is_multiple_of(2) { 1.0 } else { -1.0 };
    let (a0, a1) = if s > 0.0 {
        (lo[a], hi[a])
    } else {
        (-hi[a], -lo[a])
    };
    if a1 <= 0.0 {
        return None;
    }
    // A face coordinate is `x_k / x` with `x = s x_a` in `(max(a0, 0), a1]`.
    let (b, c) = others(a);
    let range = |k: usize| {
        let (k0, k1) = (lo[k], hi[k]);
        let (mn, mx) = if a0 > 0.0 {
            // A ratio with a positive denominator over the box: its
            // extremes are at the corners.
            let q = [k0 / a0, k0 / a1, k1 / a0, k1 / a1];
            q.iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(x, y), &v| {
                    (x.min(v), y.max(v))
                })
        } else {
            // The box reaches across the plane through the light: the ratio
            // is unbounded on the sides where `x_k` takes that sign.
            (
                if k0 >= 0.0 {
                    k0 / a1
                } else {
                    f64::NEG_INFINITY
                },
                if k1 <= 0.0 { k1 / a1 } else { f64::INFINITY },
            )
        };
        (mn - slack, mx + slack)
    };
    let ((u0, u1), (v0, v1)) = (range(b), range(c));
    (u0 <= 1.0 && u1 >= -1.0 && v0 <= 1.0 && v1 >= -1.0).then_some([u0, v0, u1, v1])
}
