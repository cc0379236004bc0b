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
//!
//! The segments are fired in tiles of a few neighbouring columns of a
//! grid, tile after tile, and in each by row, then column: the rays of a
//! packet lie close together and meet the same few zones. Within a run of
//! grid rays refined together, each ray's findings come in an order that
//! depends only on the segments (halving after halving, and in each by
//! tile, row and column), whatever other rays are refined with them: a
//! chunk's sums are the same to the bit however chunks are grouped.

use crate::analyse::RayCheck;
use crate::fire::ZoneReach;
use crate::grid::Grid;
use std::ops::Range;
use sv_math::{Aabb, Ray};
use sv_trace::{Partition, RaysShare};

/// What a ray sees, in short: its regions in order of entry and how each
/// meets the one before (overlapping it, touching it within `tol`, or
/// after a gap), hashed (FNV-1a over the numbers).
pub(crate) fn signature(parts: &[Partition], tol: f64) -> u64 {
    let mut signer = Signer::NONE;
    let Some((first, rest)) = parts.split_first() else {
        return signer.hash;
    };
    signer.first(first);
    for part in rest {
        signer.next(part, tol);
    }
    signer.hash
}

/// A [`signature`] worked out a part at a time, in order of entry (the
/// classification of a ray works it out as it reads the parts).
pub(crate) struct Signer {
    /// The hash of the parts so far.
    pub hash: u64,
    /// The farthest exit of the parts so far.
    reach: f64,
}

impl Signer {
    /// No parts yet.
    pub const NONE: Signer = Signer {
        hash: 0xcbf2_9ce4_8422_2325,
        reach: f64::NEG_INFINITY,
    };

    fn mix(&mut self, x: u64) {
        self.hash = (self.hash ^ x).wrapping_mul(0x0000_0100_0000_01b3);
    }

    /// Add the first part.
    #[inline(always)]
    pub fn first(&mut self, part: &Partition) {
        self.mix(u64::from(part.region) << 2);
        self.reach = f64::NEG_INFINITY.max(part.span.b.t);
    }

    /// Add a part after the first.
    #[inline(always)]
    pub fn next(&mut self, part: &Partition, tol: f64) {
        let (a, b) = (part.span.a.t, part.span.b.t);
        // 1 after a gap, 2 overlapping, 3 touching, worked out without
        // branches: which of the three comes is not predictable.
        let gap = u64::from(a > self.reach + tol);
        let overlap = u64::from(a < self.reach - tol);
        self.mix(u64::from(part.region) << 2 | (3 - 2 * gap - overlap));
        // One compare and select (`f64::max` adds a test for a NaN, which
        // `reach` never is and `b` loses either way), on the chain from
        // part to part.
        self.reach = if b > self.reach { b } else { self.reach };
    }
}

/// The signatures of a stretch of grid rays, by index.
pub(crate) struct Signatures {
    /// Index of the first ray held.
    first: u64,
    /// The signatures held, then places used before: the places of the
    /// next rays are written over, not cleared first.
    sigs: Vec<u64>,
    /// How many are held.
    held: usize,
}

impl Signatures {
    /// None held yet; the first to come is ray `first`'s.
    pub fn starting_at(first: u64) -> Signatures {
        Signatures {
            first,
            sigs: Vec::new(),
            held: 0,
        }
    }

    /// The places of the signatures of the next `count` rays, after those
    /// held, which the caller writes: they are held from now on.
    pub fn places_for(&mut self, count: usize) -> &mut [u64] {
        let (start, end) = (self.held, self.held + count);
        if self.sigs.len() < end {
            self.sigs.resize(end, 0);
        }
        self.held = end;
        &mut self.sigs[start..end]
    }

    /// The signatures of rays `rays`, if all are held.
    pub fn window(&self, rays: Range<u64>) -> Option<&[u64]> {
        let start = usize::try_from(rays.start.checked_sub(self.first)?).ok()?;
        let end = usize::try_from(rays.end.checked_sub(self.first)?).ok()?;
        self.sigs[..self.held].get(start..end)
    }

