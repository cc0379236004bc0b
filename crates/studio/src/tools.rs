//! The answers to the page's questions about the model: what it holds, a
//! region picked, its volume, the overlaps, a section view, the surfaces a
//! ray crosses, and pictures written to files. Each returns JSON.

use crate::limits::{MAX_FRAMES_TO_FILE, MAX_SLICE_SIDE};
use crate::model::Model;
use crate::view::{Renderers, ViewRequest};
use base64::Engine as _;
use serde_json::{json, Value};
use std::path::Path;
use sv_check::{Plane, SliceOptions, UniverseChoice, VolumeOptions};
use sv_math::{DVec3, Ray};
use sv_render::{default_camera, frame_bounds, Renderer, ViewSpec};
use sv_scene::{Camera, Lens};
use sv_trace::Scratch;

fn hex(colour: [f64; 3]) -> String {
    let byte = |v: f64| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
    format!(
        "#{:02x}{:02x}{:02x}",
        byte(colour[0]),
        byte(colour[1]),
        byte(colour[2])
    )
}

/// The material of region `index` as the page lists it: its name, else
/// its code.
fn material_label(model: &Model, index: usize) -> String {
    let props = &model.scene.regions[index];
    match &props.material_name {
        Some(name) => name.clone(),
        None => format!("{}", props.material),
    }
}

/// What the page needs to show the model: its regions and materials, the
/// default view (azimuth 35°, elevation 25°) and the film's length.
pub fn summary(model: &Model, version: u64) -> Result<Value, String> {
    let scene = &model.scene;
    let (renderer, _) = Renderer::new(scene, 4.0 / 3.0).map_err(|e| e.to_string())?;
    let bounds = frame_bounds(renderer.prepared());
    let camera = default_camera(renderer.prepared(), 4.0 / 3.0, &ViewSpec::default());
    let centre = bounds.center();
    let regions: Vec<Value> = (0..scene.regions.len())
        .map(|index| {
            let props = &scene.regions[index];
            json!({
                "index": index,
                "name": scene.geometry.regions[index].name,
                "description": props.description,
                "material": material_label(model, index),
                "colour": hex(props.colour.unwrap_or([1.0; 3])),
                "hidden": props.transparent || props.outside,
            })
        })
        .collect();
    let (frames, fps) = match &model.film {
        Some(film) => (film.timeline.frame_count(), film.timeline.fps()),
        None => (0, 0.0),
    };
    Ok(json!({
        "type": "model",
        "version": version,
        "title": scene.title,
        "file": model.sources.first().map(|s| s.name.clone()).unwrap_or_default(),
        "units": scene.units.abbrev(),
        "regions": regions,
        "target": centre.to_array(),
        "distance": (camera.eye - centre).length(),
        "radius": 0.5 * bounds.diagonal(),
        "camera": scene.camera.as_ref().and_then(orbit_of),
        "frames": frames,
        "fps": fps,
        "notes": model.notes,
    }))
}

/// A scene's own camera as the page's orbit camera (target, azimuth,
/// elevation, distance, field of view), when it has `z` up and a
/// perspective lens.
fn orbit_of(camera: &Camera) -> Option<Value> {
    let distance = camera.dir.length();
    let upright = camera.up.normalize_or_zero().dot(DVec3::Z) > 0.999;
    if !(distance > 0.0 && distance.is_finite() && upright) {
        return None;
    }
    if let Lens::Ortho { .. } = camera.lens {
        return None;
    }
    let toward = -camera.dir / distance;
    Some(json!({
        "target": (camera.eye + camera.dir).to_array(),
        "az": toward.y.atan2(toward.x).to_degrees(),
        "el": toward.z.clamp(-1.0, 1.0).asin().to_degrees(),
        "distance": distance,
        "fov": 2.0 * camera.tan_half_fov().atan().to_degrees(),
    }))
}

