//! Which zones a bundle of rays may meet: a tile's frustum tested against
//! the zones' boxes and enclosures, where a zone may be seen on a raster,
//! and the zones in a box (shadow rays toward a point light).

use crate::bvh::Bvh;
use crate::prepare::{EnclosureRef, Prepared};
use crate::raster::rect_of;
use sv_math::{Aabb, DVec3, Ray, RayGen};

impl Prepared {
    /// The opaque zones that the frustum may meet (their bounds, and the
    /// ball or hull points found for each when prepared), in hierarchy order
    /// (unbounded zones first). Gives up and returns false as soon as there
    /// are more than `max`: the rays had better walk the hierarchy then.
    pub fn frustum_zones(&self, f: &Frustum, max: usize, out: &mut Vec<u32>) -> bool {
        self.zones_meeting(
            max,
            out,
            |b| f.may_meet(b),
            // A zone whose box the frustum meets may still lie beside it:
            // the frustum can pass a box's corner and miss the ball inside,
            // or a rotor blade set at an angle across its box. Only the
            // zones left count toward `max`.
            |zi| self.enclosure_meets(zi, f),
        )
    }

    /// True when [`Prepared::frustum_zones`] would list bounded zone `zi`
    /// for frustum `f`: its box, then its ball or hull points, may meet it.
    pub fn frustum_keeps(&self, zi: u32, f: &Frustum) -> bool {
        f.may_meet(&self.zones[zi as usize].bounds) && self.enclosure_meets(zi, f)
    }

    /// The test of a zone's ball or hull points against a frustum.
    fn enclosure_meets(&self, zi: u32, f: &Frustum) -> bool {
        match self.enclosure(zi) {
            EnclosureRef::Box => true,
            EnclosureRef::Ball(c, r) => f.may_meet_ball(c, r),
            EnclosureRef::Points(pts) => f.may_meet_points(pts),
        }
    }

    /// Where bounded zone `zi` may be seen on the raster of `gen`: within
    /// the rectangle around its box, narrowed to that around its ball or
    /// hull points where it has them (up to rounding: pad it); nowhere when
    /// it lies wholly behind the plane of the eye (or, orthographic, of the
    /// rays' origins); anywhere when neither its box nor its ball or hull
    /// lies wholly in front of a perspective camera's eye. For a zone in
    /// front of the eye this is [`Prepared::frustum_zones`]' test of a
    /// tile's frustum, plane by plane, turned around: a box, ball or hull
    /// lies wholly outside a plane through the eye and a tile's edge
    /// exactly when its rectangle lies beyond that edge.
    pub fn zone_rect(&self, zi: u32, gen: &RayGen) -> RasterExtent {
        rect_of(&self.zones[zi as usize].bounds, self.enclosure(zi), gen)
    }

    /// The zones of opaque regions that have no finite bounds (they lead
    /// every list of [`Prepared::frustum_zones`], untested).
    pub fn unbounded_opaque(&self) -> &[u32] {
        &self.unbounded_opaque
    }

    /// The opaque zones whose bounds pass `meets` and that then pass `keep`
    /// (unbounded zones always), walking the hierarchy through the nodes
    /// whose bounds pass `meets`; false (and given up) past `max`.
    fn zones_meeting(
        &self,
        max: usize,
        out: &mut Vec<u32>,
        meets: impl Fn(&Aabb) -> bool,
        keep: impl Fn(u32) -> bool,
    ) -> bool {
        self.zones_of(
            (&self.bvh_opaque, &self.unbounded_opaque),
            max,
            out,
            meets,
            keep,
        )
    }

    /// [`Prepared::zones_meeting`] over the hierarchy `bvh` and the
    /// unbounded zones `unbounded`.
    fn zones_of(
        &self,
        (bvh, unbounded): (&Bvh, &[u32]),
        max: usize,
        out: &mut Vec<u32>,
        meets: impl Fn(&Aabb) -> bool,
        keep: impl Fn(u32) -> bool,
    ) -> bool {
        out.clear();
        out.extend_from_slice(unbounded);
        let nodes = &bvh.nodes;
        let mut stack = [0u32; 64];
        let mut sp = usize::from(!nodes.is_empty());
        while sp > 0 {
            sp -= 1;
            let node = nodes[stack[sp] as usize];
            if !meets(&node.bounds) {
                continue;
            }
            if node.count > 0 {
                let items = &bvh.items[node.first as usize..(node.first + node.count) as usize];
                out.extend(
                    items
                        .iter()
                        .copied()
                        .filter(|&zi| meets(&self.zones[zi as usize].bounds) && keep(zi)),
                );
            } else if sp + 2 <= stack.len() {
                stack[sp] = node.first + 1;
                stack[sp + 1] = node.first;
                sp += 2;
            } else {
                // Deeper than the stack: let the rays walk the hierarchy.
                return false;
            }
            if out.len() > max {
                return false;
            }
        }
        out.len() <= max
    }

