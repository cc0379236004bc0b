//! Refinement: rays added between neighbouring grid rays that see
//! different things, so that slivers thinner than the grid are found
//! where they lie, at the edges of parts.
//!
//! Each grid ray's view is summed up in a *signature*: the regions it
//! meets in order of entry and, between each and the next, whether they
//! overlap, touch or leave a gap. Where two neighbouring rays of a grid
//! (along its rows or across them) have different signatures, a boundary
//! passes between them; rays are fired between the two by bisection, into
//! each half whose ends still differ, down to `levels` halvings of the
//! spacing. A sliver lying across the segment between the two rays, at the
//! edge where what they see changes, is met once the segments are no
//! longer than twice its thickness.

use crate::analyse::RayCheck;
use crate::grid::Grid;
use std::ops::Range;
use sv_math::{Aabb, Ray};
use sv_trace::Partition;

/// What a ray sees, in short: its regions in order of entry and how each
/// meets the one before (overlapping it, touching it within `tol`, or
/// after a gap), hashed (FNV-1a over the numbers).
pub(crate) fn signature(parts: &[Partition], tol: f64) -> u64 {
    let mut hash = 0xcbf2_9ce4_8422_2325_u64;
    let mut mix = |x: u64| {
        hash = (hash ^ x).wrapping_mul(0x0000_0100_0000_01b3);
    };
    let mut reach = f64::NEG_INFINITY;
    for (index, part) in parts.iter().enumerate() {
        let (a, b) = (part.span.a.t, part.span.b.t);
        let link = if index == 0 {
            0
        } else if a > reach + tol {
            1
        } else if a < reach - tol {
            2
        } else {
            3
        };
        mix(u64::from(part.region) << 2 | link);
        reach = reach.max(b);
    }
    hash
}

/// The signatures of a stretch of grid rays, by index.
#[derive(Default)]
pub(crate) struct Signatures {
    /// Index of the first ray held.
    pub first: u64,
    pub sigs: Vec<u64>,
}

impl Signatures {
    /// The signatures of rays `rays`, if all are held.
    pub fn window(&self, rays: Range<u64>) -> Option<&[u64]> {
        let start = usize::try_from(rays.start.checked_sub(self.first)?).ok()?;
        let end = usize::try_from(rays.end.checked_sub(self.first)?).ok()?;
        self.sigs.get(start..end)
    }

    /// Keep only the signatures from ray `from` on.
    pub fn keep_from(&mut self, from: u64) {
        let drop = from.saturating_sub(self.first).min(self.sigs.len() as u64);
        self.sigs.drain(..drop as usize);
        self.first += drop;
    }
}

/// Where a check refines, and how far.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Refinement {
    /// Halvings of the spacing (0: none).
    pub levels: u32,
    /// Index of the first refinement ray, past the grid and random rays.
    pub first_index: u64,
}

/// A stretch between two neighbouring grid rays to bisect: the axis `w`
/// along which its ends lie apart, the ray its midpoints copy (but for
/// coordinate `w`) and its range, and the index of its first ray.
struct Segment {
    w: usize,
    template: Ray,
    tmax: f64,
    id: u64,
}

/// A piece of a segment still to bisect: the segment, its node in the
/// tree of the segment's halvings (1: the whole segment), and the
/// coordinate and signature of each end.
#[derive(Clone, Copy)]
struct Piece {
    segment: u32,
    node: u64,
    ends: [(f64, u64); 2],
}

/// Working memory of a refinement: the segments to bisect and their
/// pieces at this halving and the next, a bundle's rays, their partitions
/// and zones.
#[derive(Default)]
pub(crate) struct Bundle {
    segments: Vec<Segment>,
    pieces: Vec<Piece>,
    next: Vec<Piece>,
    rays: Vec<Ray>,
    parts: Vec<Vec<Partition>>,
    zones: Vec<u32>,
}

/// Grid rays whose signatures [`Refinement::segments`] compares with
/// their neighbours' at once.
const SCAN_BLOCK: usize = 8;

