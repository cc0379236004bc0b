//! `check`: overlaps and voids by grids of rays.

use crate::analyse::{FindingKind, RayCheck};
use crate::model::{CheckError, Model};
use crate::rng::uniform;
use rayon::prelude::*;
use serde::Serialize;
use std::collections::HashMap;
use std::fmt::Write as _;
use std::time::Instant;
use sv_math::{DVec3, Ray};

/// Options for [`check`].
#[derive(Clone, Debug)]
pub struct CheckOptions {
    /// Distance between neighbouring grid rays; default: the spacing that
    /// gives as many rays as a cube gets with [`CheckOptions::rays_per_side`]
    /// rays per side (3 × 200² = 120 000 by default), so elongated models
    /// are not sampled coarsely across their short sides.
    pub spacing: Option<f64>,
    /// Grid rays per side of the equivalent cube when no spacing is given
    /// (200).
    pub rays_per_side: u32,
    /// Overlaps and voids no longer than this along a ray are ignored;
    /// default 1e-5 of the diagonal of the box checked (as
    /// [`default_tolerance`](crate::default_tolerance) for the model's own box).
    pub tolerance: Option<f64>,
    /// Extra rays in random directions through random points of the box.
    pub random: u64,
    /// Seed of the random rays.
    pub seed: u64,
    /// Refuse to fire more grid rays, or more random rays, than this
    /// (guards against a tiny `--spacing` or a huge `--random`).
    pub max_rays: u64,
    /// Fire the rays through this box instead of [`Model::bounds`] (to look
    /// closely at part of a model, or at a model without finite regions).
    /// Nothing outside it is checked.
    pub bounds: Option<sv_math::Aabb>,
    /// Count overlaps with air regions as problems. By default they are
    /// listed apart ([`Report::air_overlaps`]) and do not make the report
    /// unclean: GIFT and BRL-CAD let an air region give way to a solid one,
    /// and decks rely on it (an "inside air" box around the crew).
    pub strict_air: bool,
}

impl Default for CheckOptions {
    fn default() -> Self {
        CheckOptions {
            spacing: None,
            rays_per_side: 200,
            tolerance: None,
            random: 0,
            seed: 1971,
            max_rays: 50_000_000,
            strict_air: false,
            bounds: None,
        }
    }
}

/// How much of a problem was seen.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Problem {
    /// Sum of the problem stretches over every ray (model units).
    pub total_length: f64,
    /// The longest single stretch.
    pub max_length: f64,
    /// Midpoint of the longest stretch: a point inside the problem.
    pub point: [f64; 3],
    /// Number of stretches seen.
    pub hits: u64,
    /// Volume estimate from the grid rays (units³): the summed length times
    /// the area each grid ray stands for, averaged over the three axes.
    pub volume: f64,
}

/// Two regions claiming the same space.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Overlap {
    /// Their names.
    pub regions: [String; 2],
    /// Their indices (0-based, deck order).
    pub region_indices: [usize; 2],
    /// True when at least one of them is an air region.
    pub air: bool,
    /// How much.
    #[serde(flatten)]
    pub problem: Problem,
}

/// Space inside the universe that no region claims.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Void {
    /// The regions met on either side of the gap along the rays (`None`:
    /// the boundary of the universe's hull).
    pub between: [Option<String>; 2],
    /// How much.
    #[serde(flatten)]
    pub problem: Problem,
}

/// A region reaching outside the universe's hull.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Outside {
    /// The region.
    pub region: String,
    /// How much.
    #[serde(flatten)]
    pub problem: Problem,
}

/// The universe a check used.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct UniverseInfo {
    /// What it is and how it was chosen.
    pub description: String,
}

