//! The change commands of a script (MOVE, TURN, SPIN, STOP, AIM, TRACK,
//! ZOOM, INTENSITY), their timing, and the values they are made of.

use super::ast::{AimAst, CmdKind, Duration, Name, TargetAst};
use crate::camera_light::{above_zero, field_of_view, intensity};
use crate::diag::Diagnostic;
use crate::text::Cursor;
use sv_director::{Easing, Zoom};
use sv_math::DVec3;

type PResult<T> = Result<T, Diagnostic>;

/// A name: a word.
pub(super) fn read_name(line: &mut Cursor, what: &str) -> PResult<Name> {
    line.word(what).map(|t| Name::of(&t))
}

/// A whole number from 1 to `max`.
pub(super) fn count(line: &mut Cursor, what: &str, max: usize) -> PResult<usize> {
    let t = line.any(what)?;
    match t.word().and_then(|w| w.parse::<usize>().ok()) {
        Some(n) if n >= 1 && n <= max => Ok(n),
        _ => Err(line.expected(&t, &format!("{what} from 1 to {max}"))),
    }
}

/// `(x, y, z)`: the parentheses are required, the commas optional.
pub(super) fn triple(line: &mut Cursor) -> PResult<DVec3> {
    match line.peek() {
        Some(t) if t.is_punct('(') => line.vector(None),
        _ => line.expect_punct('(').map(|_| DVec3::ZERO),
    }
}

/// `(AXIS a, degrees)`, `AXIS` and the comma optional.
fn axis_angle(line: &mut Cursor) -> PResult<(Name, f64)> {
    line.expect_punct('(')?;
    line.eat("AXIS");
    let axis = read_name(line, "an axis name")?;
    line.eat_punct(',');
    let degrees = line.number(None)?;
    line.expect_punct(')')?;
    Ok((axis, degrees))
}

/// What MOVE and TURN act on.
fn target(line: &mut Cursor) -> PResult<TargetAst> {
    const WHAT: &str = "an object, `CAMERA` or `LIGHT name`";
    let t = line.any(WHAT)?;
    if t.is("CAMERA") {
        Ok(TargetAst::Camera(t.span))
    } else if t.is("LIGHT") {
        Ok(TargetAst::Light(read_name(line, "a light name")?))
    } else if t.word().is_some() {
        Ok(TargetAst::Named(Name::of(&t)))
    } else {
        Err(line.expected(&t, WHAT))
    }
}

/// `OVER n [FRAMES]` or `OVER x SECONDS`, then `SMOOTH` or `LINEAR`.
pub(super) fn timing(line: &mut Cursor) -> PResult<Option<(Duration, Easing)>> {
    if !line.eat("OVER") {
        return Ok(None);
    }
    let t = line.any("a number of frames or seconds")?;
    let duration = if line.eat("SECONDS") || line.eat("SECOND") || line.eat("S") {
        match t.number().filter(|v| *v > 0.0) {
            Some(seconds) => Duration::Seconds(seconds),
            None => return Err(line.expected(&t, "a number of seconds above 0")),
        }
    } else {
        let _ = line.eat("FRAMES") || line.eat("FRAME");
        match t.word().and_then(|w| w.parse::<usize>().ok()) {
            Some(n) if (1..=sv_director::MAX_FRAMES).contains(&n) => Duration::Frames(n),
            _ => {
                let what = format!(
                    "a whole number of frames from 1 to {}",
                    sv_director::MAX_FRAMES
                );
                return Err(line.expected(&t, &what));
            }
        }
    };
    let easing = if line.eat("SMOOTH") {
        Easing::Smooth
    } else {
        line.eat("LINEAR");
        Easing::Linear
    };
    Ok(Some((duration, easing)))
}

/// A change command, after its keyword `word` (upper case).
pub(super) fn command(line: &mut Cursor, word: &str) -> PResult<CmdKind> {
    Ok(match word {
        "MOVE" => {
            let target = target(line)?;
            CmdKind::Move(target, triple(line)?)
        }
        "TURN" => {
            let target = target(line)?;
            let (axis, degrees) = axis_angle(line)?;
            CmdKind::Turn(target, axis, degrees)
        }
        "SPIN" => {
            let object = read_name(line, "an object name")?;
            let (axis, degrees) = axis_angle(line)?;
            if line.eat("PER") {
                line.expect("FRAME")?;
            }
            CmdKind::Spin(object, axis, degrees)
        }
        "STOP" => {
            let stopped = read_name(line, "an object name or `CAMERA`")?;
            if stopped.text.eq_ignore_ascii_case("CAMERA")
                || stopped.text.eq_ignore_ascii_case("TRACK")
            {
                CmdKind::StopTrack
            } else {
                CmdKind::Stop(stopped)
            }
        }
        "AIM" => {
            line.eat("CAMERA");
            line.expect("AT")?;
            if line.peek().is_some_and(|t| t.is_punct('(')) {
                CmdKind::Aim(AimAst::Point(triple(line)?))
            } else {
                CmdKind::Aim(AimAst::Object(read_name(
                    line,
                    "a point or an object name",
                )?))
            }
        }
        "TRACK" => {
            // `TRACK CAMERA` alone tracks an object named CAMERA.
            if line.peek_second().is_some() {
                line.eat("CAMERA");
            }
            CmdKind::Track(read_name(line, "an object name")?)
        }
        "ZOOM" => zoom(line)?,
        _ => {
            // INTENSITY
            line.eat("LIGHT");
            let light = read_name(line, "a light name")?;
            CmdKind::Intensity(light, intensity(line)?)
        }
    })
}

/// `ZOOM [CAMERA] FOV degrees | FOCAL f [FILM h] | HEIGHT h`: the lens
/// values read as a CAMERA reads them.
fn zoom(line: &mut Cursor) -> PResult<CmdKind> {
    const WHAT: &str = "`FOV`, `FOCAL` or `HEIGHT`";
    line.eat("CAMERA");
    let t = line.any(WHAT)?;
    let zoom = if t.is("FOV") {
        Zoom::Fov(field_of_view(line)?)
    } else if t.is("FOCAL") {
        let focal = above_zero(line, "a focal length")?;
        let film_height = if line.eat("FILM") {
            Some(above_zero(line, "a film height")?)
        } else {
            None
        };
        Zoom::Focal { focal, film_height }
    } else if t.is("HEIGHT") {
        Zoom::Height(above_zero(line, "a height")?)
    } else {
        return Err(line.expected(&t, WHAT));
    };
    Ok(CmdKind::Zoom(zoom, t.span))
}
