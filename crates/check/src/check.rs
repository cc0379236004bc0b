//! `check`: overlaps and voids by grids of rays.

use crate::analyse::{FindingKind, RayCheck};
use crate::model::{CheckError, Model};
use crate::report::{fmt_g, Outside, Overlap, Problem, Report, UniverseInfo, Void};
use crate::rng::uniform;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};
use std::ops::Range;
use std::time::Instant;
use sv_math::{Aabb, DVec3, Ray};
use sv_trace::Partition;

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

/// The summed stretches of one kind of finding.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
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

    /// One past the last ray of the row of grid ray `idx`.
    fn row_end(&self, idx: u64) -> u64 {
        let k = (0..3).find(|&k| idx < self.first[k + 1]).unwrap_or(2);
        let row = self.n[k].0;
        self.first[k] + ((idx - self.first[k]) / row + 1) * row
    }

    /// The first and last of grid rays `rays` (one run along a row) that
    /// may meet `bounds`: a ray more each side than those that pass
    /// within them, so that rounding does not leave one out.
    fn rays_near(&self, rays: Range<u64>, bounds: &Aabb) -> (u64, u64) {
        let k = (0..3)
            .find(|&k| rays.start < self.first[k + 1])
            .unwrap_or(2);
        let u = (k + 1) % 3;
        let row_start = rays.start - (rays.start - self.first[k]) % self.n[k].0;
        // Ray i of the row passes at lo[u] + (i + FRAC_U) * cell.
        let at = |x: f64| (x - self.lo[u]) / self.cell[k].0 - FRAC_U;
        let (a, b) = (at(bounds.min[u]), at(bounds.max[u]));
        let first = if a.is_finite() {
            row_start.saturating_add_signed((a.ceil() as i64).saturating_sub(1))
        } else {
            rays.start
        };
        let last = if b.is_finite() {
            row_start.saturating_add_signed((b.floor() as i64).saturating_add(1))
        } else {
            rays.end - 1
        };
        (first.max(rays.start), last.min(rays.end - 1))
    }

    /// The box that grid rays `first` to `last` (one row) cross over
    /// their range.
    fn run_box(&self, first: u64, last: u64) -> Aabb {
        let (a, t1, _) = self.ray(first);
        let (b, _, _) = self.ray(last);
        Aabb::EMPTY.including(a.origin).including(b.at(t1))
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

/// Rays are fired in chunks of this many; the chunks' findings are summed
/// in chunk order, so the sums depend neither on the number of threads
/// nor on how the chunks are shared out ([`check_part`]).
const CHUNK: u64 = 256;

/// One chunk's findings by kind, in order of kind.
type ChunkFindings = Vec<(FindingKind, Acc)>;

/// What a check fires: the box, the grid through it and the tolerance.
struct Plan {
    checked_box: Aabb,
    spacing: f64,
    tolerance: f64,
    grid: Grid,
}

impl Plan {
    fn new(model: &Model, opts: &CheckOptions) -> Result<Plan, CheckError> {
        let checked_box = checked_box(model, opts)?;
        let spacing = grid_spacing(checked_box.size(), opts)?;
        let tolerance = match opts.tolerance {
            Some(t) if t >= 0.0 && t.is_finite() => t,
            Some(t) => {
                return Err(CheckError::Option(format!(
                    "the tolerance must be zero or more, found {t}"
                )))
            }
            // 1e-5 of the diagonal of the box checked.
            None => (1e-5 * checked_box.size().length()).max(1e-12),
        };
        check_ray_counts(checked_box.size(), spacing, opts)?;
        let grid = Grid::new(checked_box.min, checked_box.max, spacing);
        Ok(Plan {
            checked_box,
            spacing,
            tolerance,
            grid,
        })
    }

    fn chunk_count(&self, opts: &CheckOptions) -> u64 {
        (self.grid.total() + opts.random).div_ceil(CHUNK)
    }
}

/// The findings of a share of a check's rays, chunk by chunk, to be
/// summed with the other shares by [`check_merge`]: a check split across
/// processes or machines. Serialisable, so shares travel as JSON.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CheckPart {
    /// The chunks of rays fired (see [`check_chunks`]).
    pub chunks: Range<u64>,
    /// Per chunk, the findings by kind, in order of kind.
    found: Vec<ChunkFindings>,
    /// The regions any ray of the share met.
    seen: Vec<bool>,
}

