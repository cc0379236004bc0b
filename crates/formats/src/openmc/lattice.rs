//! `<lattice>` (rectangular) and `<hex_lattice>` elements, and the
//! [`sv_geom::Lattice`] each becomes (lattice.cpp's conventions).
//!
//! Rectangular: element (i, j, k) spans `lower_left + (i, j, k) · pitch`
//! and holds its universe moved to the element's centre. The universes are
//! listed row by row from the top (highest y) down, layer by layer from the
//! bottom up.
//!
//! Hexagonal: OpenMC's skewed indices are the engine's: with orientation
//! `y` (the default: two faces perpendicular to y) the steps are
//! `pitch (√3/2, 1/2)` and `pitch (0, 1)`, with orientation `x`
//! `pitch (1, 0)` and `pitch (1/2, √3/2)`; the centre element is (0, 0)
//! and the rings are the elements at hexagonal distance 0, 1, … from it.
//! The listing order (rows from the top, each ring's elements interleaved)
//! is walked exactly as lattice.cpp's `fill_lattice_y`/`fill_lattice_x`.
//! Elements of the (2n-1)² grid beyond the outer ring hold the outer
//! universe, as OpenMC finds them outside the lattice.
//!
//! A lattice without a third dimension (2 values of `dimension`, or no
//! `n_axial`) leaves z as it is: its one layer spans [`UNBOUNDED`] either
//! side of z = 0 and its universes' origins stay at z = 0.

use super::xml::{self, Sink, Value, Xml};
use roxmltree::Node;
use sv_geom::{Lattice, LatticeKind};
use sv_math::{DAffine3, DVec3};

/// Half the height of the one layer of a two-dimensional lattice, in cm:
/// beyond any model.
pub const UNBOUNDED: f64 = 1.0e9;

/// A lattice as read.
pub(super) struct LatticeSpec<'a> {
    /// Its id.
    pub id: i64,
    /// Kind, steps, base and origin (lowest index 0 for a rectangular one,
    /// −(rings − 1) in the plane for a hexagonal one).
    pub geometry: Lattice,
    /// The universe ids as listed, each with its word.
    pub universes: Vec<(i64, &'a str)>,
    /// The `<universes>` value.
    pub universes_value: Value<'a>,
    /// For each engine element (`i` fastest), its place in `universes`;
    /// `None` beyond a hexagonal lattice's outer ring.
    pub order: Vec<Option<usize>>,
    /// The outer universe's id, where written.
    pub outer: Option<(i64, Value<'a>)>,
}

impl LatticeSpec<'_> {
    /// The lattice filling a cell, with universe ids turned into indices by
    /// `index` (ids were checked before) and the cell's transform.
    pub fn lower(
        &self,
        index: impl Fn(i64) -> Option<usize>,
        region_from_lattice: DAffine3,
    ) -> Lattice {
        let outer = self.outer.as_ref().and_then(|(id, _)| index(*id));
        let elements = self
            .order
            .iter()
            .map(|slot| match slot {
                Some(i) => index(self.universes[*i].0),
                None => outer,
            })
            .collect();
        Lattice {
            region_from_lattice,
            elements,
            outer,
            ..self.geometry.clone()
        }
    }
}

