//! Surfaces to bodies, cell geometries to zones and groups.

use super::cell::{Factor, SurfaceRef, Union};
use super::params::Transform;
use super::surface::{is_macrobody, Boundary, Part};
use super::transform::affine;
use super::{macrobody, surface, Frame, Loc, Reader, MAX_TERMS};
use sv_geom::{Body, Group, Op, Term, Zone};
use sv_math::DAffine3;

/// How deep parentheses and `#n` complements may nest together (through
/// other cells' geometries); deeper is an error, not a stack overflow.
pub const MAX_DEPTH: usize = 300;

/// Where a cell's zones stand while cells are lowered.
#[derive(Clone, Debug)]
pub(super) enum State {
    Todo,
    Visiting,
    Done(Vec<Zone>),
    Failed,
}

/// The other side of a term.
fn flipped(t: Term) -> Term {
    Term {
        op: match t.op {
            Op::Inside => Op::Outside,
            Op::Outside => Op::Inside,
        },
        body: t.body,
    }
}

/// How many body terms zones hold.
pub(super) fn term_count(zones: &[Zone]) -> usize {
    zones
        .iter()
        .map(|z| z.terms.len() + z.groups.iter().map(|g| term_count(&g.zones)).sum::<usize>())
        .sum()
}

impl Reader {
    /// Every surface's bodies, and the notes on boundary conditions.
    pub(super) fn lower_surfaces(&mut self) {
        let mut special: [Vec<String>; 3] = Default::default();
        for s in 0..self.surfaces.len() {
            let card = &self.surfaces[s];
            let k = match card.boundary {
                Boundary::Plain => None,
                Boundary::Reflecting => Some(0),
                Boundary::White => Some(1),
                Boundary::Periodic => Some(2),
            };
            if let Some(k) = k {
                special[k].push(card.number.to_string());
            }
            let parts = if is_macrobody(&card.mnemonic) {
                macrobody::parts(&card.mnemonic, &card.values)
            } else {
                surface::parts(&card.mnemonic, &card.values)
            };
            let sides = match parts {
                Ok(parts) => self.add_parts(s, &parts),
                Err(msg) => {
                    let (at, n, m) = (
                        card.mnemonic_at,
                        card.number,
                        card.mnemonic.to_ascii_uppercase(),
                    );
                    self.log.error(at, format!("surface {n} ({m}): {msg}"));
                    None
                }
            };
            self.sides.push(sides);
        }
        for (list, what) in special
            .iter()
            .zip(["reflecting (`*`)", "white (`+`)", "periodic"])
        {
            if !list.is_empty() {
                self.notes.push(format!(
                    "{what} surfaces are read as ordinary surfaces: {}",
                    list.join(", ")
                ));
            }
        }
    }

    /// The bodies of a surface's parts (moved by its `TR` card), as terms
    /// whose intersection is the surface's negative side.
    pub(super) fn add_parts(&mut self, s: usize, parts: &[Part]) -> Option<Vec<Term>> {
        let card = &self.surfaces[s];
        let (number, mnemonic_at) = (card.number, card.mnemonic_at);
        let mnemonic = card.mnemonic.to_ascii_uppercase();
        let xf = match card.transform {
            None => None,
            Some((t, at)) => match self.transforms.get(&t) {
                Some((xf, _)) => Some((*xf, t, at)),
                None => {
                    self.log
                        .error(at, format!("transformation TR{t} is not defined"))
                        .hint = Some(format!("define it with a `TR{t}` card in the data block"));
                    return None;
                }
            },
        };
        let mut terms = Vec::with_capacity(parts.len());
        for part in parts {
            let key = (s, part.suffix.clone());
            if let Some(&body) = self.part_bodies.get(&key) {
                terms.push(Term { op: part.op, body });
                continue;
            }
            let mut body = Body::new(
                format!("{number}{}", part.suffix),
                part.kind,
                part.params.clone(),
            );
            if let Some((xf, t, at)) = xf {
                match body.transformed(&xf) {
                    Ok(b) => body = b,
                    Err(e) => {
                        self.log.error(
                            at,
                            format!("surface {number} cannot be moved by TR{t}: {e}"),
                        );
                        return None;
                    }
                }
            }
            let mut warnings = Vec::new();
            if let Err(msg) = sv_geom::prepare(&body, &mut warnings) {
                self.log
                    .error(mnemonic_at, format!("surface {number} ({mnemonic}): {msg}"));
                return None;
            }
            for w in warnings {
                self.log.warn(
                    mnemonic_at,
                    format!("surface {number} ({mnemonic}): {}", w.message),
                );
            }
            self.part_bodies.insert(key, self.bodies.len());
            terms.push(Term {
                op: part.op,
                body: self.bodies.len(),
            });
            self.bodies.push(body);
        }
        Some(terms)
    }

