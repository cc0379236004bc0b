//! Ray casting, shading and tiles.
//!
//! Shading is the paper's, per channel:
//! `I = c ⊙ (Σ_lights I₀ · k · cosθ · f(R) · light colour + A₀)`,
//! where `c` is the region colour (white by default, giving exactly
//! `I = I₀ k cosθ + A₀`), `f(R) = R⁻ⁿ` for point lights and 1 for parallel
//! ones, and a light contributes nothing where `cosθ < 0` or, with shadows
//! on, where an opaque region blocks it. Values are linear.
//!
//! Every pixel is computed independently from its own rays, so a picture is
//! bit-for-bit the same whatever the number of threads.
#![warn(missing_docs)]

mod frame;
mod view;

pub use frame::Frame;
pub use view::{default_camera, default_lights, frame_bounds};

use crossbeam_utils::CachePadded;
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use sv_trace::{
    by_entry, Frustum, Hit, LightBuffer, PointBuffer, PrepareError, PrepareOptions, Prepared,
    RasterExtent, Scratch, Tile, Warning,
};

/// Above this many zones in the box of a tile's hit points and a point
/// light, the tile's shadow rays toward it ask the light's buffer instead.
/// The tile's zones are in no order, so a ray that reaches the light tests
/// them all; the buffer's cell lists are short and nearest the light first.
/// With 64, a crowd of spheres each minus a cylinder under a lamp ran 17 %
/// slower (BENCHMARKS.md, eleventh round); with none, the helicopter 11 %.
const MAX_SHADOW_ZONES: usize = 8;

/// A worker's memory, reused from tile to tile.
struct Workspace<'a> {
    /// Ray scratch.
    s: Scratch,
    /// The zones of the band's tiles.
    lists: BandLists,
    /// The tile's zones with their entry bounds, sorted.
    sorted: Vec<(f64, u32)>,
    /// The raster positions of the tile's primary rays, and the rays.
    pts: Vec<[f64; 2]>,
    rays: Vec<Ray>,
    /// The rays of the tile's hits, in the order of `hits`.
    hit_rays: Vec<Ray>,
    /// The tile's primary rays that hit: their sample number in the tile
    /// (an index into `rays`) and the hit, in as many first entries as
    /// there are hits. Rays that miss are not kept; the entries past the
    /// hits are slots kept for the next tile.
    hits: Vec<(u32, Hit)>,
    /// The surface normal at each hit, in the order of `hits`.
    normals: Vec<DVec3>,
    /// The zones the tile's shadow rays may meet.
    shadow: Occluders<'a>,
    /// The shadow rays toward a parallel light to be tested in packets:
    /// their origins and skipped zones, the hit each belongs to, and the
    /// answers.
    from: Vec<(DVec3, Option<u32>)>,
    which: Vec<u32>,
    answers: Vec<bool>,
}

impl<'a> Workspace<'a> {
    fn new(p: &Prepared, lights: &[Light], buffers: &'a [Buffer]) -> Workspace<'a> {
        // The direction the light's buffer casts its shadow rays along, so
        // that the shading's `cos θ` and the packets' agree.
        let toward = lights
            .iter()
            .enumerate()
            .map(|(i, l)| match (l.kind, buffers.get(i)) {
                (_, Some(Buffer::Parallel(lb))) => lb.toward(),
                (LightKind::Parallel { dir }, _) => -dir.normalize(),
                (LightKind::Point { .. }, _) => DVec3::ZERO,
            })
            .collect();
        let lights = lights.len();
        Workspace {
            s: Scratch::new(p),
            lists: BandLists::default(),
            sorted: Vec::new(),
            pts: Vec::new(),
            rays: Vec::new(),
            hits: Vec::new(),
            hit_rays: Vec::new(),
            normals: Vec::new(),
            shadow: Occluders {
                buffers,
                toward,
                last: vec![None; lights],
                sets: vec![None; lights],
                blocked: vec![Vec::new(); lights],
            },
            from: Vec::new(),
            which: Vec::new(),
            answers: Vec::new(),
        }
    }
}

/// Where the zones may be seen on a frame's raster ([`Renderer::zone_bins`]),
/// each with a lower bound of where the camera's rays can enter it
/// ([`Prepared::entry_bound`], or [`Prepared::place_proxy`]'s for a bounded
/// zone).
struct Bins {
    /// The unbounded opaque zones, which every tile lists.
    lead: Vec<(f64, u32)>,
    /// Per band of tiles, its bounded zones.
    bands: Vec<Vec<Binned>>,
}

/// The tile (or band) of raster coordinate `v`, the last one being `last`.
fn tile_of(v: f64, last: usize) -> usize {
    // Truncation is the floor once the negatives (and not-a-number) are
    // 0: without SSE4.1 a floor is a call.
    ((v / TILE as f64).max(0.0) as usize).min(last)
}

/// A zone in a band: its entry bound and number, and the first and last
/// columns of tiles it spans ([`ANYWHERE`] as the last when it may be seen
/// anywhere).
#[derive(Clone, Copy)]
struct Binned {
    near: f32,
    zi: u32,
    c0: u32,
    c1: u32,
}

/// The last column of a zone that may be seen anywhere on the raster.
const ANYWHERE: u32 = u32::MAX;

/// The zones each tile of a band (a row of tiles) may meet.
#[derive(Default)]
struct BandLists {
    /// The tiles' frusta, made for zones seen anywhere.
    frusta: Vec<Frustum>,
    /// Per tile, its zones with their entry bounds, and whether it has more
    /// than [`MAX_TILE_ZONES`] (its list is then incomplete, and its rays
    /// walk the hierarchy).
    tiles: Vec<Vec<(f64, u32)>>,
    over: Vec<bool>,
}

impl BandLists {
    /// The list of tile `t`, unless the band has no such tile or the tile
    /// is crowded (its list is then never read).
    fn list(&self, t: usize) -> Option<&[(f64, u32)]> {
        (t < self.tiles.len() && !self.over[t]).then(|| &self.tiles[t][..])
    }

