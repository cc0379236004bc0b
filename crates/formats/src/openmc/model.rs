//! The model a geometry makes: universes (the root is the one no fill
//! uses), fills resolved to universes or lattices, fill cycles found, the
//! cells beyond vacuum boundaries marked outside, and each cell's material.

use super::cells::{Cell, Content};
use super::lattice::LatticeSpec;
use super::materials::Materials;
use super::surfaces::{Boundary, Surface};
use super::xml::{Sink, Xml};
use crate::Diagnostic;
use std::collections::{HashMap, HashSet};
use sv_geom::{Fill, Geometry, Region, Universe};
use sv_scene::{RegionProps, Scene, Units};

/// At most this many lattice elements in all the lattice fills together:
/// each filled cell holds its own copy of its lattice, and a hostile file
/// could otherwise fill many cells with one large lattice.
pub const MAX_LATTICE_ELEMENTS: usize = 1 << 24;

/// Everything a geometry file holds, read.
pub(super) struct Parts<'a> {
    /// Surfaces, in file order.
    pub surfaces: Vec<Surface>,
    /// Cells, in file order.
    pub cells: Vec<Cell<'a>>,
    /// Lattices, in file order.
    pub lattices: Vec<LatticeSpec<'a>>,
    /// The ids of lattices whose definitions have errors.
    pub broken_lattices: HashSet<i64>,
    /// The universes of cells whose definitions have errors.
    pub broken_universes: HashSet<i64>,
}

/// What a cell's fill turned out to be.
#[derive(Clone, Copy)]
enum FillRef {
    /// A universe, by id.
    Universe(i64),
    /// A lattice, by index in [`Parts::lattices`].
    Lattice(usize),
}

/// The materials and the file they were read from.
pub(super) struct MaterialsFile<'m> {
    /// The materials.
    pub materials: Materials,
    /// The file, for the names in messages.
    pub xml: Xml<'m>,
}

/// The scene of a geometry, or `None` after reporting why not.
pub(super) fn build(
    xml: &Xml,
    sink: &mut Sink,
    parts: Parts,
    materials: Option<&MaterialsFile>,
) -> Option<Scene> {
    if parts.cells.is_empty() {
        if !sink.failed() {
            sink.error(Diagnostic::error(
                xml.src,
                0,
                0,
                "the geometry has no cells",
            ));
        }
        return None;
    }
    let mut universe_ids: Vec<i64> = Vec::new();
    let mut first_cell: HashMap<i64, usize> = HashMap::new();
    for (i, c) in parts.cells.iter().enumerate() {
        first_cell.entry(c.universe).or_insert_with(|| {
            universe_ids.push(c.universe);
            i
        });
    }
    let lattice_index: HashMap<i64, usize> = parts
        .lattices
        .iter()
        .enumerate()
        .map(|(i, l)| (l.id, i))
        .collect();
    let fills = resolve_fills(xml, sink, &parts, &first_cell, &lattice_index);
    check_lattice_universes(xml, sink, &parts, &first_cell);
    check_lattice_total(xml, sink, &parts, &fills);
    let props: Vec<RegionProps> = parts
        .cells
        .iter()
        .map(|cell| props(xml, sink, cell, materials))
        .collect();
    // Cycles are looked for among what was read, whatever else is wrong.
    let edges = universe_edges(&parts, &fills, &universe_ids);
    if report_cycles(xml, sink, &parts, &universe_ids, &edges) || sink.failed() {
        return None;
    }
    let root = root_universe(xml, sink, &parts, &universe_ids, &first_cell, &edges)?;
    // The root first, then the others in the order their cells come.
    let mut order = vec![root];
    order.extend(universe_ids.iter().copied().filter(|u| *u != root));
    let universe_index: HashMap<i64, usize> =
        order.iter().enumerate().map(|(i, u)| (*u, i)).collect();
    let mut scene = Scene {
        units: Units::Centimetre,
        geometry: Geometry {
            bodies: parts.surfaces.iter().map(|s| s.body.clone()).collect(),
            universes: order
                .iter()
                .map(|u| Universe {
                    name: u.to_string(),
                })
                .collect(),
            ..Geometry::default()
        },
        ..Scene::default()
    };
    for ((cell, fill), props) in parts.cells.iter().zip(&fills).zip(props) {
        let region = Region {
            name: cell.id.to_string(),
            zones: cell.zones.clone(),
            universe: universe_index[&cell.universe],
            fill: fill.map(|f| match f {
                FillRef::Universe(u) => Fill::Universe {
                    universe: universe_index[&u],
                    region_from_universe: cell.region_from_fill,
                },
                FillRef::Lattice(l) => Fill::Lattice(
                    parts.lattices[l]
                        .lower(|u| universe_index.get(&u).copied(), cell.region_from_fill),
                ),
            }),
        };
        scene.push_region(region, props);
    }
    if let Some(m) = materials {
        scene.materials = m.materials.list.clone();
    }
    super::outside::mark(&mut scene, &parts.surfaces);
    boundary_notes(&mut scene, &parts.surfaces);
    (!sink.failed()).then_some(scene)
}

