use sv_math::{orthonormal_basis, Aabb, DVec3, Ray};

/// How the camera projects.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Lens {
    /// Pinhole with a vertical field of view in degrees.
    Fov {
        /// Vertical field of view, degrees.
        vertical_deg: f64,
    },
    /// Pinhole with a focal distance (pinhole to film) and the film's height,
    /// in the same units (the paper's variable-focal-length camera).
    Focal {
        /// Pinhole to film distance.
        focal: f64,
        /// Film height; the width follows from the raster's aspect ratio.
        film_height: f64,
    },
    /// Orthographic (parallel) projection showing `height` model units
    /// vertically (BRL-CAD's default view).
    Ortho {
        /// Visible height in model units.
        height: f64,
    },
}

/// A camera: eye point, viewing direction, up vector and lens.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye point (the pinhole).
    pub eye: DVec3,
    /// Viewing direction (need not be unit).
    pub dir: DVec3,
    /// Approximate up direction.
    pub up: DVec3,
    /// Projection.
    pub lens: Lens,
}

impl Default for Camera {
    fn default() -> Self {
        Camera {
            eye: DVec3::new(10.0, -10.0, 10.0),
            dir: DVec3::new(-1.0, 1.0, -1.0),
            up: DVec3::Z,
            lens: Lens::Fov { vertical_deg: 40.0 },
        }
    }
}

impl Camera {
    /// A camera at `eye` looking at `at`.
    pub fn looking_at(eye: DVec3, at: DVec3, up: DVec3, lens: Lens) -> Camera {
        Camera {
            eye,
            dir: at - eye,
            up,
            lens,
        }
    }

    /// Right, up and forward unit vectors of the image plane. When `up` is
    /// parallel to the view direction another up is chosen.
    pub fn basis(&self) -> (DVec3, DVec3, DVec3) {
        let f = self.dir.normalize();
        let mut r = f.cross(self.up);
        if r.length_squared() < 1e-20 {
            r = orthonormal_basis(f).0;
        }
        let r = r.normalize();
        let u = r.cross(f);
        (r, u, f)
    }

    /// Half the image height at unit distance (tangent of half the vertical
    /// field of view), for perspective lenses.
    pub fn tan_half_fov(&self) -> f64 {
        match self.lens {
            Lens::Fov { vertical_deg } => (vertical_deg.to_radians() / 2.0).tan(),
            Lens::Focal { focal, film_height } => film_height / (2.0 * focal),
            Lens::Ortho { .. } => 0.0,
        }
    }

    /// A ray generator for a `width`×`height` raster.
    pub fn rays(&self, width: u32, height: u32) -> RayGen {
        let (r, u, f) = self.basis();
        let aspect = width as f64 / height as f64;
        let (half_h, ortho) = match self.lens {
            Lens::Ortho { height } => (height / 2.0, true),
            _ => (self.tan_half_fov(), false),
        };
        // Every orthographic ray has the same direction: made once.
        let along = Ray::new(DVec3::ZERO, f);
        RayGen {
            eye: self.eye,
            right: r * (half_h * aspect),
            up: u * half_h,
            forward: f,
            along,
            ortho,
            inv_w: 1.0 / width as f64,
            inv_h: 1.0 / height as f64,
        }
    }
}

/// Makes the primary ray through any point of the raster.
#[derive(Clone, Copy, Debug)]
pub struct RayGen {
    eye: DVec3,
    right: DVec3,
    up: DVec3,
    forward: DVec3,
    /// The direction of orthographic rays (origin unused).
    along: Ray,
    ortho: bool,
    inv_w: f64,
    inv_h: f64,
}

impl RayGen {
    /// The ray through raster position (`x`, `y`), measured in pixels from
    /// the top-left corner (pixel centres are at `i + 0.5`).
    #[inline]
    pub fn ray(&self, x: f64, y: f64) -> Ray {
        let sx = 2.0 * x * self.inv_w - 1.0;
        let sy = 1.0 - 2.0 * y * self.inv_h;
        if self.ortho {
            // Exactly `Ray::new(origin, self.forward)`.
            Ray {
                origin: self.eye + self.right * sx + self.up * sy,
                ..self.along
            }
        } else {
            Ray::new(self.eye, self.forward + self.right * sx + self.up * sy)
        }
    }

    /// The raster column (`x`, in pixels from the left edge) where point
    /// `p` is seen, or `None` for a point not in front of a perspective
    /// camera. The inverse of [`RayGen::ray`] up to rounding.
    pub fn raster_x(&self, p: DVec3) -> Option<f64> {
        let q = p - self.eye;
        let mut sx = q.dot(self.right) / self.right.length_squared();
        if !self.ortho {
            let z = q.dot(self.forward);
            if z <= 0.0 || z.is_nan() {
                return None;
            }
            sx /= z;
        }
        Some((sx + 1.0) / (2.0 * self.inv_w))
    }

