//! `volume`: region volumes, errors, centroids and masses by ray sampling,
//! as BRL-CAD's `gqa` does.
//!
//! A *batch* fires, along each of x, y and z, one ray through a random
//! point of every cell of an N×N grid over the box's face (a jittered
//! grid). Each ray's stretch inside a region, times the cell's area, is an
//! unbiased estimate of the region's volume; the three axes are averaged.
//! Batches are independent, so the spread of their results gives the
//! standard error of the mean. Batches over the whole model run first;
//! regions much smaller than the model that have not converged are then
//! sampled with batches over their own bounds, restarting their statistics.

use crate::analyse::RayCheck;
use crate::model::{CheckError, Model};
use crate::report::fmt_g;
use crate::rng::uniform;
use rayon::prelude::*;
use serde::Serialize;
use std::fmt::Write as _;
use std::time::Instant;
use sv_math::{Aabb, DVec3, Ray};

/// Options for [`volumes`].
#[derive(Clone, Debug)]
pub struct VolumeOptions {
    /// Target relative standard error of every region's volume (0.001).
    pub rel_error: f64,
    /// Grid cells per side of a batch over the whole model (128).
    pub rays_per_side: u32,
    /// Grid cells per side of a batch over one region's bounds (48).
    pub region_rays_per_side: u32,
    /// Batches before the error estimate is trusted (8).
    pub min_batches: u32,
    /// Stop after about this many rays in all (20 million).
    pub max_rays: u64,
    /// Seed of the jitter.
    pub seed: u64,
}

impl VolumeOptions {
    /// The fewest rays that estimate anything: the minimum of batches
    /// over the whole model. A smaller [`VolumeOptions::max_rays`] would
    /// leave regions with no estimate, not a volume of 0.
    pub fn min_rays(&self) -> u64 {
        u64::from(self.min_batches) * 3 * u64::from(self.rays_per_side).pow(2)
    }
}

impl Default for VolumeOptions {
    fn default() -> Self {
        VolumeOptions {
            rel_error: 1e-3,
            rays_per_side: 128,
            region_rays_per_side: 48,
            min_batches: 8,
            max_rays: 20_000_000,
            seed: 1971,
        }
    }
}

/// One region's measurements.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RegionVolume {
    /// Region name.
    pub region: String,
    /// Volume (units³).
    pub volume: f64,
    /// Standard error of the volume (one sigma, units³).
    pub error: f64,
    /// `error / volume` (infinite when nothing was hit).
    pub rel_error: f64,
    /// Centroid, when the region was hit.
    pub centroid: Option<[f64; 3]>,
    /// Mass in grams, when the region's density is known.
    pub mass_g: Option<f64>,
    /// Standard error of the mass in grams.
    pub mass_error_g: Option<f64>,
    /// True when the target relative error was reached.
    pub converged: bool,
    /// Batches that make up the estimate.
    pub batches: u32,
    /// True when the region is unbounded and was measured inside the
    /// model's box only.
    pub clipped: bool,
}

/// The result of [`volumes`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct VolumeReport {
    /// Model unit.
    pub unit: String,
    /// Target relative error.
    pub rel_error_target: f64,
    /// Rays fired.
    pub rays: u64,
    /// Wall-clock seconds.
    pub seconds: f64,
    /// Every region, deck order.
    pub regions: Vec<RegionVolume>,
    /// Names of the regions that did not reach the target.
    pub not_converged: Vec<String>,
}

