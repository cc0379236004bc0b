//! Shadow rays for a renderer, behind one question: is the light `li`
//! blocked for the hit `h` of this tile?
//!
//! Four ways of answering hide behind [`Occluders::occluded`]: toward a
//! parallel light, the tile's shadow rays were all tested beforehand in
//! packets through the light's buffer ([`Occluders::prepare_tile`]);
//! toward a point light, a tile whose hits and the light fit in a box
//! holding few zones tests those ([`Prepared::occluded_in`]), else the
//! light's buffer answers ([`Prepared::occluded_by`]); without buffers
//! (a single shaded point) the whole hierarchy is searched
//! ([`Prepared::occluded`]). Every way gives the same answer.

use crate::hit::{Hit, Scratch};
use crate::lightbuf::{LightBuffer, PointBuffer};
use crate::prepare::Prepared;
use sv_math::{Aabb, DVec3, Ray};

/// Above this many zones in the box of a tile's hit points and a point
/// light, the tile's shadow rays toward it ask the light's buffer instead.
/// The tile's zones are in no order, so a ray that reaches the light tests
/// them all; the buffer's cell lists are short and nearest the light first.
/// With 64, a crowd of spheres each minus a cylinder under a lamp ran 17 %
/// slower (BENCHMARKS.md, eleventh round); with none, the helicopter 11 %.
const MAX_SHADOW_ZONES: usize = 8;

/// Where a light is, as its shadow rays need it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightAt {
    /// A parallel light, shining along `dir` (not necessarily unit).
    Parallel {
        /// The direction the light travels.
        dir: DVec3,
    },
    /// A point light at `pos`.
    Point {
        /// Its position.
        pos: DVec3,
    },
}

/// A light's buffer of the zones its shadow rays may meet.
#[derive(Debug)]
enum Buffer {
    /// A parallel light's.
    Parallel(LightBuffer),
    /// A point light's.
    Point(PointBuffer),
}

/// The shadow buffers of a set of lights, one per light, made once for a
/// prepared geometry and kept while the lights stay where they are.
#[derive(Debug)]
pub struct ShadowBuffers {
    lights: Vec<LightAt>,
    buffers: Vec<Buffer>,
}

impl ShadowBuffers {
    /// The buffers of `lights` over the opaque zones of `p`.
    pub fn new(p: &Prepared, lights: &[LightAt]) -> ShadowBuffers {
        let buffers = lights
            .iter()
            .map(|l| match *l {
                LightAt::Parallel { dir } => {
                    Buffer::Parallel(LightBuffer::new(p, -dir.normalize()))
                }
                LightAt::Point { pos } => Buffer::Point(PointBuffer::new(p, pos)),
            })
            .collect();
        ShadowBuffers {
            lights: lights.to_vec(),
            buffers,
        }
    }

    /// The lights the buffers were made for.
    pub fn lights(&self) -> &[LightAt] {
        &self.lights
    }
}

/// One worker's shadow queries: the buffers to ask, and what the tile at
/// hand has found out beforehand. Made once per worker and render, and
/// reused from tile to tile.
#[derive(Default)]
pub struct Occluders<'a> {
    buffers: &'a [Buffer],
    /// Per light, the unit vector toward a parallel light (unused for a
    /// point light), as its buffer casts its rays: normalised once, not for
    /// every point shaded.
    toward: Vec<DVec3>,
    /// Per light with a buffer, the zone that blocked the last shadow ray.
    last: Vec<Option<u32>>,
    /// Per point light, the zones the tile's shadow rays may meet, when
    /// they are few.
    sets: Vec<Option<Vec<u32>>>,
    /// Per parallel light with a buffer, whether the shadow ray of each of
    /// the tile's hits is blocked, tested for the whole tile beforehand in
    /// packets (empty for other lights).
    blocked: Vec<Vec<bool>>,
    /// The shadow rays toward a parallel light to be tested in packets:
    /// their origins and skipped zones, the hit each belongs to, and the
    /// answers.
    from: Vec<(DVec3, Option<u32>)>,
    which: Vec<u32>,
    answers: Vec<bool>,
}