/// Rays fired together by a refinement: as many as a packet of the grid's.
const BUNDLE: usize = sv_math::lanes::MAX_LANES;

/// Rays bisecting different pieces go together while they lie within
/// this many grid cells of the bundle's first: their box, whose zones they
/// share, stays small.
const NEAR_CELLS: f64 = 256.0;

impl Refinement {
    /// Fire the refinement rays of the pairs of neighbouring grid rays
    /// that end at the rays `rays` (the one before along the row, and the
    /// one before across it), whose signatures `sigs` holds, a halving at a
    /// time, in bundles of nearby rays. Each ray fired is handed to `found`
    /// with its index and the partitions and findings of `ray_check`
    /// (tolerance `tol`); the number of rays fired.
    pub fn refine(
        &self,
        grid: &Grid,
        sigs: &Signatures,
        rays: Range<u64>,
        (ray_check, bundle, tol): (&mut RayCheck, &mut Bundle, f64),
        found: &mut dyn FnMut(&RayCheck, &Ray, u64),
    ) -> u64 {
        if self.levels == 0 {
            return 0;
        }
        // The lists are the bundle's, kept from chunk to chunk.
        let mut segments = std::mem::take(&mut bundle.segments);
        let mut pieces = std::mem::take(&mut bundle.pieces);
        let mut next = std::mem::take(&mut bundle.next);
        let reach = self.segments(grid, sigs, rays, &mut segments, &mut pieces);
        let mut fired = 0;
        if !segments.is_empty() {
            // The zones any of the rays can meet, listed once for all, in
            // the order the first segment's rays enter their bounds (as a
            // grid row's, see `fire::RowZones`).
            let prepared = ray_check.prepared();
            let listed = prepared.all_zones_in_box(&reach, &mut bundle.zones);
            if listed {
                let dir = segments[0].template.dir;
                let along = (0..3).find(|&k| dir[k] != 0.0).unwrap_or(0);
                bundle.zones.sort_by(|&a, &b| {
                    let entry = |z| prepared.zone_bounds(z).min[along];
                    entry(a).total_cmp(&entry(b))
                });
            }
            let near = NEAR_CELLS * grid.widest_cell().1;
            for _ in 0..self.levels {
                next.clear();
                let mut first = 0;
                while first < pieces.len() {
                    // The bundle: the pieces after `first` whose rays share
                    // a range and lie near the first's.
                    let lead = &segments[pieces[first].segment as usize];
                    let end = (first..pieces.len())
                        .take(BUNDLE)
                        .take_while(|&at| {
                            let other = &segments[pieces[at].segment as usize];
                            other.tmax == lead.tmax
                                && (other.template.origin - lead.template.origin)
                                    .abs()
                                    .max_element()
                                    <= near
                        })
                        .last()
                        .map_or(first + 1, |last| last + 1);
                    let group = &pieces[first..end];
                    let work = (&mut *ray_check, &mut *bundle, tol);
                    fired += self.fire_bundle(&segments, group, listed, work, found, &mut next);
                    first = end;
                }
                std::mem::swap(&mut pieces, &mut next);
            }
        }
        (bundle.segments, bundle.pieces, bundle.next) = (segments, pieces, next);
        fired
    }

