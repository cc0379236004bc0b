//! Tiles and bands: which zones each tile's rays may meet, found once a
//! frame by placing every zone on the raster and binning it by band of
//! tiles, then per band by the columns of tiles it reaches.

use crate::Renderer;
use rayon::prelude::*;
use sv_math::RayGen;
use sv_trace::{by_entry, Frustum, Prepared, RasterExtent};

/// How far (pixels) a zone's rectangle on the raster is widened each way
/// against rounding, which is some 1e-9 of a pixel.
pub(crate) const PAD: f64 = 0.01;
/// Tiles are TILE×TILE pixels.
pub(crate) const TILE: usize = 16;
/// Above this many candidate zones a tile's rays walk the hierarchy. A ray
/// that meets nothing tests every zone of its tile's list, so the list must
/// stay short; but walking the hierarchy costs a ray that crosses a crowd
/// of small bodies more than testing a few hundred listed boxes in turn,
/// eight rays at a time. 100,000 small spheres at constant coverage cost
/// 72, 64, 63 and 67 ns a ray with 256, 512, 1024 and 2048; seen from far
/// off (1 % of the picture on spheres), 17–19, 20–22 and 23 ns with 256,
/// 1024 and 2048 (BENCHMARKS.md, thirteenth round).
pub(crate) const MAX_TILE_ZONES: usize = 512;
/// Where the zones may be seen on a frame's raster ([`Renderer::zone_bins`]),
/// each with a lower bound of where the camera's rays can enter it
/// ([`Prepared::entry_bound`], or [`Prepared::place_proxy`]'s for a bounded
/// zone).
pub(crate) struct Bins {
    /// The unbounded opaque zones, which every tile lists.
    pub(crate) lead: Vec<(f64, u32)>,
    /// Per band of tiles, its bounded zones.
    pub(crate) bands: Vec<Vec<Binned>>,
}

/// The tile (or band) of raster coordinate `v`, the last one being `last`.
pub(crate) fn tile_of(v: f64, last: usize) -> usize {
    // Truncation is the floor once the negatives (and not-a-number) are
    // 0: without SSE4.1 a floor is a call.
    ((v / TILE as f64).max(0.0) as usize).min(last)
}

/// A zone in a band: its entry bound and number, and the first and last
/// columns of tiles it spans ([`ANYWHERE`] as the last when it may be seen
/// anywhere).
#[derive(Clone, Copy)]
pub(crate) struct Binned {
    near: f32,
    zi: u32,
    c0: u32,
    c1: u32,
}

/// The last column of a zone that may be seen anywhere on the raster.
pub(crate) const ANYWHERE: u32 = u32::MAX;

/// The zones each tile of a band (a row of tiles) may meet.
#[derive(Default)]
pub(crate) struct BandLists {
    /// The tiles' frusta, made for zones seen anywhere.
    pub(crate) frusta: Vec<Frustum>,
    /// Per tile, its zones with their entry bounds, and whether it has more
    /// than [`MAX_TILE_ZONES`] (its list is then incomplete, and its rays
    /// walk the hierarchy).
    pub(crate) tiles: Vec<Vec<(f64, u32)>>,
    pub(crate) over: Vec<bool>,
}

impl BandLists {
    /// The list of tile `t`, unless the band has no such tile or the tile
    /// is crowded (its list is then never read).
    pub(crate) fn list(&self, t: usize) -> Option<&[(f64, u32)]> {
        (t < self.tiles.len() && !self.over[t]).then(|| &self.tiles[t][..])
    }

    /// Before tile `t`'s rays: the zones of tile `t + 2` and the bodies of
    /// tile `t + 1` asked for ([`Prepared::prefetch_zones`] and
    /// [`Prepared::prefetch_bodies`]), so that each tile finds them
    /// fetched; at the band's start, those of tiles 0 and 1 too.
    pub(crate) fn prefetch(&self, p: &Prepared, t: usize) {
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

impl Renderer {
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
    pub(crate) fn zone_bins(&self, gen: &RayGen, w: usize, h: usize) -> Bins {
        let p = self.prepared();
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
    pub(crate) fn band_lists(
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
                if l.over[t] || (anywhere && !self.prepared().frustum_keeps(zi, &l.frusta[t])) {
                    continue;
                }
                l.tiles[t].push((near, zi));
                l.over[t] = l.tiles[t].len() > MAX_TILE_ZONES;
            }
        }
        lead.for_each(|e| everywhere(l, e));
    }
}
