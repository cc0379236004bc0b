//! What the page asks to see (an orbit camera, regions hidden or ghosted,
//! cut planes, a film frame) and the pictures made of it: a JPEG and the
//! region-id image, packed into one binary WebSocket message.

use crate::limits::{MAX_SIDE, MIN_SIDE};
use serde::{Deserialize, Serialize};
use std::collections::BTreeSet;
use sv_math::DVec3;
use sv_render::{default_lights, Frame, Renderer, Settings};
use sv_scene::{Camera, Lens, Light, LightKind, Scene};

/// The view the page asks for. Angles in degrees, BRL-CAD's convention
/// about the `up` axis, as [`sv_render::ViewSpec`].
#[derive(Clone, Debug, Deserialize, PartialEq)]
pub struct ViewRequest {
    /// The page's number for the request, echoed with the frame.
    pub seq: u64,
    /// The point the camera turns about.
    pub target: [f64; 3],
    /// Azimuth.
    pub az: f64,
    /// Elevation.
    pub el: f64,
    /// Distance from the target to the eye.
    pub distance: f64,
    /// Orthographic rather than perspective.
    #[serde(default)]
    pub ortho: bool,
    /// Height of an orthographic view (model units).
    #[serde(default)]
    pub view_height: f64,
    /// Vertical field of view of a perspective view.
    #[serde(default = "default_fov")]
    pub fov: f64,
    /// The axis up: `x`, `y` or `z`.
    #[serde(default)]
    pub up: String,
    /// The camera is moving: a coarse frame will do.
    #[serde(default)]
    pub moving: bool,
    /// Raster width of the full frame.
    pub width: u32,
    /// Raster height of the full frame.
    pub height: u32,
    /// The page's looks: hidden and ghosted regions, cut planes, the film
    /// frame.
    #[serde(flatten)]
    pub looks: Looks,
    /// Use the film's camera at the frame instead of the orbit camera.
    #[serde(default)]
    pub film_camera: bool,
}

fn default_fov() -> f64 {
    30.0
}

/// What decides the prepared geometry: changing any of it prepares the
/// scene again; the camera alone does not.
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
pub struct Looks {
    /// Regions not drawn.
    #[serde(default)]
    pub hidden: BTreeSet<usize>,
    /// Regions drawn see-through (blended over what is behind them).
    #[serde(default)]
    pub ghost: BTreeSet<usize>,
    /// Cut planes: normal then point; the side the normal points to is
    /// taken away.
    #[serde(default)]
    pub cuts: Vec<[f64; 6]>,
    /// The film frame shown.
    #[serde(default)]
    pub frame: Option<usize>,
}

/// The header of a frame message, JSON.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct FrameHeader {
    /// The request's number.
    pub seq: u64,
    /// `coarse` or `full`.
    pub kind: String,
    /// Raster size.
    pub width: u32,
    /// Raster height.
    pub height: u32,
    /// Bytes of JPEG that follow the header.
    pub jpeg_bytes: usize,
    /// The camera used: eye, direction, up.
    pub eye: [f64; 3],
    /// Viewing direction.
    pub dir: [f64; 3],
    /// Up vector.
    pub up: [f64; 3],
    /// Orthographic view height, or 0 for perspective.
    pub ortho_height: f64,
    /// Vertical field of view of a perspective view.
    pub fov: f64,
    /// Milliseconds spent rendering.
    pub render_ms: f64,
}

/// The unit vector from the target toward the eye for azimuth `az` and
/// elevation `el` about the `up` axis.
fn toward_eye(az: f64, el: f64, up: &str) -> DVec3 {
    turn_z_up(sv_render::az_el(az, el), up)
}

/// A direction given in a `z`-up frame, turned so that `z` goes to the
/// `up` axis (as [`sv_render::default_camera`] turns its views).
fn turn_z_up(v: DVec3, up: &str) -> DVec3 {
    match up {
        "y" => DVec3::new(v.y, v.z, v.x),
        "x" => DVec3::new(v.z, v.x, v.y),
        _ => v,
    }
}

