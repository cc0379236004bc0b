//! What each region is made of, and which substances of two models are the
//! same: by composition (atom fractions, normalised) and density (compared
//! as atoms per barn-centimetre), since codes number and name materials
//! differently.

use super::atomic::{molar_mass, AVOGADRO_PER_BARN};
use crate::report::fmt_g;
use std::collections::BTreeMap;
use sv_scene::{Material, Scene};

/// Atom fractions by (Z, A).
pub(crate) type Fractions = Vec<((u32, u32), f64)>;

/// One material at one density, as regions of a model use it.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Substance {
    /// The material as the input names it (`m12`, `UO2`).
    pub material: String,
    /// Its number as the input gives it (MCNP's `m12` is 12; OpenMC's id).
    pub number: i64,
    /// Atom fractions by (Z, A) (A = 0: the natural element), summing to
    /// 1; `None` when the input does not describe the material.
    pub fractions: Option<Fractions>,
    /// Atom density (atoms/b-cm), given or worked out from the mass
    /// density and the molar mass.
    pub atom_density: Option<f64>,
    /// Mass density (g/cm³), given or worked out.
    pub density: Option<f64>,
}

impl Substance {
    /// `m12 at 10.5 g/cm³`.
    pub fn label(&self) -> String {
        match (self.density, self.atom_density) {
            (Some(rho), _) => format!("{} at {} g/cm³", self.material, fmt_g(rho)),
            (None, Some(n)) => format!("{} at {} atoms/b-cm", self.material, fmt_g(n)),
            (None, None) => self.material.clone(),
        }
    }

    /// True when `name` names this substance's material: its name, its
    /// number, or `m` and its number.
    pub fn is_named(&self, name: &str) -> bool {
        let name = name.trim();
        name.eq_ignore_ascii_case(&self.material)
            || name == self.number.to_string()
            || name.eq_ignore_ascii_case(&format!("m{}", self.number))
    }
}

/// The substances of one model and which one each region holds.
#[derive(Clone, Debug, Default)]
pub(crate) struct Substances {
    pub list: Vec<Substance>,
    /// Per region: its substance, `None` for void and for regions beyond
    /// the model.
    pub of_region: Vec<Option<usize>>,
}

/// Atom fractions of `m` (normalised) and its molar mass, when every
/// component's mass is known and the fractions add up to something.
fn atom_fractions(m: &Material) -> Option<(Fractions, f64)> {
    let mut by_nuclide: BTreeMap<(u32, u32), f64> = BTreeMap::new();
    for c in &m.components {
        let mass = molar_mass(c.zam.0, c.zam.1)?;
        let atoms = if c.by_weight {
            c.fraction.abs() / mass
        } else {
            c.fraction.abs()
        };
        *by_nuclide.entry((c.zam.0, c.zam.1)).or_default() += atoms;
    }
    let total: f64 = by_nuclide.values().sum();
    if !(total > 0.0 && total.is_finite()) {
        return None;
    }
    let fractions: Vec<_> = by_nuclide
        .into_iter()
        .map(|(k, v)| (k, v / total))
        .collect();
    let molar: f64 = fractions
        .iter()
        .map(|&((z, a), x)| x * molar_mass(z, a).unwrap_or(0.0))
        .sum();
    Some((fractions, molar))
}

impl Substances {
    /// Read them off a scene: a region's material (by index into
    /// [`Scene::materials`] or by name) and its density.
    pub fn of_scene(scene: &Scene) -> Substances {
        let mut out = Substances::default();
        for props in &scene.regions {
            if props.outside {
                out.of_region.push(None);
                continue;
            }
            let material = props.material_index.and_then(|i| scene.materials.get(i));
            let name = match (material, &props.material_name) {
                (Some(m), _) => m.name.clone(),
                (None, Some(name)) => name.clone(),
                (None, None) => {
                    out.of_region.push(None);
                    continue;
                }
            };
            let composition = material.and_then(atom_fractions);
            let molar = composition.as_ref().map(|c| c.1);
            let (mut density, mut atom_density) = (props.density, props.atom_density);
            if let Some(molar) = molar.filter(|m| *m > 0.0) {
                match (density, atom_density) {
                    (Some(rho), None) => atom_density = Some(rho * AVOGADRO_PER_BARN / molar),
                    (None, Some(n)) => density = Some(n * molar / AVOGADRO_PER_BARN),
                    _ => {}
                }
            }
            let substance = Substance {
                material: name,
                number: props.material,
                fractions: composition.map(|c| c.0),
                atom_density,
                density,
            };
            let index = match out.list.iter().position(|s| *s == substance) {
                Some(i) => i,
                None => {
                    out.list.push(substance);
                    out.list.len() - 1
                }
            };
            out.of_region.push(Some(index));
        }
        out
    }
}