    /// Before tile `t`'s rays: the zones of tile `t + 2` and the bodies of
    /// tile `t + 1` asked for ([`Prepared::prefetch_zones`] and
    /// [`Prepared::prefetch_bodies`]), so that each tile finds them
    /// fetched; at the band's start, those of tiles 0 and 1 too.
    fn prefetch(&self, p: &Prepared, t: usize) {
        let zones = |t| self.list(t).map(|l| p.prefetch_zones(l));
        let bodies = |t| self.list(t).map(|l| p.prefetch_bodies(l));
        if t == 0 {
            zones(0);
            zones(1);
            bodies(0);
        }
        bodies(t + 1);
        zones(t + 2);
    }
}

/// Where shadow rays look for occluders, per light: a parallel light's
/// buffer; for a point light, the zones that a tile's shadow rays may
/// meet, else its buffer; else (no entry) the whole hierarchy.
#[derive(Default)]
struct Occluders<'a> {
    buffers: &'a [Buffer],
    /// Per light, the unit vector toward a parallel light (unused for a
    /// point light): normalised once, not for every point shaded.
    toward: Vec<DVec3>,
    /// Per light with a buffer, the zone that blocked the last shadow ray.
    last: Vec<Option<u32>>,
    sets: Vec<Option<Vec<u32>>>,
    /// Per parallel light with a buffer, whether the shadow ray of each of
    /// the tile's hits is blocked, tested for the whole tile beforehand in
    /// packets ([`Renderer::shadows_toward_suns`]; empty for other lights).
    blocked: Vec<Vec<bool>>,
}

/// How far (pixels) a zone's rectangle on the raster is widened each way
/// against rounding, which is some 1e-9 of a pixel.
const PAD: f64 = 0.01;
/// Tiles are TILE×TILE pixels.
const TILE: usize = 16;
/// Above this many candidate zones a tile's rays walk the hierarchy. A ray
/// that meets nothing tests every zone of its tile's list, so the list must
/// stay short; but walking the hierarchy costs a ray that crosses a crowd
/// of small bodies more than testing a few hundred listed boxes in turn,
/// eight rays at a time. 100,000 small spheres at constant coverage cost
/// 72, 64, 63 and 67 ns a ray with 256, 512, 1024 and 2048; seen from far
/// off (1 % of the picture on spheres), 17–19, 20–22 and 23 ns with 256,
/// 1024 and 2048 (BENCHMARKS.md, thirteenth round).
const MAX_TILE_ZONES: usize = 512;
use sv_math::{Aabb, DVec3, Ray};
use sv_scene::{Background, Camera, Light, LightKind, RayGen, Scene};

/// Picture settings.
#[derive(Clone, Debug)]
pub struct Settings {
    /// Raster width.
    pub width: u32,
    /// Raster height.
    pub height: u32,
    /// Cast shadows.
    pub shadows: bool,
    /// Supersampling: `samples × samples` rays per pixel (1 = none).
    pub samples: u32,
    /// Fill the region, depth and normal images.
    pub aovs: bool,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            width: 960,
            height: 720,
            shadows: true,
            samples: 1,
            aovs: false,
        }
    }
}

/// A scene ready to render: prepared geometry, camera, lights and looks.
#[derive(Clone, Debug)]
pub struct Renderer {
    /// The prepared geometry (fixed for the renderer's life: the light
    /// buffers kept between renders are made from it).
    prepared: Prepared,
    /// Camera in use (the scene's or the default framing).
    pub camera: Camera,
    /// Lights in use (the scene's or the default light).
    pub lights: Vec<Light>,
    ambient: f64,
    background: [f64; 3],
    looks: Vec<(f64, [f64; 3])>,
    buffers: BufferCache,
}

/// The light buffers of the last render with shadows, with the lights
/// they were made for. A render whose lights shine the same ways from the
/// same places reuses them: the geometry cannot change under a
/// [`Renderer`], so only the lights need comparing.
#[derive(Clone, Debug, Default)]
struct BufferCache(Arc<Mutex<Option<LightBuffers>>>);

/// Light buffers and the lights, per light, that they were made for.
#[derive(Debug)]
struct LightBuffers {
    kinds: Vec<LightKind>,
    buffers: Arc<[Buffer]>,
}

/// A light's buffer of the zones its shadow rays may meet.
#[derive(Debug)]
enum Buffer {
    /// A parallel light's.
    Parallel(LightBuffer),
    /// A point light's.
    Point(PointBuffer),
}

impl Renderer {
    /// Prepare `scene`. A scene without camera is framed from azimuth 35°,
    /// elevation 25°; one without lights gets a light over the viewer's
    /// shoulder.
    pub fn new(scene: &Scene, aspect: f64) -> Result<(Renderer, Vec<Warning>), PrepareError> {
        Renderer::with_options(scene, aspect, PrepareOptions::default())
    }

