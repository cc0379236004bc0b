//! How [`Prepared::new`](crate::Prepared::new) lays a geometry out: each
//! region's zones flattened into records over one array of body numbers,
//! their groups into records of nested zones (the expression kept as
//! written, never expanded into sums of products), bounds from the tree,
//! the boolean tolerance from the size of what rays meet, and everything in
//! the order it lies in space.

use crate::prepare::{PreparedGroup, PreparedZone};
use sv_geom::shape::Shape;
use sv_geom::{Geometry, Group, Op, Zone};
use sv_math::{Aabb, DVec3};

/// The zones of a geometry as the tracer holds them.
#[derive(Default)]
pub(crate) struct Layout {
    /// The regions' own zones (the hierarchy's items).
    pub zones: Vec<PreparedZone>,
    /// The zones inside groups, to any depth.
    pub nested: Vec<PreparedZone>,
    /// The groups of every zone; a zone's are contiguous.
    pub groups: Vec<PreparedGroup>,
    /// Body numbers: per zone its `+` bodies, its `-` bodies and, when it
    /// has groups, the index of its first group.
    pub terms: Vec<u32>,
}

/// Lays zones out over prepared bodies.
pub(crate) struct ZoneBuilder<'a> {
    pub shapes: &'a [Shape],
    pub body_bounds: &'a [Aabb],
    pub layout: Layout,
    pub problems: Vec<String>,
}

impl ZoneBuilder<'_> {
    /// The zones of every region of `universe`, checked: a region without
    /// zones (unless filled: a filled region without zones fills all the
    /// space of its universe), an empty zone, a body that does not exist
    /// are problems.
    pub fn regions(&mut self, g: &Geometry, universe: usize) {
        for (ri, r) in g.regions.iter().enumerate() {
            if r.universe != universe {
                continue;
            }
            if r.zones.is_empty() && r.fill.is_none() {
                self.problems
                    .push(format!("region `{}`: it has no bodies", r.name));
            }
            let first = self.layout.zones.len();
            if r.zones.is_empty() && r.fill.is_some() {
                self.layout
                    .zones
                    .push(everywhere(ri as u32, self.layout.terms.len() as u32));
            }
            for (zi, z) in r.zones.iter().enumerate() {
                if let Some(problem) = self.check(z, g.bodies.len()) {
                    self.problems
                        .push(format!("region `{}`: zone {}: {problem}", r.name, zi + 1));
                    continue;
                }
                if let Some(pz) = self.zone(z, ri as u32) {
                    self.layout.zones.push(pz);
                }
            }
            if r.fill.is_some() {
                for z in &mut self.layout.zones[first..] {
                    z.groups |= PreparedZone::FILLED;
                    (z.convex, z.lanes) = (false, false);
                }
            }
        }
    }

    /// What is wrong with zone `z`, if anything.
    fn check(&self, z: &Zone, bodies: usize) -> Option<String> {
        if z.is_empty() {
            return Some("it is empty".into());
        }
        if let Some(t) = z.terms.iter().find(|t| t.body >= bodies) {
            return Some(format!("body index {} does not exist", t.body));
        }
        z.groups
            .iter()
            .flat_map(|g| &g.zones)
            .find_map(|inner| self.check(inner, bodies))
    }

    /// The record of zone `z` of region `region`, with its terms and groups
    /// laid out; `None` when its bounds show it empty. Its `+` bodies are
    /// sorted by the area of their boxes (the smallest, most likely missed,
    /// first), and only `-` bodies and groups that reach its bounds are
    /// kept.
    fn zone(&mut self, z: &Zone, region: u32) -> Option<PreparedZone> {
        let bounds_of = |b: u32| self.body_bounds[b as usize];
        let mut plus: Vec<u32> = z
            .terms
            .iter()
            .filter(|t| t.op == Op::Inside)
            .map(|t| t.body as u32)
            .collect();
        plus.sort_by(|a, b| bounds_of(*a).area().total_cmp(&bounds_of(*b).area()));
        plus.dedup();
        let mut bounds = plus
            .iter()
            .fold(Aabb::INFINITE, |acc, &b| acc.intersection(&bounds_of(b)));
        // A subtracted half-space normal to an axis bounds the zone by the
        // other half.
        for t in z.terms.iter().filter(|t| t.op == Op::Outside) {
            bounds = bounds.intersection(&self.shapes[t.body].outside_bounds());
        }
        let mut groups = Vec::new();
        for g in z.groups.iter().filter(|g| g.op == Op::Inside) {
            // A `+` group that is empty empties the zone.
            let group = self.group(g, region)?;
            bounds = bounds.intersection(&group.bounds);
            groups.push(group);
        }
        if bounds.is_empty() {
            return None;
        }
        let mut minus: Vec<u32> = z
            .terms
            .iter()
            .filter(|t| {
                t.op == Op::Outside && !bounds_of(t.body as u32).intersection(&bounds).is_empty()
            })
            .map(|t| t.body as u32)
            .collect();
        minus.dedup();
        for g in z.groups.iter().filter(|g| g.op == Op::Outside) {
            if let Some(group) = self.group(g, region) {
                if !group.bounds.intersection(&bounds).is_empty() {
                    groups.push(group);
                }
            }
        }
        let convex = groups.is_empty() && plus.iter().all(|&b| self.shapes[b as usize].is_convex());
        // A lone torus is cast in the lanes by the zone itself, which
        // takes both its segments.
        let lone_torus =
            matches!(plus[..], [b] if matches!(self.shapes[b as usize], Shape::Torus(_)));
        let lanes = groups.is_empty()
            && !plus.is_empty()
            && (lone_torus || plus.iter().all(|&b| self.shapes[b as usize].has_lanes()));
        let first = self.layout.terms.len() as u32;
        self.layout.terms.extend(&plus);
        self.layout.terms.extend(&minus);
        if !groups.is_empty() {
            self.layout.terms.push(self.layout.groups.len() as u32);
            self.layout.groups.extend(groups.iter().copied());
        }
        Some(PreparedZone {
            region,
            first,
            plus: plus.len() as u16,
            minus: minus.len() as u16,
            groups: groups.len() as u16,
            bounds,
            convex,
            lanes,
        })
    }

    /// The record of group `g` (its zones laid out among the nested ones,
    /// contiguous); `None` when every zone of it is empty.
    fn group(&mut self, g: &Group, region: u32) -> Option<PreparedGroup> {
        let inner: Vec<PreparedZone> = g
            .zones
            .iter()
            .filter_map(|z| self.zone(z, region))
            .collect();
        if inner.is_empty() {
            return None;
        }
        let first = self.layout.nested.len() as u32;
        let bounds = inner
            .iter()
            .fold(Aabb::EMPTY, |acc, z| acc.union(&z.bounds));
        let count = inner.len() as u32;
        self.layout.nested.extend(inner);
        Some(PreparedGroup {
            subtract: g.op == Op::Outside,
            first,
            count,
            bounds,
        })
    }
}

