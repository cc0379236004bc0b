//! Cells to regions: `LIKE n BUT` resolved, frames (`TRCL`), universes,
//! fills checked for undefined universes and cycles, region properties.

use super::cell::CellCard;
use super::lower::State;
use super::params::{FillSpec, Params};
use super::{Frame, Loc, Reader};
use std::collections::HashMap;
use sv_geom::{Fill, Geometry, Op, Region, Term, Universe, Zone};
use sv_math::DAffine3;
use sv_scene::{RegionProps, Scene, Units};

/// All space, as the union of the inside and the outside of the first body
/// `zones` name (a zone must name something): what a lattice cell covers
/// in its universe, and a universe made to hold a moved one.
pub(super) fn all_space(zones: &[Zone]) -> Vec<Zone> {
    let mut first = None;
    for z in zones {
        z.for_each_term(&mut |t| {
            first.get_or_insert(t.body);
        });
    }
    match first {
        Some(body) => [Op::Inside, Op::Outside]
            .map(|op| Zone::new(vec![Term { op, body }]))
            .to_vec(),
        None => vec![Zone::default()],
    }
}

/// `b`'s parameters where `a` gives none.
fn merged(a: &Params, b: &Params) -> Params {
    Params {
        imp_neutron: a.imp_neutron.or(b.imp_neutron),
        imp_other: a.imp_other.or(b.imp_other),
        universe: a.universe.or(b.universe),
        lattice: a.lattice.or(b.lattice),
        fill: a.fill.clone().or_else(|| b.fill.clone()),
        trcl: a.trcl.clone().or_else(|| b.trcl.clone()),
        material: None,
        density: None,
    }
}

impl Reader {
    /// Every `LIKE n BUT` cell made a copy of cell n with its changes.
    pub(super) fn resolve_likes(&mut self) {
        let mut done = vec![false; self.cells.len()];
        for i in 0..self.cells.len() {
            let mut chain = Vec::new();
            self.resolve_like(i, &mut done, &mut chain);
        }
        // Cells in error are dropped; references to them stay quiet.
        let mut kept = Vec::with_capacity(self.cells.len());
        for c in std::mem::take(&mut self.cells) {
            if c.like.is_some() {
                self.bad_cells.insert(c.number);
            } else {
                kept.push(c);
            }
        }
        self.cells = kept;
        self.cell_index.clear();
        for (i, c) in self.cells.iter().enumerate() {
            self.cell_index.entry(c.number).or_insert(i);
        }
    }

    fn resolve_like(&mut self, i: usize, done: &mut [bool], chain: &mut Vec<usize>) {
        if done[i] {
            return;
        }
        let Some((n, at)) = self.cells[i].like else {
            done[i] = true;
            return;
        };
        let Some(&j) = self.cell_index.get(&n) else {
            self.log.error(at, format!("cell {n} is not defined"));
            done[i] = true;
            return;
        };
        if j == i || chain.contains(&j) {
            let here = self.cells[i].number;
            self.log.error(
                at,
                format!("cell {here} is LIKE cell {n}, which leads back to it"),
            );
            done[i] = true;
            return;
        }
        chain.push(i);
        self.resolve_like(j, done, chain);
        chain.pop();
        done[i] = true;
        let base = &self.cells[j];
        if base.like.is_some() {
            return;
        }
        let cell = &self.cells[i];
        let mut copy = CellCard {
            number: cell.number,
            at: cell.at,
            like: None,
            params: merged(&cell.params, &base.params),
            description: cell
                .description
                .clone()
                .or_else(|| base.description.clone()),
            ..base.clone()
        };
        if let Some((m, at)) = cell.params.material {
            copy.material = m;
            copy.material_at = at;
            if m == 0 {
                copy.density = None;
            }
        }
        if let Some((d, _)) = cell.params.density {
            copy.density = Some(d);
        }
        self.cells[i] = copy;
    }

