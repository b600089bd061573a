//! The HTTP side of `psh view` (axum on tokio): the page, the scene's facts, frames and
//! saves. No request names a file: the page is compiled in, frames are rendered, and a
//! save writes a new directory under the save directory given at start-up.
//!
//! | route | answer |
//! |---|---|
//! | `GET /` | the page (`page.html`) |
//! | `GET /info` | JSON: the scene's name, full size, band limits, pictures, bounds |
//! | `GET /frame?...` | a frame ([`super::encode`]); 400 naming a bad parameter, 503 when busy |
//! | `POST /save?...&polarizers=A,B` | the frame's pictures written as `psh render` writes them; JSON with the directory |
//! | `GET /stats` | JSON: frames and saves rendered, cancelled (their client left), refused as busy |

use super::encode::encode;
use super::limits::{Bounded, Frames, MAX_CONNECTIONS, MAX_FRAMES};
use super::query::{parse, FrameQuery};
use axum::extract::{Query, State};
use axum::http::{header, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use axum::Router;
use psh::apps::{Viewer, MAX_VIEW_SIDE};
use psh::progress::Progress;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Instant;

/// The page, compiled in.
const PAGE: &str = include_str!("page.html");

/// The server's state: the viewer (one frame renders at a time, on all cores), where
/// saves go, the frames in flight and the counts `/stats` reports.
struct App {
    viewer: Mutex<Viewer>,
    save_dir: PathBuf,
    frames: Arc<Frames>,
    rendered: AtomicU64,
    cancelled: AtomicU64,
    busy: AtomicU64,
}

/// Serves the page on `listener` until the process ends.
pub fn serve(
    listener: std::net::TcpListener,
    viewer: Viewer,
    save_dir: PathBuf,
) -> psh::Result<()> {
    let address = listener
        .local_addr()
        .map_err(|e| io("the listening address", e))?;
    listener
        .set_nonblocking(true)
        .map_err(|e| io("the listening socket", e))?;
    let app = Arc::new(App {
        viewer: Mutex::new(viewer),
        save_dir,
        frames: Arc::new(Frames::default()),
        rendered: AtomicU64::new(0),
        cancelled: AtomicU64::new(0),
        busy: AtomicU64::new(0),
    });
    let router = Router::new()
        .route("/", get(page))
        .route("/info", get(info))
        .route("/frame", get(frame))
        .route("/save", post(save))
        .route("/stats", get(stats))
        .with_state(app);
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(1)
        .enable_io()
        .build()
        .map_err(|e| io("the server's runtime", e))?;
    runtime.block_on(async move {
        let listener = tokio::net::TcpListener::from_std(listener)
            .map_err(|e| io("the listening socket", e))?;
        outln!("psh view: http://{address}/");
        axum::serve(Bounded::new(listener), router)
            .await
            .map_err(|e| io("the server", e))
    })
}

/// An I/O failure of the server as a [`psh::Error`].
fn io(what: &str, e: std::io::Error) -> psh::Error {
    psh::Error::invalid("view server", what.to_string(), e.to_string())
}

async fn page() -> Response {
    ([(header::CONTENT_TYPE, "text/html; charset=utf-8")], PAGE).into_response()
}

async fn info(State(app): State<Arc<App>>) -> Response {
    let viewer = app.viewer.lock().unwrap_or_else(|p| p.into_inner());
    let size = viewer.size();
    json(serde_json::json!({
        "scene": viewer.name(),
        "width": size.width,
        "height": size.height,
        "bands": viewer.band_limits(),
        "pictures": psh::io::PICTURES,
        "max_side": MAX_VIEW_SIDE,
        "max_frames": MAX_FRAMES,
        "max_connections": MAX_CONNECTIONS,
    }))
}

async fn stats(State(app): State<Arc<App>>) -> Response {
    json(serde_json::json!({
        "rendered": app.rendered.load(Ordering::Relaxed),
        "cancelled": app.cancelled.load(Ordering::Relaxed),
        "busy": app.busy.load(Ordering::Relaxed),
    }))
}

/// Set when the request's future is dropped (its client went away): the render stops at
/// its next check ([`psh::progress::Progress::cancelled`]).
struct Abandoned(Arc<AtomicBool>);

impl Drop for Abandoned {
    fn drop(&mut self) {
        self.0.store(true, Ordering::Relaxed);
    }
}

/// Cancellation of one frame, asked by the renderer between stages and vertices.
struct Gone(Arc<AtomicBool>);

impl Progress for Gone {
    fn advance(&self, _: u64) {}
    fn cancelled(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }
}

/// 200 with `value` as JSON.
fn json(value: serde_json::Value) -> Response {
    (
        [(header::CONTENT_TYPE, "application/json")],
        value.to_string(),
    )
        .into_response()
}

/// 400 with the reason.
fn bad_request(e: &psh::Error) -> Response {
    (StatusCode::BAD_REQUEST, format!("{e}\n")).into_response()
}

/// Runs `work` with the viewer on a blocking thread, in a frame slot (503 when none is
/// free), stopped when the client goes away.
async fn with_viewer<T: Send + 'static>(
    app: Arc<App>,
    work: impl FnOnce(&mut Viewer, &dyn Progress) -> psh::Result<T> + Send + 'static,
) -> Result<T, Response> {
    let Some(slot) = app.frames.slot() else {
        app.busy.fetch_add(1, Ordering::Relaxed);
        return Err((
            StatusCode::SERVICE_UNAVAILABLE,
            "busy: too many frames in flight\n",
        )
            .into_response());
    };
    let gone = Arc::new(AtomicBool::new(false));
    let _abandoned = Abandoned(Arc::clone(&gone));
    let worker = Arc::clone(&app);
    let done = tokio::task::spawn_blocking(move || {
        let _slot = slot;
        let progress = Gone(gone);
        let mut viewer = worker.viewer.lock().unwrap_or_else(|p| p.into_inner());
        // Its client may have left while it waited for the renderer.
        let done = progress
            .check_cancelled("a frame whose client left")
            .and_then(|()| work(&mut viewer, &progress));
        let count = match done {
            Err(psh::Error::Interrupted { .. }) => &worker.cancelled,
            _ => &worker.rendered,
        };
        count.fetch_add(1, Ordering::Relaxed);
        done
    })
    .await;
    match done {
        Ok(Ok(value)) => Ok(value),
        Ok(Err(psh::Error::Interrupted { .. })) => {
            Err((StatusCode::SERVICE_UNAVAILABLE, "cancelled\n").into_response())
        }
        Ok(Err(e)) => Err(bad_request(&e)),
        Err(e) => Err((StatusCode::INTERNAL_SERVER_ERROR, format!("{e}\n")).into_response()),
    }
}

