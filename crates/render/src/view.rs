//! Default views: what to frame, from where, and the light that goes with
//! them.

use sv_math::{Aabb, DVec3};
use sv_scene::{Camera, Lens, Light, LightKind, Scene};
use sv_trace::Prepared;

/// The axis that points up in a view.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum UpAxis {
    /// `x` up.
    X,
    /// `y` up (most accelerator halls).
    Y,
    /// `z` up (COMGEOM decks, BRL-CAD).
    #[default]
    Z,
}

impl UpAxis {
    /// The unit vector along the axis.
    pub fn vector(self) -> DVec3 {
        match self {
            UpAxis::X => DVec3::X,
            UpAxis::Y => DVec3::Y,
            UpAxis::Z => DVec3::Z,
        }
    }

    /// A direction given in a `z`-up frame, turned so that `z` goes to this
    /// axis (a cyclic permutation of the axes, a rotation).
    fn turn_z_up(self, v: DVec3) -> DVec3 {
        match self {
            UpAxis::Z => v,
            UpAxis::Y => DVec3::new(v.y, v.z, v.x),
            UpAxis::X => DVec3::new(v.z, v.x, v.y),
        }
    }
}

/// How a default view looks at a model: from azimuth `az` and elevation
/// `el` (degrees, BRL-CAD's convention about the `up` axis: azimuth from
/// the first horizontal axis toward the second), in perspective or
/// orthographic, and how wide an orthographic view is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewSpec {
    /// Azimuth, degrees.
    pub az: f64,
    /// Elevation, degrees.
    pub el: f64,
    /// The axis that points up.
    pub up: UpAxis,
    /// Orthographic (BRL-CAD's default) rather than perspective.
    pub ortho: bool,
    /// An orthographic view's height in model units; `None` fits the
    /// model (its bounds' diagonal, as `rt` sizes its view).
    pub view_size: Option<f64>,
}

impl ViewSpec {
    /// The unit vector from what is looked at toward the eye.
    fn toward_eye(&self) -> DVec3 {
        let (az, el) = (self.az.to_radians(), self.el.to_radians());
        self.up.turn_z_up(DVec3::new(
            el.cos() * az.cos(),
            el.cos() * az.sin(),
            el.sin(),
        ))
    }

    /// The direction that is up on the screen: the up axis, or, looking
    /// straight down (or up), the first horizontal axis turned toward the
    /// azimuth.
    fn screen_up(&self) -> DVec3 {
        if self.el.abs() > 89.0 {
            let az = self.az.to_radians();
            let horizontal = self.up.turn_z_up(DVec3::new(-az.cos(), -az.sin(), 0.0));
            horizontal.normalize_or(self.up.turn_z_up(DVec3::Y))
        } else {
            self.up.vector()
        }
    }
}

impl Default for ViewSpec {
    /// Azimuth 35°, elevation 25°, `z` up, perspective: the default view.
    fn default() -> Self {
        ViewSpec {
            az: 35.0,
            el: 25.0,
            up: UpAxis::Z,
            ortho: false,
            view_size: None,
        }
    }
}

/// Bounds to frame: the finite opaque regions that are part of the model,
/// else all its finite regions, the containers around them set aside (the
/// void sphere around a detector, see [`Prepared::interest_bounds`]);
/// the black hole's when nothing else is finite; a unit box when nothing
/// is.
pub fn frame_bounds(p: &Prepared) -> Aabb {
    let opaque = p.interest_bounds(|r| p.is_opaque(r) && !p.is_outside(r));
    let mut b = if opaque.is_empty() {
        p.interest_bounds(|r| !p.is_outside(r))
    } else {
        opaque
    };
    if b.is_empty() {
        // Regions bounded only by planes and quadrics: the black hole
        // around them is the only size the model has.
        b = p.bounds();
    }
    if b.is_empty() {
        Aabb::new(DVec3::splat(-1.0), DVec3::splat(1.0))
    } else {
        b
    }
}

