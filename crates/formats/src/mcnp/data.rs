//! The data block: `M` cards (materials), `TR` cards, and the cell
//! parameters given as data cards (`IMP:N`, `U`, `LAT`, `FILL`, `TRCL`),
//! one entry per cell in the order of the cell cards. Other cards do not
//! concern the geometry: they are skipped and a note names them.

use super::cell::MAX_NUMBER;
use super::input::{Card, Word};
use super::number::{integer, real, Entry, Expander};
use super::params::{Fill, FillSpec, Filler, Transform};
use super::transform::affine;
use super::Reader;
use sv_scene::{Component, Material};

/// A data card's name taken apart: `*TR12` is starred, `tr`, 12.
struct Name {
    starred: bool,
    letters: String,
    number: Option<i64>,
    particles: Option<String>,
}

fn name(w: &Word) -> Name {
    let lower = w.text.to_ascii_lowercase();
    let (starred, rest) = match lower.strip_prefix('*') {
        Some(r) => (true, r),
        None => (false, lower.as_str()),
    };
    let (head, particles) = match rest.split_once(':') {
        Some((h, p)) => (h, Some(p.to_string())),
        None => (rest, None),
    };
    let letters: String = head
        .chars()
        .take_while(|c| c.is_ascii_alphabetic())
        .collect();
    let digits = &head[letters.len()..];
    Name {
        starred,
        number: if digits.is_empty() {
            None
        } else {
            integer(digits)
        },
        letters,
        particles,
    }
}

impl Reader {
    pub(super) fn data_block(&mut self, cards: &[Card]) {
        let mut vertical = false;
        for card in cards {
            let first = &card.words[0];
            // The rows of a card in vertical format start with a number.
            if vertical && integer(&first.text).is_some() {
                continue;
            }
            vertical = first.text.starts_with('#');
            let n = name(first);
            match (n.letters.as_str(), n.number, n.particles.as_deref()) {
                ("m", Some(m), None) if m > 0 => self.material(card, m),
                ("tr", Some(t), None) => self.tr_card(card, t, n.starred),
                ("imp", None, Some(p)) if !n.starred => {
                    let neutron = p.split(',').any(|q| q == "n");
                    self.cell_data(card, if neutron { "imp:n" } else { "imp" });
                }
                ("u" | "lat", None, None) if !n.starred => self.cell_data(card, &n.letters),
                ("fill" | "trcl", None, None) => {
                    let key = format!("{}{}", if n.starred { "*" } else { "" }, n.letters);
                    self.cell_data(card, &key);
                }
                _ => {
                    let shown = first.text.to_ascii_uppercase();
                    let shown = shown
                        .trim_end_matches(|c: char| c.is_ascii_digit())
                        .to_string();
                    if first.text.starts_with('#') {
                        self.log
                            .warn(first.at, "cards in vertical format (`#` in columns 1–5) are not read")
                            .hint = Some("give the cell parameters on the cell cards or as one card per parameter".into());
                    } else if !self.skipped.contains(&shown) {
                        self.skipped.push(shown);
                    }
                }
            }
        }
    }

    /// The entries of a card after its name, shorthand expanded.
    fn entries(&mut self, words: &[Word]) -> Option<Vec<Entry>> {
        let mut e = Expander::default();
        for w in words {
            if let Err(msg) = e.push(w) {
                self.log.error(w.at, msg);
                return None;
            }
        }
        match e.finish() {
            Ok(v) => Some(v),
            Err((at, msg)) => {
                self.log.error(at, msg);
                None
            }
        }
    }

    fn tr_card(&mut self, card: &Card, t: i64, degrees: bool) {
        let first = &card.words[0];
        if !(1..=MAX_NUMBER).contains(&t) {
            self.log.error(
                first.at,
                format!("`{}` is no transformation number", first.text),
            );
            return;
        }
        let Some(entries) = self.entries(&card.words[1..]) else {
            return;
        };
        let values: Vec<Option<f64>> = entries.iter().map(|e| e.0).collect();
        match affine(&values, degrees) {
            Ok(xf) => {
                if let Some((_, before)) = self.transforms.get(&t) {
                    let line = before.line;
                    self.log.error(
                        first.at,
                        format!("TR{t} is defined twice (first on line {line})"),
                    );
                } else {
                    self.transforms.insert(t, (xf, first.at));
                }
            }
            Err(msg) => {
                self.log.error(first.at, format!("TR{t}: {msg}"));
            }
        }
    }