    /// The frame of every cell with a `TRCL`.
    fn frames(&mut self) {
        for i in 0..self.cells.len() {
            let Some(t) = self.cells[i].params.trcl.clone() else {
                continue;
            };
            let xf = self.transform_of(&t);
            let cell = self.cells[i].number;
            self.frames.insert(cell, xf.map(|xf| Frame { cell, xf }));
        }
    }

    /// Universe numbers to indices (0 is the root), in order of first use.
    fn universes(&mut self) -> (Vec<Universe>, HashMap<i64, usize>) {
        let mut list = vec![Universe { name: "0".into() }];
        let mut index = HashMap::from([(0, 0)]);
        let mut negative = Vec::new();
        for c in &self.cells {
            if let Some((u, _)) = c.params.universe {
                if u < 0 {
                    negative.push(c.number.to_string());
                }
                index.entry(u.abs()).or_insert_with(|| {
                    list.push(Universe {
                        name: u.abs().to_string(),
                    });
                    list.len() - 1
                });
            }
        }
        if !negative.is_empty() {
            self.notes.push(format!(
                "a negative U (cells {}) only tells MCNP the cell is not cut by the cell it fills; it is read as its absolute value",
                negative.join(", ")
            ));
        }
        (list, index)
    }

    /// The universes each cell's fill names: undefined ones reported, and
    /// universes that fill themselves through other universes.
    fn check_fills(&mut self, index: &HashMap<i64, usize>) {
        let mut edges: Vec<Vec<(usize, Loc)>> = vec![Vec::new(); index.len()];
        for c in &self.cells {
            let Some(fill) = &c.params.fill else { continue };
            let own = c.params.universe.map_or(0, |u| u.0.abs());
            let from = index[&own];
            let lattice = c.params.lattice.is_some();
            let fillers = match &fill.spec {
                FillSpec::One(f) => std::slice::from_ref(f),
                FillSpec::Array { elements, .. } => elements.as_slice(),
            };
            for f in fillers {
                if lattice && (f.universe == own || f.universe == 0) {
                    continue;
                }
                match index.get(&f.universe) {
                    Some(&to) if f.universe != 0 => edges[from].push((to, f.at)),
                    _ => {
                        let u = f.universe;
                        self.log.error(
                            f.at,
                            format!("universe {u} is not defined: no cell has U={u}"),
                        );
                    }
                }
            }
        }
        // Depth-first search; a universe met again on the path is a cycle.
        let mut colour = vec![0u8; edges.len()];
        for start in 0..edges.len() {
            if colour[start] != 0 {
                continue;
            }
            let mut stack = vec![(start, 0usize)];
            colour[start] = 1;
            while let Some(&mut (u, ref mut next)) = stack.last_mut() {
                if let Some(&(to, at)) = edges[u].get(*next) {
                    *next += 1;
                    match colour[to] {
                        0 => {
                            colour[to] = 1;
                            stack.push((to, 0));
                        }
                        1 => {
                            self.log.error(at, "this fill makes universes fill each other in a loop")
                                .hint = Some("a universe cannot be inside itself, directly or through other universes".into());
                        }
                        _ => {}
                    }
                } else {
                    colour[u] = 2;
                    stack.pop();
                }
            }
        }
    }