    /// As [`Renderer::new`], with explicit prepare options (the region
    /// opacity is always taken from the scene).
    pub fn with_options(
        scene: &Scene,
        aspect: f64,
        mut opts: PrepareOptions,
    ) -> Result<(Renderer, Vec<Warning>), PrepareError> {
        opts.opaque = Some(scene.regions.iter().map(|r| !r.transparent).collect());
        let (prepared, warnings) = Prepared::new(&scene.geometry, &opts)?;
        let camera = scene
            .camera
            .unwrap_or_else(|| default_camera(&prepared, aspect, 35.0, 25.0, false));
        let lights = if scene.lights.is_empty() {
            default_lights(&camera)
        } else {
            scene.lights.clone()
        };
        let Background::Colour(background) = scene.background;
        let looks = scene
            .regions
            .iter()
            .map(|r| (r.k, r.colour.unwrap_or([1.0; 3])))
            .collect();
        Ok((
            Renderer {
                prepared,
                camera,
                lights,
                ambient: scene.ambient,
                background,
                looks,
                buffers: BufferCache::default(),
            },
            warnings,
        ))
    }

    /// The prepared geometry.
    pub fn prepared(&self) -> &Prepared {
        &self.prepared
    }

    /// Set the ambient intensity A₀.
    pub fn set_ambient(&mut self, a: f64) {
        self.ambient = a;
    }

    /// Replace the camera.
    pub fn with_camera(mut self, camera: Camera) -> Renderer {
        self.camera = camera;
        self
    }

    /// Intensity (linear RGB) of the surface at `hit`.
    pub fn shade(&self, ray: &Ray, hit: &Hit, shadows: bool, s: &mut Scratch) -> [f64; 3] {
        let n = self.prepared.normal(hit, ray);
        self.shade_with(ray, hit, 0, n, shadows, &mut Occluders::default(), s)
    }

    /// The lights' buffers: those of the last render when its lights were
    /// the same, else new ones (kept for the next render).
    fn light_buffers(&self) -> Arc<[Buffer]> {
        let kinds: Vec<LightKind> = self.lights.iter().map(|l| l.kind).collect();
        let mut kept = self.buffers.0.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(k) = kept.as_ref().filter(|k| k.kinds == kinds) {
            return k.buffers.clone();
        }
        let buffers: Arc<[Buffer]> = kinds
            .iter()
            .map(|k| match *k {
                LightKind::Parallel { dir } => {
                    Buffer::Parallel(LightBuffer::new(&self.prepared, -dir.normalize()))
                }
                LightKind::Point { pos, .. } => {
                    Buffer::Point(PointBuffer::new(&self.prepared, pos))
                }
            })
            .collect();
        *kept = Some(LightBuffers {
            kinds,
            buffers: buffers.clone(),
        });
        buffers
    }

    /// Where the bounded opaque zones may be seen on the raster of `gen`
    /// (`w`×`h` pixels): for each band of tiles, the zones whose rectangle
    /// ([`Prepared::place_proxy`]) reaches it, with the columns of tiles it
    /// spans, padded for rounding. Zones seen nowhere on the raster are
    /// left out; zones that may be seen anywhere are in every band. Each
    /// comes with its entry bound for the rays of `gen`, found here once
    /// rather than in every tile that lists it, where reading the zone's
    /// bounds again missed the cache; each band is in the order of
    /// [`Prepared::by_distance`]. Made once a frame, the proxies placed in
    /// parallel: a walk of the hierarchy per tile took a fifth of the time
    /// of a frame of 10,000 spheres, and a walk per band with each zone's
    /// tiles' frusta tested a third of that of 100,000. Of a 32 ms frame of
    /// 100,000 small spheres this takes some 6 ms: placing the proxies 4, the
    /// bands and their radix sorts 1 each (a comparison sort took 3.5).
    fn zone_bins(&self, gen: &RayGen, w: usize, h: usize) -> Bins {
        let p = &self.prepared;
        // The eye, and the direction of orthographic rays.
        let (eye, parallel) = (gen.eye, gen.ortho.then_some(gen.forward));
        let (wf, hf) = (w as f64, h as f64);
        let (last_row, last_col) = (h.div_ceil(TILE) - 1, w.div_ceil(TILE) - 1);
        // Each zone seen, with the bands and columns of tiles it reaches, in
        // the order of the zones (their data is then read in turn).
        let seen: Vec<Option<(Binned, u32, u32)>> = (0..p.raster_proxy_count())
            .into_par_iter()
            .with_min_len(1024)
            .map(|k| {
                let (zi, seen, near) = p.place_proxy(k, gen);
                let rect = match seen {
                    RasterExtent::Nowhere => return None,
                    RasterExtent::Within(r) if r.iter().all(|v| v.is_finite()) => r,
                    _ => {
                        let b = Binned {
                            near,
                            zi,
                            c0: 0,
                            c1: ANYWHERE,
                        };
                        return Some((b, 0, last_row as u32));
                    }
                };
                let [x0, y0, x1, y1] = [rect[0] - PAD, rect[1] - PAD, rect[2] + PAD, rect[3] + PAD];
                if x1 < 0.0 || y1 < 0.0 || x0 > wf || y0 > hf || x0 > x1 || y0 > y1 {
                    return None;
                }
                let (c0, c1) = (tile_of(x0, last_col), tile_of(x1, last_col));
                let b = Binned {
                    near,
                    zi,
                    c0: c0 as u32,
                    c1: c1 as u32,
                };
                Some((
                    b,
                    tile_of(y0, last_row) as u32,
                    tile_of(y1, last_row) as u32,
                ))
            })
            .collect();
        // Each band's zones in one block of its own size, in the order of
        // the zones.
        let mut count = vec![0usize; last_row + 1];
        for &(_, r0, r1) in seen.iter().flatten() {
            count[r0 as usize..=r1 as usize]
                .iter_mut()
                .for_each(|c| *c += 1);
        }
        let mut bands: Vec<Vec<Binned>> = count.iter().map(|&c| Vec::with_capacity(c)).collect();
        for &(b, r0, r1) in seen.iter().flatten() {
            bands[r0 as usize..=r1 as usize]
                .iter_mut()
                .for_each(|band| band.push(b));
        }
        // Each band in the order of `Prepared::by_distance`, so that its
        // tiles' lists come out in it: by entry bound, and (the sort being
        // stable) ties in the order of the zones.
        bands
            .par_iter_mut()
            .for_each(|b| radsort::sort_by_key(b, |b| b.near));
        let mut lead: Vec<(f64, u32)> = p
            .unbounded_opaque()
            .iter()
            .map(|&zi| (p.entry_bound(zi, eye, parallel), zi))
            .collect();
        lead.sort_unstable_by(by_entry);
        Bins { lead, bands }
    }

