//! The studio: a local web page in which a model turns under the mouse,
//! ray-traced by the engine and streamed over a WebSocket.
//!
//! [`Studio::start`] binds a server (127.0.0.1 unless told otherwise),
//! loads the model and watches its file; the page (embedded: `assets/`)
//! sends the view it wants and gets frames back, each a JPEG with the
//! region-id image beside it ([`view::pack`]), coarse while the camera
//! moves and full-size when it stops. Only the newest view asked for is
//! rendered. Picking, volumes, overlaps, section views, rays and film
//! frames are asked for by JSON messages ([`tools`]).
//!
//! Every request must carry the session's token in its path and name the
//! server in its `Host` (and `Origin`) header ([`security`]); the page
//! never names a file: the server reads only the file it was started on
//! (and what that file includes) and writes pictures only into its output
//! folder, under names it makes.
#![warn(missing_docs)]

mod assets;
pub mod limits;
pub mod model;
pub mod security;
mod session;
pub mod tools;
pub mod view;

use axum::extract::{Path as UrlPath, State, WebSocketUpgrade};
use axum::http::{header, HeaderMap, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use axum::Router;
use model::{Model, Origin, Problem};
use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, RwLock};
use tokio::sync::{watch, Semaphore};

/// How to start the studio.
#[derive(Clone, Debug)]
pub struct Options {
    /// The model (the bundled helicopter when `None`).
    pub file: Option<PathBuf>,
    /// Where to listen (127.0.0.1:7171 by default; port 0 picks one).
    pub listen: SocketAddr,
    /// Where pictures asked for from the page are written.
    pub output: PathBuf,
    /// Worker threads for rendering (all cores when `None`).
    pub threads: Option<usize>,
    /// How often the file is looked at for changes, milliseconds.
    pub poll_ms: u64,
}

/// A studio that cannot start.
#[derive(Debug, thiserror::Error)]
pub enum StudioError {
    /// The model has errors.
    #[error("{}", .0.iter().map(|p| p.text.clone()).collect::<Vec<_>>().join("\n"))]
    Load(Vec<Problem>),
    /// The address cannot be listened on.
    #[error("cannot listen on {addr}: {source}")]
    Listen {
        /// The address.
        addr: SocketAddr,
        /// Why.
        source: std::io::Error,
    },
    /// The worker threads cannot start.
    #[error("cannot start threads: {0}")]
    Threads(String),
}

/// The model in use and its version (counted up at every reload).
pub struct Current {
    /// The model.
    pub model: Arc<Model>,
    /// Its version.
    pub version: u64,
}

/// What the sessions share.
pub struct Shared {
    origin: Origin,
    token: String,
    hosts: Vec<String>,
    current: RwLock<Current>,
    /// The version of the last good model and the problems of the file
    /// when the last reading failed.
    changes: watch::Sender<(u64, Vec<Problem>)>,
    pool: rayon::ThreadPool,
    renders: Semaphore,
    sessions: AtomicUsize,
    output: PathBuf,
}

impl Shared {
    /// The model in use and its version.
    pub fn current(&self) -> (Arc<Model>, u64) {
        let current = self.current.read().unwrap_or_else(|e| e.into_inner());
        (current.model.clone(), current.version)
    }
}

/// A running studio.
pub struct Studio {
    /// The address it listens on.
    pub addr: SocketAddr,
    /// The session token.
    pub token: String,
    shared: Arc<Shared>,
}

impl Studio {
    /// Load the model, bind the address and serve, on the current tokio
    /// runtime, until the runtime ends.
    pub async fn start(options: Options) -> Result<Studio, StudioError> {
        let origin = match &options.file {
            Some(path) => Origin::File(path.clone()),
            None => Origin::Bundled,
        };
        let model = Model::load(&origin).map_err(StudioError::Load)?;
        let listener = tokio::net::TcpListener::bind(options.listen)
            .await
            .map_err(|source| StudioError::Listen {
                addr: options.listen,
                source,
            })?;
        let addr = listener
            .local_addr()
            .map_err(|source| StudioError::Listen {
                addr: options.listen,
                source,
            })?;
        let mut pool = rayon::ThreadPoolBuilder::new();
        if let Some(threads) = options.threads {
            pool = pool.num_threads(threads.max(1));
        }
        let pool = pool
            .build()
            .map_err(|e| StudioError::Threads(e.to_string()))?;
        let shared = Arc::new(Shared {
            origin,
            token: security::new_token(),
            hosts: security::allowed_hosts(addr),
            current: RwLock::new(Current {
                model: Arc::new(model),
                version: 1,
            }),
            changes: watch::channel((1, Vec::new())).0,
            pool,
            renders: Semaphore::new(limits::MAX_RENDERS),
            sessions: AtomicUsize::new(0),
            output: options.output.clone(),
        });
        let app = Router::new()
            .route("/s/{token}/", get(page))
            .route("/s/{token}/{asset}", get(asset))
            .route("/s/{token}/ws", get(socket))
            .fallback(|| async { StatusCode::NOT_FOUND })
            .with_state(shared.clone());
        tokio::spawn(async move {
            let _ = axum::serve(listener, app).await;
        });
        tokio::spawn(watch_file(shared.clone(), options.poll_ms.max(50)));
        Ok(Studio {
            addr,
            token: shared.token.clone(),
            shared,
        })
    }