    /// Facet `k` of surface `s` as terms.
    pub(super) fn facet_terms(&mut self, s: usize, k: u8, at: Loc) -> Option<Vec<Term>> {
        if let Some(done) = self.facets.get(&(s, k)) {
            return done.clone();
        }
        let card = &self.surfaces[s];
        let (n, m) = (card.number, card.mnemonic.clone());
        let terms = if !is_macrobody(&m) {
            self.log.error(
                at,
                format!(
                    "surface {n} is a {} surface, not a macrobody: it has no facets",
                    m.to_ascii_uppercase()
                ),
            );
            None
        } else if self.sides[s].is_none() {
            None
        } else {
            match macrobody::facet(&m, &self.surfaces[s].values, k as usize) {
                Ok(parts) => self.add_parts(s, &parts),
                Err(msg) => {
                    self.log.error(at, format!("surface {n}: {msg}"));
                    None
                }
            }
        };
        self.facets.insert((s, k), terms.clone());
        terms
    }

    /// The body `b` moved into a cell's frame (named as MCNP names the
    /// surfaces a `TRCL` makes: 1000 × cell + surface).
    fn moved_body(&mut self, b: usize, frame: Frame, at: Loc) -> Option<usize> {
        if let Some(&m) = self.moved.get(&(b, frame.cell)) {
            return Some(m);
        }
        let body = &self.bodies[b];
        let digits = body.name.chars().take_while(|c| c.is_ascii_digit()).count();
        let (number, suffix) = body.name.split_at(digits);
        let number: i64 = number.parse().unwrap_or(0);
        let name = if number < 1000 && frame.cell < 100_000 {
            format!("{}{suffix}", frame.cell * 1000 + number)
        } else {
            format!("{number}{suffix}@{}", frame.cell)
        };
        // A frame's transformation is a rotation and a translation, which
        // every body takes; only values out of range can fail.
        let moved = body
            .transformed(&frame.xf)
            .ok()
            .filter(|m| m.params.iter().all(|v| v.is_finite()));
        let Some(mut moved) = moved else {
            let cell = frame.cell;
            self.log.error(
                at,
                format!("this surface moved by the TRCL of cell {cell} has values out of range"),
            );
            return None;
        };
        moved.name = name;
        self.moved.insert((b, frame.cell), self.bodies.len());
        self.bodies.push(moved);
        Some(self.bodies.len() - 1)
    }

    /// The negative side of a surface named in a cell, in the cell's
    /// frame.
    pub(super) fn surface_terms(
        &mut self,
        r: &SurfaceRef,
        frame: Option<Frame>,
    ) -> Option<Vec<Term>> {
        let (s, frame) = match self.surface_index.get(&r.number) {
            Some(&s) => (s, frame),
            None => match self.implicit_surface(r.number) {
                Some(found) => found,
                None => {
                    if !self.bad_surfaces.contains(&r.number) {
                        self.log
                            .error(r.at, format!("surface {} is not defined", r.number));
                    }
                    return None;
                }
            },
        };
        let terms = match r.facet {
            None => self.sides[s].clone()?,
            Some(k) => self.facet_terms(s, k, r.at)?,
        };
        match frame {
            None => Some(terms),
            Some(f) => terms
                .into_iter()
                .map(|t| {
                    let body = self.moved_body(t.body, f, r.at)?;
                    Some(Term { op: t.op, body })
                })
                .collect(),
        }
    }

    /// Surface 1000 c + s: surface s moved by cell c's `TRCL`.
    fn implicit_surface(&self, n: i64) -> Option<(usize, Option<Frame>)> {
        let (cell, s) = (n / 1000, n % 1000);
        let frame = (*self.frames.get(&cell)?)?;
        Some((*self.surface_index.get(&s)?, Some(frame)))
    }

    /// A transformation given on a cell (`TRCL`, a fill's), or `None`
    /// reported.
    pub(super) fn transform_of(&mut self, t: &Transform) -> Option<DAffine3> {
        match t {
            Transform::Card(0, _) => Some(DAffine3::IDENTITY),
            Transform::Card(n, at) => match self.transforms.get(n) {
                Some((xf, _)) => Some(*xf),
                None => {
                    self.log
                        .error(*at, format!("transformation TR{n} is not defined"));
                    None
                }
            },
            Transform::Values {
                values,
                degrees,
                at,
            } => match affine(values, *degrees) {
                Ok(xf) => Some(xf),
                Err(msg) => {
                    self.log.error(*at, msg);
                    None
                }
            },
        }
    }

