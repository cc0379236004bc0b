//! LATTICE cards: lattice cells filled with the model moved by the inverse
//! of their ROT-DEFI transformation.
//!
//! FLUKA's manual: a roto-translation must be associated with each lattice
//! "to provide the transformation bringing from any point and direction
//! inside each lattice cell to the corresponding point and direction in the
//! basic unit". FLUKA tracks a particle in a lattice cell in the prototype's
//! coordinates, so what the cell shows is the whole model (universe 0) moved
//! by the inverse transformation, seen through the cell's own shape.

use super::card::{self, Card, Field};
use super::Reader;
use sv_geom::Fill;
use sv_math::DAffine3;

/// What FLUKA's manual asks of a lattice's transformation (the hint when
/// one is missing).
const LATTICE_NEEDS: &str = "a ROT-DEFI card must give each lattice the transformation \
    bringing any point of the lattice cell to the corresponding point of the basic unit \
    (the prototype); name it in the LATTICE SDUM";

/// A lattice cell: a container region and the transformation from the
/// cell to the prototype, when one is defined.
#[derive(Clone, Debug)]
pub(super) struct Cell {
    /// The container region.
    pub region: usize,
    /// The prototype's coordinates of a point of the cell.
    pub prototype_from_cell: Option<DAffine3>,
}

impl Reader {
    /// A region named by a card field: by name, by number (1-based, as
    /// FLUKA numbers regions in input order) or `@LASTREG`.
    pub(super) fn region_ref(&self, f: &Field) -> Option<usize> {
        if let Some(&r) = self.region_index.get(&f.text) {
            return Some(r);
        }
        if f.text.eq_ignore_ascii_case("@LASTREG") {
            return self.regions.len().checked_sub(1);
        }
        card::number(&f.text)
            .filter(|v| *v >= 1.0 && v.fract() == 0.0 && *v <= self.regions.len() as f64)
            .map(|v| v as usize - 1)
    }

    /// A LATTICE card: WHAT(1) to WHAT(2) in steps of WHAT(3) are the
    /// container regions, SDUM the transformation.
    pub(super) fn lattice(&mut self, i: usize, c: &Card) {
        let Some(first_field) = &c.what[0] else {
            self.err(
                i,
                1,
                7,
                "LATTICE needs the name of its container region in WHAT(1)",
            );
            return;
        };
        let Some(first) = self.region_ref(first_field) else {
            let (col, len, name) = (first_field.col, first_field.len(), first_field.text.clone());
            let hint = self.hint_among(&name, self.region_index.keys());
            self.err(
                i,
                col,
                len,
                format!("LATTICE refers to undefined region `{name}`"),
            )
            .hint = hint;
            return;
        };
        let last = c.what[1]
            .as_ref()
            .and_then(|f| self.region_ref(f))
            .unwrap_or(first);
        let step = c.what[2]
            .as_ref()
            .and_then(|f| card::number(&f.text))
            .filter(|v| *v >= 1.0)
            .map_or(1, |v| v.min(1e9) as usize);
        let transform = self.lattice_transform(i, c);
        for region in (first..=last).step_by(step) {
            if self.assign_budget == 0 {
                break;
            }
            self.assign_budget -= 1;
            self.lattices.push(Cell {
                region,
                prototype_from_cell: transform,
            });
        }
    }

    /// The transformation a LATTICE card names (reported when missing).
    fn lattice_transform(&mut self, i: usize, c: &Card) -> Option<DAffine3> {
        let Some(t) = &c.sdum else {
            let hint = format!(
                "{LATTICE_NEEDS} (FLUKA otherwise calls the user routine LATTIC, \
                 which is not read)"
            );
            let message = "LATTICE names no transformation: its cells are drawn empty";
            self.warn_hinted(i, 1, 7, message, Some(hint));
            return None;
        };
        let found = self
            .find_transform(&t.text)
            .filter(|xf| xf.is_finite() && xf.matrix3.determinant().abs() > 1e-12);
        if found.is_none() {
            let (col, len) = (t.col, t.len());
            let name = t.text.trim_start_matches('-').to_string();
            self.warn_hinted(
                i,
                col,
                len,
                format!("LATTICE transformation `{name}` has no ROT-DEFI card"),
                Some(LATTICE_NEEDS.to_string()),
            );
        }
        found
    }

    /// Fill every lattice cell that has a transformation with the model
    /// moved into it.
    pub(super) fn fill_lattice_cells(&self, regions: &mut [sv_geom::Region]) {
        for cell in &self.lattices {
            if let (Some(xf), Some(region)) =
                (cell.prototype_from_cell, regions.get_mut(cell.region))
            {
                region.fill = Some(Fill::Universe {
                    universe: 0,
                    region_from_universe: xf.inverse(),
                });
            }
        }
    }
}
