//! Lattice cells: element (0,0,0) and the steps to its neighbours from the
//! cell's planes in MCNP's order, and the elements' universes from `FILL`.

use super::cell::{Factor, SurfaceRef, Union};
use super::params::{FillSpec, Filler, Transform};
use super::region::all_space;
use super::{Frame, Reader, UNBOUNDED};
use std::collections::HashMap;
use sv_geom::{Body, BodyKind, Fill, Lattice, LatticeKind, Region, Universe, Zone};
use sv_math::{DAffine3, DMat3, DVec3};
use sv_scene::RegionProps;

/// Relative tolerance on parallel planes and on a regular hexagon.
const TOLERANCE: f64 = 1e-6;

/// The plane a half-space body lies on: unit normal n and offset d
/// (n·x = d).
fn plane_of(b: &Body) -> Option<(DVec3, f64)> {
    let v = |i: usize| DVec3::new(b.params[i], b.params[i + 1], b.params[i + 2]);
    match b.kind {
        BodyKind::Yzp => Some((DVec3::X, b.params[0])),
        BodyKind::Xzp => Some((DVec3::Y, b.params[0])),
        BodyKind::Xyp => Some((DVec3::Z, b.params[0])),
        BodyKind::Pla => {
            let n = v(0).try_normalize()?;
            Some((n, n.dot(v(3))))
        }
        BodyKind::Haf => {
            let len = v(0).length();
            (len > 0.0).then(|| (v(0) / len, b.params[3] / len))
        }
        _ => None,
    }
}

/// The surfaces of an intersection, in order; `false` when the geometry is
/// anything else.
fn flatten(u: &Union, out: &mut Vec<SurfaceRef>) -> bool {
    let [inter] = u.as_slice() else { return false };
    inter.iter().all(|f| match f {
        Factor::Surface(r) => {
            out.push(r.clone());
            true
        }
        Factor::Group(g) => flatten(g, out),
        _ => false,
    })
}

/// Pair `k` of `planes` (the k-th and the next): the common normal, the
/// first plane's offset and the second's along that normal.
fn pair(planes: &[(DVec3, f64)], k: usize) -> Result<(DVec3, f64, f64), String> {
    let ((n, d), (m, e)) = (planes[k], planes[k + 1]);
    let cos = n.dot(m);
    if cos.abs() < 1.0 - TOLERANCE {
        return Err(format!(
            "surfaces {} and {} of the cell are not parallel",
            k + 1,
            k + 2
        ));
    }
    let e = e * cos.signum();
    if (d - e).abs() <= TOLERANCE * (d.abs() + e.abs()) {
        return Err(format!(
            "surfaces {} and {} of the cell are the same plane",
            k + 1,
            k + 2
        ));
    }
    Ok((n, d, e))
}

/// The pair of planes ending the cell along its axis (planes `k` and `k +
/// 1`), or when there are none, planes [`UNBOUNDED`] apart across the two
/// normals `n0` and `n1`.
fn axial(
    planes: &[(DVec3, f64)],
    k: usize,
    n0: DVec3,
    n1: DVec3,
) -> Result<(DVec3, f64, f64), String> {
    if planes.len() > k {
        return pair(planes, k);
    }
    let n = n0
        .cross(n1)
        .try_normalize()
        .ok_or("the cell's planes do not close a cell")?;
    Ok((n, UNBOUNDED / 2.0, -UNBOUNDED / 2.0))
}

/// Solve `rows · x = rhs`, the rows independent.
fn solve(rows: [DVec3; 3], rhs: DVec3) -> Result<DVec3, String> {
    let m = DMat3::from_cols(rows[0], rows[1], rows[2]).transpose();
    if m.determinant().abs() < TOLERANCE {
        return Err("the cell's planes do not close a cell".into());
    }
    Ok(m.inverse() * rhs)
}

/// The steps a, b, c and the base of a lattice whose element (0,0,0) the
/// `planes` bound, in MCNP's order.
pub(super) fn cell_box(
    kind: LatticeKind,
    planes: &[(DVec3, f64)],
) -> Result<([DVec3; 3], DVec3), String> {
    match kind {
        LatticeKind::Rectangular => {
            let (n0, d0, e0) = pair(planes, 0)?;
            let (n1, d1, e1) = pair(planes, 2)?;
            let (n2, d2, e2) = axial(planes, 4, n0, n1)?;
            let rows = [n0, n1, n2];
            let steps = [
                solve(rows, DVec3::new(d0 - e0, 0.0, 0.0))?,
                solve(rows, DVec3::new(0.0, d1 - e1, 0.0))?,
                solve(rows, DVec3::new(0.0, 0.0, d2 - e2))?,
            ];
            Ok((steps, solve(rows, DVec3::new(e0, e1, e2))?))
        }
        LatticeKind::Hexagonal => {
            let (n0, d0, e0) = pair(planes, 0)?;
            let (n1, d1, e1) = pair(planes, 2)?;
            pair(planes, 4)?;
            let (a, b) = (n0 * (d0 - e0), n1 * (d1 - e1));
            let pitch = a.length();
            if (b.length() - pitch).abs() > TOLERANCE * pitch
                || ((b - a).length() - pitch).abs() > TOLERANCE * pitch
            {
                return Err("the first four surfaces of a LAT=2 cell must face elements 60° apart at one pitch (MCNP's order: [1,0,0], [-1,0,0], [0,1,0], [0,-1,0], [-1,1,0], [1,-1,0], [0,0,1], [0,0,-1])".into());
            }
            let (n2, d2, e2) = axial(planes, 6, n0, n1)?;
            if n2.dot(n0).abs() > TOLERANCE || n2.dot(n1).abs() > TOLERANCE {
                return Err("the ends of a LAT=2 cell must be at right angles to its sides".into());
            }
            let base = solve([n0, n1, n2], DVec3::new(d0 + e0, d1 + e1, d2 + e2) / 2.0)?;
            Ok(([a, b, n2 * (d2 - e2)], base))
        }
    }
}

