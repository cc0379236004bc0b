//! The region algebra shared by every reader: a region is a union of
//! zones; a zone intersects its `+` terms and subtracts its `-` terms,
//! where a term is a body or a parenthesised group (itself a union of
//! zones), to any depth. This is FLUKA's grammar (`+a -(+b | +c)`), GIFT's
//! `OR` and region references, MCNP's `:`/`#` and OpenMC's `|`/`~`, held as
//! written: no expansion to sums of products, so a region's size stays
//! that of its expression.
//!
//! A region may also be filled: by another universe's regions moved into
//! it (MCNP `FILL`, OpenMC fills, FLUKA lattice cells), or by a lattice of
//! universes.

use sv_math::{DAffine3, DVec3};

/// Boolean operator of a term inside a zone.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Op {
    /// `+`: intersect with the body or group.
    Inside,
    /// `-`: subtract the body or group.
    Outside,
}

impl Op {
    /// `+` or `-`.
    pub fn sign(self) -> char {
        match self {
            Op::Inside => '+',
            Op::Outside => '-',
        }
    }
}

/// One signed body reference in a zone.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Term {
    /// `+` or `-`.
    pub op: Op,
    /// Index into [`crate::Geometry::bodies`].
    pub body: usize,
}

/// A signed parenthesised union of zones inside a zone: `+( … | … )` or
/// `-( … )`.
#[derive(Clone, Debug, PartialEq)]
pub struct Group {
    /// `+` intersects the zone with the group's union, `-` subtracts it.
    pub op: Op,
    /// The zones of the group, unioned.
    pub zones: Vec<Zone>,
}

/// A zone: the intersection of its `+` terms and groups, minus its `-`
/// terms and groups. A zone with no `+` term or group is all space less
/// its `-` ones.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Zone {
    /// Body terms, in the order written.
    pub terms: Vec<Term>,
    /// Parenthesised groups, in the order written.
    pub groups: Vec<Group>,
}

impl Zone {
    /// A zone of body terms only.
    pub fn new(terms: Vec<Term>) -> Zone {
        Zone {
            terms,
            groups: Vec::new(),
        }
    }

    /// True when the zone has neither terms nor groups.
    pub fn is_empty(&self) -> bool {
        self.terms.is_empty() && self.groups.is_empty()
    }

    /// The zone as written: `+a -b -(+c | +d)`, naming bodies with `name`.
    pub fn expression<'a>(&self, name: &impl Fn(usize) -> &'a str) -> String {
        let mut parts: Vec<String> = self
            .terms
            .iter()
            .map(|t| format!("{}{}", t.op.sign(), name(t.body)))
            .collect();
        parts.extend(self.groups.iter().map(|g| {
            let inner: Vec<String> = g.zones.iter().map(|z| z.expression(name)).collect();
            format!("{}({})", g.op.sign(), inner.join(" | "))
        }));
        parts.join(" ")
    }

    /// Every body the zone names, its groups' included, with the sign it
    /// has where it is written (a body in a `-` group keeps its own sign).
    pub fn for_each_term(&self, f: &mut impl FnMut(&Term)) {
        self.terms.iter().for_each(&mut *f);
        for g in &self.groups {
            for z in &g.zones {
                z.for_each_term(f);
            }
        }
    }

    /// The deepest nesting of groups in the zone (0 without groups).
    pub fn depth(&self) -> usize {
        self.groups
            .iter()
            .flat_map(|g| &g.zones)
            .map(|z| 1 + z.depth())
            .max()
            .unwrap_or(0)
    }

    /// The zone as a union of zones of body terms only (sums of products),
    /// if that takes at most `budget` zones: what formats that cannot nest
    /// (COMGEOM) must write. `None` when it would take more.
    pub fn flattened(&self, budget: usize) -> Option<Vec<Zone>> {
        let mut out = vec![Zone::new(self.terms.clone())];
        for g in &self.groups {
            let inner = flatten_union(&g.zones, budget)?;
            out = match g.op {
                Op::Inside => product(&out, &inner, budget)?,
                Op::Outside => product(&out, &complement(&inner, budget)?, budget)?,
            };
        }
        Some(out)
    }
}

/// The union of `zones`, each flattened, within `budget` zones.
fn flatten_union(zones: &[Zone], budget: usize) -> Option<Vec<Zone>> {
    let mut out = Vec::new();
    for z in zones {
        out.extend(z.flattened(budget)?);
        if out.len() > budget {
            return None;
        }
    }
    Some(out)
}