    /// The zones of the tiles of the band of raster rows `y0..y1`, from its
    /// bin of [`Renderer::zone_bins`] and the unbounded zones, `lead`, which
    /// every list holds: each zone in the tiles its columns reach, with its
    /// entry bound, in the order of [`Prepared::by_distance`] (the bin's and
    /// `lead`'s, merged). A zone that may be seen
    /// anywhere (it reaches behind the eye) goes only in the tiles whose
    /// frustum it may meet ([`Prepared::frustum_keeps`]). A tile with more
    /// than [`MAX_TILE_ZONES`] is marked (its list is then incomplete).
    fn band_lists(
        &self,
        lead: &[(f64, u32)],
        bin: &[Binned],
        gen: &RayGen,
        w: usize,
        (y0, y1): (usize, usize),
        l: &mut BandLists,
    ) {
        let n = w.div_ceil(TILE);
        l.tiles.resize_with(n, Vec::new);
        l.over.clear();
        l.over.resize(n, false);
        l.frusta.clear();
        l.tiles.iter_mut().for_each(Vec::clear);
        // Into every tile not yet full.
        let everywhere = |l: &mut BandLists, e: (f64, u32)| {
            for (t, over) in l.tiles.iter_mut().zip(&mut l.over) {
                if !*over {
                    t.push(e);
                    *over = t.len() > MAX_TILE_ZONES;
                }
            }
        };
        let mut lead = lead.iter().copied().peekable();
        for &Binned { near, zi, c0, c1 } in bin {
            let near = f64::from(near);
            while let Some(e) = lead.next_if(|e| by_entry(e, &(near, zi)).is_lt()) {
                everywhere(l, e);
            }
            let anywhere = c1 == ANYWHERE;
            if anywhere && l.frusta.is_empty() {
                let ray = |x: usize, y: usize| gen.ray(x as f64, y as f64);
                l.frusta.extend((0..n).map(|t| {
                    let (x0, x1) = (t * TILE, ((t + 1) * TILE).min(w));
                    Frustum::from_corners([ray(x0, y0), ray(x1, y0), ray(x1, y1), ray(x0, y1)])
                }));
            }
            for t in c0 as usize..=(c1 as usize).min(n - 1) {
                if l.over[t] || (anywhere && !self.prepared.frustum_keeps(zi, &l.frusta[t])) {
                    continue;
                }
                l.tiles[t].push((near, zi));
                l.over[t] = l.tiles[t].len() > MAX_TILE_ZONES;
            }
        }
        lead.for_each(|e| everywhere(l, e));
    }

    /// Test the shadow rays of the tile's `hits` (with their `rays`) toward
    /// each parallel light with a buffer, in packets, into `occ.blocked` (a
    /// hit facing away from the light has no shadow ray; its answer is
    /// never read).
    #[allow(clippy::too_many_arguments)]
    fn shadows_toward_suns(
        &self,
        hits: &[(u32, Hit)],
        normals: &[DVec3],
        rays: &[Ray],
        occ: &mut Occluders<'_>,
        from: &mut Vec<(DVec3, Option<u32>)>,
        which: &mut Vec<u32>,
        answers: &mut Vec<bool>,
        s: &mut Scratch,
    ) {
        let eps = 10.0 * self.prepared.tolerance();
        for (li, blocked) in occ.blocked.iter_mut().enumerate() {
            blocked.clear();
            let Some(Buffer::Parallel(lb)) = occ.buffers.get(li) else {
                continue;
            };
            from.clear();
            which.clear();
            for (h, (((_, hit), n), ray)) in hits.iter().zip(normals).zip(rays).enumerate() {
                // As `shade_with`: no shadow ray where `cos θ <= 0` (a
                // normal that is not a number does get one there).
                let cos = n.dot(lb.toward());
                if cos > 0.0 || cos.is_nan() {
                    from.push((ray.at(hit.t), self.prepared.shadow_skip(hit)));
                    which.push(h as u32);
                }
            }
            self.prepared
                .occluded_toward(lb, from, eps, &mut occ.last[li], s, answers);
            blocked.resize(hits.len(), false);
            for (&h, &a) in which.iter().zip(answers.iter()) {
                blocked[h as usize] = a;
            }
        }
    }