impl VolumeReport {
    /// The report as pretty JSON.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("a report serialises")
    }

    /// The report as a table.
    pub fn to_table(&self) -> String {
        let unit = &self.unit;
        let mut text = String::new();
        let _ = writeln!(
            text,
            "{:<24} {:>14} {:>11} {:>9} {:>36} {:>14}",
            "region",
            format!("volume {unit}³"),
            "± (1σ)",
            "rel",
            "centroid (x, y, z)",
            "mass g"
        );
        for region in &self.regions {
            let centroid = region.centroid.map_or("-".to_string(), |c| {
                format!("({}, {}, {})", fmt_g(c[0]), fmt_g(c[1]), fmt_g(c[2]))
            });
            let mass = match (region.mass_g, region.mass_error_g) {
                (Some(mass), Some(error)) => format!("{} ± {}", fmt_g(mass), fmt_g(error)),
                _ => "-".into(),
            };
            let flag = match (region.converged, region.clipped) {
                (true, false) => "",
                (true, true) => "  (clipped to the box)",
                (false, false) => "  (not converged)",
                (false, true) => "  (not converged; clipped to the box)",
            };
            let rel_error = if region.rel_error.is_finite() {
                format!("{:.2e}", region.rel_error)
            } else {
                "-".into()
            };
            let _ = writeln!(
                text,
                "{:<24} {:>14} {:>11} {:>9} {:>36} {:>14}{flag}",
                region.region,
                fmt_g(region.volume),
                fmt_g(region.error),
                rel_error,
                centroid,
                mass
            );
        }
        let _ = writeln!(
            text,
            "{} rays in {:.2} s; target relative error {}",
            self.rays,
            self.seconds,
            fmt_g(self.rel_error_target)
        );
        if self.not_converged.is_empty() {
            let _ = writeln!(text, "every region converged");
        } else {
            let _ = writeln!(
                text,
                "did not converge ({}): {}",
                self.not_converged.len(),
                self.not_converged.join(", ")
            );
        }
        text
    }
}

#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Stats {
    pub(crate) n: u32,
    pub(crate) mean: f64,
    m2: f64,
    moment: DVec3,
}

impl Stats {
    pub(crate) fn add(&mut self, v: f64, m: DVec3) {
        self.n += 1;
        let d = v - self.mean;
        self.mean += d / self.n as f64;
        self.m2 += d * (v - self.mean);
        self.moment += m;
    }

    pub(crate) fn stderr(&self) -> f64 {
        if self.n < 2 {
            return f64::INFINITY;
        }
        (self.m2 / (self.n - 1) as f64 / self.n as f64)
            .max(0.0)
            .sqrt()
    }

    fn converged(&self, rel: f64, min: u32) -> bool {
        self.n >= min && self.mean > 0.0 && self.stderr() <= rel * self.mean
    }
}

/// One batch of a jittered grid over `bx`: along each of x, y and z, one
/// ray through a random point of every cell of an `n`×`n` grid over the
/// box's face. `per_ray(state, ray, length, area, out)` is called for each
/// ray, which runs `length` through the box (padded) and stands for `area`
/// (a third of its cell: the three axes are averaged). Returns one `out`
/// per row of rays, in a fixed order whatever the threads.
pub(crate) fn jittered_batch<State, Out: Default + Send>(
    bx: &Aabb,
    n: u32,
    (seed, id): (u64, u64),
    init: impl Fn() -> State + Sync + Send,
    per_ray: impl Fn(&mut State, &Ray, f64, f64, &mut Out) + Sync + Send,
) -> Vec<Out> {
    let size = bx.size();
    let pad = 1e-3 * size.length() + 1e-9;
    (0..3 * n as u64)
        .into_par_iter()
        .map_init(&init, |state, row| {
            let k = (row / n as u64) as usize;
            let j = row % n as u64;
            let (u, v) = ((k + 1) % 3, (k + 2) % 3);
            let (cu, cv) = (size[u] / n as f64, size[v] / n as f64);
            let area = cu * cv / 3.0;
            let mut out = Out::default();
            for i in 0..n as u64 {
                let key = (row << 20) | i;
                let mut o = DVec3::ZERO;
                o[k] = bx.min[k] - pad;
                o[u] = bx.min[u] + (i as f64 + uniform(seed, id, key, 0)) * cu;
                o[v] = bx.min[v] + (j as f64 + uniform(seed, id, key, 1)) * cv;
                let mut dir = DVec3::ZERO;
                dir[k] = 1.0;
                per_ray(
                    state,
                    &Ray::new(o, dir),
                    size[k] + 2.0 * pad,
                    area,
                    &mut out,
                );
            }
            out
        })
        .collect()
}

