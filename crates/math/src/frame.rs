use glam::{DAffine3, DMat3, DVec3};

/// Two unit vectors `u`, `v` such that `(u, v, n)` is a right-handed
/// orthonormal basis, for a unit `n` (Duff et al. 2017, "Building an
/// orthonormal basis, revisited").
pub fn orthonormal_basis(n: DVec3) -> (DVec3, DVec3) {
    let sign = 1.0_f64.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    let u = DVec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    let v = DVec3::new(b, sign + n.y * n.y * a, -n.y);
    (u, v)
}

/// The rigid transform turning by `degrees` about the line through `point`
/// along `axis` (right-hand rule).
pub fn rotation_about_axis(point: DVec3, axis: DVec3, degrees: f64) -> DAffine3 {
    let rot = DMat3::from_axis_angle(axis.normalize(), degrees.to_radians());
    DAffine3::from_translation(point)
        * DAffine3::from_mat3(rot)
        * DAffine3::from_translation(-point)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn basis_is_orthonormal_for_awkward_normals() {
        for n in [
            DVec3::Z,
            -DVec3::Z,
            DVec3::X,
            DVec3::new(1.0, 2.0, -3.0).normalize(),
        ] {
            let (u, v) = orthonormal_basis(n);
            assert!((u.length() - 1.0).abs() < 1e-12);
            assert!((v.length() - 1.0).abs() < 1e-12);
            assert!(u.dot(v).abs() < 1e-12 && u.dot(n).abs() < 1e-12);
            assert!((u.cross(v) - n).length() < 1e-12);
        }
    }

    #[test]
    fn rotation_about_offset_axis_moves_points_on_circle() {
        let xf = rotation_about_axis(DVec3::new(1.0, 0.0, 0.0), DVec3::Z, 90.0);
        let p = xf.transform_point3(DVec3::new(2.0, 0.0, 5.0));
        assert!((p - DVec3::new(1.0, 1.0, 5.0)).length() < 1e-12);
    }
}
