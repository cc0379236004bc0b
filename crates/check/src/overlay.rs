//! Which pixels of a picture look through an overlap.

use crate::analyse::{FindingKind, RayCheck};
use crate::model::Model;
use rayon::prelude::*;
use std::collections::BTreeMap;
use sv_math::Ray;

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
    let (w, h) = (width as usize, height as usize);
    let air = |r: u32| model.air.get(r as usize).copied().unwrap_or(false);
    type Row = (Vec<bool>, BTreeMap<(u32, u32), (u64, f64)>);
    let rows: Vec<Row> = (0..h)
        .into_par_iter()
        .map_init(
            || RayCheck::new(model),
            |rc, y| {
                let mut mask = vec![false; w];
                let mut seen: BTreeMap<(u32, u32), (u64, f64)> = BTreeMap::new();
                for (x, m) in mask.iter_mut().enumerate() {
                    let r = ray(x as u32, y as u32);
                    rc.run(&r, 0.0, f64::INFINITY, tol);
                    let mut pairs: Vec<((u32, u32), f64)> = Vec::new();
                    for f in &rc.findings {
                        if let FindingKind::Overlap(a, b) = f.kind {
                            if strict_air || !(air(a) || air(b)) {
                                pairs.push(((a, b), f.t1 - f.t0));
                            }
                        }
                    }
                    pairs.sort_by_key(|a| a.0);
                    let mut last = None;
                    for (k, len) in pairs {
                        *m = true;
                        let e = seen.entry(k).or_insert((0, 0.0));
                        if last != Some(k) {
                            e.0 += 1;
                            last = Some(k);
                        }
                        e.1 = e.1.max(len);
                    }
                }
                (mask, seen)
            },
        )
        .collect();
    let mut mask = Vec::with_capacity(w * h);
    let mut all: BTreeMap<(u32, u32), (u64, f64)> = BTreeMap::new();
    for (m, s) in rows {
        mask.extend(m);
        for (k, (n, l)) in s {
            let e = all.entry(k).or_insert((0, 0.0));
            e.0 += n;
            e.1 = e.1.max(l);
        }
    }
    let mut pairs: Vec<PairSeen> = all
        .into_iter()
        .map(|((a, b), (n, l))| PairSeen {
            regions: [
                model.names[a as usize].clone(),
                model.names[b as usize].clone(),
            ],
            pixels: n,
            max_length: l,
        })
        .collect();
    pairs.sort_by(|a, b| b.pixels.cmp(&a.pixels).then(a.regions.cmp(&b.regions)));
    OverlapPixels { mask, pairs }
}