fn up_axis(up: &str) -> DVec3 {
    match up {
        "y" => DVec3::Y,
        "x" => DVec3::X,
        _ => DVec3::Z,
    }
}

impl ViewRequest {
    /// The camera of the request, or `None` when a number is not finite
    /// or a length not positive.
    pub fn camera(&self) -> Option<Camera> {
        let target = DVec3::from_array(self.target);
        let numbers_ok = target.is_finite()
            && self.az.is_finite()
            && self.el.is_finite()
            && self.distance.is_finite()
            && self.distance > 0.0;
        if !numbers_ok {
            return None;
        }
        let toward = toward_eye(self.az, self.el, &self.up);
        let up = if self.el.abs() > 89.0 {
            // Looking straight down (or up): the view's up is the first
            // horizontal axis turned toward the azimuth.
            let az = self.az.to_radians();
            turn_z_up(DVec3::new(-az.cos(), -az.sin(), 0.0), &self.up)
        } else {
            up_axis(&self.up)
        };
        let lens = if self.ortho {
            if !(self.view_height > 0.0 && self.view_height.is_finite()) {
                return None;
            }
            Lens::Ortho {
                height: self.view_height,
            }
        } else {
            if !(self.fov > 0.1 && self.fov < 179.0) {
                return None;
            }
            Lens::Fov {
                vertical_deg: self.fov,
            }
        };
        Some(Camera {
            eye: target + toward * self.distance,
            dir: -toward,
            up,
            lens,
        })
    }

    /// The raster of this request: the full size (bounded), or a third of
    /// it while moving.
    pub fn raster(&self) -> (u32, u32) {
        let (w, h) = (
            self.width.clamp(MIN_SIDE, MAX_SIDE),
            self.height.clamp(MIN_SIDE, MAX_SIDE),
        );
        if self.moving {
            ((w / 3).max(MIN_SIDE), (h / 3).max(MIN_SIDE))
        } else {
            (w, h)
        }
    }
}

/// The renderers of one set of looks: the solid picture and, when regions
/// are ghosted, the picture without them to blend with.
pub struct Renderers {
    /// The looks they were made for.
    pub looks: Looks,
    /// Hidden regions left out.
    pub solid: Renderer,
    /// Ghosted regions left out too.
    pub clear: Option<Renderer>,
    /// Whether the scene has lights of its own.
    pub scene_lights: bool,
    /// The film's camera at the frame, if any.
    pub film_camera: Option<Camera>,
    /// Whether the scene casts shadows.
    pub shadows: bool,
}

impl Renderers {
    /// Prepare `scene` (already at the film frame) for `looks`.
    pub fn new(scene: &Scene, looks: &Looks) -> Result<Renderers, String> {
        let mut solid_scene = scene.clone();
        for &region in &looks.hidden {
            if let Some(props) = solid_scene.regions.get_mut(region) {
                props.transparent = true;
            }
        }
        for cut in &looks.cuts {
            let normal = DVec3::new(cut[0], cut[1], cut[2]);
            let point = DVec3::new(cut[3], cut[4], cut[5]);
            if !solid_scene.cut_away(normal, point) {
                return Err(
                    "a cut plane needs a finite point and a normal that is not zero".into(),
                );
            }
        }
        let (solid, _) = Renderer::new(&solid_scene, 4.0 / 3.0).map_err(|e| e.to_string())?;
        let clear = if looks.ghost.is_empty() {
            None
        } else {
            let mut clear_scene = solid_scene.clone();
            for &region in &looks.ghost {
                if let Some(props) = clear_scene.regions.get_mut(region) {
                    props.transparent = true;
                }
            }
            Some(
                Renderer::new(&clear_scene, 4.0 / 3.0)
                    .map_err(|e| e.to_string())?
                    .0,
            )
        };
        Ok(Renderers {
            looks: looks.clone(),
            solid,
            clear,
            scene_lights: !scene.lights.is_empty(),
            film_camera: scene.camera,
            shadows: scene.shadows,
        })
    }

