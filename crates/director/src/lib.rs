//! The director's language as data: named objects, axes of rotation and a
//! timeline of changes (MOVE, TURN, AIM, ZOOM, INTENSITY, SPIN, TRACK) and
//! shots, from which the scene at any frame is computed directly.
//!
//! The text form (`.svs` scripts) is read by `sv_formats::script`; this crate
//! holds the model and its evaluation only.
//!
//! # Time
//!
//! A film is a list of [`Step`]s run top to bottom:
//!
//! - a change with no duration is applied at once and shoots nothing;
//! - a change spread over N frames shoots those N frames; at frame `k`
//!   (1…N) of the change its fraction `k/N` is done (eased when asked), so
//!   the last frame shows the whole change;
//! - [`Step::Together`] runs its changes over the same frames: all start on
//!   the block's first frame and the block lasts as long as its longest
//!   change; at every frame the changes are composed in the order written,
//!   each at its own fraction, on top of the set-up the block started from;
//! - [`Step::Shoot`] shoots frames with the current set-up (`SHOOT`,
//!   `HOLD n`); [`Step::Repeat`] repeats steps.
//!
//! Spinning objects ([`Change::Spin`]) turn by their rate for every frame
//! shot, whatever the step; a tracking camera ([`Change::Track`]) is
//! re-aimed after all other changes of each frame.
//!
//! # Exactness
//!
//! [`Timeline::scene_at`] is a pure function of the frame number: it walks
//! the steps from the start, composing each block's changes on the set-up at
//! the start of the block (never adding frame-by-frame increments), and then
//! applies every body's total transform once to the body of the base scene.
//! Frame N is therefore bit-for-bit the same whether it is computed alone,
//! in a full run, or after any other frames.
#![warn(missing_docs)]

mod build;
mod model;

pub use model::{AimPoint, Axis, Change, Easing, Object, Spec, Step, Target, Timed, Zoom};

use sv_math::{rotation_about_axis, Aabb, DAffine3, DQuat, DVec3};
use sv_scene::{Camera, Lens, LightKind, Scene};

/// Most frames a film may have.
pub const MAX_FRAMES: usize = 1_000_000;
/// Most blocks (changes and shots after expanding REPEATs) a film may have.
pub const MAX_BLOCKS: usize = 1_000_000;

/// Who a body belongs to, for [`DirectorError::SharedBody`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Owner {
    /// An object (by name).
    Object(String),
    /// A region that is in no object and so never moves (by name).
    Region(String),
}

/// A timeline that cannot be built.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum DirectorError {
    /// An index (object, region, axis or light) points past its list.
    #[error("{what} {index} does not exist")]
    BadIndex {
        /// Kind of thing (`object`, `region`, `axis`, `light`).
        what: &'static str,
        /// The index.
        index: usize,
    },
    /// An axis with a zero (or not finite) direction.
    #[error("axis `{name}` has no direction")]
    BadAxis {
        /// Axis index.
        axis: usize,
        /// Axis name.
        name: String,
    },
    /// An object carries itself, directly or not.
    #[error("object `{name}` contains itself")]
    Cycle {
        /// Object index.
        object: usize,
        /// Object name.
        name: String,
    },
    /// An object is carried by two objects.
    #[error("object `{name}` is contained in both `{first}` and `{second}`")]
    TwoParents {
        /// The carried object's index.
        object: usize,
        /// Its name.
        name: String,
        /// First carrier.
        first: String,
        /// Second carrier.
        second: String,
    },
    /// A body used by two owners that do not move together.
    #[error("{}", shared_body_message(body_name, first, second))]
    SharedBody {
        /// Body index.
        body: usize,
        /// Body name.
        body_name: String,
        /// The first owner met.
        first: Owner,
        /// An owner that moves differently.
        second: Owner,
    },
    /// Too many frames or blocks.
    #[error("the film is too long: more than {MAX_FRAMES} frames or {MAX_BLOCKS} blocks")]
    TooLong,
}

