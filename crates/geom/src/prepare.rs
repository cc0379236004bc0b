//! `prepare`: validate every body, build its ray-casting form, lay zones out
//! in flat arrays and build the bounding volume hierarchies.

use crate::bvh::Bvh;
use crate::model::{quadric_matrix, Body, Geometry, Op};
use crate::shape::polyhedron_hull as hull;
use crate::shape::{
    Cone, Ellipsoid, GeneralCone, Mesh, Plane, Polyhedron, Quadric, Shape, Sphere, Torus,
};
use crate::sight::Sight;
use crate::table::BodyKind;
use std::fmt;
use sv_math::{orthonormal_basis, Aabb, DMat3, DVec3};

/// Options for [`Prepared::new`].
#[derive(Clone, Debug, Default)]
pub struct PrepareOptions {
    /// Boolean tolerance (model units). Default: 1e-7 of the bounding-box
    /// diagonal of the finite bodies.
    pub tolerance: Option<f64>,
    /// Per region: does it stop light? `None` means every region does.
    /// Transparent regions are still traced by [`Prepared::partitions`].
    pub opaque: Option<Vec<bool>>,
    /// Test every zone for every ray instead of walking the hierarchy, and
    /// trace every ray on its own (no packets of rays in vector lanes).
    /// Slow; results are bit-for-bit the same, which the tests check.
    pub brute_force: bool,
}

/// Something wrong with a body that was nevertheless rendered.
#[derive(Clone, Debug, PartialEq)]
pub struct Warning {
    /// Body name.
    pub body: String,
    /// Body type.
    pub kind: BodyKind,
    /// What is off and what was done about it.
    pub message: String,
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} `{}`: {}", self.kind, self.body, self.message)
    }
}

/// Bodies or regions that cannot be prepared; every problem is listed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{}", .problems.join("\n"))]
pub struct PrepareError {
    /// One line per problem, naming the body or region and the rule broken
    /// (`RCC "leg": height vector is zero`).
    pub problems: Vec<String>,
}

#[derive(Clone, Copy, Debug)]
pub(crate) struct PZone {
    pub region: u32,
    /// Terms in `terms[first..first+plus]` are `+`, the next `minus` are `-`.
    pub first: u32,
    pub plus: u16,
    pub minus: u16,
    pub bounds: Aabb,
    /// Every `+` body is convex (so the zone's `+` part is convex).
    pub convex: bool,
    /// It has `+` bodies, every one of which the packet tracer casts in
    /// vector lanes ([`Shape::has_lanes`]): a packet evaluates the zone for
    /// all its rays at once, but for the rays that meet the box of a `-`
    /// body it cannot cast.
    pub lanes: bool,
}

/// Something tighter than a zone's box that holds the zone, from one of its
/// `+` bodies: for rays that meet the box but cannot meet the zone.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Tight {
    /// Nothing better than the box.
    Box,
    /// The ball of a sphere among its `+` bodies: centre and radius, kept
    /// here so that the tests of a tile's zones do not fetch the bodies
    /// (100,000 spheres' bodies are 26 MB).
    Ball(DVec3, f64),
    /// The convex hull of `hull_pts[a..b]` ([`Shape::hull_points`]).
    Points(u32, u32),
}

/// A zone's [`Tight`], resolved by [`Prepared::tighter`].
#[derive(Clone, Copy)]
pub(crate) enum Tighter<'a> {
    /// Nothing better than the box.
    Box,
    /// The ball of a sphere among its `+` bodies: centre and radius.
    Ball(DVec3, f64),
    /// Points whose convex hull holds one of its `+` bodies.
    Points(&'a [DVec3]),
}

