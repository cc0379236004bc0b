//! `prepare`: validate every body, build its ray-casting form, lay zones out
//! in flat arrays and build the bounding volume hierarchies.

use crate::build::{
    default_tolerance, in_space_order, permute, without_containers, Layout, ZoneBuilder,
};
use crate::bvh::Bvh;
use crate::fill::{FillBuilder, FillTracer};
use crate::raster::RasterProxy;
use std::sync::Arc;
use sv_geom::shape::{Shape, Sphere};
use sv_geom::{Geometry, Warning};
use sv_math::{Aabb, DVec3};

/// Options for [`Prepared::new`].
#[derive(Clone, Debug, Default)]
pub struct PrepareOptions {
    /// Boolean tolerance (model units). Default: 1e-7 of the size of the
    /// geometry, containers such as a FLUKA black hole set aside (see
    /// `default_tolerance` in build.rs).
    pub tolerance: Option<f64>,
    /// Per region: does it stop light? `None` means every region does.
    /// Transparent regions are still traced by [`Prepared::partitions`].
    pub opaque: Option<Vec<bool>>,
    /// Per region: is it beyond the model (a FLUKA black hole, an MCNP
    /// cell of importance zero)? Such regions are left out of
    /// [`Prepared::interest_bounds`]' default uses (framing, checks).
    /// `None` means none is.
    pub outside: Option<Vec<bool>>,
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

/// A zone as the tracer holds it: its terms in [`Prepared`]'s one array.
/// Sixty-four bytes, a cache line: the tile lists read zones in turn.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PreparedZone {
    pub region: u32,
    /// Terms in `terms[first..first+plus]` are `+`, the next `minus` are
    /// `-`; when the zone has groups, the term after them is the index of
    /// its first group in [`Prepared::groups`].
    pub first: u32,
    pub plus: u16,
    pub minus: u16,
    /// How many groups it has, and [`PreparedZone::FILLED`] when its
    /// region is filled.
    pub groups: u16,
    pub bounds: Aabb,
    /// Every `+` body is convex and there are no groups (so the zone is
    /// convex where its `+` bodies give one segment each).
    pub convex: bool,
    /// It has `+` bodies and no groups, and the packet tracer casts every
    /// `+` body in vector lanes ([`Shape::has_lanes`]), or its one `+`
    /// body is a torus (whose two segments the zone takes in the lanes):
    /// a packet evaluates the zone for all its rays at once, but for the
    /// rays that meet the box of a `-` body it cannot cast.
    pub lanes: bool,
}

impl PreparedZone {
    /// The bit of `groups` that marks a zone of a filled region.
    pub const FILLED: u16 = 1 << 15;

    /// How many groups it has.
    #[inline(always)]
    pub fn group_count(&self) -> usize {
        usize::from(self.groups & !Self::FILLED)
    }

    /// True for a zone of a filled region: what a ray meets there is what
    /// fills it.
    #[inline(always)]
    pub fn is_filled(&self) -> bool {
        self.groups & Self::FILLED != 0
    }
}

