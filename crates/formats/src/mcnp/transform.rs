//! MCNP transformations (`TRn`, `*TRn`, `TRCL`, the fill's own): a
//! displacement `O1 O2 O3`, up to nine matrix entries `B1…B9` and `M`.
//!
//! `B1 B2 B3` are the cosines between the main axes and the auxiliary x'
//! axis (x' written in main coordinates), `B4 B5 B6` the y' axis and
//! `B7 B8 B9` the z' axis; a starred card gives the angles in degrees. With
//! `M = 1` (the default) `O` is the auxiliary origin in main coordinates,
//! so a point `p'` of the auxiliary system is `O + Q p'` in the main one,
//! `Q` having the axes as columns; with `M = −1`, `O` is the main origin
//! in auxiliary coordinates and the point is `Q (p' − O)`.
//!
//! As MCNP does, a matrix may be given in part: nothing (no rotation),
//! one axis (the other two are any that complete it), one axis of each
//! system (5 entries, sharing one), or two axes (the third is their cross
//! product); `J` jumps over the entries not given. A matrix a little off
//! orthonormal (to 10⁻³) is made orthonormal, as MCNP does; more is an
//! error.

use sv_math::{orthonormal_basis, DAffine3, DMat3, DVec3};

/// How far from orthonormal a given matrix may be.
const TOLERANCE: f64 = 1e-3;

/// The transformation `values` give (`None` for entries jumped over),
/// taking auxiliary coordinates to main ones.
pub(crate) fn affine(values: &[Option<f64>], degrees: bool) -> Result<DAffine3, String> {
    if values.len() > 13 {
        return Err(format!(
            "a transformation has at most 13 entries (3 for the displacement, 9 for the matrix and M), not {}",
            values.len()
        ));
    }
    let get = |i: usize| values.get(i).copied().flatten();
    let origin = DVec3::new(
        get(0).unwrap_or(0.0),
        get(1).unwrap_or(0.0),
        get(2).unwrap_or(0.0),
    );
    let mut rows = [[None; 3]; 3];
    for (k, row) in rows.iter_mut().enumerate() {
        for (l, cell) in row.iter_mut().enumerate() {
            *cell = get(3 + 3 * k + l).map(|v| if degrees { v.to_radians().cos() } else { v });
        }
    }
    let axes = orthonormal(complete(rows)?)?;
    let q = DMat3::from_cols(axes[0], axes[1], axes[2]);
    let translation = match get(12) {
        None | Some(1.0) => origin,
        Some(-1.0) => -(q * origin),
        Some(m) => return Err(format!("the last entry (M) must be 1 or -1, not {m}")),
    };
    Ok(DAffine3::from_mat3_translation(q, translation))
}

type Rows = [[Option<f64>; 3]; 3];

fn full(r: &[Option<f64>; 3]) -> Option<DVec3> {
    Some(DVec3::new(r[0]?, r[1]?, r[2]?))
}

fn transpose(r: &Rows) -> Rows {
    let mut t = [[None; 3]; 3];
    for (k, row) in r.iter().enumerate() {
        for (l, v) in row.iter().enumerate() {
            t[l][k] = *v;
        }
    }
    t
}

fn from_vectors(v: [DVec3; 3]) -> Rows {
    v.map(|r| [Some(r.x), Some(r.y), Some(r.z)])
}

/// The rows of the matrix, the missing entries worked out.
fn complete(rows: Rows) -> Result<[DVec3; 3], String> {
    let given = rows.iter().flatten().filter(|v| v.is_some()).count();
    let full_rows: Vec<usize> = (0..3).filter(|&k| full(&rows[k]).is_some()).collect();
    let cols = transpose(&rows);
    let full_cols: Vec<usize> = (0..3).filter(|&k| full(&cols[k]).is_some()).collect();
    let rows_of =
        |r: &Rows| -> [DVec3; 3] { [0, 1, 2].map(|k| full(&r[k]).unwrap_or(DVec3::ZERO)) };
    match given {
        0 => Ok([DVec3::X, DVec3::Y, DVec3::Z]),
        9 => Ok(rows_of(&rows)),
        6 | 3 if full_rows.len() * 3 == given => Ok(fill_rows(&rows, &full_rows)),
        6 | 3 if full_cols.len() * 3 == given => {
            let t = fill_rows(&cols, &full_cols);
            Ok(rows_of(&transpose(&from_vectors(t))))
        }
        5 if full_rows.len() == 1 && full_cols.len() == 1 => {
            Ok(row_and_column(&rows, full_rows[0], full_cols[0]))
        }
        _ => Err(format!(
            "the rotation matrix gives {given} entries: give 9, two axes (6), one axis of each system (5), one axis (3) or none"
        )),
    }
}

