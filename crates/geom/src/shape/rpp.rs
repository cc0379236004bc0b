use super::Seg;
use sv_math::{Aabb, DVec3, Ray};

/// An axis-aligned box (RPP), cast by the slab method with the faces
/// crossed tracked. Faces: 0 −x, 1 +x, 2 −y, 3 +y, 4 −z, 5 +z.
#[derive(Clone, Debug)]
pub struct Rpp {
    b: Aabb,
}

impl Rpp {
    /// The box.
    pub fn new(b: Aabb) -> Rpp {
        Rpp { b }
    }

    #[inline]
    pub(crate) fn shoot(&self, ray: &Ray, out: &mut Vec<Seg>) {
        let (mut t0, mut t1) = (f64::NEG_INFINITY, f64::INFINITY);
        let (mut f0, mut f1) = (0u32, 0u32);
        for a in 0..3 {
            let (o, d) = (ray.origin[a], ray.dir[a]);
            if d == 0.0 {
                // Parallel: inside the slab or a miss (the boundary counts
                // as outside, as for the general polyhedron's `dist < 0`).
                if o < self.b.min[a] || o > self.b.max[a] {
                    return;
                }
                continue;
            }
            let inv = ray.inv_dir[a];
            let (lo, hi) = ((self.b.min[a] - o) * inv, (self.b.max[a] - o) * inv);
            let (near, far, fn_, ff) = if d > 0.0 {
                (lo, hi, 2 * a as u32, 2 * a as u32 + 1)
            } else {
                (hi, lo, 2 * a as u32 + 1, 2 * a as u32)
            };
            if near > t0 {
                t0 = near;
                f0 = fn_;
            }
            if far < t1 {
                t1 = far;
                f1 = ff;
            }
            if t0 > t1 {
                return;
            }
        }
        if t0 < t1 {
            out.push(Seg { t0, t1, f0, f1 });
        }
    }

    pub(crate) fn normal(&self, face: u32) -> DVec3 {
        let mut n = DVec3::ZERO;
        n[(face / 2) as usize] = if face.is_multiple_of(2) { -1.0 } else { 1.0 };
        n
    }

    pub(crate) fn contains(&self, p: DVec3) -> bool {
        p.cmpgt(self.b.min).all() && p.cmplt(self.b.max).all()
    }

    pub(crate) fn bounds(&self) -> Aabb {
        self.b
    }
}
