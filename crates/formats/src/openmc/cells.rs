//! `<cell>` elements: id, universe, material or fill, region, and the
//! rotation and translation of a fill.

use super::region;
use super::xml::{self, Sink, Value, Xml};
use roxmltree::Node;
use std::collections::HashMap;
use sv_geom::Zone;
use sv_math::{DAffine3, DMat3, DVec3};

/// What a cell holds.
pub(super) enum Content<'a> {
    /// Its material by id, `None` for `void`; one per instance when OpenMC's
    /// distributed materials list several.
    Materials(Vec<Option<i64>>, Value<'a>),
    /// The universe or lattice of this id.
    Fill(i64, Value<'a>),
}

/// A cell as read.
pub(super) struct Cell<'a> {
    /// Its id.
    pub id: i64,
    /// Where its start tag is (offset, length).
    pub tag: (usize, usize),
    /// Its name (may be empty).
    pub name: String,
    /// The universe it belongs to (OpenMC's default 0).
    pub universe: i64,
    /// Where the universe is written, if it is.
    pub universe_value: Option<Value<'a>>,
    /// Material or fill.
    pub content: Content<'a>,
    /// The region.
    pub zones: Vec<Zone>,
    /// The fill's coordinates to the cell's: OpenMC's rotation, then its
    /// translation.
    pub region_from_fill: DAffine3,
    /// The cell's own density (g/cm³), overriding the material's.
    pub density: Option<f64>,
}

/// Read one `<cell>`; `None` after reporting its errors.
pub(super) fn read<'a>(
    xml: &Xml,
    sink: &mut Sink,
    node: Node<'a, '_>,
    surfaces: &HashMap<i64, Option<usize>>,
) -> Option<Cell<'a>> {
    let tag = xml.tag(node);
    let Some(id_value) = xml.value(node, "id") else {
        sink.error(xml.error_tag(node, "cell without an id"));
        return None;
    };
    let id = xml::id_of(xml, sink, &id_value, "cell id");
    let universe_value = xml.value(node, "universe");
    let universe = match &universe_value {
        Some(v) => xml::id_of(xml, sink, v, "universe id"),
        None => Some(0),
    };
    let content = content(xml, sink, node, id.unwrap_or(0));
    let zones = match region_value(xml, sink, node) {
        Some(v) => region::parse(xml, sink, &v, surfaces),
        None => Some(region::all_space()),
    };
    let filled = matches!(content, Some(Content::Fill(..)));
    let region_from_fill = transform(xml, sink, node, filled);
    let density = density(xml, sink, node, &content);
    let (id, universe, content, zones) = (id?, universe?, content?, zones?);
    if let Content::Fill(fill, v) = &content {
        if *fill == universe {
            sink.error(xml.error(
                v,
                format!("cell {id} is filled with universe {fill}, the universe it belongs to"),
            ));
            return None;
        }
    }
    Some(Cell {
        id,
        tag,
        name: xml
            .value(node, "name")
            .map_or(String::new(), |v| v.trimmed().to_string()),
        universe,
        universe_value,
        content,
        zones,
        region_from_fill: region_from_fill?,
        density: density?,
    })
}

/// The region expression (`region`, or the `surfaces` of OpenMC's early
/// files, an intersection in the same syntax).
fn region_value<'a>(xml: &Xml, sink: &mut Sink, node: Node<'a, '_>) -> Option<Value<'a>> {
    if let Some(v) = xml.value(node, "region") {
        return Some(v);
    }
    let old = xml.value(node, "surfaces")?;
    sink.warn(
        xml.error(&old, "`surfaces` is the old name of `region`")
            .with_hint("OpenMC since 0.7 reads `region`: rename the attribute"),
    );
    Some(old)
}