/// Region `index` picked: names, description, material, its expression and
/// bodies, and where they are written.
pub fn pick(model: &Model, index: usize) -> Result<Value, String> {
    let geometry = &model.scene.geometry;
    let region = geometry
        .regions
        .get(index)
        .ok_or_else(|| format!("there is no region {index}"))?;
    let props = &model.scene.regions[index];
    let body_name = |b: usize| geometry.bodies[b].name.as_str();
    let mut bodies = Vec::new();
    region.for_each_term(&mut |term| {
        if !bodies.contains(&term.body) {
            bodies.push(term.body);
        }
    });
    let bodies: Vec<Value> = bodies
        .into_iter()
        .map(|b| {
            let body = &geometry.bodies[b];
            json!({
                "name": body.name,
                "type": body.kind.name(),
                "params": body.params,
                "written": written(model, &body.name, "BODY"),
            })
        })
        .collect();
    Ok(json!({
        "type": "pick",
        "index": index,
        "name": region.name,
        "number": index + 1,
        "description": props.description,
        "material": material_label(model, index),
        "density": props.density,
        "ident": props.ident,
        "air": props.air,
        "expression": region.expression(&body_name),
        "written": written(model, &region.name, "REGION"),
        "bodies": bodies,
    }))
}

fn written(model: &Model, name: &str, keyword: &str) -> Value {
    match model.written_at(name, keyword) {
        Some((file, line, text)) => json!({ "file": file, "line": line, "text": text }),
        None => Value::Null,
    }
}

/// The volume of region `index` by ray sampling, to 1 % (the whole
/// model's regions are sampled together, so this takes as long as
/// `volume` with `--rel-error 0.01`).
pub fn volume(model: &Model, index: usize) -> Result<Value, String> {
    let (check_model, _) =
        sv_check::Model::new(&model.scene, &UniverseChoice::None).map_err(|e| e.to_string())?;
    let opts = VolumeOptions {
        rel_error: 0.01,
        max_rays: 4_000_000,
        ..VolumeOptions::default()
    };
    let report = sv_check::volumes(&check_model, &opts).map_err(|e| e.to_string())?;
    let region = report
        .regions
        .get(index)
        .ok_or_else(|| format!("there is no region {index}"))?;
    Ok(json!({
        "type": "volume",
        "index": index,
        "unit": report.unit,
        "volume": region.volume,
        "error": region.error,
        "centroid": region.centroid,
        "mass_g": region.mass_g,
    }))
}

/// The overlapping pairs `check` finds, each with a point inside it.
pub fn check(model: &Model) -> Result<Value, String> {
    let (check_model, _) =
        sv_check::Model::new(&model.scene, &UniverseChoice::Auto).map_err(|e| e.to_string())?;
    let opts = sv_check::CheckOptions {
        strict_air: model.strict_air(),
        ..sv_check::CheckOptions::default()
    };
    let report = sv_check::check(&check_model, &opts).map_err(|e| e.to_string())?;
    let overlaps: Vec<Value> = report
        .overlaps
        .iter()
        .map(|o| {
            json!({
                "regions": o.regions,
                "indices": o.region_indices,
                "point": o.problem.point,
                "max_length": o.problem.max_length,
                "volume": o.problem.volume,
            })
        })
        .collect();
    Ok(json!({
        "type": "check",
        "overlaps": overlaps,
        "voids": report.voids.len(),
        "rays": report.grid_rays + report.random_rays,
        "seconds": report.seconds,
    }))
}

/// A section view through the plane with `normal` through `point`, as a
/// PNG (a data URL) with its legend.
pub fn slice(
    model: &Model,
    normal: [f64; 3],
    point: [f64; 3],
    size: (u32, u32),
) -> Result<Value, String> {
    let plane = Plane::new(DVec3::from_array(point), DVec3::from_array(normal))
        .ok_or("the section plane needs a finite point and a normal that is not zero")?;
    let (check_model, _) =
        sv_check::Model::new(&model.scene, &UniverseChoice::Auto).map_err(|e| e.to_string())?;
    let size = (
        size.0.clamp(16, MAX_SLICE_SIDE),
        size.1.clamp(16, MAX_SLICE_SIDE),
    );
    let opts = SliceOptions {
        plane,
        extent: None,
        size: Some(size),
        tolerance: None,
        strict_air: model.strict_air(),
        centre: None,
    };
    let section = sv_check::slice(&check_model, &opts).map_err(|e| e.to_string())?;
    let bytes: Vec<u8> = section
        .rgb
        .iter()
        .flat_map(|c| c.map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8))
        .collect();
    let picture = image::RgbImage::from_raw(section.width, section.height, bytes)
        .ok_or("a section picture of the wrong size")?;
    let mut png = Vec::new();
    picture
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .map_err(|e| e.to_string())?;
    let legend: Vec<Value> = section
        .legend
        .iter()
        .chain(&section.overlaps)
        .take(40)
        .map(|l| json!({ "label": l.label, "colour": l.colour }))
        .collect();
    Ok(json!({
        "type": "slice",
        "png": format!(
            "data:image/png;base64,{}",
            base64::engine::general_purpose::STANDARD.encode(&png)
        ),
        "legend": legend,
        "overlaps": section.overlaps.len(),
    }))
}

