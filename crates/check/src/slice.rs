//! `slice`: a section view of the regions in a plane.
//!
//! One ray per pixel row runs along the plane's `u` direction; each pixel
//! takes the region whose stretch holds the pixel's centre. Overlaps and
//! voids come from the same classification as [`check`](crate::check).

use crate::analyse::{FindingKind, RayCheck};
use crate::colour::{region_colour, OVERLAP_COLOUR, VOID_COLOUR};
use crate::model::{default_tolerance, CheckError, Model};
use rayon::prelude::*;
use serde::Serialize;
use std::collections::BTreeMap;
use sv_math::{DVec3, Ray};

/// A cutting plane with its in-plane axes: `u` runs left to right in the
/// picture, `v` bottom to top.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    /// A point of the plane.
    pub origin: DVec3,
    /// Unit normal.
    pub normal: DVec3,
    /// Unit in-plane axis to the right.
    pub u: DVec3,
    /// Unit in-plane axis up.
    pub v: DVec3,
}

impl Plane {
    /// The plane `x = value` (`axis` 0), `y = value` (1) or `z = value` (2).
    /// Pictures show x = : (y right, z up); y = : (x right, z up);
    /// z = : (x right, y up).
    pub fn axis(axis: usize, value: f64) -> Plane {
        let e = |i: usize| {
            let mut d = DVec3::ZERO;
            d[i] = 1.0;
            d
        };
        let (u, v) = match axis {
            0 => (e(1), e(2)),
            1 => (e(0), e(2)),
            _ => (e(0), e(1)),
        };
        Plane {
            origin: e(axis.min(2)) * value,
            normal: e(axis.min(2)),
            u,
            v,
        }
    }

    /// The plane through `origin` with normal `normal` (not zero). `v` is
    /// the projection of +z on the plane (of +y when the plane is
    /// horizontal); `u = v × normal`.
    pub fn new(origin: DVec3, normal: DVec3) -> Option<Plane> {
        let n = normal.try_normalize()?;
        if !origin.is_finite() {
            return None;
        }
        let up = if n.z.abs() > 0.999 {
            DVec3::Y
        } else {
            DVec3::Z
        };
        let v = (up - n * up.dot(n)).normalize();
        let u = v.cross(n);
        Some(Plane {
            origin,
            normal: n,
            u,
            v,
        })
    }
}

/// Options for [`slice()`].
#[derive(Clone, Debug)]
pub struct SliceOptions {
    /// The plane.
    pub plane: Plane,
    /// Width and height of the view in model units; default: the model's
    /// bounds projected on the plane, with a 4% margin on each side, widened
    /// to the aspect of `size` when that is given (square pixels).
    pub extent: Option<(f64, f64)>,
    /// Raster size; default: 800 pixels on the long side of the extent.
    pub size: Option<(u32, u32)>,
    /// Overlap and void tolerance; default [`default_tolerance`].
    pub tolerance: Option<f64>,
    /// Draw overlaps with air regions as overlaps too. By default the
    /// solid region is drawn there, as GIFT and BRL-CAD resolve them (see
    /// [`CheckOptions::strict_air`](crate::CheckOptions::strict_air)).
    pub strict_air: bool,
}

/// One line of the legend.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LegendEntry {
    /// Region name, `A × B` for an overlap, `void` for voids.
    pub label: String,
    /// The region's description (empty for overlaps and voids).
    pub description: String,
    /// Colour as `#rrggbb`.
    pub colour: String,
    /// Pixels of the picture it covers.
    pub pixels: u64,
    /// Area in the plane (units²).
    pub area: f64,
}

/// A section view.
#[derive(Clone, Debug)]
pub struct Slice {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Display colours 0…1, row-major from the top left.
    pub rgb: Vec<[f32; 3]>,
    /// Per pixel: 0 nothing, `r + 1` region `r`, [`Slice::OVERLAP`] or
    /// [`Slice::VOID`].
    pub class: Vec<u32>,
    /// Regions in the picture, largest area first.
    pub legend: Vec<LegendEntry>,
    /// Overlapping pairs in the picture, largest first.
    pub overlaps: Vec<LegendEntry>,
    /// Void in the picture, if any.
    pub void: Option<LegendEntry>,
    /// Centre of the picture (a point of the plane).
    pub centre: DVec3,
    /// Width and height of the view (units).
    pub extent: (f64, f64),
    /// The plane.
    pub plane: Plane,
}