/// Each cell's fill: a universe if one has that id, else a lattice.
fn resolve_fills(
    xml: &Xml,
    sink: &mut Sink,
    parts: &Parts,
    first_cell: &HashMap<i64, usize>,
    lattice_index: &HashMap<i64, usize>,
) -> Vec<Option<FillRef>> {
    let mut out = Vec::with_capacity(parts.cells.len());
    for cell in &parts.cells {
        let Content::Fill(id, value) = &cell.content else {
            out.push(None);
            continue;
        };
        if first_cell.contains_key(id) {
            out.push(Some(FillRef::Universe(*id)));
        } else if let Some(&l) = lattice_index.get(id) {
            out.push(Some(FillRef::Lattice(l)));
        } else if parts.broken_lattices.contains(id) || parts.broken_universes.contains(id) {
            // Its errors are reported where it is defined.
            out.push(None);
        } else {
            sink.error(
                xml.error(value, format!("fill {id} of cell {} is neither a universe nor a lattice", cell.id))
                    .with_hint(format!(
                        "a universe is made by cells with universe=\"{id}\"; a lattice by <lattice id=\"{id}\">"
                    )),
            );
            out.push(None);
        }
    }
    out
}

/// The lattice fills together stay within [`MAX_LATTICE_ELEMENTS`].
fn check_lattice_total(xml: &Xml, sink: &mut Sink, parts: &Parts, fills: &[Option<FillRef>]) {
    let mut total = 0usize;
    for (cell, fill) in parts.cells.iter().zip(fills) {
        let (Some(FillRef::Lattice(l)), Content::Fill(_, value)) = (fill, &cell.content) else {
            continue;
        };
        total += parts.lattices[*l].order.len();
        if total > MAX_LATTICE_ELEMENTS {
            sink.error(xml.error(
                value,
                format!("the lattice fills up to cell {} hold more than {MAX_LATTICE_ELEMENTS} elements", cell.id),
            ));
            return;
        }
    }
}

/// Every universe a lattice lists must have cells.
fn check_lattice_universes(
    xml: &Xml,
    sink: &mut Sink,
    parts: &Parts,
    first_cell: &HashMap<i64, usize>,
) {
    // Universes whose cells have errors were reported there.
    let mut reported = parts.broken_universes.clone();
    for l in &parts.lattices {
        for (u, word) in &l.universes {
            if !first_cell.contains_key(u) && reported.insert(*u) {
                sink.error(xml.error_at(
                    &l.universes_value,
                    word,
                    format!(
                        "lattice {} holds universe {u}, which no cell belongs to",
                        l.id
                    ),
                ));
            }
        }
        if let Some((u, value)) = &l.outer {
            if !first_cell.contains_key(u) && !parts.broken_universes.contains(u) {
                sink.error(xml.error(
                    value,
                    format!("the outer universe {u} of lattice {} has no cells", l.id),
                ));
            }
        }
    }
}

