//! Firing a check's rays: chunk by chunk on the rayon pool, grid rays in
//! packets along their rows, each chunk's findings summed by kind.

use crate::analyse::{Finding, FindingKind, RayCheck};
use crate::check::{CheckOptions, Plan};
use crate::grid::random_ray;
use crate::model::Model;
use crate::refine::{Bundle, Signatures};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;
use std::ops::Range;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use sv_math::{Aabb, DVec3, Ray};
use sv_trace::{Partition, PerThread, Prepared, RaysShare};

/// The summed stretches of one kind of finding.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub(crate) struct Acc {
    pub total: f64,
    pub weighted: f64,
    pub max: f64,
    pub point: DVec3,
    pub at: u64,
    pub hits: u64,
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

/// Rays are fired in chunks of this many; the chunks' findings are summed
/// in chunk order, so the sums depend neither on the number of threads
/// nor on how the chunks are shared out ([`check_part`](crate::check_part)).
pub(crate) const CHUNK: u64 = 256;

/// One chunk's findings by kind, in order of kind.
pub(crate) type ChunkFindings = Vec<(FindingKind, Acc)>;

/// The findings of chunks summed in chunk order, and the regions their
/// rays met.
pub(crate) struct Totals {
    pub found: HashMap<FindingKind, Acc>,
    pub seen: Vec<bool>,
    /// Refinement rays fired.
    pub refine_rays: u64,
}

impl Totals {
    pub fn new(regions: usize) -> Totals {
        Totals {
            found: HashMap::new(),
            seen: vec![false; regions],
            refine_rays: 0,
        }
    }

    /// Add the next chunk's findings.
    pub fn add_chunk(&mut self, chunk: &ChunkFindings) {
        for (kind, acc) in chunk {
            self.found
                .entry(*kind)
                .and_modify(|sum| sum.merge(acc))
                .or_insert(*acc);
        }
    }

    /// Add regions met.
    pub fn add_seen(&mut self, seen: &[bool]) {
        for (any, this) in self.seen.iter_mut().zip(seen) {
            *any |= this;
        }
    }
}

/// Chunks fired at once, whose findings are then handed on before the
/// next: a quarter of a million rays' findings and signatures held at a
/// time, however many rays.
const BATCH: u64 = 1024;

/// Chunks refined together: the refinement rays of neighbouring chunks
/// and rows share packets (each ray's findings still go to its own
/// chunk's sums, in an order that depends on the chunk alone; see
/// [`crate::refine`]). More chunks make taller tiles, with more pieces
/// to fill each bundle and fewer tiles to list zones for; fewer leave
/// every thread of the pool a few groups of each batch to take.
fn refine_group() -> usize {
    (BATCH as usize / (4 * rayon::current_num_threads())).clamp(64, 256)
}

/// Fire the chunks `chunks` of the grid and random rays on the rayon pool,
/// each followed by the refinement rays of the neighbouring grid rays that
/// end in it (see [`crate::refine`]): per chunk, in chunk order, every
/// kind of finding with its stretches summed (in order of kind) is handed
/// to `each`. Returns which regions any ray met and the number of
/// refinement rays.
pub(crate) fn fire_chunks(
    model: &Model,
    plan: &Plan,
    opts: &CheckOptions,
    chunks: Range<u64>,
    each: &mut dyn FnMut(ChunkFindings),
) -> (Vec<bool>, u64) {
    let seen = Met::new(model.names.len());
    let refining = plan.refinement.levels > 0;
    let grid = &plan.grid;
    let mut sigs = Signatures::starting_at(chunks.start * CHUNK);
    if refining {
        sigs = signatures_before(model, plan, chunks.start * CHUNK);
    }
    let mut refined = 0;
    // Working memory kept from batch to batch: made anew, a refinement's
    // lists grow again, and their pages are faulted in again.
    let workers = PerThread::new();
    let refiners = PerThread::new();
    for first in chunks.clone().step_by(BATCH as usize) {
        let batch = first..(first + BATCH).min(chunks.end);
        // Each chunk's signatures go straight to their place, after those
        // held from before.
        let batch_grid_rays = if refining {
            let total = grid.total();
            (batch.end * CHUNK).min(total) - (batch.start * CHUNK).min(total)
        } else {
            0
        };
        let new_sigs = sigs.places_for(batch_grid_rays as usize);
        let mut slots: Vec<&mut [u64]> = new_sigs.chunks_mut(CHUNK as usize).collect();
        slots.resize_with((batch.end - batch.start) as usize, Default::default);
        let mut sums: Vec<KindSums> = slots
            .into_par_iter()
            .enumerate()
            .map(|(at, chunk_sigs)| {
                let chunk = batch.start + at as u64;
                workers.with(
                    || Worker::new(model),
                    |worker| fire_chunk(model, plan, opts, worker, (chunk, chunk_sigs), &seen),
                )
            })
            .collect();
        let group = refine_group();
        let done: Vec<(Vec<ChunkFindings>, u64)> = sums
            .par_chunks_mut(group)
            .enumerate()
            .map(|(at, group_sums)| {
                let first = batch.start + (at * group) as u64;
                refiners.with(
                    || (RayCheck::new(model), Bundle::default()),
                    |(ray_check, bundle)| {
                        let work = (ray_check, bundle);
                        refine_chunks(plan, work, first, &sigs, group_sums, &seen)
                    },
                )
            })
            .collect();
        for (found, rays) in done {
            refined += rays;
            found.into_iter().for_each(&mut *each);
        }
        sigs.keep_from((batch.end * CHUNK).saturating_sub(grid.longest_row()));
    }
    let seen = seen
        .regions
        .into_iter()
        .map(AtomicBool::into_inner)
        .collect();
    (seen, refined)
}

