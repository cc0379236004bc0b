//! Filled regions: another universe moved into a region (MCNP `FILL`,
//! OpenMC fills, FLUKA lattice cells) or a lattice of universes. Nothing is
//! copied into the scene: each universe is prepared once, in its own
//! frame, and a ray that crosses a filled region is moved into that frame
//! along the stretches where it is inside the region; through a lattice,
//! it walks the elements it crosses, one after another, each element's
//! universe moved to its place.

use crate::hit::{Hit, Partition, Scratch};
use crate::prepare::{Prepared, PreparedZone};
use crate::query::insert_by_entry;
use std::sync::Arc;
use sv_geom::boolean::{Bound, Span};
use sv_geom::{Fill, Geometry, Lattice, LatticeKind};
use sv_math::{DAffine3, DMat3, DVec3, Ray};

/// No sub-universe: an element that holds nothing.
const NOTHING: u32 = u32::MAX;
/// Most elements one ray walks through in one lattice.
const MAX_STEPS: usize = 1 << 20;

/// How the frame inside a filled region sits in the region's frame: a
/// rotation, a translation and a uniform scale.
#[derive(Clone, Debug)]
pub(crate) struct Moved {
    inside_from_region: DAffine3,
    /// The rotation from the inside frame to the region's (for normals).
    rotation: DMat3,
    /// Lengths inside per length in the region's frame.
    scale: f64,
}

impl Moved {
    /// The move of `region_from_inside`, which must be a similarity.
    fn new(region_from_inside: &DAffine3) -> Result<Moved, String> {
        let m = region_from_inside.matrix3;
        let det = m.determinant();
        if !(det > 0.0 && det.is_finite()) {
            return Err("its transformation is not a rotation (it mirrors or flattens)".into());
        }
        let s = det.cbrt();
        let rotation = m * (1.0 / s);
        if !(rotation.transpose() * rotation).abs_diff_eq(DMat3::IDENTITY, 1e-6) {
            return Err("its transformation shears or stretches unevenly".into());
        }
        Ok(Moved {
            inside_from_region: region_from_inside.inverse(),
            rotation,
            scale: 1.0 / s,
        })
    }

    /// The ray in the inside frame, with a unit direction: a point at `t`
    /// along `ray` is at `t * scale` along it.
    #[inline]
    fn ray(&self, ray: &Ray) -> Ray {
        let origin = self.inside_from_region.transform_point3(ray.origin);
        let dir = self.inside_from_region.transform_vector3(ray.dir) / self.scale;
        Ray::new(origin, dir)
    }

    /// A normal of the inside frame in the region's.
    #[inline]
    fn normal_out(&self, n: DVec3) -> DVec3 {
        (self.rotation * n).normalize()
    }
}

/// A lattice as the tracer walks it.
#[derive(Clone, Debug)]
pub(crate) struct LatticeWalk {
    kind: LatticeKind,
    steps: [DVec3; 3],
    /// Rectangular: grid coordinates of a point, `steps⁻¹ (p - base)`.
    grid_from_offset: DMat3,
    base: DVec3,
    origin: DVec3,
    lowest: [i32; 3],
    counts: [u32; 3],
    /// The sub-universe of each element ([`NOTHING`] where none).
    elements: Vec<u32>,
    outer: u32,
    /// Hexagonal: unit normals toward the six neighbours (±a, ±b, ±(b−a))
    /// and half the flat-to-flat pitch.
    sides: [DVec3; 3],
    apothem: f64,
    /// A step small beside an element, to find the element past a face.
    nudge: f64,
}

/// What fills a region, as the tracer reaches it.
#[derive(Clone, Debug)]
pub(crate) enum FillTracer {
    /// One universe (its index among [`Prepared::subs`]) moved in.
    Universe { sub: u32, moved: Moved },
    /// A lattice, its frame moved in.
    Lattice {
        moved: Moved,
        walk: Box<LatticeWalk>,
    },
    /// A fill that would lead back into a universe being filled (FLUKA's
    /// lattice cells hold the root itself): inside its copy, it holds
    /// nothing.
    Nothing,
}

/// Builds the fills of one prepared universe and the sub-universes they
/// hold.
pub(crate) struct FillBuilder<'a> {
    pub geometry: &'a Geometry,
    pub opts: &'a crate::PrepareOptions,
    /// The universes being prepared, outermost first, this one last.
    pub path: Vec<usize>,
    pub subs: Vec<Arc<Prepared>>,
    /// Per universe, its index among `subs` when prepared already.
    made: Vec<Option<u32>>,
    pub problems: Vec<String>,
}