    /// The opaque zones whose bounds meet the box `from`. A shadow ray
    /// toward a point light from any point of `from` can only meet these
    /// when `from` holds both the points and the light. Gives up past
    /// `max`. (Shadow rays toward parallel lights use a
    /// [`crate::LightBuffer`].)
    pub fn zones_in_box(&self, from: &Aabb, max: usize, out: &mut Vec<u32>) -> bool {
        let near = from.padded(self.tol);
        self.zones_meeting(max, out, |b| !b.intersection(&near).is_empty(), |_| true)
    }

    /// The zones of every region, transparent ones too, whose bounds meet
    /// the box `from` (unbounded zones first): the list
    /// [`Prepared::partitions_in`] needs for rays that cross `from` within
    /// their range. False when the hierarchy is too deep to list them
    /// (use [`Prepared::partitions`] then).
    pub fn all_zones_in_box(&self, from: &Aabb, out: &mut Vec<u32>) -> bool {
        let near = from.padded(self.tol);
        self.zones_of(
            (&self.bvh_all, &self.unbounded_all),
            usize::MAX,
            out,
            |b| !b.intersection(&near).is_empty(),
            |_| true,
        )
    }
}

/// Where a zone may be seen on a camera's raster
/// ([`Prepared::zone_rect`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RasterExtent {
    /// Nowhere: it lies behind the rays.
    Nowhere,
    /// Anywhere: it reaches behind a perspective camera's eye.
    Anywhere,
    /// Within the rectangle `[x0, y0, x1, y1]` of the raster, in pixels
    /// from its top-left corner (up to rounding).
    Within([f64; 4]),
}

/// The volume swept by a bundle of rays (a tile of pixels): the
/// intersection of half-spaces `n·x >= d`. Used only to rule zones out, so
/// it must contain every ray of the bundle.
#[derive(Clone, Copy, Debug)]
pub struct Frustum {
    /// Normal `n`, offset `d`, the rounding slack `1e-9 (|d| + |n|)` and
    /// `|n|`.
    planes: [(DVec3, f64, f64, f64); 4],
}

impl Frustum {
    /// The frustum bounded by four corner rays given in order around the
    /// bundle (their origins may differ, as for an orthographic view; the
    /// rays must diverge or stay parallel).
    pub fn from_corners(c: [Ray; 4]) -> Frustum {
        let centre_o = (c[0].origin + c[1].origin + c[2].origin + c[3].origin) * 0.25;
        let centre_d = (c[0].dir + c[1].dir + c[2].dir + c[3].dir).normalize();
        let probe = centre_o + centre_d;
        let planes = std::array::from_fn(|i| {
            let (a, b) = (&c[i], &c[(i + 1) % 4]);
            // The plane holds ray a and the point where ray b starts.
            let mut n = a.dir.cross(b.dir + (b.origin - a.origin));
            if n.dot(probe - a.origin) < 0.0 {
                n = -n;
            }
            let d = n.dot(a.origin);
            (n, d, 1e-9 * (d.abs() + n.length()), n.length())
        });
        Frustum { planes }
    }

    /// False only when the box lies wholly outside.
    pub fn may_meet(&self, b: &sv_math::Aabb) -> bool {
        self.planes.iter().all(|&(n, d, slack, _)| {
            let p = DVec3::new(
                if n.x > 0.0 { b.max.x } else { b.min.x },
                if n.y > 0.0 { b.max.y } else { b.min.y },
                if n.z > 0.0 { b.max.z } else { b.min.z },
            );
            let v = n.dot(p);
            // Rounding slack: rule a box out only when clearly outside.
            // (A NaN compares as unordered and keeps the box.)
            v.partial_cmp(&(d - slack - 1e-9 * v.abs())) != Some(std::cmp::Ordering::Less)
        })
    }