    /// The segments between neighbouring grid rays that end at `rays` and
    /// see different things into `segments`, a piece for each (the whole
    /// segment) into `pieces`; the box their rays cross.
    fn segments(
        &self,
        grid: &Grid,
        sigs: &Signatures,
        rays: Range<u64>,
        segments: &mut Vec<Segment>,
        pieces: &mut Vec<Piece>,
    ) -> Aabb {
        segments.clear();
        pieces.clear();
        let mut reach = Aabb::EMPTY;
        for run in grid.row_runs(rays) {
            // The run's signatures, after those of the neighbours before
            // it: most rays see what both neighbours see, so the scan
            // compares neighbouring signatures and stops only where they
            // differ.
            let along_before = u64::from(run.rays.start > run.row_start);
            let back = run.across.unwrap_or(along_before);
            let Some(held) = sigs.window(run.rays.start - back..run.rays.end) else {
                continue;
            };
            let back = back as usize;
            let across_mask = if run.across.is_some() { u64::MAX } else { 0 };
            let mut offset = 0;
            while offset < held.len() - back {
                let index = run.rays.start + offset as u64;
                // A block of rays that all see what both their neighbours
                // see is passed over with one test.
                if index > run.row_start && offset + SCAN_BLOCK <= held.len() - back {
                    let differ = (offset..offset + SCAN_BLOCK).fold(0, |differ, at| {
                        let sig = held[back + at];
                        differ | (sig ^ held[back + at - 1]) | ((sig ^ held[at]) & across_mask)
                    });
                    if differ == 0 {
                        offset += SCAN_BLOCK;
                        continue;
                    }
                }
                let at = offset;
                offset += 1;
                let sig = held[back + at];
                let along = (index > run.row_start).then(|| held[back + at - 1]);
                let across = run.across.map(|_| held[at]);
                if along.is_none_or(|other| other == sig) && across.is_none_or(|other| other == sig)
                {
                    continue;
                }
                let neighbours = [
                    (along, index.wrapping_sub(1), run.axes.0),
                    (
                        across,
                        index.wrapping_sub(run.across.unwrap_or(0)),
                        run.axes.1,
                    ),
                ];
                for (side, (other, before, w)) in neighbours.into_iter().enumerate() {
                    let Some(other) = other.filter(|&other| other != sig) else {
                        continue;
                    };
                    let (ray, tmax, _) = grid.ray(index);
                    let (from, _, _) = grid.ray(before);
                    reach = reach.including(from.origin).including(ray.at(tmax));
                    pieces.push(Piece {
                        segment: segments.len() as u32,
                        node: 1,
                        ends: [(from.origin[w], other), (ray.origin[w], sig)],
                    });
                    segments.push(Segment {
                        w,
                        template: ray,
                        tmax,
                        id: self.first_index + ((2 * index + side as u64) << self.levels),
                    });
                }
            }
        }
        reach
    }

    /// Fire the midpoints of `pieces` together (through the zones of
    /// `bundle` when `listed`, else walking the hierarchy), and add to
    /// `next` the halves whose ends still see different things; the rays
    /// fired.
    fn fire_bundle(
        &self,
        segments: &[Segment],
        pieces: &[Piece],
        listed: bool,
        (ray_check, bundle, tol): (&mut RayCheck, &mut Bundle, f64),
        found: &mut dyn FnMut(&RayCheck, &Ray, u64),
        next: &mut Vec<Piece>,
    ) -> u64 {
        let tmax = segments[pieces[0].segment as usize].tmax;
        bundle.rays.clear();
        for piece in pieces {
            let segment = &segments[piece.segment as usize];
            let mut ray = segment.template;
            ray.origin[segment.w] = 0.5 * (piece.ends[0].0 + piece.ends[1].0);
            bundle.rays.push(ray);
        }
        bundle
            .parts
            .resize_with(pieces.len().max(bundle.parts.len()), Vec::new);
        let zones = listed.then_some(&bundle.zones[..]);
        ray_check.partitions_of_rays(zones, &bundle.rays, 0.0, tmax, &mut bundle.parts);
        for ((piece, ray), parts) in pieces.iter().zip(&bundle.rays).zip(&mut bundle.parts) {
            ray_check.run_on(parts, ray, 0.0, tmax, tol);
            let segment = &segments[piece.segment as usize];
            found(ray_check, ray, segment.id + piece.node);
            let sig = signature(&ray_check.parts, tol);
            let mid = (ray.origin[segment.w], sig);
            let [low, high] = piece.ends;
            if 64 - piece.node.leading_zeros() < self.levels {
                for (half, ends) in [(0, [low, mid]), (1, [mid, high])] {
                    if ends[0].1 != ends[1].1 {
                        next.push(Piece {
                            node: 2 * piece.node + half,
                            ends,
                            ..*piece
                        });
                    }
                }
            }
        }
        pieces.len() as u64
    }
}