impl<'a> FillBuilder<'a> {
    /// A builder for universe `path.last()`.
    pub fn new(geometry: &'a Geometry, opts: &'a crate::PrepareOptions, path: Vec<usize>) -> Self {
        FillBuilder {
            geometry,
            opts,
            path,
            subs: Vec::new(),
            made: vec![None; universe_count(geometry)],
            problems: Vec::new(),
        }
    }

    /// The fill of region `r`, or a problem.
    pub fn fill(&mut self, r: usize, fill: &Fill) -> FillTracer {
        let name = &self.geometry.regions[r].name;
        let moved = match fill {
            Fill::Universe {
                region_from_universe,
                ..
            } => Moved::new(region_from_universe),
            Fill::Lattice(l) => Moved::new(&l.region_from_lattice),
        };
        let moved = match moved {
            Ok(m) => m,
            Err(e) => {
                self.problems
                    .push(format!("region `{name}`: its fill: {e}"));
                return FillTracer::Nothing;
            }
        };
        match fill {
            Fill::Universe { universe, .. } => match self.sub(*universe, r) {
                Some(sub) if sub != NOTHING => FillTracer::Universe { sub, moved },
                _ => FillTracer::Nothing,
            },
            Fill::Lattice(l) => match self.walk(l, r) {
                Some(walk) => FillTracer::Lattice {
                    moved,
                    walk: Box::new(walk),
                },
                None => FillTracer::Nothing,
            },
        }
    }

    /// The index among `subs` of universe `u` prepared (for region `r`'s
    /// fill); [`NOTHING`] when it would lead back into a universe being
    /// filled twice over; `None` (a problem) when it does not exist or
    /// cannot be prepared.
    fn sub(&mut self, u: usize, r: usize) -> Option<u32> {
        if u >= self.made.len() {
            self.problems.push(format!(
                "region `{}` is filled by universe {u}, which does not exist",
                self.geometry.regions[r].name
            ));
            return None;
        }
        if let Some(k) = self.made[u] {
            return Some(k);
        }
        // A universe may hold a copy of one that holds it (a FLUKA
        // lattice cell holds the root), whose own fills back hold nothing.
        if self.path.iter().filter(|&&p| p == u).count() >= 2 || self.path.len() > 32 {
            return Some(NOTHING);
        }
        let mut path = self.path.clone();
        path.push(u);
        match Prepared::universe(self.geometry, self.opts, path) {
            Ok(p) => {
                let k = self.subs.len() as u32;
                self.subs.push(Arc::new(p));
                self.made[u] = Some(k);
                Some(k)
            }
            Err(e) => {
                self.problems.extend(e.problems);
                None
            }
        }
    }

    /// Lattice `l` of region `r` ready to walk.
    fn walk(&mut self, l: &Lattice, r: usize) -> Option<LatticeWalk> {
        let name = self.geometry.regions[r].name.clone();
        let expected: usize = l.counts.iter().map(|&c| c as usize).product();
        if l.elements.len() != expected {
            self.problems.push(format!(
                "region `{name}`: its lattice lists {} elements for {}×{}×{}",
                l.elements.len(),
                l.counts[0],
                l.counts[1],
                l.counts[2]
            ));
            return None;
        }
        let [a, b, c] = l.steps;
        let grid = DMat3::from_cols(a, b, c);
        if !(grid.determinant().abs() > 0.0 && grid.determinant().is_finite()) {
            self.problems.push(format!(
                "region `{name}`: its lattice's steps span no volume"
            ));
            return None;
        }
        let sub_of = |u: Option<usize>, me: &mut Self| match u {
            None => Some(NOTHING),
            Some(u) => me.sub(u, r),
        };
        let mut elements = Vec::with_capacity(l.elements.len());
        for &u in &l.elements {
            elements.push(sub_of(u, self)?);
        }
        let outer = sub_of(l.outer, self)?;
        let pitch = a.length().min(b.length()).min(c.length());
        Some(LatticeWalk {
            kind: l.kind,
            steps: l.steps,
            grid_from_offset: grid.inverse(),
            base: l.base,
            origin: l.origin,
            lowest: l.lowest,
            counts: l.counts,
            elements,
            outer,
            sides: [a.normalize(), b.normalize(), (b - a).normalize()],
            apothem: 0.5 * a.length(),
            nudge: 1e-9 * pitch,
        })
    }
}

/// How many universes a geometry has (the root at least).
pub(crate) fn universe_count(g: &Geometry) -> usize {
    g.universes
        .len()
        .max(1)
        .max(g.regions.iter().map(|r| r.universe + 1).max().unwrap_or(1))
}