/// A geometry ready for ray casting: flat arrays of prepared bodies and
/// zones, bounds for every body and zone, and two hierarchies (all zones,
/// and the zones of opaque regions).
#[derive(Clone, Debug)]
pub struct Prepared {
    pub(crate) shapes: Vec<Shape>,
    pub(crate) body_bounds: Vec<Aabb>,
    pub(crate) zones: Vec<PZone>,
    pub(crate) terms: Vec<u32>,
    pub(crate) opaque: Vec<bool>,
    pub(crate) bvh_all: Bvh,
    pub(crate) bvh_opaque: Bvh,
    pub(crate) unbounded_all: Vec<u32>,
    pub(crate) unbounded_opaque: Vec<u32>,
    /// The bounded zones of opaque regions, in the order of the zones, as
    /// a raster sees them.
    pub(crate) sights: Vec<Sight>,
    pub(crate) tol: f64,
    /// Per zone, something tighter than its box that holds it.
    pub(crate) tight: Vec<Tight>,
    /// The points of [`Tight::Points`].
    pub(crate) hull_pts: Vec<DVec3>,
    bounds: Aabb,
    opaque_bounds: Aabb,
    region_count: usize,
    /// The bodies are stored in the order their zones lie in space (see
    /// [`in_space_order`]): the body index of each stored body, and the
    /// place of each body.
    body_ids: Vec<u32>,
    places: Vec<u32>,
    /// Trace rays in packets where the processor has vector instructions
    /// for it: [`Prepared::first_hits_in`], [`Prepared::first_hits`],
    /// [`Prepared::tile_hits`] and [`Prepared::occluded_toward`]. Off with
    /// [`PrepareOptions::brute_force`].
    pub(crate) packets: bool,
}