/// A camera that frames the model as `view` says, perspective (30°
/// vertical field of view) or orthographic as BRL-CAD's `rt` does (view
/// size = bounding-box diagonal). An eye that would stand inside an opaque
/// region is moved back along the view until it is out of that region's
/// bounds.
pub fn default_camera(p: &Prepared, aspect: f64, view: &ViewSpec) -> Camera {
    let b = frame_bounds(p);
    let c = b.center();
    let r = 0.5 * b.diagonal();
    let (toward_eye, up) = (view.toward_eye(), view.screen_up());
    let (distance, lens) = if view.ortho {
        let height = view.view_size.unwrap_or(2.0 * r);
        (2.0 * r, Lens::Ortho { height })
    } else {
        let fov: f64 = 30.0;
        // Fit the bounding sphere in the narrower of the two fields of view.
        let half_v = (fov.to_radians() / 2.0).tan();
        let half = half_v.min(half_v * aspect).atan();
        (r / half.sin(), Lens::Fov { vertical_deg: fov })
    };
    let eye = out_of_regions(p, c + toward_eye * distance, toward_eye);
    Camera {
        eye,
        dir: -toward_eye,
        up,
        lens,
    }
}

/// BRL-CAD `rt`'s own view of `scene` at `width` × `height`, as its
/// `-a`/`-e` options set it (`view.az`, `view.el`; `view.view_size`
/// replaces its size): orthographic, centred on the model's box (the
/// bodies the regions use, infinite ones aside, widened to whole
/// millimetres), as wide as that box's diagonal (times the aspect when
/// wider than tall), the eye √2 half-widths back, and every ray fired
/// through its pixel's lower-left corner instead of its centre.
pub fn rt_camera(scene: &Scene, p: &Prepared, width: u32, height: u32, view: &ViewSpec) -> Camera {
    let mut used = vec![false; scene.geometry.bodies.len()];
    for region in &scene.geometry.regions {
        region.for_each_term(&mut |t| used[t.body] = true);
    }
    let model = (0..used.len())
        .filter(|&i| used[i])
        .map(|i| p.body_bounds(i))
        .filter(|b| !b.is_empty() && b.is_finite())
        // The tracer's bounds are padded by its tolerance (`Prepared`).
        .map(|b| b.padded(-4.0 * p.tolerance()))
        .fold(Aabb::EMPTY, |acc, b| acc.union(&b));
    let mm = scene.units.mm();
    let model = if model.is_empty() {
        Aabb::new(DVec3::splat(-1.0), DVec3::splat(1.0))
    } else {
        Aabb::new((model.min * mm).floor() / mm, (model.max * mm).ceil() / mm)
    };
    let aspect = f64::from(width) / f64::from(height);
    let size = view
        .view_size
        .unwrap_or_else(|| model.diagonal() * aspect.max(1.0));
    let toward_eye = view.toward_eye();
    let mut camera = Camera {
        eye: model.center() + toward_eye * (std::f64::consts::SQRT_2 * 0.5 * size),
        dir: -toward_eye,
        up: view.screen_up(),
        lens: Lens::Ortho {
            height: size / aspect,
        },
    };
    // Square pixels `size / width` wide; a ray through the lower-left
    // corner of each is the centre's ray moved half a pixel left and down.
    let (right, up, _) = camera.basis();
    let cell = size / f64::from(width);
    camera.eye -= (right + up) * (0.5 * cell);
    camera
}

/// `eye`, or, when it lies inside opaque regions of `p`, the first point
/// along `away` beyond their bounds (unbounded regions cannot be left).
fn out_of_regions(p: &Prepared, eye: DVec3, away: DVec3) -> DVec3 {
    let around = p
        .regions_at(eye)
        .into_iter()
        .filter(|&r| p.is_opaque(r as usize) && !p.is_outside(r as usize))
        .fold(Aabb::EMPTY, |acc, r| {
            acc.union(&p.region_bounds(r as usize))
        });
    if around.is_empty() || !around.is_finite() {
        return eye;
    }
    // The far side of the box along `away`, and a little beyond.
    let exit = (0..3)
        .filter(|&a| away[a] != 0.0)
        .map(|a| {
            let side = if away[a] > 0.0 {
                around.max[a]
            } else {
                around.min[a]
            };
            (side - eye[a]) / away[a]
        })
        .fold(f64::INFINITY, f64::min);
    if exit.is_finite() && exit > 0.0 {
        eye + away * (exit + 0.05 * around.diagonal())
    } else {
        eye
    }
}

/// One parallel light from over the viewer's left shoulder: it comes from
/// behind, above and to the left of the camera.
pub fn default_lights(cam: &Camera) -> Vec<Light> {
    let (right, up, fwd) = cam.basis();
    let dir = (fwd - up * 0.8 + right * 0.5).normalize();
    vec![Light {
        name: "SUN".into(),
        kind: LightKind::Parallel { dir },
        intensity: 0.85,
        colour: [1.0; 3],
    }]
}

