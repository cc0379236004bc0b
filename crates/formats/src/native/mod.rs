//! The native scene language (`.sv`).
//!
//! Line oriented, keywords case-insensitive, `#` starts a comment. Values
//! are separated by spaces; commas and parentheses may be used to group
//! vectors for readability: `(0, 0, 1)` is the same as `0 0 1`.
//!
//! ```text
//! TITLE  Figure 1 of the paper
//! UNITS  in
//! BODY 1 SPH  (0,0,0) 1.0                  # sphere: centre, radius
//! BODY 2 RCC  (0.45,-0.2,-1.4) (0,0,2.8) 0.6
//! REGION D = +1 -2   COLOR 0.9 0.5 0.2  K 0.9
//! REGION E = +2 -1 OR +3                    # OR unions zones
//! REGION C TRANSPARENT                      # change a region defined earlier
//! INCLUDE "deck.cg"                         # .sv, COMGEOM or FLUKA
//! CAMERA EYE (9,-13,6.5) AT (-1.6,0,2) UP (0,0,1) FOV 46
//! CAMERA ORTHO EYE (10,10,10) AT (0,0,0) HEIGHT 12
//! CAMERA EYE (0,-20,0) DIR (0,1,0) FOCAL 50 FILM 24
//! LIGHT SUN  PARALLEL DIR (0.6,1,-1.5) INTENSITY 0.85
//! LIGHT LAMP POINT AT (0,0,10) INTENSITY 100 DECAY 2 COLOR 1 0.9 0.8
//! AMBIENT 0.15
//! BACKGROUND 0.1            # or three values for a colour
//! SHADOWS OFF
//! SIZE 960 720
//! ```

mod geometry;
mod include;
mod merge;
mod write;

pub use merge::{merge, Clash, MergeError};
pub use write::write;

use crate::camera_light;
use crate::diag::{did_you_mean, Diagnostic, Diagnostics, SourceFile};
use crate::text::{Cursor, Token, SCENE};
use crate::{LoadOptions, Loaded};
use std::collections::HashMap;
use std::path::PathBuf;
use sv_geom::BodyKind;
use sv_scene::{Background, Scene, Units};

/// The statement keywords, for suggestions.
pub const KEYWORDS: &[&str] = &[
    "TITLE",
    "UNITS",
    "BODY",
    "REGION",
    "INCLUDE",
    "CAMERA",
    "LIGHT",
    "AMBIENT",
    "BACKGROUND",
    "SHADOWS",
    "SIZE",
];

/// Read a scene file.
pub fn read(src: &SourceFile, opts: &LoadOptions) -> Result<Loaded, Diagnostics> {
    let mut session = Session {
        opts,
        diags: Diagnostics::default(),
        warnings: Vec::new(),
        includes: vec![PathBuf::from(&src.name)],
    };
    let file = session.read_file(src);
    if file.scene.geometry.regions.is_empty() && !session.diags.has_errors() {
        // An empty model would draw a black picture over the output, as
        // if all were well; decks without regions are refused alike.
        let message = if file.scene.geometry.bodies.is_empty() {
            "the scene has no bodies and no regions: there is nothing to draw"
        } else {
            "the scene has bodies but no region: there is nothing to draw"
        };
        session.diags.push(
            Diagnostic::error_at(src, 1, 1, 0, message)
                .with_hint("a region makes bodies visible: `REGION name = +body`"),
        );
    }
    if session.diags.has_errors() {
        return Err(session.diags);
    }
    let mut warnings = session.warnings;
    warnings.extend(session.diags.items);
    Ok(Loaded {
        scene: file.scene,
        warnings,
        format: crate::Format::Native,
    })
}

/// What the files of one reading share: the options, every diagnostic and
/// the chain of files being included.
struct Session<'a> {
    opts: &'a LoadOptions,
    diags: Diagnostics,
    /// Warnings of included decks.
    warnings: Vec<Diagnostic>,
    /// The file read and the files it is including, outermost first.
    includes: Vec<PathBuf>,
}

/// One scene file as read so far.
#[derive(Default)]
struct File {
    scene: Scene,
    /// Whether the file has said its units (or taken them from a deck).
    units_set: bool,
    names: Names,
}

/// Name → index maps of the scene being read, kept in step with it, so a
/// look-up costs O(1): a linear search per reference made reading a
/// 100,000-body scene quadratic.
#[derive(Default)]
struct Names {
    bodies: HashMap<String, usize>,
    regions: HashMap<String, usize>,
}

impl Names {
    /// Take in bodies and regions added since the last call.
    fn sync(&mut self, scene: &Scene) {
        let geometry = &scene.geometry;
        for (i, b) in geometry.bodies.iter().enumerate().skip(self.bodies.len()) {
            self.bodies.entry(b.name.clone()).or_insert(i);
        }
        for (i, r) in geometry.regions.iter().enumerate().skip(self.regions.len()) {
            self.regions.entry(r.name.clone()).or_insert(i);
        }
    }
}

