//! The renderer: a prepared scene with its camera, lights and looks, and a
//! frame rendered in named steps: the frame's plan ([`Renderer::plan`]),
//! each band of tiles ([`Renderer::render_band`]), each tile's primary
//! rays ([`Renderer::trace_tile`]) and its pixels ([`Renderer::fill_tile`];
//! under rt's shading with one ray a pixel, the band's pixels at once,
//! [`Renderer::fill_band_rt`]), then the auxiliary images
//! ([`Renderer::render_aovs`]).
//!
//! Every pixel is computed independently from its own rays, so a picture is
//! bit-for-bit the same whatever the number of threads.

use crate::shading::rt_grey;
use crate::tiles::{Bins, TILE};
use crate::workspace::{Workers, Workspace};
use crate::{default_camera, default_lights, Frame, Settings, Shading, ViewSpec};
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use sv_math::Ray;
use sv_scene::{Background, Camera, Light, LightKind, RayGen, Scene};
use sv_trace::{
    Hit, LightAt, PrepareError, PrepareOptions, Prepared, Scratch, ShadowBuffers, Tile, Warning,
    FACING_MISS,
};

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
    /// The shading formula: the paper's (default) or `rt -l1`'s.
    pub shading: Shading,
    pub(crate) ambient: f64,
    background: [f64; 3],
    /// Per region, its reflectance `k` and colour.
    pub(crate) looks: Vec<(f64, [f64; 3])>,
    buffers: BufferCache,
}

/// The light buffers of the last render with shadows. A render whose
/// lights shine the same ways from the same places reuses them: the
/// geometry cannot change under a [`Renderer`], so only the lights need
/// comparing.
#[derive(Clone, Debug, Default)]
struct BufferCache(Arc<Mutex<Option<Arc<ShadowBuffers>>>>);

/// What every band of a frame shares.
struct FramePlan<'a> {
    settings: &'a Settings,
    width: usize,
    /// The primary rays.
    gen: RayGen,
    /// Where each zone may be seen, binned by band of tiles.
    bins: Bins,
    /// Rays a pixel along each side (`samples × samples` a pixel).
    samples: usize,
    /// Where a pixel's samples lie in it, from its corner.
    offsets: Vec<f64>,
    /// One over the number of samples a pixel.
    inv: f64,
    /// A tile row of background, copied whole (a fill writes it a pixel at
    /// a time).
    bg_row: [[f32; 3]; TILE],
    /// A supersampled pixel of background, summed as the samples are.
    bg_pixel: [f32; 3],
    /// The lights as the shadow rays see them.
    lights: Vec<LightAt>,
}

/// The tiles of a band `rows` high from row `y0` of a picture `width`
/// wide, left to right, numbered from 0.
fn band_tiles(width: usize, y0: usize, rows: usize) -> impl Iterator<Item = (usize, Tile)> {
    (0..width)
        .step_by(TILE)
        .enumerate()
        .map(move |(index, x0)| {
            let tile = Tile {
                x0,
                x1: (x0 + TILE).min(width),
                y0,
                y1: y0 + rows,
            };
            (index, tile)
        })
}

