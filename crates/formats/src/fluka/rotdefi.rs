//! ROT-DEFI roto-translations and the transform a body gets from the
//! `$start_…` directives around it.
//!
//! The convention is described in the parent module's documentation.

use super::card::{self, Card};
use sv_math::{DAffine3, DMat3, DVec3};

/// One ROT-DEFI card.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct RotDefi {
    /// Axis: 1 = x, 2 = y, 3 = z.
    pub axis: u8,
    /// Polar angle θ in degrees.
    pub polar: f64,
    /// Azimuthal angle φ in degrees.
    pub azimuth: f64,
    /// Offset added before the rotation.
    pub offset: DVec3,
}

/// Split WHAT(1) into the transformation index and the axis (1 = x, 2 = y,
/// 3 = z); `Err(j)` for an axis code that is not 0…3.
pub(crate) fn index_and_axis(what1: f64) -> Result<(i64, u8), i64> {
    let w = if what1.is_finite() && what1 > 0.0 {
        what1.min(1e15) as i64
    } else {
        0
    };
    let (i, j) = if w >= 1000 {
        (w / 1000, w % 1000)
    } else if w >= 100 {
        (w % 100, w / 100)
    } else {
        (w, 0)
    };
    match j {
        0 | 3 => Ok((i, 3)),
        1 | 2 => Ok((i, j as u8)),
        _ => Err(j),
    }
}

fn rows(r0: [f64; 3], r1: [f64; 3], r2: [f64; 3]) -> DMat3 {
    DMat3::from_cols(DVec3::from(r0), DVec3::from(r1), DVec3::from(r2)).transpose()
}

impl RotDefi {
    /// The card as a transform of body points.
    pub fn affine(&self) -> DAffine3 {
        let (st, ct) = self.polar.to_radians().sin_cos();
        let (sp, cp) = self.azimuth.to_radians().sin_cos();
        let (rt, rp) = match self.axis {
            1 => (
                rows([ct, st, 0.0], [-st, ct, 0.0], [0.0, 0.0, 1.0]),
                rows([1.0, 0.0, 0.0], [0.0, cp, sp], [0.0, -sp, cp]),
            ),
            2 => (
                rows([1.0, 0.0, 0.0], [0.0, ct, st], [0.0, -st, ct]),
                rows([cp, 0.0, -sp], [0.0, 1.0, 0.0], [sp, 0.0, cp]),
            ),
            _ => (
                rows([ct, 0.0, -st], [0.0, 1.0, 0.0], [st, 0.0, ct]),
                rows([cp, sp, 0.0], [-sp, cp, 0.0], [0.0, 0.0, 1.0]),
            ),
        };
        let m = rt * rp;
        DAffine3::from_mat3_translation(m, m * self.offset)
    }
}

/// The transformation made by a list of cards with one name.
pub(crate) fn compose(cards: &[RotDefi]) -> DAffine3 {
    cards
        .iter()
        .fold(DAffine3::IDENTITY, |acc, c| c.affine() * acc)
}