    /// Keep only the signatures from ray `from` on.
    pub fn keep_from(&mut self, from: u64) {
        let drop = from.saturating_sub(self.first).min(self.held as u64) as usize;
        self.sigs.copy_within(drop..self.held, 0);
        self.held -= drop;
        self.first += drop as u64;
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
/// coordinate `w`) and its range, the index of its first ray, the grid ray
/// it ends at, and its tile.
#[derive(Clone, Copy)]
struct Segment {
    w: usize,
    template: Ray,
    tmax: f64,
    id: u64,
    grid_ray: u64,
    tile: u32,
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

/// [`TILE_COLUMNS`] neighbouring columns of one grid, over the rows
/// refined together.
struct Tile {
    /// The grid's axis and the first column.
    key: (usize, u64),
    /// The box its segments' rays cross.
    reach: Aabb,
    /// While the segments are put in order of their tiles: how many are
    /// in it, then where its next goes in `Bundle::segments`.
    slot: u32,
    /// Its zones in `Bundle::zones` (`None`: walk the hierarchy).
    zones: Option<Range<usize>>,
}

/// Working memory of a refinement: the segments to bisect as found and
/// by tile, their tiles, the pieces at this halving and the next, a
/// bundle's rays, their partitions, and the tiles' zones.
#[derive(Default)]
pub(crate) struct Bundle {
    unsorted: Vec<Segment>,
    segments: Vec<Segment>,
    tiles: Vec<Tile>,
    /// Per block of [`TILE_COLUMNS`] columns of the current grid, its tile.
    tile_of_block: Vec<u32>,
    /// The tiles in order of their keys.
    tile_order: Vec<u32>,
    pieces: Vec<Piece>,
    next: Vec<Piece>,
    rays: Vec<Ray>,
    parts: Vec<Vec<Partition>>,
    zones: Vec<u32>,
    /// One tile's zones as the hierarchy lists them.
    listed: Vec<u32>,
}

/// What a refinement hands on of each ray it fires: the partitions and
/// findings of the check, the ray, its index and the grid ray its segment
/// ends at, and whether it sees what one of its piece's ends sees (so
/// that the regions it meets were met before).
pub(crate) type Found<'a> = dyn FnMut(&RayCheck, &Ray, (u64, u64), bool) + 'a;

/// Grid rays whose signatures [`Refinement::segments`] compares with
/// their neighbours' at once: first this many,
const LONG_BLOCK: usize = 64;

/// then this many.
const SCAN_BLOCK: usize = 8;

/// Rays fired together by a refinement: as many as a packet of the grid's.
const BUNDLE: usize = sv_math::lanes::MAX_LANES;

/// Columns of a grid in a tile: the rays of a bundle lie within this many
/// columns of each other, and within the rows refined together, so that
/// they meet the same few zones.
const TILE_COLUMNS: u64 = 8;

impl Refinement {
    /// Fire the refinement rays of the pairs of neighbouring grid rays
    /// that end at the rays `rays` (the one before along the row, and the
    /// one before across it), whose signatures `sigs` holds, a halving at a
    /// time, tile by tile in bundles of neighbouring rays. Each ray fired
    /// is handed to `found` with its index, the grid ray its segment ends
    /// at, and the partitions and findings of `ray_check` (tolerance
    /// `tol`), in the order the module describes; the number of rays
    /// fired.
    pub fn refine(
        &self,
        (grid, reach): (&Grid, &ZoneReach),
        sigs: &Signatures,
        rays: Range<u64>,
        (ray_check, bundle, tol): (&mut RayCheck, &mut Bundle, f64),
        found: &mut Found,
    ) -> u64 {
        if self.levels == 0 {
            return 0;
        }
        self.segments(grid, sigs, rays, bundle);
        bundle.order_by_tile();
        bundle.list_zones(ray_check, reach);
        // The lists are the bundle's, kept from run to run.
        let segments = std::mem::take(&mut bundle.segments);
        let mut pieces = std::mem::take(&mut bundle.pieces);
        let mut next = std::mem::take(&mut bundle.next);
        let mut fired = 0;
        for _ in 0..self.levels {
            next.clear();
            let mut first = 0;
            while first < pieces.len() {
                // The bundle: the pieces after `first` in its tile.
                let tile = segments[pieces[first].segment as usize].tile;
                let end = (first..pieces.len())
                    .take(BUNDLE)
                    .take_while(|&at| segments[pieces[at].segment as usize].tile == tile)
                    .last()
                    .map_or(first + 1, |last| last + 1);
                let zones = bundle.tiles[tile as usize].zones.clone();
                let work = (&mut *ray_check, &mut *bundle, tol);
                let group = (&segments[..], &pieces[first..end]);
                fired += self.fire_bundle(group, zones, work, found, &mut next);
                first = end;
            }
            std::mem::swap(&mut pieces, &mut next);
        }
        (bundle.segments, bundle.pieces, bundle.next) = (segments, pieces, next);
        fired
    }

    /// The segments between neighbouring grid rays that end at `rays` and
    /// see different things, in the order of the rays, into
    /// `bundle.unsorted`, a piece for each (the whole segment) into
    /// `bundle.next`, and the tiles they lie in, with the box their rays
    /// cross, into `bundle.tiles`.
    fn segments(&self, grid: &Grid, sigs: &Signatures, rays: Range<u64>, bundle: &mut Bundle) {
        let Bundle {
            unsorted: segments,
            next: pieces,
            tiles,
            tile_of_block,
            ..
        } = bundle;
        segments.clear();
        pieces.clear();
        tiles.clear();
        tile_of_block.clear();
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
            // Whether the `width` rays from `offset` on all see what both
            // their neighbours see, compared as whole slices (the
            // library's comparison of memory, in wide vectors).
            let alike = |offset: usize, width: usize| {
                let end = offset + width;
                let index = run.rays.start + offset as u64;
                if index <= run.row_start || end > held.len() - back {
                    return false;
                }
                let here = &held[back + offset..back + end];
                here == &held[back + offset - 1..back + end - 1]
                    && (run.across.is_none() || here == &held[offset..end])
            };
            let mut offset = 0;
            while offset < held.len() - back {
                let index = run.rays.start + offset as u64;
                // Most rays are passed over a long stretch at a time, then
                // a short one nearer where neighbours differ.
                if let Some(width) = [LONG_BLOCK, SCAN_BLOCK]
                    .into_iter()
                    .find(|&width| alike(offset, width))
                {
                    offset += width;
                    continue;
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
                    let (axis, column, _) = grid.place(index);
                    let tile = tile_of(tiles, tile_of_block, axis, column);
                    let reach = &mut tiles[tile as usize].reach;
                    *reach = reach.including(from.origin).including(ray.at(tmax));
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
                        grid_ray: index,
                        tile,
                    });
                }
            }
        }
    }