/// A zone of region `region` that is all space (its terms would start at
/// `first`; it has none).
fn everywhere(region: u32, first: u32) -> PreparedZone {
    PreparedZone {
        region,
        first,
        plus: 0,
        minus: 0,
        groups: 0,
        bounds: Aabb::INFINITE,
        convex: false,
        lanes: false,
    }
}

/// The boolean tolerance: 1e-7 of the size of the geometry rays meet,
/// floored at 1e-12. That size is the diagonal of the box of the bounded
/// bodies and of the finite sides of the unbounded ones (a plane's
/// position), less the containers around it: a body whose box holds all
/// the others' and is more than twice their size (a FLUKA black hole, the
/// void sphere around a detector) is set aside, in turn from the largest,
/// so that a detector in a world of 1e10 cm keeps millimetre layers.
/// Coincident faces of containers are computed with errors far below this
/// (some 1e-16 of their size).
pub(crate) fn default_tolerance(body_bounds: &[Aabb]) -> f64 {
    let mut bounded: Vec<Aabb> = body_bounds
        .iter()
        .copied()
        .filter(|b| b.is_finite())
        .collect();
    let planes = body_bounds
        .iter()
        .filter(|b| !b.is_finite() && !b.is_empty())
        .filter_map(finite_sides)
        .fold(Aabb::EMPTY, |acc, b| acc.union(&b));
    let (inner, innermost_container) = without_containers(&mut bounded, planes);
    let d = if inner.is_empty() || inner.diagonal() == 0.0 {
        // Nothing but containers, or planes through one point: the
        // innermost container, else a unit.
        innermost_container.map_or(1.0, |b| b.diagonal())
    } else {
        inner.diagonal()
    };
    (1e-7 * d).max(1e-12)
}