impl Prepared {
    /// Validate and prepare `g`. Warnings are returned beside the result;
    /// errors list every bad body and region at once.
    pub fn new(
        g: &Geometry,
        opts: &PrepareOptions,
    ) -> Result<(Prepared, Vec<Warning>), PrepareError> {
        let mut problems = Vec::new();
        let mut warnings = Vec::new();
        let mut shapes = Vec::with_capacity(g.bodies.len());
        let mut body_bounds = Vec::with_capacity(g.bodies.len());
        for b in &g.bodies {
            match build(b, &mut warnings) {
                Ok((s, bb)) => {
                    shapes.push(s);
                    body_bounds.push(bb);
                }
                Err(e) => {
                    problems.push(format!("{} `{}`: {e}", b.kind, b.name));
                    shapes.push(Shape::Sphere(Sphere::new(DVec3::ZERO, 1.0)));
                    body_bounds.push(Aabb::EMPTY);
                }
            }
        }
        let opaque = match &opts.opaque {
            Some(o) if o.len() == g.regions.len() => o.clone(),
            Some(o) => {
                problems.push(format!(
                    "{} opacity flags given for {} regions",
                    o.len(),
                    g.regions.len()
                ));
                vec![true; g.regions.len()]
            }
            None => vec![true; g.regions.len()],
        };
        let mut zones = Vec::new();
        let mut terms = Vec::new();
        for (ri, r) in g.regions.iter().enumerate() {
            if r.zones.is_empty() {
                problems.push(format!("region `{}`: it has no bodies", r.name));
            }
            for (zi, z) in r.zones.iter().enumerate() {
                if z.terms.is_empty() {
                    problems.push(format!("region `{}`: zone {} is empty", r.name, zi + 1));
                    continue;
                }
                if let Some(t) = z.terms.iter().find(|t| t.body >= g.bodies.len()) {
                    problems.push(format!(
                        "region `{}`: body index {} does not exist",
                        r.name, t.body
                    ));
                    continue;
                }
                let mut plus: Vec<u32> = z
                    .terms
                    .iter()
                    .filter(|t| t.op == Op::Inside)
                    .map(|t| t.body as u32)
                    .collect();
                plus.sort_by(|a, b| {
                    body_bounds[*a as usize]
                        .area()
                        .total_cmp(&body_bounds[*b as usize].area())
                });
                plus.dedup();
                let bounds = plus.iter().fold(Aabb::INFINITE, |acc, &b| {
                    acc.intersection(&body_bounds[b as usize])
                });
                if bounds.is_empty() {
                    // The + bodies never overlap: the zone is empty.
                    continue;
                }
                // Only subtracted bodies that reach the zone's bounds matter.
                let mut minus: Vec<u32> = z
                    .terms
                    .iter()
                    .filter(|t| {
                        t.op == Op::Outside && !body_bounds[t.body].intersection(&bounds).is_empty()
                    })
                    .map(|t| t.body as u32)
                    .collect();
                minus.dedup();
                let convex = plus.iter().all(|&b| shapes[b as usize].is_convex());
                let lanes =
                    !plus.is_empty() && plus.iter().all(|&b| shapes[b as usize].has_lanes());
                zones.push(PZone {
                    convex,
                    lanes,
                    region: ri as u32,
                    first: terms.len() as u32,
                    plus: plus.len() as u16,
                    minus: minus.len() as u16,
                    bounds,
                });
                terms.extend(plus);
                terms.extend(minus);
            }
        }
        if !problems.is_empty() {
            return Err(PrepareError { problems });
        }
        let (mut zones, terms, body_ids, places) = in_space_order(zones, terms, g.bodies.len());
        permute(&mut shapes, &body_ids);
        permute(&mut body_bounds, &body_ids);
        let finite = body_bounds
            .iter()
            .filter(|b| b.is_finite())
            .fold(Aabb::EMPTY, |a, b| a.union(b));
        let tol = opts.tolerance.unwrap_or_else(|| {
            let d = if finite.is_empty() {
                1.0
            } else {
                finite.diagonal()
            };
            (1e-7 * d).max(1e-12)
        });
        // Pad every box by the tolerance so that rounding never makes a box
        // test reject a hit on its boundary.
        let pad = 4.0 * tol;
        for b in body_bounds.iter_mut() {
            *b = b.padded(pad);
        }
        for z in zones.iter_mut() {
            z.bounds = z.bounds.padded(pad);
        }
        let mut bounded_all = Vec::new();
        let mut bounded_opaque = Vec::new();
        let (mut unbounded_all, mut unbounded_opaque) = (Vec::new(), Vec::new());
        let (mut bounds, mut opaque_bounds) = (Aabb::EMPTY, Aabb::EMPTY);
        for (i, z) in zones.iter().enumerate() {
            let vis = opaque[z.region as usize];
            if z.bounds.is_finite() && !opts.brute_force {
                bounded_all.push((i as u32, z.bounds));
                bounds = bounds.union(&z.bounds);
                if vis {
                    bounded_opaque.push((i as u32, z.bounds));
                    opaque_bounds = opaque_bounds.union(&z.bounds);
                }
            } else {
                unbounded_all.push(i as u32);
                if vis {
                    unbounded_opaque.push(i as u32);
                }
            }
        }
        let mut hull_pts = Vec::new();
        let tight: Vec<Tight> = zones
            .iter()
            .map(|z| {
                let plus = &terms[z.first as usize..z.first as usize + z.plus as usize];
                plus.iter()
                    .find_map(|&b| match &shapes[b as usize] {
                        Shape::Sphere(sp) => Some(Tight::Ball(sp.c, sp.r)),
                        s => s.hull_points(tol).map(|pts| {
                            let a = hull_pts.len() as u32;
                            hull_pts.extend(pts);
                            Tight::Points(a, hull_pts.len() as u32)
                        }),
                    })
                    .unwrap_or(Tight::Box)
            })
            .collect();
        let sights = bounded_opaque
            .iter()
            .map(|&(zi, b)| Sight::new(zi, &b, &tight[zi as usize]))
            .collect();
        let p = Prepared {
            shapes,
            body_bounds,
            bvh_all: Bvh::build(&bounded_all),
            bvh_opaque: Bvh::build(&bounded_opaque),
            zones,
            terms,
            opaque,
            unbounded_all,
            unbounded_opaque,
            sights,
            tol,
            tight,
            hull_pts,
            bounds,
            opaque_bounds,
            region_count: g.regions.len(),
            body_ids,
            places,
            packets: !opts.brute_force,
        };
        Ok((p, warnings))
    }

