//! `materials.xml` (or the `<materials>` of a `model.xml`): each
//! `<material>` with its density and its nuclides (`U235`, `Am242_m1`,
//! `C0`) or natural elements (`<element name="C">`, older files), atom
//! (`ao`) or weight (`wo`) fractions.

use super::xml::{self, children, Sink, Value, Xml};
use roxmltree::Node;
use std::collections::{HashMap, HashSet};
use sv_scene::{Component, Material};

/// The materials read, by id.
#[derive(Default)]
pub(super) struct Materials {
    /// In file order.
    pub list: Vec<Material>,
    /// Each one's id, same order.
    pub ids: Vec<i64>,
    /// Index in `list` by id.
    pub by_id: HashMap<i64, usize>,
    /// The ids of materials whose definitions have errors.
    pub broken: HashSet<i64>,
}

/// The chemical symbols, Z = 1 first.
const SYMBOLS: [&str; 118] = [
    "H", "He", "Li", "Be", "B", "C", "N", "O", "F", "Ne", "Na", "Mg", "Al", "Si", "P", "S", "Cl",
    "Ar", "K", "Ca", "Sc", "Ti", "V", "Cr", "Mn", "Fe", "Co", "Ni", "Cu", "Zn", "Ga", "Ge", "As",
    "Se", "Br", "Kr", "Rb", "Sr", "Y", "Zr", "Nb", "Mo", "Tc", "Ru", "Rh", "Pd", "Ag", "Cd", "In",
    "Sn", "Sb", "Te", "I", "Xe", "Cs", "Ba", "La", "Ce", "Pr", "Nd", "Pm", "Sm", "Eu", "Gd", "Tb",
    "Dy", "Ho", "Er", "Tm", "Yb", "Lu", "Hf", "Ta", "W", "Re", "Os", "Ir", "Pt", "Au", "Hg", "Tl",
    "Pb", "Bi", "Po", "At", "Rn", "Fr", "Ra", "Ac", "Th", "Pa", "U", "Np", "Pu", "Am", "Cm", "Bk",
    "Cf", "Es", "Fm", "Md", "No", "Lr", "Rf", "Db", "Sg", "Bh", "Hs", "Mt", "Ds", "Rg", "Cn", "Nh",
    "Fl", "Mc", "Lv", "Ts", "Og",
];

/// Z of a chemical symbol (any case).
fn atomic_number(symbol: &str) -> Option<u32> {
    SYMBOLS
        .iter()
        .position(|s| s.eq_ignore_ascii_case(symbol))
        .map(|i| i as u32 + 1)
}

/// (Z, A, m) of a nuclide or element name: OpenMC's `U235`, `Am242_m1`,
/// `C0` (natural) and `C` (an element), and the older `U-235`, `Am-242m`,
/// `C-Nat` spellings. A is 0 for a natural element.
pub(super) fn zam(name: &str) -> Option<(u32, u32, u32)> {
    let name = name.trim();
    let letters = name.bytes().take_while(u8::is_ascii_alphabetic).count();
    let (symbol, rest) = name.split_at(letters);
    let z = atomic_number(symbol)?;
    let rest = rest.strip_prefix('-').unwrap_or(rest);
    if rest.is_empty() || rest.eq_ignore_ascii_case("nat") {
        return Some((z, 0, 0));
    }
    let digits = rest.bytes().take_while(u8::is_ascii_digit).count();
    let (mass, state) = rest.split_at(digits);
    let a: u32 = mass.parse().ok()?;
    let m = match state {
        "" => 0,
        "m" | "M" => 1,
        _ => state.strip_prefix("_m")?.parse().ok()?,
    };
    (a < 1000 && m < 10).then_some((z, a, m))
}

/// Read the `<material>` elements under `node`.
pub(super) fn read(xml: &Xml, sink: &mut Sink, node: Node) -> Materials {
    let mut out = Materials::default();
    let mut seen = HashSet::new();
    for m in children(node, "material") {
        let Some(id_value) = xml.value(m, "id") else {
            sink.error(xml.error_tag(m, "material without an id"));
            continue;
        };
        let Some(id) = xml::id_of(xml, sink, &id_value, "material id") else {
            continue;
        };
        if !seen.insert(id) {
            sink.error(xml.error(&id_value, format!("material {id} is defined twice")));
            continue;
        }
        let Some(material) = material(xml, sink, m, id) else {
            out.broken.insert(id);
            continue;
        };
        out.by_id.insert(id, out.list.len());
        out.ids.push(id);
        out.list.push(material);
    }
    out
}

/// A component as read: its fraction is negative for a weight fraction,
/// as OpenMC keeps it.
fn components(xml: &Xml, sink: &mut Sink, m: Node, macro_units: bool) -> Option<Vec<Component>> {
    let mut out = Vec::new();
    let mut ok = true;
    let parts = m
        .children()
        .filter(|c| c.is_element() && matches!(c.tag_name().name(), "nuclide" | "element"));
    for part in parts {
        let Some(name) = xml.value(part, "name") else {
            sink.error(xml.error_tag(part, "nuclide without a name"));
            ok = false;
            continue;
        };
        let Some(zam) = zam(name.text) else {
            sink.error(
                xml.error(
                    &name,
                    format!("`{}` is not a nuclide or element name", name.trimmed()),
                )
                .with_hint("nuclides are written U235, Am242_m1, C0 (natural carbon)"),
            );
            ok = false;
            continue;
        };
        if macro_units {
            continue;
        }
        match fraction(xml, sink, part, &name) {
            Some((fraction, by_weight)) => out.push(Component {
                zam,
                fraction,
                by_weight,
            }),
            None => ok = false,
        }
    }
    ok.then_some(out)
}