/// How many chunks of rays a check with `opts` fires: [`check_part`]
/// takes a range of them.
pub fn check_chunks(model: &Model, opts: &CheckOptions) -> Result<u64, CheckError> {
    Ok(Plan::new(model, opts)?.chunk_count(opts))
}

/// Fire the chunks `chunks` of the rays of a check with `opts` (on the
/// current rayon pool).
pub fn check_part(
    model: &Model,
    opts: &CheckOptions,
    chunks: Range<u64>,
) -> Result<CheckPart, CheckError> {
    let plan = Plan::new(model, opts)?;
    let chunks = chunks.start.min(plan.chunk_count(opts))..chunks.end.min(plan.chunk_count(opts));
    let (found, seen) = fire_rays(model, &plan, opts, chunks.clone());
    Ok(CheckPart {
        chunks,
        found,
        seen,
    })
}

/// The report of a check whose rays were fired in `parts` (any order;
/// together they must hold every chunk once): the same report, to the
/// bit, as [`check`] makes (but for the time taken).
pub fn check_merge(
    model: &Model,
    opts: &CheckOptions,
    parts: &[CheckPart],
) -> Result<Report, CheckError> {
    let start = Instant::now();
    let plan = Plan::new(model, opts)?;
    let mut ordered: Vec<&CheckPart> = parts.iter().collect();
    ordered.sort_by_key(|part| part.chunks.start);
    let mut next = 0;
    for part in &ordered {
        let consistent = part.found.len() as u64 == part.chunks.end - part.chunks.start
            && part.seen.len() == model.names.len();
        if part.chunks.start != next || !consistent {
            return Err(CheckError::Option(format!(
                "the parts of the check do not cover its chunks once each: chunk {next} is missing or repeated"
            )));
        }
        next = part.chunks.end;
    }
    if next != plan.chunk_count(opts) {
        return Err(CheckError::Option(format!(
            "the parts of the check end at chunk {next} of {}",
            plan.chunk_count(opts)
        )));
    }
    Ok(report(model, opts, &plan, &ordered, start))
}

/// Fire the grids (and random rays) through `model` and gather every
/// overlap, void and stretch outside the universe. Runs on the current
/// rayon pool.
pub fn check(model: &Model, opts: &CheckOptions) -> Result<Report, CheckError> {
    let start = Instant::now();
    let plan = Plan::new(model, opts)?;
    let chunks = 0..plan.chunk_count(opts);
    let (found, seen) = fire_rays(model, &plan, opts, chunks.clone());
    let part = CheckPart {
        chunks,
        found,
        seen,
    };
    Ok(report(model, opts, &plan, &[&part], start))
}

/// The report of the chunks of `parts`, summed in chunk order.
fn report(
    model: &Model,
    opts: &CheckOptions,
    plan: &Plan,
    parts: &[&CheckPart],
    start: Instant,
) -> Report {
    let mut findings: HashMap<FindingKind, Acc> = HashMap::new();
    let mut seen = vec![false; model.names.len()];
    for part in parts {
        for (any, this) in seen.iter_mut().zip(&part.seen) {
            *any |= this;
        }
        for (kind, acc) in part.found.iter().flatten() {
            findings
                .entry(*kind)
                .and_modify(|sum| sum.merge(acc))
                .or_insert(*acc);
        }
    }
    // A lattice-filled cell is seen when its contents are.
    model.container_seen(&mut seen);
    let sorted = sort_findings(model, findings, opts.strict_air);
    let checked_box = plan.checked_box;
    // Regions no ray met, beyond the model (black holes) aside: those the
    // box reaches were missed, the others were not looked at.
    let (unseen, beyond_box): (Vec<usize>, Vec<usize>) = (0..model.names.len())
        .filter(|&region| !seen[region] && !model.outside.get(region).copied().unwrap_or(false))
        .partition(|&region| {
            !model.region_bounds[region]
                .intersection(&checked_box)
                .is_empty()
        });
    let names = |regions: Vec<usize>| -> Vec<String> {
        regions
            .into_iter()
            .map(|r| model.names[r].clone())
            .collect()
    };
    let (unseen, beyond_box) = (names(unseen), names(beyond_box));
    Report {
        unit: model.unit.clone(),
        regions: model.names.len(),
        bounds: [checked_box.min.to_array(), checked_box.max.to_array()],
        spacing: plan.spacing,
        grid_rays: plan.grid.total(),
        random_rays: opts.random,
        tolerance: plan.tolerance,
        universe: model
            .universe_note
            .clone()
            .map(|description| UniverseInfo { description }),
        overlaps: sorted.overlaps,
        air_overlaps: sorted.air_overlaps,
        voids: sorted.voids,
        outside: sorted.outside,
        unseen,
        beyond_box,
        seconds: start.elapsed().as_secs_f64(),
    }
}

