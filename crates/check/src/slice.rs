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

    /// The plane written `x=VALUE`, `y=VALUE` or `z=VALUE` (as `slice
    /// --plane` takes it); `None` for anything else.
    pub fn parse(text: &str) -> Option<Plane> {
        let (axis, value) = text.split_once('=')?;
        let axis = match axis.trim().to_ascii_lowercase().as_str() {
            "x" => 0,
            "y" => 1,
            "z" => 2,
            _ => return None,
        };
        let value: f64 = value.trim().parse().ok()?;
        value.is_finite().then(|| Plane::axis(axis, value))
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
    /// The point of the plane at the picture's centre (projected on the
    /// plane); default: the centre of the model's bounds projected on it.
    pub centre: Option<DVec3>,
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

/// Where a section view lies in its plane, and its raster.
struct View {
    /// Plane coordinates (along `u`, `v`) of the picture's centre.
    centre: (f64, f64),
    /// Width and height in model units.
    extent: (f64, f64),
    /// Width and height in pixels.
    width: u32,
    height: u32,
}

impl View {
    /// Model units across a pixel, along `u` and `v`.
    fn pixel(&self) -> (f64, f64) {
        (
            self.extent.0 / self.width as f64,
            self.extent.1 / self.height as f64,
        )
    }
}

/// The lowest and the highest of a coordinate.
type Span = (f64, f64);

/// Per pixel, row-major: 0 nothing, `r + 1` region `r`, [`Slice::OVERLAP`]
/// or [`Slice::VOID`]; and the pixels of every overlapping pair.
type Classes = (Vec<u32>, BTreeMap<(u32, u32), u64>);

/// Cut `model` with the plane of `opts`. Runs on the current rayon pool.
pub fn slice(model: &Model, opts: &SliceOptions) -> Result<Slice, CheckError> {
    let tolerance = match opts.tolerance {
        Some(t) if t >= 0.0 && t.is_finite() => t,
        Some(t) => {
            return Err(CheckError::Option(format!(
                "the tolerance must be zero or more, found {t}"
            )))
        }
        None => default_tolerance(&model.prepared),
    };
    let view = view(model, opts)?;
    let (class, pairs) = classify(model, opts, &view, tolerance);
    let colours: Vec<[f32; 3]> = model.names.iter().map(|n| region_colour(n)).collect();
    let (rgb, region_pixels, void_pixels) = paint(&class, view.width, &colours);
    let (dx, dy) = view.pixel();
    let pixel_area = dx * dy;
    let entry = |label: String, description: String, colour: [f32; 3], pixels: u64| LegendEntry {
        label,
        description,
        colour: hex(colour),
        pixels,
        area: pixels as f64 * pixel_area,
    };
    let mut legend: Vec<LegendEntry> = region_pixels
        .iter()
        .enumerate()
        .filter(|(_, pixels)| **pixels > 0)
        .map(|(region, pixels)| {
            let description = model.descriptions.get(region).cloned().unwrap_or_default();
            entry(
                model.names[region].clone(),
                description,
                colours[region],
                *pixels,
            )
        })
        .collect();
    legend.sort_by(|a, b| b.pixels.cmp(&a.pixels).then(a.label.cmp(&b.label)));
    let mut overlaps: Vec<LegendEntry> = pairs
        .into_iter()
        .filter(|(_, pixels)| *pixels > 0)
        .map(|((a, b), pixels)| {
            let label = format!("{} × {}", model.names[a as usize], model.names[b as usize]);
            entry(label, String::new(), OVERLAP_COLOUR, pixels)
        })
        .collect();
    overlaps.sort_by(|a, b| b.pixels.cmp(&a.pixels).then(a.label.cmp(&b.label)));
    let void =
        (void_pixels > 0).then(|| entry("void".into(), String::new(), VOID_COLOUR, void_pixels));
    let plane = opts.plane;
    Ok(Slice {
        width: view.width,
        height: view.height,
        rgb,
        class,
        legend,
        overlaps,
        void,
        centre: plane.origin + plane.u * view.centre.0 + plane.v * view.centre.1,
        extent: view.extent,
        plane,
    })
}

/// The part of the plane to show (`opts.extent`, or the model's bounds
/// projected on the plane with a margin) and the raster (`opts.size`, or
/// 800 pixels on the long side).
fn view(model: &Model, opts: &SliceOptions) -> Result<View, CheckError> {
    let ((umin, umax), (vmin, vmax)) = projected_bounds(model, opts)?;
    let (extent_w, extent_h) = match opts.extent {
        Some((w, h)) if w > 0.0 && h > 0.0 && w.is_finite() && h.is_finite() => (w, h),
        Some((w, h)) => {
            return Err(CheckError::Option(format!(
                "the extent must be positive, found {w} × {h}"
            )))
        }
        None => {
            // Centred on a given point, the view reaches the farther side.
            let (w, h) = if let Some(point) = opts.centre.filter(|p| p.is_finite()) {
                let offset = point - opts.plane.origin;
                let (cu, cv) = (offset.dot(opts.plane.u), offset.dot(opts.plane.v));
                let reach = |lo: f64, hi: f64, c: f64| 2.0 * (lo - c).abs().max((hi - c).abs());
                (reach(umin, umax, cu) * 1.08, reach(vmin, vmax, cv) * 1.08)
            } else {
                ((umax - umin) * 1.08, (vmax - vmin) * 1.08)
            };
            let longest = w.max(h).max(1e-9);
            (w.max(longest * 0.02), h.max(longest * 0.02))
        }
    };
    let (width, height) = match opts.size {
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
            if extent_w >= extent_h {
                (800, ((800.0 * extent_h / extent_w).round() as u32).max(1))
            } else {
                (((800.0 * extent_w / extent_h).round() as u32).max(1), 800)
            }
        }
    };
    // A size without an extent keeps pixels square: the default extent
    // grows to the picture's aspect.
    let extent = match (opts.extent, opts.size) {
        (None, Some(_)) => {
            let aspect = width as f64 / height as f64;
            if extent_w / extent_h < aspect {
                (extent_h * aspect, extent_h)
            } else {
                (extent_w, extent_w / aspect)
            }
        }
        _ => (extent_w, extent_h),
    };
    let centre = match opts.centre {
        Some(point) if point.is_finite() => {
            let offset = point - opts.plane.origin;
            (offset.dot(opts.plane.u), offset.dot(opts.plane.v))
        }
        Some(_) => return Err(CheckError::Option("the centre must be finite".into())),
        None => (0.5 * (umin + umax), 0.5 * (vmin + vmax)),
    };
    Ok(View {
        centre,
        extent,
        width,
        height,
    })
}

