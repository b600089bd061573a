//! Applications: reports, demos, figure reproductions, the render job and run time against
//! error. They compose the library and write files; nothing in the library imports them.
//!
//! | module | what | source |
//! |---|---|---|
//! | [`render_settings`] | a render job's settings and their defaults ([`RenderJob`], [`SceneSetup`]) | |
//! | [`render_job`](mod@render_job) | the render job (`cargo run --release`, `psh render`) | PSH Sec. 7 |
//! | [`render_report`], [`render_pictures`] | its reports and pictures | PSH Sec. 7 |
//! | [`bench_error`] | run time against error (`psh bench-error`) | PSH Fig. 19 |
//! | [`filter_report`] | the polarizing filter report (`psh filter-report`) | PF |
//! | [`isd_report`] | the ISD report (`psh isd-report`) | ISD Sec. 7 |
//! | [`lights_demo`] | adaptive light grids (`psh lights-demo`) | SHH Fig. 2 |
//! | [`polygon_lights_demo`] | polygonal lights on grids (`psh polygon-lights-demo`) | SHG |
//! | [`plot`] | line plots as PNG | |
//! | [`view`] | the interactive viewer's frames and saved views (`psh view`) | PSH Sec. 7, Fig. 1 |

pub mod bench_error;
pub mod filter_report;
pub mod isd_report;
pub mod lights_demo;
pub mod plot;
pub mod polygon_lights_demo;
pub mod render_job;
pub mod render_pictures;
pub mod render_report;
pub mod render_settings;
pub mod view;

pub use render_job::{ablation_job, reference_job, render_job, JobReport, LoadedJob};
pub use render_pictures::polarizer_exposure;
pub use render_report::{AblationReport, ReferenceReport, RenderReport};
pub use render_settings::{ImageSize, Orbit, RenderJob, Renderer, SceneSetup, Shadows, ValidRange};
pub use view::{ViewFrame, ViewRequest, Viewer, MAX_VIEW_SIDE};