impl LatticeWalk {
    /// The element holding the point `p` (lattice frame).
    fn element_at(&self, p: DVec3) -> [i32; 3] {
        match self.kind {
            LatticeKind::Rectangular => {
                let g = self.grid_from_offset * (p - self.base);
                [g.x.floor() as i32, g.y.floor() as i32, g.z.floor() as i32]
            }
            LatticeKind::Hexagonal => {
                // Grid coordinates with the centre of (0, 0, 0) at 0; the
                // nearest centre of the triangular lattice of centres, by
                // rounding the cube coordinates (q, r, −q−r) of the basis
                // a, b, 60° apart (Red Blob Games, "Hexagonal grids").
                let g = self.grid_from_offset * (p - self.base);
                let (q, r) = (g.x, g.y);
                let s = -q - r;
                let (mut rq, mut rr, rs) = (q.round(), r.round(), s.round());
                let (dq, dr, ds) = ((rq - q).abs(), (rr - r).abs(), (rs - s).abs());
                if dq > dr && dq > ds {
                    rq = -rr - rs;
                } else if dr > ds {
                    rr = -rq - rs;
                }
                [rq as i32, rr as i32, g.z.round() as i32]
            }
        }
    }

    /// Where the ray leaves element `e` going forward from `t`.
    fn exit(&self, e: [i32; 3], ray: &Ray, t: f64) -> f64 {
        let idx = DVec3::new(f64::from(e[0]), f64::from(e[1]), f64::from(e[2]));
        let g0 = self.grid_from_offset * (ray.origin - self.base);
        let gd = self.grid_from_offset * ray.dir;
        let mut exit = f64::INFINITY;
        let mut along = |lo: f64, hi: f64, from: f64, rate: f64| {
            if rate > 0.0 {
                exit = exit.min((hi - from) / rate);
            } else if rate < 0.0 {
                exit = exit.min((lo - from) / rate);
            }
        };
        match self.kind {
            LatticeKind::Rectangular => {
                for a in 0..3 {
                    along(idx[a], idx[a] + 1.0, g0[a], gd[a]);
                }
            }
            LatticeKind::Hexagonal => {
                along(idx.z - 0.5, idx.z + 0.5, g0.z, gd.z);
                let centre = self.base + self.steps[0] * idx.x + self.steps[1] * idx.y;
                for n in self.sides {
                    for n in [n, -n] {
                        let rate = n.dot(ray.dir);
                        if rate > 0.0 {
                            exit = exit.min((self.apothem - n.dot(ray.origin - centre)) / rate);
                        }
                    }
                }
            }
        }
        exit.max(t)
    }

    /// The sub-universe of element `e` and where its origin goes.
    fn universe(&self, e: [i32; 3]) -> (u32, DVec3) {
        let mut flat = 0usize;
        let mut stride = 1usize;
        let mut listed = true;
        for ((&i, &lowest), &count) in e.iter().zip(&self.lowest).zip(&self.counts) {
            let d = i64::from(i) - i64::from(lowest);
            if d < 0 || d >= i64::from(count) {
                listed = false;
                break;
            }
            flat += d as usize * stride;
            stride *= count as usize;
        }
        let sub = if listed {
            self.elements[flat]
        } else {
            self.outer
        };
        let [a, b, c] = self.steps;
        let at = self.origin + a * f64::from(e[0]) + b * f64::from(e[1]) + c * f64::from(e[2]);
        (sub, at)
    }

    /// Each element the ray crosses between `t0` and `t1` (lattice frame),
    /// in order, with the stretch inside it ([`NOTHING`] for an element
    /// that holds no universe: the lattice region's own material); `visit`
    /// stops the walk by returning true.
    fn for_each_element(
        &self,
        ray: &Ray,
        t0: f64,
        t1: f64,
        mut visit: impl FnMut(u32, DVec3, f64, f64) -> bool,
    ) {
        let mut t = t0;
        for _ in 0..MAX_STEPS {
            if t >= t1 || !t.is_finite() {
                return;
            }
            let e = self.element_at(ray.at(t + self.nudge));
            let end = self.exit(e, ray, t).min(t1);
            let (sub, at) = self.universe(e);
            if visit(sub, at, t, end) {
                return;
            }
            t = end.max(t + self.nudge);
        }
    }
}

