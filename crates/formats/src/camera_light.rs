//! The CAMERA and LIGHT statements: one grammar, read by scenes and by the
//! director's scripts alike (and the lens values of a script's ZOOM).
//!
//! ```text
//! CAMERA [ORTHO [height] | PERSPECTIVE] EYE v (AT v | DIR v) [UP v]
//!        [FOV degrees | FOCAL f FILM h | HEIGHT h]
//! LIGHT name PARALLEL DIR v [INTENSITY i] [COLOR r g b]
//! LIGHT name POINT AT v [INTENSITY i] [DECAY n] [COLOR r g b]
//! ```
//!
//! The settings of a CAMERA come in any order, each at most once; a vector
//! is `(x, y, z)`, `x, y, z` or `x y z`. The lens is one of a field of view
//! (degrees, above 0 and below 180; 40 when none is given), a focal length
//! with the film height in the same units (FOCAL and FILM go together: no
//! film height is assumed), or for an ORTHO camera the visible height
//! (`HEIGHT h`, or `ORTHO h`). `ORTHOGRAPHIC` spells ORTHO and `SUN`
//! spells PARALLEL.

use crate::diag::{did_you_mean, Diagnostic};
use crate::text::{Cursor, Token};
use sv_math::DVec3;
use sv_scene::{Camera, Lens, Light, LightKind};

/// The words of a CAMERA statement, for suggestions.
const CAMERA_WORDS: &[&str] = &[
    "PERSPECTIVE",
    "ORTHO",
    "EYE",
    "AT",
    "DIR",
    "UP",
    "FOV",
    "FOCAL",
    "FILM",
    "HEIGHT",
];

/// A field of view in degrees: above 0 and below 180.
pub(crate) fn field_of_view(c: &mut Cursor) -> Result<f64, Diagnostic> {
    let (degrees, t) = c.number_token(Some("the field of view (degrees)"))?;
    if degrees > 0.0 && degrees < 180.0 {
        return Ok(degrees);
    }
    Err(c
        .error(
            &t,
            format!("field of view must lie between 0 and 180 degrees (is {degrees})"),
        )
        .with_hint("FOV is the vertical angle the picture spans, in degrees"))
}

/// A number above 0: `expected {what} above 0, found …`.
pub(crate) fn above_zero(c: &mut Cursor, what: &str) -> Result<f64, Diagnostic> {
    let what = format!("{what} above 0");
    let t = c.any(&what)?;
    match t.number() {
        Some(v) if v > 0.0 => Ok(v),
        _ => Err(c.expected(&t, &what)),
    }
}

/// A light's intensity: a number, not negative.
pub(crate) fn intensity(c: &mut Cursor) -> Result<f64, Diagnostic> {
    let (value, t) = c.number_token(Some("the intensity"))?;
    if value < 0.0 {
        return Err(c.error(&t, "an intensity cannot be negative"));
    }
    Ok(value)
}

/// The hint for FOCAL without FILM or the reverse.
pub(crate) const FILM_HINT: &str =
    "write both, in the same units: `FOCAL 50 FILM 24` is a 50 mm lens on 35 mm film";

