//! FLUKA materials: the predefined ones, MATERIAL and COMPOUND cards, and
//! the numbers FLUKA gives them.
//!
//! FLUKA numbers its 25 predefined materials 1 (`BLCKHOLE`) to 25
//! (`NICKEL`). A MATERIAL card takes the number in its WHAT(4), else keeps
//! the number of the material it redefines, else takes the first number
//! after those in use; a material used without a card (FLUKA's predefined
//! compounds such as `WATER` or `AIR`) takes the next free number when it
//! is first met.

use super::card::{self, Card};
use super::Reader;
use std::collections::HashMap;
use sv_scene::{Component, Material};

/// The predefined materials in FLUKA's order (number = position + 1), with
/// their atomic number (0 for the black hole and vacuum).
pub(super) const PREDEFINED: [(&str, u32); 25] = [
    ("BLCKHOLE", 0),
    ("VACUUM", 0),
    ("HYDROGEN", 1),
    ("HELIUM", 2),
    ("BERYLLIU", 4),
    ("CARBON", 6),
    ("NITROGEN", 7),
    ("OXYGEN", 8),
    ("MAGNESIU", 12),
    ("ALUMINUM", 13),
    ("IRON", 26),
    ("COPPER", 29),
    ("SILVER", 47),
    ("SILICON", 14),
    ("GOLD", 79),
    ("MERCURY", 80),
    ("LEAD", 82),
    ("TANTALUM", 73),
    ("SODIUM", 11),
    ("ARGON", 18),
    ("CALCIUM", 20),
    ("TIN", 50),
    ("TUNGSTEN", 74),
    ("TITANIUM", 22),
    ("NICKEL", 28),
];

/// What is known of one material.
#[derive(Clone, Debug)]
pub(super) struct Known {
    /// FLUKA's material number.
    pub number: i64,
    /// Index into the scene's materials, when a card describes it.
    pub index: Option<usize>,
    /// The element (Z, mass number or 0) when it is a single element.
    element: Option<(u32, u32)>,
}

/// The materials of an input.
#[derive(Debug, Default)]
pub(super) struct Materials {
    by_name: HashMap<String, Known>,
    by_number: HashMap<i64, String>,
    /// The materials MATERIAL and COMPOUND cards describe, in input order.
    pub list: Vec<Material>,
}

impl Materials {
    fn next_free(&self) -> i64 {
        self.by_number.keys().max().map_or(1, |n| n + 1)
    }

    fn insert(&mut self, name: &str, known: Known) {
        self.by_number
            .entry(known.number)
            .or_insert_with(|| name.to_string());
        self.by_name.insert(name.to_string(), known);
    }

    /// The material a WHAT names (a name or a number), as its name and
    /// what is known of it; a name met for the first time takes the next
    /// free number.
    pub fn resolve(&mut self, text: &str) -> (String, Known) {
        if let Some(v) = card::number(text) {
            let number = if v <= 1.0 { 1 } else { v.min(1e9) as i64 };
            if let Some(name) = self.by_number.get(&number).cloned() {
                let known = self.by_name[&name].clone();
                return (name, known);
            }
            let known = Known {
                number,
                index: None,
                element: None,
            };
            return (format!("material #{number}"), known);
        }
        if let Some(known) = self.by_name.get(text) {
            return (text.to_string(), known.clone());
        }
        let known = Known {
            number: self.next_free(),
            index: None,
            element: None,
        };
        self.insert(text, known.clone());
        (text.to_string(), known)
    }
}

/// A number in a WHAT, when there is one.
fn what(c: &Card, k: usize) -> Option<f64> {
    c.what[k].as_ref().and_then(|f| card::number(&f.text))
}