/// How far apart two substances are.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Distance {
    /// Half the sum of the differences of atom fractions: 0 for the same
    /// composition, 1 for nothing in common; `None` when either is not
    /// described.
    pub composition: Option<f64>,
    /// Relative difference of the atom densities (of the mass densities
    /// when an atom density is missing); `None` when not comparable.
    pub density: Option<f64>,
}

impl Distance {
    /// True when both are within the tolerances (a density that cannot be
    /// compared does not count against).
    pub fn within(&self, composition_tolerance: f64, density_tolerance: f64) -> bool {
        self.composition.is_some_and(|c| c <= composition_tolerance)
            && self.density.is_none_or(|d| d <= density_tolerance)
    }

    /// `composition differs by 3.2 %, density by 0.1 %`.
    pub fn describe(&self) -> String {
        let composition = match self.composition {
            Some(c) => format!("composition differs by {} %", fmt_g(100.0 * c)),
            None => "composition unknown".into(),
        };
        match self.density {
            Some(d) => format!("{composition}, density by {} %", fmt_g(100.0 * d)),
            None => format!("{composition}, densities not comparable"),
        }
    }
}

/// The fractions with every nuclide of an element in `natural` summed
/// into the element (A = 0): one model may give natural iron where the
/// other lists its isotopes.
fn collapsed(fractions: &[((u32, u32), f64)], natural: &[u32]) -> BTreeMap<(u32, u32), f64> {
    let mut out = BTreeMap::new();
    for &((z, a), x) in fractions {
        let a = if natural.contains(&z) { 0 } else { a };
        *out.entry((z, a)).or_default() += x;
    }
    out
}

/// How far apart `a` and `b` are.
pub(crate) fn distance(a: &Substance, b: &Substance) -> Distance {
    let composition = match (&a.fractions, &b.fractions) {
        (Some(fa), Some(fb)) => {
            let mut natural: Vec<u32> = fa
                .iter()
                .chain(fb)
                .filter(|((_, mass_number), _)| *mass_number == 0)
                .map(|((z, _), _)| *z)
                .collect();
            natural.dedup();
            let (ca, cb) = (collapsed(fa, &natural), collapsed(fb, &natural));
            let mut sum = 0.0;
            for key in ca.keys().chain(cb.keys().filter(|k| !ca.contains_key(k))) {
                let x = ca.get(key).copied().unwrap_or(0.0);
                let y = cb.get(key).copied().unwrap_or(0.0);
                sum += (x - y).abs();
            }
            Some(0.5 * sum)
        }
        _ => None,
    };
    let relative = |x: f64, y: f64| (x - y).abs() / x.abs().max(y.abs()).max(1e-300);
    let density = match (a.atom_density, b.atom_density, a.density, b.density) {
        (Some(x), Some(y), _, _) => Some(relative(x, y)),
        (_, _, Some(x), Some(y)) => Some(relative(x, y)),
        _ => None,
    };
    Distance {
        composition,
        density,
    }
}

/// Which substances are the same: classes over both models' substances.
/// Class 0 is void (and space beyond the model).
#[derive(Clone, Debug)]
pub(crate) struct Matching {
    /// Per substance of A, its class.
    pub class_a: Vec<u32>,
    /// Per substance of B, its class.
    pub class_b: Vec<u32>,
    /// Number of classes, void included.
    pub classes: usize,
    /// Substances of A with no partner in B: the closest one and how far.
    pub unmatched_a: Vec<(usize, Option<(usize, Distance)>)>,
    /// The same for B.
    pub unmatched_b: Vec<(usize, Option<(usize, Distance)>)>,
}

