//! Writing a scene in the scene language.

use sv_math::DVec3;
use sv_scene::{Background, Lens, LightKind, Scene};

fn fmt_num(v: f64) -> String {
    // Shortest text that reads back to the same f64.
    let s = format!("{v}");
    if s.parse::<f64>().ok() == Some(v) {
        s
    } else {
        format!("{v:e}")
    }
}

/// Write a scene in the native language; reading it back gives the same
/// scene (bodies, regions, properties, camera, lights).
pub fn write(scene: &Scene) -> String {
    let mut s = String::new();
    if !scene.title.is_empty() {
        s.push_str(&format!("TITLE {}\n", scene.title));
    }
    s.push_str(&format!("UNITS {}\n\n", scene.units.abbrev()));
    let names: Vec<String> = scene
        .geometry
        .bodies
        .iter()
        .map(|b| quote_name(&b.name))
        .collect();
    for (b, n) in scene.geometry.bodies.iter().zip(&names) {
        let vals: Vec<String> = b.params.iter().map(|v| fmt_num(*v)).collect();
        s.push_str(&format!("BODY {n} {} {}\n", b.kind, vals.join(" ")));
    }
    s.push('\n');
    for (r, p) in scene.geometry.regions.iter().zip(&scene.regions) {
        let zones: Vec<String> = r
            .zones
            .iter()
            .map(|z| z.expression(|b| &names[b]))
            .collect();
        s.push_str(&format!(
            "REGION {} = {}",
            quote_name(&r.name),
            zones.join(" OR ")
        ));
        if let Some(c) = p.colour {
            s.push_str(&format!(
                " COLOR {} {} {}",
                fmt_num(c[0]),
                fmt_num(c[1]),
                fmt_num(c[2])
            ));
        }
        s.push_str(&format!(" K {}", fmt_num(p.k)));
        if p.transparent {
            s.push_str(" TRANSPARENT");
        }
        if let Some(d) = p.density {
            s.push_str(&format!(" DENSITY {}", fmt_num(d)));
        }
        s.push('\n');
    }
    s.push('\n');
    let v = |d: DVec3| format!("({}, {}, {})", fmt_num(d.x), fmt_num(d.y), fmt_num(d.z));
    if let Some(c) = &scene.camera {
        let lens = match c.lens {
            Lens::Fov { vertical_deg } => format!("FOV {}", fmt_num(vertical_deg)),
            Lens::Focal { focal, film_height } => {
                format!("FOCAL {} FILM {}", fmt_num(focal), fmt_num(film_height))
            }
            Lens::Ortho { height } => format!("HEIGHT {}", fmt_num(height)),
        };
        let ortho = if matches!(c.lens, Lens::Ortho { .. }) {
            "ORTHO "
        } else {
            ""
        };
        s.push_str(&format!(
            "CAMERA {ortho}EYE {} DIR {} UP {} {lens}\n",
            v(c.eye),
            v(c.dir),
            v(c.up)
        ));
    }
    for l in &scene.lights {
        let kind = match l.kind {
            LightKind::Parallel { dir } => format!("PARALLEL DIR {}", v(dir)),
            LightKind::Point { pos, decay } => {
                format!("POINT AT {} DECAY {}", v(pos), fmt_num(decay))
            }
        };
        s.push_str(&format!(
            "LIGHT {} {kind} INTENSITY {} COLOR {} {} {}\n",
            l.name,
            fmt_num(l.intensity),
            fmt_num(l.colour[0]),
            fmt_num(l.colour[1]),
            fmt_num(l.colour[2])
        ));
    }
    s.push_str(&format!("AMBIENT {}\n", fmt_num(scene.ambient)));
    let Background::Colour(bg) = scene.background;
    s.push_str(&format!(
        "BACKGROUND {} {} {}\n",
        fmt_num(bg[0]),
        fmt_num(bg[1]),
        fmt_num(bg[2])
    ));
    s.push_str(&format!(
        "SHADOWS {}\n",
        if scene.shadows { "ON" } else { "OFF" }
    ));
    if let Some((w, h)) = scene.size {
        s.push_str(&format!("SIZE {w} {h}\n"));
    }
    s
}

fn quote_name(n: &str) -> String {
    // Names are single tokens; anything else is replaced so the file reads back.
    let ok = !n.is_empty()
        && n.chars().all(|c| {
            !c.is_whitespace() && !matches!(c, ',' | '(' | ')' | '#' | '=' | '"' | '+' | '-')
        });
    if ok {
        n.to_string()
    } else {
        n.chars()
            .map(|c| {
                if c.is_whitespace() || matches!(c, ',' | '(' | ')' | '#' | '=' | '"' | '+' | '-') {
                    '_'
                } else {
                    c
                }
            })
            .collect()
    }
}