impl Session<'_> {
    /// Read the statements of one file; every error goes to `self.diags`.
    fn read_file(&mut self, src: &SourceFile) -> File {
        let mut file = File::default();
        for (i, text) in src.text.lines().enumerate() {
            let mut line = Cursor::new(src, i + 1, text, &SCENE);
            let Some(keyword) = line.advance() else {
                continue;
            };
            file.names.sync(&file.scene);
            match self.statement(src, &mut file, &mut line, keyword, text) {
                Err(d) => self.diags.push(d),
                Ok(()) => {
                    if let Err(d) = line.finish() {
                        self.diags.push(d);
                    }
                }
            }
        }
        file
    }

    /// One statement, whose keyword is taken.
    fn statement(
        &mut self,
        src: &SourceFile,
        file: &mut File,
        line: &mut Cursor,
        keyword: Token,
        text: &str,
    ) -> Result<(), Diagnostic> {
        let scene = &mut file.scene;
        match keyword.text.to_ascii_uppercase().as_str() {
            "TITLE" => {
                let after = text.to_ascii_uppercase().find("TITLE").unwrap_or(0) + 5;
                scene.title = text[after..].trim().to_string();
                line.skip_rest();
                Ok(())
            }
            "UNITS" => units(line, file),
            "BODY" => geometry::body(line, scene, &file.names, &mut self.warnings),
            "REGION" => geometry::region(line, scene, &file.names),
            "INCLUDE" => {
                let name = line.any("a file name in quotes")?;
                self.include(src, &name, file);
                Ok(())
            }
            "CAMERA" => camera_light::camera(line).map(|c| scene.camera = Some(c)),
            "LIGHT" => camera_light::light(line).map(|light| {
                scene
                    .lights
                    .retain(|old| !old.name.eq_ignore_ascii_case(&light.name));
                scene.lights.push(light)
            }),
            "AMBIENT" => {
                camera_light::fraction(line, "the ambient intensity").map(|a| scene.ambient = a)
            }
            "BACKGROUND" => background(line, scene),
            "SHADOWS" => shadows(line, scene),
            "SIZE" => size(line, scene),
            _ => Err(unknown_statement(line, &keyword)),
        }
    }
}

fn units(line: &mut Cursor, file: &mut File) -> Result<(), Diagnostic> {
    let t = line.any("a unit (in, ft, mm, cm, m)")?;
    let Some(units) = Units::parse(t.text) else {
        return Err(line
            .error(&t, format!("unknown unit `{}`", t.text))
            .with_hint("use one of in, ft, mm, cm, m"));
    };
    if !file.scene.geometry.bodies.is_empty() && units != file.scene.units {
        return Err(line.error(&t, "UNITS must come before the first body or INCLUDE"));
    }
    file.scene.units = units;
    file.units_set = true;
    Ok(())
}

/// `BACKGROUND grey` or `BACKGROUND r g b`.
fn background(line: &mut Cursor, scene: &mut Scene) -> Result<(), Diagnostic> {
    let grey = camera_light::fraction(line, "the background intensity")?;
    let colour = if line.peek().is_some() {
        [
            grey,
            camera_light::fraction(line, "green")?,
            camera_light::fraction(line, "blue")?,
        ]
    } else {
        [grey; 3]
    };
    scene.background = Background::Colour(colour);
    Ok(())
}

fn shadows(line: &mut Cursor, scene: &mut Scene) -> Result<(), Diagnostic> {
    let t = line.any("ON or OFF")?;
    scene.shadows = match t.text.to_ascii_uppercase().as_str() {
        "ON" => true,
        "OFF" => false,
        _ => return Err(line.error(&t, format!("expected ON or OFF, found `{}`", t.text))),
    };
    Ok(())
}

fn size(line: &mut Cursor, scene: &mut Scene) -> Result<(), Diagnostic> {
    let (width, first) = line.number_token(Some("the width"))?;
    let height = line.number(Some("the height"))?;
    let whole = |v: f64| (1.0..=65536.0).contains(&v) && v.fract() == 0.0;
    if !whole(width) || !whole(height) {
        return Err(line.error(&first, "picture size must be whole numbers from 1 to 65536"));
    }
    scene.size = Some((width as u32, height as u32));
    Ok(())
}

fn unknown_statement(line: &mut Cursor, keyword: &Token) -> Diagnostic {
    line.skip_rest();
    let word = keyword.text;
    let d = line.error(keyword, format!("unknown statement `{word}`"));
    if let Some(s) = did_you_mean(word, KEYWORDS.iter().copied()) {
        d.with_hint(format!("did you mean `{s}`?"))
    } else if BodyKind::from_name(word).is_some() {
        d.with_hint(format!(
            "bodies are written `BODY name {} values…`",
            word.to_ascii_uppercase()
        ))
    } else {
        d
    }
}