    /// [`Renderer::shade`], with the occluders that shadow rays may meet.
    /// Inlined into both pixel loops of the tile: called through a function
    /// it costs some scenes a few per cent.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn shade_with(
        &self,
        ray: &Ray,
        hit: &Hit,
        h: usize,
        n: DVec3,
        shadows: bool,
        occ: &mut Occluders<'_>,
        s: &mut Scratch,
    ) -> [f64; 3] {
        let p = ray.at(hit.t);
        let (k, colour) = self.looks[hit.region as usize];
        let mut sum = [0.0; 3];
        let eps = 10.0 * self.prepared.tolerance();
        for (li, l) in self.lights.iter().enumerate() {
            let buffer = occ.buffers.get(li);
            // The fall-off's exponent: none for a parallel light.
            let (to_light, dist, decay) = match l.kind {
                // Made once a render (as the light's buffer has it).
                LightKind::Parallel { dir } => (
                    occ.toward
                        .get(li)
                        .copied()
                        .unwrap_or_else(|| -dir.normalize()),
                    f64::INFINITY,
                    None,
                ),
                LightKind::Point { pos, decay } => {
                    let d = pos - p;
                    let r = d.length();
                    (d / r, r, Some(decay))
                }
            };
            let cos = n.dot(to_light);
            if cos <= 0.0 {
                continue;
            }
            if shadows {
                // A parallel light's buffer has answered for the tile's hits
                // (`shadows_toward_suns`); the rest are tested here.
                let blocked = if let Some(&b) = occ.blocked.get(li).and_then(|b| b.get(h)) {
                    b
                } else {
                    let skip = self.prepared.shadow_skip(hit);
                    let shadow = Ray::new(p, to_light);
                    if let Some(zones) = occ.sets.get(li).and_then(Option::as_ref) {
                        self.prepared
                            .occluded_in(zones, skip, &shadow, eps, dist, s)
                    } else if let Some(Buffer::Point(pb)) = buffer {
                        self.prepared.occluded_by(
                            pb,
                            &shadow,
                            eps,
                            dist,
                            skip,
                            &mut occ.last[li],
                            s,
                        )
                    } else {
                        self.prepared.occluded(&shadow, eps, dist, skip, s)
                    }
                };
                if blocked {
                    continue;
                }
            }
            // Only for a surface the light reaches: the power took 8 % of a
            // crowd's time under a lamp.
            let fall = decay.map_or(1.0, |n| dist.powf(-n));
            let e = l.intensity * k * cos * fall;
            for (acc, lc) in sum.iter_mut().zip(l.colour) {
                *acc += e * lc;
            }
        }
        std::array::from_fn(|c| colour[c] * (sum[c] + self.ambient))
    }

    /// Render the picture. `progress` is called with the number of rows
    /// finished so far, from any thread.
    pub fn render(&self, st: &Settings, progress: &(dyn Fn(usize) + Sync)) -> Frame {
        let mut frame = Frame::new(st.width, st.height, st.aovs);
        self.render_into(st, &mut frame, progress);
        frame
    }

    /// As [`Renderer::render`], into `frame`: its memory is reused when it
    /// already has the size (and the auxiliary images) asked for, and every
    /// pixel is written.
    pub fn render_into(&self, st: &Settings, frame: &mut Frame, progress: &(dyn Fn(usize) + Sync)) {
        let (w, h) = (st.width as usize, st.height as usize);
        if frame.width != st.width
            || frame.height != st.height
            || frame.rgb.len() != w * h
            || frame.region.len() != if st.aovs { w * h } else { 0 }
        {
            *frame = Frame::new(st.width, st.height, st.aovs);
        }
        if w == 0 || h == 0 {
            return;
        }
        let gen = self.camera.rays(st.width, st.height);
        let n = st.samples.max(1);
        // Where a pixel's n × n samples lie in it, from its corner.
        let offsets: Vec<f64> = (0..n).map(|i| (i as f64 + 0.5) / n as f64).collect();
        let inv = 1.0 / (n * n) as f64;
        let done = AtomicUsize::new(0);
        let point_lights = self
            .lights
            .iter()
            .any(|l| matches!(l.kind, LightKind::Point { .. }));
        // Where each zone may be seen, binned by band of tiles.
        let bins = self.zone_bins(&gen, w, h);
        let buffers = if st.shadows {
            self.light_buffers()
        } else {
            Arc::from([])
        };
        // One working memory per worker thread, made once: a `Scratch` is
        // sized by the body count, too big to make for every piece of work.
        // Each is made by its own thread on first use, so that its heap
        // blocks come from that thread's arena, and each sits on cache
        // lines of its own: workers that wrote to one line (a small
        // vector, or neighbouring vector headers) made two threads barely
        // faster than one.
        let pool: Vec<CachePadded<Mutex<Option<Workspace>>>> = (0..rayon::current_num_threads())
            .map(|_| CachePadded::new(Mutex::new(None)))
            .collect();
        let mine = || {
            let i = rayon::current_thread_index().unwrap_or(0) % pool.len();
            pool[i].lock().unwrap_or_else(|e| e.into_inner())
        };
        let make = || Workspace::new(&self.prepared, &self.lights, &buffers);
        // A tile row of background, copied whole (a fill writes it a
        // pixel at a time).
        let bg_row = [self.background.map(|v| v as f32); TILE];
        // A supersampled pixel of background, summed as the loop below
        // sums its samples.
        let bg_pixel = {
            let mut acc = [0.0f64; 3];
            for _ in 0..n * n {
                for (a, v) in acc.iter_mut().zip(self.background) {
                    *a += v;
                }
            }
            acc.map(|v| (v * inv) as f32)
        };
        frame
            .rgb
            .par_chunks_mut(w * TILE)
            .zip(frame.alpha.par_chunks_mut(w * TILE))
            .enumerate()
            // Every band a piece of work of its own: bands differ widely in
            // cost (the model fills the middle of the picture), and a
            // worker that runs out can then take any band not yet begun.
            .with_max_len(1)
            .for_each(|(band, (rgb, alpha))| {
                let mut guard = mine();
                let ws = guard.get_or_insert_with(make);
                let y0 = band * TILE;
                let rows = rgb.len() / w;
                // Zones that any ray of each tile may meet, each with a lower
                // bound of where the rays can enter it: a ray stops at the
                // first zone that cannot come nearer than its best hit. The
                // answer is that of a full search.
                self.band_lists(
                    &bins.lead,
                    &bins.bands[band],
                    &gen,
                    w,
                    (y0, y0 + rows),
                    &mut ws.lists,
                );
                for (tile, x0) in (0..w).step_by(TILE).enumerate() {
                    let x1 = (x0 + TILE).min(w);
                    let few = !ws.lists.over[tile];
                    ws.lists.prefetch(&self.prepared, tile);
                    // In the order `Prepared::by_distance` gives. A crowded
                    // tile's list is cut short and never read.
                    if few {
                        std::mem::swap(&mut ws.sorted, &mut ws.lists.tiles[tile]);
                    }
                    // Primary rays of the whole tile first (none when no
                    // zone meets the tile: it is all background).
                    let mut found = 0;
                    // A crowded tile's rays walk the hierarchy.
                    let zones = few.then_some(&ws.sorted[..]);
                    if !(few && ws.sorted.is_empty()) && n == 1 {
                        // One ray a pixel: made several at once with the
                        // hits, where the processor can (only the hits'
                        // rays are kept).
                        let tile = Tile {
                            x0,
                            x1,
                            y0,
                            y1: y0 + rows,
                        };
                        found = self.prepared.tile_hits(
                            &gen,
                            tile,
                            zones,
                            0.0,
                            f64::INFINITY,
                            &mut ws.s,
                            &mut ws.hits,
                            &mut ws.hit_rays,
                            &mut ws.normals,
                        );
                    } else if !(few && ws.sorted.is_empty()) {
                        ws.pts.clear();
                        for yy in 0..rows {
                            for x in x0..x1 {
                                let (fx, fy) = (x as f64, (y0 + yy) as f64);
                                for &oy in &offsets {
                                    for &ox in &offsets {
                                        ws.pts.push([fx + ox, fy + oy]);
                                    }
                                }
                            }
                        }
                        ws.rays.clear();
                        gen.rays(&ws.pts, &mut ws.rays);
                        // The hits' slots are only ever added to (see
                        // `first_hits_in`): filling them anew for every tile
                        // stalls as a copy does.
                        found = match zones {
                            Some(zones) => self.prepared.first_hits_in(
                                zones,
                                &ws.rays,
                                0.0,
                                f64::INFINITY,
                                &mut ws.s,
                                &mut ws.hits,
                            ),
                            None => self.prepared.first_hits(
                                &ws.rays,
                                0.0,
                                f64::INFINITY,
                                &mut ws.s,
                                &mut ws.hits,
                            ),
                        };
                        ws.hit_rays.clear();
                        ws.hit_rays
                            .extend(ws.hits[..found].iter().map(|(k, _)| ws.rays[*k as usize]));
                        // The normals before any shading: the shading loop
                        // reads a normal whole, which stalls when it was
                        // just written a coordinate at a time.
                        ws.normals.clear();
                        ws.normals.extend(
                            ws.hits[..found]
                                .iter()
                                .zip(&ws.hit_rays)
                                .map(|((_, h), ray)| self.prepared.normal(h, ray)),
                        );
                    }
                    // Then the shadow rays toward parallel lights, in
                    // packets through their light buffers.
                    let hits = &ws.hits[..found];
                    if st.shadows && !hits.is_empty() {
                        self.shadows_toward_suns(
                            hits,
                            &ws.normals,
                            &ws.hit_rays,
                            &mut ws.shadow,
                            &mut ws.from,
                            &mut ws.which,
                            &mut ws.answers,
                            &mut ws.s,
                        );
                    }
                    // And per point light, the zones the tile's shadow rays
                    // may meet: those in the box of the tile's hit points
                    // and the light.
                    if st.shadows && !hits.is_empty() && point_lights {
                        let from = Aabb::from_points(
                            hits.iter()
                                .zip(&ws.hit_rays)
                                .map(|((_, h), ray)| ray.at(h.t)),
                        );
                        for (l, set) in self.lights.iter().zip(ws.shadow.sets.iter_mut()) {
                            if let LightKind::Point { pos, .. } = l.kind {
                                let v = set.get_or_insert_with(Vec::new);
                                let few = self.prepared.zones_in_box(
                                    &from.including(pos),
                                    MAX_SHADOW_ZONES,
                                    v,
                                );
                                if !few {
                                    *set = None;
                                }
                            }
                        }
                    }
                    if n == 1 {
                        // One ray a pixel: the tile filled with background,
                        // then each hit's pixel shaded (the same values as
                        // the sums below). Written a pixel at a time, the
                        // background made an empty picture take 1.6 times
                        // as long. Sharing the shading call with the loop
                        // below through a closure costs 4 % more
                        // instructions.
                        let tw = x1 - x0;
                        for yy in 0..rows {
                            let row = yy * w + x0;
                            rgb[row..row + tw].copy_from_slice(&bg_row[..tw]);
                            alpha[row..row + tw].fill(0.0);
                        }
                        for (h, ((k, hit), &normal)) in hits.iter().zip(&ws.normals).enumerate() {
                            let k = *k as usize;
                            let i = k / tw * w + x0 + k % tw;
                            let c = self.shade_with(
                                &ws.hit_rays[h],
                                hit,
                                h,
                                normal,
                                st.shadows,
                                &mut ws.shadow,
                                &mut ws.s,
                            );
                            rgb[i] = c.map(|v| v as f32);
                            alpha[i] = 1.0;
                        }
                        continue;
                    }
                    let (mut k, mut next) = (0, 0);
                    let nn = n * n;
                    for yy in 0..rows {
                        for x in x0..x1 {
                            let i = yy * w + x;
                            // A pixel none of whose rays hit: background.
                            if hits.get(next).is_none_or(|(kk, _)| *kk >= k + nn) {
                                rgb[i] = bg_pixel;
                                alpha[i] = 0.0;
                                k += nn;
                                continue;
                            }
                            let mut acc = [0.0f64; 3];
                            let mut cover = 0.0;
                            for _ in 0..nn {
                                // Shaded in place: no copy of the ray and hit.
                                let c = match hits.get(next) {
                                    Some((kk, hit)) if *kk == k => {
                                        next += 1;
                                        cover += 1.0;
                                        self.shade_with(
                                            &ws.hit_rays[next - 1],
                                            hit,
                                            next - 1,
                                            ws.normals[next - 1],
                                            st.shadows,
                                            &mut ws.shadow,
                                            &mut ws.s,
                                        )
                                    }
                                    _ => self.background,
                                };
                                k += 1;
                                for (a, v) in acc.iter_mut().zip(c) {
                                    *a += v;
                                }
                            }
                            rgb[i] = acc.map(|v| (v * inv) as f32);
                            alpha[i] = (cover * inv) as f32;
                        }
                    }
                }
                progress(done.fetch_add(rows, Ordering::Relaxed) + rows);
            });
        if st.aovs {
            // The auxiliary images describe the pixel centres.
            frame
                .region
                .par_chunks_mut(w)
                .zip(frame.depth.par_chunks_mut(w))
                .zip(frame.normal.par_chunks_mut(w))
                .enumerate()
                .for_each(|(y, ((region, depth), normal))| {
                    let mut guard = mine();
                    let s = &mut guard.get_or_insert_with(make).s;
                    for x in 0..w {
                        let ray = gen.ray(x as f64 + 0.5, y as f64 + 0.5);
                        (region[x], depth[x], normal[x]) =
                            match self.prepared.first_hit(&ray, 0.0, f64::INFINITY, s) {
                                Some(hit) => (
                                    hit.region + 1,
                                    hit.t as f32,
                                    self.prepared.normal(&hit, &ray).as_vec3().to_array(),
                                ),
                                None => (0, f32::INFINITY, [0.0; 3]),
                            };
                    }
                });
        }
        debug_assert_eq!(frame.rgb.len(), w * h);
    }

    /// Trace one primary ray: the hit and its shaded intensity.
    pub fn trace(&self, ray: &Ray, shadows: bool, s: &mut Scratch) -> Option<(Hit, [f64; 3])> {
        let hit = self.prepared.first_hit(ray, 0.0, f64::INFINITY, s)?;
        Some((hit, self.shade(ray, &hit, shadows, s)))
    }
}