/// Read one `<lattice>` or `<hex_lattice>`; `None` after reporting errors.
pub(super) fn read<'a>(xml: &Xml, sink: &mut Sink, node: Node<'a, '_>) -> Option<LatticeSpec<'a>> {
    let hex = node.has_tag_name("hex_lattice");
    let Some(id_value) = xml.value(node, "id") else {
        sink.error(xml.error_tag(node, "lattice without an id"));
        return None;
    };
    let id = xml::id_of(xml, sink, &id_value, "lattice id");
    let outer = match xml.value(node, "outer") {
        Some(v) => Some((xml::id_of(xml, sink, &v, "outer universe")?, v)),
        None => None,
    };
    let Some(universes_value) = xml.value(node, "universes") else {
        sink.error(xml.error_tag(node, "lattice without universes"));
        return None;
    };
    let mut universes = Vec::new();
    for word in universes_value.words() {
        match xml::integer(word) {
            Some(u) => universes.push((u, word)),
            None => sink.error(xml.error_at(
                &universes_value,
                word,
                format!("universe `{word}` is not an integer"),
            )),
        }
    }
    let shape = if hex {
        hexagonal(xml, sink, node)
    } else {
        rectangular(xml, sink, node)
    };
    let (
        id,
        Shape {
            geometry,
            expected,
            size,
            x_orientation,
        },
    ) = (id?, shape?);
    let listed = universes_value.words().count() as u64;
    if listed != expected {
        sink.error(
            xml.error(
                &universes_value,
                format!("lattice {id} lists {listed} universes; {size} takes {expected}"),
            )
            .with_hint("a lattice lists one universe per element"),
        );
        return None;
    }
    if universes.len() as u64 != expected {
        return None;
    }
    let order = if hex {
        let rings = (geometry.counts[0] as usize).div_ceil(2);
        hex_order(rings, geometry.counts[2] as usize, !x_orientation)
    } else {
        rect_order(geometry.counts)
    };
    Some(LatticeSpec {
        id,
        geometry,
        universes,
        universes_value,
        order,
        outer,
    })
}

/// A lattice's frame as read, before its universes.
struct Shape {
    /// Kind, steps, base, origin, lowest indices and counts.
    geometry: Lattice,
    /// How many universes it lists.
    expected: u64,
    /// Its size in words (`a 3×3 lattice`).
    size: String,
    /// A hexagonal lattice of orientation `x`.
    x_orientation: bool,
}

/// A positive count, or an error.
fn count_of(xml: &Xml, sink: &mut Sink, value: &Value, word: &str, what: &str) -> Option<u32> {
    match xml::integer(word) {
        Some(n) if n >= 1 => Some(n as u32),
        _ => {
            sink.error(xml.error_at(value, word, format!("{what} must be a positive integer")));
            None
        }
    }
}

/// A required value of a lattice.
fn required<'a>(xml: &Xml, sink: &mut Sink, node: Node<'a, '_>, name: &str) -> Option<Value<'a>> {
    let v = xml.value(node, name);
    if v.is_none() {
        sink.error(xml.error_tag(node, format!("lattice without <{name}>")));
    }
    v
}

/// Positive pitches, or an error.
fn pitches(xml: &Xml, sink: &mut Sink, value: &Value, allowed: usize) -> Option<Vec<f64>> {
    let p = xml::reals_n(xml, sink, value, "the pitch", &[allowed])?;
    if p.iter().any(|v| *v <= 0.0) {
        sink.error(xml.error(value, "a pitch must be positive"));
        return None;
    }
    Some(p)
}

/// The rectangular lattice's frame.
fn rectangular(xml: &Xml, sink: &mut Sink, node: Node) -> Option<Shape> {
    let dimension = required(xml, sink, node, "dimension");
    let lower_left = required(xml, sink, node, "lower_left");
    let pitch = required(xml, sink, node, "pitch");
    let (dimension, lower_left, pitch) = (dimension?, lower_left?, pitch?);
    let words: Vec<&str> = dimension.words().collect();
    if !(2..=3).contains(&words.len()) {
        sink.error(xml.error(&dimension, "a rectangular lattice has 2 or 3 dimensions"));
        return None;
    }
    let mut counts = [1u32; 3];
    for (i, w) in words.iter().enumerate() {
        counts[i] = count_of(xml, sink, &dimension, w, "a lattice dimension")?;
    }
    let n = words.len();
    let ll = xml::reals_n(xml, sink, &lower_left, "the lower left corner", &[n]);
    let p = pitches(xml, sink, &pitch, n);
    let (ll, p) = (ll?, p?);
    let three_d = n == 3;
    let (z0, dz) = if three_d {
        (ll[2], p[2])
    } else {
        (-UNBOUNDED, 2.0 * UNBOUNDED)
    };
    let base = DVec3::new(ll[0], ll[1], z0);
    let steps = [DVec3::X * p[0], DVec3::Y * p[1], DVec3::Z * dz];
    let mut origin = base + (steps[0] + steps[1] + steps[2]) / 2.0;
    if !three_d {
        origin.z = 0.0;
    }
    let expected = counts
        .iter()
        .try_fold(1u64, |n, c| n.checked_mul(u64::from(*c)))
        .unwrap_or(u64::MAX);
    Some(Shape {
        geometry: Lattice {
            kind: LatticeKind::Rectangular,
            region_from_lattice: DAffine3::IDENTITY,
            steps,
            base,
            origin,
            lowest: [0; 3],
            counts,
            elements: Vec::new(),
            outer: None,
        },
        expected,
        size: format!("a {} lattice", words.join("×")),
        x_orientation: false,
    })
}