/// For each universe (index in `universe_ids`), the universes its cells'
/// fills hold, each with the cell that fills.
fn universe_edges(
    parts: &Parts,
    fills: &[Option<FillRef>],
    universe_ids: &[i64],
) -> Vec<Vec<(usize, usize)>> {
    let position: HashMap<i64, usize> = universe_ids
        .iter()
        .enumerate()
        .map(|(i, u)| (*u, i))
        .collect();
    let mut edges = vec![Vec::new(); universe_ids.len()];
    for (c, (cell, fill)) in parts.cells.iter().zip(fills).enumerate() {
        let from = position[&cell.universe];
        let mut held: Vec<i64> = match fill {
            Some(FillRef::Universe(u)) => vec![*u],
            Some(FillRef::Lattice(l)) => {
                let l = &parts.lattices[*l];
                l.universes
                    .iter()
                    .map(|(u, _)| *u)
                    .chain(l.outer.as_ref().map(|(u, _)| *u))
                    .collect()
            }
            None => Vec::new(),
        };
        held.sort_unstable();
        held.dedup();
        edges[from].extend(
            held.iter()
                .filter_map(|u| position.get(u))
                .map(|&to| (to, c)),
        );
    }
    edges
}

/// Report every fill cycle (a universe inside itself); true if any.
fn report_cycles(
    xml: &Xml,
    sink: &mut Sink,
    parts: &Parts,
    universe_ids: &[i64],
    edges: &[Vec<(usize, usize)>],
) -> bool {
    // Iterative depth-first search: 0 unvisited, 1 on the path, 2 done.
    let mut state = vec![0u8; edges.len()];
    let mut found = false;
    for start in 0..edges.len() {
        if state[start] != 0 {
            continue;
        }
        let mut stack: Vec<(usize, usize)> = vec![(start, 0)];
        // The cells of the edges taken down the stack.
        let mut path: Vec<usize> = Vec::new();
        state[start] = 1;
        while let Some(&mut (node, ref mut next)) = stack.last_mut() {
            let Some(&(to, cell)) = edges[node].get(*next) else {
                state[node] = 2;
                stack.pop();
                path.pop();
                continue;
            };
            *next += 1;
            match state[to] {
                0 => {
                    state[to] = 1;
                    stack.push((to, 0));
                    path.push(cell);
                }
                1 => {
                    found = true;
                    let from = stack.iter().position(|(n, _)| *n == to).unwrap_or(0);
                    let cycle: Vec<usize> = path[from..].iter().copied().chain([cell]).collect();
                    sink.error(cycle_error(xml, parts, universe_ids[to], &cycle));
                }
                _ => {}
            }
        }
    }
    found
}

fn cycle_error(xml: &Xml, parts: &Parts, universe: i64, cells: &[usize]) -> Diagnostic {
    // A long cycle is shown by its ends.
    const SHOWN: usize = 4;
    let mut chain = format!("universe {universe}");
    for (i, &c) in cells.iter().enumerate() {
        if cells.len() > 3 * SHOWN && (SHOWN..cells.len() - SHOWN).contains(&i) {
            if i == SHOWN {
                chain.push_str(&format!(" → … {} more fills", cells.len() - 2 * SHOWN));
            }
            continue;
        }
        let cell = &parts.cells[c];
        if let Content::Fill(fill, _) = &cell.content {
            chain.push_str(&format!(" → cell {} fills {fill}", cell.id));
        }
    }
    let last = &parts.cells[cells[cells.len() - 1]];
    let d = match &last.content {
        Content::Fill(_, value) => xml.error(value, format!("fill cycle: {chain}")),
        Content::Materials(..) => Diagnostic::error(xml.src, last.tag.0, last.tag.1, chain),
    };
    d.with_hint(format!("universe {universe} ends up inside itself: no fill may lead back to a universe that contains it"))
}