/// The signatures of the grid rays up to a row before ray `start`, for the
/// refinement of the rays from `start` on: fired anew when a check is
/// split into parts.
fn signatures_before(model: &Model, plan: &Plan, start: u64) -> Signatures {
    let start = start.min(plan.grid.total());
    let rays = start.saturating_sub(plan.grid.longest_row())..start;
    let mut sigs = Signatures::starting_at(rays.start);
    let mut places = sigs.places_for((rays.end - rays.start) as usize).iter_mut();
    let mut worker = Worker::new(model);
    fire_grid_rays(model, plan, &mut worker, rays, |ray_check, _, _, _, _| {
        if let Some(place) = places.next() {
            *place = ray_check.signature;
        }
    });
    sigs
}

/// Fire the refinement rays that end in the chunks from `first` on, one
/// for each of `sums` (see [`Refinement::refine`]), adding their findings
/// to each chunk's sums: each chunk's findings in order of kind, and the
/// number of rays.
fn refine_chunks(
    plan: &Plan,
    (ray_check, bundle): (&mut RayCheck, &mut Bundle),
    first: u64,
    sigs: &Signatures,
    sums: &mut [KindSums],
    seen: &Met,
) -> (Vec<ChunkFindings>, u64) {
    let total = plan.grid.total();
    let rays = (first * CHUNK).min(total)..((first + sums.len() as u64) * CHUNK).min(total);
    let mut fired = 0;
    if rays.start < rays.end {
        fired = plan.refinement.refine(
            (&plan.grid, &plan.reach),
            sigs,
            rays,
            (ray_check, bundle, plan.tolerance),
            &mut |ray_check, ray, (id, grid_ray), as_an_end| {
                let chunk_sums = &mut sums[(grid_ray / CHUNK - first) as usize];
                // A ray that sees what an end of its piece sees meets
                // regions that are marked (as a grid ray's, below).
                let seen = (!as_an_end).then_some(seen);
                gather(ray_check, ray, (id, 0.0), chunk_sums, (seen, false));
            },
        );
    }
    (sums.iter_mut().map(KindSums::take_sorted).collect(), fired)
}

/// Where each zone lies within the box the rays cross, padded by the
/// tolerance: a zone that a half-space leaves unbounded (a ground plane
/// not square to an axis) reaches only its side of the box, and the rows
/// and tiles of rays that pass beside that part do not list it.
pub(crate) struct ZoneReach(Vec<Aabb>);

impl ZoneReach {
    /// The reach of every zone of `prepared` within `crossed`.
    pub(crate) fn new(prepared: &Prepared, crossed: &Aabb) -> ZoneReach {
        let tolerance = prepared.tolerance();
        let zones = 0..prepared.zone_count() as u32;
        ZoneReach(
            zones
                .map(|zone| prepared.zone_reach(zone, crossed).padded(tolerance))
                .collect(),
        )
    }

    /// The reach of zone `zone`.
    pub(crate) fn of(&self, zone: u32) -> &Aabb {
        &self.0[zone as usize]
    }