/// What the elements of one lattice cell share.
struct Owner {
    /// The lattice's own universe number.
    universe: i64,
    /// The lattice cell's number.
    cell: i64,
    /// All space, for the universes made to hold moved ones.
    space: Vec<Zone>,
}

impl Reader {
    /// The planes bounding lattice cell `i`, in order: its surfaces, or the
    /// facets of the one macrobody it is the inside of.
    fn lattice_planes(&mut self, i: usize, kind: LatticeKind) -> Option<Vec<(DVec3, f64)>> {
        let (number, at) = (self.cells[i].number, self.cells[i].at);
        let mut refs = Vec::new();
        if !flatten(&self.cells[i].geometry, &mut refs) {
            self.log.error(at, format!("lattice cell {number} must be an intersection of planes, written in MCNP's order"));
            return None;
        }
        let facets = match kind {
            LatticeKind::Rectangular => ["rpp", "box"].as_slice(),
            LatticeKind::Hexagonal => ["rhp", "hex"].as_slice(),
        };
        if let [r] = refs.as_slice() {
            let s = self.surface_index.get(&r.number).copied();
            let m = s.map(|s| self.surfaces[s].mnemonic.as_str());
            if r.facet.is_none() && m.is_some_and(|m| facets.contains(&m)) {
                let n = if kind == LatticeKind::Rectangular {
                    6
                } else {
                    8
                };
                refs = (1..=n)
                    .map(|k| SurfaceRef {
                        facet: Some(k),
                        ..r.clone()
                    })
                    .collect();
            }
        }
        let want: &[usize] = match kind {
            LatticeKind::Rectangular => &[4, 6],
            LatticeKind::Hexagonal => &[6, 8],
        };
        if !want.contains(&refs.len()) {
            let lat = if kind == LatticeKind::Rectangular {
                1
            } else {
                2
            };
            self.log.error(
                at,
                format!(
                    "a LAT={lat} cell is bounded by {} or {} planes, not {} (cell {number})",
                    want[0],
                    want[1],
                    refs.len()
                ),
            );
            return None;
        }
        let mut planes = Vec::with_capacity(refs.len());
        for r in &refs {
            let terms = self.surface_terms(r, None)?;
            let plane = match terms.as_slice() {
                [t] => plane_of(&self.bodies[t.body]),
                _ => None,
            };
            let Some(plane) = plane else {
                self.log.error(
                    r.at,
                    format!(
                        "surface {} of lattice cell {number} is not a plane",
                        r.number
                    ),
                );
                return None;
            };
            planes.push(plane);
        }
        Some(planes)
    }

    /// The fill of lattice cell `i`.
    pub(super) fn lattice(
        &mut self,
        i: usize,
        frame: Option<Frame>,
        index: &HashMap<i64, usize>,
        universes: &mut Vec<Universe>,
        wrappers: &mut Vec<(Region, RegionProps)>,
    ) -> Option<Fill> {
        let c = self.cells[i].clone();
        let (lat, lat_at) = c.params.lattice?;
        let kind = match lat {
            1 => LatticeKind::Rectangular,
            2 => LatticeKind::Hexagonal,
            _ => {
                self.log.error(
                    lat_at,
                    format!("LAT must be 1 (hexahedra) or 2 (hexagonal prisms), not {lat}"),
                );
                return None;
            }
        };
        let Some(fill) = &c.params.fill else {
            self.log
                .error(lat_at, format!("lattice cell {} has no FILL", c.number));
            return None;
        };
        let planes = self.lattice_planes(i, kind)?;
        let (steps, base) = match cell_box(kind, &planes) {
            Ok(b) => b,
            Err(msg) => {
                self.log
                    .error(c.at, format!("lattice cell {}: {msg}", c.number));
                return None;
            }
        };
        let own = c.params.universe.map_or(0, |u| u.0.abs());
        let (lowest, counts, fillers, infinite) = match &fill.spec {
            FillSpec::One(f) => ([0; 3], [1; 3], std::slice::from_ref(f), true),
            FillSpec::Array { ranges, elements } => {
                let counts = ranges.map(|(lo, hi)| (hi - lo + 1) as u128);
                let want: u128 = counts.iter().product();
                if want != elements.len() as u128 {
                    let r = ranges.map(|(lo, hi)| format!("{lo}:{hi}")).join(" ");
                    self.log.error(
                        fill.at,
                        format!(
                            "lattice cell {} lists {} elements; its ranges {r} need {want}",
                            c.number,
                            elements.len()
                        ),
                    );
                    return None;
                }
                (
                    ranges.map(|r| r.0 as i32),
                    counts.map(|n| n as u32),
                    elements.as_slice(),
                    false,
                )
            }
        };
        let written = self.cell_zones(i, 0)?;
        let owner = Owner {
            universe: own,
            cell: c.number,
            space: all_space(&written),
        };
        let mut made: HashMap<String, usize> = HashMap::new();
        let mut elements = Vec::with_capacity(fillers.len());
        for f in fillers {
            elements.push(self.element(f, &owner, index, universes, wrappers, &mut made)?);
        }
        Some(Fill::Lattice(Lattice {
            kind,
            region_from_lattice: frame.map_or(DAffine3::IDENTITY, |f| f.xf),
            steps,
            base,
            origin: DVec3::ZERO,
            lowest,
            counts,
            outer: if infinite { elements[0] } else { None },
            elements,
        }))
    }