/// The hexagonal lattice's frame.
fn hexagonal(xml: &Xml, sink: &mut Sink, node: Node) -> Option<Shape> {
    let rings_value = required(xml, sink, node, "n_rings");
    let center = required(xml, sink, node, "center");
    let pitch = required(xml, sink, node, "pitch");
    let (rings_value, center, pitch) = (rings_value?, center?, pitch?);
    let rings = count_of(xml, sink, &rings_value, rings_value.trimmed(), "n_rings")?;
    let axial = match xml.value(node, "n_axial") {
        Some(v) => Some(count_of(xml, sink, &v, v.trimmed(), "n_axial")?),
        None => None,
    };
    let x_orientation = match xml.value(node, "orientation") {
        None => false,
        Some(v) => match v.trimmed() {
            "y" => false,
            "x" => true,
            other => {
                sink.error(xml.error(&v, format!("unknown orientation `{other}`; use x or y")));
                return None;
            }
        },
    };
    let dims = if axial.is_some() { 3 } else { 2 };
    let c = xml::reals_n(xml, sink, &center, "the centre", &[dims]);
    let p = pitches(xml, sink, &pitch, dims - 1);
    let (c, p) = (c?, p?);
    let layers = axial.unwrap_or(1);
    let root3 = 3f64.sqrt();
    let (a, b) = if x_orientation {
        (
            DVec3::new(p[0], 0.0, 0.0),
            DVec3::new(p[0] / 2.0, root3 / 2.0 * p[0], 0.0),
        )
    } else {
        (
            DVec3::new(root3 / 2.0 * p[0], p[0] / 2.0, 0.0),
            DVec3::new(0.0, p[0], 0.0),
        )
    };
    let (z_base, dz) = match axial {
        // Layer k's centre: centre - (n/2 - k - 1/2) pitch.
        Some(n) => (c[2] - (f64::from(n) / 2.0 - 0.5) * p[1], p[1]),
        None => (0.0, 2.0 * UNBOUNDED),
    };
    let base = DVec3::new(c[0], c[1], z_base);
    let n = u64::from(rings);
    let per_layer = (3 * n * n - 3 * n + 1).checked_mul(u64::from(layers));
    let side = 2 * rings - 1;
    let lowest = 1 - rings as i32;
    Some(Shape {
        geometry: Lattice {
            kind: LatticeKind::Hexagonal,
            region_from_lattice: DAffine3::IDENTITY,
            steps: [a, b, DVec3::Z * dz],
            base,
            origin: base,
            lowest: [lowest, lowest, 0],
            counts: [side, side, layers],
            elements: Vec::new(),
            outer: None,
        },
        expected: per_layer.unwrap_or(u64::MAX),
        size: format!("a hexagonal lattice of {rings} rings and {layers} layers"),
        x_orientation,
    })
}

/// Place in the listing of each element of a rectangular lattice: rows
/// from the top down.
fn rect_order(counts: [u32; 3]) -> Vec<Option<usize>> {
    let [nx, ny, nz] = counts.map(|c| c as usize);
    let mut order = vec![None; nx * ny * nz];
    for iz in 0..nz {
        for iy in 0..ny {
            for ix in 0..nx {
                order[ix + nx * (iy + ny * iz)] = Some(nx * ny * iz + nx * (ny - 1 - iy) + ix);
            }
        }
    }
    order
}