impl Slice {
    /// Class of a pixel inside an overlap.
    pub const OVERLAP: u32 = u32::MAX;
    /// Class of a pixel inside a void.
    pub const VOID: u32 = u32::MAX - 1;
}

fn hex(c: [f32; 3]) -> String {
    let b = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
    format!("#{:02x}{:02x}{:02x}", b(c[0]), b(c[1]), b(c[2]))
}

/// Cut `model` with the plane of `opts`. Runs on the current rayon pool.
pub fn slice(model: &Model, opts: &SliceOptions) -> Result<Slice, CheckError> {
    let pl = opts.plane;
    let tol = match opts.tolerance {
        Some(t) if t >= 0.0 && t.is_finite() => t,
        Some(t) => {
            return Err(CheckError::Option(format!(
                "the tolerance must be zero or more, found {t}"
            )))
        }
        None => default_tolerance(&model.prepared),
    };
    // The box's corners in plane coordinates (the plane's origin when
    // there is no finite box and the extent is given).
    let b = match (model.finite_bounds(), opts.extent) {
        (Ok(b), _) => b,
        (Err(_), Some(_)) => sv_math::Aabb::new(pl.origin, pl.origin),
        (Err(e), None) => return Err(e),
    };
    let (mut umin, mut umax, mut vmin, mut vmax) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for i in 0..8 {
        let c = DVec3::new(
            if i & 1 == 0 { b.min.x } else { b.max.x },
            if i & 2 == 0 { b.min.y } else { b.max.y },
            if i & 4 == 0 { b.min.z } else { b.max.z },
        );
        let d = c - pl.origin;
        let (cu, cv) = (d.dot(pl.u), d.dot(pl.v));
        umin = umin.min(cu);
        umax = umax.max(cu);
        vmin = vmin.min(cv);
        vmax = vmax.max(cv);
    }
    let (uc, vc) = (0.5 * (umin + umax), 0.5 * (vmin + vmax));
    let (ew, eh) = match opts.extent {
        Some((w, h)) if w > 0.0 && h > 0.0 && w.is_finite() && h.is_finite() => (w, h),
        Some((w, h)) => {
            return Err(CheckError::Option(format!(
                "the extent must be positive, found {w} × {h}"
            )))
        }
        None => {
            let (w, h) = ((umax - umin) * 1.08, (vmax - vmin) * 1.08);
            let m = w.max(h).max(1e-9);
            (w.max(m * 0.02), h.max(m * 0.02))
        }
    };
    let (w, h) = match opts.size {
        Some((w, h))
            if w > 0 && h > 0 && w <= 16384 && h <= 16384 && (w as u64) * (h as u64) <= 1 << 26 =>
        {
            (w, h)
        }
        Some((w, h)) => {
            return Err(CheckError::Option(format!(
                "the size {w}x{h} is out of range (1 to 16384 each way, at most 67 million pixels)"
            )))
        }
        None => {
            if ew >= eh {
                (800, ((800.0 * eh / ew).round() as u32).max(1))
            } else {
                (((800.0 * ew / eh).round() as u32).max(1), 800)
            }
        }
    };
    // A size without an extent keeps pixels square: the default extent
    // grows to the picture's aspect.
    let (ew, eh) = match (opts.extent, opts.size) {
        (None, Some(_)) => {
            let aspect = w as f64 / h as f64;
            if ew / eh < aspect {
                (eh * aspect, eh)
            } else {
                (ew, ew / aspect)
            }
        }
        _ => (ew, eh),
    };
    let (dx, dy) = (ew / w as f64, eh / h as f64);
    let pad = 0.01 * ew + dx;
    let centre = pl.origin + pl.u * uc + pl.v * vc;
    let wu = w as usize;
    let air = |r: u32| model.air.get(r as usize).copied().unwrap_or(false);
    type Row = (Vec<u32>, BTreeMap<(u32, u32), u64>);
    let rows: Vec<Row> = (0..h)
        .into_par_iter()
        .map_init(
            || RayCheck::new(model),
            |rc, j| {
                let v = vc + 0.5 * eh - (j as f64 + 0.5) * dy;
                let o = pl.origin + pl.u * (uc - 0.5 * ew - pad) + pl.v * v;
                let ray = Ray::new(o, pl.u);
                rc.run(&ray, 0.0, ew + 2.0 * pad, tol);
                let mut class = vec![0u32; wu];
                let range = |a: f64, b: f64| {
                    let f = |t: f64| ((t - pad) / dx - 0.5).ceil().clamp(0.0, w as f64) as usize;
                    f(a)..f(b)
                };
                for p in &rc.parts {
                    for c in &mut class[range(p.span.a.t, p.span.b.t)] {
                        if *c == 0 {
                            *c = p.region + 1;
                        }
                    }
                }
                let mut pairs = BTreeMap::new();
                for f in &rc.findings {
                    let code = match f.kind {
                        FindingKind::Overlap(a, b) if !opts.strict_air && (air(a) || air(b)) => {
                            // Air gives way: the solid region is drawn (two
                            // air regions: the first claim stays).
                            if air(a) != air(b) {
                                let solid = if air(a) { b } else { a };
                                for c in &mut class[range(f.t0, f.t1)] {
                                    if *c != Slice::OVERLAP && *c != Slice::VOID {
                                        *c = solid + 1;
                                    }
                                }
                            }
                            continue;
                        }
                        FindingKind::Overlap(..) => Slice::OVERLAP,
                        FindingKind::Void(..) => Slice::VOID,
                        FindingKind::Outside(_) => continue,
                    };
                    let r = range(f.t0, f.t1);
                    if let FindingKind::Overlap(a, b) = f.kind {
                        *pairs.entry((a, b)).or_insert(0) += r.len() as u64;
                    }
                    for c in &mut class[r] {
                        *c = code;
                    }
                }
                (class, pairs)
            },
        )
        .collect();
    let mut class = Vec::with_capacity(wu * h as usize);
    let mut pairs: BTreeMap<(u32, u32), u64> = BTreeMap::new();
    for (c, p) in rows {
        class.extend(c);
        for (k, n) in p {
            *pairs.entry(k).or_insert(0) += n;
        }
    }
    let colours: Vec<[f32; 3]> = model.names.iter().map(|n| region_colour(n)).collect();
    let hh = h as usize;
    let mut rgb = vec![[1.0f32; 3]; class.len()];
    let mut counts = vec![0u64; model.names.len()];
    let mut void_px = 0u64;
    for j in 0..hh {
        for i in 0..wu {
            let k = j * wu + i;
            let c = class[k];
            let stripe = ((i + j) / 4) % 2 == 0;
            let mut col = match c {
                0 => [1.0; 3],
                Slice::OVERLAP => {
                    if stripe {
                        OVERLAP_COLOUR
                    } else {
                        [0.1, 0.0, 0.1]
                    }
                }
                Slice::VOID => {
                    void_px += 1;
                    if stripe {
                        VOID_COLOUR
                    } else {
                        [0.05, 0.05, 0.05]
                    }
                }
                r => {
                    counts[(r - 1) as usize] += 1;
                    colours[(r - 1) as usize]
                }
            };
            let edge = (i + 1 < wu && class[k + 1] != c) || (j + 1 < hh && class[k + wu] != c);
            if edge {
                col = col.map(|x| x * 0.35);
            }
            rgb[k] = col;
        }
    }
    let px_area = dx * dy;
    let mut legend: Vec<LegendEntry> = counts
        .iter()
        .enumerate()
        .filter(|(_, n)| **n > 0)
        .map(|(r, n)| LegendEntry {
            label: model.names[r].clone(),
            description: model.descriptions.get(r).cloned().unwrap_or_default(),
            colour: hex(colours[r]),
            pixels: *n,
            area: *n as f64 * px_area,
        })
        .collect();
    legend.sort_by(|a, b| b.pixels.cmp(&a.pixels).then(a.label.cmp(&b.label)));
    let mut overlaps: Vec<LegendEntry> = pairs
        .into_iter()
        .filter(|(_, n)| *n > 0)
        .map(|((a, b), n)| LegendEntry {
            label: format!("{} × {}", model.names[a as usize], model.names[b as usize]),
            description: String::new(),
            colour: hex(OVERLAP_COLOUR),
            pixels: n,
            area: n as f64 * px_area,
        })
        .collect();
    overlaps.sort_by(|a, b| b.pixels.cmp(&a.pixels).then(a.label.cmp(&b.label)));
    let void = (void_px > 0).then(|| LegendEntry {
        label: "void".into(),
        description: String::new(),
        colour: hex(VOID_COLOUR),
        pixels: void_px,
        area: void_px as f64 * px_area,
    });
    Ok(Slice {
        width: w,
        height: h,
        rgb,
        class,
        legend,
        overlaps,
        void,
        centre,
        extent: (ew, eh),
        plane: pl,
    })
}