    /// The regions, then the scene.
    pub(super) fn lower_cells(&mut self) -> Option<Scene> {
        self.frames();
        let (mut universes, index) = self.universes();
        self.check_fills(&index);
        self.states = vec![State::Todo; self.cells.len()];
        let mut regions = Vec::with_capacity(self.cells.len());
        let mut props = Vec::with_capacity(self.cells.len());
        let mut wrappers = Vec::new();
        for i in 0..self.cells.len() {
            let Some(zones) = self.cell_zones(i, 0) else {
                continue;
            };
            let c = self.cells[i].clone();
            let universe = index[&c.params.universe.map_or(0, |u| u.0.abs())];
            let frame = self.frames.get(&c.number).copied().flatten();
            let mut region = Region {
                name: c.number.to_string(),
                zones,
                universe,
                fill: None,
            };
            if c.params.lattice.is_some() {
                if universe == 0 {
                    let at = c.params.lattice.map_or(c.at, |l| l.1);
                    self.log
                        .error(
                            at,
                            format!("lattice cell {} belongs to no universe", c.number),
                        )
                        .hint = Some(
                        "a lattice cell needs `U=`: its universe is what the lattice fills".into(),
                    );
                    continue;
                }
                region.zones = all_space(&region.zones);
                region.fill = self.lattice(i, frame, &index, &mut universes, &mut wrappers);
            } else if let Some(fill) = &c.params.fill {
                region.fill = match &fill.spec {
                    FillSpec::One(f) => {
                        let moved = match &f.transform {
                            Some(t) => self.transform_of(t),
                            None => Some(DAffine3::IDENTITY),
                        };
                        let universe = index.get(&f.universe).copied();
                        moved.zip(universe).map(|(m, universe)| Fill::Universe {
                            universe,
                            region_from_universe: frame.map_or(DAffine3::IDENTITY, |f| f.xf) * m,
                        })
                    }
                    FillSpec::Array { .. } => {
                        self.log
                            .error(
                                fill.at,
                                format!("cell {} has a FILL array but no LAT", c.number),
                            )
                            .hint = Some(
                            "only a lattice cell (`LAT=1` or `LAT=2`) takes an array of universes"
                                .into(),
                        );
                        None
                    }
                };
            }
            props.push(self.props(&c, region.fill.is_some()));
            regions.push(region);
        }
        for (region, p) in wrappers {
            regions.push(region);
            props.push(p);
        }
        if !self.log.errors.is_empty() {
            return None;
        }
        Some(self.scene(regions, props, universes))
    }

    fn props(&mut self, c: &CellCard, filled: bool) -> RegionProps {
        let p = &c.params;
        let outside =
            p.imp_neutron == Some(0.0) || (p.imp_neutron.is_none() && p.imp_other == Some(0.0));
        let mut props = RegionProps {
            material: c.material,
            outside,
            description: c.description.clone().unwrap_or_default(),
            ..RegionProps::default()
        };
        if c.material > 0 {
            props.material_name = Some(format!("m{}", c.material));
            props.material_index = self.material_index.get(&c.material).copied();
            if props.material_index.is_none() && self.missing_materials.insert(c.material) {
                self.log.warn(
                    c.material_at,
                    format!("material {} has no M card", c.material),
                );
            }
            match c.density {
                Some(d) if d < 0.0 => props.density = Some(-d),
                Some(d) if d > 0.0 => props.atom_density = Some(d),
                _ => {}
            }
        } else if !filled && !outside {
            // A void that nothing fills is air: left out of pictures unless
            // asked for, as COMGEOM's air regions are.
            props.air = 1;
            props.transparent = true;
        }
        if outside {
            props.transparent = true;
        }
        props
    }

    fn scene(
        &mut self,
        regions: Vec<Region>,
        props: Vec<RegionProps>,
        universes: Vec<Universe>,
    ) -> Scene {
        if !self.skipped.is_empty() {
            let shown = if self.skipped.len() > 12 {
                format!("{}, …", self.skipped[..12].join(", "))
            } else {
                self.skipped.join(", ")
            };
            self.notes.push(format!(
                "data cards that do not concern the geometry were skipped: {shown}"
            ));
        }
        Scene {
            title: self.title.clone(),
            units: Units::Centimetre,
            geometry: Geometry {
                bodies: std::mem::take(&mut self.bodies),
                regions,
                universes: if universes.len() > 1 {
                    universes
                } else {
                    Vec::new()
                },
            },
            regions: props,
            materials: std::mem::take(&mut self.materials),
            notes: std::mem::take(&mut self.notes),
            ..Scene::default()
        }
    }
}
