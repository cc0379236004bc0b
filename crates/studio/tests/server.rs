//! The studio's server as a page sees it: a WebSocket on an ephemeral port,
//! views in, frames out; picking, reloading and the requests refused.

use futures_util::{SinkExt, StreamExt};
use serde_json::{json, Value};
use std::path::PathBuf;
use std::time::Duration;
use sv_render::{Renderer, Settings};
use sv_studio::view::{unpack, FrameHeader, ViewRequest};
use sv_studio::{Options, Studio};
use tokio_tungstenite::tungstenite::client::IntoClientRequest;
use tokio_tungstenite::tungstenite::http::HeaderValue;
use tokio_tungstenite::tungstenite::Message;
use tokio_tungstenite::{connect_async, MaybeTlsStream, WebSocketStream};

type Socket = WebSocketStream<MaybeTlsStream<tokio::net::TcpStream>>;

async fn start(file: Option<PathBuf>, output: PathBuf) -> Studio {
    Studio::start(Options {
        file,
        listen: "127.0.0.1:0".parse().unwrap(),
        output,
        threads: Some(2),
        poll_ms: 50,
    })
    .await
    .expect("the studio starts")
}

fn ws_url(studio: &Studio, token: &str) -> String {
    format!("ws://{}/s/{token}/ws", studio.addr)
}

/// Connect with the page's own `Origin`, or `origin` when given.
async fn connect(url: &str, origin: Option<&str>) -> Result<Socket, String> {
    let mut request = url.into_client_request().unwrap();
    let own = format!("http://{}", request.uri().authority().unwrap());
    let origin = origin.map(str::to_string).unwrap_or(own);
    request
        .headers_mut()
        .insert("Origin", HeaderValue::from_str(&origin).unwrap());
    connect_async(request)
        .await
        .map(|(socket, _)| socket)
        .map_err(|e| e.to_string())
}

/// The next message, within a minute.
async fn next_message(socket: &mut Socket) -> Message {
    tokio::time::timeout(Duration::from_secs(60), socket.next())
        .await
        .expect("a message within a minute")
        .expect("the socket stays open")
        .unwrap()
}

/// The next text message of type `kind` (frames and others skipped).
async fn next_json(socket: &mut Socket, kind: &str) -> Value {
    loop {
        if let Message::Text(text) = next_message(socket).await {
            let value: Value = serde_json::from_str(&text).unwrap();
            if value["type"] == kind {
                return value;
            }
            assert_ne!(value["type"], "error", "{value}");
        }
    }
}

/// The next frame: its header and region ids.
async fn next_frame(socket: &mut Socket) -> (FrameHeader, Vec<u32>) {
    loop {
        if let Message::Binary(bytes) = next_message(socket).await {
            let (header, jpeg, ids) = unpack(&bytes).expect("a frame unpacks");
            assert_eq!(&jpeg[..2], &[0xff, 0xd8], "a JPEG");
            return (header, ids);
        }
    }
}

fn view(model: &Value, seq: u64, az: f64, moving: bool) -> Value {
    json!({
        "type": "view", "seq": seq, "target": model["target"], "az": az, "el": 25.0,
        "distance": model["distance"], "width": 120, "height": 90, "moving": moving,
    })
}

/// The region ids the renderer gives for `scene` at 120×90 through
/// `camera` (the scene's own when `None`).
fn region_ids(scene: &sv_scene::Scene, camera: Option<sv_scene::Camera>) -> Vec<u32> {
    let mut renderer = Renderer::new(scene, 4.0 / 3.0).unwrap().0;
    if let Some(camera) = camera {
        renderer.camera = camera;
    }
    let settings = Settings {
        width: 120,
        height: 90,
        shadows: false,
        samples: 1,
        aovs: true,
    };
    renderer.render(&settings, &|_| {}).region
}