/// A camera's settings as read, before they are checked together.
#[derive(Default)]
struct CameraWords<'a> {
    ortho: Option<Token<'a>>,
    eye: Option<DVec3>,
    at: Option<DVec3>,
    dir: Option<DVec3>,
    up: Option<DVec3>,
    fov: Option<f64>,
    focal: Option<(f64, Token<'a>)>,
    film: Option<(f64, Token<'a>)>,
    height: Option<(f64, Token<'a>)>,
}

/// The settings of a CAMERA statement, after the keyword.
pub(crate) fn camera(c: &mut Cursor) -> Result<Camera, Diagnostic> {
    let words = camera_words(c)?;
    let end = c.end();
    let eye = words.eye.ok_or_else(|| {
        c.error_at(end, "the camera needs an EYE point")
            .with_hint("CAMERA EYE (x,y,z) AT (x,y,z)")
    })?;
    let dir = match (words.at, words.dir) {
        (Some(at), None) => at - eye,
        (None, Some(dir)) => dir,
        _ => {
            return Err(c.error_at(
                end,
                "the camera needs exactly one of AT (aim point) or DIR (direction)",
            ))
        }
    };
    if dir.length_squared() == 0.0 {
        return Err(c.error_at(end, "the aim point coincides with the eye"));
    }
    Ok(Camera {
        eye,
        dir,
        up: words.up.unwrap_or(DVec3::Z),
        lens: lens(c, &words)?,
    })
}

/// Read every setting of a CAMERA, refusing unknown and repeated ones.
fn camera_words<'a>(c: &mut Cursor<'a>) -> Result<CameraWords<'a>, Diagnostic> {
    let mut words = CameraWords::default();
    let mut seen: Vec<&str> = Vec::new();
    while let Some(t) = c.advance() {
        let keyword = match t.word().map(str::to_ascii_uppercase).as_deref() {
            Some("ORTHOGRAPHIC") => "ORTHO",
            Some(w) => CAMERA_WORDS.iter().copied().find(|k| *k == w).unwrap_or(""),
            None => "",
        };
        if seen.contains(&keyword) {
            return Err(c
                .error(&t, format!("`{}` is given twice", t.text))
                .with_hint("give each camera setting once"));
        }
        seen.push(keyword);
        match keyword {
            "PERSPECTIVE" => {}
            "ORTHO" => {
                words.ortho = Some(t);
                // `ORTHO h` gives the visible height at once.
                if c.peek().is_some_and(|n| n.number().is_some()) {
                    words.height = Some((above_zero(c, "a height")?, t));
                    seen.push("HEIGHT");
                }
            }
            "EYE" => words.eye = Some(c.vector(Some("the eye point"))?),
            "AT" => words.at = Some(c.vector(Some("the aim point"))?),
            "DIR" => words.dir = Some(c.vector(Some("the view direction"))?),
            "UP" => words.up = Some(c.vector(Some("the up vector"))?),
            "FOV" => words.fov = Some(field_of_view(c)?),
            "FOCAL" => words.focal = Some((above_zero(c, "a focal length")?, t)),
            "FILM" => words.film = Some((above_zero(c, "a film height")?, t)),
            "HEIGHT" => words.height = Some((above_zero(c, "a height")?, t)),
            _ => {
                let mut d = c.error(&t, format!("unknown camera setting `{}`", t.shown()));
                if let Some(s) = did_you_mean(t.text, CAMERA_WORDS.iter().copied()) {
                    d = d.with_hint(format!("did you mean `{s}`?"));
                }
                return Err(d);
            }
        }
    }
    Ok(words)
}

/// The lens the settings describe.
fn lens(c: &Cursor, words: &CameraWords) -> Result<Lens, Diagnostic> {
    let end = c.end();
    if let (Some((_, t)), None) | (None, Some((_, t))) = (words.focal, words.film) {
        return Err(c
            .error(
                &t,
                "FOCAL needs FILM (the film height) and FILM needs FOCAL",
            )
            .with_hint(FILM_HINT));
    }
    let focal = words
        .focal
        .zip(words.film)
        .map(|((focal, _), (film, _))| Lens::Focal {
            focal,
            film_height: film,
        });
    let fov = words.fov.map(|vertical_deg| Lens::Fov { vertical_deg });
    if fov.is_some() && focal.is_some() {
        return Err(c
            .error_at(end, "the camera has two lenses, FOV and FOCAL")
            .with_hint("give one of FOV, FOCAL with FILM, or HEIGHT"));
    }
    let perspective = fov.or(focal);
    match (words.ortho, words.height, perspective) {
        (Some(_), Some((height, _)), None) => Ok(Lens::Ortho { height }),
        (Some(_), _, _) => Err(c.error_at(
            end,
            "an ORTHO camera needs HEIGHT (the visible height in model units)",
        )),
        (None, Some((_, t)), _) => {
            Err(c.error(&t, "HEIGHT belongs to ORTHO cameras; use FOV or FOCAL/FILM"))
        }
        (None, None, lens) => Ok(lens.unwrap_or(Lens::Fov { vertical_deg: 40.0 })),
    }
}

/// Three numbers for a colour, each from 0 to 1.
pub(crate) fn colour(c: &mut Cursor) -> Result<[f64; 3], Diagnostic> {
    Ok([
        fraction(c, "red")?,
        fraction(c, "green")?,
        fraction(c, "blue")?,
    ])
}

/// A number from 0 to 1: a colour's share, an ambient light.
pub(crate) fn fraction(c: &mut Cursor, what: &str) -> Result<f64, Diagnostic> {
    let (value, t) = c.number_token(Some(what))?;
    if !(0.0..=1.0).contains(&value) {
        return Err(c
            .error(&t, format!("{what} must lie between 0 and 1 (is {value})"))
            .with_hint("colours and ambient light are fractions of full brightness"));
    }
    Ok(value)
}