/// The result of [`check`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Report {
    /// Model unit (`in`, `mm`, …).
    pub unit: String,
    /// Number of regions.
    pub regions: usize,
    /// The box the rays cross: lower and upper corners.
    pub bounds: [[f64; 3]; 2],
    /// Grid spacing used.
    pub spacing: f64,
    /// Grid rays fired (all three axes).
    pub grid_rays: u64,
    /// Random rays fired.
    pub random_rays: u64,
    /// Tolerance used.
    pub tolerance: f64,
    /// The universe, if voids were looked for.
    pub universe: Option<UniverseInfo>,
    /// Overlapping pairs, most severe (largest total length) first. Pairs
    /// with an air region are here only with [`CheckOptions::strict_air`].
    pub overlaps: Vec<Overlap>,
    /// Overlapping pairs in which at least one region is air, when they are
    /// not counted as problems.
    pub air_overlaps: Vec<Overlap>,
    /// Voids, largest first.
    pub voids: Vec<Void>,
    /// Regions outside the universe, largest first.
    pub outside: Vec<Outside>,
    /// Regions no ray crossed: empty (subtracted away entirely) or thinner
    /// than the spacing. Listed for information; not counted as problems.
    pub unseen: Vec<String>,
    /// Wall-clock time of the ray casting, seconds.
    pub seconds: f64,
}

impl Report {
    /// True when nothing was found.
    pub fn is_clean(&self) -> bool {
        self.overlaps.is_empty() && self.voids.is_empty() && self.outside.is_empty()
    }

    /// The report as pretty JSON.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("a report serialises")
    }

    /// The report as a human-readable table.
    pub fn to_table(&self) -> String {
        let u = &self.unit;
        let mut s = String::new();
        let _ = writeln!(
            s,
            "checked {} regions with {} grid rays (spacing {} {u}) and {} random rays in {:.2} s; tolerance {} {u}",
            self.regions,
            self.grid_rays,
            fmt_g(self.spacing),
            self.random_rays,
            self.seconds,
            fmt_g(self.tolerance)
        );
        let b = &self.bounds;
        let _ = writeln!(
            s,
            "box ({}, {}, {}) to ({}, {}, {})",
            fmt_g(b[0][0]),
            fmt_g(b[0][1]),
            fmt_g(b[0][2]),
            fmt_g(b[1][0]),
            fmt_g(b[1][1]),
            fmt_g(b[1][2])
        );
        match &self.universe {
            Some(un) => {
                let _ = writeln!(s, "universe: {}", un.description);
            }
            None => {
                let _ = writeln!(
                    s,
                    "universe: none (voids not looked for; give --universe REGION|BODY)"
                );
            }
        }
        let header = |s: &mut String, first: &str| {
            let _ = writeln!(
                s,
                "  {:<32} {:>12} {:>12} {:>12} {:>7}  point (x, y, z)",
                first, "total len", "max len", "volume", "hits"
            );
        };
        // Coordinates within rounding of zero print as 0.
        let diag = (0..3)
            .map(|k| (self.bounds[1][k] - self.bounds[0][k]).powi(2))
            .sum::<f64>()
            .sqrt();
        let coord = |v: f64| fmt_g(if v.abs() < 1e-12 * diag { 0.0 } else { v });
        let row = |s: &mut String, name: String, p: &Problem| {
            let _ = writeln!(
                s,
                "  {:<32} {:>12} {:>12} {:>12} {:>7}  ({}, {}, {})",
                name,
                fmt_g(p.total_length),
                fmt_g(p.max_length),
                fmt_g(p.volume),
                p.hits,
                coord(p.point[0]),
                coord(p.point[1]),
                coord(p.point[2])
            );
        };
        if self.overlaps.is_empty() {
            let _ = writeln!(s, "no overlaps");
        } else {
            let _ = writeln!(s, "{} overlapping pairs:", self.overlaps.len());
            header(&mut s, "regions");
            for o in &self.overlaps {
                row(
                    &mut s,
                    format!("{} × {}", o.regions[0], o.regions[1]),
                    &o.problem,
                );
            }
        }
        if !self.air_overlaps.is_empty() {
            let _ = writeln!(
                s,
                "{} overlapping pairs with air regions (not counted: air gives way to solids, as in GIFT and BRL-CAD; --strict-air counts them):",
                self.air_overlaps.len()
            );
            header(&mut s, "regions");
            for o in &self.air_overlaps {
                row(
                    &mut s,
                    format!("{} × {}", o.regions[0], o.regions[1]),
                    &o.problem,
                );
            }
        }
        if self.universe.is_some() {
            if self.voids.is_empty() {
                let _ = writeln!(s, "no voids");
            } else {
                let _ = writeln!(s, "{} voids:", self.voids.len());
                header(&mut s, "between");
                for v in &self.voids {
                    let n = |x: &Option<String>| x.clone().unwrap_or_else(|| "(universe)".into());
                    row(
                        &mut s,
                        format!("{} | {}", n(&v.between[0]), n(&v.between[1])),
                        &v.problem,
                    );
                }
            }
            if !self.outside.is_empty() {
                let _ = writeln!(
                    s,
                    "{} regions reach outside the universe:",
                    self.outside.len()
                );
                header(&mut s, "region");
                for o in &self.outside {
                    row(&mut s, o.region.clone(), &o.problem);
                }
            }
        }
        if !self.unseen.is_empty() {
            let _ = writeln!(
                s,
                "{} regions met by no ray (empty, or thinner than the spacing): {}",
                self.unseen.len(),
                self.unseen.join(", ")
            );
        }
        let _ = writeln!(
            s,
            "{}",
            if self.is_clean() {
                "clean"
            } else {
                "problems found"
            }
        );
        s
    }
}