impl Reader {
    /// The predefined materials and those the MATERIAL and COMPOUND cards
    /// describe.
    pub(super) fn materials(&mut self) -> Materials {
        let mut m = Materials::default();
        for (i, (name, z)) in PREDEFINED.iter().enumerate() {
            let element = (*z > 0).then_some((*z, 0));
            let number = i as i64 + 1;
            m.insert(
                name,
                Known {
                    number,
                    index: None,
                    element,
                },
            );
        }
        let cards = std::mem::take(&mut self.material_cards);
        let mut compounds: Vec<(String, Vec<(f64, String)>)> = Vec::new();
        for (i, c) in &cards {
            let Some(name) = c.sdum.as_ref().map(|f| f.text.clone()) else {
                self.warn(
                    *i,
                    1,
                    8,
                    format!("{} card without a name in SDUM: ignored", c.keyword),
                );
                continue;
            };
            if c.keyword == "COMPOUND" {
                let parts = (0..3).filter_map(|k| {
                    let fraction = what(c, 2 * k)?;
                    let of = c.what[2 * k + 1].as_ref()?.text.clone();
                    Some((fraction, of))
                });
                match compounds.iter_mut().find(|(n, _)| *n == name) {
                    Some((_, list)) => list.extend(parts),
                    None => compounds.push((name, parts.collect())),
                }
                continue;
            }
            material_card(&mut m, &name, c);
        }
        for (name, parts) in compounds {
            let components = components(&m, &parts);
            let index = match m.by_name.get(&name).and_then(|k| k.index) {
                Some(index) => index,
                None => {
                    let number = m
                        .by_name
                        .get(&name)
                        .map_or_else(|| m.next_free(), |k| k.number);
                    m.list.push(Material {
                        name: name.clone(),
                        ..Material::default()
                    });
                    let index = m.list.len() - 1;
                    m.insert(
                        &name,
                        Known {
                            number,
                            index: Some(index),
                            element: None,
                        },
                    );
                    index
                }
            };
            m.list[index].components = components;
            if let Some(k) = m.by_name.get_mut(&name) {
                k.element = None;
            }
        }
        m
    }
}

/// Record one MATERIAL card (a later card of the same name redefines it).
fn material_card(m: &mut Materials, name: &str, c: &Card) {
    let earlier = m.by_name.get(name).cloned();
    let number = what(c, 3)
        .filter(|v| *v >= 1.0)
        .map(|v| v.min(1e9) as i64)
        .or(earlier.as_ref().map(|k| k.number))
        .unwrap_or_else(|| m.next_free());
    let z = what(c, 0)
        .filter(|z| *z >= 1.0 && *z < 200.0)
        .map(|z| z.round() as u32);
    let mass = what(c, 5)
        .filter(|a| *a >= 1.0 && *a < 400.0)
        .map_or(0, |a| a.round() as u32);
    let material = Material {
        name: name.to_string(),
        density: what(c, 2).filter(|d| *d > 0.0),
        ..Material::default()
    };
    let index = match earlier.as_ref().and_then(|k| k.index) {
        Some(index) => {
            m.list[index] = material;
            index
        }
        None => {
            m.list.push(material);
            m.list.len() - 1
        }
    };
    let element = z.map(|z| (z, mass));
    m.by_number.insert(number, name.to_string());
    m.by_name.insert(
        name.to_string(),
        Known {
            number,
            index: Some(index),
            element,
        },
    );
}

/// A compound's components, when every one is a single element (else none:
/// a partial list would mislead).
fn components(m: &Materials, parts: &[(f64, String)]) -> Vec<Component> {
    let mut out = Vec::with_capacity(parts.len());
    for (fraction, of) in parts {
        let name = match card::number(of) {
            Some(v) => m
                .by_number
                .get(&(v.abs().min(1e9) as i64))
                .map(String::as_str),
            None => Some(of.as_str()),
        };
        let Some((z, a)) = name.and_then(|n| m.by_name.get(n)).and_then(|k| k.element) else {
            return Vec::new();
        };
        out.push(Component {
            zam: (z, a, 0),
            fraction: fraction.abs(),
            by_weight: *fraction < 0.0,
        });
    }
    out
}
