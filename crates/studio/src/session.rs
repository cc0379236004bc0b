//! One page's WebSocket: views in, frames out (newest view only), and
//! questions answered one at a time beside the frames.

use crate::limits::MAX_CUTS;
use crate::view::{self, Renderers, ViewRequest};
use crate::{tools, Shared};
use axum::extract::ws::{Message, WebSocket};
use futures_util::{SinkExt, StreamExt};
use serde::Deserialize;
use serde_json::{json, Value};
use std::sync::Arc;
use std::time::Instant;
use tokio::sync::{mpsc, watch};

/// A message from the page.
#[derive(Debug, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
enum Request {
    /// The view wanted now.
    View(ViewRequest),
    /// A region clicked.
    Pick { region: usize },
    /// A region's volume.
    Volume { region: usize },
    /// The overlaps.
    Check,
    /// A section view.
    Slice {
        normal: [f64; 3],
        point: [f64; 3],
        width: u32,
        height: u32,
    },
    /// The ray through a pixel of the current view.
    Shoot { x: f64, y: f64 },
    /// The current view, or film frames, to files.
    RenderFile {
        #[serde(default)]
        first: Option<usize>,
        #[serde(default)]
        last: Option<usize>,
    },
}

/// Serve one page until it goes.
pub async fn run(socket: WebSocket, shared: Arc<Shared>) {
    let (mut sink, mut stream) = socket.split();
    let (out, mut outgoing) = mpsc::channel::<Message>(8);
    let writer = tokio::spawn(async move {
        while let Some(message) = outgoing.recv().await {
            if sink.send(message).await.is_err() {
                break;
            }
        }
    });
    let (views, latest_view) = watch::channel::<Option<ViewRequest>>(None);
    let (questions, pending) = mpsc::channel::<Request>(4);
    let renderer = tokio::spawn(render_loop(
        shared.clone(),
        latest_view.clone(),
        out.clone(),
    ));
    let answerer = tokio::spawn(answer_loop(
        shared.clone(),
        latest_view,
        pending,
        out.clone(),
    ));
    send_model(&shared, &out).await;
    while let Some(Ok(message)) = stream.next().await {
        let text = match message {
            Message::Text(text) => text,
            Message::Close(_) => break,
            _ => continue,
        };
        match serde_json::from_str::<Request>(&text) {
            Ok(Request::View(view)) if view.looks.cuts.len() > MAX_CUTS => {
                send_json(&out, error(format!("at most {MAX_CUTS} cut planes"))).await;
            }
            Ok(Request::View(view)) => {
                views.send_replace(Some(view));
            }
            Ok(question) => {
                if questions.try_send(question).is_err() {
                    send_json(&out, error("busy: wait for the answers asked for".into())).await;
                }
            }
            Err(e) => send_json(&out, error(format!("a message not understood: {e}"))).await,
        }
    }
    renderer.abort();
    answerer.abort();
    drop(out);
    let _ = writer.await;
}

fn error(message: String) -> Value {
    json!({ "type": "error", "message": message })
}

async fn send_json(out: &mpsc::Sender<Message>, value: Value) {
    let _ = out.send(Message::Text(value.to_string().into())).await;
}

/// Tell the page about the model in use.
async fn send_model(shared: &Arc<Shared>, out: &mpsc::Sender<Message>) {
    let (model, version) = shared.current();
    let summary = tokio::task::spawn_blocking(move || tools::summary(&model, version)).await;
    match summary {
        Ok(Ok(summary)) => send_json(out, summary).await,
        Ok(Err(message)) => send_json(out, error(message)).await,
        Err(_) => {}
    }
}

/// Render the newest view whenever it or the model changes; views asked
/// for while a frame renders replace one another, so only the last is
/// drawn.
async fn render_loop(
    shared: Arc<Shared>,
    mut latest_view: watch::Receiver<Option<ViewRequest>>,
    out: mpsc::Sender<Message>,
) {
    let mut changes = shared.changes.subscribe();
    let mut kept: Option<(u64, Renderers)> = None;
    loop {
        tokio::select! {
            changed = latest_view.changed() => if changed.is_err() { return },
            changed = changes.changed() => {
                if changed.is_err() {
                    return;
                }
                let problems = changes.borrow_and_update().1.clone();
                if !problems.is_empty() {
                    send_json(&out, json!({ "type": "problems", "problems": problems })).await;
                    continue;
                }
                send_model(&shared, &out).await;
            }
        }
        let Some(request) = latest_view.borrow_and_update().clone() else {
            continue;
        };
        let Ok(_permit) = shared.renders.acquire().await else {
            return;
        };
        let (model, version) = shared.current();
        let cached = kept
            .take()
            .filter(|(v, p)| *v == version && p.looks == request.looks);
        let worker = shared.clone();
        let rendered = tokio::task::spawn_blocking(move || {
            let started = Instant::now();
            let mut prepared = match cached {
                Some((_, prepared)) => prepared,
                None => Renderers::new(&model.scene_at(request.looks.frame), &request.looks)?,
            };
            let (frame, camera) = worker
                .pool
                .install(|| prepared.render(&request))
                .ok_or("the view asked for is not valid")?;
            let kind = if request.moving { "coarse" } else { "full" };
            let ms = started.elapsed().as_secs_f64() * 1e3;
            let message = view::pack(&frame, &camera, request.seq, kind, ms);
            Ok::<_, String>((prepared, message))
        })
        .await;
        match rendered {
            Ok(Ok((prepared, message))) => {
                kept = Some((version, prepared));
                if out.send(Message::Binary(message.into())).await.is_err() {
                    return;
                }
            }
            Ok(Err(message)) => send_json(&out, error(message)).await,
            Err(_) => send_json(&out, error("the render failed".into())).await,
        }
    }
}

/// Answer the page's questions in turn.
async fn answer_loop(
    shared: Arc<Shared>,
    latest_view: watch::Receiver<Option<ViewRequest>>,
    mut pending: mpsc::Receiver<Request>,
    out: mpsc::Sender<Message>,
) {
    while let Some(question) = pending.recv().await {
        let (model, _) = shared.current();
        let view = latest_view.borrow().clone();
        let worker = shared.clone();
        let answer = tokio::task::spawn_blocking(move || {
            worker.pool.install(|| match question {
                Request::Pick { region } => tools::pick(&model, region),
                Request::Volume { region } => tools::volume(&model, region),
                Request::Check => tools::check(&model),
                Request::Slice {
                    normal,
                    point,
                    width,
                    height,
                } => tools::slice(&model, normal, point, (width, height)),
                Request::Shoot { x, y } => match &view {
                    Some(view) => tools::shoot(&model, view, x, y),
                    None => Err("no view yet".into()),
                },
                Request::RenderFile { first, last } => match &view {
                    Some(view) => {
                        let frames = first.map(|f| (f, last.unwrap_or(f)));
                        tools::render_to_file(&model, view, frames, &worker.output)
                    }
                    None => Err("no view yet".into()),
                },
                Request::View(_) => Err("a view is not a question".into()),
            })
        })
        .await;
        let reply = match answer {
            Ok(Ok(value)) => value,
            Ok(Err(message)) => error(message),
            Err(_) => error("the answer failed".into()),
        };
        send_json(&out, reply).await;
    }
}