/// A group of a zone: the union of `count` nested zones from `first` in
/// [`Prepared::nested`], intersected with the zone or subtracted from it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PreparedGroup {
    pub subtract: bool,
    pub first: u32,
    pub count: u32,
    pub bounds: Aabb,
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
    /// The zones inside groups, to any depth.
    pub(crate) nested: Vec<PreparedZone>,
    /// Every zone's groups.
    pub(crate) groups: Vec<PreparedGroup>,
    /// What fills the filled regions, and per region (of every universe)
    /// the index of its fill here, `u32::MAX` for none.
    pub(crate) fills: Vec<FillTracer>,
    pub(crate) region_fills: Vec<u32>,
    /// The universes the fills hold, each prepared in its own frame.
    pub(crate) subs: Vec<Arc<Prepared>>,
    pub(crate) terms: Vec<u32>,
    pub(crate) opaque: Vec<bool>,
    outside: Vec<bool>,
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
    pub(crate) places: Vec<u32>,
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
        let mut warnings = Vec::new();
        let p = Prepared::universe_with(g, opts, vec![0], &mut warnings)?;
        Ok((p, warnings))
    }

    /// Universe `path.last()` of `g` prepared in its own frame, with the
    /// universes its regions' fills hold (`path` lists the universes
    /// being prepared, outermost first).
    pub(crate) fn universe(
        g: &Geometry,
        opts: &PrepareOptions,
        path: Vec<usize>,
    ) -> Result<Prepared, PrepareError> {
        Prepared::universe_with(g, opts, path, &mut Vec::new())
    }

    fn universe_with(
        g: &Geometry,
        opts: &PrepareOptions,
        path: Vec<usize>,
        warnings: &mut Vec<Warning>,
    ) -> Result<Prepared, PrepareError> {
        let universe = *path.last().expect("a universe");
        let (mut shapes, mut body_bounds, mut problems) = prepare_bodies(g, warnings);
        let opaque = opacity(g, opts, &mut problems);
        let mut builder = ZoneBuilder {
            shapes: &shapes,
            body_bounds: &body_bounds,
            layout: Layout::default(),
            problems: Vec::new(),
        };
        builder.regions(g, universe);
        problems.append(&mut builder.problems);
        let mut fills = FillBuilder::new(g, opts, path);
        let mut region_fills = vec![u32::MAX; g.regions.len()];
        let mut fill_tracers = Vec::new();
        for (r, region) in g.regions.iter().enumerate() {
            if let (true, Some(fill)) = (region.universe == universe, &region.fill) {
                region_fills[r] = fill_tracers.len() as u32;
                fill_tracers.push(fills.fill(r, fill));
            }
        }
        problems.append(&mut fills.problems);
        if !problems.is_empty() {
            return Err(PrepareError { problems });
        }
        let (mut layout, body_ids, places) = in_space_order(builder.layout, g.bodies.len());
        permute(&mut shapes, &body_ids);
        permute(&mut body_bounds, &body_ids);
        let tol = opts
            .tolerance
            .unwrap_or_else(|| default_tolerance(&body_bounds));
        // Pad every box by the tolerance so that rounding never makes a box
        // test reject a hit on its boundary.
        let pad = 4.0 * tol;
        for b in body_bounds.iter_mut() {
            *b = b.padded(pad);
        }
        for z in layout.zones.iter_mut().chain(layout.nested.iter_mut()) {
            z.bounds = z.bounds.padded(pad);
        }
        for group in layout.groups.iter_mut() {
            group.bounds = group.bounds.padded(pad);
        }
        let lists = ZoneLists::of(&layout.zones, &opaque, opts.brute_force);
        let (enclosures, hull_pts) = enclosures(&layout, &shapes, tol);
        let raster_proxies = lists
            .bounded_opaque
            .iter()
            .map(|&(zi, b)| RasterProxy::new(zi, &b, &enclosures[zi as usize]))
            .collect();
        let p = Prepared {
            shapes,
            body_bounds,
            bvh_all: Bvh::build(&lists.bounded_all),
            bvh_opaque: Bvh::build(&lists.bounded_opaque),
            zones: layout.zones,
            nested: layout.nested,
            groups: layout.groups,
            terms: layout.terms,
            opaque,
            outside: match &opts.outside {
                Some(o) if o.len() == g.regions.len() => o.clone(),
                _ => vec![false; g.regions.len()],
            },
            unbounded_all: lists.unbounded_all,
            unbounded_opaque: lists.unbounded_opaque,
            raster_proxies,
            tol,
            enclosures,
            hull_pts,
            bounds: lists.bounds,
            opaque_bounds: lists.opaque_bounds,
            region_count: g.regions.len(),
            body_ids,
            places,
            packets: !opts.brute_force,
            fills: fill_tracers,
            region_fills,
            subs: fills.subs,
        };
        Ok(p)
    }

    /// Bounds of every zone with finite bounds (unbounded regions are
    /// left out, so framing stays finite).
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// How many zones there are (numbered from 0).
    pub fn zone_count(&self) -> usize {
        self.zones.len()
    }

    /// Bounds of zone `zi` (as listed by [`Prepared::all_zones_in_box`]).
    pub fn zone_bounds(&self, zi: u32) -> Aabb {
        self.zones[zi as usize].bounds
    }

    /// Bounds of the part of zone `zi` inside the finite box `within`:
    /// its bounds there, narrowed by each of its `+` bodies' part of the
    /// box ([`sv_geom::shape::Shape::bounds_within`]): a half-space not
    /// square to an axis leaves a zone only its side of the box, and a
    /// grid row's plane cuts a sphere or a mesh across less than its
    /// bounds. Never smaller than the part but for rounding: pad it by the
    /// tolerance.
    pub fn zone_reach(&self, zi: u32, within: &Aabb) -> Aabb {
        let z = &self.zones[zi as usize];
        let mut reach = z.bounds.intersection(within);
        for shape in self.zone_plus_shapes(z) {
            if reach.is_empty() {
                break;
            }
            if shape.narrows_within() {
                reach = reach.intersection(&shape.bounds_within(&reach));
            }
        }
        reach
    }

    /// Whether [`Prepared::zone_reach`] can give less than zone `zi`'s
    /// bounds within a box ([`Shape::narrows_within`]).
    pub fn zone_narrows(&self, zi: u32) -> bool {
        let z = &self.zones[zi as usize];
        self.zone_plus_shapes(z).any(Shape::narrows_within)
    }

    /// The zone's `+` bodies.
    fn zone_plus_shapes<'a>(&'a self, z: &'a PreparedZone) -> impl Iterator<Item = &'a Shape> {
        let plus = &self.zone_terms(z)[..usize::from(z.plus)];
        plus.iter().map(|&b| &self.shapes[b as usize])
    }

    /// Bounds of region `r`'s zones in this universe (empty when it has
    /// none here; infinite sides where a zone is unbounded).
    pub fn region_bounds(&self, r: usize) -> Aabb {
        self.zones
            .iter()
            .filter(|z| z.region as usize == r)
            .fold(Aabb::EMPTY, |acc, z| acc.union(&z.bounds))
    }

    /// The box of what a view or a check should cover: the finite regions
    /// that `keep` accepts (a reader's black holes left out), less the
    /// containers around them (a region whose box holds all the others'
    /// and is more than twice their size: the void sphere around a
    /// detector). Empty when no kept region is finite.
    pub fn interest_bounds(&self, keep: impl Fn(usize) -> bool) -> Aabb {
        let mut per_region = vec![Aabb::EMPTY; self.region_count];
        for z in &self.zones {
            let r = z.region as usize;
            if keep(r) {
                per_region[r] = per_region[r].union(&z.bounds);
            }
        }
        let mut finite: Vec<Aabb> = per_region
            .into_iter()
            .filter(|b| !b.is_empty() && b.is_finite())
            .collect();
        let (inner, innermost) = without_containers(&mut finite, Aabb::EMPTY);
        if inner.is_empty() {
            innermost.unwrap_or(Aabb::EMPTY)
        } else {
            inner
        }
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

    /// Is region `r` beyond the model ([`PrepareOptions::outside`])?
    pub fn is_outside(&self, r: usize) -> bool {
        self.outside.get(r).copied().unwrap_or(false)
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
        let (plus, minus) = self.zone_terms(z).split_at(z.plus as usize);
        let inside = |b: &u32| self.shapes[*b as usize].contains(p);
        if !plus.iter().all(inside) || minus.iter().any(inside) {
            return false;
        }
        self.zone_groups(z).iter().all(|g| {
            let zones = &self.nested[g.first as usize..(g.first + g.count) as usize];
            zones.iter().any(|inner| self.zone_contains(inner, p)) != g.subtract
        })
    }

    /// The bodies of zone `z`: its `+` bodies, then its `-` bodies.
    #[inline]
    pub(crate) fn zone_terms(&self, z: &PreparedZone) -> &[u32] {
        let first = z.first as usize;
        &self.terms[first..first + usize::from(z.plus) + usize::from(z.minus)]
    }

    /// The groups of zone `z`.
    #[inline]
    pub(crate) fn zone_groups(&self, z: &PreparedZone) -> &[PreparedGroup] {
        if z.group_count() == 0 {
            return &[];
        }
        let first = self.terms[z.first as usize + z.plus as usize + z.minus as usize] as usize;
        &self.groups[first..first + z.group_count()]
    }
}