fn content<'a>(xml: &Xml, sink: &mut Sink, node: Node<'a, '_>, id: i64) -> Option<Content<'a>> {
    match (xml.value(node, "material"), xml.value(node, "fill")) {
        (Some(_), Some(fill)) => {
            sink.error(xml.error(
                &fill,
                format!("cell {id} has both a material and a fill; only one can be given"),
            ));
            None
        }
        (None, None) => {
            sink.error(
                xml.error_tag(node, format!("cell {id} has neither a material nor a fill"))
                    .with_hint("give material=\"void\" for an empty cell"),
            );
            None
        }
        (None, Some(fill)) => Some(Content::Fill(xml::id_of(xml, sink, &fill, "fill")?, fill)),
        (Some(m), None) => {
            let mut ids = Vec::new();
            for word in m.words() {
                if word == "void" {
                    ids.push(None);
                } else if let Some(i) = xml::integer(word) {
                    ids.push(Some(i));
                } else {
                    sink.error(xml.error_at(
                        &m,
                        word,
                        format!("material `{word}` is neither an id nor `void`"),
                    ));
                    return None;
                }
            }
            if ids.is_empty() {
                sink.error(xml.error(&m, format!("cell {id} has an empty material")));
                return None;
            }
            Some(Content::Materials(ids, m))
        }
    }
}

/// The cell's `density` (g/cm³; the first of a distributed list).
fn density(
    xml: &Xml,
    sink: &mut Sink,
    node: Node,
    content: &Option<Content>,
) -> Option<Option<f64>> {
    let Some(value) = xml.value(node, "density") else {
        return Some(None);
    };
    let values = xml::reals(xml, sink, &value, "a cell density")?;
    let material =
        matches!(content, Some(Content::Materials(ids, _)) if ids.iter().all(Option::is_some));
    if !material {
        sink.error(xml.error(
            &value,
            "only a cell of (non-void) material can have a density",
        ));
        return None;
    }
    match values.first() {
        Some(&rho) if values.iter().all(|v| *v > 0.0) => Some(Some(rho)),
        _ => {
            sink.error(xml.error(&value, "a cell density must be positive"));
            None
        }
    }
}

/// The rows of the matrix OpenMC applies to a position entering the fill
/// (cell.cpp): for angles (φ, θ, ψ) in degrees, Rz(ψ') Ry(θ') Rx(φ') with
/// the angles negated, so that the fill turns by +φ about x, +θ about y,
/// +ψ about z.
pub(super) fn fill_from_cell_rows(degrees: [f64; 3]) -> [f64; 9] {
    let [phi, theta, psi] = degrees.map(|d| -d.to_radians());
    let (sf, cf) = phi.sin_cos();
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = psi.sin_cos();
    [
        ct * cp,
        -cf * sp + sf * st * cp,
        sf * sp + cf * st * cp,
        ct * sp,
        cf * cp + sf * st * sp,
        -sf * cp + cf * st * sp,
        -st,
        sf * ct,
        cf * ct,
    ]
}

/// The fill's coordinates to the cell's: x = R⁻¹ u + t, where OpenMC finds
/// the fill's u = R (x - t).
fn transform(xml: &Xml, sink: &mut Sink, node: Node, filled: bool) -> Option<DAffine3> {
    let mut out = DAffine3::IDENTITY;
    let mut ok = true;
    for name in ["translation", "rotation"] {
        let Some(value) = xml.value(node, name) else {
            continue;
        };
        if !filled {
            sink.error(xml.error(
                &value,
                format!("a {name} applies to a fill, and this cell has none"),
            ));
            ok = false;
            continue;
        }
        let allowed: &[usize] = if name == "translation" { &[3] } else { &[3, 9] };
        let Some(v) = xml::reals_n(xml, sink, &value, &format!("a {name}"), allowed) else {
            ok = false;
            continue;
        };
        if name == "translation" {
            out.translation = DVec3::new(v[0], v[1], v[2]);
            continue;
        }
        let rows: [f64; 9] = match v.len() {
            3 => fill_from_cell_rows([v[0], v[1], v[2]]),
            _ => std::array::from_fn(|i| v[i]),
        };
        // Reading rows as columns transposes: the inverse of a rotation.
        let m = DMat3::from_cols_array(&rows);
        let orthonormal = (m.transpose() * m).abs_diff_eq(DMat3::IDENTITY, 1e-6);
        if !orthonormal || m.determinant() <= 0.0 {
            sink.error(
                xml.error(&value, "this rotation matrix is not a rotation")
                    .with_hint("its rows must be orthogonal unit vectors, with determinant 1"),
            );
            ok = false;
            continue;
        }
        out.matrix3 = m;
    }
    ok.then_some(out)
}
