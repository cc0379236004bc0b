//! The grids of rays a check fires, and its random rays.

use crate::rng::uniform;
use std::ops::Range;
use sv_math::{Aabb, DVec3, Ray};

/// A run of grid rays within one row, and their neighbours before them:
/// along the row, the ray before (from the row's second ray on), and
/// across it, the ray in the same place of the row before.
pub(crate) struct RowRun {
    pub rays: Range<u64>,
    /// The axis the rays run along.
    pub axis: usize,
    /// The first ray of the row.
    pub row_start: u64,
    /// How many rays before each lies its neighbour across the row; `None`
    /// in the first row.
    pub across: Option<u64>,
    /// The axes along which a ray lies apart from its neighbour along the
    /// row, and from its neighbour across it.
    pub axes: (usize, usize),
}

/// The grid of one check: per axis, counts and cell sizes.
pub(crate) struct Grid {
    lo: DVec3,
    size: DVec3,
    pad: f64,
    n: [(u64, u64); 3],
    cell: [(f64, f64); 3],
    first: [u64; 4],
}

/// Grid cells of about `d` across `len`: rounding noise (2/0.01 =
/// 200.00000000000003) does not add a cell.
pub(crate) fn cells(len: f64, d: f64) -> f64 {
    (len / d * (1.0 - 1e-12)).ceil()
}

const FRAC_U: f64 = 0.561_803_398_874_989_5;
const FRAC_V: f64 = 0.458_578_643_762_690_5;

impl Grid {
    pub(crate) fn new(lo: DVec3, hi: DVec3, d: f64) -> Grid {
        let size = hi - lo;
        let count = |len: f64| (cells(len, d) as u64).max(1);
        let mut n = [(0, 0); 3];
        let mut cell = [(0.0, 0.0); 3];
        let mut first = [0u64; 4];
        for k in 0..3 {
            let (u, v) = ((k + 1) % 3, (k + 2) % 3);
            n[k] = (count(size[u]), count(size[v]));
            cell[k] = (size[u] / n[k].0 as f64, size[v] / n[k].1 as f64);
            first[k + 1] = first[k] + n[k].0 * n[k].1;
        }
        Grid {
            lo,
            size,
            pad: 0.01 * size.length() + 1e-9,
            n,
            cell,
            first,
        }
    }

    /// The box every grid ray crosses within its range (and every ray
    /// between two neighbours).
    pub(crate) fn crossed(&self) -> Aabb {
        let pad = DVec3::splat(self.pad);
        Aabb::new(self.lo - pad, self.lo + self.size + pad)
    }

    pub(crate) fn total(&self) -> u64 {
        self.first[3]
    }

    /// The axis grid ray `idx` runs along (in the positive direction).
    pub(crate) fn axis(&self, idx: u64) -> usize {
        (0..3).find(|&k| idx < self.first[k + 1]).unwrap_or(2)
    }

    /// One past the last ray of the row of grid ray `idx`.
    pub(crate) fn row_end(&self, idx: u64) -> u64 {
        let k = self.axis(idx);
        let row = self.n[k].0;
        self.first[k] + ((idx - self.first[k]) / row + 1) * row
    }

    /// The first and last of grid rays `rays` (one run along a row) that
    /// may meet `bounds`: a ray more each side than those that pass
    /// within them, so that rounding does not leave one out.
    pub(crate) fn rays_near(&self, rays: Range<u64>, bounds: &Aabb) -> (u64, u64) {
        let k = self.axis(rays.start);
        let u = (k + 1) % 3;
        let row_start = rays.start - (rays.start - self.first[k]) % self.n[k].0;
        // Ray i of the row passes at lo[u] + (i + FRAC_U) * cell.
        let at = |x: f64| (x - self.lo[u]) / self.cell[k].0 - FRAC_U;
        let (a, b) = (at(bounds.min[u]), at(bounds.max[u]));
        let first = if a.is_finite() {
            row_start.saturating_add_signed((a.ceil() as i64).saturating_sub(1))
        } else {
            rays.start
        };
        let last = if b.is_finite() {
            row_start.saturating_add_signed((b.floor() as i64).saturating_add(1))
        } else {
            rays.end - 1
        };
        (first.max(rays.start), last.min(rays.end - 1))
    }