fn shared_body_message(body: &str, a: &Owner, b: &Owner) -> String {
    match (a, b) {
        (Owner::Object(a), Owner::Object(b)) => {
            format!("body `{body}` is shared by objects `{a}` and `{b}`, which move differently")
        }
        (Owner::Object(o), Owner::Region(r)) | (Owner::Region(r), Owner::Object(o)) => format!(
            "body `{body}` is shared by object `{o}`, which moves, and region `{r}`, which is in no object"
        ),
        (Owner::Region(a), Owner::Region(b)) => format!("body `{body}` is shared by regions `{a}` and `{b}`"),
    }
}

/// A block of the expanded film: changes shot over `len` frames.
#[derive(Clone, Debug)]
struct Block {
    start: usize,
    len: usize,
    changes: std::ops::Range<usize>,
}

/// The set-up at one frame: every object's total transform, the camera and
/// the lights.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameState {
    xf: Vec<DAffine3>,
    camera: Option<Camera>,
    lights: Vec<(LightKind, f64)>,
    spins: Vec<(usize, usize, f64)>,
    track: Option<usize>,
}

impl FrameState {
    /// The total transform of an object (identity for a bad index): where
    /// the base scene's bodies of the object are carried.
    pub fn object_transform(&self, object: usize) -> DAffine3 {
        self.xf.get(object).copied().unwrap_or(DAffine3::IDENTITY)
    }

    /// The camera, if there is one.
    pub fn camera(&self) -> Option<&Camera> {
        self.camera.as_ref()
    }

    /// A light's kind (position or direction) and intensity.
    pub fn light(&self, light: usize) -> Option<(LightKind, f64)> {
        self.lights.get(light).copied()
    }
}

/// A validated film: objects, axes and the expanded steps.
#[derive(Clone, Debug)]
pub struct Timeline {
    spec: Spec,
    subtree: Vec<Vec<usize>>,
    subtree_bodies: Vec<Vec<usize>>,
    body_owner: Vec<Option<usize>>,
    ref_points: Vec<Vec<DVec3>>,
    changes: Vec<Timed>,
    blocks: Vec<Block>,
    frames: usize,
    initial: FrameState,
}

impl Timeline {
    /// The specification the timeline was built from.
    pub fn spec(&self) -> &Spec {
        &self.spec
    }

    /// Number of frames the film shoots.
    pub fn frame_count(&self) -> usize {
        self.frames
    }

    /// Frames per second.
    pub fn fps(&self) -> f64 {
        self.spec.fps
    }

    /// Raster size set by the film, if any (else the scene's).
    pub fn size(&self) -> Option<(u32, u32)> {
        self.spec.size
    }

    /// A SHA-256 digest (hex) of everything that decides the film's
    /// pictures apart from render settings: the specification (objects,
    /// axes, steps, rate, size, camera) and the base scene. Comments and
    /// layout of a script do not change it. Film runners combine it with
    /// their own settings to tell which frames on disk are still valid.
    pub fn fingerprint(&self, base: &Scene) -> String {
        use sha2::{Digest, Sha256};
        let mut h = Sha256::new();
        h.update(format!("{:?}", self.spec).as_bytes());
        h.update([0u8]);
        h.update(format!("{base:?}").as_bytes());
        h.finalize().iter().map(|b| format!("{b:02x}")).collect()
    }

    /// The object that moves a body of the base scene, if any.
    pub fn body_owner(&self, body: usize) -> Option<usize> {
        self.body_owner.get(body).copied().flatten()
    }

    /// The set-up at `frame` (0-based). Frames past the end give the final
    /// set-up.
    pub fn state_at(&self, frame: usize) -> FrameState {
        let mut s = self.initial.clone();
        for b in &self.blocks {
            if b.len > 0 && frame < b.start + b.len {
                return self.block_state(&s, b, frame - b.start + 1);
            }
            s = self.block_state(&s, b, b.len);
        }
        s
    }