    /// Bounds of every zone with finite bounds (unbounded regions are
    /// left out, so framing stays finite).
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// Bounds of the opaque regions' finite zones.
    pub fn opaque_bounds(&self) -> Aabb {
        self.opaque_bounds
    }

    /// The boolean tolerance in model units.
    pub fn tolerance(&self) -> f64 {
        self.tol
    }

    /// Number of regions.
    pub fn region_count(&self) -> usize {
        self.region_count
    }

    /// Number of bodies.
    pub fn body_count(&self) -> usize {
        self.shapes.len()
    }

    /// The prepared form of body `i`.
    pub fn shape(&self, i: usize) -> &Shape {
        &self.shapes[self.places[i] as usize]
    }

    /// The body index (in the geometry) of prepared body `b`, as found in
    /// a [`Bound`](crate::boolean::Bound) of a hit or partition: bodies
    /// are stored in the order their zones lie in space.
    pub fn body_index(&self, b: u32) -> usize {
        self.body_ids[b as usize] as usize
    }

    /// What is known of zone `zi`'s shape beyond its box.
    #[inline]
    pub(crate) fn tighter(&self, zi: u32) -> Tighter<'_> {
        match self.tight[zi as usize] {
            Tight::Ball(c, r) => Tighter::Ball(c, r),
            Tight::Points(a, e) => Tighter::Points(&self.hull_pts[a as usize..e as usize]),
            Tight::Box => Tighter::Box,
        }
    }

    /// Bounds of body `i`.
    pub fn body_bounds(&self, i: usize) -> Aabb {
        self.body_bounds[self.places[i] as usize]
    }

    /// Does region `r` stop light?
    pub fn is_opaque(&self, r: usize) -> bool {
        self.opaque[r]
    }

    /// True when point `p` lies inside region `r` (by its zones).
    pub fn region_contains(&self, r: usize, p: DVec3) -> bool {
        self.zones
            .iter()
            .filter(|z| z.region as usize == r)
            .any(|z| self.zone_contains(z, p))
    }

    pub(crate) fn zone_contains(&self, z: &PZone, p: DVec3) -> bool {
        let t = &self.terms[z.first as usize..];
        let (plus, minus) = t.split_at(z.plus as usize);
        plus.iter().all(|&b| self.shapes[b as usize].contains(p))
            && !minus[..z.minus as usize]
                .iter()
                .any(|&b| self.shapes[b as usize].contains(p))
    }
}

fn finite(b: &Body) -> Result<(), String> {
    for (i, v) in b.params.iter().enumerate() {
        if !v.is_finite() {
            return Err(format!("value {} is not a finite number", i + 1));
        }
    }
    Ok(())
}

/// Reorder `v` in place so that `v[i]` becomes the old `v[from[i]]`
/// (`from` a permutation): a model's prepared bodies are too many to copy.
fn permute<T>(v: &mut [T], from: &[u32]) {
    let mut done = vec![false; v.len()];
    for start in 0..v.len() {
        let mut i = start;
        while !done[i] {
            done[i] = true;
            let j = from[i] as usize;
            if j == start {
                break;
            }
            // Place `i` takes its body; place `j` holds the start's for now.
            v.swap(i, j);
            i = j;
        }
    }
}