    /// Grid rays `rays` split where rows end, each piece with what its
    /// neighbours before it are (see [`RowRun`]).
    pub(crate) fn row_runs(&self, rays: Range<u64>) -> impl Iterator<Item = RowRun> + '_ {
        let mut start = rays.start;
        std::iter::from_fn(move || {
            if start >= rays.end {
                return None;
            }
            let k = self.axis(start);
            let row = self.n[k].0;
            let local = start - self.first[k];
            let row_start = start - local % row;
            let run = start..(row_start + row).min(rays.end);
            start = run.end;
            Some(RowRun {
                rays: run,
                axis: k,
                row_start,
                across: (local >= row).then_some(row),
                axes: ((k + 1) % 3, (k + 2) % 3),
            })
        })
    }

    /// The widest cell of the three grids: its diagonal, and its longer
    /// side.
    pub(crate) fn widest_cell(&self) -> (f64, f64) {
        self.cell
            .iter()
            .fold((0.0f64, 0.0f64), |(diagonal, side), &(a, b)| {
                (diagonal.max(a.hypot(b)), side.max(a.max(b)))
            })
    }

    /// The longest row of the grid: a ray's neighbour across its row lies
    /// at most this many rays before it.
    pub(crate) fn longest_row(&self) -> u64 {
        self.n.iter().map(|n| n.0).max().unwrap_or(1)
    }

    /// The box that grid rays `first` to `last` (one row) cross over
    /// their range.
    pub(crate) fn run_box(&self, first: u64, last: u64) -> Aabb {
        let (a, t1, _) = self.ray(first);
        let (b, _, _) = self.ray(last);
        Aabb::EMPTY.including(a.origin).including(b.at(t1))
    }

    /// Where grid ray `idx` lies: the axis it runs along, its place along
    /// its row and its row.
    pub(crate) fn place(&self, idx: u64) -> (usize, u64, u64) {
        let k = self.axis(idx);
        let local = idx - self.first[k];
        (k, local % self.n[k].0, local / self.n[k].0)
    }

    /// Ray `idx` of the grid, its t range and the area it stands for.
    pub(crate) fn ray(&self, idx: u64) -> (Ray, f64, f64) {
        let (k, i, j) = self.place(idx);
        let (u, v) = ((k + 1) % 3, (k + 2) % 3);
        let mut o = DVec3::ZERO;
        o[k] = self.lo[k] - self.pad;
        o[u] = self.lo[u] + (exactly(i) + FRAC_U) * self.cell[k].0;
        o[v] = self.lo[v] + (exactly(j) + FRAC_V) * self.cell[k].1;
        let mut dir = DVec3::ZERO;
        dir[k] = 1.0;
        (
            Ray::new(o, dir),
            self.size[k] + 2.0 * self.pad,
            self.cell[k].0 * self.cell[k].1,
        )
    }

    /// Where grid ray `index` of run `run` passes along the run's row:
    /// its coordinate `run.axes.0`, exactly as [`Grid::ray`] gives it (the
    /// other coordinates are those of the run's first ray).
    pub(crate) fn along_row(&self, run: &RowRun, index: u64) -> f64 {
        let (k, u) = (run.axis, run.axes.0);
        self.lo[u] + (exactly(index - run.row_start) + FRAC_U) * self.cell[k].0
    }
}

/// A ray's place in its row or column (far below 2⁵³) as `f64`, exactly:
/// through `i64`, whose conversion is one instruction where `u64`'s takes
/// a test and several (every grid ray's origin is worked out from it).
fn exactly(place: u64) -> f64 {
    debug_assert!(place < 1 << 53);
    place as i64 as f64
}

/// A random ray through a random point of the box, and its range inside
/// the padded box.
pub(crate) fn random_ray(lo: DVec3, hi: DVec3, seed: u64, i: u64) -> Option<(Ray, f64, f64)> {
    let r = |c: u64| uniform(seed, i, c, 0x5eed);
    let z = 2.0 * r(0) - 1.0;
    let phi = std::f64::consts::TAU * r(1);
    let s = (1.0 - z * z).max(0.0).sqrt();
    let dir = DVec3::new(s * phi.cos(), s * phi.sin(), z);
    let p = lo + (hi - lo) * DVec3::new(r(2), r(3), r(4));
    let pad = 0.01 * (hi - lo).length() + 1e-9;
    let bx = sv_math::Aabb::new(lo, hi).padded(pad);
    let ray = Ray::new(p - dir * (2.0 * (hi - lo).length() + 1.0), dir);
    bx.ray_range(&ray).map(|(a, b)| (ray, a.max(0.0), b))
}
