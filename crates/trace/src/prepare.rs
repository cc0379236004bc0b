//! `prepare`: validate every body, build its ray-casting form, lay zones out
//! in flat arrays and build the bounding volume hierarchies.

use crate::bvh::Bvh;
use crate::raster::RasterProxy;
use sv_geom::shape::{Shape, Sphere};
use sv_geom::{Geometry, Op, Warning};
use sv_math::{Aabb, DVec3};

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

/// Bodies or regions that cannot be prepared; every problem is listed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{}", .problems.join("\n"))]
pub struct PrepareError {
    /// One line per problem, naming the body or region and the rule broken
    /// (`RCC "leg": height vector is zero`).
    pub problems: Vec<String>,
}

#[derive(Clone, Copy, Debug)]
pub(crate) struct PreparedZone {
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
pub(crate) enum Enclosure {
    /// Nothing better than the box.
    Box,
    /// The ball of a sphere among its `+` bodies: centre and radius, kept
    /// here so that the tests of a tile's zones do not fetch the bodies
    /// (100,000 spheres' bodies are 26 MB).
    Ball(DVec3, f64),
    /// The convex hull of `hull_pts[a..b]` ([`Shape::hull_points`]).
    Points(u32, u32),
}

/// A zone's [`Enclosure`], resolved by [`Prepared::enclosure`].
#[derive(Clone, Copy)]
pub(crate) enum EnclosureRef<'a> {
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
    pub(crate) zones: Vec<PreparedZone>,
    pub(crate) terms: Vec<u32>,
    pub(crate) opaque: Vec<bool>,
    pub(crate) bvh_all: Bvh,
    pub(crate) bvh_opaque: Bvh,
    pub(crate) unbounded_all: Vec<u32>,
    pub(crate) unbounded_opaque: Vec<u32>,
    /// The bounded zones of opaque regions, in the order of the zones, as
    /// a raster sees them.
    pub(crate) raster_proxies: Vec<RasterProxy>,
    pub(crate) tol: f64,
    /// Per zone, something tighter than its box that holds it.
    pub(crate) enclosures: Vec<Enclosure>,
    /// The points of [`Enclosure::Points`].
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
            match sv_geom::prepare(b, &mut warnings) {
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
                zones.push(PreparedZone {
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
        let enclosures: Vec<Enclosure> = zones
            .iter()
            .map(|z| {
                let plus = &terms[z.first as usize..z.first as usize + z.plus as usize];
                plus.iter()
                    .find_map(|&b| match &shapes[b as usize] {
                        Shape::Sphere(sp) => Some(Enclosure::Ball(sp.c, sp.r)),
                        s => s.hull_points(tol).map(|pts| {
                            let a = hull_pts.len() as u32;
                            hull_pts.extend(pts);
                            Enclosure::Points(a, hull_pts.len() as u32)
                        }),
                    })
                    .unwrap_or(Enclosure::Box)
            })
            .collect();
        let raster_proxies = bounded_opaque
            .iter()
            .map(|&(zi, b)| RasterProxy::new(zi, &b, &enclosures[zi as usize]))
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
            raster_proxies,
            tol,
            enclosures,
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
    /// a [`Bound`](sv_geom::boolean::Bound) of a hit or partition: bodies
    /// are stored in the order their zones lie in space.
    pub fn body_index(&self, b: u32) -> usize {
        self.body_ids[b as usize] as usize
    }

    /// What is known of zone `zi`'s shape beyond its box.
    #[inline]
    pub(crate) fn enclosure(&self, zi: u32) -> EnclosureRef<'_> {
        match self.enclosures[zi as usize] {
            Enclosure::Ball(c, r) => EnclosureRef::Ball(c, r),
            Enclosure::Points(a, e) => EnclosureRef::Points(&self.hull_pts[a as usize..e as usize]),
            Enclosure::Box => EnclosureRef::Box,
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

    pub(crate) fn zone_contains(&self, z: &PreparedZone, p: DVec3) -> bool {
        let t = &self.terms[z.first as usize..];
        let (plus, minus) = t.split_at(z.plus as usize);
        plus.iter().all(|&b| self.shapes[b as usize].contains(p))
            && !minus[..z.minus as usize]
                .iter()
                .any(|&b| self.shapes[b as usize].contains(p))
    }
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
    zones: Vec<PreparedZone>,
    terms: Vec<u32>,
    bodies: usize,
) -> (Vec<PreparedZone>, Vec<u32>, Vec<u32>, Vec<u32>) {
    let all = zones
        .iter()
        .filter(|z| z.bounds.is_finite())
        .fold(Aabb::EMPTY, |a, z| a.union(&z.bounds));
    let size = all.size().max(DVec3::splat(f64::MIN_POSITIVE));
    let key = |z: &PreparedZone| -> u64 {
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
        new_zones.push(PreparedZone {
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
