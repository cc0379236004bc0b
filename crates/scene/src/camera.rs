use sv_math::{orthonormal_basis, DVec3, RayGen};

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
        RayGen::new(
            self.eye,
            r * (half_h * aspect),
            u * half_h,
            f,
            ortho,
            width,
            height,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sv_math::Ray;

    /// A perspective and an orthographic view of the same scene, 640×480.
    fn views() -> [(Lens, RayGen); 2] {
        [
            Lens::Fov { vertical_deg: 37.0 },
            Lens::Ortho { height: 3.0 },
        ]
        .map(|lens| {
            let cam = Camera::looking_at(
                DVec3::new(-3.0, 7.0, 2.5),
                DVec3::new(0.3, -0.2, 0.1),
                DVec3::Z,
                lens,
            );
            (lens, cam.rays(640, 480))
        })
    }

    #[test]
    fn rays_made_together_equal_rays_made_one_by_one() {
        for (_, g) in views() {
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
    fn a_point_on_the_ray_through_a_pixel_is_seen_there() {
        for (lens, g) in views() {
            for i in 0..50 {
                let (x, y) = (i as f64 * 13.7 - 20.0, 479.0 - i as f64 * 9.3);
                let r = g.ray(x, y);
                for t in [0.5, 3.0, 40.0] {
                    let (gx, gy) = g.raster(r.at(t)).expect("in front of the eye");
                    assert!(
                        (gx - x).abs() < 1e-6 && (gy - y).abs() < 1e-6,
                        "{lens:?}: ({gx}, {gy}) for ({x}, {y})"
                    );
                }
                if matches!(lens, Lens::Fov { .. }) {
                    assert_eq!(g.raster(r.at(-1.0)), None);
                }
            }
        }
    }

    #[test]
    fn a_balls_rectangle_holds_its_outline_and_no_more() {
        for lens in [
            Lens::Fov { vertical_deg: 50.0 },
            Lens::Ortho { height: 8.0 },
        ] {
            let cam = Camera::looking_at(DVec3::new(-9.0, 4.0, 3.0), DVec3::ZERO, DVec3::Z, lens);
            let g = cam.rays(640, 480);
            for (c, r) in [
                (DVec3::ZERO, 1.0),
                (DVec3::new(1.0, -3.0, 2.0), 0.4),
                (DVec3::new(-4.0, 3.0, -1.0), 2.0),
            ] {
                let rect = g.ball_rect(c, r).expect("in front of the eye");
                // Points on the sphere lie inside; the rectangle's sides
                // are reached.
                let mut seen = [
                    f64::INFINITY,
                    f64::INFINITY,
                    f64::NEG_INFINITY,
                    f64::NEG_INFINITY,
                ];
                for i in 0..200 {
                    for j in 0..100 {
                        let step = std::f64::consts::PI / 100.0;
                        let (a, e) = (
                            i as f64 * step,
                            -std::f64::consts::FRAC_PI_2 + j as f64 * step,
                        );
                        let p = c + DVec3::new(e.cos() * a.cos(), e.cos() * a.sin(), e.sin()) * r;
                        let (x, y) = g.raster(p).unwrap();
                        assert!(
                            x >= rect[0] - 1e-6 && x <= rect[2] + 1e-6,
                            "{x} outside {rect:?}"
                        );
                        assert!(
                            y >= rect[1] - 1e-6 && y <= rect[3] + 1e-6,
                            "{y} outside {rect:?}"
                        );
                        seen = [
                            seen[0].min(x),
                            seen[1].min(y),
                            seen[2].max(x),
                            seen[3].max(y),
                        ];
                    }
                }
                for k in 0..4 {
                    assert!(
                        (seen[k] - rect[k]).abs() < 0.5,
                        "{lens:?}: {seen:?} against {rect:?}"
                    );
                }
            }
            // A ball around the eye is seen everywhere.
            if matches!(lens, Lens::Fov { .. }) {
                assert_eq!(g.ball_rect(cam.eye, 0.5), None);
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
