//! `synthavision export`: write a scene as a POV-Ray scene or in the native
//! scene language.

use crate::args::{ExportArgs, ExportFormat};
use crate::load::{input, load, renderer, size, CliError};
use std::process::ExitCode;

/// Run `export`. The camera and lights written to a POV-Ray scene are the
/// ones `render` would use with the same options (the default framing and
/// light when the scene has none); a native scene gets them only when view
/// options are given.
pub fn export(a: ExportArgs) -> Result<ExitCode, CliError> {
    let mut scene = load(Some(&a.scene), &a.input)?;
    let (w, h) = size(&a.view, &scene)?;
    let v = &a.view;
    let view_given = v.ortho
        || v.az.is_some()
        || v.el.is_some()
        || v.eye.is_some()
        || v.at.is_some()
        || v.fov.is_some()
        || v.eye_light;
    if a.format == ExportFormat::Pov || view_given {
        let r = renderer(&scene, v, w, h)?;
        scene.camera = Some(r.camera);
        scene.lights = r.lights.clone();
        if v.eye_light {
            scene.ambient = 0.0;
        }
    }
    if v.no_shadows {
        scene.shadows = false;
    }
    if v.size.is_some() {
        scene.size = Some((w, h));
    }
    let text = match a.format {
        ExportFormat::Pov => sv_formats::pov::write(&scene, w, h).map_err(|e| {
            input(format!(
                "cannot write `{}` for POV-Ray:\n{e}",
                a.scene.display()
            ))
        })?,
        ExportFormat::Sv => sv_formats::native::write(&scene),
    };
    sv_output::write_atomic(&a.output, |f| f.write_all(text.as_bytes()))
        .map_err(|e| CliError::Runtime(format!("error: {e}")))?;
    Ok(ExitCode::SUCCESS)
}