/// The root universe: 0 when it has cells (OpenMC's early rule, which
/// current OpenMC's agrees with whenever 0 is used), else the one universe
/// no fill uses.
fn root_universe(
    xml: &Xml,
    sink: &mut Sink,
    parts: &Parts,
    universe_ids: &[i64],
    first_cell: &HashMap<i64, usize>,
    edges: &[Vec<(usize, usize)>],
) -> Option<i64> {
    let mut used = vec![false; universe_ids.len()];
    for e in edges.iter().flatten() {
        used[e.0] = true;
    }
    let unused: Vec<i64> = universe_ids
        .iter()
        .zip(&used)
        .filter(|(_, used)| !**used)
        .map(|(u, _)| *u)
        .collect();
    let root = if first_cell.contains_key(&0) {
        0
    } else if let [only] = unused[..] {
        only
    } else {
        let second = unused.get(1).copied().unwrap_or(universe_ids[0]);
        let cell = &parts.cells[first_cell[&second]];
        let at = cell.universe_value.map_or_else(
            || Diagnostic::error(xml.src, cell.tag.0, cell.tag.1, ""),
            |v| xml.error(&v, ""),
        );
        let names: Vec<String> = unused.iter().map(i64::to_string).collect();
        sink.error(Diagnostic {
            message: format!(
                "universes {} are not filled into anything: which one is the root?",
                names.join(", ")
            ),
            hint: Some(
                "the root universe is the one no cell or lattice fills; use universe 0 for it"
                    .into(),
            ),
            ..at
        });
        return None;
    };
    for u in unused.iter().filter(|u| **u != root) {
        let cell = &parts.cells[first_cell[u]];
        if let Some(v) = &cell.universe_value {
            sink.warn(xml.error(
                v,
                format!("universe {u} is not filled into anything: its cells are not drawn"),
            ));
        }
    }
    Some(root)
}

/// A cell's region properties: its name, material and density.
fn props(
    xml: &Xml,
    sink: &mut Sink,
    cell: &Cell,
    materials: Option<&MaterialsFile>,
) -> RegionProps {
    let mut props = RegionProps {
        description: cell.name.clone(),
        density: cell.density,
        ..RegionProps::default()
    };
    let Content::Materials(ids, value) = &cell.content else {
        return props;
    };
    if ids.len() > 1 {
        sink.warn(xml.error(
            value,
            format!(
                "cell {} lists {} materials, one per instance: every instance is drawn with the first",
                cell.id,
                ids.len()
            ),
        ));
    }
    let Some(id) = ids[0] else {
        // Void is drawn as air: hidden unless asked for.
        props.transparent = true;
        props.air = 1;
        return props;
    };
    props.material = id;
    props.material_name = Some(id.to_string());
    let Some(file) = materials else {
        return props;
    };
    let Some(&index) = file.materials.by_id.get(&id) else {
        if file.materials.broken.contains(&id) {
            // Its errors are reported where it is defined.
            return props;
        }
        let first = value.words().next().unwrap_or("");
        sink.error(xml.error_at(
            value,
            first,
            format!("material {id} is not defined in {}", file.xml.src.name),
        ));
        return props;
    };
    let m = &file.materials.list[index];
    props.material_name = Some(m.name.clone());
    props.material_index = Some(index);
    if cell.density.is_none() {
        props.density = m.density;
        props.atom_density = m.atom_density;
    }
    props
}

/// Notes on the boundaries that return particles into the model
/// (reflective, white, periodic): the model stands for more than is drawn.
fn boundary_notes(scene: &mut Scene, surfaces: &[Surface]) {
    for (boundary, word, meaning) in [
        (Boundary::Reflective, "reflective", "mirror particles back"),
        (
            Boundary::White,
            "white",
            "send particles back in random directions",
        ),
        (
            Boundary::Periodic,
            "periodic",
            "send particles on through their partners",
        ),
    ] {
        let ids: Vec<String> = surfaces
            .iter()
            .filter(|s| s.boundary == boundary)
            .map(|s| s.id.to_string())
            .collect();
        let (noun, verb) = match ids.len() {
            0 => continue,
            1 => ("surface", "is"),
            _ => ("surfaces", "are"),
        };
        scene.notes.push(format!(
            "{noun} {} {verb} {word} (OpenMC's boundaries {meaning}): only the model itself is drawn",
            ids.join(", ")
        ));
    }
}