async fn frame(
    State(app): State<Arc<App>>,
    Query(pairs): Query<Vec<(String, String)>>,
) -> Response {
    let FrameQuery { request, show } = match parse(&pairs) {
        Ok(q) => q,
        Err(e) => return bad_request(&e),
    };
    let done = with_viewer(app, move |viewer, progress| {
        let frame = viewer.frame(&request, progress)?;
        let bands = viewer.band_limits()[request.bands];
        let t = Instant::now();
        let s = frame.seconds;
        let header = serde_json::json!({
            "l_low": bands.0,
            "l_high": bands.1,
            "seconds": {"turn": s[0], "camera": s[1], "frame": s[2]},
        });
        let mut bytes = encode(&frame, show, header)?;
        // The encoding's own time goes after the bytes (the page reads it from the header
        // `server-timing`).
        let encode_s = t.elapsed().as_secs_f64();
        bytes.shrink_to_fit();
        Ok((bytes, s, encode_s))
    })
    .await;
    match done {
        Ok((bytes, s, encode_s)) => {
            let timing = format!(
                "turn;dur={:.3}, camera;dur={:.3}, frame;dur={:.3}, encode;dur={:.3}",
                1e3 * s[0],
                1e3 * s[1],
                1e3 * s[2],
                1e3 * encode_s
            );
            (
                [
                    (header::CONTENT_TYPE, "application/octet-stream".to_string()),
                    (header::HeaderName::from_static("server-timing"), timing),
                ],
                bytes,
            )
                .into_response()
        }
        Err(response) => response,
    }
}

async fn save(
    State(app): State<Arc<App>>,
    Query(mut pairs): Query<Vec<(String, String)>>,
) -> Response {
    let polarizers = match take_polarizers(&mut pairs) {
        Ok(p) => p,
        Err(e) => return bad_request(&e),
    };
    let FrameQuery { mut request, .. } = match parse(&pairs) {
        Ok(q) => q,
        Err(e) => return bad_request(&e),
    };
    // A save is of the full frame.
    request.preview = false;
    let dir = app.save_dir.clone();
    let done = with_viewer(app, move |viewer, progress| {
        let frame = viewer.frame(&request, progress)?;
        viewer.save(&frame, &request, &polarizers, &dir)
    })
    .await;
    match done {
        Ok(out) => json(serde_json::json!({ "saved": out.display().to_string() })),
        Err(response) => response,
    }
}

/// Removes `polarizers=A,B,...` (degrees) from `pairs`; the angles. Error: missing, or
/// not numbers.
fn take_polarizers(pairs: &mut Vec<(String, String)>) -> psh::Result<Vec<f64>> {
    let k = pairs
        .iter()
        .position(|(k, _)| k == "polarizers")
        .ok_or_else(|| psh::Error::invalid("query parameter", "polarizers", "required"))?;
    let (_, text) = pairs.remove(k);
    text.split(',').map(crate::args::parse_degrees).collect()
}