    /// The page's address, token included.
    pub fn url(&self) -> String {
        format!("http://{}/s/{}/", self.addr, self.token)
    }

    /// What the sessions share (the model in use).
    pub fn shared(&self) -> &Arc<Shared> {
        &self.shared
    }
}

/// Look at the file every `poll_ms` and read it again when it changed:
/// the new model replaces the old one, or its problems are sent to the
/// pages and the last good model stays.
async fn watch_file(shared: Arc<Shared>, poll_ms: u64) {
    let mut watched = shared.current().0.watched.clone();
    let mut seen = model::stamps(&watched);
    loop {
        tokio::time::sleep(std::time::Duration::from_millis(poll_ms)).await;
        let now = model::stamps(&watched);
        if now == seen {
            continue;
        }
        seen = now;
        let origin = shared.origin.clone();
        let loaded = tokio::task::spawn_blocking(move || Model::load(&origin)).await;
        let Ok(loaded) = loaded else { continue };
        match loaded {
            Ok(model) => {
                let version = {
                    let mut current = shared.current.write().unwrap_or_else(|e| e.into_inner());
                    current.version += 1;
                    current.model = Arc::new(model);
                    watched = current.model.watched.clone();
                    current.version
                };
                seen = model::stamps(&watched);
                shared.changes.send_replace((version, Vec::new()));
            }
            Err(problems) => {
                let version = shared.current().1;
                shared.changes.send_replace((version, problems));
            }
        }
    }
}

/// Refuse requests with a wrong token, `Host` or `Origin`.
fn refused(shared: &Shared, token: &str, headers: &HeaderMap) -> Option<Response> {
    if !security::token_matches(token, &shared.token) {
        return Some((StatusCode::FORBIDDEN, "wrong token\n").into_response());
    }
    security::refusal(headers, &shared.hosts)
        .map(|why| (StatusCode::FORBIDDEN, format!("{why}\n")).into_response())
}

async fn page(
    State(shared): State<Arc<Shared>>,
    UrlPath(token): UrlPath<String>,
    headers: HeaderMap,
) -> Response {
    if let Some(refusal) = refused(&shared, &token, &headers) {
        return refusal;
    }
    assets::response("index.html").unwrap_or_else(|| StatusCode::NOT_FOUND.into_response())
}

async fn asset(
    State(shared): State<Arc<Shared>>,
    UrlPath((token, name)): UrlPath<(String, String)>,
    headers: HeaderMap,
) -> Response {
    if let Some(refusal) = refused(&shared, &token, &headers) {
        return refusal;
    }
    // Only the embedded files, by exact name: nothing here reaches the
    // file system.
    assets::response(&name).unwrap_or_else(|| StatusCode::NOT_FOUND.into_response())
}

async fn socket(
    State(shared): State<Arc<Shared>>,
    UrlPath(token): UrlPath<String>,
    headers: HeaderMap,
    upgrade: WebSocketUpgrade,
) -> Response {
    if let Some(refusal) = refused(&shared, &token, &headers) {
        return refusal;
    }
    if shared.sessions.fetch_add(1, Ordering::SeqCst) >= limits::MAX_SESSIONS {
        shared.sessions.fetch_sub(1, Ordering::SeqCst);
        return (StatusCode::SERVICE_UNAVAILABLE, "too many pages open\n").into_response();
    }
    upgrade
        .max_message_size(limits::MAX_MESSAGE)
        .max_frame_size(limits::MAX_MESSAGE)
        .on_upgrade(move |socket| async move {
            session::run(socket, shared.clone()).await;
            shared.sessions.fetch_sub(1, Ordering::SeqCst);
        })
        .into_response()
}

/// Headers every response carries: nothing cached, nothing framed, no
/// referrer (the token is in the address), only the page's own scripts.
pub(crate) fn guarded(content_type: &'static str, body: &'static [u8]) -> Response {
    (
        [
            (header::CONTENT_TYPE, content_type),
            (header::CACHE_CONTROL, "no-store"),
            (header::X_FRAME_OPTIONS, "DENY"),
            (header::REFERRER_POLICY, "no-referrer"),
            (
                header::CONTENT_SECURITY_POLICY,
                "default-src 'self'; img-src 'self' blob: data:; connect-src 'self'",
            ),
        ],
        body,
    )
        .into_response()
}