/// Where light `l` is, as its shadow rays need it.
fn light_at(l: &Light) -> LightAt {
    match l.kind {
        LightKind::Parallel { dir } => LightAt::Parallel { dir },
        LightKind::Point { pos, .. } => LightAt::Point { pos },
    }
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
        // Regions beyond the model (black holes) are never drawn.
        opts.opaque = Some(
            scene
                .regions
                .iter()
                .map(|r| !r.transparent && !r.outside)
                .collect(),
        );
        opts.outside = Some(scene.regions.iter().map(|r| r.outside).collect());
        let (prepared, warnings) = Prepared::new(&scene.geometry, &opts)?;
        let camera = scene
            .camera
            .unwrap_or_else(|| default_camera(&prepared, aspect, &ViewSpec::default()));
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
                shading: Shading::Paper,
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

    /// The shadow buffers of `lights`: those of the last render when its
    /// lights were the same, else new ones (kept for the next render).
    fn light_buffers(&self, lights: &[LightAt]) -> Arc<ShadowBuffers> {
        let mut kept = self.buffers.0.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(buffers) = kept.as_ref().filter(|b| b.lights() == lights) {
            return buffers.clone();
        }
        let buffers = Arc::new(ShadowBuffers::new(&self.prepared, lights));
        *kept = Some(buffers.clone());
        buffers
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
        let plan = self.plan(st);
        let buffers = st.shadows.then(|| self.light_buffers(&plan.lights));
        let workers = Workers::new();
        let make = || Workspace::new(&self.prepared, &plan.lights, buffers.as_deref());
        let done = AtomicUsize::new(0);
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
                let rows = rgb.len() / w;
                workers.with(make, |ws| self.render_band(&plan, band, rgb, alpha, ws));
                progress(done.fetch_add(rows, Ordering::Relaxed) + rows);
            });
        if st.aovs {
            self.render_aovs(&plan.gen, frame, &workers, make);
        }
        debug_assert_eq!(frame.rgb.len(), w * h);
    }

    /// What every band of a frame of `st` shares: the rays, where each
    /// zone may be seen, the samples and the background.
    fn plan<'a>(&self, st: &'a Settings) -> FramePlan<'a> {
        let (w, h) = (st.width as usize, st.height as usize);
        let gen = self.camera.rays(st.width, st.height);
        let samples = st.samples.max(1) as usize;
        let offsets = (0..samples)
            .map(|i| (i as f64 + 0.5) / samples as f64)
            .collect();
        let inv = 1.0 / (samples * samples) as f64;
        let bg_pixel = {
            let mut acc = [0.0f64; 3];
            for _ in 0..samples * samples {
                for (a, v) in acc.iter_mut().zip(self.background) {
                    *a += v;
                }
            }
            acc.map(|v| (v * inv) as f32)
        };
        FramePlan {
            settings: st,
            width: w,
            bins: self.zone_bins(&gen, w, h),
            gen,
            samples,
            offsets,
            inv,
            bg_row: [self.background.map(|v| v as f32); TILE],
            bg_pixel,
            lights: self.lights.iter().map(light_at).collect(),
        }
    }

    /// The band of tiles `band` (its rows of pixels in `rgb` and `alpha`):
    /// the zones each tile's rays may meet, then tile by tile the primary
    /// rays, the shadow rays that can be tested ahead, and the pixels.
    fn render_band(
        &self,
        plan: &FramePlan<'_>,
        band: usize,
        rgb: &mut [[f32; 3]],
        alpha: &mut [f32],
        ws: &mut Workspace<'_>,
    ) {
        let w = plan.width;
        let y0 = band * TILE;
        let rows = rgb.len() / w;
        // Zones that any ray of each tile may meet, each with a lower bound
        // of where the rays can enter it: a ray stops at the first zone that
        // cannot come nearer than its best hit. The answer is that of a
        // full search.
        self.band_lists(
            &plan.bins.lead,
            &plan.bins.bands[band],
            &plan.gen,
            w,
            (y0, y0 + rows),
            &mut ws.lists,
        );
        if plan.samples == 1 && self.shading == Shading::RtEyeLight {
            let tiles = w.div_ceil(TILE);
            ws.band_facing.resize_with(tiles, Default::default);
            for (index, tile) in band_tiles(w, y0, rows) {
                // Traced into the tile's own place of the band.
                std::mem::swap(&mut ws.facing, &mut ws.band_facing[index].1);
                let found = self.trace_tile(plan, index, tile, ws);
                std::mem::swap(&mut ws.facing, &mut ws.band_facing[index].1);
                ws.band_facing[index].0 = found;
            }
            Self::fill_band_rt(plan, rows, rgb, alpha, &ws.band_facing[..tiles]);
            return;
        }
        for (index, tile) in band_tiles(w, y0, rows) {
            let found = self.trace_tile(plan, index, tile, ws);
            // rt's shading casts no shadows.
            if plan.settings.shadows && self.shading != Shading::RtEyeLight {
                let hits = (&ws.hits[..found], &ws.normals[..], &ws.hit_rays[..]);
                ws.occluders
                    .prepare_tile(&self.prepared, &plan.lights, hits, &mut ws.scratch);
            }
            self.fill_tile(plan, tile, found, rgb, alpha, ws);
        }
    }

    /// The primary rays of tile number `index` of the band (none when no
    /// zone meets the tile: it is all background): the hits in `ws.hits`,
    /// with their rays and normals. Returns how many hit.
    #[inline]
    fn trace_tile(
        &self,
        plan: &FramePlan<'_>,
        index: usize,
        tile: Tile,
        ws: &mut Workspace<'_>,
    ) -> usize {
        let listed = !ws.lists.over[index];
        ws.lists.prefetch(&self.prepared, index);
        // In the order `Prepared::by_distance` gives. A crowded tile's list
        // is cut short and never read: its rays walk the hierarchy.
        if listed {
            std::mem::swap(&mut ws.sorted, &mut ws.lists.tiles[index]);
        }
        let zones = listed.then_some(&ws.sorted[..]);
        if listed && ws.sorted.is_empty() {
            return 0;
        }
        let inf = f64::INFINITY;
        if plan.samples == 1 && self.shading == Shading::RtEyeLight {
            // rt's grey needs no more of a hit than how it faces its ray.
            let (gen, s) = (&plan.gen, &mut ws.scratch);
            return self
                .prepared
                .tile_facing(gen, tile, zones, 0.0, inf, s, &mut ws.facing);
        }
        if plan.samples == 1 {
            // One ray a pixel: made several at once with the hits, where
            // the processor can (only the hits' rays are kept).
            return self.prepared.tile_hits(
                &plan.gen,
                tile,
                zones,
                0.0,
                inf,
                &mut ws.scratch,
                &mut ws.hits,
                &mut ws.hit_rays,
                &mut ws.normals,
            );
        }
        ws.pts.clear();
        for y in tile.y0..tile.y1 {
            for x in tile.x0..tile.x1 {
                let (fx, fy) = (x as f64, y as f64);
                for &oy in &plan.offsets {
                    for &ox in &plan.offsets {
                        ws.pts.push([fx + ox, fy + oy]);
                    }
                }
            }
        }
        ws.rays.clear();
        plan.gen.rays(&ws.pts, &mut ws.rays);
        // The hits' slots are only ever added to (see `first_hits_in`):
        // filling them anew for every tile stalls as a copy does.
        let (rays, s, hits) = (&ws.rays, &mut ws.scratch, &mut ws.hits);
        let found = match zones {
            Some(zones) => self.prepared.first_hits_in(zones, rays, 0.0, inf, s, hits),
            None => self.prepared.first_hits(rays, 0.0, inf, s, hits),
        };
        ws.hit_rays.clear();
        ws.hit_rays
            .extend(ws.hits[..found].iter().map(|(k, _)| ws.rays[*k as usize]));
        // The normals before any shading: the shading loop reads a normal
        // whole, which stalls when it was just written a coordinate at a
        // time.
        ws.normals.clear();
        ws.normals.extend(
            ws.hits[..found]
                .iter()
                .zip(&ws.hit_rays)
                .map(|((_, h), ray)| self.prepared.normal(h, ray)),
        );
        found
    }

    /// Under rt's shading with one ray a pixel, the `rows` rows of a band's
    /// pixels from its tiles' hits, `tiles` (for each tile, left to right,
    /// its number of hits and how its pixels face their rays,
    /// [`Prepared::tile_facing`]): each pixel a grey (one value: the colour
    /// array of `intensity` would be read back whole from the stack it was
    /// just stored to, which stalls) or the background. Written row by
    /// row across the whole band, so that the picture's memory is written
    /// in order: tile by tile, each row of a tile began a line of memory
    /// that the processor had to fetch first, and the writes waited for it.
    fn fill_band_rt(
        plan: &FramePlan<'_>,
        rows: usize,
        rgb: &mut [[f32; 3]],
        alpha: &mut [f32],
        tiles: &[(usize, Vec<f64>)],
    ) {
        let w = plan.width;
        for row in 0..rows {
            for (index, (found, facing)) in tiles.iter().enumerate() {
                let x0 = index * TILE;
                let tw = (x0 + TILE).min(w) - x0;
                let start = row * w + x0;
                let (rgb, alpha) = (&mut rgb[start..start + tw], &mut alpha[start..start + tw]);
                // No hit: `facing` was not written (see `trace_tile`).
                if *found == 0 {
                    rgb.copy_from_slice(&plan.bg_row[..tw]);
                    alpha.fill(0.0);
                    continue;
                }
                let facing = &facing[row * tw..(row + 1) * tw];
                if *found == tw * rows {
                    // Every pixel hit: no test, and the loops vectorise.
                    for (c, &f) in rgb.iter_mut().zip(facing) {
                        *c = [rt_grey(f) as f32; 3];
                    }
                    alpha.fill(1.0);
                    continue;
                }
                let pixels = rgb.iter_mut().zip(alpha);
                for (((c, a), &f), &bg) in pixels.zip(facing).zip(&plan.bg_row) {
                    (*c, *a) = if f == FACING_MISS {
                        (bg, 0.0)
                    } else {
                        ([rt_grey(f) as f32; 3], 1.0)
                    };
                }
            }
        }
    }

    /// The pixels of `tile` from its `found` hits: each shaded, the others
    /// background; supersampled pixels the mean of their samples.
    #[inline]
    fn fill_tile(
        &self,
        plan: &FramePlan<'_>,
        tile: Tile,
        found: usize,
        rgb: &mut [[f32; 3]],
        alpha: &mut [f32],
        ws: &mut Workspace<'_>,
    ) {
        let (w, shadows) = (plan.width, plan.settings.shadows);
        let (x0, x1, rows) = (tile.x0, tile.x1, tile.y1 - tile.y0);
        if plan.samples == 1 {
            // One ray a pixel: the tile filled with background, then each
            // hit's pixel shaded (the same values as the sums below).
            // Written a pixel at a time, the background made an empty
            // picture take 1.6 times as long. Sharing the shading call with
            // the loop below through a closure costs 4 % more instructions.
            let tw = x1 - x0;
            for row in 0..rows {
                let start = row * w + x0;
                if tw == TILE {
                    // A whole tile's row, of a size known here: written
                    // with a few vector stores instead of two library calls
                    // for every row of every tile.
                    let (rgb_row, alpha_row) = (
                        &mut rgb[start..start + TILE],
                        &mut alpha[start..start + TILE],
                    );
                    rgb_row.copy_from_slice(&plan.bg_row);
                    alpha_row.copy_from_slice(&[0.0; TILE]);
                } else {
                    rgb[start..start + tw].copy_from_slice(&plan.bg_row[..tw]);
                    alpha[start..start + tw].fill(0.0);
                }
            }
            // rt's shading with one ray a pixel fills whole bands instead.
            debug_assert!(self.shading != Shading::RtEyeLight, "see fill_band_rt");
            let hits = &ws.hits[..found];
            for (h, ((k, hit), &normal)) in hits.iter().zip(&ws.normals).enumerate() {
                let k = *k as usize;
                let i = k / tw * w + x0 + k % tw;
                let ray = &ws.hit_rays[h];
                let c = self.intensity(
                    ray,
                    (h, hit),
                    normal,
                    shadows,
                    &mut ws.occluders,
                    &mut ws.scratch,
                );
                rgb[i] = c.map(|v| v as f32);
                alpha[i] = 1.0;
            }
            return;
        }
        let hits = &ws.hits[..found];
        // The sample number of the next ray, and the next hit.
        let (mut sample, mut next) = (0, 0);
        let per_pixel = plan.samples * plan.samples;
        for row in 0..rows {
            for x in x0..x1 {
                let i = row * w + x;
                // A pixel none of whose rays hit: background.
                if hits
                    .get(next)
                    .is_none_or(|(k, _)| *k as usize >= sample + per_pixel)
                {
                    rgb[i] = plan.bg_pixel;
                    alpha[i] = 0.0;
                    sample += per_pixel;
                    continue;
                }
                let mut acc = [0.0f64; 3];
                let mut cover = 0.0;
                for _ in 0..per_pixel {
                    // Shaded in place: no copy of the ray and hit.
                    let c = match hits.get(next) {
                        Some((k, hit)) if *k as usize == sample => {
                            next += 1;
                            cover += 1.0;
                            let (ray, normal) = (&ws.hit_rays[next - 1], ws.normals[next - 1]);
                            let occluders = &mut ws.occluders;
                            self.intensity(
                                ray,
                                (next - 1, hit),
                                normal,
                                shadows,
                                occluders,
                                &mut ws.scratch,
                            )
                        }
                        _ => self.background,
                    };
                    sample += 1;
                    for (a, v) in acc.iter_mut().zip(c) {
                        *a += v;
                    }
                }
                rgb[i] = acc.map(|v| (v * plan.inv) as f32);
                alpha[i] = (cover * plan.inv) as f32;
            }
        }
    }

    /// The auxiliary images of `frame`: region, depth and normal of the
    /// pixel centres.
    fn render_aovs<'a>(
        &self,
        gen: &RayGen,
        frame: &mut Frame,
        workers: &Workers<'a>,
        make: impl Fn() -> Workspace<'a> + Sync,
    ) {
        let w = frame.width as usize;
        frame
            .region
            .par_chunks_mut(w)
            .zip(frame.depth.par_chunks_mut(w))
            .zip(frame.normal.par_chunks_mut(w))
            .enumerate()
            .for_each(|(y, ((region, depth), normal))| {
                workers.with(&make, |ws| {
                    for x in 0..w {
                        let ray = gen.ray(x as f64 + 0.5, y as f64 + 0.5);
                        let first =
                            self.prepared
                                .first_hit(&ray, 0.0, f64::INFINITY, &mut ws.scratch);
                        (region[x], depth[x], normal[x]) = match first {
                            Some(hit) => (
                                hit.region + 1,
                                hit.t as f32,
                                self.prepared.normal(&hit, &ray).as_vec3().to_array(),
                            ),
                            None => (0, f32::INFINITY, [0.0; 3]),
                        };
                    }
                });
            });
    }

    /// Trace one primary ray: the hit and its shaded intensity.
    pub fn trace(&self, ray: &Ray, shadows: bool, s: &mut Scratch) -> Option<(Hit, [f64; 3])> {
        let hit = self.prepared.first_hit(ray, 0.0, f64::INFINITY, s)?;
        Some((hit, self.shade(ray, &hit, shadows, s)))
    }
}
