//! `synthavision export`: write a scene as a POV-Ray scene or in the native
//! scene language.

use crate::args::{InputArgs, ViewArgs};
use crate::error::{bad_input, runtime, CliError};
use crate::load::load;
use crate::view::{renderer, size};
use clap::Args;
use std::path::PathBuf;
use std::process::ExitCode;
use sv_scene::{Light, LightKind, RegionProps};

/// Output formats of `export`.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExportFormat {
    /// POV-Ray 3.7 scene.
    Pov,
    /// SynthaVision scene language.
    Sv,
}

#[derive(Args, Debug)]
pub struct ExportArgs {
    /// Scene, deck or FLUKA, MCNP or OpenMC input (`-`: standard input).
    pub scene: PathBuf,
    /// Output format.
    #[arg(long, value_enum)]
    pub format: ExportFormat,
    /// Output file.
    #[arg(short, long)]
    pub output: PathBuf,
    #[command(flatten)]
    pub input: InputArgs,
    #[command(flatten)]
    pub view: ViewArgs,
}

/// Run `export`. The camera and lights written to a POV-Ray scene are the
/// ones `render` would use with the same options (the default framing and
/// light when the scene has none); a native scene gets them only when view
/// options are given.
pub fn export(args: ExportArgs) -> Result<ExitCode, CliError> {
    let mut scene = load(Some(&args.scene), &args.input)?.scene;
    let (width, height) = size(&args.view, &scene)?;
    let view = &args.view;
    let view_given = view.ortho
        || view.az.is_some()
        || view.el.is_some()
        || view.eye.is_some()
        || view.at.is_some()
        || view.fov.is_some()
        || view.up.is_some()
        || view.view_size.is_some()
        || view.eye_light
        || view.rt;
    if args.format == ExportFormat::Pov || view_given {
        let renderer = renderer(&scene, view, width, height)?;
        scene.camera = Some(renderer.camera);
        scene.lights = renderer.lights.clone();
        if view.eye_light || view.rt {
            // rt -l1 as the paper's formula: a light along the view and
            // ambient 0.4 give 0.4 + 0.6·cos θ for the default k = 0.8.
            scene.lights = vec![Light {
                name: "EYE".into(),
                kind: LightKind::Parallel {
                    dir: renderer.camera.dir,
                },
                intensity: 0.6 / RegionProps::DEFAULT_K,
                colour: [1.0; 3],
            }];
            scene.ambient = 0.4;
            if scene.regions.iter().any(|r| r.k != RegionProps::DEFAULT_K) {
                eprintln!(
                    "note: regions whose reflectance is not {} are shaded by their own k in the written scene, not as rt -l1 shades them",
                    RegionProps::DEFAULT_K
                );
            }
        }
    }
    if view.no_shadows {
        scene.shadows = false;
    }
    if view.size.is_some() {
        scene.size = Some((width, height));
    }
    let text = match args.format {
        ExportFormat::Pov => sv_formats::pov::write(&scene, width, height).map_err(|e| {
            bad_input(format!(
                "cannot write `{}` for POV-Ray:\n{e}",
                args.scene.display()
            ))
        })?,
        ExportFormat::Sv => sv_formats::native::write(&scene),
    };
    sv_output::write_atomic(&args.output, |f| f.write_all(text.as_bytes())).map_err(runtime)?;
    Ok(ExitCode::SUCCESS)
}