/// Place in the listing of each element of a hexagonal lattice of `rings`
/// rings and `layers` layers, walked as lattice.cpp does; `y` for the
/// default orientation.
fn hex_order(rings: usize, layers: usize, y_orientation: bool) -> Vec<Option<usize>> {
    let n = rings as i64;
    let side = 2 * rings - 1;
    let mut order = vec![None; side * side * layers];
    let mut listed = 0usize;
    for layer in 0..layers {
        let mut put = |i: i64, j: i64| {
            let flat = (i + n - 1) as usize + side * ((j + n - 1) as usize + side * layer);
            order[flat] = Some(listed);
            listed += 1;
        };
        if y_orientation {
            walk_y(n, &mut put);
        } else {
            walk_x(n, &mut put);
        }
    }
    order
}

/// `fill_lattice_y`: (x, α) indices from the centre, in listing order.
fn walk_y(n: i64, put: &mut impl FnMut(i64, i64)) {
    let (mut ix, mut ia) = (1i64, n - 1);
    // The upper triangle: the first n − 1 rows.
    for k in 0..n - 1 {
        ix -= 1;
        for _ in 0..=k {
            put(ix, ia);
            ix += 2;
            ia -= 1;
        }
        ix -= 2 * (k + 1);
        ia += k + 1;
    }
    // The middle: 2n − 1 rows of n and n − 1 elements in turn.
    for k in 0..2 * n - 1 {
        if k % 2 == 0 {
            ix -= 1;
        } else {
            ix += 1;
            ia -= 1;
        }
        for _ in 0..n - k % 2 {
            put(ix, ia);
            ix += 2;
            ia -= 1;
        }
        ix -= 2 * (n - k % 2);
        ia += n - k % 2;
    }
    // The lower triangle.
    for k in 0..n - 1 {
        ix += 1;
        ia -= 1;
        for _ in 0..n - k - 1 {
            put(ix, ia);
            ix += 2;
            ia -= 1;
        }
        ix -= 2 * (n - k - 1);
        ia += n - k - 1;
    }
}

/// `fill_lattice_x`: (α, y) indices from the centre, in listing order.
fn walk_x(n: i64, put: &mut impl FnMut(i64, i64)) {
    let mut iy = n - 1;
    // The upper rows, n … 2n − 2 elements long.
    for k in 0..n - 1 {
        for j in 0..k + n {
            put(-(n - 1) + j, iy);
        }
        iy -= 1;
    }
    // The centre row and those below, 2n − 1 … n elements long.
    for k in 0..n {
        for j in 0..2 * n - k - 1 {
            put(-(n - 1) + k + j, iy);
        }
        iy -= 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_are_listed_from_the_top() {
        // 2×2: listing "a b / c d" puts c at (0,0), d at (1,0), a at (0,1).
        assert_eq!(rect_order([2, 2, 1]), [Some(2), Some(3), Some(0), Some(1)]);
    }

    #[test]
    fn hexagonal_rings_cover_the_hexagon_once() {
        for y in [true, false] {
            for n in 1..6 {
                let order = hex_order(n, 2, y);
                let mut seen: Vec<usize> = order.iter().flatten().copied().collect();
                seen.sort_unstable();
                let per_layer = 3 * n * n - 3 * n + 1;
                assert_eq!(seen, (0..2 * per_layer).collect::<Vec<_>>());
                // Listed elements are those within n − 1 of the centre.
                let side = 2 * n - 1;
                for (flat, slot) in order.iter().enumerate().take(side * side) {
                    let (i, j) = (
                        (flat % side) as i64 - (n as i64 - 1),
                        (flat / side) as i64 - (n as i64 - 1),
                    );
                    let distance = i.abs().max(j.abs()).max((i + j).abs());
                    assert_eq!(slot.is_some(), distance < n as i64, "n {n} ({i}, {j})");
                }
            }
        }
    }

    #[test]
    fn the_first_listed_element_is_at_the_top() {
        // Orientation y, 2 rings: the first word is the element above the
        // centre, at (x, α) = (0, 1); the centre is the fourth word.
        let order = hex_order(2, 1, true);
        assert_eq!(order[1 + 3 * 2], Some(0));
        assert_eq!(order[1 + 3], Some(3));
        // Orientation x: the first row is the top one, from its left:
        // (α, y) = (-1, 1), at -a + b = (-1/2, √3/2) pitches.
        let order = hex_order(2, 1, false);
        assert_eq!(order[3 * 2], Some(0));
        assert_eq!(order[1 + 3], Some(3));
    }
}
