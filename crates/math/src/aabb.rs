use crate::Ray;
use glam::DVec3;

/// An axis-aligned bounding box. The empty box has `min > max`; unbounded
/// sides (half-spaces, infinite cylinders) are `±inf`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Aabb {
    /// Lower corner.
    pub min: DVec3,
    /// Upper corner.
    pub max: DVec3,
}

impl Aabb {
    /// The box that contains nothing.
    pub const EMPTY: Aabb = Aabb {
        min: DVec3::splat(f64::INFINITY),
        max: DVec3::splat(f64::NEG_INFINITY),
    };
    /// The box that contains everything.
    pub const INFINITE: Aabb = Aabb {
        min: DVec3::splat(f64::NEG_INFINITY),
        max: DVec3::splat(f64::INFINITY),
    };

    /// A box from its corners.
    pub fn new(min: DVec3, max: DVec3) -> Aabb {
        Aabb { min, max }
    }

    /// The smallest box holding every point.
    pub fn from_points<I: IntoIterator<Item = DVec3>>(pts: I) -> Aabb {
        pts.into_iter().fold(Aabb::EMPTY, |b, p| b.including(p))
    }

    /// True when the box holds no point.
    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x || self.min.y > self.max.y || self.min.z > self.max.z
    }

    /// True when every side is finite.
    pub fn is_finite(&self) -> bool {
        self.min.is_finite() && self.max.is_finite()
    }

    /// This box grown to hold `p`.
    pub fn including(&self, p: DVec3) -> Aabb {
        Aabb {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }

    /// The smallest box holding both.
    pub fn union(&self, o: &Aabb) -> Aabb {
        Aabb {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }

    /// The common part of both (possibly empty).
    pub fn intersection(&self, o: &Aabb) -> Aabb {
        Aabb {
            min: self.min.max(o.min),
            max: self.max.min(o.max),
        }
    }

    /// Centre point.
    pub fn center(&self) -> DVec3 {
        (self.min + self.max) * 0.5
    }

    /// Edge lengths.
    pub fn size(&self) -> DVec3 {
        self.max - self.min
    }

    /// Length of the diagonal.
    pub fn diagonal(&self) -> f64 {
        self.size().length()
    }

    /// Surface area (for the surface area heuristic).
    pub fn area(&self) -> f64 {
        if self.is_empty() {
            return 0.0;
        }
        let d = self.size();
        2.0 * (d.x * d.y + d.y * d.z + d.z * d.x)
    }

    /// True when `p` is inside or on the boundary.
    pub fn contains(&self, p: DVec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }

    /// This box widened by `d` on every side.
    pub fn padded(&self, d: f64) -> Aabb {
        Aabb {
            min: self.min - DVec3::splat(d),
            max: self.max + DVec3::splat(d),
        }
    }

    /// The parameter range `(t_enter, t_exit)` over which the line of the ray
    /// is inside the box, or `None` if it misses. The range is not clipped to
    /// `t >= 0`. Uses the slab method (Kay & Kajiya 1986) with the NaN-safe
    /// min/max ordering of Williams et al. 2005.
    pub fn ray_range(&self, ray: &Ray) -> Option<(f64, f64)> {
        let mut t0 = f64::NEG_INFINITY;
        let mut t1 = f64::INFINITY;
        for a in 0..3 {
            let o = ray.origin[a];
            let inv = ray.inv_dir[a];
            if ray.dir[a] == 0.0 {
                if o < self.min[a] || o > self.max[a] {
                    return None;
                }
                continue;
            }
            let mut ta = (self.min[a] - o) * inv;
            let mut tb = (self.max[a] - o) * inv;
            if ta > tb {
                std::mem::swap(&mut ta, &mut tb);
            }
            // Infinite slabs give NaN only for inf - inf, which the dir == 0
            // branch above excludes.
            t0 = t0.max(ta);
            t1 = t1.min(tb);
            if t0 > t1 {
                return None;
            }
        }
        Some((t0, t1))
    }
}