/// Every surface crossing along the ray through pixel (`x`, `y`) of the
/// view `view` (full-size pixels from the top left).
pub fn shoot(model: &Model, view: &ViewRequest, x: f64, y: f64) -> Result<Value, String> {
    let camera = view.camera().ok_or("no view yet")?;
    let ray = camera.rays(view.width, view.height).ray(x, y);
    let geometry = &model.scene.geometry;
    let (prepared, _) =
        sv_trace::Prepared::new(geometry, &Default::default()).map_err(|e| e.to_string())?;
    let mut scratch = Scratch::new(&prepared);
    let steps: Vec<Value> = prepared
        .walk(&Ray::new(ray.origin, ray.dir), 0.0, &mut scratch)
        .iter()
        .take(200)
        .map(|step| {
            let body = &geometry.bodies[step.body as usize];
            let after: Vec<&str> = step
                .regions_after
                .iter()
                .map(|r| geometry.regions[*r as usize].name.as_str())
                .collect();
            json!({
                "t": step.t,
                "entering": step.entering,
                "body": body.name,
                "kind": body.kind.name(),
                "after": after,
            })
        })
        .collect();
    Ok(json!({
        "type": "shoot",
        "from": ray.origin.to_array(),
        "dir": ray.dir.to_array(),
        "steps": steps,
    }))
}

/// Write the view (or film frames `first..=last` with the view's looks)
/// as PNGs into `output`, under names made here from the model's file
/// name.
pub fn render_to_file(
    model: &Model,
    view: &ViewRequest,
    frames: Option<(usize, usize)>,
    output: &Path,
) -> Result<Value, String> {
    let stem = model
        .sources
        .first()
        .and_then(|s| {
            Path::new(&s.name)
                .file_stem()
                .map(|n| n.to_string_lossy().into_owned())
        })
        .unwrap_or_else(|| "studio".into())
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect::<String>();
    std::fs::create_dir_all(output).map_err(|e| format!("{}: {e}", output.display()))?;
    let mut full = view.clone();
    full.moving = false;
    let numbers: Vec<Option<usize>> = match frames {
        Some((first, last)) => {
            if last < first || last - first >= MAX_FRAMES_TO_FILE {
                return Err(format!(
                    "a range of 1 to {MAX_FRAMES_TO_FILE} frames, first before last"
                ));
            }
            (first..=last).map(Some).collect()
        }
        None => vec![None],
    };
    let mut written = Vec::new();
    for number in numbers {
        let mut looks = full.looks.clone();
        if number.is_some() {
            looks.frame = number;
        }
        let scene = model.scene_at(looks.frame);
        let mut prepared = Renderers::new(&scene, &looks)?;
        let (frame, _) = prepared.render(&full).ok_or("the view is not valid")?;
        let picture = sv_output::to_rgb8(
            frame.width,
            frame.height,
            &frame.rgb,
            sv_output::Encoding::Linear,
        );
        let name = match number {
            Some(n) => format!("{stem}-frame-{n:05}.png"),
            None => format!("{stem}-view-{}.png", view.seq),
        };
        let path = output.join(name);
        picture
            .save(&path)
            .map_err(|e| format!("{}: {e}", path.display()))?;
        written.push(path.display().to_string());
    }
    Ok(json!({ "type": "written", "files": written }))
}