    /// Render the request: the frame (region ids of the solid picture) and
    /// the camera used.
    pub fn render(&mut self, request: &ViewRequest) -> Option<(Frame, Camera)> {
        let camera = match (request.film_camera, self.film_camera) {
            (true, Some(camera)) => camera,
            _ => request.camera()?,
        };
        let lights = self.lights(&camera);
        let (width, height) = request.raster();
        let settings = Settings {
            width,
            height,
            shadows: self.shadows && !request.moving,
            samples: 1,
            aovs: true,
        };
        let mut frame = render_one(&mut self.solid, camera, &lights, &settings);
        if let Some(clear) = &mut self.clear {
            let behind = render_one(clear, camera, &lights, &settings);
            for (front, back) in frame.rgb.iter_mut().zip(&behind.rgb) {
                for channel in 0..3 {
                    front[channel] = 0.35 * front[channel] + 0.65 * back[channel];
                }
            }
        }
        Some((frame, camera))
    }

    fn lights(&self, camera: &Camera) -> Option<Vec<Light>> {
        if self.scene_lights {
            return None;
        }
        if self.looks.cuts.is_empty() {
            return Some(default_lights(camera));
        }
        // A cutaway view: the light comes with the eye, so that the cut
        // faces are lit whatever their angle (as `render --cut`).
        Some(vec![Light {
            name: "HEADLIGHT".into(),
            kind: LightKind::Parallel { dir: camera.dir },
            intensity: 0.85,
            colour: [1.0; 3],
        }])
    }
}

fn render_one(
    renderer: &mut Renderer,
    camera: Camera,
    lights: &Option<Vec<Light>>,
    settings: &Settings,
) -> Frame {
    renderer.camera = camera;
    if let Some(lights) = lights {
        renderer.lights = lights.clone();
    }
    renderer.render(settings, &|_| {})
}

/// Pack a frame: a little-endian `u32` length of the JSON header, the
/// header, the JPEG, then the region ids as little-endian `u32`s (region
/// index + 1, 0 for background).
pub fn pack(frame: &Frame, camera: &Camera, seq: u64, kind: &str, render_ms: f64) -> Vec<u8> {
    let picture = sv_output::to_rgb8(
        frame.width,
        frame.height,
        &frame.rgb,
        sv_output::Encoding::Linear,
    );
    let quality = if kind == "coarse" { 75 } else { 92 };
    let mut jpeg = Vec::new();
    let encoder = image::codecs::jpeg::JpegEncoder::new_with_quality(&mut jpeg, quality);
    picture
        .write_with_encoder(encoder)
        .expect("a JPEG encodes into memory");
    let (ortho_height, fov) = match camera.lens {
        Lens::Ortho { height } => (height, 0.0),
        _ => (0.0, 2.0 * camera.tan_half_fov().atan().to_degrees()),
    };
    let header = FrameHeader {
        seq,
        kind: kind.into(),
        width: frame.width,
        height: frame.height,
        jpeg_bytes: jpeg.len(),
        eye: camera.eye.to_array(),
        dir: camera.dir.to_array(),
        up: camera.up.to_array(),
        ortho_height,
        fov,
        render_ms,
    };
    let header = serde_json::to_vec(&header).expect("a header serialises");
    let mut message = Vec::with_capacity(4 + header.len() + jpeg.len() + frame.region.len() * 4);
    message.extend_from_slice(&(header.len() as u32).to_le_bytes());
    message.extend_from_slice(&header);
    message.extend_from_slice(&jpeg);
    for id in &frame.region {
        message.extend_from_slice(&id.to_le_bytes());
    }
    message
}

/// Unpack a frame message: the header, the JPEG and the region ids.
pub fn unpack(message: &[u8]) -> Option<(FrameHeader, &[u8], Vec<u32>)> {
    let header_len = u32::from_le_bytes(message.get(..4)?.try_into().ok()?) as usize;
    let header: FrameHeader = serde_json::from_slice(message.get(4..4 + header_len)?).ok()?;
    let jpeg_start = 4 + header_len;
    let jpeg = message.get(jpeg_start..jpeg_start + header.jpeg_bytes)?;
    let ids = message
        .get(jpeg_start + header.jpeg_bytes..)?
        .chunks_exact(4)
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    Some((header, jpeg, ids))
}
