//! Region references (`G` fields): a region used inside another becomes a
//! group of that region's zones, `+( … )` or `-( … )`, as written: nothing
//! is expanded into sums of products. Copies of referenced regions are
//! counted against [`MAX_EXPANSION`] terms, so that chains of regions that
//! each use the next many times stay bounded.

use super::{at, RawRegion, Reader, MAX_EXPANSION, MAX_REF_DEPTH};
use std::collections::HashMap;
use sv_geom::{Group, Op, Term, Zone};

enum Resolve {
    Todo,
    Visiting,
    Done(Option<Vec<Zone>>),
}

/// The terms a region's zones hold, groups included.
fn size(zones: &[Zone]) -> usize {
    zones
        .iter()
        .map(|z| z.terms.len() + z.groups.iter().map(|g| size(&g.zones)).sum::<usize>())
        .sum()
}

impl<'a> Reader<'a> {
    pub(super) fn resolve_all(&mut self, regions: &[RawRegion]) -> Vec<Vec<Zone>> {
        let by_number: HashMap<usize, usize> = regions
            .iter()
            .enumerate()
            .map(|(i, r)| (r.number as usize, i))
            .collect();
        let mut memo: Vec<Resolve> = regions.iter().map(|_| Resolve::Todo).collect();
        (0..regions.len())
            .map(|i| {
                self.resolve(i, regions, &by_number, &mut memo, 0)
                    .unwrap_or_default()
            })
            .collect()
    }

    /// Take `n` terms from the expansion budget; false when it is spent.
    fn charge(&mut self, n: usize) -> bool {
        match self.budget.checked_sub(n) {
            Some(b) => {
                self.budget = b;
                true
            }
            None => {
                self.budget = 0;
                false
            }
        }
    }

    /// The zones of region `i`, each region it refers to a group.
    fn resolve(
        &mut self,
        i: usize,
        regions: &[RawRegion],
        by_number: &HashMap<usize, usize>,
        memo: &mut Vec<Resolve>,
        depth: usize,
    ) -> Option<Vec<Zone>> {
        match &memo[i] {
            // Its copies are charged by `referred`.
            Resolve::Done(z) => return z.clone(),
            Resolve::Visiting => return None,
            Resolve::Todo => {}
        }
        memo[i] = Resolve::Visiting;
        let r = &regions[i];
        let mut out = Some(Vec::new());
        for raw_zone in &r.zones {
            let mut zone = Zone::default();
            for t in raw_zone {
                let op = if t.negate { Op::Outside } else { Op::Inside };
                if !t.region_ref {
                    zone.terms.push(Term {
                        op,
                        body: t.number - 1,
                    });
                    continue;
                }
                match self.referred(t, r, regions, by_number, memo, depth) {
                    Some(zones) => zone.groups.push(Group { op, zones }),
                    None => out = None,
                }
            }
            if let Some(o) = &mut out {
                o.push(zone);
            }
        }
        memo[i] = Resolve::Done(out.clone());
        out
    }

    /// The zones of the region that term `t` of region `r` refers to;
    /// `None` (reported) when it is not defined, leads back to `r`, nests
    /// too deep or spends the budget.
    fn referred(
        &mut self,
        t: &super::RawTerm,
        r: &RawRegion,
        regions: &[RawRegion],
        by_number: &HashMap<usize, usize>,
        memo: &mut Vec<Resolve>,
        depth: usize,
    ) -> Option<Vec<Zone>> {
        let fail = |me: &mut Self, msg: String| {
            me.error(t.line, t.col, 5, format!("{}: {msg}", at(t.line, t.col, 5)));
        };
        let Some(&target) = by_number.get(&t.number) else {
            fail(
                self,
                format!(
                    "region {} refers to region {}, which is not defined",
                    r.number, t.number
                ),
            );
            return None;
        };
        if matches!(memo[target], Resolve::Visiting) {
            fail(
                self,
                format!(
                    "region {} refers to region {}, which leads back to region {} (a cycle)",
                    r.number, t.number, r.number
                ),
            );
            return None;
        }
        if depth >= MAX_REF_DEPTH {
            fail(
                self,
                format!("region references nest more than {MAX_REF_DEPTH} deep"),
            );
            return None;
        }
        let zones = self.resolve(target, regions, by_number, memo, depth + 1)?;
        if !self.charge(size(&zones)) {
            fail(
                self,
                format!(
                    "region {}: region references copy more than {MAX_EXPANSION} terms in all",
                    r.number
                ),
            );
            return None;
        }
        Some(zones)
    }
}