    /// The raster columns (`x`, in pixels from the left edge) between
    /// which a box may be seen, or `None` when it reaches to or behind the
    /// plane of a perspective camera's eye. Conservative up to rounding:
    /// the box's extent across and along the view, in the camera's frame,
    /// bounds the columns of its corners.
    pub fn raster_x_span(&self, b: &Aabb) -> Option<(f64, f64)> {
        let across = self.right / self.right.length_squared();
        let (c, e) = (b.center() - self.eye, b.size() * 0.5);
        let (x, ex) = (c.dot(across), e.dot(across.abs()));
        let (x0, x1) = if self.ortho {
            (x - ex, x + ex)
        } else {
            let (z, ez) = (c.dot(self.forward), e.dot(self.forward.abs()));
            let (near, far) = (z - ez, z + ez);
            if near <= 0.0 || near.is_nan() {
                return None;
            }
            // The least and greatest of x / z over the box's (x, z) range.
            let lo = x - ex;
            let hi = x + ex;
            (
                lo / if lo >= 0.0 { far } else { near },
                hi / if hi >= 0.0 { near } else { far },
            )
        };
        let to_raster = |sx: f64| (sx + 1.0) / (2.0 * self.inv_w);
        Some((to_raster(x0), to_raster(x1)))
    }

    /// The rays through many raster positions, appended to `out`: exactly
    /// what [`RayGen::ray`] makes for each, but made eight at a time so
    /// that the square roots and divisions of perspective rays run as
    /// vector instructions.
    pub fn rays(&self, pts: &[[f64; 2]], out: &mut Vec<Ray>) {
        const N: usize = 8;
        if self.ortho {
            out.extend(pts.iter().map(|&[x, y]| self.ray(x, y)));
            return;
        }
        for chunk in pts.chunks(N) {
            // The same operations in the same order as `ray`, `Ray::new`
            // and glam's `normalize` and `recip`, one lane per ray.
            let (mut dx, mut dy, mut dz) = ([0.0; N], [0.0; N], [0.0; N]);
            for (k, &[x, y]) in chunk.iter().enumerate() {
                let sx = 2.0 * x * self.inv_w - 1.0;
                let sy = 1.0 - 2.0 * y * self.inv_h;
                let d = self.forward + self.right * sx + self.up * sy;
                (dx[k], dy[k], dz[k]) = (d.x, d.y, d.z);
            }
            let mut r = [0.0; N];
            for k in 0..N {
                r[k] = 1.0 / ((dx[k] * dx[k]) + (dy[k] * dy[k]) + (dz[k] * dz[k])).sqrt();
            }
            let mut inv = [[0.0; N]; 3];
            for k in 0..N {
                (dx[k], dy[k], dz[k]) = (dx[k] * r[k], dy[k] * r[k], dz[k] * r[k]);
                inv[0][k] = 1.0 / dx[k];
                inv[1][k] = 1.0 / dy[k];
                inv[2][k] = 1.0 / dz[k];
            }
            out.extend((0..chunk.len()).map(|k| Ray {
                origin: self.eye,
                dir: DVec3::new(dx[k], dy[k], dz[k]),
                inv_dir: DVec3::new(inv[0][k], inv[1][k], inv[2][k]),
            }));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rays_made_together_equal_rays_made_one_by_one() {
        for lens in [
            Lens::Fov { vertical_deg: 37.0 },
            Lens::Ortho { height: 3.0 },
        ] {
            let cam = Camera::looking_at(
                DVec3::new(-3.0, 7.0, 2.5),
                DVec3::new(0.3, -0.2, 0.1),
                DVec3::Z,
                lens,
            );
            let g = cam.rays(640, 480);
            let pts: Vec<[f64; 2]> = (0..37)
                .map(|i| [i as f64 * 17.3 + 0.5, 479.5 - i as f64 * 11.1])
                .collect();
            let mut got = Vec::new();
            g.rays(&pts, &mut got);
            let want: Vec<Ray> = pts.iter().map(|&[x, y]| g.ray(x, y)).collect();
            assert_eq!(got, want);
        }
    }

    #[test]
    fn a_point_on_the_ray_through_a_column_is_seen_in_that_column() {
        for lens in [
            Lens::Fov { vertical_deg: 37.0 },
            Lens::Ortho { height: 3.0 },
        ] {
            let cam = Camera::looking_at(
                DVec3::new(-3.0, 7.0, 2.5),
                DVec3::new(0.3, -0.2, 0.1),
                DVec3::Z,
                lens,
            );
            let g = cam.rays(640, 480);
            for i in 0..50 {
                let (x, y) = (i as f64 * 13.7 - 20.0, 479.0 - i as f64 * 9.3);
                let r = g.ray(x, y);
                for t in [0.5, 3.0, 40.0] {
                    let got = g.raster_x(r.at(t)).expect("in front of the eye");
                    assert!((got - x).abs() < 1e-6, "{lens:?}: {got} for {x}");
                }
                if matches!(lens, Lens::Fov { .. }) {
                    assert_eq!(g.raster_x(r.at(-1.0)), None);
                }
            }
        }
    }

    #[test]
    fn centre_pixel_looks_along_the_view_direction_and_corners_span_the_fov() {
        let cam = Camera::looking_at(
            DVec3::ZERO,
            DVec3::new(0.0, 10.0, 0.0),
            DVec3::Z,
            Lens::Fov { vertical_deg: 90.0 },
        );
        let g = cam.rays(200, 100);
        let c = g.ray(100.0, 50.0);
        assert!((c.dir - DVec3::Y).length() < 1e-12);
        let top = g.ray(100.0, 0.0);
        assert!(
            (top.dir.z - top.dir.y).abs() < 1e-12,
            "45 degrees up: {:?}",
            top.dir
        );
        let focal = Camera {
            lens: Lens::Focal {
                focal: 1.0,
                film_height: 2.0,
            },
            ..cam
        };
        assert!((focal.tan_half_fov() - 1.0).abs() < 1e-12);
    }
}