/// The box of `boxes` (bounded) and `extra` less the containers around
/// them: the boxes that each hold all the smaller ones' (a FLUKA black
/// hole, the world sphere, the void around a detector), set aside from
/// the largest down to the innermost that is more than twice the size of
/// what it holds. Returns that box and the innermost
/// container set aside, if any. Sorts `boxes`, largest first.
pub(crate) fn without_containers(boxes: &mut [Aabb], extra: Aabb) -> (Aabb, Option<Aabb>) {
    boxes.sort_by(|a, b| b.diagonal().total_cmp(&a.diagonal()));
    let rest = |from: usize| boxes[from..].iter().fold(extra, |acc, b| acc.union(b));
    // Walk the chain of boxes that each hold all the smaller ones; cut it
    // below the innermost that is more than twice what it holds (a black
    // hole only twice the world sphere inside it is still a container).
    let (mut first, mut cut) = (0, 0);
    while first + 1 < boxes.len() || (first < boxes.len() && !extra.is_empty()) {
        let inner = rest(first + 1);
        let outer = boxes[first];
        if outer.union(&inner) != outer {
            break;
        }
        if outer.diagonal() > 2.0 * inner.diagonal() {
            cut = first + 1;
        }
        first += 1;
    }
    (rest(cut), cut.checked_sub(1).map(|i| boxes[i]))
}

/// The finite sides of an unbounded box as a box: along each axis, its
/// finite ends (a half-space `z < 5` gives `z = 5`), 0 where both are
/// infinite; `None` when no side is finite (a plane across the axes).
fn finite_sides(b: &Aabb) -> Option<Aabb> {
    if !(0..3).any(|a| b.min[a].is_finite() || b.max[a].is_finite()) {
        return None;
    }
    let mut out = Aabb::new(DVec3::ZERO, DVec3::ZERO);
    for a in 0..3 {
        let (lo, hi) = (b.min[a], b.max[a]);
        (out.min[a], out.max[a]) = match (lo.is_finite(), hi.is_finite()) {
            (true, true) => (lo, hi),
            (true, false) => (lo, lo),
            (false, true) => (hi, hi),
            (false, false) => (0.0, 0.0),
        };
    }
    Some(out)
}

/// Reorder `v` in place so that `v[i]` becomes the old `v[from[i]]`
/// (`from` a permutation): a model's prepared bodies are too many to copy.
pub(crate) fn permute<T>(v: &mut [T], from: &[u32]) {
    let mut done = vec![false; v.len()];
    for start in 0..v.len() {
        let mut i = start;
        while !done[i] {
            done[i] = true;
            let j = from[i] as usize;
            if j == start {
                break;
            }
            // Place `i` takes its body; place `j` holds the start's for now.
            v.swap(i, j);
            i = j;
        }
    }
}