/// A unit vector from azimuth and elevation in degrees (BRL-CAD's
/// convention: azimuth from +x toward +y, elevation above the xy plane).
pub fn az_el(az: f64, el: f64) -> DVec3 {
    let (a, e) = (az.to_radians(), el.to_radians());
    DVec3::new(e.cos() * a.cos(), e.cos() * a.sin(), e.sin())
}

#[cfg(test)]
mod tests {
    use super::*;
    use sv_geom::{Body, BodyKind, Region};
    use sv_scene::{Lens, RegionProps};

    /// A crowd of spheres and turned boxes about the origin, over a ground
    /// half-space, each its own region.
    fn crowd() -> Scene {
        let mut s = Scene::default();
        let mut seed = 3u64;
        let mut rnd = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for i in 0..600 {
            let c = [rnd() * 10.0, rnd() * 10.0, rnd() * 10.0];
            let body = if i % 3 == 0 {
                let (a, b) = (rnd(), rnd());
                Body::new(
                    format!("b{i}"),
                    BodyKind::Box,
                    vec![c[0], c[1], c[2], a, b, 0.0, -b, a, 0.0, 0.0, 0.0, 0.8],
                )
            } else {
                Body::new(format!("b{i}"), BodyKind::Sph, vec![c[0], c[1], c[2], 0.4])
            };
            s.geometry.bodies.push(body);
            s.geometry.regions.push(Region::of_body(format!("r{i}"), i));
        }
        // A rod passing beside the first camera's eye, partly behind it.
        let n = s.geometry.bodies.len();
        s.geometry.bodies.push(Body::new(
            "rod",
            BodyKind::Rpp,
            vec![-10.0, 10.0, 0.5, 0.7, -0.2, 0.2],
        ));
        s.geometry.regions.push(Region::of_body("rod", n));
        s.geometry.bodies.push(Body::new(
            "ground",
            BodyKind::Haf,
            vec![0.0, 0.0, 1.0, -11.0],
        ));
        s.geometry.regions.push(Region::of_body("ground", n + 1));
        s.regions = vec![RegionProps::default(); n + 2];
        s
    }