/// The box the rays cross: the one asked for, or the model's bounds.
fn checked_box(model: &Model, opts: &CheckOptions) -> Result<Aabb, CheckError> {
    match opts.bounds {
        Some(b) if !b.is_empty() && b.is_finite() && b.size().min_element() >= 0.0 => Ok(b),
        Some(_) => Err(CheckError::Option(
            "the box must have finite corners, lower before upper".into(),
        )),
        None => model.check_bounds(),
    }
}

/// The distance between grid rays across a box of `size`.
fn grid_spacing(size: DVec3, opts: &CheckOptions) -> Result<f64, CheckError> {
    match opts.spacing {
        Some(d) if d > 0.0 && d.is_finite() => Ok(d),
        Some(d) => Err(CheckError::Option(format!(
            "the spacing must be positive, found {d}"
        ))),
        None => {
            if opts.rays_per_side == 0 {
                return Err(CheckError::Option(
                    "rays per side must be at least 1".into(),
                ));
            }
            // As many rays as a cube with `rays_per_side` per side gets:
            // Σ face areas / d² = 3 n².
            let areas = size.x * size.y + size.y * size.z + size.z * size.x;
            let per_side = opts.rays_per_side as f64;
            let longest = size.max_element();
            Ok(if areas > 0.0 {
                (areas / (3.0 * per_side * per_side)).sqrt()
            } else if longest > 0.0 {
                longest / per_side
            } else {
                1.0
            })
        }
    }
}

/// Refuse more grid or random rays than [`CheckOptions::max_rays`], counted
/// before anything is allocated.
fn check_ray_counts(size: DVec3, spacing: f64, opts: &CheckOptions) -> Result<(), CheckError> {
    let mut grid_rays = 0f64;
    for axis in 0..3 {
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        grid_rays += cells(size[u], spacing).max(1.0) * cells(size[v], spacing).max(1.0);
    }
    if opts.random > opts.max_rays {
        return Err(CheckError::Option(format!(
            "{} random rays are more than the limit of {}",
            opts.random, opts.max_rays
        )));
    }
    if grid_rays > opts.max_rays as f64 {
        return Err(CheckError::Option(format!(
            "a spacing of {} gives {grid_rays:.0} grid rays, more than the limit of {}; use a larger spacing",
            fmt_g(spacing),
            opts.max_rays
        )));
    }
    Ok(())
}

/// Fire the chunks `chunks` of the grid and random rays on the rayon
/// pool: per chunk, every kind of finding with its stretches summed (in
/// order of kind), and which regions any ray met.
fn fire_rays(
    model: &Model,
    plan: &Plan,
    opts: &CheckOptions,
    chunks: Range<u64>,
) -> (Vec<ChunkFindings>, Vec<bool>) {
    let fired: Vec<(ChunkFindings, Vec<bool>)> = chunks
        .into_par_iter()
        .map_init(
            || Worker::new(model),
            |worker, chunk| fire_chunk(model, plan, opts, worker, chunk),
        )
        .collect();
    let mut seen = vec![false; model.names.len()];
    let mut found = Vec::with_capacity(fired.len());
    for (entries, chunk_seen) in fired {
        for (any, this) in seen.iter_mut().zip(chunk_seen) {
            *any |= this;
        }
        found.push(entries);
    }
    (found, seen)
}

/// The zones a run of grid rays along one row can meet: those whose
/// bounds meet the box the run crosses, listed once for the run, each with
/// the rays of the run that pass near its bounds, so that the rays neither
/// walk the hierarchy nor test the boxes of zones far beside them.
#[derive(Default)]
struct RowZones {
    /// The run of rays listed.
    rays: Range<u64>,
    /// False when the hierarchy was too deep to list the zones: the rays
    /// walk it.
    listed: bool,
    /// The zones listed, each with the first and last ray of the run that
    /// may meet it (up to a ray more each side), by first ray.
    near: Vec<(u64, u64, u32)>,
    /// How many of `near` the rays so far have reached.
    next: usize,
    /// The zones near the current ray, and the last ray near each.
    zones: Vec<u32>,
    last: Vec<u64>,
    scratch: Vec<u32>,
}