    /// Keep only the zones of `zones` that reach into `within`.
    pub(crate) fn keep_meeting(&self, zones: &mut Vec<u32>, within: &Aabb) {
        zones.retain(|&zone| !self.of(zone).intersection(within).is_empty());
    }
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
    /// may meet it (up to a ray more each side) and where the rays enter
    /// its bounds, by first ray.
    near: Vec<(u64, u64, u32, f64)>,
    /// How many of `near` the rays so far have reached.
    next: usize,
    /// The zones near the current ray in the order the rays enter their
    /// bounds, each with the last ray near it and that entry.
    zones: Vec<u32>,
    last: Vec<(u64, f64)>,
    scratch: Vec<u32>,
    /// Per zone, the row whose plane it was last cut by (one more than
    /// the row's first ray; 0: none; `u64::MAX`: a plane cuts it across
    /// no less than its reach) and its reach within that plane (see
    /// [`RowZones::cut`]).
    cuts: Vec<(u64, Aabb)>,
}

impl RowZones {
    /// The zones grid rays `rays` (in one row) may meet (`None`: walk the
    /// hierarchy); listed anew for the rest of their row within the chunk
    /// ending at `end` when the last list does not cover them. Rays come
    /// in order.
    fn for_rays(
        &mut self,
        model: &Model,
        plan: &Plan,
        rays: Range<u64>,
        end: u64,
    ) -> Option<&[u32]> {
        if !self.rays.contains(&rays.start) {
            let grid = &plan.grid;
            self.list(model, plan, rays.start..grid.row_end(rays.start).min(end));
        }
        if !self.listed {
            return None;
        }
        while let Some(&(first, last, zone, entry)) = self.near.get(self.next) {
            if first >= rays.end {
                break;
            }
            // In the order the rays enter the zones' bounds, the spans
            // come out nearly in the order of their entries, which their
            // union sorts them by.
            let at = self
                .last
                .iter()
                .rposition(|l| l.1 <= entry)
                .map_or(0, |at| at + 1);
            self.zones.insert(at, zone);
            self.last.insert(at, (last, entry));
            self.next += 1;
        }
        // Drop the zones the run has passed.
        let mut kept = 0;
        for at in 0..self.zones.len() {
            if self.last[at].0 >= rays.start {
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
    fn list(&mut self, model: &Model, plan: &Plan, rays: Range<u64>) {
        let grid = &plan.grid;
        let crossed = grid.run_box(rays.start, rays.end - 1);
        self.listed = model.prepared.all_zones_in_box(&crossed, &mut self.scratch);
        let tolerance = model.prepared.tolerance();
        plan.reach
            .keep_meeting(&mut self.scratch, &crossed.padded(tolerance));
        self.near.clear();
        self.zones.clear();
        self.last.clear();
        self.next = 0;
        let along = grid.axis(rays.start);
        let (_, column, _) = grid.place(rays.start);
        let row_start = rays.start - column;
        for at in 0..self.scratch.len() {
            let zone = self.scratch[at];
            let cut = self.cut(model, plan, zone, row_start);
            let (first, last) = grid.rays_near(rays.clone(), &cut);
            if first > last {
                continue;
            }
            let entry = model.prepared.zone_bounds(zone).min[along] - tolerance;
            self.near.push((first, last, zone, entry));
        }
        self.near
            .sort_unstable_by_key(|&(first, last, zone, _)| (first, last, zone));
        self.rays = rays;
    }

    /// The reach of zone `zone` within the plane of the row whose first
    /// ray is `row_start`, padded by the tolerance: a row's rays lie in
    /// one plane, which cuts a sphere, a mesh or a polyhedron turned to
    /// the axes across less than their bounds
    /// ([`Prepared::zone_reach`]). Kept for the rest of the row.
    fn cut(&mut self, model: &Model, plan: &Plan, zone: u32, row_start: u64) -> Aabb {
        let prepared = &model.prepared;
        if self.cuts.is_empty() {
            let zones = 0..prepared.zone_count() as u32;
            let never = |zone| (u64::MAX, *plan.reach.of(zone));
            let cuts = zones.map(|zone| match prepared.zone_narrows(zone) {
                true => (0, Aabb::EMPTY),
                false => never(zone),
            });
            self.cuts = cuts.collect();
        }
        let (row, cut) = &mut self.cuts[zone as usize];
        if *row != row_start + 1 && *row != u64::MAX {
            let grid = &plan.grid;
            let plane = grid.run_box(row_start, grid.row_end(row_start) - 1);
            let within = prepared
                .zone_reach(zone, &plane)
                .padded(prepared.tolerance());
            *cut = within.intersection(plan.reach.of(zone));
            *row = row_start + 1;
        }
        *cut
    }
}

/// Grid rays traced together: as many as the widest vector lanes hold.
const PACKET: u64 = 8;

/// Working memory of a thread: the rays' classification, the zones of the
/// row under way, a packet's rays and partitions, and how many kinds of
/// finding its last chunk found.
struct Worker<'a> {
    ray_check: RayCheck<'a>,
    row: RowZones,
    rays: Vec<Ray>,
    parts: Vec<Vec<Partition>>,
    kinds: usize,
}

impl<'a> Worker<'a> {
    fn new(model: &'a Model) -> Worker<'a> {
        Worker {
            ray_check: RayCheck::new(model),
            row: RowZones::default(),
            rays: Vec::with_capacity(PACKET as usize),
            parts: vec![Vec::new(); PACKET as usize],
            kinds: 0,
        }
    }
}

/// Fire the rays of chunk `chunk`: its findings by kind; when the check
/// refines, the signatures of its grid rays go to `sigs`, one place for
/// each. The regions its rays meet are marked in `seen`. The findings are
/// summed ray by ray in the order of the rays.
fn fire_chunk(
    model: &Model,
    plan: &Plan,
    opts: &CheckOptions,
    worker: &mut Worker,
    (chunk, sigs): (u64, &mut [u64]),
    seen: &Met,
) -> KindSums {
    let (grid, checked_box, tolerance) = (&plan.grid, &plan.checked_box, plan.tolerance);
    let grid_rays = grid.total();
    let end = ((chunk + 1) * CHUNK).min(grid_rays + opts.random);
    // Neighbouring chunks find much the same kinds: room for as many as
    // the last, made once instead of grown kind by kind.
    let mut sums = KindSums::with_capacity(worker.kinds);
    let refining = plan.refinement.levels > 0;
    let rays = chunk * CHUNK..end.min(grid_rays);
    let mut sig_slots = sigs.iter_mut();
    let mut last_sig = None;
    fire_grid_rays(
        model,
        plan,
        worker,
        rays,
        |ray_check, ray, at, area, repeated| {
            let mut as_before = repeated;
            if refining {
                if let Some(slot) = sig_slots.next() {
                    // A repeated ray's is the ray before's, kept.
                    let sig = ray_check.signature;
                    *slot = sig;
                    as_before = last_sig.replace(sig) == Some(sig);
                }
            }
            // A ray with the signature of the one before it meets the regions
            // that one met (but for a collision of 64-bit hashes, which the
            // refinement relies on too), and they are marked.
            let seen = (!as_before).then_some(seen);
            gather(ray_check, ray, (at, area), &mut sums, (seen, repeated));
        },
    );
    let randoms = (chunk * CHUNK).max(grid_rays) - grid_rays..end.saturating_sub(grid_rays);
    for random_index in randoms {
        let (lo, hi) = (checked_box.min, checked_box.max);
        if let Some((ray, t0, t1)) = random_ray(lo, hi, opts.seed, random_index) {
            let ray_check = &mut worker.ray_check;
            ray_check.run(&ray, t0, t1, tolerance);
            let at = grid_rays + random_index;
            gather(ray_check, &ray, (at, 0.0), &mut sums, (Some(seen), false));
        }
    }
    worker.kinds = sums.sums.len();
    sums
}

/// Fire the grid rays `rays` in packets along their rows, handing each,
/// in order, to `each` with its index, the area it stands for, the
/// partitions and findings of the worker's classification, and whether
/// they are the ray before's, kept (see
/// [`RayCheck::run_on_unless_repeated`]).
fn fire_grid_rays(
    model: &Model,
    plan: &Plan,
    worker: &mut Worker,
    rays: Range<u64>,
    mut each: impl FnMut(&RayCheck, &Ray, u64, f64, bool),
) {
    let grid = &plan.grid;
    for run in grid.row_runs(rays.clone()) {
        // The run's rays differ only along the row: a packet's are its
        // first ray with that coordinate changed.
        let (first, t1, area) = grid.ray(run.rays.start);
        worker.rays.clear();
        worker.rays.resize(PACKET as usize, first);
        // Whether the worker's last ray was one of this run's.
        let mut follows = false;
        for start in run.rays.clone().step_by(PACKET as usize) {
            let packet = start..(start + PACKET).min(run.rays.end);
            let zones = worker.row.for_rays(model, plan, packet.clone(), rays.end);
            let Worker {
                ray_check,
                rays,
                parts,
                ..
            } = worker;
            let rays = &mut rays[..(packet.end - packet.start) as usize];
            for (ray, index) in rays.iter_mut().zip(packet.clone()) {
                // As an array: DVec3's index is a match on the axis.
                let origin: &mut [f64; 3] = ray.origin.as_mut();
                origin[run.axes.0] = grid.along_row(&run, index);
            }
            // A packet near no zone (most of those that meet nothing) is
            // not traced.
            let near_none = zones.is_some_and(<[u32]>::is_empty);
            let mut repeats = 0;
            if near_none {
                parts.iter_mut().for_each(Vec::clear);
            } else {
                let row = (&rays[..], RaysShare::AllBut(run.axes.0));
                repeats = ray_check.partitions_of_rays(zones, row, 0.0, t1, parts);
            }
            // Where a packet meets nothing (a third of some grids' packets,
            // nearly all of them near no zone) its rays are not classified
            // one by one: each ray after the first finds what the one
            // before found, nothing.
            let met_nothing = parts[..rays.len()].iter().all(Vec::is_empty);
            if met_nothing && ray_check.run_on_empty() {
                for (lane, (at, ray)) in packet.zip(rays.iter()).enumerate() {
                    each(ray_check, ray, at, area, lane > 0);
                }
                follows = true;
                continue;
            }
            // Where faces square to the rays cross a row (most of a boxy
            // deck's), neighbouring rays see the same stretches to the
            // bit, and one's findings are the other's. The packet has
            // compared each lane after the first with the lane before:
            // only the first is compared here, with the last packet's last.
            let lanes = packet.zip(rays.iter().zip(parts.iter_mut()));
            for (lane, (at, (ray, ray_parts))) in lanes.enumerate() {
                let range = (0.0, t1, plan.tolerance);
                let as_last = repeats >> lane & 1 != 0;
                let compare = follows && lane == 0;
                let repeated =
                    ray_check.run_on_unless_repeated(ray_parts, ray, range, (compare, as_last));
                each(ray_check, ray, at, area, repeated);
                follows = true;
            }
        }
    }
}

/// Add the findings of ray `index` (standing for `area`) to `sums`, and
/// mark the regions it met in `seen` (`None`: they are marked).
/// `repeated`: the ray's findings are those of ray `index - 1`, to the
/// bit. Most rays find nothing and meet regions already marked: they
/// return here, at the caller, without a call.
#[inline(always)]
fn gather(
    ray_check: &RayCheck,
    ray: &Ray,
    (index, area): (u64, f64),
    sums: &mut KindSums,
    (seen, repeated): (Option<&Met>, bool),
) {
    let marking = seen.filter(|seen| !seen.all_marked());
    if marking.is_some() || !ray_check.findings.is_empty() {
        gather_findings(ray_check, ray, (index, area), sums, (marking, repeated));
    }
}

/// [`gather`] of a ray that finds something or meets regions to mark.
#[inline(never)]
fn gather_findings(
    ray_check: &RayCheck,
    ray: &Ray,
    (index, area): (u64, f64),
    sums: &mut KindSums,
    (seen, repeated): (Option<&Met>, bool),
) {
    if let Some(seen) = seen {
        seen.mark(&ray_check.parts);
    }
    sums.add_ray(&ray_check.findings, ray, (index, area), repeated);
}

/// The regions any ray has met, marked by the rays of all threads.
struct Met {
    regions: Vec<AtomicBool>,
    /// How many are not marked yet: once none are left, a ray need not
    /// read its regions at all.
    unmarked: AtomicUsize,
}

impl Met {
    fn new(regions: usize) -> Met {
        Met {
            regions: (0..regions).map(|_| AtomicBool::new(false)).collect(),
            unmarked: AtomicUsize::new(regions),
        }
    }

    /// Whether every region is marked.
    fn all_marked(&self) -> bool {
        self.unmarked.load(Ordering::Relaxed) == 0
    }

    /// Mark the regions of `parts`.
    fn mark(&self, parts: &[Partition]) {
        if self.all_marked() {
            return;
        }
        for part in parts {
            let met = &self.regions[part.region as usize];
            // Read first: once every thread has seen the region, its line
            // stays shared instead of passing from core to core.
            if !met.load(Ordering::Relaxed) && !met.swap(true, Ordering::Relaxed) {
                self.unmarked.fetch_sub(1, Ordering::Relaxed);
            }
        }
    }
}

/// A chunk's findings by kind, in the order first met. A ray meets a
/// kind or two, and a chunk a few dozen, one after another: each kind is
/// found through a small table by a hash of the kind, and along the list
/// only when two kinds share a slot.
pub(crate) struct KindSums {
    sums: Vec<(FindingKind, Acc)>,
    /// Per slot, one more than the index in `sums` of the last kind that
    /// hashed to it (0: none yet, or an index past 254). Bytes: the table
    /// is made and moved for every chunk.
    slots: [u8; KIND_SLOTS],
    /// The ray whose findings were added last, and where in `sums` each
    /// of them went, in order.
    last_ray: Option<u64>,
    last_places: Vec<u32>,
    /// While a ray's findings are added: the places of the ray before.
    places_before: Vec<u32>,
}

/// Slots of [`KindSums`]'s table: a power of two.
const KIND_SLOTS: usize = 256;

impl KindSums {
    /// No sums yet, with room for `kinds` kinds.
    fn with_capacity(kinds: usize) -> KindSums {
        KindSums {
            sums: Vec::with_capacity(kinds),
            slots: [0; KIND_SLOTS],
            last_ray: None,
            last_places: Vec::new(),
            places_before: Vec::new(),
        }
    }
}

/// The slot of `kind` in [`KindSums`]'s table: the top bits of a
/// multiplicative hash of its regions.
fn kind_slot(kind: FindingKind) -> usize {
    let region = |r: Option<u32>| r.map_or(u64::from(u32::MAX), u64::from);
    let (tag, a, b) = match kind {
        FindingKind::Overlap(a, b) => (0, u64::from(a), u64::from(b)),
        FindingKind::Void(a, b) => (1, region(a), region(b)),
        FindingKind::Outside(a) => (2, u64::from(a), 0),
    };
    let mixed = (a << 32 | b)
        .wrapping_add(tag)
        .wrapping_mul(0x9e37_79b9_7f4a_7c15);
    (mixed >> (64 - KIND_SLOTS.trailing_zeros())) as usize
}

impl KindSums {
    /// Add `findings`, those of ray `ray` of index `index` standing for
    /// `area`; `repeated`: they are those of ray `index - 1`, to the bit.
    fn add_ray(
        &mut self,
        findings: &[Finding],
        ray: &Ray,
        (index, area): (u64, f64),
        repeated: bool,
    ) {
        if repeated && index.checked_sub(1) == self.last_ray {
            // The ray before was added last, and its findings went where
            // these go: most of a boxy deck's findings are repeats.
            self.add_as_before(findings, area);
        } else {
            // The places of the ray added last are where these are first
            // looked for when their slots hold other kinds.
            std::mem::swap(&mut self.last_places, &mut self.places_before);
            self.last_places.clear();
            for (nth, finding) in findings.iter().enumerate() {
                let length = finding.t1 - finding.t0;
                let midpoint = || ray.at(0.5 * (finding.t0 + finding.t1));
                let at = self.add((finding.kind, nth), (length, area, index), midpoint);
                self.last_places.push(at);
            }
        }
        self.last_ray = Some(index);
    }

    /// Add a stretch of kind `kind`, the `nth` finding of its ray,
    /// `length` long, on ray `index` standing for `area`: as
    /// [`Acc::merge`] of the stretch alone, its midpoint worked out only
    /// when it is the longest so far; where in `sums` it went.
    fn add(
        &mut self,
        (kind, nth): (FindingKind, usize),
        (length, area, index): (f64, f64, u64),
        midpoint: impl FnOnce() -> DVec3,
    ) -> u32 {
        let slot = kind_slot(kind);
        let at = match self.slots[slot].checked_sub(1) {
            Some(at) if self.sums[usize::from(at)].0 == kind => Some(usize::from(at)),
            // No kind has hashed to the slot (while every index fits one):
            // the kind is new to the chunk.
            None if self.sums.len() <= usize::from(u8::MAX) => None,
            // Another kind holds the slot: two kinds of one ray that share
            // a slot take it in turns, and each is where the ray before
            // had it.
            _ => match self.places_before.get(nth) {
                Some(&at) if self.sums[at as usize].0 == kind => Some(at as usize),
                _ => self.sums.iter().position(|(k, _)| *k == kind),
            },
        };
        let slot_of = |at: usize| u8::try_from(at + 1).unwrap_or(0);
        let Some(at) = at else {
            self.slots[slot] = slot_of(self.sums.len());
            let stretch = Acc {
                total: length,
                weighted: length * area,
                max: length,
                point: midpoint(),
                at: index,
                hits: 1,
            };
            self.sums.push((kind, stretch));
            return (self.sums.len() - 1) as u32;
        };
        self.slots[slot] = slot_of(at);
        let sum = &mut self.sums[at].1;
        sum.total += length;
        sum.weighted += length * area;
        sum.hits += 1;
        if length > sum.max || (length == sum.max && index < sum.at) {
            sum.max = length;
            sum.point = midpoint();
            sum.at = index;
        }
        at as u32
    }

    /// [`KindSums::add`] of each of `findings`, those of the ray added
    /// last, to the bit, where that ray's went: none is the longest of its
    /// kind (one as long came first), so only the totals change.
    fn add_as_before(&mut self, findings: &[Finding], area: f64) {
        debug_assert_eq!(self.last_places.len(), findings.len());
        for (finding, &at) in findings.iter().zip(&self.last_places) {
            let length = finding.t1 - finding.t0;
            let sum = &mut self.sums[at as usize].1;
            sum.total += length;
            sum.weighted += length * area;
            sum.hits += 1;
        }
    }

    /// The sums in order of kind, taken (none are left).
    fn take_sorted(&mut self) -> ChunkFindings {
        let mut sums = std::mem::take(&mut self.sums);
        self.last_ray = None;
        self.last_places.clear();
        self.places_before.clear();
        sums.sort_by_key(|entry| entry.0);
        sums
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analyse::analyse_ray;
    use crate::model::UniverseChoice;
    use crate::refine::signature;
    use sv_formats::{load_source, Format, LoadOptions, SourceFile};

    /// Two spheres at the ends of a long room, a box overlapping the
    /// second: the rows between the spheres pass packets that meet one,
    /// then packets near no zone (which are not traced); the box's faces
    /// square to the rays give rays whose stretches repeat the ray
    /// before's.
    const ROOM: &str = "
BODY room RPP -6 6 -2 2 -2 2
BODY a    SPH (-4.5,0,0) 1.2
BODY b    SPH (4.5,0.3,0) 1.2
BODY c    RPP 3 5 -1 1 -0.5 0.5
REGION A = +a
REGION B = +b
REGION C = +c
";

    /// The model of the native scene `text` in `universe`, and the plan of
    /// a check of it at `spacing`.
    fn model_and_plan(text: &str, universe: &UniverseChoice, spacing: f64) -> (Model, Plan) {
        let source = SourceFile::new("test.sv", text);
        let scene = load_source(&source, Format::Native, &LoadOptions::default())
            .expect("the test scene reads")
            .scene;
        let (model, _) = Model::new(&scene, universe).expect("the test model prepares");
        let opts = CheckOptions {
            spacing: Some(spacing),
            ..CheckOptions::default()
        };
        let plan = Plan::new(&model, &opts).expect("the plan");
        (model, plan)
    }

    /// Every grid ray of [`ROOM`], fired in packets along its row, finds
    /// what it finds fired alone, and has its signature: with the room as
    /// the universe (voids between the spheres, none of its rays taken as
    /// the ray before's) and without one (overlaps only, and rays that
    /// repeat).
    #[test]
    fn grid_rays_in_packets_find_what_each_finds_alone() {
        for universe in [UniverseChoice::Named("room".into()), UniverseChoice::None] {
            let (model, plan) = model_and_plan(ROOM, &universe, 0.0913);
            let mut worker = Worker::new(&model);
            let mut alone = RayCheck::new(&model);
            let (mut fired, mut repeated_rays, mut found) = (0, 0, 0);
            let mut sig_before = None;
            let rays = 0..plan.grid.total();
            fire_grid_rays(
                &model,
                &plan,
                &mut worker,
                rays,
                |ray_check, ray, at, _, repeated| {
                    let (grid_ray, t1, _) = plan.grid.ray(at);
                    assert_eq!(ray.origin, grid_ray.origin, "ray {at}");
                    analyse_ray(&mut alone, &grid_ray, 0.0, t1, plan.tolerance);
                    assert_eq!(ray_check.findings, alone.findings, "ray {at}, {universe:?}");
                    // A ray taken as the ray before sees what that one saw,
                    // and the signature worked out with the classification
                    // (or kept) is the ray's.
                    let sig = signature(&alone.parts, plan.tolerance);
                    assert!(!repeated || sig_before == Some(sig), "ray {at}");
                    assert_eq!(ray_check.signature, sig, "ray {at}, {universe:?}");
                    sig_before = Some(sig);
                    fired += 1;
                    repeated_rays += u64::from(repeated);
                    found += u64::from(!alone.findings.is_empty());
                },
            );
            assert_eq!(fired, plan.grid.total());
            assert!(found > 100, "{found} rays found something, {universe:?}");
            if universe == UniverseChoice::None {
                assert!(repeated_rays > 1000, "{repeated_rays} rays repeated");
            }
        }
    }

    /// Kinds that share a slot of the table and take it in turns within
    /// each ray, a kind new to the chunk on some rays and not others, rays
    /// that repeat the ray before and rays that do not: each kind's sums
    /// are those of merging its findings one by one.
    #[test]
    fn kinds_sharing_a_slot_sum_as_each_finding_merged_alone() {
        let first = FindingKind::Overlap(0, 1);
        let second = (2..)
            .map(|b| FindingKind::Overlap(0, b))
            .find(|&kind| kind_slot(kind) == kind_slot(first))
            .expect("a kind in the first's slot");
        let third = FindingKind::Void(None, Some(3));
        let ray = Ray::new(DVec3::ZERO, DVec3::new(1.0, 2.0, 2.0));
        let (area, mut sums) = (0.25, KindSums::with_capacity(0));
        let mut merged: Vec<(FindingKind, Acc)> = Vec::new();
        let (mut findings, mut repeats) = (Vec::new(), 0);
        for index in 0..300u64 {
            let repeated = index % 3 == 2;
            if !repeated {
                findings.clear();
                let t0 = index as f64 * 0.01;
                for (nth, kind) in [first, second, third, first, second]
                    .into_iter()
                    .enumerate()
                {
                    // Each ray finds some of them, of lengths of its own.
                    if !(index as usize + nth).is_multiple_of(4) {
                        let t1 = t0 + 0.5 + nth as f64 * 0.1 + (index % 7) as f64 * 0.03;
                        findings.push(Finding { kind, t0, t1 });
                    }
                }
            }
            repeats += u64::from(repeated);
            sums.add_ray(&findings, &ray, (index, area), repeated);
            for finding in &findings {
                let length = finding.t1 - finding.t0;
                let alone = Acc {
                    total: length,
                    weighted: length * area,
                    max: length,
                    point: ray.at(0.5 * (finding.t0 + finding.t1)),
                    at: index,
                    hits: 1,
                };
                match merged.iter_mut().find(|(kind, _)| *kind == finding.kind) {
                    Some((_, sum)) => sum.merge(&alone),
                    None => merged.push((finding.kind, alone)),
                }
            }
        }
        assert_eq!(repeats, 100);
        merged.sort_by_key(|entry| entry.0);
        let sums = sums.take_sorted();
        assert_eq!(sums.len(), 3);
        for ((kind, sum), (other_kind, other)) in sums.iter().zip(&merged) {
            assert_eq!(kind, other_kind);
            assert_eq!(acc_bits(sum), acc_bits(other), "{kind:?}");
        }
    }

    /// An [`Acc`]'s numbers to the bit.
    fn acc_bits(acc: &Acc) -> (u64, u64, u64, [u64; 3], u64, u64) {
        let point = acc.point.to_array().map(f64::to_bits);
        let (total, weighted, max) = (
            acc.total.to_bits(),
            acc.weighted.to_bits(),
            acc.max.to_bits(),
        );
        (total, weighted, max, point, acc.at, acc.hits)
    }

    /// The findings of a ray that repeats the ray before are added where
    /// that ray's went, unlooked-up: the sums are those of adding every
    /// ray's findings as new, to the bit. Two boxes overlap in a cube
    /// whose faces are square to the rays, so that most rays through it
    /// repeat the ray before, overlap and all.
    #[test]
    fn repeated_rays_add_what_looking_their_kinds_up_adds() {
        let boxes = "
BODY x RPP 0 2 0 2 0 2
BODY y RPP 1 3 1 3 1 3
BODY z SPH (2,2,2) 0.7
REGION X = +x
REGION Y = +y
REGION Z = +z
";
        let (model, plan) = model_and_plan(boxes, &UniverseChoice::None, 0.03);
        let mut worker = Worker::new(&model);
        let (mut as_before, mut looked_up) =
            (KindSums::with_capacity(0), KindSums::with_capacity(0));
        let mut repeats_finding = 0;
        fire_grid_rays(
            &model,
            &plan,
            &mut worker,
            0..plan.grid.total(),
            |ray_check, ray, at, area, repeated| {
                gather(ray_check, ray, (at, area), &mut as_before, (None, repeated));
                gather(ray_check, ray, (at, area), &mut looked_up, (None, false));
                repeats_finding += u64::from(repeated && !ray_check.findings.is_empty());
            },
        );
        assert!(
            repeats_finding > 1000,
            "{repeats_finding} repeated rays found something"
        );
        let (as_before, looked_up) = (as_before.take_sorted(), looked_up.take_sorted());
        assert_eq!(as_before.len(), 3, "{as_before:?}");
        for ((kind, sum), (other_kind, other)) in as_before.iter().zip(&looked_up) {
            assert_eq!(kind, other_kind);
            assert_eq!(acc_bits(sum), acc_bits(other), "{kind:?}");
        }
    }
}