/// `a ∩ b` of two unions of flat zones, within `budget` zones; zones that
/// hold a body both with `+` and `-` are empty and dropped.
fn product(a: &[Zone], b: &[Zone], budget: usize) -> Option<Vec<Zone>> {
    let mut out = Vec::new();
    for x in a {
        for y in b {
            let mut terms = x.terms.clone();
            for t in &y.terms {
                if !terms.contains(t) {
                    terms.push(*t);
                }
            }
            let contradicts = terms.iter().any(|t| {
                t.op == Op::Inside
                    && terms.contains(&Term {
                        op: Op::Outside,
                        ..*t
                    })
            });
            if !contradicts {
                out.push(Zone::new(terms));
                if out.len() > budget {
                    return None;
                }
            }
        }
    }
    Some(out)
}

/// The complement of a union of flat zones (De Morgan), within `budget`.
fn complement(zones: &[Zone], budget: usize) -> Option<Vec<Zone>> {
    let mut out = vec![Zone::default()];
    for z in zones {
        let negated: Vec<Zone> = z
            .terms
            .iter()
            .map(|t| {
                let op = match t.op {
                    Op::Inside => Op::Outside,
                    Op::Outside => Op::Inside,
                };
                Zone::new(vec![Term { op, ..*t }])
            })
            .collect();
        out = product(&out, &negated, budget)?;
    }
    Some(out)
}

/// What fills a region instead of (or inside) its own material.
#[derive(Clone, Debug, PartialEq)]
pub enum Fill {
    /// The regions of `universe`, moved into the region by
    /// `region_from_universe` (MCNP `FILL=u (TR)`, OpenMC's fill, FLUKA's
    /// lattice cells, which hold the root universe moved).
    Universe {
        /// Index into [`crate::Geometry::universes`] (0 is the root).
        universe: usize,
        /// Universe coordinates to the filled region's.
        region_from_universe: DAffine3,
    },
    /// A lattice of universes.
    Lattice(Lattice),
}

/// A lattice: elements in a rectangular or hexagonal grid, each holding a
/// universe moved to its place. Element `(i, j, k)` lies at
/// `base + i a + j b + k c` in the lattice's frame and its universe's
/// origin is moved to `origin + i a + j b + k c`.
#[derive(Clone, Debug, PartialEq)]
pub struct Lattice {
    /// The element shape.
    pub kind: LatticeKind,
    /// The lattice frame to the filled region's coordinates.
    pub region_from_lattice: DAffine3,
    /// The grid's steps: `a` and `b` in the plane, `c` along the third
    /// direction (for a hexagonal lattice, `a` and `b` are 60° apart and
    /// of the flat-to-flat pitch; `c` is the axial pitch).
    pub steps: [DVec3; 3],
    /// Rectangular: the lower corner of element (0, 0, 0). Hexagonal: its
    /// centre, at the middle of its height.
    pub base: DVec3,
    /// Where the universe's origin goes for element (0, 0, 0).
    pub origin: DVec3,
    /// The lowest index along each direction.
    pub lowest: [i32; 3],
    /// How many elements along each direction.
    pub counts: [u32; 3],
    /// The universe of each element, `i` fastest, then `j`, then `k`;
    /// `None` where an element holds nothing (the region's own material).
    pub elements: Vec<Option<usize>>,
    /// The universe beyond the listed elements, if any (OpenMC's outer
    /// universe); without one, space beyond them is the region's own.
    pub outer: Option<usize>,
}

/// The shape of a lattice's elements.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LatticeKind {
    /// Parallelepipeds spanned by the three steps.
    Rectangular,
    /// Hexagonal prisms: the points nearer the element's axis than any
    /// other's, between planes `c/2` either side of its centre.
    Hexagonal,
}

impl Lattice {
    /// The universe of element `(i, j, k)`: `None` beyond the listed
    /// elements unless there is an outer universe, or where the element
    /// holds nothing.
    pub fn element(&self, index: [i32; 3]) -> Option<usize> {
        let mut flat = 0usize;
        let mut stride = 1usize;
        for ((&i, &lowest), &count) in index.iter().zip(&self.lowest).zip(&self.counts) {
            let d = i64::from(i) - i64::from(lowest);
            if d < 0 || d >= i64::from(count) {
                return self.outer;
            }
            flat += d as usize * stride;
            stride *= count as usize;
        }
        self.elements.get(flat).copied().flatten()
    }
}

