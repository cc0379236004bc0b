use glam::DVec3;

/// A ray `origin + t * dir`. The direction is kept unit length by
/// [`Ray::new`], so the parameter `t` is a distance in model units; the
/// boolean tolerances rely on that.
///
/// Laid out as nine `f64` in the order of the fields (`repr(C)`), so that a
/// list of rays can be read one coordinate across many rays at once.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct Ray {
    /// Start point.
    pub origin: DVec3,
    /// Unit direction.
    pub dir: DVec3,
    /// Component-wise reciprocal of `dir` (infinite where a component is 0).
    pub inv_dir: DVec3,
}

// `Ray::coordinates` reads a ray as nine `f64`.
const _: () = assert!(size_of::<Ray>() == 72 && align_of::<Ray>() == 8);

impl Ray {
    /// The rays' coordinates, nine per ray: origin, direction and its
    /// reciprocal.
    pub fn coordinates(rays: &[Ray]) -> &[f64] {
        // SAFETY: `Ray` is `repr(C)` with three `DVec3` fields, and a
        // `DVec3` is three `f64` without padding (glam lays it out as
        // `repr(C)` of its `x`, `y`, `z`), so the rays are `9 * len`
        // contiguous, aligned, initialised `f64`.
        unsafe { std::slice::from_raw_parts(rays.as_ptr().cast::<f64>(), rays.len() * 9) }
    }

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
