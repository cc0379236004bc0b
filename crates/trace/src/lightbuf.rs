//! The light buffer of a parallel light (Haines and Greenberg 1986, "The
//! light buffer: a shadow-testing accelerator"): the opaque zones binned by
//! where their bounds fall on a plane normal to the light. A point light's
//! buffer ([`PointBuffer`]) bins them by direction on the faces of a cube
//! around the light, as that paper first did.
//!
//! Every shadow ray toward a parallel light runs along the same direction,
//! so its projection on that plane is a single point: it can only meet the
//! zones whose projected bounds hold that point, which are the zones listed
//! in the point's cell. Each cell's zones are sorted by how far their
//! bounds reach toward the light, farthest first, so a shadow ray stops
//! at the first zone wholly behind its origin. Zones large beside the rest
//! (a ground under a vehicle) are kept apart in one list, so that they do
//! not stretch the grid. A shadow test then looks at a handful of zones
//! instead of walking the hierarchy.

use crate::prepare::{EnclosureRef, Prepared};
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
    /// `short`: how far (along `dir`) their bounds reach, negated (so the
    /// zones that reach past a point come first).
    start: Vec<u32>,
    items: Vec<u32>,
    short: Vec<f64>,
    /// The large zones, left out of the grid's extent, sorted by
    /// `big_far`: tested by shadow rays from off the grid.
    big: Vec<u32>,
    big_far: Vec<f64>,
    /// Those of them not also listed in the cells they cover, sorted by
    /// `loose_far`: tested by every shadow ray from the grid.
    loose: Vec<u32>,
    loose_far: Vec<f64>,
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
    fn cell_meets(&self, i: usize, j: usize, hull: &[[f64; 2]], slack: f64) -> bool {
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
    fn span(&self, r: &[f64; 4]) -> ((usize, usize), (usize, usize)) {
        let (i0, j0) = self.cell_of(r[0], r[1]);
        let (i1, j1) = self.cell_of(r[2], r[3]);
        ((i0, i1), (j0, j1))
    }

    /// How many cells a rectangle covers.
    fn cells_in(&self, r: &[f64; 4]) -> usize {
        let ((u0, u1), (v0, v1)) = self.span(r);
        (u1 - u0 + 1) * (v1 - v0 + 1)
    }

    /// The cell holding plane point `(a, b)`, clamped to the grid.
    fn cell_of(&self, a: f64, b: f64) -> (usize, usize) {
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

/// The length of the prefix of `keys` that passes `pred`, which holds for
/// a prefix of them (sorted keys, as `partition_point`). Short lists, the
/// usual case, are counted: the comparisons are independent of each other,
/// where each step of a binary search waits for the load the step before
/// chose (on the helicopter such a search was 6 % of the frame).
#[inline]
fn prefix(keys: &[f64], pred: impl Fn(f64) -> bool) -> usize {
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
fn outline(p: &Prepared, zi: u32, u: DVec3, v: DVec3) -> Option<Vec<[f64; 2]>> {
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
fn convex_hull_2d(mut pts: Vec<[f64; 2]>) -> Vec<[f64; 2]> {
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
fn clamped_cell(x: f64, origin: f64, scale: f64, n: usize) -> usize {
    let i = ((x - origin) * scale).floor();
    (i.max(0.0) as usize).min(n - 1)
}

/// A counting sort of zone references by cell: `refs` gives its visitor
/// every reference as (cell, zone, key), in the order each cell's list is
/// to keep. Returns where each of the `cells` lists starts (and, last,
/// where the last one ends), the zones and their keys.
fn bin_by_cell(
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
    pos: DVec3,
    /// Each face's grid.
    faces: [FaceGrid; 6],
    /// Zones of cell `c` (face-major, then rows, then columns) are
    /// `items[start[c]..start[c + 1]]`, sorted by `near`: how close to the
    /// light their bounds come.
    start: Vec<u32>,
    items: Vec<u32>,
    near: Vec<f64>,
    /// Zones whose bounds hold the light (or come within rounding of it).
    big: Vec<u32>,
}

/// A zone seen from a point light through one face of its cube: the
/// zone, how near the light its bounds come, the face, and the zone's
/// rectangle on it.
type ZoneOnFace = (u32, f64, usize, [f64; 4]);

/// The grid over one face of a point light's cube: `n` × `n` cells over the
/// extent from `(u0, v0)` (face coordinates) of the zones seen through the
/// face, `su` and `sv` cells per unit; its cells start at `first`.
#[derive(Clone, Copy, Debug, Default)]
struct FaceGrid {
    u0: f64,
    v0: f64,
    su: f64,
    sv: f64,
    n: usize,
    first: usize,
}

impl FaceGrid {
    /// The grid over `rects`: about four cells a rectangle, no finer than
    /// half the typical rectangle's side and at most `n` a side, its cells
    /// numbered from `first`.
    fn new<'r>(rects: impl Iterator<Item = &'r [f64; 4]> + Clone, n: usize, first: usize) -> Self {
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
    fn index(u: f64, origin: f64, scale: f64, n: usize) -> Option<usize> {
        let x = (u - origin) * scale;
        (x >= 0.0 && x <= n as f64).then(|| (x.floor() as usize).min(n - 1))
    }

    /// The cell of direction `(u, v)`, `None` off the grid (or when the
    /// face has none: no zone is seen through it).
    fn cell(&self, u: f64, v: f64) -> Option<usize> {
        if self.n == 0 {
            return None;
        }
        let i = Self::index(u, self.u0, self.su, self.n)?;
        let j = Self::index(v, self.v0, self.sv, self.n)?;
        Some(self.first + j * self.n + i)
    }

    /// The cells (inclusive ranges of columns and rows) a rectangle covers.
    fn span(&self, r: &[f64; 4]) -> (usize, usize, usize, usize) {
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

/// The zones a shadow ray may meet, from a buffer: all of `big`, and the
/// zones of a cell while their keys (sorted) are at most `bound`.
pub struct Candidates<'a> {
    big: &'a [u32],
    cell: &'a [u32],
    keys: &'a [f64],
    bound: f64,
}

impl<'a> Candidates<'a> {
    /// Only the zones of `big`.
    fn only(big: &'a [u32]) -> Candidates<'a> {
        Candidates {
            big,
            cell: &[],
            keys: &[],
            bound: f64::NEG_INFINITY,
        }
    }

    /// Every zone listed: the large ones, then the cell's.
    pub(crate) fn all(&self) -> impl Iterator<Item = u32> + 'a {
        self.big.iter().copied().chain(self.cell())
    }

    /// The cell's zones that may be met, in order: the loop that tests
    /// them stops at the first whose key is past the bound (no search for
    /// where they end first).
    fn cell(&self) -> impl Iterator<Item = u32> + 'a {
        let bound = self.bound;
        self.cell
            .iter()
            .zip(self.keys)
            .take_while(move |(_, &k)| k <= bound)
            .map(|(&zi, _)| zi)
    }
}

/// A shadow-ray accelerator, for [`Prepared::occluded_by`]: a parallel
/// light's [`LightBuffer`] or a point light's [`PointBuffer`].
pub trait ShadowBuffer: sealed::Zones {}

impl ShadowBuffer for LightBuffer {}
impl ShadowBuffer for PointBuffer {}

/// What [`Prepared::occluded_by`] asks of a buffer, kept out of the public
/// interface.
mod sealed {
    use super::Candidates;
    use sv_math::{DVec3, Ray};

    pub trait Zones {
        /// The zones that a shadow ray from `p` may meet, or `None` to
        /// search everything.
        fn zones_at(&self, p: DVec3) -> Option<Candidates<'_>>;

        /// Check (in debug builds) that `ray` is one of the buffer's.
        fn check(&self, _ray: &Ray) {}
    }
}

impl Prepared {
    /// As [`Prepared::occluded`] for a shadow ray toward the light of
    /// `buf`: the same answer, looking only at the zones the buffer lists
    /// for the ray's origin. Toward a parallel light the ray must come
    /// from [`LightBuffer::shadow_ray`]; toward a point light `tmax` must
    /// be no farther than the light.
    ///
    /// `last` is the buffer's shadow cache: the zone that blocked the
    /// previous shadow ray (`None` if it was not blocked). Neighbouring
    /// points are mostly shadowed by the same zone, so it is tried first;
    /// the answer does not depend on it.
    #[allow(clippy::too_many_arguments)]
    pub fn occluded_by<B: ShadowBuffer>(
        &self,
        buf: &B,
        ray: &Ray,
        tmin: f64,
        tmax: f64,
        skip: Option<u32>,
        last: &mut Option<u32>,
        s: &mut Scratch,
    ) -> bool {
        buf.check(ray);
        let Some(zones) = buf.zones_at(ray.origin) else {
            // A point that is not a number: let the full search decide.
            return self.occluded(ray, tmin, tmax, skip, s);
        };
        s.new_ray();
        if let Some(z) = *last {
            if self.any_opaque([z], skip, ray, tmin, tmax, s).is_some() {
                return true;
            }
        }
        let all = self.unbounded_opaque.iter().copied().chain(zones.all());
        *last = self.any_opaque(all, skip, ray, tmin, tmax, s);
        last.is_some()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::PrepareOptions;
    use sv_geom::{Body, BodyKind, Geometry, Region};

    /// A grid of spheres, each its own region, on a much larger ground
    /// slab (region 0).
    fn spheres(n: usize) -> Prepared {
        let mut g = Geometry::default();
        g.bodies.push(Body::new(
            "ground",
            BodyKind::Rpp,
            vec![-500.0, 500.0, -500.0, 500.0, -3.0, -2.5],
        ));
        g.regions.push(Region::of_body("ground", 0));
        for i in 0..n {
            for j in 0..n {
                let b = g.bodies.len();
                g.bodies.push(Body::new(
                    format!("s{i}_{j}"),
                    BodyKind::Sph,
                    vec![i as f64 * 3.0, j as f64 * 3.0, (i + j) as f64 * 0.5, 1.0],
                ));
                g.regions.push(Region::of_body(format!("r{b}"), b));
            }
        }
        Prepared::new(&g, &PrepareOptions::default()).unwrap().0
    }

    /// Check that shadow rays toward `lb`'s light from `origins` are
    /// blocked exactly when the full search says so; the number blocked.
    fn sun_agrees(
        p: &Prepared,
        lb: &LightBuffer,
        origins: impl Iterator<Item = DVec3>,
        s: &mut Scratch,
    ) -> usize {
        let mut last = None;
        let mut met = 0;
        for o in origins {
            let ray = lb.shadow_ray(o);
            assert_eq!(ray, Ray::new(o, lb.toward()));
            let want = p.occluded(&ray, 1e-6, f64::INFINITY, None, s);
            let got = p.occluded_by(lb, &ray, 1e-6, f64::INFINITY, None, &mut last, s);
            assert_eq!(got, want, "origin {o:?} toward {:?}", lb.toward());
            met += usize::from(want);
        }
        met
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
            // Origins on a lattice through and around the spheres.
            let origins = (0..40 * 40 * 3).map(|i| {
                let (a, b, c) = (i / 120, i / 3 % 40, i % 3);
                DVec3::new(
                    -3.0 + a as f64 * 0.61,
                    -3.0 + b as f64 * 0.59 + k as f64 * 0.01,
                    -2.0 + c as f64 * 2.7,
                )
            });
            met += sun_agrees(&p, &lb, origins, &mut s);
        }
        assert!(met > 500, "the lattice should be shadowed often: {met}");
    }

    #[test]
    fn the_point_buffer_agrees_with_the_full_search_on_many_shadow_rays() {
        let p = spheres(6);
        let mut s = Scratch::new(&p);
        let (mut met, mut lit) = (0, 0);
        // Above the lattice, beside it at the height of the spheres, inside
        // a sphere, level with the ground's face, and far off.
        for pos in [
            DVec3::new(7.0, 8.0, 12.0),
            DVec3::new(-4.0, 7.5, 1.25),
            DVec3::new(6.0, 6.0, 2.0),
            DVec3::new(30.0, -20.0, -2.5),
            DVec3::new(-400.0, 300.0, 900.0),
        ] {
            let pb = PointBuffer::new(&p, pos);
            assert_eq!(pb.position(), pos);
            let mut last = None;
            for a in 0..36 {
                for b in 0..36 {
                    for c in 0..3 {
                        let o = DVec3::new(
                            -3.0 + a as f64 * 0.61,
                            -3.0 + b as f64 * 0.59,
                            -2.0 + c as f64 * 2.7,
                        );
                        let d = pos - o;
                        let ray = Ray::new(o, d);
                        let r = d.length();
                        let want = p.occluded(&ray, 1e-6, r, None, &mut s);
                        let got = p.occluded_by(&pb, &ray, 1e-6, r, None, &mut last, &mut s);
                        assert_eq!(got, want, "origin {o:?}, light at {pos:?}");
                        met += usize::from(want);
                        lit += usize::from(!want);
                    }
                }
            }
        }
        assert!(met > 1000 && lit > 1000, "{met} shadowed, {lit} lit");
    }

    #[test]
    fn the_point_buffer_lists_few_zones_a_cell() {
        let p = spheres(20);
        let pb = PointBuffer::new(&p, DVec3::new(30.0, 28.0, 40.0));
        // The ground holds no light here: it is listed like the spheres.
        assert!(pb.big.is_empty());
        let cells = pb.start.len() - 1;
        let longest = (0..cells)
            .map(|c| pb.start[c + 1] - pb.start[c])
            .max()
            .unwrap();
        let refs = pb.items.len();
        // About four cells a zone, where the zones are seen.
        assert!(cells >= 3 * 401, "{cells} cells");
        assert!(longest <= 10, "a cell lists {longest} of 401 zones");
        assert!(refs <= 4 * cells, "{refs} references in {cells} cells");
        // A light inside a sphere: that sphere is kept apart.
        let inside = PointBuffer::new(&p, DVec3::new(3.0, 3.0, 1.0));
        assert_eq!(inside.big.len(), 1);
    }

    #[test]
    fn a_face_grid_holds_its_far_edges_and_nothing_beyond() {
        let r = [[0.0, -0.5, 0.25, 0.0], [0.5, 0.0, 1.0, 0.5]];
        let g = FaceGrid::new(r.iter(), 1024, 7);
        assert_eq!(g.n, 3);
        assert_eq!(g.cell(0.0, -0.5), Some(7));
        assert_eq!(g.cell(1.0, 0.5), Some(7 + 8));
        assert_eq!(g.span(&r[1]), (1, 2, 1, 2));
        for (u, v) in [(-0.01, 0.0), (0.0, 0.51), (1.01, 0.0), (f64::NAN, 0.0)] {
            assert_eq!(g.cell(u, v), None, "({u}, {v})");
        }
        // A face through which no zone is seen has no cells.
        let empty = FaceGrid::new(std::iter::empty(), 1024, 9);
        assert_eq!(empty.cell(0.0, 0.0), None);
    }

    #[test]
    fn a_cell_lists_few_zones_and_the_ground_stays_apart() {
        let p = spheres(20);
        let lb = LightBuffer::new(&p, DVec3::new(0.1, 0.2, 1.0));
        // The ground does not stretch the grid: it is kept apart for rays
        // from off the grid, and listed in the cells, which it all covers.
        assert_eq!(lb.big, [0], "the ground is kept apart");
        assert!(lb.loose.is_empty());
        let cells = lb.start.len() - 1;
        let longest = (0..cells)
            .map(|c| lb.start[c + 1] - lb.start[c])
            .max()
            .unwrap();
        assert!(cells >= 400, "{cells} cells");
        assert!(
            longest <= 9,
            "a cell lists {longest} of 401 zones, the ground among them"
        );
        assert!((0..cells)
            .all(|c| lb.items[lb.start[c] as usize..lb.start[c + 1] as usize].contains(&0)));
    }

    /// Four long thin boxes turned 30° about z (rotor blades) and a wide
    /// plate turned the same way, over a lattice of small spheres on a
    /// ground slab; the boxes are large beside the spheres.
    fn blades() -> Prepared {
        let mut g = Geometry::default();
        let mut add = |kind, params: Vec<f64>| {
            let b = g.bodies.len();
            g.bodies.push(Body::new(format!("b{b}"), kind, params));
            g.regions.push(Region::of_body(format!("r{b}"), b));
        };
        add(BodyKind::Rpp, vec![-12.0, 12.0, -12.0, 12.0, -1.0, 0.0]);
        for i in 0..5 {
            for j in 0..5 {
                let (x, y) = (-10.0 + 5.0 * i as f64, -10.0 + 5.0 * j as f64);
                add(BodyKind::Sph, vec![x, y, 1.0, 0.5]);
            }
        }
        let (c, s) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
        let plate = [8.0 * c, 8.0 * s, 0.0, -5.0 * s, 5.0 * c, 0.0, 0.0, 0.0, 0.2];
        add(
            BodyKind::Box,
            [vec![-2.0, -6.0, 6.0], plate.to_vec()].concat(),
        );
        for k in 0..4 {
            let z = 3.0 + k as f64 * 0.5;
            let (along, across) = ([10.0 * c, 10.0 * s], [-0.3 * s, 0.3 * c]);
            add(
                BodyKind::Box,
                vec![
                    -5.0 * c + k as f64,
                    -5.0 * s,
                    z,
                    along[0],
                    along[1],
                    0.0,
                    across[0],
                    across[1],
                    0.0,
                    0.0,
                    0.0,
                    0.1,
                ],
            );
        }
        Prepared::new(&g, &PrepareOptions::default()).unwrap().0
    }

    #[test]
    fn turned_thin_boxes_are_listed_only_where_they_lie() {
        let p = blades();
        let mut s = Scratch::new(&p);
        let mut met = 0;
        for to_light in [
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::new(0.3, -0.2, 1.0),
            DVec3::new(-1.0, 0.5, 0.4),
        ] {
            let lb = LightBuffer::new(&p, to_light);
            // A blade covers a fifth of its box's shadow at most: its
            // outline leaves most of the box's cells alone.
            let listed = lb.items.iter().filter(|&&z| z >= 27).count();
            let boxed: usize = (27..31)
                .map(|zi| lb.cells_in(&project(&p.zones[zi].bounds, lb.u, lb.v, 4.0 * p.tol)))
                .sum();
            assert!(2 * listed < boxed, "{listed} of {boxed} cells");
            let origins = (0..60 * 60 * 4).map(|i| {
                let (a, b, h) = (i / 240, i / 4 % 60, [0.5, 1.2, 3.2, 5.0][i % 4]);
                DVec3::new(-11.0 + a as f64 * 0.37, -11.0 + b as f64 * 0.37, h)
            });
            met += sun_agrees(&p, &lb, origins, &mut s);
        }
        assert!(met > 1000, "the blades should shadow often: {met}");
    }

    #[test]
    fn the_hull_of_points_on_a_plane_runs_counter_clockwise_without_inner_points() {
        let pts = vec![
            [0.0, 0.0],
            [2.0, 0.0],
            [1.0, 1.0],
            [2.0, 2.0],
            [0.0, 2.0],
            [1.0, 0.0],
            [2.0, 0.0],
        ];
        assert_eq!(
            convex_hull_2d(pts),
            [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]]
        );
    }
}