/// One batch over `bx` with `n`×`n` cells per axis. Returns, per region
/// hit (only `only` when given), the volume estimate and the first moment.
fn batch(
    model: &Model,
    bx: &Aabb,
    n: u32,
    seed: u64,
    id: u64,
    only: Option<u32>,
) -> Vec<(u32, f64, DVec3)> {
    let rows = jittered_batch(
        bx,
        n,
        (seed, id),
        || RayCheck::new(model),
        |rc, ray, length, area, out: &mut Vec<(u32, f64, DVec3)>| {
            rc.partitions(ray, 0.0, length);
            for p in &rc.parts {
                if only.is_some_and(|r| r != p.region) {
                    continue;
                }
                let len = p.span.b.t - p.span.a.t;
                let mid = ray.at(0.5 * (p.span.a.t + p.span.b.t));
                out.push((p.region, len * area, mid * (len * area)));
            }
        },
    );
    rows.into_iter().flatten().collect()
}

/// The sampled box: `b` with a margin of 3.14 % of its diagonal. Without
/// it, a region that fills its bounds (a box) would have its faces on the
/// cell edges, every batch would give the same answer up to rare misses in
/// the engine's tiny padding of the bounds, and the spread of the batches
/// would understate the error.
fn margin(b: &Aabb) -> Aabb {
    b.padded(0.0314 * b.size().length() + 1e-12)
}

/// Measure every region of `model`. Runs on the current rayon pool.
pub fn volumes(model: &Model, opts: &VolumeOptions) -> Result<VolumeReport, CheckError> {
    if !(opts.rel_error > 0.0 && opts.rel_error < 1.0) {
        return Err(CheckError::Option(format!(
            "the relative error must lie between 0 and 1, found {}",
            opts.rel_error
        )));
    }
    if opts.rays_per_side == 0 || opts.region_rays_per_side == 0 || opts.min_batches < 2 {
        return Err(CheckError::Option(
            "batches need at least one ray per side and two batches".into(),
        ));
    }
    let start = Instant::now();
    let model_box = model.finite_bounds()?;
    let box_volume = model_box.size().x * model_box.size().y * model_box.size().z;
    // Regions whose bounds fill less than an eighth of the box get their
    // own batches when the global ones do not settle them.
    let small: Vec<bool> = (0..model.names.len())
        .map(|region| {
            let bounds = model.region_bounds(region);
            let size = bounds.size();
            !bounds.is_empty() && size.x * size.y * size.z < box_volume / 8.0
        })
        .collect();
    let mut stats = vec![Stats::default(); model.names.len()];
    let rays = global_batches(model, &model_box, opts, &small, &mut stats);
    let rays = targeted_batches(model, opts, &small, &mut stats, rays);
    let mut regions = Vec::with_capacity(stats.len());
    let mut not_converged = Vec::new();
    for (region, region_stats) in stats.iter().enumerate() {
        let measured = region_volume(model, opts, region, region_stats);
        if !measured.converged {
            not_converged.push(measured.region.clone());
        }
        regions.push(measured);
    }
    Ok(VolumeReport {
        unit: model.unit.clone(),
        rel_error_target: opts.rel_error,
        rays,
        seconds: start.elapsed().as_secs_f64(),
        regions,
        not_converged,
    })
}