/// A number in a compact form (up to 6 significant digits).
pub(crate) fn fmt_g(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if !(1e-4..1e7).contains(&a) {
        return format!("{v:.4e}");
    }
    let digits = (5 - a.log10().floor() as i32).clamp(0, 10) as usize;
    let s = format!("{v:.digits$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

#[derive(Clone, Copy, Debug)]
struct Acc {
    total: f64,
    weighted: f64,
    max: f64,
    point: DVec3,
    at: u64,
    hits: u64,
}

impl Acc {
    fn merge(&mut self, o: &Acc) {
        self.total += o.total;
        self.weighted += o.weighted;
        self.hits += o.hits;
        if o.max > self.max || (o.max == self.max && o.at < self.at) {
            self.max = o.max;
            self.point = o.point;
            self.at = o.at;
        }
    }
}

/// The grid of one check: per axis, counts and cell sizes.
struct Grid {
    lo: DVec3,
    size: DVec3,
    pad: f64,
    n: [(u64, u64); 3],
    cell: [(f64, f64); 3],
    first: [u64; 4],
}

/// Grid cells of about `d` across `len`: rounding noise (2/0.01 =
/// 200.00000000000003) does not add a cell.
fn cells(len: f64, d: f64) -> f64 {
    (len / d * (1.0 - 1e-12)).ceil()
}

const FRAC_U: f64 = 0.561_803_398_874_989_5;
const FRAC_V: f64 = 0.458_578_643_762_690_5;

impl Grid {
    fn new(lo: DVec3, hi: DVec3, d: f64) -> Grid {
        let size = hi - lo;
        let count = |len: f64| (cells(len, d) as u64).max(1);
        let mut n = [(0, 0); 3];
        let mut cell = [(0.0, 0.0); 3];
        let mut first = [0u64; 4];
        for k in 0..3 {
            let (u, v) = ((k + 1) % 3, (k + 2) % 3);
            n[k] = (count(size[u]), count(size[v]));
            cell[k] = (size[u] / n[k].0 as f64, size[v] / n[k].1 as f64);
            first[k + 1] = first[k] + n[k].0 * n[k].1;
        }
        Grid {
            lo,
            size,
            pad: 0.01 * size.length() + 1e-9,
            n,
            cell,
            first,
        }
    }

    fn total(&self) -> u64 {
        self.first[3]
    }

    /// Ray `idx` of the grid, its t range and the area it stands for.
    fn ray(&self, idx: u64) -> (Ray, f64, f64) {
        let k = (0..3).find(|&k| idx < self.first[k + 1]).unwrap_or(2);
        let local = idx - self.first[k];
        let (i, j) = (local % self.n[k].0, local / self.n[k].0);
        let (u, v) = ((k + 1) % 3, (k + 2) % 3);
        let mut o = DVec3::ZERO;
        o[k] = self.lo[k] - self.pad;
        o[u] = self.lo[u] + (i as f64 + FRAC_U) * self.cell[k].0;
        o[v] = self.lo[v] + (j as f64 + FRAC_V) * self.cell[k].1;
        let mut dir = DVec3::ZERO;
        dir[k] = 1.0;
        (
            Ray::new(o, dir),
            self.size[k] + 2.0 * self.pad,
            self.cell[k].0 * self.cell[k].1,
        )
    }
}

/// A random ray through a random point of the box, and its range inside
/// the padded box.
fn random_ray(lo: DVec3, hi: DVec3, seed: u64, i: u64) -> Option<(Ray, f64, f64)> {
    let r = |c: u64| uniform(seed, i, c, 0x5eed);
    let z = 2.0 * r(0) - 1.0;
    let phi = std::f64::consts::TAU * r(1);
    let s = (1.0 - z * z).max(0.0).sqrt();
    let dir = DVec3::new(s * phi.cos(), s * phi.sin(), z);
    let p = lo + (hi - lo) * DVec3::new(r(2), r(3), r(4));
    let pad = 0.01 * (hi - lo).length() + 1e-9;
    let bx = sv_math::Aabb::new(lo, hi).padded(pad);
    let ray = Ray::new(p - dir * (2.0 * (hi - lo).length() + 1.0), dir);
    bx.ray_range(&ray).map(|(a, b)| (ray, a.max(0.0), b))
}

/// Fire the grids (and random rays) through `model` and gather every
/// overlap, void and stretch outside the universe. Runs on the current
/// rayon pool.
pub fn check(model: &Model, opts: &CheckOptions) -> Result<Report, CheckError> {
    let start = Instant::now();
    let bx = match opts.bounds {
        Some(b) if !b.is_empty() && b.is_finite() && b.size().min_element() >= 0.0 => b,
        Some(_) => {
            return Err(CheckError::Option(
                "the box must have finite corners, lower before upper".into(),
            ))
        }
        None => model.finite_bounds()?,
    };
    let size = bx.size();
    let longest = size.max_element();
    let spacing = match opts.spacing {
        Some(d) if d > 0.0 && d.is_finite() => d,
        Some(d) => {
            return Err(CheckError::Option(format!(
                "the spacing must be positive, found {d}"
            )))
        }
        None => {
            if opts.rays_per_side == 0 {
                return Err(CheckError::Option(
                    "rays per side must be at least 1".into(),
                ));
            }
            // As many rays as a cube with `rays_per_side` per side gets:
            // Σ face areas / d² = 3 n².
            let areas = size.x * size.y + size.y * size.z + size.z * size.x;
            let n = opts.rays_per_side as f64;
            if areas > 0.0 {
                (areas / (3.0 * n * n)).sqrt()
            } else if longest > 0.0 {
                longest / n
            } else {
                1.0
            }
        }
    };
    let tol = match opts.tolerance {
        Some(t) if t >= 0.0 && t.is_finite() => t,
        Some(t) => {
            return Err(CheckError::Option(format!(
                "the tolerance must be zero or more, found {t}"
            )))
        }
        // 1e-5 of the diagonal of the box checked.
        None => (1e-5 * bx.size().length()).max(1e-12),
    };
    // Count before allocating anything.
    let mut count = 0f64;
    for k in 0..3 {
        let (u, v) = ((k + 1) % 3, (k + 2) % 3);
        count += cells(size[u], spacing).max(1.0) * cells(size[v], spacing).max(1.0);
    }
    if opts.random > opts.max_rays {
        return Err(CheckError::Option(format!(
            "{} random rays are more than the limit of {}",
            opts.random, opts.max_rays
        )));
    }
    if count > opts.max_rays as f64 {
        return Err(CheckError::Option(format!(
            "a spacing of {} gives {count:.0} grid rays, more than the limit of {}; use a larger spacing",
            fmt_g(spacing),
            opts.max_rays
        )));
    }
    let grid = Grid::new(bx.min, bx.max, spacing);
    let n_grid = grid.total();
    let n = n_grid + opts.random;
    const CHUNK: u64 = 256;
    let chunks = n.div_ceil(CHUNK);
    let nreg = model.names.len();
    let parts: Vec<(HashMap<FindingKind, Acc>, Vec<bool>)> = (0..chunks)
        .into_par_iter()
        .map_init(
            || RayCheck::new(model),
            |rc, c| {
                let mut acc: HashMap<FindingKind, Acc> = HashMap::new();
                let mut seen = vec![false; nreg];
                for idx in c * CHUNK..((c + 1) * CHUNK).min(n) {
                    let (ray, t0, t1, area) = if idx < n_grid {
                        let (r, t1, a) = grid.ray(idx);
                        (r, 0.0, t1, a)
                    } else {
                        match random_ray(bx.min, bx.max, opts.seed, idx - n_grid) {
                            Some((r, a, b)) => (r, a, b, 0.0),
                            None => continue,
                        }
                    };
                    rc.run(&ray, t0, t1, tol);
                    for p in &rc.parts {
                        seen[p.region as usize] = true;
                    }
                    for f in &rc.findings {
                        let len = f.t1 - f.t0;
                        let e = Acc {
                            total: len,
                            weighted: len * area,
                            max: len,
                            point: ray.at(0.5 * (f.t0 + f.t1)),
                            at: idx,
                            hits: 1,
                        };
                        acc.entry(f.kind).and_modify(|a| a.merge(&e)).or_insert(e);
                    }
                }
                (acc, seen)
            },
        )
        .collect();
    let mut all: HashMap<FindingKind, Acc> = HashMap::new();
    let mut seen = vec![false; nreg];
    for (p, s) in parts {
        for (a, b) in seen.iter_mut().zip(s) {
            *a |= b;
        }
        let mut keys: Vec<_> = p.into_iter().collect();
        keys.sort_by_key(|a| a.0);
        for (k, a) in keys {
            all.entry(k).and_modify(|x| x.merge(&a)).or_insert(a);
        }
    }
    let problem = |a: &Acc| Problem {
        total_length: a.total,
        max_length: a.max,
        point: a.point.to_array(),
        hits: a.hits,
        volume: a.weighted / 3.0,
    };
    let name = |r: u32| model.names[r as usize].clone();
    let mut overlaps = Vec::new();
    let mut air_overlaps = Vec::new();
    let mut voids = Vec::new();
    let mut outside = Vec::new();
    let mut entries: Vec<_> = all.into_iter().collect();
    entries.sort_by(|a, b| b.1.total.total_cmp(&a.1.total).then(a.0.cmp(&b.0)));
    for (k, a) in &entries {
        match *k {
            FindingKind::Overlap(x, y) => {
                let air = model.air.get(x as usize).copied().unwrap_or(false)
                    || model.air.get(y as usize).copied().unwrap_or(false);
                let o = Overlap {
                    regions: [name(x), name(y)],
                    region_indices: [x as usize, y as usize],
                    air,
                    problem: problem(a),
                };
                if air && !opts.strict_air {
                    air_overlaps.push(o);
                } else {
                    overlaps.push(o);
                }
            }
            FindingKind::Void(x, y) => voids.push(Void {
                between: [x.map(name), y.map(name)],
                problem: problem(a),
            }),
            FindingKind::Outside(r) => outside.push(Outside {
                region: name(r),
                problem: problem(a),
            }),
        }
    }
    Ok(Report {
        unit: model.unit.clone(),
        regions: model.names.len(),
        bounds: [bx.min.to_array(), bx.max.to_array()],
        spacing,
        grid_rays: n_grid,
        random_rays: opts.random,
        tolerance: tol,
        universe: model
            .universe_note
            .clone()
            .map(|description| UniverseInfo { description }),
        overlaps,
        air_overlaps,
        voids,
        outside,
        unseen: (0..nreg)
            .filter(|&r| !seen[r])
            .map(|r| model.names[r].clone())
            .collect(),
        seconds: start.elapsed().as_secs_f64(),
    })
}
