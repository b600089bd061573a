//! The viewer (`psh view`'s renderer, `psh::apps::Viewer`): its frames are the render
//! job's for the same orbit, environment turn and band limits; its bad requests are
//! errors naming the value; a save never lands on an earlier one.

use psh::apps::{ImageSize, Orbit, RenderJob, ValidRange, ViewRequest, Viewer};
use psh::progress::Silent;

/// The largest difference between two images' components, relative to the largest `|s0|`.
fn relative_difference(a: &psh::pprt::StokesImage, b: &psh::pprt::StokesImage) -> f64 {
    let scale = a
        .channels
        .iter()
        .flatten()
        .map(|s| s[0].abs())
        .fold(0.0, f64::max);
    let diff = a
        .channels
        .iter()
        .flatten()
        .zip(b.channels.iter().flatten())
        .flat_map(|(x, y)| (0..4).map(move |p| (x[p] - y[p]).abs()))
        .fold(0.0, f64::max);
    diff / scale
}

/// A frame with the camera orbited and the environment turned (the transfer interpolated
/// over turns from 9 samples, `TransferTurns`, each the products redone with the
/// visibility kept; the high orders and the sky turned) equals the render job of a scene
/// set up with the same orbit and turn (precomputed from scratch), to rounding; a frame
/// back at turn 0 equals the job without a turn.
#[test]
fn a_view_frame_is_the_render_jobs_image() {
    let size = ImageSize {
        width: 64,
        height: 48,
    };
    let mut job = RenderJob::default();
    job.scene.size = size;
    let mut viewer = Viewer::new(&job, &[], &Silent).unwrap();
    assert_eq!(viewer.band_limits(), vec![(4, 9)]);
    let dir = std::env::temp_dir().join(format!("psh_view_{}", std::process::id()));
    for (k, (orbit, turn)) in [
        (
            Orbit {
                azimuth_deg: 25.0,
                elevation_deg: 10.0,
                zoom: 1.3,
            },
            40.0,
        ),
        (
            Orbit {
                azimuth_deg: -30.0,
                elevation_deg: -5.0,
                zoom: 0.8,
            },
            0.0,
        ),
    ]
    .into_iter()
    .enumerate()
    {
        let request = ViewRequest {
            orbit,
            environment_turn_deg: turn,
            size,
            bands: 0,
            valid_range: ValidRange::Keep,
            preview: false,
        };
        let frame = viewer.frame(&request, &Silent).unwrap();
        // Under the analytic sky a preview is the full frame.
        let preview = ViewRequest {
            preview: true,
            ..request
        };
        let quick = viewer.frame(&preview, &Silent).unwrap();
        assert_eq!(quick.image.channels, frame.image.channels);
        let mut other = job.clone();
        other.scene.orbit = Some(orbit);
        other.scene.environment_turn_deg = turn;
        other.valid_range = ValidRange::Keep;
        other.polarizers_deg = vec![0.0];
        other.out = dir.join(k.to_string());
        let (_, image) = other.load().unwrap().run(&Silent).unwrap();
        let image = image.unwrap();
        let d = relative_difference(&frame.image, &image);
        assert!(d < 1e-9, "orbit {orbit:?}, turn {turn}: {d:e}");
        assert_eq!(frame.image.object, image.object);
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// Requests out of range are errors naming the value, before any work; saves land in new
/// directories, never over an earlier one.
#[test]
fn bad_view_requests_are_errors_and_saves_never_clobber() {
    let size = ImageSize {
        width: 32,
        height: 24,
    };
    let mut job = RenderJob::default();
    job.scene.size = size;
    job.l_low = Some(2);
    job.l_high = Some(None);
    let mut viewer = Viewer::new(&job, &[], &Silent).unwrap();
    let good = ViewRequest {
        orbit: Orbit {
            azimuth_deg: 0.0,
            elevation_deg: 0.0,
            zoom: 1.0,
        },
        environment_turn_deg: 0.0,
        size,
        bands: 0,
        valid_range: ValidRange::Project,
        preview: false,
    };
    let bad = [
        (ViewRequest { bands: 1, ..good }, "band limits"),
        (
            ViewRequest {
                environment_turn_deg: f64::NAN,
                ..good
            },
            "environment turn",
        ),
        (
            ViewRequest {
                environment_turn_deg: 400.0,
                ..good
            },
            "environment turn",
        ),
        (
            ViewRequest {
                size: ImageSize {
                    width: 0,
                    height: 24,
                },
                ..good
            },
            "view size",
        ),
        (
            ViewRequest {
                size: ImageSize {
                    width: 5000,
                    height: 24,
                },
                ..good
            },
            "view size",
        ),
        (
            ViewRequest {
                orbit: Orbit {
                    elevation_deg: 95.0,
                    ..good.orbit
                },
                ..good
            },
            "camera orbit",
        ),
        (
            ViewRequest {
                orbit: Orbit {
                    zoom: 0.0,
                    ..good.orbit
                },
                ..good
            },
            "camera orbit",
        ),
        (
            ViewRequest {
                orbit: Orbit {
                    azimuth_deg: f64::INFINITY,
                    ..good.orbit
                },
                ..good
            },
            "camera orbit",
        ),
    ];
    for (request, word) in bad {
        let e = viewer.frame(&request, &Silent).err().expect("an error");
        assert!(e.to_string().contains(word), "{request:?}: {e}");
    }
    let frame = viewer.frame(&good, &Silent).unwrap();
    let dir = std::env::temp_dir().join(format!("psh_view_saves_{}", std::process::id()));
    let first = viewer.save(&frame, &good, &[0.0, 45.0], &dir).unwrap();
    let second = viewer.save(&frame, &good, &[0.0], &dir).unwrap();
    assert_ne!(first, second);
    assert!(first.join("polarizer_45.png").exists() && first.join("render_s0.exr").exists());
    assert!(!second.join("polarizer_45.png").exists());
    assert!(viewer.save(&frame, &good, &[f64::NAN], &dir).is_err());
    std::fs::remove_dir_all(&dir).ok();
}

/// The transfer interpolated over turns (`TransferTurns`, `2 l_low + 1` samples) equals the
/// products redone for the turned environment (`retransfer`) at turns between the samples:
/// each coefficient is a trigonometric polynomial of degree `l_low` in the turn.
#[test]
fn the_transfer_interpolated_over_turns_is_exact() {
    use psh::pprt::stages::{precompute_planned, retransfer, TransferTurns};
    use psh::pprt::{builtin_scene, Plan, Planning, TransferSettings};
    let scene = builtin_scene(9, 8, 6).unwrap();
    let plan = Plan::new(&scene, TransferSettings::default(), Planning::Full).unwrap();
    let transfer = precompute_planned(&scene, &plan, &Silent).unwrap();
    let turns = TransferTurns::new(&scene, &plan, &transfer, &Silent).unwrap();
    for angle in [0.3f64, -2.0, 4.0] {
        let turned = scene.clone().with_environment_turned(angle).unwrap();
        let direct = retransfer(&turned, &plan, &transfer, &Silent).unwrap();
        let interpolated = turns.at(&transfer, angle).unwrap();
        let (mut worst, mut scale) = (0.0f64, 0.0f64);
        for (a, b) in direct.iter().flatten().zip(interpolated.iter().flatten()) {
            for (x, y) in a.radiance.data().iter().zip(b.radiance.data()) {
                worst = worst.max((x - y).abs());
                scale = scale.max(x.abs());
            }
        }
        assert!(
            worst <= 1e-11 * scale,
            "turn {angle}: {worst:e} of {scale:e}"
        );
    }
}