/// The ranges along `u` and `v` of the model's box projected on the
/// plane (the plane's origin when there is no finite box and the extent
/// is given).
fn projected_bounds(model: &Model, opts: &SliceOptions) -> Result<(Span, Span), CheckError> {
    let plane = opts.plane;
    let bounds = match (model.finite_bounds(), opts.extent) {
        (Ok(b), _) => b,
        (Err(_), Some(_)) => sv_math::Aabb::new(plane.origin, plane.origin),
        (Err(e), None) => return Err(e),
    };
    let (mut umin, mut umax, mut vmin, mut vmax) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for corner_index in 0..8 {
        let pick = |bit: usize, low: f64, high: f64| {
            if corner_index & bit == 0 {
                low
            } else {
                high
            }
        };
        let corner = DVec3::new(
            pick(1, bounds.min.x, bounds.max.x),
            pick(2, bounds.min.y, bounds.max.y),
            pick(4, bounds.min.z, bounds.max.z),
        );
        let offset = corner - plane.origin;
        let (u, v) = (offset.dot(plane.u), offset.dot(plane.v));
        umin = umin.min(u);
        umax = umax.max(u);
        vmin = vmin.min(v);
        vmax = vmax.max(v);
    }
    Ok(((umin, umax), (vmin, vmax)))
}