/// The `ao` or `wo` of a nuclide: (fraction, by weight).
fn fraction(xml: &Xml, sink: &mut Sink, part: Node, name: &Value) -> Option<(f64, bool)> {
    let ao = xml.value(part, "ao");
    let wo = xml.value(part, "wo");
    let (value, by_weight) = match (ao, wo) {
        (Some(v), None) => (v, false),
        (None, Some(v)) => (v, true),
        (None, None) => {
            sink.error(xml.error(
                name,
                format!(
                    "`{}` has no atom (ao) or weight (wo) fraction",
                    name.trimmed()
                ),
            ));
            return None;
        }
        (Some(_), Some(v)) => {
            sink.error(xml.error(
                &v,
                format!(
                    "`{}` has both an atom and a weight fraction",
                    name.trimmed()
                ),
            ));
            return None;
        }
    };
    let v = xml::reals_n(xml, sink, &value, "a fraction", &[1])?;
    Some((v[0], by_weight))
}

fn material(xml: &Xml, sink: &mut Sink, m: Node, id: i64) -> Option<Material> {
    let name = xml
        .value(m, "name")
        .map(|v| v.trimmed().to_string())
        .filter(|n| !n.is_empty())
        .unwrap_or_else(|| id.to_string());
    let Some(density) = xml::children(m, "density").next() else {
        sink.error(
            xml.error_tag(m, format!("material {id} has no <density>"))
                .with_hint("give it as <density value=\"10.5\" units=\"g/cm3\"/> or units=\"sum\""),
        );
        return None;
    };
    let units = xml.value(density, "units");
    let is_macro = units.is_some_and(|u| u.trimmed() == "macro");
    let components = components(xml, sink, m, is_macro)?;
    if components.iter().any(|c| c.by_weight) && components.iter().any(|c| !c.by_weight) {
        sink.error(xml.error_tag(m, format!("material {id} mixes atom and weight fractions")));
        return None;
    }
    let mut out = Material {
        name,
        components,
        ..Material::default()
    };
    density_of(xml, sink, density, units, &mut out)?;
    Some(out)
}

/// The material's density from its `<density>` element.
fn density_of(
    xml: &Xml,
    sink: &mut Sink,
    density: Node,
    units: Option<Value>,
    out: &mut Material,
) -> Option<()> {
    let Some(units) = units else {
        sink.error(xml.error_tag(density, "<density> without units"));
        return None;
    };
    let unit = units.trimmed();
    if unit == "sum" {
        // The sum of the fractions: atoms/b-cm for atom fractions, g/cm³
        // for weight fractions.
        let sum: f64 = out.components.iter().map(|c| c.fraction).sum();
        if out.components.first().is_some_and(|c| c.by_weight) {
            out.density = Some(sum);
        } else {
            out.atom_density = Some(sum);
        }
        return Some(());
    }
    let value = xml.value(density, "value");
    if unit == "macro" {
        // A multigroup cross-section multiplier, not a density.
        return Some(());
    }
    let factor = match unit {
        "g/cm3" | "g/cc" | "atom/b-cm" => 1.0,
        "kg/m3" => 1e-3,
        "atom/cm3" | "atom/cc" => 1e-24,
        _ => {
            sink.error(xml.error(&units, format!("unknown density units `{unit}`")).with_hint(
                "OpenMC's units: g/cm3, g/cc, kg/m3, atom/b-cm, atom/cm3, atom/cc, sum, macro",
            ));
            return None;
        }
    };
    let Some(value) = value else {
        sink.error(xml.error_tag(density, format!("a density in {unit} needs a value")));
        return None;
    };
    let v = xml::reals_n(xml, sink, &value, "a density", &[1])?[0];
    if v <= 0.0 {
        sink.error(xml.error(&value, format!("a density must be positive (is {v})")));
        return None;
    }
    if unit.starts_with("atom") {
        out.atom_density = Some(v * factor);
    } else {
        out.density = Some(v * factor);
    }
    Some(())
}

#[cfg(test)]
mod tests {
    use super::zam;

    #[test]
    fn nuclide_names_give_z_a_and_state() {
        assert_eq!(zam("U235"), Some((92, 235, 0)));
        assert_eq!(zam("Am242_m1"), Some((95, 242, 1)));
        assert_eq!(zam("C0"), Some((6, 0, 0)));
        assert_eq!(zam("C"), Some((6, 0, 0)));
        assert_eq!(zam("H1"), Some((1, 1, 0)));
        assert_eq!(zam("U-235"), Some((92, 235, 0)));
        assert_eq!(zam("Am-242m"), Some((95, 242, 1)));
        assert_eq!(zam("C-Nat"), Some((6, 0, 0)));
        assert_eq!(zam("Og294"), Some((118, 294, 0)));
        assert_eq!(zam("Xx12"), None);
        assert_eq!(zam("U235_x"), None);
        assert_eq!(zam("92235"), None);
        assert_eq!(zam(""), None);
    }
}
