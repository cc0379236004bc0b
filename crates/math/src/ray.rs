use glam::DVec3;

/// A ray `origin + t * dir`. The direction is kept unit length by
/// [`Ray::new`], so the parameter `t` is a distance in model units; the
/// boolean tolerances rely on that.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Start point.
    pub origin: DVec3,
    /// Unit direction.
    pub dir: DVec3,
    /// Component-wise reciprocal of `dir` (infinite where a component is 0).
    pub inv_dir: DVec3,
}

impl Ray {
    /// A ray from `origin` along `dir`, normalised. A zero direction gives a
    /// ray whose direction is NaN; callers validate user directions first.
    pub fn new(origin: DVec3, dir: DVec3) -> Ray {
        let dir = dir.normalize();
        Ray {
            origin,
            dir,
            inv_dir: dir.recip(),
        }
    }

    /// The point at parameter `t`.
    #[inline]
    pub fn at(&self, t: f64) -> DVec3 {
        self.origin + self.dir * t
    }
}