impl Prepared {
    /// The first opaque surface inside filled zone `z` (number `zi`) along
    /// the ray within `(tmin, limit)`: a hit of the region there, its
    /// surface's normal carried in the bound ([`Bound::nested`]), or, where
    /// the ray enters the filled region already inside opaque content, the
    /// filled region's own surface.
    pub(crate) fn fill_hit(
        &self,
        z: &PreparedZone,
        zi: u32,
        ray: &Ray,
        tmin: f64,
        limit: f64,
        s: &mut Scratch,
    ) -> Option<Hit> {
        if !self.zone_spans(z, ray, tmin, limit, s) {
            return None;
        }
        let spans = s.spare_copy();
        let fill = &self.fills[self.region_fills[z.region as usize] as usize];
        let mut found = None;
        for sp in &spans {
            let (t0, t1) = (sp.a.t.max(tmin), sp.b.t.min(limit));
            if t0 >= limit {
                break;
            }
            // Elements that hold no universe are the filled region's own
            // material, seen where the ray enters them when it is opaque.
            let own = Some(z.region).filter(|&r| self.is_opaque(r as usize));
            if let Some(h) = self.content_hit(fill, own, ray, t0, t1, s) {
                found = Some(if h.inside && sp.a.t > tmin && h.t <= t0 {
                    // Entering the filled region into opaque content: its
                    // own surface is what is seen.
                    Hit {
                        t: sp.a.t,
                        region: h.region,
                        bound: sp.a,
                        inside: false,
                        zone: zi,
                    }
                } else {
                    Hit { zone: zi, ..h }
                });
                break;
            }
        }
        s.give_back(spans);
        found
    }

    /// The first opaque hit of what `fill` holds along the ray within
    /// `(t0, t1)`, its normal in this frame; a lattice element that holds
    /// no universe is a hit of region `own` where the ray enters it (its
    /// face's normal not kept: it is shaded as facing the ray), when given.
    fn content_hit(
        &self,
        fill: &FillTracer,
        own: Option<u32>,
        ray: &Ray,
        t0: f64,
        t1: f64,
        s: &mut Scratch,
    ) -> Option<Hit> {
        match fill {
            FillTracer::Nothing => None,
            FillTracer::Universe { sub, moved } => {
                self.sub_hit(*sub, moved, DVec3::ZERO, ray, t0, t1, s)
            }
            FillTracer::Lattice { moved, walk } => {
                let inside = moved.ray(ray);
                let frame = |t: f64| t * moved.scale;
                let mut found = None;
                walk.for_each_element(&inside, frame(t0), frame(t1), |sub, at, a, b| {
                    if sub == NOTHING {
                        let Some(region) = own else {
                            return false;
                        };
                        let t = a / moved.scale;
                        found = Some(Hit {
                            t,
                            region,
                            bound: Bound::new(t, u32::MAX, 0),
                            inside: t <= t0,
                            zone: u32::MAX,
                        });
                        return true;
                    }
                    found = self.sub_hit(sub, moved, at, ray, a / moved.scale, b / moved.scale, s);
                    found.is_some()
                });
                found
            }
        }
    }

    /// The first opaque hit in sub-universe `sub`, moved by `moved` then
    /// with its origin at `at` (in the moved frame), within `(t0, t1)` of
    /// the ray (this frame).
    #[allow(clippy::too_many_arguments)]
    fn sub_hit(
        &self,
        sub: u32,
        moved: &Moved,
        at: DVec3,
        ray: &Ray,
        t0: f64,
        t1: f64,
        s: &mut Scratch,
    ) -> Option<Hit> {
        let p = &self.subs[sub as usize];
        let mut inner_ray = moved.ray(ray);
        inner_ray.origin -= at;
        let mut inner = s.take_sub(sub as usize, p);
        let found = p
            .first_hit(&inner_ray, t0 * moved.scale, t1 * moved.scale, &mut inner)
            .map(|h| {
                let normal = moved.normal_out(p.normal(&h, &inner_ray));
                let t = h.t / moved.scale;
                Hit {
                    t,
                    region: h.region,
                    bound: Bound::nested(t, normal),
                    inside: h.inside,
                    zone: h.zone,
                }
            });
        s.put_sub(sub as usize, inner);
        found
    }

