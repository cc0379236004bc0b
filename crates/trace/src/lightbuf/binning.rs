//! What both buffers use to bin zones: outlines of their projections,
//! counting sorts by cell, and extents on a plane.

use crate::prepare::{EnclosureRef, Prepared};
use sv_math::{Aabb, DVec3};

/// Upper bound on the number of cells.
pub(super) const MAX_CELLS: usize = 1 << 20;
/// Upper bound on the zone references, as a multiple of the zone count (the
/// grid is made coarser until it fits).
pub(super) const MAX_REFS_PER_ZONE: usize = 32;

/// The length of the prefix of `keys` that passes `pred`, which holds for
/// a prefix of them (sorted keys, as `partition_point`). Short lists, the
/// usual case, are counted: the comparisons are independent of each other,
/// where each step of a binary search waits for the load the step before
/// chose (on the helicopter such a search was 6 % of the frame).
#[inline]
pub(super) fn prefix(keys: &[f64], pred: impl Fn(f64) -> bool) -> usize {
    if keys.len() <= 16 {
        keys.iter().map(|&k| usize::from(pred(k))).sum()
    } else {
        keys.partition_point(|&k| pred(k))
    }
}

/// A convex polygon on the plane of `u` and `v` (counter-clockwise) that
/// holds the projection of zone `zi`, where a tighter one than its box's
/// may be at hand: the outline of the hull points of one of its `+` bodies
/// ([`Shape::hull_points`]), or the octagon around a sphere's. (A rotor
/// blade set at an angle to the axes covers a tenth of its box's
/// projection; a sphere's box, seen along a diagonal, casts a hexagon
/// whose rectangle has three times the area of the sphere's disc.)
pub(super) fn outline(p: &Prepared, zi: u32, u: DVec3, v: DVec3) -> Option<Vec<[f64; 2]>> {
    let hull = match p.enclosure(zi) {
        EnclosureRef::Box => return None,
        // A sphere's shadow is a disc: the regular octagon around it.
        EnclosureRef::Ball(c, r) => {
            let (cu, cv) = (c.dot(u), c.dot(v));
            let r = r / (std::f64::consts::PI / 8.0).cos();
            (0..8)
                .map(|k| {
                    let a = (2 * k + 1) as f64 * std::f64::consts::PI / 8.0;
                    [cu + r * a.cos(), cv + r * a.sin()]
                })
                .collect()
        }
        EnclosureRef::Points(pts) => {
            convex_hull_2d(pts.iter().map(|c| [c.dot(u), c.dot(v)]).collect())
        }
    };
    (hull.len() >= 3).then_some(hull)
}

/// The convex hull of points on a plane, counter-clockwise, without
/// collinear points (Andrew's monotone chain).
pub(super) fn convex_hull_2d(mut pts: Vec<[f64; 2]>) -> Vec<[f64; 2]> {
    pts.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    pts.dedup();
    if pts.len() < 3 {
        return pts;
    }
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    let mut hull: Vec<[f64; 2]> = Vec::with_capacity(2 * pts.len());
    for pass in 0..2 {
        let start = hull.len();
        let mut half = |q: [f64; 2]| {
            while hull.len() >= start + 2
                && cross(hull[hull.len() - 2], hull[hull.len() - 1], q) <= 0.0
            {
                hull.pop();
            }
            hull.push(q);
        };
        if pass == 0 {
            pts.iter().for_each(|&q| half(q));
        } else {
            pts.iter().rev().for_each(|&q| half(q));
        }
        // The last point of each half is the first of the other.
        hull.pop();
    }
    hull
}

/// The cell of `x` along a grid axis of `n` cells from `origin`, `scale`
/// cells per unit, clamped to the grid.
pub(super) fn clamped_cell(x: f64, origin: f64, scale: f64, n: usize) -> usize {
    let i = ((x - origin) * scale).floor();
    (i.max(0.0) as usize).min(n - 1)
}

/// A counting sort of zone references by cell: `refs` gives its visitor
/// every reference as (cell, zone, key), in the order each cell's list is
/// to keep. Returns where each of the `cells` lists starts (and, last,
/// where the last one ends), the zones and their keys.
pub(super) fn bin_by_cell(
    cells: usize,
    refs: impl Fn(&mut dyn FnMut(usize, u32, f64)),
) -> (Vec<u32>, Vec<u32>, Vec<f64>) {
    let mut start = vec![0u32; cells + 1];
    refs(&mut |c, _, _| start[c + 1] += 1);
    for c in 1..start.len() {
        start[c] += start[c - 1];
    }
    let total = *start.last().unwrap_or(&0) as usize;
    let (mut items, mut keys) = (vec![0u32; total], vec![0.0; total]);
    let mut fill = start.clone();
    refs(&mut |c, zi, key| {
        items[fill[c] as usize] = zi;
        keys[fill[c] as usize] = key;
        fill[c] += 1;
    });
    (start, items, keys)
}

/// True when a rectangle side of length `side` is large beside the whole
/// extent `whole` along the same axis.
pub(super) fn is_large(side: f64, whole: f64) -> bool {
    side > 0.25 * whole
}

/// The extent `[u0, v0, u1, v1]` of projected rectangles.
pub(super) fn extent(rects: &[(u32, [f64; 4], f64)]) -> [f64; 4] {
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
pub(super) fn reach(b: &Aabb, dir: DVec3, pad: f64) -> f64 {
    let (c, h) = (b.center().dot(dir), (b.size() * 0.5).dot(dir.abs()));
    c + h + pad + 1e-12 * (c.abs() + h)
}

/// A box's extent on the plane spanned by `u` and `v`: `[u0, v0, u1, v1]`.
pub(super) fn project(b: &Aabb, u: DVec3, v: DVec3, pad: f64) -> [f64; 4] {
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
