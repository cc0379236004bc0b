//! The timeline's vocabulary: objects, axes, changes and steps.

use sv_math::DVec3;
use sv_scene::Camera;

/// A named set of regions that moves as one (`HELICOPTER`), possibly
/// carrying other objects (`ROTOR`).
#[derive(Clone, Debug, PartialEq)]
pub struct Object {
    /// Name as the director writes it.
    pub name: String,
    /// Region indices (into the scene's `geometry.regions`) that belong to
    /// the object itself.
    pub regions: Vec<usize>,
    /// Objects carried by this one (indices into [`Spec::objects`]).
    pub children: Vec<usize>,
}

/// An axis of rotation: a line through `point` along `dir`.
#[derive(Clone, Debug, PartialEq)]
pub struct Axis {
    /// Name (`1` for `AXIS 1`, `MAST`).
    pub name: String,
    /// A point on the axis, in the base scene's coordinates.
    pub point: DVec3,
    /// Direction of the axis (right-hand rule for positive angles).
    pub dir: DVec3,
    /// The object the axis is fixed to: it then moves and turns with it.
    pub on: Option<usize>,
}

/// What a MOVE or TURN acts on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target {
    /// An object and everything it carries.
    Object(usize),
    /// The camera (eye, direction and up).
    Camera,
    /// A light, by index into the scene's `lights`.
    Light(usize),
}

/// Where `AIM CAMERA AT` points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AimPoint {
    /// A fixed point.
    Point(DVec3),
    /// The centre of an object as it is at that frame (see
    /// [`crate::Timeline::object_centre`]).
    Object(usize),
}

/// A new lens setting for `ZOOM`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Zoom {
    /// Vertical field of view in degrees (perspective cameras).
    Fov(f64),
    /// Focal length (perspective cameras). The film height is kept when the
    /// camera already has a focal lens, otherwise it is `film_height`.
    Focal {
        /// Pinhole to film distance.
        focal: f64,
        /// Film height used when the lens was given as a field of view;
        /// `None` leaves such a lens alone (the script reader refuses it).
        film_height: Option<f64>,
    },
    /// Visible height (orthographic cameras).
    Height(f64),
}

/// One change to the set-up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Change {
    /// Translate the target by a vector.
    Move {
        /// What moves.
        target: Target,
        /// Displacement.
        by: DVec3,
    },
    /// Rotate the target about an axis, in degrees (right-hand rule).
    Turn {
        /// What turns.
        target: Target,
        /// Axis index.
        axis: usize,
        /// Angle in degrees.
        degrees: f64,
    },
    /// Point the camera at a point or an object.
    Aim(AimPoint),
    /// Change the camera's lens.
    Zoom(Zoom),
    /// Set a light's intensity.
    Intensity {
        /// Light index.
        light: usize,
        /// New intensity.
        value: f64,
    },
    /// Start turning an object continuously about an axis, by
    /// `degrees_per_frame` for every frame shot from then on (a rotor).
    Spin {
        /// The spinning object.
        object: usize,
        /// Axis index.
        axis: usize,
        /// Degrees per frame.
        degrees_per_frame: f64,
    },
    /// Stop an object's spin.
    Stop {
        /// The object.
        object: usize,
    },
    /// Keep the camera aimed at an object after every change of every
    /// frame (`Some`), or stop doing so (`None`).
    Track(Option<usize>),
}

/// How a change spread over frames progresses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Easing {
    /// Equal steps.
    #[default]
    Linear,
    /// Slow in and out (`3t² − 2t³`).
    Smooth,
}

impl Easing {
    /// The eased fraction for `t` in `[0, 1]`; exactly 0 at 0 and 1 at 1.
    pub fn apply(self, t: f64) -> f64 {
        match self {
            Easing::Linear => t,
            Easing::Smooth => t * t * (3.0 - 2.0 * t),
        }
    }
}

/// A change and the number of frames it is spread over.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Timed {
    /// The change.
    pub change: Change,
    /// Frames it takes; 0 applies it at once without shooting.
    pub frames: usize,
    /// Progression over the frames.
    pub easing: Easing,
}

impl Timed {
    /// A change applied at once.
    pub fn now(change: Change) -> Timed {
        Timed {
            change,
            frames: 0,
            easing: Easing::Linear,
        }
    }

    /// A change spread linearly over `frames` frames.
    pub fn over(change: Change, frames: usize) -> Timed {
        Timed {
            change,
            frames,
            easing: Easing::Linear,
        }
    }

    /// Fraction of the change done at frame `k` (1-based) of its block.
    pub(crate) fn fraction(&self, k: usize) -> f64 {
        if self.frames == 0 || k >= self.frames {
            1.0
        } else {
            self.easing.apply(k as f64 / self.frames as f64)
        }
    }
}

/// One statement of a film, in script order.
#[derive(Clone, Debug, PartialEq)]
pub enum Step {
    /// A change on its own: applied at once (no frame) or, spread over N
    /// frames, shooting those N frames.
    Change(Timed),
    /// Changes running over the same frames: all start together and the
    /// block shoots as many frames as the longest of them. Changes are
    /// composed in the order written at every frame.
    Together(Vec<Timed>),
    /// Shoot this many frames with the current set-up (`SHOOT`, `HOLD n`);
    /// spinning objects keep spinning.
    Shoot(usize),
    /// The steps, this many times.
    Repeat(usize, Vec<Step>),
}

/// Everything a [`crate::Timeline`] is built from.
#[derive(Clone, Debug, PartialEq)]
pub struct Spec {
    /// Named objects.
    pub objects: Vec<Object>,
    /// Named axes.
    pub axes: Vec<Axis>,
    /// The film, top to bottom.
    pub steps: Vec<Step>,
    /// Frames per second.
    pub fps: f64,
    /// Raster size for every frame, overriding the scene's.
    pub size: Option<(u32, u32)>,
    /// Camera at the start, overriding the scene's.
    pub camera: Option<Camera>,
}

impl Default for Spec {
    fn default() -> Self {
        Spec {
            objects: Vec::new(),
            axes: Vec::new(),
            steps: Vec::new(),
            fps: 24.0,
            size: None,
            camera: None,
        }
    }
}