    /// The universe of one element: `None` for the lattice's own universe
    /// or 0 (the cell's material), a universe made to hold a moved one when
    /// the element has a transformation.
    fn element(
        &mut self,
        f: &Filler,
        owner: &Owner,
        index: &HashMap<i64, usize>,
        universes: &mut Vec<Universe>,
        wrappers: &mut Vec<(Region, RegionProps)>,
        made: &mut HashMap<String, usize>,
    ) -> Option<Option<usize>> {
        let cell = owner.cell;
        if f.universe == owner.universe || f.universe == 0 {
            return Some(None);
        }
        // An undefined universe is reported with the fills.
        let u = *index.get(&f.universe)?;
        let Some(t) = &f.transform else {
            return Some(Some(u));
        };
        let key = match t {
            Transform::Card(n, _) => format!("{}(TR{n})", f.universe),
            Transform::Values {
                values, degrees, ..
            } => {
                let shown: Vec<String> = values
                    .iter()
                    .map(|v| v.map_or("J".to_string(), |x| x.to_string()))
                    .collect();
                format!(
                    "{}{}({})",
                    f.universe,
                    if *degrees { "*" } else { "" },
                    shown.join(" ")
                )
            }
        };
        if let Some(&w) = made.get(&key) {
            return Some(Some(w));
        }
        let xf = self.transform_of(t)?;
        let w = universes.len();
        universes.push(Universe { name: key.clone() });
        let region = Region {
            name: format!("{cell}:{key}"),
            zones: owner.space.clone(),
            universe: w,
            fill: Some(Fill::Universe {
                universe: u,
                region_from_universe: xf,
            }),
        };
        let props = RegionProps {
            description: format!("universe {} moved as lattice cell {cell} asks", f.universe),
            ..RegionProps::default()
        };
        wrappers.push((region, props));
        made.insert(key, w);
        Some(Some(w))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_follow_the_order_of_the_planes() {
        // MCNP's Hoogenboom–Martin pin cell: px -0.63 first, so element
        // (1,0,0) lies toward -x.
        let planes = [
            (DVec3::X, -0.63),
            (DVec3::X, 0.63),
            (DVec3::Y, -0.63),
            (DVec3::Y, 0.63),
        ];
        let (steps, base) = cell_box(LatticeKind::Rectangular, &planes).unwrap();
        assert!((steps[0] - DVec3::new(-1.26, 0.0, 0.0)).length() < 1e-12);
        assert!((steps[1] - DVec3::new(0.0, -1.26, 0.0)).length() < 1e-12);
        assert!((steps[2].z - UNBOUNDED).abs() < 1.0);
        assert!((base - DVec3::new(0.63, 0.63, -UNBOUNDED / 2.0)).length() < 1e-3);
        // A hexagon of pitch 2: faces at ±1 along 0°, 60° and 120°.
        let dir = |deg: f64| DVec3::new(deg.to_radians().cos(), deg.to_radians().sin(), 0.0);
        let hex = [
            (dir(0.0), 1.0),
            (dir(0.0), -1.0),
            (dir(60.0), 1.0),
            (dir(60.0), -1.0),
            (dir(120.0), 1.0),
            (dir(120.0), -1.0),
            (DVec3::Z, 5.0),
            (DVec3::Z, -5.0),
        ];
        let (steps, base) = cell_box(LatticeKind::Hexagonal, &hex).unwrap();
        assert!((steps[0] - dir(0.0) * 2.0).length() < 1e-12);
        assert!((steps[1] - dir(60.0) * 2.0).length() < 1e-12);
        assert!((steps[2] - DVec3::Z * 10.0).length() < 1e-12);
        assert!(base.length() < 1e-12);
        let mut wrong = hex;
        wrong.swap(2, 4);
        assert!(cell_box(LatticeKind::Hexagonal, &wrong).is_err());
    }
}