fn root(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

/// Match the substances of `a` and `b`: forced pairs from `map` (material
/// names or numbers, A's first), then every pair within the tolerances
/// for the substances no pair of the map names.
pub(crate) fn match_substances(
    a: &[Substance],
    b: &[Substance],
    map: &[(String, String)],
    tolerances: (f64, f64),
) -> Matching {
    let mut parent: Vec<usize> = (0..a.len() + b.len()).collect();
    let mapped_a = |i: usize| map.iter().any(|(x, _)| a[i].is_named(x));
    let mapped_b = |j: usize| map.iter().any(|(_, y)| b[j].is_named(y));
    let mut partnered = vec![false; a.len() + b.len()];
    for i in 0..a.len() {
        for j in 0..b.len() {
            let same = if mapped_a(i) || mapped_b(j) {
                map.iter()
                    .any(|(x, y)| a[i].is_named(x) && b[j].is_named(y))
            } else {
                distance(&a[i], &b[j]).within(tolerances.0, tolerances.1)
            };
            if same {
                let (ra, rb) = (root(&mut parent, i), root(&mut parent, a.len() + j));
                parent[ra] = rb;
                partnered[i] = true;
                partnered[a.len() + j] = true;
            }
        }
    }
    let mut class_of_root = BTreeMap::new();
    let mut class = |parent: &mut [usize], i: usize| {
        let r = root(parent, i);
        let next = class_of_root.len() as u32 + 1;
        *class_of_root.entry(r).or_insert(next)
    };
    let class_a: Vec<u32> = (0..a.len()).map(|i| class(&mut parent, i)).collect();
    let class_b: Vec<u32> = (0..b.len())
        .map(|j| class(&mut parent, a.len() + j))
        .collect();
    let closest = |s: &Substance, others: &[Substance]| {
        others
            .iter()
            .enumerate()
            .map(|(k, o)| (k, distance(s, o)))
            .min_by(|x, y| score(&x.1).total_cmp(&score(&y.1)))
    };
    Matching {
        classes: class_of_root.len() + 1,
        class_a,
        class_b,
        unmatched_a: (0..a.len())
            .filter(|&i| !partnered[i])
            .map(|i| (i, closest(&a[i], b)))
            .collect(),
        unmatched_b: (0..b.len())
            .filter(|&j| !partnered[a.len() + j])
            .map(|j| (j, closest(&b[j], a)))
            .collect(),
    }
}

/// A single figure to rank candidates by: composition first.
fn score(d: &Distance) -> f64 {
    d.composition.unwrap_or(2.0) * 10.0 + d.density.unwrap_or(1.0).min(1.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use sv_scene::{Component, RegionProps};

    fn water(by_weight: bool, density: Option<f64>, atom_density: Option<f64>) -> Scene {
        let (h, o) = if by_weight {
            (0.111_898, 0.888_102)
        } else {
            (2.0, 1.0)
        };
        let mut scene = Scene::default();
        scene.materials.push(Material {
            name: "water".into(),
            components: vec![
                Component {
                    zam: (1, 1, 0),
                    fraction: h,
                    by_weight,
                },
                Component {
                    zam: (8, 0, 0),
                    fraction: o,
                    by_weight,
                },
            ],
            ..Material::default()
        });
        scene.regions.push(RegionProps {
            material: 3,
            material_index: Some(0),
            density,
            atom_density,
            ..RegionProps::default()
        });
        scene
    }

    #[test]
    fn weight_and_atom_fractions_and_both_density_units_match() {
        // Water at 1 g/cm³ is 0.10033 atoms/b-cm (3 atoms of 18.015 g/mol).
        let a = Substances::of_scene(&water(true, Some(1.0), None));
        let b = Substances::of_scene(&water(false, None, Some(0.100_33)));
        let d = distance(&a.list[0], &b.list[0]);
        assert!(d.composition.unwrap() < 1e-4, "{d:?}");
        assert!(d.density.unwrap() < 1e-3, "{d:?}");
        let matching = match_substances(&a.list, &b.list, &[], (0.01, 0.01));
        assert_eq!(matching.class_a, matching.class_b);
        assert!(matching.unmatched_a.is_empty());
        // Denser water is another substance, unless the map pairs them.
        let c = Substances::of_scene(&water(false, None, Some(0.11)));
        let matching = match_substances(&a.list, &c.list, &[], (0.01, 0.01));
        assert_ne!(matching.class_a, matching.class_b);
        assert_eq!(matching.unmatched_a.len(), 1);
        let map = [("m3".to_string(), "water".to_string())];
        let matching = match_substances(&a.list, &c.list, &map, (0.01, 0.01));
        assert_eq!(matching.class_a, matching.class_b);
    }

    #[test]
    fn isotopes_collapse_into_a_natural_element() {
        let natural = Substance {
            material: "fe".into(),
            number: 1,
            fractions: Some(vec![((26, 0), 1.0)]),
            atom_density: Some(0.08),
            density: None,
        };
        let isotopes = Substance {
            fractions: Some(vec![((26, 54), 0.06), ((26, 56), 0.94)]),
            ..natural.clone()
        };
        assert_eq!(distance(&natural, &isotopes).composition, Some(0.0));
        let steel = Substance {
            fractions: Some(vec![((26, 0), 0.7), ((24, 0), 0.3)]),
            ..natural.clone()
        };
        let d = distance(&natural, &steel).composition.unwrap();
        assert!((d - 0.3).abs() < 1e-12);
    }
}
