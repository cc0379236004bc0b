use crate::az_el;
use sv_math::{Aabb, DVec3};
use sv_scene::{Camera, Lens, Light, LightKind};
use sv_trace::Prepared;

/// Bounds to frame: the opaque regions' finite zones, else all finite
/// zones, else a unit box.
pub fn frame_bounds(p: &Prepared) -> Aabb {
    let b = p.opaque_bounds();
    let b = if b.is_empty() { p.bounds() } else { b };
    if b.is_empty() {
        Aabb::new(DVec3::splat(-1.0), DVec3::splat(1.0))
    } else {
        b
    }
}

/// A camera that frames the whole model from azimuth `az` and elevation
/// `el` (degrees), perspective (30° vertical field of view) or
/// orthographic as BRL-CAD's `rt` does (view size = bounding-box diagonal).
pub fn default_camera(p: &Prepared, aspect: f64, az: f64, el: f64, ortho: bool) -> Camera {
    let b = frame_bounds(p);
    let c = b.center();
    let r = 0.5 * b.diagonal();
    let toward_eye = az_el(az, el);
    let up = if el.abs() > 89.0 {
        DVec3::new(-toward_eye.x, -toward_eye.y, 0.0).normalize_or(DVec3::Y)
    } else {
        DVec3::Z
    };
    if ortho {
        return Camera {
            eye: c + toward_eye * (2.0 * r),
            dir: -toward_eye,
            up,
            lens: Lens::Ortho { height: 2.0 * r },
        };
    }
    let fov: f64 = 30.0;
    // Fit the bounding sphere in the narrower of the two fields of view.
    let half_v = (fov.to_radians() / 2.0).tan();
    let half = half_v.min(half_v * aspect).atan();
    let dist = r / half.sin();
    Camera {
        eye: c + toward_eye * dist,
        dir: -toward_eye,
        up,
        lens: Lens::Fov { vertical_deg: fov },
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
