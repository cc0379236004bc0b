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
    let mut out = String::new();
    if !scene.title.is_empty() {
        out.push_str(&format!("TITLE {}\n", scene.title));
    }
    out.push_str(&format!("UNITS {}\n\n", scene.units.abbrev()));
    let names: Vec<String> = scene
        .geometry
        .bodies
        .iter()
        .map(|body| quote_name(&body.name))
        .collect();
    for (body, name) in scene.geometry.bodies.iter().zip(&names) {
        let values: Vec<String> = body.params.iter().map(|v| fmt_num(*v)).collect();
        out.push_str(&format!(
            "BODY {name} {} {}
",
            body.kind,
            values.join(" ")
        ));
    }
    out.push('\n');
    for (region, props) in scene.geometry.regions.iter().zip(&scene.regions) {
        let zones: Vec<String> = region
            .zones
            .iter()
            .map(|z| z.expression(&|b| &names[b]))
            .collect();
        out.push_str(&format!(
            "REGION {} = {}",
            quote_name(&region.name),
            zones.join(" OR ")
        ));
        if let Some(colour) = props.colour {
            out.push_str(&format!(
                " COLOR {} {} {}",
                fmt_num(colour[0]),
                fmt_num(colour[1]),
                fmt_num(colour[2])
            ));
        }
        out.push_str(&format!(" K {}", fmt_num(props.k)));
        if props.transparent {
            out.push_str(" TRANSPARENT");
        }
        if let Some(density) = props.density {
            out.push_str(&format!(" DENSITY {}", fmt_num(density)));
        }
        out.push('\n');
    }
    out.push('\n');
    let vector = |d: DVec3| format!("({}, {}, {})", fmt_num(d.x), fmt_num(d.y), fmt_num(d.z));
    if let Some(camera) = &scene.camera {
        let lens = match camera.lens {
            Lens::Fov { vertical_deg } => format!("FOV {}", fmt_num(vertical_deg)),
            Lens::Focal { focal, film_height } => {
                format!("FOCAL {} FILM {}", fmt_num(focal), fmt_num(film_height))
            }
            Lens::Ortho { height } => format!("HEIGHT {}", fmt_num(height)),
        };
        let ortho = if matches!(camera.lens, Lens::Ortho { .. }) {
            "ORTHO "
        } else {
            ""
        };
        out.push_str(&format!(
            "CAMERA {ortho}EYE {} DIR {} UP {} {lens}\n",
            vector(camera.eye),
            vector(camera.dir),
            vector(camera.up)
        ));
    }
    for light in &scene.lights {
        let kind = match light.kind {
            LightKind::Parallel { dir } => format!("PARALLEL DIR {}", vector(dir)),
            LightKind::Point { pos, decay } => {
                format!("POINT AT {} DECAY {}", vector(pos), fmt_num(decay))
            }
        };
        out.push_str(&format!(
            "LIGHT {} {kind} INTENSITY {} COLOR {} {} {}\n",
            light.name,
            fmt_num(light.intensity),
            fmt_num(light.colour[0]),
            fmt_num(light.colour[1]),
            fmt_num(light.colour[2])
        ));
    }
    out.push_str(&format!("AMBIENT {}\n", fmt_num(scene.ambient)));
    let Background::Colour(bg) = scene.background;
    out.push_str(&format!(
        "BACKGROUND {} {} {}\n",
        fmt_num(bg[0]),
        fmt_num(bg[1]),
        fmt_num(bg[2])
    ));
    out.push_str(&format!(
        "SHADOWS {}\n",
        if scene.shadows { "ON" } else { "OFF" }
    ));
    if let Some((width, height)) = scene.size {
        out.push_str(&format!(
            "SIZE {width} {height}
"
        ));
    }
    out
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