/// Classify every pixel: one ray per row along `u`, each pixel taking the
/// region whose stretch holds its centre, then the overlaps and voids.
fn classify(model: &Model, opts: &SliceOptions, view: &View, tolerance: f64) -> Classes {
    let plane = opts.plane;
    let (extent_w, extent_h) = view.extent;
    let (dx, dy) = view.pixel();
    let pad = 0.01 * extent_w + dx;
    let width = view.width;
    let air = |region: u32| model.is_air(region as usize);
    let rows: Vec<Classes> = (0..view.height)
        .into_par_iter()
        .map_init(
            || RayCheck::new(model),
            |ray_check, row| {
                let v = view.centre.1 + 0.5 * extent_h - (row as f64 + 0.5) * dy;
                let start =
                    plane.origin + plane.u * (view.centre.0 - 0.5 * extent_w - pad) + plane.v * v;
                let ray = Ray::new(start, plane.u);
                ray_check.run(&ray, 0.0, extent_w + 2.0 * pad, tolerance);
                let mut class = vec![0u32; width as usize];
                // The pixels whose centres lie between ray parameters a and b.
                let pixels = |a: f64, b: f64| {
                    let column =
                        |t: f64| ((t - pad) / dx - 0.5).ceil().clamp(0.0, width as f64) as usize;
                    column(a)..column(b)
                };
                for part in &ray_check.parts {
                    for c in &mut class[pixels(part.span.a.t, part.span.b.t)] {
                        if *c == 0 {
                            *c = part.region + 1;
                        }
                    }
                }
                let mut pairs = BTreeMap::new();
                for finding in &ray_check.findings {
                    let code = match finding.kind {
                        FindingKind::Overlap(a, b)
                            if !opts.strict_air && model.is_air_overlap(a as usize, b as usize) =>
                        {
                            // Air gives way: the solid region is drawn (two
                            // air regions: the first claim stays).
                            if air(a) != air(b) {
                                let solid = if air(a) { b } else { a };
                                for c in &mut class[pixels(finding.t0, finding.t1)] {
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
                    let covered = pixels(finding.t0, finding.t1);
                    if let FindingKind::Overlap(a, b) = finding.kind {
                        *pairs.entry((a, b)).or_insert(0) += covered.len() as u64;
                    }
                    for c in &mut class[covered] {
                        *c = code;
                    }
                }
                (class, pairs)
            },
        )
        .collect();
    let mut class = Vec::with_capacity(width as usize * view.height as usize);
    let mut pairs: BTreeMap<(u32, u32), u64> = BTreeMap::new();
    for (row_class, row_pairs) in rows {
        class.extend(row_class);
        for (pair, pixels) in row_pairs {
            *pairs.entry(pair).or_insert(0) += pixels;
        }
    }
    (class, pairs)
}

/// Colour the classified pixels: regions in `colours`, overlaps and voids
/// in stripes, the edges between classes darkened. Also the pixels of
/// every region and of the void.
fn paint(class: &[u32], width: u32, colours: &[[f32; 3]]) -> (Vec<[f32; 3]>, Vec<u64>, u64) {
    let columns = width as usize;
    let rows = class.len() / columns.max(1);
    let mut rgb = vec![[1.0f32; 3]; class.len()];
    let mut region_pixels = vec![0u64; colours.len()];
    let mut void_pixels = 0u64;
    for row in 0..rows {
        for column in 0..columns {
            let index = row * columns + column;
            let here = class[index];
            let stripe = ((column + row) / 4) % 2 == 0;
            let mut colour = match here {
                0 => [1.0; 3],
                Slice::OVERLAP => {
                    if stripe {
                        OVERLAP_COLOUR
                    } else {
                        [0.1, 0.0, 0.1]
                    }
                }
                Slice::VOID => {
                    void_pixels += 1;
                    if stripe {
                        VOID_COLOUR
                    } else {
                        [0.05, 0.05, 0.05]
                    }
                }
                region => {
                    region_pixels[(region - 1) as usize] += 1;
                    colours[(region - 1) as usize]
                }
            };
            let edge = (column + 1 < columns && class[index + 1] != here)
                || (row + 1 < rows && class[index + columns] != here);
            if edge {
                colour = colour.map(|x| x * 0.35);
            }
            rgb[index] = colour;
        }
    }
    (rgb, region_pixels, void_pixels)
}