    /// Every frame's set-up in order, computed by carrying the set-up from
    /// block to block (a full sequential run).
    pub fn states(&self) -> impl Iterator<Item = FrameState> + '_ {
        let mut start = self.initial.clone();
        self.blocks.iter().flat_map(move |b| {
            let from = start.clone();
            start = self.block_state(&from, b, b.len);
            (1..=b.len).map(move |k| self.block_state(&from, b, k))
        })
    }

    /// The scene at `frame`: the base scene with every moved body replaced
    /// by the base body under its object's total transform (applied once),
    /// and the camera, lights and size of that frame.
    pub fn scene_at(&self, base: &Scene, frame: usize) -> Scene {
        self.scene_from_state(base, &self.state_at(frame))
    }

    /// The scene for a set-up computed by [`Timeline::state_at`] or
    /// [`Timeline::states`].
    pub fn scene_from_state(&self, base: &Scene, state: &FrameState) -> Scene {
        let mut scene = base.clone();
        for (i, body) in scene.geometry.bodies.iter_mut().enumerate() {
            if let Some(o) = self.body_owner(i) {
                let t = state.object_transform(o);
                if t != DAffine3::IDENTITY {
                    // A product of rigid transforms stays a similarity far
                    // within the tolerance of `transformed`; should it ever
                    // not, the body is left where the scene put it.
                    if let Ok(moved) = body.transformed(&t) {
                        *body = moved;
                    }
                }
            }
        }
        if state.camera.is_some() {
            scene.camera = state.camera;
        }
        for (light, &(kind, intensity)) in scene.lights.iter_mut().zip(&state.lights) {
            light.kind = kind;
            light.intensity = intensity;
        }
        if let Some(size) = self.spec.size {
            scene.size = Some(size);
        }
        scene
    }

    /// Centre of an object at a frame's set-up: the centre of the bounding
    /// box of its bodies' reference points (for every body of the object and
    /// of the objects it carries: each point parameter, each point plus each
    /// vector parameter written after it, the corners of an RPP, the points
    /// of an ARS; bodies extending to infinity are left out). An object
    /// without such points is centred on the image of the origin.
    pub fn object_centre(&self, object: usize, state: &FrameState) -> DVec3 {
        let mut bb = Aabb::EMPTY;
        for &b in self.subtree_bodies.get(object).map_or(&[][..], |v| v) {
            let t = self
                .body_owner(b)
                .map_or(DAffine3::IDENTITY, |o| state.object_transform(o));
            for p in &self.ref_points[b] {
                bb = bb.including(t.transform_point3(*p));
            }
        }
        if bb.is_empty() {
            state.object_transform(object).transform_point3(DVec3::ZERO)
        } else {
            bb.center()
        }
    }

    /// World position and direction of an axis at a set-up.
    pub fn axis_at(&self, axis: usize, state: &FrameState) -> (DVec3, DVec3) {
        let Some(a) = self.spec.axes.get(axis) else {
            return (DVec3::ZERO, DVec3::Z);
        };
        match a.on {
            Some(o) => {
                let t = state.object_transform(o);
                (t.transform_point3(a.point), t.transform_vector3(a.dir))
            }
            None => (a.point, a.dir),
        }
    }

    fn block_state(&self, start: &FrameState, b: &Block, k: usize) -> FrameState {
        let mut s = start.clone();
        for t in &self.changes[b.changes.clone()] {
            self.apply(&mut s, &t.change, t.fraction(k));
        }
        if k > 0 {
            let spins = s.spins.clone();
            for (o, a, rate) in spins {
                let angle = rate * k as f64;
                if angle != 0.0 {
                    let (p, d) = self.axis_at(a, &s);
                    self.transform_object(&mut s, o, rotation_about_axis(p, d, angle));
                }
            }
        }
        if let Some(o) = s.track {
            let c = self.object_centre(o, &s);
            if let Some(cam) = s.camera.as_mut() {
                let d = c - cam.eye;
                if d.length_squared() > 0.0 && d.is_finite() {
                    cam.dir = d;
                }
            }
        }
        s
    }

    fn transform_object(&self, s: &mut FrameState, o: usize, t: DAffine3) {
        for &m in &self.subtree[o] {
            s.xf[m] = t * s.xf[m];
        }
    }

    fn apply(&self, state: &mut FrameState, change: &Change, fraction: f64) {
        match *change {
            Change::Move { target, by } => {
                let shift = by * fraction;
                match target {
                    Target::Object(o) => {
                        self.transform_object(state, o, DAffine3::from_translation(shift))
                    }
                    Target::Camera => {
                        if let Some(camera) = state.camera.as_mut() {
                            camera.eye += shift;
                        }
                    }
                    Target::Light(i) => {
                        if let Some((LightKind::Point { pos, .. }, _)) = state.lights.get_mut(i) {
                            *pos += shift;
                        }
                    }
                }
            }
            Change::Turn {
                target,
                axis,
                degrees,
            } => {
                let (point, dir) = self.axis_at(axis, state);
                let rotation = rotation_about_axis(point, dir, degrees * fraction);
                match target {
                    Target::Object(o) => self.transform_object(state, o, rotation),
                    Target::Camera => {
                        if let Some(camera) = state.camera.as_mut() {
                            camera.eye = rotation.transform_point3(camera.eye);
                            camera.dir = rotation.transform_vector3(camera.dir);
                            camera.up = rotation.transform_vector3(camera.up);
                        }
                    }
                    Target::Light(i) => match state.lights.get_mut(i) {
                        Some((LightKind::Point { pos, .. }, _)) => {
                            *pos = rotation.transform_point3(*pos)
                        }
                        Some((LightKind::Parallel { dir }, _)) => {
                            *dir = rotation.transform_vector3(*dir)
                        }
                        None => {}
                    },
                }
            }
            Change::Aim(at) => {
                let target = match at {
                    AimPoint::Point(p) => p,
                    AimPoint::Object(o) => self.object_centre(o, state),
                };
                if let Some(camera) = state.camera.as_mut() {
                    let to_target = target - camera.eye;
                    if to_target.length_squared() == 0.0 || !to_target.is_finite() {
                        return;
                    }
                    if fraction >= 1.0 {
                        camera.dir = to_target;
                    } else {
                        let from = camera.dir.normalize();
                        let turn = DQuat::from_rotation_arc(from, to_target.normalize());
                        camera.dir = DQuat::IDENTITY.slerp(turn, fraction) * from;
                    }
                }
            }
            Change::Zoom(z) => {
                if let Some(camera) = state.camera.as_mut() {
                    camera.lens = zoom(camera, z, fraction);
                }
            }
            Change::Intensity { light, value } => {
                if let Some((_, intensity)) = state.lights.get_mut(light) {
                    *intensity = lerp(*intensity, value, fraction);
                }
            }
            Change::Spin {
                object,
                axis,
                degrees_per_frame,
            } => {
                state.spins.retain(|sp| sp.0 != object);
                state.spins.push((object, axis, degrees_per_frame));
            }
            Change::Stop { object } => state.spins.retain(|sp| sp.0 != object),
            Change::Track(t) => state.track = t,
        }
    }
}

