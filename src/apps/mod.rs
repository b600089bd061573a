//! Applications: reports, demos, figure reproductions, the render job and run time against
//! error. They compose the library and write files; nothing in the library imports them.
//!
//! | module | what | source |
//! |---|---|---|
//! | [`render_job`] | the render job (`cargo run --release`, `psh render`) | PSH Sec. 7 |
//! | [`bench_error`] | run time against error (`psh bench-error`) | PSH Fig. 19 |
//! | [`figure10`] | the rotation coefficient matrices of PSH Fig. 10 | PSH Fig. 10 |
//! | [`filter_report`] | the polarizing filter report (`psh filter-report`) | PF |
//! | [`isd_report`] | the ISD report (`psh isd-report`) | ISD Sec. 7 |
//! | [`light_scene`] | a procedural many-light scene | SHH Sec. 6.2 |
//! | [`lights_demo`] | adaptive light grids (`psh lights-demo`) | SHH Fig. 2 |
//! | [`polygon_scene`] | a procedural polygonal-light scene | SHG |
//! | [`polygon_lights_demo`] | polygonal lights on grids (`psh polygon-lights-demo`) | SHG |
//! | [`plot`] | line plots as PNG | |

pub mod bench_error;
pub mod figure10;
pub mod filter_report;
pub mod isd_report;
pub mod light_scene;
pub mod lights_demo;
pub mod plot;
pub mod polygon_lights_demo;
pub mod polygon_scene;
pub mod render_job;