    #[test]
    fn a_picture_without_pixels_is_empty() {
        let (r, _) = Renderer::new(&crowd(), 4.0 / 3.0).unwrap();
        for (width, height) in [(0, 0), (0, 48), (64, 0)] {
            let st = Settings {
                width,
                height,
                ..Settings::default()
            };
            let frame = r.render(&st, &|_| {});
            assert!(frame.rgb.is_empty() && frame.alpha.is_empty());
        }
    }

    #[test]
    fn tile_lists_hold_every_zone_in_front_of_the_eye_their_frustum_keeps() {
        let scene = crowd();
        let (r, _) = Renderer::new(&scene, 4.0 / 3.0).unwrap();
        // From far off (the crowd in a few tiles, too many for their
        // lists), from inside the crowd (zones straddle the eye's plane or
        // lie behind it), from outside, and orthographic.
        let cameras = [
            Camera::looking_at(
                DVec3::new(3000.0, -2500.0, 1200.0),
                DVec3::ZERO,
                DVec3::Z,
                Lens::Fov { vertical_deg: 40.0 },
            ),
            Camera::looking_at(
                DVec3::ZERO,
                DVec3::new(1.0, 2.0, 0.3),
                DVec3::Z,
                Lens::Fov { vertical_deg: 70.0 },
            ),
            Camera::looking_at(
                DVec3::new(30.0, -25.0, 12.0),
                DVec3::ZERO,
                DVec3::Z,
                Lens::Fov { vertical_deg: 40.0 },
            ),
            Camera::looking_at(
                DVec3::new(5.0, 30.0, 8.0),
                DVec3::ZERO,
                DVec3::Z,
                Lens::Ortho { height: 16.0 },
            ),
        ];
        // The picture's centre inside a tile, not on the tiles' corners: the
        // far-off crowd lands in one tile.
        let (w, h) = (328, 248);
        let (mut lists, mut own) = (BandLists::default(), Vec::new());
        let (mut kept, mut extra, mut behind, mut overflowing) = (0, 0, 0, 0);
        for cam in cameras {
            let gen = cam.rays(w as u32, h as u32);
            let parallel = matches!(cam.lens, Lens::Ortho { .. }).then(|| cam.dir.normalize());
            let bins = r.zone_bins(&gen, w, h);
            assert!(!bins.lead.is_empty(), "the ground is in every list");
            for (band, y0) in (0..h).step_by(TILE).enumerate() {
                let y1 = (y0 + TILE).min(h);
                r.band_lists(&bins.lead, &bins.bands[band], &gen, w, (y0, y1), &mut lists);
                for (t, x0) in (0..w).step_by(TILE).enumerate() {
                    let x1 = (x0 + TILE).min(w);
                    let corners = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
                        .map(|(x, y)| gen.ray(x as f64, y as f64));
                    r.prepared
                        .frustum_zones(&Frustum::from_corners(corners), usize::MAX, &mut own);
                    if lists.over[t] {
                        overflowing += 1;
                        assert!(own.len() > MAX_TILE_ZONES, "tile {t} of band {band}");
                        continue;
                    }
                    let list = &lists.tiles[t];
                    // Each with its entry bound for the camera (a bounded
                    // zone's in single precision, rounded down: never above
                    // it, and as tight as single precision allows), the
                    // unbounded zones among them, in the order of
                    // `by_distance`.
                    for &(near, z) in list {
                        let exact = r.prepared.entry_bound(z, cam.eye, parallel);
                        assert!(near <= exact, "zone {z}: {near} past {exact}");
                        let close = exact - near <= 1e-6 * exact.abs().max(1.0);
                        assert!(near == exact || close, "zone {z}: {near} for {exact}");
                    }
                    assert!(bins.lead.iter().all(|e| list.contains(e)));
                    assert!(list.is_sorted_by(|a, b| by_entry(a, b).is_lt()));
                    let list: Vec<u32> = list.iter().map(|&(_, z)| z).collect();
                    for &z in &own {
                        if r.prepared.zone_rect(z, &gen) == RasterExtent::Nowhere {
                            behind += 1;
                        } else {
                            assert!(list.contains(&z), "zone {z}, tile {t} of band {band}");
                            kept += 1;
                        }
                    }
                    extra += list.iter().filter(|z| !own.contains(z)).count();
                }
            }
        }
        assert!(kept > 3000, "{kept} zones listed");
        assert!(behind > 0, "no zone behind the eye");
        assert!(overflowing > 0, "no tile overflows");
        // A pixel's padding and zones across the eye's plane: a few more.
        assert!(
            extra * 10 < kept,
            "{extra} more than the frusta keep, of {kept}"
        );
    }
}