    /// The zones of cell `i`'s geometry as written (its `TRCL` applied).
    pub(super) fn cell_zones(&mut self, i: usize, depth: usize) -> Option<Vec<Zone>> {
        match &self.states[i] {
            State::Done(z) => return Some(z.clone()),
            State::Failed | State::Visiting => return None,
            State::Todo => {}
        }
        self.states[i] = State::Visiting;
        let geometry = std::mem::take(&mut self.cells[i].geometry);
        let frame = self.frames.get(&self.cells[i].number).copied().flatten();
        let zones = self.union_zones(&geometry, frame, i, depth);
        self.cells[i].geometry = geometry;
        self.states[i] = match &zones {
            Some(z) => State::Done(z.clone()),
            None => State::Failed,
        };
        zones
    }

    fn union_zones(
        &mut self,
        u: &Union,
        frame: Option<Frame>,
        me: usize,
        depth: usize,
    ) -> Option<Vec<Zone>> {
        let mut out = Vec::with_capacity(u.len());
        let mut ok = true;
        for inter in u {
            let mut zone = Zone::default();
            for f in inter {
                ok &= self.add_factor(&mut zone, f, frame, me, depth).is_some();
            }
            out.push(zone);
        }
        ok.then_some(out)
    }

    fn count_terms(&mut self, n: usize, me: usize) -> Option<()> {
        let before = self.terms;
        self.terms += n;
        if self.terms > MAX_TERMS {
            if before <= MAX_TERMS {
                let at = self.cells[me].at;
                self.log.error(at, format!("the geometry grows past {MAX_TERMS} terms as `#` complements are copied in"));
            }
            return None;
        }
        Some(())
    }

    fn add_factor(
        &mut self,
        zone: &mut Zone,
        f: &Factor,
        frame: Option<Frame>,
        me: usize,
        depth: usize,
    ) -> Option<()> {
        if depth > MAX_DEPTH {
            if !std::mem::replace(&mut self.too_deep, true) {
                let (at, n) = (self.cells[me].at, self.cells[me].number);
                self.log.error(at, format!("the geometry of cell {n} nests more than {MAX_DEPTH} deep (parentheses and `#` complements together)"));
            }
            return None;
        }
        match f {
            Factor::Surface(r) => {
                let terms = self.surface_terms(r, frame)?;
                self.count_terms(terms.len(), me)?;
                if r.negative {
                    zone.terms.extend(terms);
                } else if let [t] = terms.as_slice() {
                    zone.terms.push(flipped(*t));
                } else {
                    zone.groups.push(Group {
                        op: Op::Outside,
                        zones: vec![Zone::new(terms)],
                    });
                }
            }
            Factor::NotCell(n, at) => {
                let zones = self.complement(*n, *at, me, depth)?;
                self.count_terms(term_count(&zones), me)?;
                zone.groups.push(Group {
                    op: Op::Outside,
                    zones,
                });
            }
            Factor::Not(u) => {
                let zones = self.union_zones(u, frame, me, depth + 1)?;
                zone.groups.push(Group {
                    op: Op::Outside,
                    zones,
                });
            }
            Factor::Group(u) if u.len() == 1 => {
                let mut ok = true;
                for g in &u[0] {
                    ok &= self.add_factor(zone, g, frame, me, depth + 1).is_some();
                }
                ok.then_some(())?;
            }
            Factor::Group(u) => {
                let zones = self.union_zones(u, frame, me, depth + 1)?;
                zone.groups.push(Group {
                    op: Op::Inside,
                    zones,
                });
            }
        }
        Some(())
    }

    /// The zones of cell `n` for a `#n` written in cell `me`.
    fn complement(&mut self, n: i64, at: Loc, me: usize, depth: usize) -> Option<Vec<Zone>> {
        let Some(&j) = self.cell_index.get(&n) else {
            if !self.bad_cells.contains(&n) {
                self.log.error(at, format!("cell {n} is not defined"));
            }
            return None;
        };
        let here = self.cells[me].number;
        if j == me {
            self.log
                .error(at, format!("cell {here} refers to itself through `#{n}`"));
            return None;
        }
        if matches!(self.states[j], State::Visiting) {
            self.log
                .error(
                    at,
                    format!("cell {here} and cell {n} refer to each other through `#`"),
                )
                .hint = Some("a cell's complement `#n` cannot lead back to the cell".into());
            return None;
        }
        self.cell_zones(j, depth + 1)
    }
}