#[cfg(test)]
mod tests {
    use super::*;
    use sv_geom::{Body, BodyKind, Geometry, Region};
    use sv_trace::PrepareOptions;

    /// Each body its own region; regions beyond the model and voids
    /// (named `void`) let light through, as the readers mark them.
    fn prepared(bodies: Vec<Body>, outside: Vec<bool>) -> Prepared {
        let mut g = Geometry::default();
        let mut opaque = Vec::new();
        for (i, b) in bodies.into_iter().enumerate() {
            opaque.push(!outside[i] && b.name != "void");
            g.bodies.push(b);
            g.regions.push(Region::of_body(format!("r{i}"), i));
        }
        let opts = PrepareOptions {
            opaque: Some(opaque),
            outside: Some(outside),
            ..PrepareOptions::default()
        };
        Prepared::new(&g, &opts).unwrap().0
    }

    #[test]
    fn black_holes_and_containers_are_not_framed() {
        // A 10 cm detector in a void sphere of 1e6 cm in a black hole of
        // 1e10 cm: the view frames the detector.
        let p = prepared(
            vec![
                Body::new("bh", BodyKind::Sph, vec![0.0, 0.0, 0.0, 1e10]),
                Body::new("void", BodyKind::Sph, vec![0.0, 0.0, 0.0, 1e6]),
                Body::new("det", BodyKind::Rpp, vec![-5.0, 5.0, -5.0, 5.0, -5.0, 5.0]),
            ],
            vec![true, false, false],
        );
        let b = frame_bounds(&p);
        assert!(b.diagonal() < 20.0, "{b:?}");
        let cam = default_camera(&p, 1.0, &ViewSpec::default());
        assert!(cam.eye.length() < 100.0, "{}", cam.eye);
    }

    #[test]
    fn looking_straight_down_keeps_a_screen_up() {
        // At elevation ±90° the up axis lies along the view; both the
        // default and rt's camera turn to the azimuth's horizontal axis.
        let mut g = Geometry::default();
        g.bodies
            .push(Body::new("b", BodyKind::Sph, vec![0.0, 0.0, 0.0, 1.0]));
        g.regions.push(Region::of_body("r", 0));
        let scene = Scene {
            geometry: g,
            ..Scene::default()
        };
        let p = Prepared::new(&scene.geometry, &PrepareOptions::default())
            .unwrap()
            .0;
        for el in [90.0, -90.0] {
            let view = ViewSpec {
                el,
                ..ViewSpec::default()
            };
            for cam in [
                default_camera(&p, 1.0, &view),
                rt_camera(&scene, &p, 64, 64, &view),
            ] {
                let (right, up, _) = cam.basis();
                assert!(right.is_finite() && up.is_finite(), "{el}: {cam:?}");
                assert!(
                    cam.up.dot(cam.dir.normalize()).abs() < 1e-9,
                    "{el}: {cam:?}"
                );
            }
        }
    }

    #[test]
    fn the_up_axis_turns_the_view() {
        let p = prepared(
            vec![Body::new("b", BodyKind::Sph, vec![0.0, 0.0, 0.0, 1.0])],
            vec![false],
        );
        for (up, axis) in [
            (UpAxis::Z, DVec3::Z),
            (UpAxis::Y, DVec3::Y),
            (UpAxis::X, DVec3::X),
        ] {
            let view = ViewSpec {
                up,
                el: 30.0,
                ..ViewSpec::default()
            };
            let cam = default_camera(&p, 1.0, &view);
            assert_eq!(cam.up, axis);
            // Seen from 30° above the horizontal plane of that axis.
            let toward_eye = -cam.dir.normalize();
            assert!((toward_eye.dot(axis) - 0.5).abs() < 1e-12, "{up:?}");
        }
    }

    #[test]
    fn an_eye_inside_a_region_steps_out_of_it() {
        // An opaque shell around the model would put the default eye
        // inside it; the eye steps out beyond the shell's bounds.
        let p = prepared(
            vec![
                Body::new("core", BodyKind::Sph, vec![0.0, 0.0, 0.0, 1.0]),
                Body::new("room", BodyKind::Rpp, vec![-6.0, 6.0, -6.0, 6.0, -6.0, 6.0]),
            ],
            vec![false, false],
        );
        let cam = default_camera(&p, 1.0, &ViewSpec::default());
        assert!(p.regions_at(cam.eye).is_empty(), "{}", cam.eye);
    }
}