/// Rows `given` are known (one or two); the others complete a
/// right-handed frame.
fn fill_rows(rows: &Rows, given: &[usize]) -> [DVec3; 3] {
    let mut out = [DVec3::ZERO; 3];
    for &k in given {
        out[k] = full(&rows[k]).unwrap_or(DVec3::ZERO);
    }
    let k = given[0];
    let (next, last) = ((k + 1) % 3, (k + 2) % 3);
    if given.len() == 1 {
        let (u, _) = orthonormal_basis(out[k].normalize_or_zero());
        out[next] = u;
        out[last] = out[k].cross(u);
    } else {
        let missing = (0..3).find(|m| !given.contains(m)).unwrap_or(0);
        out[missing] = out[(missing + 1) % 3].cross(out[(missing + 2) % 3]);
    }
    out
}

/// Row `i` and column `j` are known: the rest of a rotation, found with
/// both rolled to row 0 and column 0 (cyclic rolls keep the handedness).
fn row_and_column(rows: &Rows, i: usize, j: usize) -> [DVec3; 3] {
    let at = |a: usize, b: usize| rows[(a + i) % 3][(b + j) % 3].unwrap_or(0.0);
    let (a, b, c) = (at(0, 0), at(0, 1), at(0, 2));
    let (d, g) = (at(1, 0), at(2, 0));
    let row0 = DVec3::new(a, b, c);
    // Row 1 is (d, e, f), at right angles to row 0, and row 0 × row 1 (row
    // 2) starts with g: b e + c f = −a d and −c e + b f = g.
    let s = b * b + c * c;
    let row1 = if s > 1e-12 {
        DVec3::new(d, (-a * d * b - c * g) / s, (-a * d * c + b * g) / s)
    } else {
        DVec3::new(0.0, 1.0, 0.0)
    };
    let row2 = row0.cross(row1);
    let rolled = [row0, row1, row2];
    let mut out = [DVec3::ZERO; 3];
    for (a, row) in rolled.iter().enumerate() {
        for b in 0..3 {
            out[(a + i) % 3][(b + j) % 3] = row[b];
        }
    }
    out
}

/// The rows made orthonormal, or why they are too far from it.
fn orthonormal(rows: [DVec3; 3]) -> Result<[DVec3; 3], String> {
    let m = DMat3::from_cols(rows[0], rows[1], rows[2]);
    let skew = (m.transpose() * m - DMat3::IDENTITY)
        .to_cols_array()
        .iter()
        .fold(0.0f64, |a, v| a.max(v.abs()));
    if !skew.is_finite() || skew > TOLERANCE {
        return Err(format!(
            "the rotation matrix is not orthonormal (off by {skew:.3e}; MCNP allows {TOLERANCE})"
        ));
    }
    let x = rows[0].normalize();
    let y = (rows[1] - x * rows[1].dot(x)).normalize();
    let z = x.cross(y);
    if z.dot(rows[2]) <= 0.0 {
        return Err("the matrix is a reflection (its determinant is -1), not a rotation".into());
    }
    Ok([x, y, z])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: DVec3, b: DVec3) -> bool {
        (a - b).length() < 1e-9
    }

    #[test]
    fn displacement_and_rotation() {
        // x' along main y, y' along -x: a quarter turn about z.
        let v = [1.0, 2.0, 3.0, 0.0, 1.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 1.0];
        let xf = affine(&v.map(Some), false).unwrap();
        assert!(close(
            xf.transform_point3(DVec3::X),
            DVec3::new(1.0, 3.0, 3.0)
        ));
        let back = affine(&[v.map(Some).to_vec(), vec![Some(-1.0)]].concat(), false).unwrap();
        assert!(close(
            back.transform_point3(DVec3::new(1.0, 2.0, 3.0)),
            DVec3::ZERO
        ));
        let deg = [
            0.0, 0.0, 0.0, 90.0, 0.0, 90.0, 180.0, 90.0, 90.0, 90.0, 90.0, 0.0,
        ];
        let xf2 = affine(&deg.map(Some), true).unwrap();
        assert!(close(xf2.transform_point3(DVec3::X), DVec3::Y));
    }

    #[test]
    fn partial_matrices_are_completed() {
        let rot = DMat3::from_rotation_z(0.3) * DMat3::from_rotation_x(0.7);
        let rows: Vec<f64> = rot.transpose().to_cols_array().to_vec(); // rows of Qᵀ = axes
        let mut v: Vec<Option<f64>> = vec![Some(0.0); 3];
        v.extend(rows.iter().map(|x| Some(*x)));
        let want = affine(&v, false).unwrap();
        // Two axes given, the third jumped over.
        let mut six = v.clone();
        for e in &mut six[9..12] {
            *e = None;
        }
        assert!(affine(&six, false).unwrap().abs_diff_eq(want, 1e-9));
        // One axis and one column.
        let mut five = v.clone();
        for k in [7, 8, 10, 11] {
            five[k] = None;
        }
        assert!(affine(&five, false).unwrap().abs_diff_eq(want, 1e-9));
        let mut four = five.clone();
        four[3] = None;
        assert!(affine(&four, false).is_err());
        assert!(affine(&[Some(0.0); 12], false).is_err());
    }
}
