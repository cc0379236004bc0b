//! The model the studio shows: a scene, deck or input (or a director's
//! script and its scene) read from the one file opened, with what the page
//! lists about it and where each region and body is written.

use serde::Serialize;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::SystemTime;
use sv_formats::script::{load_script, Film};
use sv_formats::{Diagnostics, Format, LoadError, LoadOptions, SourceFile};
use sv_scene::Scene;

/// The bundled default scene: the paper's helicopter.
pub const HELICOPTER: &str = include_str!("../../../examples/helicopter/helicopter.sv");

/// Where the model comes from.
#[derive(Clone, Debug)]
pub enum Origin {
    /// A file on disk (watched for changes).
    File(PathBuf),
    /// The bundled helicopter.
    Bundled,
}

/// A model loaded: the scene (a film's scene at its start) and, for a
/// director's script, the film.
pub struct Model {
    /// The scene.
    pub scene: Scene,
    /// The film, when the file is a director's script.
    pub film: Option<Film>,
    /// The input format (a film's scene is read as its files say).
    pub format: Format,
    /// The texts read, by name, for finding where things are written.
    pub sources: Vec<SourceFile>,
    /// The files to watch for changes.
    pub watched: Vec<PathBuf>,
    /// Notes and warnings met while reading.
    pub notes: Vec<String>,
}

/// One problem with the file, located, for the page.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Problem {
    /// The file's name.
    pub file: String,
    /// 1-based line (0 when the problem has no place).
    pub line: usize,
    /// 1-based column.
    pub column: usize,
    /// What is wrong.
    pub message: String,
    /// The whole report: the line, a caret and the hint.
    pub text: String,
}

impl Model {
    /// Read the model from `origin`. A `.svs` file is a director's script.
    pub fn load(origin: &Origin) -> Result<Model, Vec<Problem>> {
        let opts = LoadOptions::default();
        match origin {
            Origin::Bundled => {
                let source = SourceFile::new("helicopter.sv (bundled)", HELICOPTER);
                let loaded =
                    sv_formats::load_source(&source, Format::Native, &opts).map_err(problems)?;
                Ok(Model::from_scene(loaded, vec![source], Vec::new()))
            }
            Origin::File(path) if is_script(path) => {
                let film = load_script(path, &opts).map_err(problems)?;
                let mut sources = vec![film.source.clone()];
                sources.extend(film.scene_paths.iter().filter_map(|p| read_source(p)));
                let mut watched = vec![path.clone()];
                watched.extend(film.scene_paths.iter().cloned());
                let mut scene = film.scene.clone();
                scene.show_air_if_nothing_else();
                let notes = film.warnings.iter().map(|w| w.to_string()).collect();
                Ok(Model {
                    scene,
                    film: Some(film),
                    format: Format::Native,
                    sources,
                    watched,
                    notes,
                })
            }
            Origin::File(path) => {
                let loaded = sv_formats::load_file(path, &opts).map_err(problems)?;
                let sources = read_source(path).into_iter().collect();
                Ok(Model::from_scene(loaded, sources, vec![path.clone()]))
            }
        }
    }

    fn from_scene(
        loaded: sv_formats::Loaded,
        sources: Vec<SourceFile>,
        watched: Vec<PathBuf>,
    ) -> Model {
        let mut scene = loaded.scene;
        scene.show_air_if_nothing_else();
        let mut notes: Vec<String> = loaded.warnings.iter().map(|w| w.to_string()).collect();
        notes.extend(scene.notes.iter().cloned());
        Model {
            scene,
            film: None,
            format: loaded.format,
            sources,
            watched,
            notes,
        }
    }

    /// Whether overlaps with air regions count (FLUKA, MCNP and OpenMC
    /// have no rule that air gives way).
    pub fn strict_air(&self) -> bool {
        matches!(self.format, Format::Fluka | Format::Mcnp | Format::OpenMc)
    }

    /// The scene at film frame `frame` (the scene itself without a film
    /// or a frame, or past the film's end).
    pub fn scene_at(&self, frame: Option<usize>) -> Scene {
        match (&self.film, frame) {
            (Some(film), Some(frame)) if frame < film.timeline.frame_count() => {
                let mut scene = film.scene_at(frame);
                scene.show_air_if_nothing_else();
                scene
            }
            _ => self.scene.clone(),
        }
    }

    /// Where `name` is defined: the first line of the texts read whose
    /// first word, or the word after `REGION`/`BODY`, is `name` (the
    /// readers keep no places, so the text is searched), as
    /// `(file, line, the line)`.
    pub fn written_at(&self, name: &str, keyword: &str) -> Option<(String, usize, String)> {
        for source in &self.sources {
            for (index, line) in source.text.lines().enumerate() {
                let mut words = line.split_whitespace();
                let first = words.next().unwrap_or("");
                let named = if first.eq_ignore_ascii_case(keyword) {
                    words.next() == Some(name)
                } else {
                    first == name
                };
                if named {
                    return Some((source.name.clone(), index + 1, line.trim_end().to_string()));
                }
            }
        }
        None
    }
}

/// The modification times (and lengths) of `paths`, to notice a change.
pub fn stamps(paths: &[PathBuf]) -> Vec<Option<(SystemTime, u64)>> {
    paths
        .iter()
        .map(|p| {
            let meta = std::fs::metadata(p).ok()?;
            Some((meta.modified().ok()?, meta.len()))
        })
        .collect()
}

fn is_script(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("svs"))
}

fn read_source(path: &Path) -> Option<SourceFile> {
    let bytes = std::fs::read(path).ok()?;
    Some(SourceFile::new(
        path.display().to_string(),
        Arc::<str>::from(String::from_utf8_lossy(&bytes).as_ref()),
    ))
}

/// The problems of a failed load, located.
fn problems(error: LoadError) -> Vec<Problem> {
    match error {
        LoadError::Io { path, source } => vec![Problem {
            file: path.display().to_string(),
            line: 0,
            column: 0,
            message: format!("cannot read {}: {source}", path.display()),
            text: format!("cannot read {}: {source}", path.display()),
        }],
        LoadError::Invalid(diagnostics) => located(&diagnostics),
    }
}

fn located(diagnostics: &Diagnostics) -> Vec<Problem> {
    diagnostics
        .errors()
        .map(|d| {
            let (line, column) = d.line_col();
            Problem {
                file: d.source.name.clone(),
                line,
                column,
                message: d.message.clone(),
                text: d.render_plain(),
            }
        })
        .collect()
}