impl RowZones {
    /// The zones grid rays `rays` (in one row) may meet (`None`: walk the
    /// hierarchy); listed anew for the rest of their row within the chunk
    /// ending at `end` when the last list does not cover them. Rays come
    /// in order.
    fn for_rays(
        &mut self,
        model: &Model,
        grid: &Grid,
        rays: Range<u64>,
        end: u64,
    ) -> Option<&[u32]> {
        if !self.rays.contains(&rays.start) {
            self.list(model, grid, rays.start..grid.row_end(rays.start).min(end));
        }
        if !self.listed {
            return None;
        }
        while let Some(&(first, last, zone)) = self.near.get(self.next) {
            if first >= rays.end {
                break;
            }
            self.zones.push(zone);
            self.last.push(last);
            self.next += 1;
        }
        // Drop the zones the run has passed.
        let mut kept = 0;
        for at in 0..self.zones.len() {
            if self.last[at] >= rays.start {
                self.zones[kept] = self.zones[at];
                self.last[kept] = self.last[at];
                kept += 1;
            }
        }
        self.zones.truncate(kept);
        self.last.truncate(kept);
        Some(&self.zones)
    }

    /// List the zones of the run `rays`.
    fn list(&mut self, model: &Model, grid: &Grid, rays: Range<u64>) {
        let crossed = grid.run_box(rays.start, rays.end - 1);
        self.listed = model.prepared.all_zones_in_box(&crossed, &mut self.scratch);
        self.near.clear();
        self.zones.clear();
        self.last.clear();
        self.next = 0;
        let tolerance = model.prepared.tolerance();
        for &zone in &self.scratch {
            let bounds = model.prepared.zone_bounds(zone).padded(tolerance);
            let (first, last) = grid.rays_near(rays.clone(), &bounds);
            self.near.push((first, last, zone));
        }
        self.near.sort_unstable();
        self.rays = rays;
    }
}

/// Grid rays traced together: as many as the widest vector lanes hold.
const PACKET: u64 = 8;

/// Working memory of a thread: the rays' classification, the zones of the
/// row under way, and a packet's rays and partitions.
struct Worker<'a> {
    ray_check: RayCheck<'a>,
    row: RowZones,
    rays: Vec<Ray>,
    parts: Vec<Vec<Partition>>,
}