async fn send(socket: &mut Socket, value: &Value) {
    socket
        .send(Message::Text(value.to_string().into()))
        .await
        .unwrap();
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_frame_has_the_renderers_region_ids_and_picking_names_them() {
    let out = tempfile::tempdir().unwrap();
    let studio = start(None, out.path().into()).await;
    let mut socket = connect(&ws_url(&studio, &studio.token), None)
        .await
        .unwrap();
    let model = next_json(&mut socket, "model").await;
    assert_eq!(model["regions"][0]["name"], "fuselage");
    let asked = view(&model, 1, 35.0, false);
    send(&mut socket, &asked).await;
    let (header, ids) = next_frame(&mut socket).await;
    assert_eq!((header.seq, header.kind.as_str()), (1, "full"));
    assert_eq!((header.width, header.height), (120, 90));

    let request: ViewRequest = serde_json::from_value(asked).unwrap();
    let camera = request.camera().unwrap();
    assert_eq!(header.eye, camera.eye.to_array());
    let scene = studio.shared().current().0.scene.clone();
    assert_eq!(ids, region_ids(&scene, Some(camera)));
    let centre = ids[45 * 120 + 60];
    assert!(centre > 0, "the model fills the middle of the picture");

    send(&mut socket, &json!({"type": "pick", "region": centre - 1})).await;
    let picked = next_json(&mut socket, "pick").await;
    let name = &scene.geometry.regions[centre as usize - 1].name;
    assert_eq!(&picked["name"], name);
    assert!(picked["written"]["line"].as_u64().unwrap() > 0);
    assert!(!picked["expression"].as_str().unwrap().is_empty());

    // A coarse frame while moving is a third of the size.
    send(&mut socket, &view(&model, 2, 60.0, true)).await;
    let (header, ids) = next_frame(&mut socket).await;
    assert_eq!(
        (header.kind.as_str(), header.width, header.height),
        ("coarse", 40, 30)
    );
    assert_eq!(ids.len(), 40 * 30);

    // Only the newest view counts: whatever is skipped, the last frame
    // is the last view's, full-size.
    for seq in 3..20 {
        send(&mut socket, &view(&model, seq, 60.0 + seq as f64, true)).await;
    }
    send(&mut socket, &view(&model, 20, 90.0, false)).await;
    let mut frames = 0;
    loop {
        let (header, _) = next_frame(&mut socket).await;
        frames += 1;
        if header.seq == 20 {
            assert_eq!(header.kind, "full");
            break;
        }
    }
    assert!(frames <= 18);

    let section = json!({"type": "slice", "normal": [0, 0, 1], "point": [0, 0, 2],
                         "width": 160, "height": 120});
    send(&mut socket, &section).await;
    let slice = next_json(&mut socket, "slice").await;
    assert!(slice["png"]
        .as_str()
        .unwrap()
        .starts_with("data:image/png;base64,"));
    assert!(!slice["legend"].as_array().unwrap().is_empty());

    send(&mut socket, &json!({"type": "render_file"})).await;
    let written = next_json(&mut socket, "written").await;
    let file = PathBuf::from(written["files"][0].as_str().unwrap());
    assert!(file.starts_with(out.path()) && file.exists());
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_wrong_token_origin_or_host_is_refused() {
    let out = tempfile::tempdir().unwrap();
    let studio = start(None, out.path().into()).await;
    let wrong = connect(&ws_url(&studio, "0123456789abcdef0123456789abcdef"), None).await;
    assert!(wrong.unwrap_err().contains("403"));
    let foreign = connect(&ws_url(&studio, &studio.token), Some("http://evil.example")).await;
    assert!(foreign.unwrap_err().contains("403"));

    let mut request = ws_url(&studio, &studio.token)
        .into_client_request()
        .unwrap();
    request
        .headers_mut()
        .insert("Host", HeaderValue::from_static("rebound.example:80"));
    assert!(connect_async(request)
        .await
        .unwrap_err()
        .to_string()
        .contains("403"));

    // A message over the size limit ends the connection.
    let mut socket = connect(&ws_url(&studio, &studio.token), None)
        .await
        .unwrap();
    next_json(&mut socket, "model").await;
    let huge = "x".repeat(sv_studio::limits::MAX_MESSAGE + 1);
    let _ = socket.send(Message::Text(huge.into())).await;
    let closed = tokio::time::timeout(Duration::from_secs(10), async {
        loop {
            match socket.next().await {
                None | Some(Err(_)) | Some(Ok(Message::Close(_))) => return true,
                Some(Ok(_)) => {}
            }
        }
    })
    .await;
    assert_eq!(closed, Ok(true));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_changed_file_reloads_and_errors_keep_the_last_good_model() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("two.sv");
    let good = "BODY a SPH (0, 0, 0) 1\nBODY b SPH (3, 0, 0) 1\n\
                REGION left = +a\nREGION right = +b\n";
    std::fs::write(&path, good).unwrap();
    let studio = start(Some(path.clone()), dir.path().join("out")).await;
    let mut socket = connect(&ws_url(&studio, &studio.token), None)
        .await
        .unwrap();
    let first = next_json(&mut socket, "model").await;
    assert_eq!(first["regions"].as_array().unwrap().len(), 2);

    std::fs::write(&path, format!("{good}REGION broken = +nowhere\n")).unwrap();
    let problems = next_json(&mut socket, "problems").await;
    assert_eq!(problems["problems"][0]["line"], 5);
    assert_eq!(studio.shared().current().1, 1, "the last good model stays");

    std::fs::write(
        &path,
        format!("{good}BODY c SPH (6, 0, 0) 1\nREGION third = +c\n"),
    )
    .unwrap();
    let reloaded = next_json(&mut socket, "model").await;
    assert_eq!(reloaded["version"], 2);
    assert_eq!(reloaded["regions"][2]["name"], "third");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn film_frames_sections_rays_and_overlaps_are_answered() {
    let out = tempfile::tempdir().unwrap();
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let script = root.join("examples/helicopter-film/film.svs");
    let studio = start(Some(script.clone()), out.path().into()).await;
    let mut socket = connect(&ws_url(&studio, &studio.token), None)
        .await
        .unwrap();
    let model = next_json(&mut socket, "model").await;
    assert_eq!(model["frames"], 720);

    // Frame 300 through the film's own camera.
    let mut asked = view(&model, 1, 35.0, false);
    asked["frame"] = json!(300);
    asked["film_camera"] = json!(true);
    send(&mut socket, &asked).await;
    let (header, ids) = next_frame(&mut socket).await;
    let film = sv_formats::script::load_script(&script, &Default::default()).unwrap();
    let scene = film.scene_at(300);
    let camera = scene.camera.expect("the film has a camera");
    assert_eq!(header.eye, camera.eye.to_array());
    assert_eq!(ids, region_ids(&scene, None));

    // Film frames to files, under names the server makes.
    send(
        &mut socket,
        &json!({"type": "render_file", "first": 2, "last": 3}),
    )
    .await;
    let written = next_json(&mut socket, "written").await;
    let files: Vec<&str> = written["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_str().unwrap())
        .collect();
    assert_eq!(files.len(), 2);
    assert!(files[1].ends_with("film-frame-00003.png"), "{files:?}");

    // The ray through the middle of the orbit view meets the fuselage.
    send(&mut socket, &view(&model, 2, 35.0, false)).await;
    next_frame(&mut socket).await;
    send(&mut socket, &json!({"type": "shoot", "x": 60.0, "y": 45.0})).await;
    let ray = next_json(&mut socket, "shoot").await;
    let steps = ray["steps"].as_array().unwrap();
    assert!(steps.iter().any(|s| s["entering"] == true));

    send(&mut socket, &json!({"type": "check"})).await;
    let check = next_json(&mut socket, "check").await;
    assert!(check["rays"].as_u64().unwrap() > 0);
}