    /// False only when the convex hull of `pts` lies wholly outside.
    pub fn may_meet_points(&self, pts: &[DVec3]) -> bool {
        self.planes.iter().all(|&(n, d, slack, _)| {
            pts.iter().any(|&p| {
                let v = n.dot(p);
                v.partial_cmp(&(d - slack - 1e-9 * v.abs())) != Some(std::cmp::Ordering::Less)
            })
        })
    }

    /// False only when the ball of centre `c` and radius `r` lies wholly
    /// outside.
    pub fn may_meet_ball(&self, c: DVec3, r: f64) -> bool {
        self.planes.iter().all(|&(n, d, slack, len)| {
            let v = n.dot(c) + r * len;
            v.partial_cmp(&(d - slack - 1e-9 * (v.abs() + r * len)))
                != Some(std::cmp::Ordering::Less)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::PrepareOptions;
    use sv_geom::{Body, BodyKind, Geometry, Region};

    #[test]
    fn a_frustum_rules_out_a_ball_whose_box_it_meets() {
        // Rays from the origin through the square |x|, |y| <= 1 at z = 1.
        let f = Frustum::from_corners(
            [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
                .map(|(x, y)| Ray::new(DVec3::ZERO, DVec3::new(x, y, 1.0))),
        );
        let ball = |c: DVec3, r: f64| (f.may_meet(&Aabb::new(c - r, c + r)), f.may_meet_ball(c, r));
        // 0.71 beyond the side x = z: its box reaches over the side.
        assert_eq!(ball(DVec3::new(2.0, 0.0, 1.0), 0.6), (true, false));
        // 0.57 beyond it: the ball reaches over too.
        assert_eq!(ball(DVec3::new(1.8, 0.0, 1.0), 0.6), (true, true));
        assert_eq!(ball(DVec3::new(0.0, 0.0, 5.0), 0.1), (true, true));
        assert_eq!(ball(DVec3::new(9.0, 0.0, 1.0), 0.6), (false, false));
        // Grazing: kept.
        let graze = DVec3::new(2.0, 0.0, 1.0);
        let r = (2.0 - 1.0) / 2f64.sqrt();
        assert!(f.may_meet_ball(graze, r));
        // A rod running parallel to the side x = z, 0.28 beyond it: its
        // box reaches over the side, its ends (and so the rod) do not.
        let rod = [DVec3::new(1.2, 0.0, 0.8), DVec3::new(2.0, 0.0, 1.6)];
        assert!(f.may_meet(&Aabb::from_points(rod)));
        assert!(!f.may_meet_points(&rod));
        assert!(f.may_meet_points(&[rod[0], DVec3::new(0.5, 0.0, 1.6)]));
    }

    #[test]
    fn a_tile_lists_its_zones_when_only_their_boxes_crowd_it() {
        // Rays from the origin through the square |x|, |y| <= 1 at z = 1
        // (as above). Three small spheres sit on the z axis; twelve beside
        // the four sides, like the ball 0.71 beyond the side x = z above,
        // have boxes that reach over the sides and balls that do not.
        let mut g = Geometry::default();
        let mut add = |c: DVec3, r: f64| {
            let i = g.bodies.len();
            g.bodies.push(Body::new(
                format!("s{i}"),
                BodyKind::Sph,
                vec![c.x, c.y, c.z, r],
            ));
            g.regions.push(Region::of_body(format!("r{i}"), i));
        };
        for z in [2.0, 8.0, 30.0] {
            add(DVec3::new(0.0, 0.0, z), 0.1);
        }
        for z in [1.0, 4.0, 16.0] {
            for (x, y) in [(2.0, 0.0), (-2.0, 0.0), (0.0, 2.0), (0.0, -2.0)] {
                add(DVec3::new(x * z, y * z, z), 0.6 * z);
            }
        }
        let p = Prepared::new(&g, &PrepareOptions::default()).unwrap().0;
        let f = Frustum::from_corners(
            [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
                .map(|(x, y)| Ray::new(DVec3::ZERO, DVec3::new(x, y, 1.0))),
        );
        let mut out = Vec::new();
        // Fifteen boxes meet the frustum, three balls: within a limit of
        // five, the tile keeps a list, of those three.
        assert!(p.frustum_zones(&f, 5, &mut out));
        out.sort_unstable();
        let regions: Vec<u32> = out.iter().map(|&zi| p.zones[zi as usize].region).collect();
        assert_eq!(regions, [0, 1, 2]);
        assert!(!p.frustum_zones(&f, 2, &mut out));
    }
}