impl<'a> Occluders<'a> {
    /// A worker's queries toward `lights`, through `buffers` (made for the
    /// same lights) or, without them, the whole hierarchy.
    pub fn new(lights: &[LightAt], buffers: Option<&'a ShadowBuffers>) -> Occluders<'a> {
        let buffers = buffers.map_or(&[][..], |b| &b.buffers[..]);
        let toward = lights
            .iter()
            .enumerate()
            .map(|(i, l)| match (l, buffers.get(i)) {
                (_, Some(Buffer::Parallel(lb))) => lb.toward(),
                (LightAt::Parallel { dir }, _) => -dir.normalize(),
                (LightAt::Point { .. }, _) => DVec3::ZERO,
            })
            .collect();
        Occluders {
            buffers,
            toward,
            last: vec![None; lights.len()],
            sets: vec![None; lights.len()],
            blocked: vec![Vec::new(); lights.len()],
            ..Occluders::default()
        }
    }

    /// The unit vector toward parallel light `li`, as its shadow rays run
    /// (so that the shading's `cos θ` and the packets' agree).
    #[inline(always)]
    pub fn toward(&self, li: usize) -> Option<DVec3> {
        self.toward.get(li).copied()
    }

    /// Before a tile is shaded: its shadow rays toward each parallel light
    /// tested in packets, and per point light the zones the tile's shadow
    /// rays may meet (those in the box of the hit points and the light).
    /// `hits`, `normals` and `rays` are the tile's, in the order the
    /// shading will name them.
    pub fn prepare_tile(
        &mut self,
        p: &Prepared,
        lights: &[LightAt],
        (hits, normals, rays): (&[(u32, Hit)], &[DVec3], &[Ray]),
        s: &mut Scratch,
    ) {
        if hits.is_empty() {
            return;
        }
        self.shadows_toward_suns(p, hits, normals, rays, s);
        if !lights.iter().any(|l| matches!(l, LightAt::Point { .. })) {
            return;
        }
        let points = Aabb::from_points(hits.iter().zip(rays).map(|((_, h), ray)| ray.at(h.t)));
        for (l, set) in lights.iter().zip(self.sets.iter_mut()) {
            if let LightAt::Point { pos } = *l {
                let zones = set.get_or_insert_with(Vec::new);
                if !p.zones_in_box(&points.including(pos), MAX_SHADOW_ZONES, zones) {
                    *set = None;
                }
            }
        }
    }

    /// Test the shadow rays of the tile's `hits` (with their `rays`) toward
    /// each parallel light with a buffer, in packets, into `blocked` (a hit
    /// facing away from the light has no shadow ray; its answer is never
    /// read).
    fn shadows_toward_suns(
        &mut self,
        p: &Prepared,
        hits: &[(u32, Hit)],
        normals: &[DVec3],
        rays: &[Ray],
        s: &mut Scratch,
    ) {
        let eps = 10.0 * p.tolerance();
        for (li, blocked) in self.blocked.iter_mut().enumerate() {
            blocked.clear();
            let Some(Buffer::Parallel(lb)) = self.buffers.get(li) else {
                continue;
            };
            self.from.clear();
            self.which.clear();
            for (h, (((_, hit), n), ray)) in hits.iter().zip(normals).zip(rays).enumerate() {
                // As the shading: no shadow ray where `cos θ <= 0` (a
                // normal that is not a number does get one there).
                let cos = n.dot(lb.toward());
                if cos > 0.0 || cos.is_nan() {
                    self.from.push((ray.at(hit.t), p.shadow_skip(hit)));
                    self.which.push(h as u32);
                }
            }
            p.occluded_toward(
                lb,
                &self.from,
                eps,
                &mut self.last[li],
                s,
                &mut self.answers,
            );
            blocked.resize(hits.len(), false);
            for (&h, &a) in self.which.iter().zip(self.answers.iter()) {
                blocked[h as usize] = a;
            }
        }
    }

    /// True when an opaque region blocks light `li` from `hit` (the tile's
    /// hit number `h`, at `point`): the shadow ray along unit `to_light`
    /// up to `dist` (infinite for a parallel light). Inlined into the
    /// shading: called through a function it costs some scenes a few per
    /// cent.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub fn occluded(
        &mut self,
        p: &Prepared,
        li: usize,
        (h, hit): (usize, &Hit),
        point: DVec3,
        to_light: DVec3,
        dist: f64,
        s: &mut Scratch,
    ) -> bool {
        // A parallel light's buffer has answered for the tile's hits
        // (`prepare_tile`); the rest are tested here.
        if let Some(&b) = self.blocked.get(li).and_then(|b| b.get(h)) {
            return b;
        }
        let eps = 10.0 * p.tolerance();
        let skip = p.shadow_skip(hit);
        let shadow = Ray::new(point, to_light);
        if let Some(zones) = self.sets.get(li).and_then(Option::as_ref) {
            p.occluded_in(zones, skip, &shadow, eps, dist, s)
        } else if let Some(Buffer::Point(pb)) = self.buffers.get(li) {
            p.occluded_by(pb, &shadow, eps, dist, skip, &mut self.last[li], s)
        } else {
            p.occluded(&shadow, eps, dist, skip, s)
        }
    }
}
