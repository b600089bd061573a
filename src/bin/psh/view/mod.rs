//! `psh view`: the scene precomputed once ([`psh::apps::Viewer`]), then a page on
//! loopback whose frames the server renders on request (`server`, the HTTP side; `query`,
//! a frame's parameters; `encode`, a frame's bytes; `page.html`, the page).

mod encode;
mod limits;
mod query;
mod server;

use crate::args::SceneArgs;
use crate::terminal::TerminalProgress;
use crate::Outcome;
use clap::Args;
use psh::apps::{ImageSize, RenderJob, Viewer};
use std::net::IpAddr;
use std::path::PathBuf;
use std::process::ExitCode;

/// The band limits a page can switch to besides the scene's own: the paper's (`l_low` 4,
/// `l_high` 9, PSH Fig. 18) and the low orders alone at `l_low` 2 (the fastest).
const MORE_BANDS: [(usize, Option<usize>); 2] = [(4, Some(9)), (2, None)];

#[derive(Args)]
pub struct ViewArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Image size WxH of the built-in scene at full size (a scene file gives its camera's).
    #[arg(long, default_value = "512x384")]
    size: ImageSize,
    /// The port to listen on (0: one the system chooses; the URL is printed).
    #[arg(long, default_value_t = 0)]
    port: u16,
    /// The address to listen on: loopback unless told otherwise (any other address
    /// serves the scene to the network).
    #[arg(long, default_value = "127.0.0.1")]
    bind: IpAddr,
    /// Where the page's "save" writes (a new view-NNN directory per save, never over an
    /// existing file).
    #[arg(long, default_value = "psh-view")]
    save_dir: PathBuf,
}

/// `psh view`: precomputes the scene (with progress on stderr), prints the page's URL on
/// stdout and serves it until interrupted.
pub fn run(a: &ViewArgs) -> psh::Result<Outcome> {
    let mut job = RenderJob::default();
    job.scene = a.scene.setup(a.size);
    job.out.clone_from(&a.save_dir);
    job.check_outputs()?;
    eprintln!("precomputing the scene for the view (and the paper's band limits, and l_low 2)");
    let viewer = Viewer::new(&job, &MORE_BANDS, &TerminalProgress::new())?;
    let listener = std::net::TcpListener::bind((a.bind, a.port)).map_err(|e| {
        psh::Error::invalid(
            "view address",
            format!("{}:{}", a.bind, a.port),
            format!("an address and port to listen on ({e})"),
        )
    })?;
    server::serve(listener, viewer, a.save_dir.clone())?;
    Ok(Outcome::Exit(ExitCode::SUCCESS))
}