/// Batches over the whole model's box until every region that is not
/// small has settled and every small one has the minimum of batches, or
/// the global share of the rays is spent. Returns the rays fired.
fn global_batches(
    model: &Model,
    model_box: &Aabb,
    opts: &VolumeOptions,
    small: &[bool],
    stats: &mut [Stats],
) -> u64 {
    let (rel, min) = (opts.rel_error, opts.min_batches);
    let per_batch = 3 * (opts.rays_per_side as u64).pow(2);
    let budget = if small.iter().any(|s| *s) {
        opts.max_rays / 2
    } else {
        opts.max_rays
    };
    let sampled = margin(model_box);
    let mut rays: u64 = 0;
    let mut batch_id: u64 = 0;
    loop {
        let mut sums = vec![(0.0, DVec3::ZERO); stats.len()];
        for (region, volume, moment) in batch(
            model,
            &sampled,
            opts.rays_per_side,
            opts.seed,
            batch_id,
            None,
        ) {
            sums[region as usize].0 += volume;
            sums[region as usize].1 += moment;
        }
        batch_id += 1;
        rays += per_batch;
        for (region_stats, (volume, moment)) in stats.iter_mut().zip(sums) {
            region_stats.add(volume, moment);
        }
        // Regions never hit after the minimum are empty or too thin to see.
        let settled = |st: &Stats| st.converged(rel, min) || (st.n >= min && st.mean == 0.0);
        let regions = 0..stats.len();
        let pending = regions.clone().any(|r| !small[r] && !settled(&stats[r]));
        let more_small = regions.clone().any(|r| small[r] && stats[r].n < min);
        if (!pending && !more_small) || rays + per_batch > budget {
            return rays;
        }
    }
}

/// Batches over the bounds of each small region the global batches left
/// unconverged (its statistics restarted), round robin, until each
/// converges or is seen to be empty, or [`VolumeOptions::max_rays`] is
/// reached. `rays` were fired before; returns the rays fired in all.
fn targeted_batches(
    model: &Model,
    opts: &VolumeOptions,
    small: &[bool],
    stats: &mut [Stats],
    mut rays: u64,
) -> u64 {
    let (rel, min) = (opts.rel_error, opts.min_batches);
    let per_batch = 3 * (opts.region_rays_per_side as u64).pow(2);
    let mut todo: Vec<usize> = (0..stats.len())
        .filter(|&r| small[r] && !stats[r].converged(rel, min))
        .collect();
    for &region in &todo {
        stats[region] = Stats::default();
    }
    while !todo.is_empty() && rays + per_batch <= opts.max_rays {
        let mut next = Vec::new();
        for &region in &todo {
            if rays + per_batch > opts.max_rays {
                next.push(region);
                continue;
            }
            let sampled = margin(&model.region_bounds(region));
            let (mut volume, mut moment) = (0.0, DVec3::ZERO);
            for (_, batch_volume, batch_moment) in batch(
                model,
                &sampled,
                opts.region_rays_per_side,
                opts.seed ^ 0x7a29_e7ed,
                ((region as u64) << 24) | stats[region].n as u64,
                Some(region as u32),
            ) {
                volume += batch_volume;
                moment += batch_moment;
            }
            rays += per_batch;
            stats[region].add(volume, moment);
            let region_stats = stats[region];
            let hopeless = region_stats.n >= min && region_stats.mean == 0.0;
            if !region_stats.converged(rel, min) && !hopeless {
                next.push(region);
            }
        }
        todo = next;
    }
    rays
}

/// What the batches tell of `region`.
fn region_volume(model: &Model, opts: &VolumeOptions, region: usize, st: &Stats) -> RegionVolume {
    let error = if st.mean > 0.0 { st.stderr() } else { 0.0 };
    let centroid = if st.mean > 0.0 {
        Some((st.moment / (st.mean * st.n as f64)).to_array())
    } else {
        None
    };
    let cm3 = model.cm_per_unit.powi(3);
    let (mass_g, mass_error_g) = match model.densities.get(region).copied().flatten() {
        Some(density) => (Some(st.mean * cm3 * density), Some(error * cm3 * density)),
        None => (None, None),
    };
    RegionVolume {
        region: model.names[region].clone(),
        volume: st.mean,
        error,
        rel_error: if st.mean > 0.0 {
            error / st.mean
        } else {
            f64::INFINITY
        },
        centroid,
        mass_g,
        mass_error_g,
        converged: st.converged(opts.rel_error, opts.min_batches),
        batches: st.n,
        clipped: model.region_is_clipped(region),
    }
}