/// Every body's prepared shape and bounds, and what is wrong with the
/// bodies that cannot be prepared (each stands in as a unit sphere with
/// empty bounds, so that the regions can still be checked).
fn prepare_bodies(
    g: &Geometry,
    warnings: &mut Vec<Warning>,
) -> (Vec<Shape>, Vec<Aabb>, Vec<String>) {
    let mut problems = Vec::new();
    let mut shapes = Vec::with_capacity(g.bodies.len());
    let mut body_bounds = Vec::with_capacity(g.bodies.len());
    for b in &g.bodies {
        match sv_geom::prepare(b, warnings) {
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
    (shapes, body_bounds, problems)
}

/// Per region, whether it stops light.
fn opacity(g: &Geometry, opts: &PrepareOptions, problems: &mut Vec<String>) -> Vec<bool> {
    match &opts.opaque {
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
    }
}

/// The zones the hierarchies hold (bounded ones, of all regions and of
/// opaque ones) and those every ray tries (unbounded ones), with the
/// bounds of each kind.
struct ZoneLists {
    bounded_all: Vec<(u32, Aabb)>,
    bounded_opaque: Vec<(u32, Aabb)>,
    unbounded_all: Vec<u32>,
    unbounded_opaque: Vec<u32>,
    bounds: Aabb,
    opaque_bounds: Aabb,
}

impl ZoneLists {
    /// The lists of `zones`; with `brute_force`, every zone is tried by
    /// every ray.
    fn of(zones: &[PreparedZone], opaque: &[bool], brute_force: bool) -> ZoneLists {
        let mut lists = ZoneLists {
            bounded_all: Vec::new(),
            bounded_opaque: Vec::new(),
            unbounded_all: Vec::new(),
            unbounded_opaque: Vec::new(),
            bounds: Aabb::EMPTY,
            opaque_bounds: Aabb::EMPTY,
        };
        for (i, z) in zones.iter().enumerate() {
            // What fills a region is traced whatever the region's own
            // opacity: its content's decides.
            let visible = opaque[z.region as usize] || z.is_filled();
            if z.bounds.is_finite() && !brute_force {
                lists.bounded_all.push((i as u32, z.bounds));
                lists.bounds = lists.bounds.union(&z.bounds);
                if visible {
                    lists.bounded_opaque.push((i as u32, z.bounds));
                    lists.opaque_bounds = lists.opaque_bounds.union(&z.bounds);
                }
            } else {
                lists.unbounded_all.push(i as u32);
                if visible {
                    lists.unbounded_opaque.push(i as u32);
                }
            }
        }
        lists
    }
}

/// Per zone, something tighter than its box that holds it (from its first
/// `+` body that has a ball or hull points), and the hull points.
fn enclosures(layout: &Layout, shapes: &[Shape], tol: f64) -> (Vec<Enclosure>, Vec<DVec3>) {
    let mut hull_pts = Vec::new();
    let enclosures = layout
        .zones
        .iter()
        .map(|z| {
            let plus = &layout.terms[z.first as usize..z.first as usize + z.plus as usize];
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
    (enclosures, hull_pts)
}