    /// The partitions inside filled zone `z` along the ray within
    /// `(tmin, tmax)`, each added to `out` by [`insert_by_entry`]: what
    /// the fill holds, cut to where the ray is inside the zone.
    pub(crate) fn fill_partitions(
        &self,
        z: &PreparedZone,
        ray: &Ray,
        tmin: f64,
        tmax: f64,
        s: &mut Scratch,
        out: &mut Vec<Partition>,
    ) {
        if !self.zone_spans(z, ray, tmin, tmax, s) {
            return;
        }
        let spans = s.spare_copy();
        let fill = &self.fills[self.region_fills[z.region as usize] as usize];
        for sp in &spans {
            match fill {
                FillTracer::Nothing => {}
                FillTracer::Universe { sub, moved } => {
                    self.sub_partitions(*sub, moved, DVec3::ZERO, ray, (sp.a, sp.b), s, out)
                }
                FillTracer::Lattice { moved, walk } => {
                    let inside = moved.ray(ray);
                    let (a, b) = (sp.a.t.max(tmin), sp.b.t.min(tmax));
                    walk.for_each_element(
                        &inside,
                        a * moved.scale,
                        b * moved.scale,
                        |sub, at, ea, eb| {
                            let (ea, eb) = (ea / moved.scale, eb / moved.scale);
                            let lo = if ea <= sp.a.t {
                                sp.a
                            } else {
                                Bound::new(ea, u32::MAX, 0)
                            };
                            let hi = if eb >= sp.b.t {
                                sp.b
                            } else {
                                Bound::new(eb, u32::MAX, 0)
                            };
                            if sub == NOTHING {
                                // The lattice region's own material (not
                                // the slivers where the walk steps over a
                                // face).
                                if hi.t - lo.t > self.tol {
                                    let (region, span) = (z.region, Span { a: lo, b: hi });
                                    insert_by_entry(out, Partition { region, span });
                                }
                            } else {
                                self.sub_partitions(sub, moved, at, ray, (lo, hi), s, out);
                            }
                            false
                        },
                    );
                }
            }
        }
        s.give_back(spans);
    }

    /// The partitions of sub-universe `sub` (moved, origin at `at`) cut to
    /// `(lo, hi)` of the ray, their bodies numbered as this universe
    /// numbers them.
    #[allow(clippy::too_many_arguments)]
    fn sub_partitions(
        &self,
        sub: u32,
        moved: &Moved,
        at: DVec3,
        ray: &Ray,
        (lo, hi): (Bound, Bound),
        s: &mut Scratch,
        out: &mut Vec<Partition>,
    ) {
        let p = &self.subs[sub as usize];
        let mut inner_ray = moved.ray(ray);
        inner_ray.origin -= at;
        let mut inner = s.take_sub(sub as usize, p);
        let mut parts: Vec<Partition> = Vec::new();
        p.partitions(
            &inner_ray,
            lo.t * moved.scale,
            hi.t * moved.scale,
            &mut inner,
            &mut parts,
        );
        s.put_sub(sub as usize, inner);
        let ours = |b: Bound| -> Bound {
            let t = b.t / moved.scale;
            if b.body >= Bound::NESTED {
                return Bound::from_parts(t, b.body, b.face_flip());
            }
            let body = self.places[p.body_index(b.body)];
            Bound::from_parts(t, body, b.face_flip())
        };
        for q in parts {
            let a = if q.span.a.t * (1.0 / moved.scale) <= lo.t {
                lo
            } else {
                ours(q.span.a)
            };
            let b = if q.span.b.t * (1.0 / moved.scale) >= hi.t {
                hi
            } else {
                ours(q.span.b)
            };
            if b.t > a.t {
                let (region, span) = (q.region, Span { a, b });
                insert_by_entry(out, Partition { region, span });
            }
        }
    }

    /// The regions whose content holds point `p`, innermost last: a point
    /// in a filled region is also in the region of the fill that holds it.
    pub fn regions_at(&self, p: DVec3) -> Vec<u32> {
        let mut out = Vec::new();
        for z in &self.zones {
            if !z.bounds.contains(p) || !self.zone_contains(z, p) {
                continue;
            }
            out.push(z.region);
            if z.is_filled() {
                let fill = &self.fills[self.region_fills[z.region as usize] as usize];
                out.extend(self.content_at(fill, p));
            }
        }
        out.sort_unstable();
        out.dedup();
        out
    }

    /// The regions inside `fill` that hold `p` (this frame).
    fn content_at(&self, fill: &FillTracer, p: DVec3) -> Vec<u32> {
        match fill {
            FillTracer::Nothing => Vec::new(),
            FillTracer::Universe { sub, moved } => {
                self.subs[*sub as usize].regions_at(moved.inside_from_region.transform_point3(p))
            }
            FillTracer::Lattice { moved, walk } => {
                let q = moved.inside_from_region.transform_point3(p);
                let (sub, at) = walk.universe(walk.element_at(q));
                if sub == NOTHING {
                    Vec::new()
                } else {
                    self.subs[sub as usize].regions_at(q - at)
                }
            }
        }
    }
}