/// The rest of a LIGHT statement, after the keyword.
pub(crate) fn light(c: &mut Cursor) -> Result<Light, Diagnostic> {
    let name = c.any("a light name")?.text.to_string();
    let kind = c.any("PARALLEL or POINT")?;
    let parallel = match kind.text.to_ascii_uppercase().as_str() {
        "PARALLEL" | "SUN" if kind.word().is_some() => true,
        "POINT" if kind.word().is_some() => false,
        _ => return Err(c.expected(&kind, "PARALLEL or POINT")),
    };
    let (mut dir, mut pos, mut decay) = (None, None, 0.0);
    let mut light = Light {
        name,
        kind: LightKind::Parallel { dir: -DVec3::Z },
        intensity: 1.0,
        colour: [1.0; 3],
    };
    while let Some(t) = c.advance() {
        let word = t.word().map(str::to_ascii_uppercase).unwrap_or_default();
        match word.as_str() {
            "DIR" if parallel => dir = Some(c.vector(Some("the light direction"))?),
            "AT" if !parallel => pos = Some(c.vector(Some("the light position"))?),
            "DECAY" if !parallel => {
                let (value, t) = c.number_token(Some("the decay exponent n"))?;
                if value < 0.0 {
                    return Err(c
                        .error(
                            &t,
                            format!("a decay exponent cannot be negative (is {value})"),
                        )
                        .with_hint("0 keeps the intensity, 2 falls off as the inverse square"));
                }
                decay = value;
            }
            "INTENSITY" => light.intensity = intensity(c)?,
            "COLOR" | "COLOUR" => light.colour = colour(c)?,
            _ => {
                let hint = if parallel {
                    "a PARALLEL light takes DIR, INTENSITY, COLOR"
                } else {
                    "a POINT light takes AT, INTENSITY, DECAY, COLOR"
                };
                return Err(c
                    .error(&t, format!("unexpected `{}` in a light", t.shown()))
                    .with_hint(hint));
            }
        }
    }
    let end = c.end();
    light.kind = if parallel {
        let dir = dir.ok_or_else(|| {
            c.error_at(
                end,
                "a PARALLEL light needs DIR (the direction the light travels)",
            )
        })?;
        if dir.length_squared() == 0.0 {
            return Err(c.error_at(end, "the light direction is zero"));
        }
        LightKind::Parallel { dir }
    } else {
        LightKind::Point {
            pos: pos.ok_or_else(|| c.error_at(end, "a POINT light needs AT (its position)"))?,
            decay,
        }
    };
    Ok(light)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diag::SourceFile;
    use crate::text::{SCENE, SCRIPT};

    /// The camera of `text` (what follows CAMERA) read as a scene and as a
    /// script line: both must agree.
    fn read(text: &str) -> Result<Camera, String> {
        let src = SourceFile::new("t", text);
        let [scene, script] = [&SCENE, &SCRIPT].map(|syntax| {
            let mut c = Cursor::new(&src, 1, text, syntax);
            camera(&mut c).map_err(|d| d.message)
        });
        assert_eq!(scene, script, "scene and script disagree on {text}");
        scene
    }

    #[test]
    fn the_readme_forms_read() {
        let ortho = read("ORTHO EYE (10,10,10) AT (0,0,0) HEIGHT 12").unwrap();
        assert_eq!(ortho.lens, Lens::Ortho { height: 12.0 });
        assert_eq!(ortho.dir, DVec3::splat(-10.0));
        assert_eq!(read("EYE (10,10,10) AT (0,0,0) ORTHO 12").unwrap(), ortho);
        let focal = read("EYE (0,-20,0) DIR (0,1,0) FOCAL 50 FILM 24").unwrap();
        assert_eq!(
            focal.lens,
            Lens::Focal {
                focal: 50.0,
                film_height: 24.0
            }
        );
        let default = read("EYE 1 2 3 AT 0 0 0").unwrap();
        assert_eq!(default.lens, Lens::Fov { vertical_deg: 40.0 });
        assert_eq!(default.up, DVec3::Z);
    }

    #[test]
    fn lenses_are_checked_alike() {
        let eye = "EYE (0,-20,0) AT (0,0,0)";
        for (settings, message) in [
            (
                "FOV 200",
                "field of view must lie between 0 and 180 degrees (is 200)",
            ),
            (
                "FOCAL 50",
                "FOCAL needs FILM (the film height) and FILM needs FOCAL",
            ),
            (
                "FILM 24",
                "FOCAL needs FILM (the film height) and FILM needs FOCAL",
            ),
            (
                "FOCAL -5 FILM 24",
                "expected a focal length above 0, found `-5`",
            ),
            (
                "FOV 30 FOCAL 50 FILM 24",
                "the camera has two lenses, FOV and FOCAL",
            ),
            (
                "HEIGHT 3",
                "HEIGHT belongs to ORTHO cameras; use FOV or FOCAL/FILM",
            ),
            (
                "ORTHO",
                "an ORTHO camera needs HEIGHT (the visible height in model units)",
            ),
            ("FOV 30 FOV 20", "`FOV` is given twice"),
            ("FOVV 30", "unknown camera setting `FOVV`"),
        ] {
            assert_eq!(
                read(&format!("{eye} {settings}")),
                Err(message.into()),
                "{settings}"
            );
        }
        assert_eq!(
            read("EYE (1,1,1) AT (1,1,1)"),
            Err("the aim point coincides with the eye".into())
        );
    }
}
