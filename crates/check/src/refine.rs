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
    /// The signature of grid ray `index`, if held.
    pub fn get(&self, index: u64) -> Option<u64> {
        let at = index.checked_sub(self.first)?;
        self.sigs.get(usize::try_from(at).ok()?).copied()
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

/// A segment between two neighbouring grid rays to bisect: the varying
/// coordinate (axis `w`) of its ends, their signatures, the ray the
/// midpoints copy and its range, and the zones its rays may meet (`None`:
/// walk the hierarchy).
#[derive(Clone, Copy)]
struct Segment<'z> {
    w: usize,
    ends: [(f64, u64); 2],
    template: Ray,
    tmax: f64,
    zones: Option<&'z [u32]>,
}

impl Refinement {
    /// Fire the refinement rays of the pairs of neighbouring grid rays
    /// that end at the rays `rays` (the one before along the row, and the
    /// one before across it), whose signatures `sigs` holds. Each ray
    /// fired is handed to `found` with its index and the partitions and
    /// findings of `ray_check` (tolerance `tol`); the number of rays fired.
    pub fn refine(
        &self,
        grid: &Grid,
        sigs: &Signatures,
        rays: Range<u64>,
        (ray_check, tol): (&mut RayCheck, f64),
        found: &mut dyn FnMut(&RayCheck, &Ray, u64),
    ) -> u64 {
        if self.levels == 0 {
            return 0;
        }
        let mut fired = 0;
        let mut zones = Vec::new();
        for index in rays {
            let Some(sig) = sigs.get(index) else { continue };
            for (side, before) in grid.neighbours_before(index).into_iter().enumerate() {
                let Some((before, w)) = before else { continue };
                let other = match sigs.get(before) {
                    Some(other) if other != sig => other,
                    _ => continue,
                };
                let (ray, tmax, _) = grid.ray(index);
                let (from, _, _) = grid.ray(before);
                // The zones the rays between the two can meet, listed once.
                let between = Aabb::EMPTY.including(from.origin).including(ray.at(tmax));
                let listed = ray_check.prepared().all_zones_in_box(&between, &mut zones);
                let segment = Segment {
                    w,
                    ends: [(from.origin[w], other), (ray.origin[w], sig)],
                    template: ray,
                    tmax,
                    zones: listed.then_some(&zones[..]),
                };
                let id = self.first_index + ((2 * index + side as u64) << self.levels);
                fired += self.bisect(&segment, 1, id, (ray_check, tol), found);
            }
        }
        fired
    }

    /// Bisect `segment`, node `node` of the tree of its halvings (1: the
    /// whole segment), at `level`; the rays fired.
    fn bisect(
        &self,
        segment: &Segment,
        node: u64,
        id: u64,
        (ray_check, tol): (&mut RayCheck, f64),
        found: &mut dyn FnMut(&RayCheck, &Ray, u64),
    ) -> u64 {
        let level = 64 - node.leading_zeros();
        if level > self.levels {
            return 0;
        }
        let [(a, sig_a), (b, sig_b)] = segment.ends;
        let mut ray = segment.template;
        ray.origin[segment.w] = 0.5 * (a + b);
        match segment.zones {
            Some(zones) => ray_check.run_in(zones, &ray, 0.0, segment.tmax, tol),
            None => ray_check.run(&ray, 0.0, segment.tmax, tol),
        }
        let sig = signature(&ray_check.parts, tol);
        found(ray_check, &ray, id + node);
        let mut fired = 1;
        let mid = ray.origin[segment.w];
        for (half, (end, end_sig)) in [(0, (a, sig_a)), (1, (b, sig_b))] {
            if end_sig != sig {
                let mut ends = [(end, end_sig), (mid, sig)];
                if half == 1 {
                    ends.swap(0, 1);
                }
                let part = Segment { ends, ..*segment };
                fired += self.bisect(&part, 2 * node + half, id, (ray_check, tol), found);
            }
        }
        fired
    }
}