/// Zones sorted along a space-filling curve through the centres of their
/// bounds (unbounded zones first, in their order), and the bodies numbered
/// in the order these zones first name them (then the bodies no zone
/// names): neighbours in space become neighbours in memory, so that a ray
/// crossing a crowd of small bodies finds their data in the lines it has
/// just loaded. Returns the zones and terms renumbered, the body index of
/// each new body number, and the new number of each body. Unsorted,
/// 100,000 random spheres rendered 20 % slower (BENCHMARKS.md, twelfth
/// round).
fn in_space_order(
    zones: Vec<PZone>,
    terms: Vec<u32>,
    bodies: usize,
) -> (Vec<PZone>, Vec<u32>, Vec<u32>, Vec<u32>) {
    let all = zones
        .iter()
        .filter(|z| z.bounds.is_finite())
        .fold(Aabb::EMPTY, |a, z| a.union(&z.bounds));
    let size = all.size().max(DVec3::splat(f64::MIN_POSITIVE));
    let key = |z: &PZone| -> u64 {
        if !z.bounds.is_finite() || all.is_empty() {
            return 0;
        }
        // 21 bits an axis, interleaved (Morton order).
        let q = ((z.bounds.center() - all.min) / size * 2_097_151.0)
            .clamp(DVec3::ZERO, DVec3::splat(2_097_151.0));
        let spread = |v: f64| {
            let mut x = v as u64 & 0x1f_ffff;
            x = (x | x << 32) & 0x1f_0000_0000_ffff;
            x = (x | x << 16) & 0x1f_0000_ff00_00ff;
            x = (x | x << 8) & 0x100f_00f0_0f00_f00f;
            x = (x | x << 4) & 0x10c3_0c30_c30c_30c3;
            (x | x << 2) & 0x1249_2492_4924_9249
        };
        1 + (spread(q.x) | spread(q.y) << 1 | spread(q.z) << 2)
    };
    let mut order: Vec<u32> = (0..zones.len() as u32).collect();
    let keys: Vec<u64> = zones.iter().map(key).collect();
    order.sort_unstable_by_key(|&zi| (keys[zi as usize], zi));
    const NONE: u32 = u32::MAX;
    let mut places = vec![NONE; bodies];
    let mut body_ids = Vec::with_capacity(bodies);
    let mut place = |b: u32| {
        if places[b as usize] == NONE {
            places[b as usize] = body_ids.len() as u32;
            body_ids.push(b);
        }
        places[b as usize]
    };
    let mut new_zones = Vec::with_capacity(zones.len());
    let mut new_terms = Vec::with_capacity(terms.len());
    for &zi in &order {
        let z = &zones[zi as usize];
        let first = z.first as usize;
        let n = z.plus as usize + z.minus as usize;
        new_zones.push(PZone {
            first: new_terms.len() as u32,
            ..*z
        });
        new_terms.extend(terms[first..first + n].iter().map(|&b| place(b)));
    }
    for b in 0..bodies as u32 {
        place(b);
    }
    (new_zones, new_terms, body_ids, places)
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

fn polyhedron_from_points(
    b: &Body,
    pts: &[DVec3],
    warnings: &mut Vec<Warning>,
    check_faces: bool,
) -> Result<(Shape, Aabb), String> {
    let bounds = Aabb::from_points(pts.iter().copied());
    let size = bounds.diagonal();
    if size == 0.0 {
        return Err("all vertices coincide".into());
    }
    let eps = 1e-9 * size;
    if check_faces {
        for f in ARB_FACES {
            let v: Vec<DVec3> = f.iter().map(|&i| pts[i - 1]).collect();
            let mut distinct: Vec<DVec3> = Vec::new();
            for p in &v {
                if !distinct.iter().any(|q| (*q - *p).length() <= eps) {
                    distinct.push(*p);
                }
            }
            if distinct.len() == 4 {
                let n = (distinct[1] - distinct[0]).cross(distinct[2] - distinct[0]);
                if n.length() > 0.0 {
                    let off = (distinct[3] - distinct[0]).dot(n.normalize()).abs();
                    if off > 1e-6 * size {
                        warnings.push(Warning {
                            body: b.name.clone(),
                            kind: b.kind,
                            message: format!(
                                "face {}{}{}{} is not planar (a vertex is {:.4} off the plane of the other three); using the convex hull of the vertices",
                                f[0], f[1], f[2], f[3], off
                            ),
                        });
                    }
                }
            }
        }
    }
    let h = hull(pts, eps);
    if h.volume <= 1e-12 * size * size * size || h.planes.len() < 4 {
        return Err("the vertices span no volume (degenerate polyhedron)".into());
    }
    Ok((Shape::Polyhedron(Polyhedron::new(h.planes, bounds)), bounds))
}

fn half_space(n: DVec3, d: f64) -> Result<(Shape, Aabb), String> {
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
        Shape::Polyhedron(Polyhedron::new(vec![Plane { n, d }], bounds)),
        bounds,
    ))
}