    /// Fire the midpoints of `pieces` together (through the zones `zones`
    /// of `bundle`, or walking the hierarchy when `None`), and add to
    /// `next` the halves whose ends still see different things; the rays
    /// fired.
    fn fire_bundle(
        &self,
        (segments, pieces): (&[Segment], &[Piece]),
        zones: Option<Range<usize>>,
        (ray_check, bundle, tol): (&mut RayCheck, &mut Bundle, f64),
        found: &mut Found,
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
        let zones = zones.map(|range| &bundle.zones[range]);
        let parts = &mut bundle.parts;
        // The bundle's rays lie in one tile: along one axis.
        let rays = (&bundle.rays[..], RaysShare::Direction);
        let repeats = ray_check.partitions_of_rays(zones, rays, 0.0, tmax, parts);
        let lanes = pieces.iter().zip(&bundle.rays).zip(&mut bundle.parts);
        for (lane, ((piece, ray), parts)) in lanes.enumerate() {
            // A ray whose stretches the packet left as the ray before's
            // keeps that ray's findings and signature.
            let as_last = (false, repeats >> lane & 1 != 0);
            ray_check.run_on_unless_repeated(parts, ray, (0.0, tmax, tol), as_last);
            let segment = &segments[piece.segment as usize];
            // A repeated ray's is the ray before's, kept.
            let sig = ray_check.signature;
            let [low, high] = piece.ends;
            let as_an_end = sig == low.1 || sig == high.1;
            found(
                ray_check,
                ray,
                (segment.id + piece.node, segment.grid_ray),
                as_an_end,
            );
            let mid = (ray.origin[segment.w], sig);
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

/// The tile of column `column` of the grid along `axis`, added to `tiles`
/// if new; `tile_of_block` holds the tile of each block of columns of the
/// grid of the last tile added.
fn tile_of(tiles: &mut Vec<Tile>, tile_of_block: &mut Vec<u32>, axis: usize, column: u64) -> u32 {
    if tiles.last().is_some_and(|last| last.key.0 != axis) {
        tile_of_block.clear();
    }
    let block = (column / TILE_COLUMNS) as usize;
    if tile_of_block.len() <= block {
        tile_of_block.resize(block + 1, u32::MAX);
    }
    if tile_of_block[block] == u32::MAX {
        tile_of_block[block] = tiles.len() as u32;
        tiles.push(Tile {
            key: (axis, column - column % TILE_COLUMNS),
            reach: Aabb::EMPTY,
            slot: 0,
            zones: None,
        });
    }
    tile_of_block[block]
}

impl Bundle {
    /// Put the segments found (`unsorted`, with their whole pieces in
    /// `next`) in order of their tiles' keys, each tile's in the order
    /// found (by row, then column), into `segments`, and their pieces
    /// into `pieces`.
    fn order_by_tile(&mut self) {
        let tiles = &mut self.tiles;
        self.tile_order.clear();
        self.tile_order.extend(0..tiles.len() as u32);
        self.tile_order
            .sort_unstable_by_key(|&tile| tiles[tile as usize].key);
        // Where each tile's segments start, in the order of the keys.
        for segment in &self.unsorted {
            tiles[segment.tile as usize].slot += 1;
        }
        let mut start = 0;
        for &tile in &self.tile_order {
            let count = tiles[tile as usize].slot;
            tiles[tile as usize].slot = start;
            start += count;
        }
        self.segments.clone_from(&self.unsorted);
        self.pieces.clone_from(&self.next);
        for (segment, piece) in self.unsorted.iter().zip(&self.next) {
            let at = &mut tiles[segment.tile as usize].slot;
            self.segments[*at as usize] = *segment;
            self.pieces[*at as usize] = Piece {
                segment: *at,
                ..*piece
            };
            *at += 1;
        }
    }

    /// List the zones each tile's rays may meet (whose reach meets the
    /// tile's box) into `zones`, in the order the rays enter their bounds
    /// (as a grid row's, see `fire::RowZones`).
    fn list_zones(&mut self, ray_check: &RayCheck, reach: &ZoneReach) {
        let prepared = ray_check.prepared();
        self.zones.clear();
        let mut listed = std::mem::take(&mut self.listed);
        for tile in &mut self.tiles {
            tile.zones = None;
            if !prepared.all_zones_in_box(&tile.reach, &mut listed) {
                continue;
            }
            reach.keep_meeting(&mut listed, &tile.reach.padded(prepared.tolerance()));
            let along = tile.key.0;
            listed.sort_by(|&a, &b| {
                let entry = |z| prepared.zone_bounds(z).min[along];
                entry(a).total_cmp(&entry(b))
            });
            tile.zones = Some(self.zones.len()..self.zones.len() + listed.len());
            self.zones.extend_from_slice(&listed);
        }
        self.listed = listed;
    }
}
