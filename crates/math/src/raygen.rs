//! The primary rays of a camera's raster.

use crate::Ray;
use glam::DVec3;

/// Makes the primary ray through any point of the raster of a camera
/// (`Camera::rays` in the scene crate makes one).
///
/// The fields are what [`RayGen::ray`] computes with; code that makes rays
/// several at a time reads them to compute the same values.
#[derive(Clone, Copy, Debug)]
pub struct RayGen {
    /// The eye (perspective), or the centre of the view's plane (orthographic).
    pub eye: DVec3,
    /// Half the raster's width along the image plane's right-hand axis, at
    /// unit distance (perspective) or in model units (orthographic).
    pub right: DVec3,
    /// Half the raster's height along its up axis, likewise.
    pub up: DVec3,
    /// The unit view direction.
    pub forward: DVec3,
    /// The direction of orthographic rays (origin unused).
    pub along: Ray,
    /// Orthographic rather than perspective.
    pub ortho: bool,
    /// One over the raster's width and height in pixels.
    pub inv_w: f64,
    /// See `inv_w`.
    pub inv_h: f64,
    /// For [`RayGen::ball_rect`], which places every ball of a model on
    /// the raster in every frame: one over the lengths of `right` and
    /// `up`, and half the raster's width and height in pixels.
    inv_len: [f64; 2],
    half: [f64; 2],
}

impl RayGen {
    /// The generator of a `width`×`height` raster through the image plane
    /// spanned by `right` and `up` (half sizes) about `forward`.
    pub fn new(
        eye: DVec3,
        right: DVec3,
        up: DVec3,
        forward: DVec3,
        ortho: bool,
        width: u32,
        height: u32,
    ) -> RayGen {
        RayGen {
            eye,
            right,
            up,
            forward,
            // Every orthographic ray has the same direction: made once.
            along: Ray::new(DVec3::ZERO, forward),
            ortho,
            inv_w: 1.0 / width as f64,
            inv_h: 1.0 / height as f64,
            inv_len: [1.0 / right.length(), 1.0 / up.length()],
            half: [0.5 * width as f64, 0.5 * height as f64],
        }
    }

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

    /// Where point `p` is seen on the raster, `(x, y)` in pixels from the
    /// top-left corner, or `None` for a point not in front of a
    /// perspective camera. The inverse of [`RayGen::ray`] up to rounding.
    pub fn raster(&self, p: DVec3) -> Option<(f64, f64)> {
        let q = p - self.eye;
        let mut sx = q.dot(self.right) / self.right.length_squared();
        let mut sy = q.dot(self.up) / self.up.length_squared();
        if !self.ortho {
            let z = q.dot(self.forward);
            if z <= 0.0 || z.is_nan() {
                return None;
            }
            (sx, sy) = (sx / z, sy / z);
        }
        Some(self.raster_of(sx, sy))
    }

    /// The raster position of image-plane coordinates `(sx, sy)` (each −1
    /// to 1 across the raster), as [`RayGen::ray`] maps them.
    fn raster_of(&self, sx: f64, sy: f64) -> (f64, f64) {
        (
            (sx + 1.0) / (2.0 * self.inv_w),
            (1.0 - sy) / (2.0 * self.inv_h),
        )
    }

    /// The smallest rectangle of the raster, `[x0, y0, x1, y1]`, that holds
    /// where the points are seen, or `None` when one of them is not in
    /// front of a perspective camera.
    pub fn raster_rect(&self, pts: impl IntoIterator<Item = DVec3>) -> Option<[f64; 4]> {
        let mut r = [
            f64::INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        ];
        for p in pts {
            let (x, y) = self.raster(p)?;
            r = [r[0].min(x), r[1].min(y), r[2].max(x), r[3].max(y)];
        }
        Some(r)
    }

    /// The rectangle of the raster, `[x0, y0, x1, y1]`, around where the
    /// ball of centre `c` and radius `r` is seen (up to rounding: its
    /// outline's tangents through the eye), or `None` when the ball reaches
    /// to or behind the plane of a perspective camera's eye.
    pub fn ball_rect(&self, c: DVec3, r: f64) -> Option<[f64; 4]> {
        // Multiplications where `raster` divides: a few units of rounding
        // in the last place, for 4 divisions instead of 14.
        let q = c - self.eye;
        let [ir, iu] = self.inv_len;
        let (x, y) = (q.dot(self.right) * ir, q.dot(self.up) * iu);
        let ((x0, x1), (y0, y1)) = if self.ortho {
            ((x - r, x + r), (y - r, y + r))
        } else {
            let z = q.dot(self.forward);
            if z - r <= 0.0 || (z - r).is_nan() {
                return None;
            }
            // The slopes of the tangents from the eye to the disc the ball
            // casts on the plane of the view and one image axis.
            let slopes = |a: f64| {
                let s = (a * a + z * z - r * r).sqrt();
                (
                    (a * s - r * z) / (z * s + r * a),
                    (a * s + r * z) / (z * s - r * a),
                )
            };
            (slopes(x), slopes(y))
        };
        // To the image plane's units: the right and up vectors' lengths are
        // half the raster's width and height there.
        let [hw, hh] = self.half;
        Some([
            (x0 * ir + 1.0) * hw,
            (1.0 - y1 * iu) * hh,
            (x1 * ir + 1.0) * hw,
            (1.0 - y0 * iu) * hh,
        ])
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