fn lerp(a: f64, b: f64, f: f64) -> f64 {
    if f >= 1.0 {
        b
    } else {
        a + (b - a) * f
    }
}

fn zoom(camera: &Camera, to: Zoom, fraction: f64) -> Lens {
    match (to, camera.lens) {
        (Zoom::Fov(v1), Lens::Fov { vertical_deg }) => Lens::Fov {
            vertical_deg: lerp(vertical_deg, v1, fraction),
        },
        (Zoom::Fov(v1), Lens::Focal { .. }) => {
            let v0 = 2.0 * camera.tan_half_fov().atan().to_degrees();
            Lens::Fov {
                vertical_deg: lerp(v0, v1, fraction),
            }
        }
        (
            Zoom::Focal { focal, .. },
            Lens::Focal {
                focal: f0,
                film_height,
            },
        ) => Lens::Focal {
            focal: lerp(f0, focal, fraction),
            film_height,
        },
        (
            Zoom::Focal {
                focal,
                film_height: Some(film_height),
            },
            Lens::Fov { .. },
        ) => {
            let f0 = film_height / (2.0 * camera.tan_half_fov());
            Lens::Focal {
                focal: lerp(f0, focal, fraction),
                film_height,
            }
        }
        (Zoom::Height(h1), Lens::Ortho { height }) => Lens::Ortho {
            height: lerp(height, h1, fraction),
        },
        // A perspective setting on an orthographic camera and the reverse,
        // and a focal length without a film height for a lens given as a
        // field of view, are refused by the script reader; here they leave
        // the lens alone.
        (_, lens) => lens,
    }
}