    fn material(&mut self, card: &Card, m: i64) {
        let first = &card.words[0];
        if m > MAX_NUMBER {
            self.log
                .error(first.at, format!("`{}` is no material number", first.text));
            return;
        }
        if self.material_index.contains_key(&m) {
            self.log.warn(
                first.at,
                format!("material {m} is defined again; the first M{m} card is used"),
            );
            return;
        }
        let mut material = Material {
            name: format!("m{m}"),
            ..Material::default()
        };
        let words = &card.words[1..];
        let mut i = 0;
        let (mut atoms, mut weights) = (false, false);
        while i < words.len() {
            let w = &words[i];
            if w.text.starts_with(|c: char| c.is_ascii_alphabetic()) {
                // A keyword (`NLIB=80c`, `GAS = 1`): skip it and its value.
                i += match w.text.find('=') {
                    Some(e) if e + 1 < w.text.len() => 1,
                    Some(_) => 2,
                    None if words.get(i + 1).is_some_and(|n| n.text == "=") => 3,
                    None => 2,
                };
                continue;
            }
            let Some(f) = words.get(i + 1) else {
                self.log
                    .warn(w.at, format!("`{}` has no fraction after it", w.text));
                break;
            };
            i += 2;
            let Some(fraction) = real(&f.text) else {
                self.log
                    .warn(f.at, format!("expected a fraction, found `{}`", f.text));
                continue;
            };
            match zam(&w.text) {
                Some(zam) => {
                    atoms |= fraction > 0.0;
                    weights |= fraction < 0.0;
                    material.components.push(Component {
                        zam,
                        fraction: fraction.abs(),
                        by_weight: fraction < 0.0,
                    });
                }
                None => {
                    self.log.warn(
                        w.at,
                        format!(
                            "`{}` is no ZAID (ZZZAAA.nnX); the component is left out",
                            w.text
                        ),
                    );
                }
            }
        }
        if atoms && weights {
            self.log.warn(
                first.at,
                format!("M{m} mixes atom fractions (positive) and weight fractions (negative)"),
            );
        }
        self.material_index.insert(m, self.materials.len());
        self.materials.push(material);
    }

    /// A cell parameter given as a data card: one entry per cell.
    fn cell_data(&mut self, card: &Card, key: &str) {
        let first = &card.words[0];
        if key.ends_with("fill") && card.words.iter().any(|w| w.text.contains(['(', ')'])) {
            self.log.warn(
                first.at,
                "a FILL data card with transformations is not read; give them on the cell cards",
            );
            return;
        }
        let Some(entries) = self.entries(&card.words[1..]) else {
            return;
        };
        if entries.len() != self.cells.len() {
            self.log.warn(
                first.at,
                format!(
                    "{} gives {} entries for {} cells",
                    first.text.to_ascii_uppercase(),
                    entries.len(),
                    self.cells.len()
                ),
            );
        }
        for (cell, (value, at)) in self.cells.iter_mut().zip(&entries) {
            let Some(v) = *value else { continue };
            let p = &mut cell.params;
            let whole = (v.fract() == 0.0 && v.abs() <= MAX_NUMBER as f64).then_some(v as i64);
            let taken = match key {
                "imp:n" => p.imp_neutron.replace(v).is_some(),
                "imp" => p.imp_other.replace(v).is_some(),
                "u" | "lat" => match whole {
                    Some(0) => false,
                    Some(n) => {
                        let slot = if key == "u" {
                            &mut p.universe
                        } else {
                            &mut p.lattice
                        };
                        slot.replace((n, *at)).is_some()
                    }
                    None => false,
                },
                "trcl" | "*trcl" => match whole {
                    Some(n) if n > 0 => p.trcl.replace(Transform::Card(n, *at)).is_some(),
                    _ => false,
                },
                _ => match whole {
                    Some(n) if n > 0 => {
                        let filler = Filler {
                            universe: n,
                            transform: None,
                            at: *at,
                        };
                        let fill = Fill {
                            spec: FillSpec::One(filler),
                            at: *at,
                        };
                        p.fill.replace(fill).is_some()
                    }
                    _ => false,
                },
            };
            if taken {
                let number = cell.number;
                self.log.warn(*at, format!("cell {number} also gives this parameter on its card; the card's value is used"));
            }
        }
    }
}

/// A ZAID's (Z, A, metastable state): `92235.80c` is (92, 235, 0), `6000`
/// natural carbon (6, 0, 0), `95642` Am-242m (A + 300 + 100 m).
fn zam(zaid: &str) -> Option<(u32, u32, u32)> {
    let number = zaid.split('.').next()?;
    let z_a = u32::try_from(integer(number)?).ok()?;
    let (z, a) = (z_a / 1000, z_a % 1000);
    if !(1..=130).contains(&z) {
        return None;
    }
    if a > 300 {
        for m in 1..=4 {
            if let Some(ground) = a.checked_sub(300 + 100 * m) {
                if ground >= z {
                    return Some((z, ground, m));
                }
            }
        }
    }
    Some((z, a, 0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zaids() {
        assert_eq!(zam("92235.80c"), Some((92, 235, 0)));
        assert_eq!(zam("6000.70c"), Some((6, 0, 0)));
        assert_eq!(zam("95642"), Some((95, 242, 1)));
        assert_eq!(zam("47510.80c"), Some((47, 110, 1)));
        assert_eq!(zam("lwtr.10t"), None);
        assert_eq!(zam("0.70c"), None);
    }
}
