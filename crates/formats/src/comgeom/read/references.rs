//! Region references (`G` fields): a region used inside another is
//! expanded into body terms (subtracting one uses De Morgan's law), within
//! the limits of [`MAX_ZONES`] zones and [`MAX_TERMS`] terms.

use super::{at, RawRegion, Reader, MAX_EXPANSION, MAX_REF_DEPTH, MAX_TERMS, MAX_ZONES};
use std::collections::HashMap;
use sv_geom::{Op, Term};

enum Resolve {
    Todo,
    Visiting,
    Done(Option<Vec<Vec<Term>>>),
}

impl<'a> Reader<'a> {
    pub(super) fn resolve_all(&mut self, regions: &[RawRegion]) -> Vec<Vec<Vec<Term>>> {
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

    /// The zones of region `i` with its region references expanded.
    // Over 120 lines, kept whole: this sum-of-products expansion is to be
    // replaced by expression trees, so it is moved here unchanged.
    fn resolve(
        &mut self,
        i: usize,
        regions: &[RawRegion],
        by_number: &HashMap<usize, usize>,
        memo: &mut Vec<Resolve>,
        depth: usize,
    ) -> Option<Vec<Vec<Term>>> {
        match &memo[i] {
            Resolve::Done(z) => {
                let z = z.clone();
                let size = z.as_ref().map_or(0, |z| z.iter().map(Vec::len).sum());
                return if self.charge(size) { z } else { None };
            }
            Resolve::Visiting => return None,
            Resolve::Todo => {}
        }
        memo[i] = Resolve::Visiting;
        let r = &regions[i];
        let mut out: Option<Vec<Vec<Term>>> = Some(Vec::new());
        for raw_zone in &r.zones {
            let mut set: Vec<Vec<Term>> = vec![Vec::new()];
            for t in raw_zone {
                let fail = |me: &mut Self, msg: String| {
                    me.error(t.line, t.col, 5, format!("{}: {msg}", at(t.line, t.col, 5)));
                };
                if !t.region_ref {
                    if !self.charge(set.len()) {
                        fail(self, format!("region {}: region references expand to more than {MAX_EXPANSION} terms in all", r.number));
                        out = None;
                        break;
                    }
                    let op = if t.negate { Op::Outside } else { Op::Inside };
                    for z in &mut set {
                        z.push(Term {
                            op,
                            body: t.number - 1,
                        });
                    }
                    continue;
                }
                let Some(&target) = by_number.get(&t.number) else {
                    fail(
                        self,
                        format!(
                            "region {} refers to region {}, which is not defined",
                            r.number, t.number
                        ),
                    );
                    out = None;
                    continue;
                };
                if matches!(memo[target], Resolve::Visiting) {
                    fail(
                        self,
                        format!("region {} refers to region {}, which leads back to region {} (a cycle)", r.number, t.number, r.number),
                    );
                    out = None;
                    continue;
                }
                if depth >= MAX_REF_DEPTH {
                    fail(
                        self,
                        format!("region references nest more than {MAX_REF_DEPTH} deep"),
                    );
                    out = None;
                    continue;
                }
                let Some(tz) = self.resolve(target, regions, by_number, memo, depth + 1) else {
                    out = None;
                    continue;
                };
                let expanded = if t.negate {
                    subtract(&set, &tz)
                } else {
                    intersect(&set, &tz)
                };
                let size = expanded
                    .as_ref()
                    .map_or(0, |e| e.iter().map(Vec::len).sum());
                match expanded {
                    Some(e) if self.charge(size) => set = e,
                    Some(_) => {
                        fail(self, format!("region {}: region references expand to more than {MAX_EXPANSION} terms in all", r.number));
                        out = None;
                        break;
                    }
                    None => {
                        let verb = if t.negate {
                            "subtracting"
                        } else {
                            "intersecting with"
                        };
                        fail(self, format!("region {}: {verb} region {} expands to more than {MAX_ZONES} zones", r.number, t.number))
                            ;
                        if let Some(last) = self.errors.last_mut() {
                            last.hint =
                                Some("write the region with body references instead".into());
                        }
                        out = None;
                        set = vec![Vec::new()];
                    }
                }
            }
            if let Some(o) = &mut out {
                o.extend(set);
                if o.len() > MAX_ZONES {
                    self.error(
                        r.line,
                        1,
                        5,
                        format!(
                            "line {}: region {} expands to more than {MAX_ZONES} zones",
                            r.line, r.number
                        ),
                    );
                    out = None;
                }
            }
        }
        if r.has_refs {
            if let Some(o) = &mut out {
                simplify(o);
            }
        }
        memo[i] = Resolve::Done(out.clone());
        out
    }
}

/// Each zone of `set` joined with each zone of `region`.
fn intersect(set: &[Vec<Term>], region: &[Vec<Term>]) -> Option<Vec<Vec<Term>>> {
    if set.len().checked_mul(region.len())? > MAX_ZONES {
        return None;
    }
    let mut out = Vec::with_capacity(set.len() * region.len());
    for z in set {
        for rz in region {
            if z.len() + rz.len() > MAX_TERMS {
                return None;
            }
            out.push(z.iter().chain(rz).copied().collect());
        }
    }
    Some(prune(out))
}

/// `set` minus every zone of `region`: by De Morgan, minus a zone
/// `t1 ∩ t2 ∩ …` is the union of the complements `¬t1 ∪ ¬t2 ∪ …`, so each
/// zone splits into one zone per term of the subtracted zone.
fn subtract(set: &[Vec<Term>], region: &[Vec<Term>]) -> Option<Vec<Vec<Term>>> {
    let mut cur = set.to_vec();
    for rz in region {
        if cur.len().checked_mul(rz.len())? > MAX_ZONES {
            return None;
        }
        let mut next = Vec::with_capacity(cur.len() * rz.len());
        for z in &cur {
            if z.len() >= MAX_TERMS {
                return None;
            }
            for t in rz {
                let op = if t.op == Op::Inside {
                    Op::Outside
                } else {
                    Op::Inside
                };
                let mut nz = z.clone();
                nz.push(Term { op, body: t.body });
                next.push(nz);
            }
        }
        cur = prune(next);
    }
    Some(cur)
}

/// Drop repeated terms, and zones that hold a body both inside and outside
/// (they are empty).
fn prune(zones: Vec<Vec<Term>>) -> Vec<Vec<Term>> {
    zones
        .into_iter()
        .filter_map(|z| {
            let mut seen: HashMap<usize, Op> = HashMap::with_capacity(z.len());
            let mut out: Vec<Term> = Vec::with_capacity(z.len());
            for t in z {
                match seen.insert(t.body, t.op) {
                    Some(op) if op != t.op => return None,
                    Some(_) => {}
                    None => out.push(t),
                }
            }
            Some(out)
        })
        .collect()
}

/// Prune, then drop repeated zones.
fn simplify(zones: &mut Vec<Vec<Term>>) {
    let mut seen = std::collections::HashSet::new();
    let z = prune(std::mem::take(zones));
    zones.extend(z.into_iter().filter(|zone| seen.insert(zone.clone())));
}