impl<'a> Worker<'a> {
    fn new(model: &'a Model) -> Worker<'a> {
        Worker {
            ray_check: RayCheck::new(model),
            row: RowZones::default(),
            rays: Vec::with_capacity(PACKET as usize),
            parts: vec![Vec::new(); PACKET as usize],
        }
    }
}

/// Fire the rays of chunk `chunk`: its findings by kind (in order of kind)
/// and which regions its rays met. Grid rays go in packets along their
/// row; the findings are summed ray by ray in the order of the rays.
fn fire_chunk(
    model: &Model,
    plan: &Plan,
    opts: &CheckOptions,
    worker: &mut Worker,
    chunk: u64,
) -> (ChunkFindings, Vec<bool>) {
    let (grid, checked_box, tolerance) = (&plan.grid, &plan.checked_box, plan.tolerance);
    let grid_rays = grid.total();
    let end = ((chunk + 1) * CHUNK).min(grid_rays + opts.random);
    let mut found: KindMap = KindMap::default();
    let mut seen = vec![false; model.names.len()];
    let mut index = chunk * CHUNK;
    while index < end.min(grid_rays) {
        let packet = index..(index + PACKET).min(grid.row_end(index)).min(end);
        let (_, t1, area) = grid.ray(index);
        worker.rays.clear();
        worker.rays.extend(packet.clone().map(|i| grid.ray(i).0));
        let zones = worker.row.for_rays(model, grid, packet.clone(), end);
        let Worker {
            ray_check,
            rays,
            parts,
            ..
        } = worker;
        ray_check.partitions_of_rays(zones, rays, 0.0, t1, parts);
        for (at, (ray, ray_parts)) in packet.clone().zip(rays.iter().zip(parts.iter_mut())) {
            ray_check.run_on(ray_parts, ray, 0.0, t1, tolerance);
            gather(ray_check, ray, at, area, &mut found, &mut seen);
        }
        index = packet.end;
    }
    for random_index in index.max(grid_rays) - grid_rays..end.saturating_sub(grid_rays) {
        let (lo, hi) = (checked_box.min, checked_box.max);
        if let Some((ray, t0, t1)) = random_ray(lo, hi, opts.seed, random_index) {
            let ray_check = &mut worker.ray_check;
            ray_check.run(&ray, t0, t1, tolerance);
            gather(
                ray_check,
                &ray,
                grid_rays + random_index,
                0.0,
                &mut found,
                &mut seen,
            );
        }
    }
    let mut entries: Vec<_> = found.into_iter().collect();
    entries.sort_by_key(|entry| entry.0);
    (entries, seen)
}

/// Add the findings of ray `index` (standing for `area`) to `found`, and
/// mark the regions it met in `seen`.
fn gather(
    ray_check: &RayCheck,
    ray: &Ray,
    index: u64,
    area: f64,
    found: &mut KindMap,
    seen: &mut [bool],
) {
    for part in &ray_check.parts {
        seen[part.region as usize] = true;
    }
    for finding in &ray_check.findings {
        let length = finding.t1 - finding.t0;
        let stretch = Acc {
            total: length,
            weighted: length * area,
            max: length,
            point: ray.at(0.5 * (finding.t0 + finding.t1)),
            at: index,
            hits: 1,
        };
        found
            .entry(finding.kind)
            .and_modify(|acc| acc.merge(&stretch))
            .or_insert(stretch);
    }
}

/// A chunk's findings by kind. The keys are a few small integers, which
/// the standard library's keyed hash (made to resist crafted keys) spent
/// more time on than the sums.
type KindMap = HashMap<FindingKind, Acc, BuildHasherDefault<KindHasher>>;

/// A multiplicative hash of a [`FindingKind`]'s integers (as FxHash).
#[derive(Default)]
struct KindHasher(u64);

impl Hasher for KindHasher {
    fn finish(&self) -> u64 {
        self.0
    }

    fn write(&mut self, bytes: &[u8]) {
        for &byte in bytes {
            self.write_u64(u64::from(byte));
        }
    }

    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(5) ^ x).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }

    fn write_u32(&mut self, x: u32) {
        self.write_u64(u64::from(x));
    }

    fn write_usize(&mut self, x: usize) {
        self.write_u64(x as u64);
    }

    fn write_isize(&mut self, x: isize) {
        self.write_u64(x as u64);
    }
}

/// The findings of a check, by kind, each list largest first.
struct Sorted {
    overlaps: Vec<Overlap>,
    air_overlaps: Vec<Overlap>,
    voids: Vec<Void>,
    outside: Vec<Outside>,
}

/// Sort the summed findings into the report's lists, largest total length
/// first; overlaps with air apart unless `strict_air`.
fn sort_findings(model: &Model, found: HashMap<FindingKind, Acc>, strict_air: bool) -> Sorted {
    let problem = |acc: &Acc| Problem {
        total_length: acc.total,
        max_length: acc.max,
        point: acc.point.to_array(),
        hits: acc.hits,
        volume: acc.weighted / 3.0,
    };
    let name = |region: u32| model.names[region as usize].clone();
    let mut sorted = Sorted {
        overlaps: Vec::new(),
        air_overlaps: Vec::new(),
        voids: Vec::new(),
        outside: Vec::new(),
    };
    let mut entries: Vec<_> = found.into_iter().collect();
    entries.sort_by(|a, b| b.1.total.total_cmp(&a.1.total).then(a.0.cmp(&b.0)));
    for (kind, acc) in &entries {
        match *kind {
            FindingKind::Overlap(first, second) => {
                let air = model.is_air_overlap(first as usize, second as usize);
                let overlap = Overlap {
                    regions: [name(first), name(second)],
                    region_indices: [first as usize, second as usize],
                    air,
                    problem: problem(acc),
                };
                if air && !strict_air {
                    sorted.air_overlaps.push(overlap);
                } else {
                    sorted.overlaps.push(overlap);
                }
            }
            FindingKind::Void(before, after) => sorted.voids.push(Void {
                between: [before.map(name), after.map(name)],
                problem: problem(acc),
            }),
            FindingKind::Outside(region) => sorted.outside.push(Outside {
                region: name(region),
                problem: problem(acc),
            }),
        }
    }
    sorted
}
