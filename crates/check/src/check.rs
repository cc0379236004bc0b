//! `check`: overlaps and voids by grids of rays.

use crate::analyse::FindingKind;
use crate::fire::{fire_chunks, Acc, ChunkFindings, Totals, ZoneReach, CHUNK};
use crate::grid::{cells, Grid};
use crate::model::{CheckError, Model};
use crate::refine::Refinement;
use crate::report::{
    fmt_g, Outside, Overlap, Problem, Report, SmallestFeature, UniverseInfo, Void,
};
use serde::{Deserialize, Serialize};
use std::collections::HashMap;
use std::ops::Range;
use std::time::Instant;
use sv_math::{Aabb, DVec3};

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
    /// Halvings of the spacing down to which rays are added between
    /// neighbouring grid rays that see different regions (0: none); see
    /// [`refine_levels`]. Default 4: down to a sixteenth of the spacing.
    pub refine: u32,
    /// Refine down to this distance instead (as many halvings of the
    /// spacing as bring it there; none when it is not below the spacing).
    pub refine_to: Option<f64>,
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
            refine: 4,
            refine_to: None,
        }
    }
}

/// The most halvings of the spacing a check refines by.
pub const MAX_REFINE: u32 = 20;

/// The halvings of `spacing` that bring it down to `finest` or below (at
/// most [`MAX_REFINE`]): the [`CheckOptions::refine`] for refining down to
/// a length. Zero when `finest` is not below the spacing.
pub fn refine_levels(spacing: f64, finest: f64) -> u32 {
    if !(finest > 0.0 && finest < spacing) {
        return 0;
    }
    let levels = (spacing / finest).log2().ceil();
    (levels as u32).clamp(1, MAX_REFINE)
}

/// What a check fires: the box, the grid through it, the tolerance and
/// the refinement.
pub(crate) struct Plan {
    pub checked_box: Aabb,
    pub spacing: f64,
    pub tolerance: f64,
    pub grid: Grid,
    pub refinement: Refinement,
    pub reach: ZoneReach,
}

impl Plan {
    pub(crate) fn new(model: &Model, opts: &CheckOptions) -> Result<Plan, CheckError> {
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
        let levels = match opts.refine_to {
            Some(d) if d > 0.0 && d.is_finite() => refine_levels(spacing, d),
            Some(d) => {
                return Err(CheckError::Option(format!(
                    "the refinement distance must be positive, found {d}"
                )))
            }
            None if opts.refine > MAX_REFINE => {
                return Err(CheckError::Option(format!(
                "refinement by {} halvings of the spacing is more than the limit of {MAX_REFINE}",
                opts.refine
            )))
            }
            None => opts.refine,
        };
        let grid = Grid::new(checked_box.min, checked_box.max, spacing);
        let refinement = Refinement {
            levels,
            first_index: grid.total() + opts.random,
        };
        let reach = ZoneReach::new(&model.prepared, &grid.crossed());
        Ok(Plan {
            checked_box,
            spacing,
            tolerance,
            grid,
            refinement,
            reach,
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
    /// Refinement rays fired.
    refine_rays: u64,
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
    let mut found = Vec::with_capacity(chunks.end.saturating_sub(chunks.start) as usize);
    let (seen, refine_rays) = fire_chunks(model, &plan, opts, chunks.clone(), &mut |chunk| {
        found.push(chunk)
    });
    Ok(CheckPart {
        chunks,
        found,
        seen,
        refine_rays,
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
    let mut totals = Totals::new(model.names.len());
    for part in ordered {
        part.found.iter().for_each(|chunk| totals.add_chunk(chunk));
        totals.add_seen(&part.seen);
        totals.refine_rays += part.refine_rays;
    }
    Ok(report(model, opts, &plan, totals, start))
}

/// Fire the grids (and random rays) through `model` and gather every
/// overlap, void and stretch outside the universe. Runs on the current
/// rayon pool.
pub fn check(model: &Model, opts: &CheckOptions) -> Result<Report, CheckError> {
    let start = Instant::now();
    let plan = Plan::new(model, opts)?;
    let mut totals = Totals::new(model.names.len());
    let chunks = 0..plan.chunk_count(opts);
    let (seen, refine_rays) = fire_chunks(model, &plan, opts, chunks, &mut |chunk| {
        totals.add_chunk(&chunk)
    });
    totals.add_seen(&seen);
    totals.refine_rays = refine_rays;
    Ok(report(model, opts, &plan, totals, start))
}

/// The report of the findings summed in `totals`.
fn report(
    model: &Model,
    opts: &CheckOptions,
    plan: &Plan,
    totals: Totals,
    start: Instant,
) -> Report {
    let Totals {
        found: findings,
        mut seen,
        refine_rays,
    } = totals;
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
        refine: plan.refinement.levels,
        refine_rays,
        smallest_feature: smallest_feature(plan, &model.unit),
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

/// What the grid and refinement of `plan` are sure to meet.
fn smallest_feature(plan: &Plan, unit: &str) -> SmallestFeature {
    let (diagonal, side) = plan.grid.widest_cell();
    let levels = plan.refinement.levels;
    let at_edges = (levels > 0).then(|| side / f64::from(1u32 << levels));
    let mut note = format!(
        "sure to meet: any overlap or void whose cross-section across an axis holds a circle of {} {unit} (the grid's cell diagonal)",
        fmt_g(diagonal)
    );
    match at_edges {
        Some(thick) => note.push_str(&format!(
            "; where neighbouring rays see different regions, slivers {} {unit} thick (refined {levels} times)",
            fmt_g(thick)
        )),
        None => note.push_str("; no refinement"),
    }
    SmallestFeature {
        anywhere: diagonal,
        at_edges,
        note,
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