impl super::Reader {
    /// Record a ROT-DEFI card under its name (SDUM) and index.
    pub(super) fn rotdefi(&mut self, i: usize, c: &Card) {
        let mut w = [0.0; 6];
        for (k, f) in c.what.iter().enumerate() {
            if let Some(f) = f {
                match card::number(&f.text) {
                    Some(v) => w[k] = v,
                    None => {
                        let (col, len) = (f.col, f.len());
                        self.err(
                            i,
                            col,
                            len,
                            format!(
                                "expected a number in ROT-DEFI WHAT({}), found `{}`",
                                k + 1,
                                f.text
                            ),
                        );
                        return;
                    }
                }
            }
        }
        let (index, axis) = match index_and_axis(w[0]) {
            Ok(x) => x,
            Err(j) => {
                let (col, len) = c.what[0].as_ref().map_or((1, 8), |f| (f.col, f.len()));
                self.err(
                    i,
                    col,
                    len,
                    format!("ROT-DEFI axis code j = {j} is not 1 (x), 2 (y) or 3 (z)"),
                )
                .hint = Some("WHAT(1) is i + 100 j below 1000 and j + 1000 i above".into());
                return;
            }
        };
        // FLUKA keeps an index for every transformation: a card without
        // one (WHAT(1) = 0) but with a name takes the first free index, and
        // a card without a name is called `ROT#index`, the name LATTICE and
        // `$start_transform` may use (or the bare index).
        let index = if index > 0 {
            index
        } else if c.sdum.is_some() {
            (1..).find(|k| !self.rot_index.contains_key(k)).unwrap_or(1)
        } else {
            return; // ignored by FLUKA too
        };
        let name = match &c.sdum {
            Some(s) => s.text.clone(),
            None => self
                .rot_index
                .get(&index)
                .cloned()
                .unwrap_or_else(|| format!("ROT#{index}")),
        };
        self.rot_index.entry(index).or_insert_with(|| name.clone());
        self.rot.entry(name).or_default().push(RotDefi {
            axis,
            polar: w[1],
            azimuth: w[2],
            offset: DVec3::new(w[3], w[4], w[5]),
        });
    }

    /// The transformation a LATTICE, VOXELS or `$start_transform` card
    /// names: a ROT-DEFI name, `ROT#n` or the index `n`, with a leading `-`
    /// for its inverse. `None` when no ROT-DEFI card defines it.
    pub(super) fn find_transform(&self, text: &str) -> Option<DAffine3> {
        let (inverse, name) = match text.strip_prefix('-') {
            Some(n) => (true, n),
            None => (false, text),
        };
        let cards = self.rot.get(name).or_else(|| {
            let index = name.strip_prefix("ROT#").unwrap_or(name);
            let index = card::number(index).filter(|v| v.fract() == 0.0 && *v >= 1.0)?;
            self.rot.get(self.rot_index.get(&(index.min(1e15) as i64))?)
        })?;
        let xf = compose(cards);
        Some(if inverse { xf.inverse() } else { xf })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn what1_encodings() {
        assert_eq!(index_and_axis(0.0), Ok((0, 3)));
        assert_eq!(index_and_axis(1.0), Ok((1, 3)));
        assert_eq!(index_and_axis(100.0), Ok((0, 1)));
        assert_eq!(index_and_axis(200.0), Ok((0, 2)));
        assert_eq!(index_and_axis(305.0), Ok((5, 3)));
        assert_eq!(index_and_axis(2001.0), Ok((2, 1)));
        assert_eq!(index_and_axis(500.0), Err(5));
    }

    #[test]
    fn azimuth_about_x_turns_y_towards_minus_z() {
        let r = RotDefi {
            axis: 1,
            polar: 0.0,
            azimuth: 90.0,
            offset: DVec3::ZERO,
        };
        let p = r.affine().transform_point3(DVec3::Y);
        assert!((p - DVec3::new(0.0, 0.0, -1.0)).length() < 1e-12);
    }

    #[test]
    fn offset_is_added_before_turning() {
        let r = RotDefi {
            axis: 3,
            polar: 0.0,
            azimuth: 90.0,
            offset: DVec3::new(1.0, 0.0, 0.0),
        };
        // (0,0,0) + (1,0,0) then x→(cφ, -sφ) = (0,-1,0).
        let p = r.affine().transform_point3(DVec3::ZERO);
        assert!((p - DVec3::new(0.0, -1.0, 0.0)).length() < 1e-12);
        let two = compose(&[
            RotDefi {
                axis: 3,
                polar: 0.0,
                azimuth: 0.0,
                offset: DVec3::X,
            },
            r,
        ]);
        assert!((two.transform_point3(DVec3::ZERO) - DVec3::new(0.0, -2.0, 0.0)).length() < 1e-12);
    }
}
