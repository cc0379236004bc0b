//! A picture of where two models differ: sections through the middle of
//! the compared box across x, y and z (top row), and views along x, y and
//! z that add up the disagreement along each ray (bottom row).

use super::{compared, Classes, DiffOptions, DiffSide, PairRays};
use crate::colour::region_colour;
use crate::model::CheckError;
use rayon::prelude::*;
use sv_math::{Aabb, DVec3, Ray};

/// Colour where both models hold nothing.
const NOTHING: [f32; 3] = [0.08, 0.08, 0.08];
/// Colour where both hold material, but different.
pub const DIFFERENT_MATERIAL: [f32; 3] = [1.0, 0.0, 1.0];
/// Colour where only A holds material.
pub const ONLY_A: [f32; 3] = [1.0, 0.5, 0.0];
/// Colour where only B holds material.
pub const ONLY_B: [f32; 3] = [0.0, 0.8, 1.0];
/// Gap between panels.
const GAP: u32 = 4;

/// The picture, display values 0…1, row-major from the top left.
#[derive(Clone, Debug)]
pub struct DiffPicture {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Colours.
    pub rgb: Vec<[f32; 3]>,
}

/// One panel: which axis is the normal, where its pixels lie.
struct Panel {
    normal: usize,
    u: usize,
    v: usize,
    /// Model units per pixel and the view's lower corner (u, v).
    scale: f64,
    corner: (f64, f64),
}

impl Panel {
    fn new(normal: usize, bx: &Aabb, side: u32) -> Panel {
        let (u, v) = match normal {
            0 => (1, 2),
            1 => (0, 2),
            _ => (0, 1),
        };
        let size = bx.size();
        let scale = size[u].max(size[v]) * 1.04 / side as f64;
        let centre = bx.center();
        let half = 0.5 * side as f64 * scale;
        Panel {
            normal,
            u,
            v,
            scale,
            corner: (centre[u] - half, centre[v] - half),
        }
    }

    /// The point of pixel (i, j) (j from the top) in the plane at `depth`.
    fn point(&self, i: f64, j: f64, side: u32, depth: f64) -> DVec3 {
        let mut p = DVec3::ZERO;
        p[self.u] = self.corner.0 + i * self.scale;
        p[self.v] = self.corner.1 + (side as f64 - j) * self.scale;
        p[self.normal] = depth;
        p
    }
}

fn class_colour(class: u32) -> [f32; 3] {
    region_colour(&format!("class {class}")).map(|c| 0.45 * c)
}

fn colour_of(ca: u32, cb: u32) -> [f32; 3] {
    match (ca, cb) {
        (0, 0) => NOTHING,
        (a, b) if a == b => class_colour(a),
        (_, 0) => ONLY_A,
        (0, _) => ONLY_B,
        _ => DIFFERENT_MATERIAL,
    }
}

/// A section row: one ray along the panel's `u` through pixel centres.
fn section_row(
    pair: &mut PairRays,
    cl: &Classes,
    panel: &Panel,
    row: u32,
    side: u32,
    depth: f64,
) -> Vec<[f32; 3]> {
    let mut out = vec![NOTHING; side as usize];
    let start = panel.point(0.0, row as f64 + 0.5, side, depth);
    let mut dir = DVec3::ZERO;
    dir[panel.u] = 1.0;
    let length = side as f64 * panel.scale;
    pair.trace(&Ray::new(start, dir), (0.0, length), |t0, t1, ra, rb| {
        let colour = colour_of(cl.class(0, ra), cl.class(1, rb));
        let first = (t0 / panel.scale - 0.5).ceil().max(0.0) as usize;
        let last = ((t1 / panel.scale - 0.5).ceil().max(0.0) as usize).min(out.len());
        for pixel in out.iter_mut().take(last).skip(first) {
            *pixel = colour;
        }
    });
    out
}

/// A view row: rays along the panel's normal through the box, one per
/// pixel, shaded by how much material they cross and red by how much of
/// it differs.
fn view_row(
    pair: &mut PairRays,
    cl: &Classes,
    panel: &Panel,
    row: u32,
    side: u32,
    bx: &Aabb,
) -> Vec<[f32; 3]> {
    let depth = bx.size()[panel.normal].max(1e-300);
    let mut dir = DVec3::ZERO;
    dir[panel.normal] = 1.0;
    (0..side)
        .map(|i| {
            let start = panel.point(i as f64 + 0.5, row as f64 + 0.5, side, bx.min[panel.normal]);
            let (mut material, mut differ) = (0.0, 0.0);
            pair.trace(&Ray::new(start, dir), (0.0, depth), |t0, t1, ra, rb| {
                let (ca, cb) = (cl.class(0, ra), cl.class(1, rb));
                if ca != 0 || cb != 0 {
                    material += t1 - t0;
                }
                if ca != cb {
                    differ += t1 - t0;
                }
            });
            if differ > 0.0 {
                let strength = 0.5 + 0.5 * (differ / material).sqrt();
                [strength as f32, 0.1, 0.1]
            } else {
                [(0.08 + 0.5 * material / depth) as f32; 3]
            }
        })
        .collect()
}

/// Draw where `a` and `b` differ, panels `side` pixels square.
pub fn diff_picture(
    a: DiffSide,
    b: DiffSide,
    opts: &DiffOptions,
    side: u32,
) -> Result<DiffPicture, CheckError> {
    let side = side.clamp(16, 4096);
    let (_, common) = compared(&a, &b, opts)?;
    if common.is_empty() {
        return Err(CheckError::Option(
            "the models' bounds do not overlap: nothing to draw".into(),
        ));
    }
    let (_, _, classes) = Classes::of(&a, &b, opts);
    let width = 3 * side + 2 * GAP;
    let height = 2 * side + GAP;
    let mut rgb = vec![[0.3f32; 3]; (width * height) as usize];
    let panels: Vec<Panel> = (0..3).map(|axis| Panel::new(axis, &common, side)).collect();
    let centre = common.center();
    // Rows of every panel: (panel, section or view, row).
    let jobs: Vec<(usize, bool, u32)> = (0..3)
        .flat_map(|p| {
            [true, false]
                .into_iter()
                .flat_map(move |s| (0..side).map(move |r| (p, s, r)))
        })
        .collect();
    let rows: Vec<Vec<[f32; 3]>> = jobs
        .par_iter()
        .map_init(
            || PairRays::new(a.model, b.model),
            |pair, &(p, section, row)| {
                let panel = &panels[p];
                if section {
                    section_row(pair, &classes, panel, row, side, centre[panel.normal])
                } else {
                    view_row(pair, &classes, panel, row, side, &common)
                }
            },
        )
        .collect();
    for (&(p, section, row), pixels) in jobs.iter().zip(rows) {
        let x0 = p as u32 * (side + GAP);
        let y = row + if section { 0 } else { side + GAP };
        let at = (y * width + x0) as usize;
        rgb[at..at + side as usize].copy_from_slice(&pixels);
    }
    Ok(DiffPicture { width, height, rgb })
}
