//! Frames per second a page receives while orbiting a model, and the time
//! from a view sent to its picture received, measured from a WebSocket
//! client as the page is one.
//!
//!     cargo run --release -p sv-studio --example studio_bench -- [FILE|-] [SECONDS]
//!
//! `-` (or nothing) is the bundled helicopter. Orbiting: a moving view
//! every 16 ms (a display frame), the azimuth one degree further each
//! time, for SECONDS (5); the server renders only the newest, coarse
//! (320×240). Then single views, one at a time: coarse and full (960×720),
//! the latency from sending to the frame received, and the server's share
//! (rendering, JPEG, packing).

use futures_util::{SinkExt, StreamExt};
use serde_json::{json, Value};
use std::collections::HashMap;
use std::path::PathBuf;
use std::time::{Duration, Instant};
use sv_studio::view::unpack;
use sv_studio::{Options, Studio};
use tokio_tungstenite::tungstenite::client::IntoClientRequest;
use tokio_tungstenite::tungstenite::http::HeaderValue;
use tokio_tungstenite::tungstenite::Message;

type Socket =
    tokio_tungstenite::WebSocketStream<tokio_tungstenite::MaybeTlsStream<tokio::net::TcpStream>>;

fn view(model: &Value, seq: u64, az: f64, moving: bool) -> Message {
    let value = json!({
        "type": "view", "seq": seq, "target": model["target"], "az": az, "el": 25.0,
        "distance": model["distance"], "width": 960, "height": 720, "moving": moving,
    });
    Message::Text(value.to_string().into())
}

/// The next frame's sequence number and the server's milliseconds on it.
async fn next_frame(socket: &mut Socket) -> (u64, f64) {
    loop {
        if let Some(Ok(Message::Binary(bytes))) = socket.next().await {
            let (header, _, _) = unpack(&bytes).expect("a frame");
            return (header.seq, header.render_ms);
        }
    }
}

fn percentile(sorted: &[f64], p: f64) -> f64 {
    sorted[((sorted.len() - 1) as f64 * p).round() as usize]
}

fn summary(name: &str, mut ms: Vec<f64>) {
    ms.sort_by(f64::total_cmp);
    println!(
        "{name}: median {:.1} ms, 90th percentile {:.1} ms ({} samples)",
        percentile(&ms, 0.5),
        percentile(&ms, 0.9),
        ms.len()
    );
}

#[tokio::main(flavor = "multi_thread", worker_threads = 2)]
async fn main() {
    let mut args = std::env::args().skip(1);
    let file = args.next().filter(|a| a != "-").map(PathBuf::from);
    let seconds: f64 = args.next().and_then(|s| s.parse().ok()).unwrap_or(5.0);
    let studio = Studio::start(Options {
        file: file.clone(),
        listen: "127.0.0.1:0".parse().unwrap(),
        output: std::env::temp_dir().join("studio-bench"),
        threads: None,
        poll_ms: 1000,
    })
    .await
    .expect("the studio starts");
    let url = format!("ws://{}/s/{}/ws", studio.addr, studio.token);
    let mut request = url.into_client_request().unwrap();
    let origin = format!("http://{}", studio.addr);
    request
        .headers_mut()
        .insert("Origin", HeaderValue::from_str(&origin).unwrap());
    let (socket, _) = tokio_tungstenite::connect_async(request).await.unwrap();
    let (mut sink, mut stream) = socket.split();
    let model: Value = loop {
        if let Some(Ok(Message::Text(text))) = stream.next().await {
            break serde_json::from_str(&text).unwrap();
        }
    };
    println!(
        "{}: {} regions",
        file.map_or("the bundled helicopter".into(), |f| f.display().to_string()),
        model["regions"].as_array().map_or(0, Vec::len)
    );
    // Warm up: the scene prepared, the first frame drawn.
    sink.send(view(&model, 1, 35.0, false)).await.unwrap();
    let mut socket = sink.reunite(stream).unwrap();
    next_frame(&mut socket).await;
    let (mut sink, mut stream) = socket.split();

    let sent_at = std::sync::Arc::new(std::sync::Mutex::new(HashMap::new()));
    let sender_times = sent_at.clone();
    let orbit_model = model.clone();
    let sender = tokio::spawn(async move {
        let start = Instant::now();
        let mut seq = 100;
        let mut ticker = tokio::time::interval(Duration::from_millis(16));
        while start.elapsed().as_secs_f64() < seconds {
            ticker.tick().await;
            seq += 1;
            sender_times.lock().unwrap().insert(seq, Instant::now());
            let az = 35.0 + (seq - 100) as f64;
            sink.send(view(&orbit_model, seq, az, true)).await.unwrap();
        }
        sink
    });
    let start = Instant::now();
    let (mut frames, mut latencies) = (0, Vec::new());
    while start.elapsed().as_secs_f64() < seconds {
        let Ok(Some(Ok(Message::Binary(bytes)))) =
            tokio::time::timeout(Duration::from_millis(200), stream.next()).await
        else {
            continue;
        };
        let (header, _, _) = unpack(&bytes).expect("a frame");
        frames += 1;
        if let Some(sent) = sent_at.lock().unwrap().get(&header.seq) {
            latencies.push(sent.elapsed().as_secs_f64() * 1e3);
        }
    }
    let elapsed = start.elapsed().as_secs_f64();
    let sink = sender.await.unwrap();
    println!(
        "orbiting: {frames} coarse frames in {elapsed:.1} s: {:.1} frames/s received",
        frames as f64 / elapsed
    );
    summary("orbiting, view sent to its picture received", latencies);
    let mut socket = sink.reunite(stream).unwrap();
    // Let the frames still in flight arrive.
    while let Ok(Some(_)) = tokio::time::timeout(Duration::from_millis(1500), socket.next()).await {
    }

    for (name, moving) in [("coarse 320×240", true), ("full 960×720", false)] {
        let (mut times, mut server_times) = (Vec::new(), Vec::new());
        for n in 0..10 {
            let seq = 10_000 + n + if moving { 0 } else { 100 };
            let sent = Instant::now();
            socket
                .send(view(&model, seq, 40.0 + n as f64 * 7.0, moving))
                .await
                .unwrap();
            loop {
                let (received, server_ms) = next_frame(&mut socket).await;
                if received == seq {
                    server_times.push(server_ms);
                    break;
                }
            }
            times.push(sent.elapsed().as_secs_f64() * 1e3);
        }
        summary(&format!("single view, {name}, sent to received"), times);
        summary(
            &format!("single view, {name}, rendered (server side)"),
            server_times,
        );
    }
}
