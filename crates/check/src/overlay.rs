//! Which pixels of a picture look through an overlap, and the picture
//! with them painted (`render --overlaps`).

use crate::analyse::{FindingKind, RayCheck};
use crate::colour::OVERLAP_COLOUR;
use crate::model::{default_tolerance, Model};
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use sv_math::Ray;
use sv_scene::Camera;

/// A pair of overlapping regions seen in a picture.
#[derive(Clone, Debug, PartialEq)]
pub struct PairSeen {
    /// The two regions' names.
    pub regions: [String; 2],
    /// Pixels whose ray crosses their overlap.
    pub pixels: u64,
    /// Longest overlap stretch along any of those rays.
    pub max_length: f64,
}

/// The result of [`overlap_pixels`].
#[derive(Clone, Debug, PartialEq)]
pub struct OverlapPixels {
    /// Row-major from the top left: true where the pixel's ray passes
    /// through an overlap longer than the tolerance, anywhere along it
    /// (also behind the first visible surface).
    pub mask: Vec<bool>,
    /// The pairs seen, most pixels first.
    pub pairs: Vec<PairSeen>,
}

impl OverlapPixels {
    /// Paint the pixels that see an overlap in [`OVERLAP_COLOUR`], opaque,
    /// over a picture of the same size (`rgb` and `alpha` row-major from the
    /// top left, as [`OverlapPixels::mask`]).
    pub fn paint(&self, rgb: &mut [[f32; 3]], alpha: &mut [f32]) {
        for ((seen, colour), coverage) in self.mask.iter().zip(rgb).zip(alpha) {
            if *seen {
                *colour = OVERLAP_COLOUR;
                *coverage = 1.0;
            }
        }
    }

    /// The pairs seen, one line each, as `render --overlaps` lists them.
    pub fn summary(&self) -> String {
        if self.pairs.is_empty() {
            return "overlaps: none seen\n".into();
        }
        let mut text = format!("overlaps seen ({} pairs, magenta):\n", self.pairs.len());
        for pair in &self.pairs {
            let _ = writeln!(
                text,
                "  {} × {}: {} pixels, longest {:.6}",
                pair.regions[0], pair.regions[1], pair.pixels, pair.max_length
            );
        }
        text
    }
}

/// The overlaps seen through the pixel centres of `camera`'s
/// `width`×`height` picture of `model`, with the model's
/// [`default_tolerance`]; `strict_air` as in [`overlap_pixels`]. Runs on
/// the current rayon pool.
pub fn camera_overlaps(
    model: &Model,
    camera: &Camera,
    width: u32,
    height: u32,
    strict_air: bool,
) -> OverlapPixels {
    let tolerance = default_tolerance(&model.prepared);
    let rays = camera.rays(width, height);
    overlap_pixels(model, width, height, tolerance, strict_air, |x, y| {
        rays.ray(x as f64 + 0.5, y as f64 + 0.5)
    })
}

/// Classify the primary ray of every pixel of a `width`×`height` picture;
/// `ray(x, y)` gives the ray of pixel (x, y). Overlaps no longer than `tol`
/// are ignored, and so are overlaps with an air region unless `strict_air`
/// (as [`CheckOptions::strict_air`](crate::CheckOptions::strict_air)).
/// Runs on the current rayon pool.
pub fn overlap_pixels<F>(
    model: &Model,
    width: u32,
    height: u32,
    tol: f64,
    strict_air: bool,
    ray: F,
) -> OverlapPixels
where
    F: Fn(u32, u32) -> Ray + Sync,
{
    let (columns, rows) = (width as usize, height as usize);
    /// A row's mask, and per pair its pixels and longest stretch.
    type Row = (Vec<bool>, BTreeMap<(u32, u32), (u64, f64)>);
    let row_results: Vec<Row> = (0..rows)
        .into_par_iter()
        .map_init(
            || RayCheck::new(model),
            |ray_check, y| {
                let mut mask = vec![false; columns];
                let mut seen: BTreeMap<(u32, u32), (u64, f64)> = BTreeMap::new();
                for (x, pixel_seen) in mask.iter_mut().enumerate() {
                    let pixel_ray = ray(x as u32, y as u32);
                    ray_check.run(&pixel_ray, 0.0, f64::INFINITY, tol);
                    let mut pairs: Vec<((u32, u32), f64)> = Vec::new();
                    for finding in &ray_check.findings {
                        if let FindingKind::Overlap(a, b) = finding.kind {
                            if strict_air || !model.is_air_overlap(a as usize, b as usize) {
                                pairs.push(((a, b), finding.t1 - finding.t0));
                            }
                        }
                    }
                    pairs.sort_by_key(|pair| pair.0);
                    let mut last = None;
                    for (pair, length) in pairs {
                        *pixel_seen = true;
                        let entry = seen.entry(pair).or_insert((0, 0.0));
                        if last != Some(pair) {
                            entry.0 += 1;
                            last = Some(pair);
                        }
                        entry.1 = entry.1.max(length);
                    }
                }
                (mask, seen)
            },
        )
        .collect();
    let mut mask = Vec::with_capacity(columns * rows);
    let mut all: BTreeMap<(u32, u32), (u64, f64)> = BTreeMap::new();
    for (row_mask, row_seen) in row_results {
        mask.extend(row_mask);
        for (pair, (pixels, longest)) in row_seen {
            let entry = all.entry(pair).or_insert((0, 0.0));
            entry.0 += pixels;
            entry.1 = entry.1.max(longest);
        }
    }
    let mut pairs: Vec<PairSeen> = all
        .into_iter()
        .map(|((a, b), (pixels, max_length))| PairSeen {
            regions: [
                model.names[a as usize].clone(),
                model.names[b as usize].clone(),
            ],
            pixels,
            max_length,
        })
        .collect();
    pairs.sort_by(|a, b| b.pixels.cmp(&a.pixels).then(a.regions.cmp(&b.regions)));
    OverlapPixels { mask, pairs }
}