fn nonzero(v: DVec3, what: &str) -> Result<DVec3, String> {
    if v.length_squared() == 0.0 {
        Err(format!("{what} is zero"))
    } else {
        Ok(v)
    }
}

fn positive(x: f64, what: &str) -> Result<f64, String> {
    if x > 0.0 {
        Ok(x)
    } else {
        Err(format!("{what} must be positive (is {x})"))
    }
}

fn independent(a: DVec3, b: DVec3, c: DVec3, what: &str) -> Result<(), String> {
    let det = a.cross(b).dot(c).abs();
    if det <= 1e-12 * a.length() * b.length() * c.length() {
        Err(format!("{what} are coplanar (zero volume)"))
    } else {
        Ok(())
    }
}

fn perpendicular(a: DVec3, b: DVec3, what: &str) -> Result<(), String> {
    if a.dot(b).abs() > 1e-5 * a.length() * b.length() {
        Err(format!("{what} are not perpendicular"))
    } else {
        Ok(())
    }
}

/// Build the prepared shape of one body and its bounds.
fn build(b: &Body, warnings: &mut Vec<Warning>) -> Result<(Shape, Aabb), String> {
    use BodyKind::*;
    finite(b)?;
    let expect = b.kind.info().value_count();
    if b.kind == Ars {
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
    } else if b.params.len() != expect {
        return Err(format!("takes {expect} values, found {}", b.params.len()));
    }
    let v = |i: usize| b.vec3(i);
    let s = |i: usize| b.params[i];
    let shape = match b.kind {
        Sph => {
            let sp = Sphere::new(v(0), positive(s(3), "radius")?);
            let bb = sp.bounds();
            return Ok((Shape::Sphere(sp), bb));
        }
        Rcc => {
            let h = nonzero(v(3), "height vector")?;
            let r = positive(s(6), "radius")?;
            let (u, w) = orthonormal_basis(h.normalize());
            Shape::Cone(Cone::new(v(0), u * r, w * r, h, 1.0))
        }
        Rec => {
            let (h, a, bb) = (
                nonzero(v(3), "height vector")?,
                nonzero(v(6), "semi-axis A")?,
                nonzero(v(9), "semi-axis B")?,
            );
            independent(a, bb, h, "A, B and H")?;
            Shape::Cone(Cone::new(v(0), a, bb, h, 1.0))
        }
        Trc => {
            let h = nonzero(v(3), "height vector")?;
            let (r1, r2) = (s(6), s(7));
            if r1 < 0.0 || r2 < 0.0 || (r1 == 0.0 && r2 == 0.0) {
                return Err(format!(
                    "radii must be non-negative and not both zero (are {r1} and {r2})"
                ));
            }
            let (u, w) = orthonormal_basis(h.normalize());
            if r1 > 0.0 {
                Shape::Cone(Cone::new(v(0), u * r1, w * r1, h, r2 / r1))
            } else {
                // Apex at the base: build it from the top down.
                Shape::Cone(Cone::new(v(0) + h, u * r2, w * r2, -h, 0.0))
            }
        }
        Tec => {
            let (h, a, bb) = (
                nonzero(v(3), "height vector")?,
                nonzero(v(6), "semi-axis A")?,
                nonzero(v(9), "semi-axis B")?,
            );
            independent(a, bb, h, "A, B and H")?;
            let p = positive(s(12), "ratio P")?;
            Shape::Cone(Cone::new(v(0), a, bb, h, 1.0 / p))
        }
        Tgc => {
            let (h, a, bb) = (
                nonzero(v(3), "height vector")?,
                nonzero(v(6), "semi-axis A")?,
                nonzero(v(9), "semi-axis B")?,
            );
            independent(a, bb, h, "A, B and H")?;
            let (c, d) = (s(12), s(13));
            if c < 0.0 || d < 0.0 {
                return Err(format!(
                    "top semi-axes must be non-negative (are {c} and {d})"
                ));
            }
            let (ra, rb) = (c / a.length(), d / bb.length());
            if (ra - rb).abs() <= 1e-12 * ra.max(rb) {
                Shape::Cone(Cone::new(v(0), a, bb, h, ra))
            } else {
                Shape::GeneralCone(GeneralCone::new(v(0), a, bb, h, ra, rb))
            }
        }
        Ell => {
            let (f1, f2, l) = (v(0), v(3), s(6));
            let fd = (f2 - f1).length();
            if l <= fd {
                return Err(format!(
                    "major axis length {l} must exceed the distance between the foci ({fd})"
                ));
            }
            let c = (f1 + f2) * 0.5;
            if fd == 0.0 {
                let sp = Sphere::new(c, l / 2.0);
                let bb = sp.bounds();
                return Ok((Shape::Sphere(sp), bb));
            }
            let a = (f2 - f1) * (l / (2.0 * fd));
            let r = (a.length_squared() - (fd / 2.0).powi(2)).sqrt();
            ellipsoid_of_revolution(c, a, r)
        }
        Ell1 => {
            let a = nonzero(v(3), "semi-major axis")?;
            ellipsoid_of_revolution(v(0), a, positive(s(6), "radius of revolution")?)
        }
        Ellg => {
            let (a, bb, c) = (
                nonzero(v(3), "semi-axis A")?,
                nonzero(v(6), "semi-axis B")?,
                nonzero(v(9), "semi-axis C")?,
            );
            independent(a, bb, c, "semi-axes A, B and C")?;
            Shape::Ellipsoid(Ellipsoid::new(v(0), DMat3::from_cols(a, bb, c)))
        }
        Rpp => {
            let min = DVec3::new(s(0), s(2), s(4));
            let max = DVec3::new(s(1), s(3), s(5));
            for (a, n) in ["x", "y", "z"].iter().enumerate() {
                if min[a] >= max[a] {
                    return Err(format!(
                        "{n}min ({}) must be less than {n}max ({})",
                        min[a], max[a]
                    ));
                }
            }
            let bb = Aabb::new(min, max);
            return Ok((Shape::Rpp(crate::shape::Rpp::new(bb)), bb));
        }
        Box => {
            let (a, bb, c) = (
                nonzero(v(3), "edge A")?,
                nonzero(v(6), "edge B")?,
                nonzero(v(9), "edge C")?,
            );
            perpendicular(a, bb, "edges A and B")?;
            perpendicular(a, c, "edges A and C")?;
            perpendicular(bb, c, "edges B and C")?;
            let o = v(0);
            let pts: Vec<DVec3> = (0..8)
                .map(|i| {
                    o + a * (i & 1) as f64 + bb * ((i >> 1) & 1) as f64 + c * ((i >> 2) & 1) as f64
                })
                .collect();
            return polyhedron_from_points(b, &pts, warnings, false);
        }
        Raw => {
            let (a, bb, c) = (
                nonzero(v(3), "leg A")?,
                nonzero(v(6), "leg B")?,
                nonzero(v(9), "sweep C")?,
            );
            independent(a, bb, c, "A, B and C")?;
            let o = v(0);
            let pts = [o, o + a, o + bb, o + c, o + a + c, o + bb + c];
            return polyhedron_from_points(b, &pts, warnings, false);
        }
        Arb4 | Arb5 | Arb6 | Arb7 | Arb8 => {
            let pts = arb_points(b);
            return polyhedron_from_points(b, &pts, warnings, b.kind == Arb8);
        }
        ArbF => {
            let pts: Vec<DVec3> = (0..8).map(|i| v(3 * i)).collect();
            let mut used = [false; 8];
            for code in &b.params[24..30] {
                let c = code.abs().round() as u64;
                let mut x = c;
                while x > 0 {
                    let d = (x % 10) as usize;
                    if d == 0 || d > 8 {
                        return Err(format!(
                            "face code {code} names vertex {d}, which does not exist"
                        ));
                    }
                    used[d - 1] = true;
                    x /= 10;
                }
            }
            let pts: Vec<DVec3> = pts
                .iter()
                .zip(used)
                .filter(|(_, u)| *u)
                .map(|(p, _)| *p)
                .collect();
            if pts.len() < 4 {
                return Err("face codes use fewer than 4 vertices".into());
            }
            return polyhedron_from_points(b, &pts, warnings, false);
        }
        Tor => {
            let n = nonzero(v(3), "normal")?;
            let (r1, r2) = (
                positive(s(6), "major radius")?,
                positive(s(7), "minor radius")?,
            );
            if r2 >= r1 {
                return Err(format!(
                    "minor radius {r2} must be smaller than major radius {r1}"
                ));
            }
            let t = Torus::new(v(0), n, r1, r2);
            let bb = t.bounds();
            return Ok((Shape::Torus(t), bb));
        }
        Haf => return half_space(v(0), s(3)),
        Xyp => return half_space(DVec3::Z, s(0)),
        Xzp => return half_space(DVec3::Y, s(0)),
        Yzp => return half_space(DVec3::X, s(0)),
        Pla => {
            let n = nonzero(v(0), "normal")?;
            return half_space(n, n.dot(v(3)));
        }
        Xcc | Ycc | Zcc | Xec | Yec | Zec => {
            let radii: &[f64] = &b.params[2..];
            for r in radii {
                positive(*r, "radius")?;
            }
            let (a1, a2) = crate::model::cyl_axes(b.kind);
            let (r1, r2) = (radii[0], *radii.last().unwrap_or(&radii[0]));
            let mut bb = Aabb::INFINITE;
            bb.min[a1] = s(0) - r1;
            bb.max[a1] = s(0) + r1;
            bb.min[a2] = s(1) - r2;
            bb.max[a2] = s(1) + r2;
            let (m, bv, c) = quadric_matrix(&b.as_quadric());
            return Ok((Shape::Quadric(Quadric::new(m, bv, c)), bb));
        }
        Qua => {
            if b.params.iter().all(|x| *x == 0.0) {
                return Err("all coefficients are zero".into());
            }
            let (m, bv, c) = quadric_matrix(&b.params);
            return Ok((Shape::Quadric(Quadric::new(m, bv, c)), Aabb::INFINITE));
        }
        Ars => {
            let tris = ars_triangles(b);
            let m = Mesh::new(&tris);
            if m.triangle_count() < 4 {
                return Err("the curves span no surface (degenerate ARS)".into());
            }
            let bb = m.bounds();
            return Ok((Shape::Mesh(m), bb));
        }
    };
    let bb = shape.bounds();
    Ok((shape, bb))
}

fn ellipsoid_of_revolution(c: DVec3, a: DVec3, r: f64) -> Shape {
    let (u, w) = orthonormal_basis(a.normalize());
    Shape::Ellipsoid(Ellipsoid::new(c, DMat3::from_cols(a, u * r, w * r)))
}