/// A universe: a set of regions that fill space together, referred to by
/// fills. Universe 0 is the root, the model itself.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Universe {
    /// Name or number as the input refers to it.
    pub name: String,
}

/// A region: the union of its zones (GIFT `OR`, FLUKA `|`, MCNP `:`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Region {
    /// Name or number.
    pub name: String,
    /// Zones, unioned.
    pub zones: Vec<Zone>,
    /// The universe the region belongs to (0: the root).
    pub universe: usize,
    /// What fills it, if anything.
    pub fill: Option<Fill>,
}

impl Region {
    /// The root region `name` of `zones`, unfilled.
    pub fn new(name: impl Into<String>, zones: Vec<Zone>) -> Region {
        Region {
            name: name.into(),
            zones,
            universe: 0,
            fill: None,
        }
    }

    /// The region `name` of one zone: body `body` alone.
    pub fn of_body(name: impl Into<String>, body: usize) -> Region {
        Region::new(
            name,
            vec![Zone::new(vec![Term {
                op: Op::Inside,
                body,
            }])],
        )
    }

    /// The region's expression as written, zones joined by `|`.
    pub fn expression<'a>(&self, name: &impl Fn(usize) -> &'a str) -> String {
        let zones: Vec<String> = self.zones.iter().map(|z| z.expression(name)).collect();
        zones.join(" | ")
    }

    /// Every body term of the region, its groups' included.
    pub fn for_each_term(&self, f: &mut impl FnMut(&Term)) {
        for z in &self.zones {
            z.for_each_term(f);
        }
    }

    /// The region's zones as zones of body terms only, if that takes at
    /// most `budget` zones (see [`Zone::flattened`]).
    pub fn flattened(&self, budget: usize) -> Option<Vec<Zone>> {
        flatten_union(&self.zones, budget)
    }

    /// True when the region has groups (it is not a plain union of zones of
    /// body terms).
    pub fn is_nested(&self) -> bool {
        self.zones.iter().any(|z| !z.groups.is_empty())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn t(op: char, body: usize) -> Term {
        let op = if op == '+' { Op::Inside } else { Op::Outside };
        Term { op, body }
    }

    #[test]
    fn flattening_distributes_and_uses_de_morgan() {
        // +0 -( +1 | +2 -3 ) = +0 -1 -2 | +0 -1 +3
        let z = Zone {
            terms: vec![t('+', 0)],
            groups: vec![Group {
                op: Op::Outside,
                zones: vec![
                    Zone::new(vec![t('+', 1)]),
                    Zone::new(vec![t('+', 2), t('-', 3)]),
                ],
            }],
        };
        let names = ["a", "b", "c", "d"];
        let name = |i: usize| names[i];
        assert_eq!(z.expression(&name), "+a -(+b | +c -d)");
        let flat: Vec<String> = z
            .flattened(10)
            .unwrap()
            .iter()
            .map(|z| z.expression(&name))
            .collect();
        assert_eq!(flat, ["+a -b -c", "+a -b +d"]);
        assert_eq!(z.flattened(1), None);
        assert_eq!(z.depth(), 1);
        let mut bodies = Vec::new();
        z.for_each_term(&mut |t| bodies.push(t.body));
        assert_eq!(bodies, [0, 1, 2, 3]);
    }

    #[test]
    fn a_lattice_finds_its_elements_and_its_outer_universe() {
        let mut l = Lattice {
            kind: LatticeKind::Rectangular,
            region_from_lattice: DAffine3::IDENTITY,
            steps: [DVec3::X, DVec3::Y, DVec3::Z],
            base: DVec3::ZERO,
            origin: DVec3::splat(0.5),
            lowest: [-1, 0, 0],
            counts: [3, 2, 1],
            elements: vec![Some(1), Some(2), None, Some(3), Some(4), Some(5)],
            outer: None,
        };
        assert_eq!(l.element([-1, 0, 0]), Some(1));
        assert_eq!(l.element([1, 0, 0]), None);
        assert_eq!(l.element([0, 1, 0]), Some(4));
        assert_eq!(l.element([2, 0, 0]), None);
        l.outer = Some(9);
        assert_eq!(l.element([2, 0, 0]), Some(9));
        assert_eq!(l.element([0, 0, -1]), Some(9));
    }
}