/// The layout with its zones sorted along a space-filling curve through
/// the centres of their bounds (unbounded zones first, in their order), and
/// the bodies numbered in the order these zones first name them (then the
/// nested zones' bodies, then the bodies no zone names): neighbours in
/// space become neighbours in memory, so that a ray crossing a crowd of
/// small bodies finds their data in the lines it has just loaded. Returns
/// it renumbered, the body index of each new body number, and the new
/// number of each body. Unsorted, 100,000 random spheres rendered 20 %
/// slower (BENCHMARKS.md, twelfth round).
pub(crate) fn in_space_order(layout: Layout, bodies: usize) -> (Layout, Vec<u32>, Vec<u32>) {
    let Layout {
        zones,
        nested,
        groups,
        terms,
    } = layout;
    let all = zones
        .iter()
        .filter(|z| z.bounds.is_finite())
        .fold(Aabb::EMPTY, |a, z| a.union(&z.bounds));
    let size = all.size().max(DVec3::splat(f64::MIN_POSITIVE));
    let key = |z: &PreparedZone| -> u64 {
        if !z.bounds.is_finite() || all.is_empty() {
            return 0;
        }
        // 21 bits an axis, interleaved (Morton order).
        let q = ((z.bounds.center() - all.min) / size * 2_097_151.0)
            .clamp(DVec3::ZERO, DVec3::splat(2_097_151.0));
        let spread = |v: f64| {
            let mut x = v as u64 & 0x1f_ffff;
            x = (x | x << 32) & 0x1f_0000_0000_ffff;
            x = (x | x << 16) & 0x1f_0000_ff00_00ff;
            x = (x | x << 8) & 0x100f_00f0_0f00_f00f;
            x = (x | x << 4) & 0x10c3_0c30_c30c_30c3;
            (x | x << 2) & 0x1249_2492_4924_9249
        };
        1 + (spread(q.x) | spread(q.y) << 1 | spread(q.z) << 2)
    };
    let mut order: Vec<u32> = (0..zones.len() as u32).collect();
    let keys: Vec<u64> = zones.iter().map(key).collect();
    order.sort_unstable_by_key(|&zi| (keys[zi as usize], zi));
    const NONE: u32 = u32::MAX;
    let mut places = vec![NONE; bodies];
    let mut body_ids = Vec::with_capacity(bodies);
    let mut place = |b: u32| {
        if places[b as usize] == NONE {
            places[b as usize] = body_ids.len() as u32;
            body_ids.push(b);
        }
        places[b as usize]
    };
    let mut new_terms = Vec::with_capacity(terms.len());
    let mut renumber = |z: &PreparedZone, new_terms: &mut Vec<u32>| {
        let first = z.first as usize;
        let n = z.plus as usize + z.minus as usize;
        let moved = PreparedZone {
            first: new_terms.len() as u32,
            ..*z
        };
        new_terms.extend(terms[first..first + n].iter().map(|&b| place(b)));
        if z.group_count() > 0 {
            // The index of its first group, not a body.
            new_terms.push(terms[first + n]);
        }
        moved
    };
    let zones: Vec<PreparedZone> = order
        .iter()
        .map(|&zi| renumber(&zones[zi as usize], &mut new_terms))
        .collect();
    let nested: Vec<PreparedZone> = nested.iter().map(|z| renumber(z, &mut new_terms)).collect();
    for b in 0..bodies as u32 {
        place(b);
    }
    let layout = Layout {
        zones,
        nested,
        groups,
        terms: new_terms,
    };
    (layout, body_ids, places)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube(c: f64, half: f64) -> Aabb {
        Aabb::new(DVec3::splat(c - half), DVec3::splat(c + half))
    }

    #[test]
    fn containers_do_not_set_the_tolerance() {
        // A 1.6 cm slab 100 cm wide in a void of 1e6 cm in a black hole of
        // 1e10 cm: the slab's size sets it.
        let slab = Aabb::new(DVec3::new(-50.0, -50.0, 0.0), DVec3::new(50.0, 50.0, 1.6));
        let tol = default_tolerance(&[cube(0.0, 1e10), slab, cube(0.0, 1e6)]);
        assert!((tol - 1e-7 * slab.diagonal()).abs() < 1e-18, "{tol}");
        // Two bodies of the same size side by side: neither contains.
        let pair = [cube(0.0, 1.0), cube(1.5, 1.0)];
        let whole = pair[0].union(&pair[1]).diagonal();
        assert!((default_tolerance(&pair) - 1e-7 * whole).abs() < 1e-18);
        // A container no more than twice its content's size stays.
        let snug = [cube(0.0, 1.5), cube(0.0, 1.0)];
        assert!((default_tolerance(&snug) - 1e-7 * snug[0].diagonal()).abs() < 1e-18);
    }

    #[test]
    fn planes_inside_a_container_set_the_tolerance() {
        // Layers between planes z = 0, 0.16 and 10 cut from a world sphere
        // of 1e6 cm: the planes' positions set the scale.
        let mut below = Aabb::INFINITE;
        below.max.z = 0.16;
        let mut above = Aabb::INFINITE;
        above.min.z = 10.0;
        let tol = default_tolerance(&[cube(0.0, 1e6), below, above]);
        assert!((tol - 1e-7 * 9.84).abs() < 1e-15, "{tol}");
        // Nothing but a container: its own size.
        assert!(
            (default_tolerance(&[cube(0.0, 1e6)]) - 1e-7 * cube(0.0, 1e6).diagonal()).abs() < 1e-9
        );
        assert_eq!(default_tolerance(&[]), 1e-7);
    }
}
