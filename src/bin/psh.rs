//! The `psh` command line: `verify`, `eval`, the environment-map pipeline
//! `project`, `rotate`, `reconstruct`, `filter-report` (PF), `convolve` and
//! `lights-demo` (SHH).

use clap::{Args, Parser, Subcommand, ValueEnum};
use num_complex::Complex64;
use psh::geometry::rotation_from_rotvec;
use psh::map::{MapLayout, StokesMap};
use psh::polarized::{Codomain, FieldArgument};
use psh::sh::MAX_DEGREE;
use psh::sh::{for_each_block, real_block};
use psh::sh::{sh_complex, sh_real};
use psh::Error;
use serde_json::json;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// `print!` that ends the process quietly (exit 0) when standard output is a closed pipe
/// (`psh eval ... | head`) instead of panicking; other write errors exit 1.
macro_rules! out {
    ($($arg:tt)*) => {
        write_stdout(format_args!($($arg)*))
    };
}

/// [`out!`] with a newline.
macro_rules! outln {
    ($($arg:tt)*) => {
        write_stdout(format_args!("{}\n", format_args!($($arg)*)))
    };
}

fn write_stdout(text: std::fmt::Arguments) {
    use std::io::Write;
    let mut stdout = std::io::stdout().lock();
    if let Err(e) = stdout.write_fmt(text).and_then(|()| stdout.flush()) {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        eprintln!("error: standard output: {e}");
        std::process::exit(1);
    }
}

#[derive(Parser)]
#[command(
    name = "psh",
    version,
    about = "Spherical harmonics for polarized light transport"
)]
struct Cli {
    /// Memory budget for work sized by the input (bytes, or with K, M, G, T: powers of
    /// 1024); default 4G, or $PSH_MAX_MEMORY. Work over it stops with an error naming the
    /// bytes it needs.
    #[arg(long, global = true, value_parser = psh::budget::parse_bytes)]
    max_memory: Option<u64>,
    #[command(subcommand)]
    command: Option<Command>,
}

/// Every argument that takes a value accepts a negative number as one (`--tolerance -0.5`
/// is the value -0.5, which psh then refuses with its reason, not an unknown flag).
fn allow_negative_numbers(cmd: clap::Command) -> clap::Command {
    cmd.mut_args(|a| {
        if a.get_action().takes_values() {
            a.allow_negative_numbers(true)
        } else {
            a
        }
    })
    .mut_subcommands(allow_negative_numbers)
}

#[derive(Subcommand)]
enum Command {
    /// Run the library's checks and print a table (or JSON); non-zero exit if any fails.
    Verify {
        /// Print a JSON array of {"id","source","description","max_error","tolerance","passed"}.
        #[arg(long)]
        json: bool,
        /// Run only the checks whose id contains this text.
        #[arg(long)]
        filter: Option<String>,
    },
    /// Evaluate basis functions or rotation matrices, printing JSON.
    #[command(subcommand)]
    Eval(Eval),
    /// Project a polarized environment map (EXR, one file per Stokes component) to PSH
    /// coefficients, written as a polarsh-compatible .npz.
    Project(ProjectArgs),
    /// Rotate a PSH coefficient vector (.npz) in the frequency domain (PSH (35)-(37)).
    Rotate(RotateArgs),
    /// Reconstruct a PSH coefficient vector (.npz) on an image: EXR per Stokes component
    /// and PNG pictures (s0..s3, degree and angle of polarization).
    Reconstruct(ReconstructArgs),
    /// Write the polarizing factor psi of PF Table 1's materials and the error of its
    /// specular-colour approximation (PF Fig. 3, Fig. 5) as CSV and PNG plots into a
    /// directory; print the largest errors (JSON, or a Markdown table).
    FilterReport(FilterReportArgs),
    /// Convolve a PSH coefficient vector (.npz) with a polarized kernel k(theta) by the
    /// convolution theorem (PSH (68)-(69)), writing a POLAR4 .npz.
    Convolve(ConvolveArgs),
    /// Apply an isotropic pBRDF coefficient matrix (ISOBI2 .npz, one matrix per channel) to
    /// a PSH coefficient vector (.npz) cut to the matrix's band limit (PSH (41)), writing the
    /// reflected field as a POLAR4 .npz; both files in polarsh's convention.
    Apply(ApplyArgs),
    /// Render a scene by precomputed polarized radiance transfer (PSH Sec. 7): pictures
    /// and report.json into a directory (the default command: the built-in scene into
    /// ./psh-out).
    Render(RenderArgs),
    /// Many spherical lights: uniform grids vs a Hessian-adaptive grid (SHH Sec. 5, 6.2),
    /// errors against the per-point exact SH coefficients; writes table.md and
    /// false-colour error images into a directory and prints the table (Markdown).
    LightsDemo(LightsDemoArgs),
    /// Many triangular lights (SHG): per-point exact SH coefficients vs grids of
    /// coefficients and gradients interpolated trilinearly and by cubic Hermite;
    /// writes table.md and error images into --out.
    PolygonLightsDemo(LightsDemoArgs),
    /// Isotropic spherical decomposition: condition numbers of M against L (ISD Fig. 13)
    /// as CSV and PNG, and ISD filtering timed against SH rotation; writes into a
    /// directory and prints the tables (Markdown).
    IsdReport(LightsDemoArgs),
    /// Run time against error: PPRT at l_max = 2..9 (full, no_shadow, low_only) and the
    /// reference renderer at a ladder of samples, against a high-sample ground truth;
    /// writes bench-error.json, .csv, .png and fig19.png (PSH Fig. 19) into a directory.
    BenchError(BenchErrorArgs),
    /// The paper's computable figures (PSH Figs. 5, 7, 8, 10, 11, 13, 16, 17, 19-22) as
    /// labelled PNGs, each with figN.md (caption, equations, the `psh verify` checks, the numbers),
    /// and the gallery figures.md into a directory; non-zero exit if a figure's
    /// comparison does not hold.
    Figures(FiguresArgs),
    /// The scene as a Mitsuba 3 scene (scene.xml, PLY meshes, the environment as a lat-long
    /// EXR, docs/mitsuba.md) into a directory; prints the files and the ways Mitsuba's
    /// scene differs from psh's (JSON).
    ExportMitsuba(ExportMitsubaArgs),
}

#[derive(Args)]
struct FiguresArgs {
    /// Output directory (created if missing).
    #[arg(long)]
    out: PathBuf,
    /// Only these figures (numbers such as 5,10 or stems such as fig10).
    #[arg(long, value_delimiter = ',')]
    only: Vec<String>,
    /// Smaller sizes: every figure in under a minute on 2 vCPUs.
    #[arg(long)]
    quick: bool,
    /// A Python interpreter with the `mitsuba` package (Mitsuba 3): PSH Fig. 19 also
    /// against Mitsuba 3's render of scenes/mitsuba_sky.toml.
    #[arg(long)]
    mitsuba: Option<PathBuf>,
}

#[derive(Args)]
struct ExportMitsubaArgs {
    /// A scene file (TOML); the built-in scene without it.
    #[arg(long)]
    scene: Option<PathBuf>,
    /// Output directory (created if missing).
    #[arg(long, default_value = "psh-mitsuba")]
    out: PathBuf,
    /// Image size WxH of the built-in scene.
    #[arg(long, default_value = "480x360", value_parser = parse_size)]
    size: ImageSize,
    /// How the analytic sky carries its sun (lobe or directional). Default: the scene's.
    #[arg(long, value_parser = parse_sun)]
    sun: Option<psh::pprt::Sun>,
    /// Mitsuba's samples per pixel.
    #[arg(long, default_value_t = 256)]
    spp: usize,
    /// Rows of the environment's lat-long map (columns: twice as many).
    #[arg(long, default_value_t = psh::io::ENVMAP_ROWS)]
    env_rows: usize,
}

#[derive(Args)]
struct BenchErrorArgs {
    /// A scene file (TOML); the built-in scene without it.
    #[arg(long)]
    scene: Option<PathBuf>,
    /// Output directory.
    #[arg(long)]
    out: PathBuf,
    /// Image size WxH (replaces the scene camera's).
    #[arg(long, default_value = "160x120", value_parser = parse_size)]
    size: ImageSize,
    /// Largest band limit of the PPRT rows.
    #[arg(long, default_value_t = 9)]
    lmax: usize,
    /// Visibility rays per vertex of the PPRT rows.
    #[arg(long, default_value_t = 256)]
    rays: usize,
    /// Samples per pixel of the reference rows, comma-separated.
    #[arg(long, default_value = "1,4,16,64,256", value_delimiter = ',', value_parser = parse_spp)]
    spp: Vec<usize>,
    /// Samples per pixel of the ground truth.
    #[arg(long, default_value_t = 2048)]
    ground_truth_spp: usize,
    /// An outside ground truth: a Stokes image EXR with layers S0..S3 (R, G, B), as
    /// Mitsuba 3's stokes integrator writes it, of the scene's camera (docs/mitsuba.md);
    /// psh's reference still renders the band-limit floor at --ground-truth-spp.
    #[arg(long)]
    ground_truth: Option<PathBuf>,
    /// How the analytic sky carries its sun (lobe or directional; the scene's by
    /// default), as in render.
    #[arg(long, value_parser = parse_sun)]
    sun: Option<psh::pprt::Sun>,
    /// Taper the environment's band limit (--lmax) by a window (none, hann, lanczos), as
    /// in render; the rows below --lmax cut the windowed coefficients.
    #[arg(long, default_value = "none", value_parser = parse_window)]
    window: psh::sh::Window,
}

#[derive(Args)]
struct RenderArgs {
    /// A scene file (TOML, format in src/pprt/scene_file.rs and docs/pprt.md); the
    /// built-in scene when absent. Its [settings] are overridden by the options given.
    #[arg(long)]
    scene: Option<PathBuf>,
    /// Band limit of the high orders by convolution and of the environment in the
    /// background (default 9, or the scene file's; no high orders when <= l_low).
    #[arg(long)]
    l_high: Option<usize>,
    /// Output directory.
    #[arg(long, default_value = "psh-out")]
    out: PathBuf,
    /// Band limit of the transfer (l <= l_low; default 4, or the scene file's).
    #[arg(long)]
    l_low: Option<usize>,
    /// Visibility rays per vertex (default 256, or the scene file's).
    #[arg(long)]
    rays: Option<usize>,
    /// Render without shadows (no visibility rays).
    #[arg(long)]
    no_shadows: bool,
    /// The ablation of PSH Figs. 20, 21 instead of one render: low orders only, then with
    /// shadows, then with the high orders, each in its own subdirectory, side by side in
    /// ablation_*.png, with times in ablation.json.
    #[arg(long, conflicts_with = "no_shadows")]
    ablation: bool,
    /// Image size WxH of the built-in scene (a scene file gives its camera's).
    #[arg(long, default_value = "480x360", value_parser = parse_size)]
    size: ImageSize,
    /// Polarizer angles in degrees (from image-right towards image-up), comma-separated.
    #[arg(
        long,
        default_value = "0,45,90,135",
        allow_hyphen_values = true,
        value_delimiter = ',',
        value_parser = parse_angle
    )]
    polarizer: Vec<f64>,
    /// Print the plan (what the scene needs and why, src/pprt/plan.rs) after rendering
    /// with it; the render is planned unless --no-plan.
    #[arg(long, conflicts_with = "no_plan")]
    plan: bool,
    /// Compute everything: full Stokes vectors, visibility rays, every nonzero matrix
    /// entry, every high order up to --l-high.
    #[arg(long)]
    no_plan: bool,
    /// Error tolerance of the plan's decisions (relative; in (0, 1)).
    #[arg(long, default_value_t = 1e-3)]
    tolerance: f64,
    /// Keep every pixel's Stokes vector as the transport computed it (the pixels breaking
    /// PSH (70) show in magenta). By default each is projected onto the physically valid
    /// range s0 >= |(s1, s2, s3)| (PSH (70), Fig. 22): the nearest valid vector, AoLP
    /// kept, never farther from the true one (proofs/stokes-valid-range.md); report.json
    /// counts the pixels before the projection either way.
    #[arg(long, conflicts_with = "ablation")]
    no_valid_range: bool,
    /// Taper the environment's band limit by a window (none, hann, lanczos;
    /// proofs/windowed-band-limits.md) before the transfer: less ringing, more blur.
    #[arg(long, default_value = "none", value_parser = parse_window)]
    window: psh::sh::Window,
    /// How the analytic sky carries its sun: lobe (in the environment's PSH
    /// coefficients) or directional (a directional light reflected exactly, with a shadow
    /// ray; src/pprt/direct.rs). Default: the scene's.
    #[arg(long, value_parser = parse_sun)]
    sun: Option<psh::pprt::Sun>,
    /// Print report.json's content (JSON) instead of a few lines for a person.
    #[arg(long)]
    json: bool,
    /// Render with the reference renderer instead of PPRT (quasi-Monte Carlo, the
    /// source environment, the materials' models, ray-cast visibility) with this many
    /// directions per pixel; the same pictures, and reference.json.
    #[arg(long, conflicts_with_all = ["ablation", "no_valid_range"], value_parser = parse_spp)]
    reference: Option<usize>,
    /// With --reference: each pixel the mean over G x G positions spread over its area (a
    /// box filter, as Mitsuba 3's), each with the --reference directions (G^2 times the work).
    #[arg(long, requires = "reference", default_value_t = 1)]
    pixel_grid: usize,
}

impl Default for RenderArgs {
    fn default() -> Self {
        Self {
            scene: None,
            l_high: None,
            out: "psh-out".into(),
            l_low: None,
            rays: None,
            no_shadows: false,
            ablation: false,
            size: ImageSize {
                width: 480,
                height: 360,
            },
            polarizer: vec![0.0, 45.0, 90.0, 135.0],
            plan: false,
            no_plan: false,
            tolerance: 1e-3,
            no_valid_range: false,
            window: psh::sh::Window::None,
            sun: None,
            json: false,
            reference: None,
            pixel_grid: 1,
        }
    }
}

#[derive(Args)]
struct LightsDemoArgs {
    /// Output directory (created if missing).
    #[arg(long)]
    out: PathBuf,
}

#[derive(Args)]
struct ConvolveArgs {
    /// Input .npz.
    input: PathBuf,
    /// A built-in kernel: linear-zenith, k(theta) = (pi - theta) I (PSH Sec. 6.4.3).
    #[arg(
        long,
        conflicts_with = "kernel_table",
        required_unless_present = "kernel_table"
    )]
    kernel: Option<KernelName>,
    /// A kernel table (CSV: theta in radians, then the 16 entries row-major; angles
    /// strictly increasing from 0 to pi; docs/conventions.md).
    #[arg(long)]
    kernel_table: Option<PathBuf>,
    /// Output .npz.
    #[arg(short, long)]
    output: PathBuf,
    /// Taper the band limit by a window (none, hann, lanczos; psh::sh::Window,
    /// proofs/windowed-band-limits.md): less ringing, more blur.
    #[arg(long, default_value = "none", value_parser = parse_window)]
    window: psh::sh::Window,
}

#[derive(Args)]
struct ApplyArgs {
    /// The pBRDF's isotropic coefficient matrices (.npz, dom_type ISOBI2).
    matrix: PathBuf,
    /// The incident field's coefficient vector (.npz).
    input: PathBuf,
    /// Output .npz.
    #[arg(short, long)]
    output: PathBuf,
}

#[derive(Clone, Copy, ValueEnum)]
enum KernelName {
    LinearZenith,
}

#[derive(Args)]
struct FilterReportArgs {
    /// Output directory (created if missing).
    #[arg(long)]
    out: PathBuf,
    /// Print the largest errors as a Markdown table instead of JSON.
    #[arg(long)]
    markdown: bool,
}

/// The polarsh names of the Stokes codomains.
#[derive(Clone, Copy, ValueEnum)]
enum CodomainName {
    #[value(name = "SCALAR")]
    Scalar,
    #[value(name = "POLAR2")]
    Polar2,
    #[value(name = "POLAR3")]
    Polar3,
    #[value(name = "POLAR4")]
    Polar4,
}

impl CodomainName {
    fn codomain(self) -> Codomain {
        match self {
            CodomainName::Scalar => Codomain::Intensity,
            CodomainName::Polar2 => Codomain::Linear,
            CodomainName::Polar3 => Codomain::NoCircular,
            CodomainName::Polar4 => Codomain::Full,
        }
    }
}

#[derive(Args)]
struct ProjectArgs {
    /// The component files: a pattern with %d (map_s%d.exr) or one of them (map_s0.exr);
    /// or one EXR file with layers S0..S3 (Mitsuba 3's multichannel layout), same frames.
    input: String,
    /// Band limit: coefficients of degrees l <= lmax.
    #[arg(long)]
    lmax: usize,
    /// Stokes components to keep: POLAR2 (s1, s2), POLAR3 (s0..s2) or POLAR4 (s0..s3).
    #[arg(long, value_enum, default_value = "POLAR4")]
    codomain: CodomainName,
    /// Output .npz.
    #[arg(short, long)]
    output: PathBuf,
    /// Taper the band limit by a window (none, hann, lanczos; psh::sh::Window,
    /// proofs/windowed-band-limits.md): less ringing, more blur.
    #[arg(long, default_value = "none", value_parser = parse_window)]
    window: psh::sh::Window,
}

#[derive(Args)]
struct RotateArgs {
    /// Input .npz.
    input: PathBuf,
    /// Rotation vector X,Y,Z: axis times angle in radians (active rotation, PSH (8)).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_rotvec)]
    rotvec: [f64; 3],
    /// Output .npz.
    #[arg(short, long)]
    output: PathBuf,
}

#[derive(Args)]
struct ReconstructArgs {
    /// Input .npz.
    input: PathBuf,
    /// Equirectangular image of H rows and W = 2H columns.
    #[arg(
        long,
        conflicts_with = "cube",
        required_unless_present = "cube",
        value_parser = parse_equirect
    )]
    equirect: Option<EquirectSize>,
    /// Cube cross of faces of E x E texels (3E x 4E image).
    #[arg(long)]
    cube: Option<usize>,
    /// Output prefix: writes {prefix}_s0..s3.exr and {prefix}_{s0,s1,s2,s3,dop,aop}.png.
    #[arg(short, long)]
    output: String,
    /// Taper the band limit by a window (none, hann, lanczos; psh::sh::Window,
    /// proofs/windowed-band-limits.md): less ringing, more blur.
    #[arg(long, default_value = "none", value_parser = parse_window)]
    window: psh::sh::Window,
}

#[derive(Subcommand)]
enum Eval {
    /// SH of all l <= lmax at one direction, flat order l*l + l + m, as [re, im] pairs.
    Sh(ShArgs),
    /// Wigner D blocks l <= lmax of the rotation given by a rotation vector.
    Wigner(WignerArgs),
    /// Spin-weighted SH sY_lm of all l <= lmax at one direction (flat order, zeros where
    /// l < |spin|), as [re, im] pairs.
    Swsh(SwshArgs),
    /// One complex or real Wigner D block D^l (PSH (9), (13)) of the rotation given by a
    /// rotation vector, written as a .npy file (rows m, columns m'; complex as [re, im]).
    WignerBlock(WignerBlockArgs),
    /// Spin-weighted SH sY_lm, l <= lmax, at many directions (a .npy of [theta, phi] rows),
    /// written as a .npy of shape [points, (lmax+1)^2, 2] (flat order, [re, im]).
    SwshPoints(SwshPointsArgs),
    /// Real SH (PSH (12)) with their Cartesian gradients and Hessians (psh::sh::solid) at
    /// many unit directions (a .npy of [x, y, z] rows), written as a .npy of shape
    /// [points, (lmax+1)^2, 10]: value, gradient x, y, z, Hessian xx, xy, xz, yy, yz, zz.
    ShDerivatives(ShDerivativesArgs),
    /// Normalized associated Legendre functions Pbar_lm(theta), m = 0..=l, at one degree l
    /// (PSH (1)), printing JSON.
    Legendre(LegendreArgs),
    /// The Gauss-Legendre rule of n rings (psh::sh::GaussLegendre): polar angles theta_j
    /// (increasing from the north pole) and weights w_j, printing JSON.
    Grid(GridArgs),
    /// Scalar SH transform (psh::sh::ShTransform) on the Gauss-Legendre grid of
    /// lmax + 1 rings by 2 lmax + 2 meridians, .npy in and out.
    Sht(ShtArgs),
    /// Spin-weighted SH transform (psh::swsh::SpinTransform) on the same grid,
    /// .npy in and out (complex as [re, im]).
    SpinSht(SpinShtArgs),
    /// Fresnel reflection of a planar interface (psh::optics::fresnel): amplitude
    /// coefficients and the Mueller matrices in the travel frames and in psh's frames,
    /// printing JSON.
    Fresnel(FresnelArgs),
    /// The cosine-weighted GGX microfacet pBRDF P(w_i, w_o) of a complex index
    /// (psh::optics::MicrofacetSpecular) in its s/p frames, printing JSON.
    Microfacet(MicrofacetArgs),
    /// The Mueller matrix of the ideal linear polarizer (psh::optics::LinearPolarizer),
    /// printing JSON.
    Polarizer(PolarizerArgs),
}

#[derive(Args)]
struct WignerBlockArgs {
    #[arg(long, value_enum)]
    kind: Kind,
    /// The degree l of the block.
    #[arg(long)]
    l: usize,
    /// Rotation vector X,Y,Z: axis times angle in radians (active rotation, PSH (8)).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_rotvec)]
    rotvec: [f64; 3],
    /// Output .npy: float64 [2l+1, 2l+1] (real) or [2l+1, 2l+1, 2] (complex).
    #[arg(short, long)]
    output: PathBuf,
}

#[derive(Args)]
struct SwshPointsArgs {
    /// Spin weight s.
    #[arg(long, allow_hyphen_values = true)]
    spin: i64,
    #[arg(long)]
    lmax: usize,
    /// Input .npy: float64 [points, 2] of (theta, phi) in radians.
    #[arg(long)]
    points: PathBuf,
    /// Output .npy: float64 [points, (lmax+1)^2, 2].
    #[arg(short, long)]
    output: PathBuf,
}

#[derive(Args)]
struct ShDerivativesArgs {
    #[arg(long)]
    lmax: usize,
    /// Input .npy: float64 [points, 3] of unit directions.
    #[arg(long)]
    points: PathBuf,
    /// Output .npy: float64 [points, (lmax+1)^2, 10].
    #[arg(short, long)]
    output: PathBuf,
}

#[derive(Args)]
struct LegendreArgs {
    /// The degree l.
    #[arg(long)]
    l: usize,
    /// Polar angle in radians, in [0, pi].
    #[arg(long, allow_hyphen_values = true)]
    theta: f64,
    /// The f64 path of the transforms (psh::sh::Legendre) instead of the
    /// double-double path (for_each_column_accurate).
    #[arg(long)]
    fast: bool,
}

#[derive(Args)]
struct GridArgs {
    /// Number of rings, 1..=8193 (the grid of band limit 8192).
    #[arg(long)]
    n: usize,
}

#[derive(Clone, Copy, ValueEnum)]
enum TransformOp {
    /// Coefficients (flat order l*l + l + m) to grid values (ring-major).
    Synthesis,
    /// Grid values to coefficients.
    Analysis,
}

#[derive(Args)]
struct ShtArgs {
    #[arg(long, value_enum)]
    kind: Kind,
    #[arg(long)]
    lmax: usize,
    #[arg(long, value_enum)]
    op: TransformOp,
    /// Input .npy: coefficients [(lmax+1)^2] (real) or [(lmax+1)^2, 2] (complex) for
    /// synthesis; grid values [lmax+1, 2 lmax+2] (real) or [lmax+1, 2 lmax+2, 2] (complex)
    /// for analysis.
    #[arg(long)]
    input: PathBuf,
    /// Output .npy (the other of the two shapes).
    #[arg(short, long)]
    output: PathBuf,
}

#[derive(Args)]
struct SpinShtArgs {
    /// Spin weight s, 1 <= |s| <= lmax.
    #[arg(long, allow_hyphen_values = true)]
    spin: i64,
    #[arg(long)]
    lmax: usize,
    #[arg(long, value_enum)]
    op: TransformOp,
    /// Input .npy: coefficients [(lmax+1)^2, 2] for synthesis; grid values
    /// [lmax+1, 2 lmax+2, 2] for analysis.
    #[arg(long)]
    input: PathBuf,
    /// Output .npy (the other of the two shapes).
    #[arg(short, long)]
    output: PathBuf,
}

#[derive(Args)]
struct FresnelArgs {
    /// Real part n of the relative index of refraction eta = n + i k.
    #[arg(long)]
    n: f64,
    /// Extinction coefficient k >= 0 (e^{-i omega t} convention).
    #[arg(long, default_value_t = 0.0)]
    k: f64,
    /// Cosines of the angle of incidence, comma-separated, each in [0, 1].
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        required = true
    )]
    cos_i: Vec<f64>,
}

#[derive(Args)]
struct MicrofacetArgs {
    /// GGX roughness alpha.
    #[arg(long)]
    alpha: f64,
    /// Real part n of the relative index eta = n + i k.
    #[arg(long)]
    n: f64,
    /// Extinction coefficient k >= 0.
    #[arg(long, default_value_t = 0.0)]
    k: f64,
    /// Smith's masking-shadowing form: height-correlated or separable.
    #[arg(long, default_value = "height-correlated")]
    masking: String,
    /// Direction towards the source X,Y,Z in the shading frame (normal +z).
    #[arg(
        long,
        allow_hyphen_values = true,
        value_delimiter = ',',
        required = true
    )]
    wi: Vec<f64>,
    /// Direction towards the viewer X,Y,Z.
    #[arg(
        long,
        allow_hyphen_values = true,
        value_delimiter = ',',
        required = true
    )]
    wo: Vec<f64>,
}

#[derive(Args)]
struct PolarizerArgs {
    /// Angle varphi of the transmission axis from x towards y, in radians.
    #[arg(long, allow_hyphen_values = true)]
    angle: f64,
}

#[derive(Args)]
struct SwshArgs {
    /// Spin weight s (2 for linear polarization).
    #[arg(long, allow_hyphen_values = true)]
    spin: i64,
    #[command(flatten)]
    at: Evaluation,
}

/// The band limit and direction of an evaluation.
#[derive(Args)]
struct Evaluation {
    #[arg(long)]
    lmax: usize,
    /// Polar angle in radians, in [0, pi].
    #[arg(long, allow_hyphen_values = true)]
    theta: f64,
    /// Azimuth in radians.
    #[arg(long, allow_hyphen_values = true)]
    phi: f64,
}

/// Largest degree `psh eval swsh` and `swsh-points` evaluate: the Wigner-d construction
/// of [`psh::swsh::swsh`] costs `lmax^3` per direction (5 s at 1024, 41 s at 2048). It is
/// the reference the `O(lmax^2)` `SpinEvaluator` (Python's `psh.swsh`) is checked against;
/// both meet `10 l eps` of the bound at the poles (`proofs/swsh.md`).
const MAX_SWSH_EVAL_DEGREE: usize = 1024;

/// Largest `points x (lmax+1)^3` of `psh eval swsh-points` (about a minute).
const MAX_SWSH_POINTS_WORK: u128 = 1 << 36;

#[derive(Clone, Copy, ValueEnum)]
enum Kind {
    Real,
    Complex,
}

impl Kind {
    fn name(self) -> &'static str {
        match self {
            Kind::Real => "real",
            Kind::Complex => "complex",
        }
    }
}

#[derive(Args)]
struct ShArgs {
    #[arg(long, value_enum)]
    kind: Kind,
    #[command(flatten)]
    at: Evaluation,
}

#[derive(Args)]
struct WignerArgs {
    #[arg(long, value_enum)]
    kind: Kind,
    #[arg(long)]
    lmax: usize,
    /// Rotation vector X,Y,Z: axis times angle in radians (active rotation, PSH (8)).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_rotvec)]
    rotvec: [f64; 3],
}

/// Largest degree `psh eval wigner` prints (the output grows like lmax^3).
const MAX_WIGNER_EVAL_DEGREE: usize = 200;

/// Progress drawn on stderr by indicatif when it is a terminal (hidden otherwise).
struct TerminalProgress(indicatif::ProgressBar);

impl TerminalProgress {
    fn new() -> Self {
        Self(indicatif::ProgressBar::hidden())
    }
}

impl psh::progress::Progress for TerminalProgress {
    fn start(&self, what: &str, total: u64) {
        self.0.reset();
        self.0
            .set_draw_target(indicatif::ProgressDrawTarget::stderr());
        self.0.set_length(total);
        self.0.set_position(0);
        // The template is a constant: it parses.
        if let Ok(style) =
            indicatif::ProgressStyle::with_template("{msg} {bar:40} {pos}/{len}, {eta} left")
        {
            self.0.set_style(style);
        }
        self.0.set_message(what.to_string());
    }

    fn advance(&self, n: u64) {
        self.0.inc(n);
    }

    fn finish(&self) {
        self.0.finish_and_clear();
    }
}

fn main() -> ExitCode {
    use clap::{CommandFactory, FromArgMatches};
    let parsed = allow_negative_numbers(Cli::command())
        .try_get_matches()
        .and_then(|m| Cli::from_arg_matches(&m));
    let cli = match parsed {
        Ok(c) => c,
        Err(e) => {
            use clap::error::ErrorKind::{DisplayHelp, DisplayVersion};
            if matches!(e.kind(), DisplayHelp | DisplayVersion) {
                out!("{e}");
                return ExitCode::SUCCESS;
            }
            // clap's whole message: the error, the usage, and its suggestions.
            eprint!("{e}");
            return ExitCode::from(2);
        }
    };
    if let Some(bytes) = cli.max_memory {
        psh::budget::set_budget(bytes);
    }
    let result = match cli
        .command
        .unwrap_or(Command::Render(RenderArgs::default()))
    {
        Command::Verify { json, filter } => return verify(json, filter.as_deref()),
        Command::Eval(Eval::Sh(a)) => eval_sh(&a),
        Command::Eval(Eval::Wigner(a)) => eval_wigner(&a),
        Command::Eval(Eval::Swsh(a)) => eval_swsh(&a),
        Command::Eval(Eval::WignerBlock(a)) => eval_wigner_block(&a),
        Command::Eval(Eval::SwshPoints(a)) => eval_swsh_points(&a),
        Command::Eval(Eval::ShDerivatives(a)) => eval_sh_derivatives(&a),
        Command::Eval(Eval::Legendre(a)) => eval_legendre(&a),
        Command::Eval(Eval::Grid(a)) => eval_grid(&a),
        Command::Eval(Eval::Sht(a)) => eval_sht(&a),
        Command::Eval(Eval::SpinSht(a)) => eval_spin_sht(&a),
        Command::Eval(Eval::Fresnel(a)) => eval_fresnel(&a),
        Command::Eval(Eval::Microfacet(a)) => eval_microfacet(&a),
        Command::Eval(Eval::Polarizer(a)) => eval_polarizer(&a),
        Command::Project(a) => project(&a),
        Command::Rotate(a) => rotate(&a),
        Command::Reconstruct(a) => reconstruct(&a),
        Command::FilterReport(a) => return filter_report(&a),
        Command::Convolve(a) => convolve(&a),
        Command::Apply(a) => apply(&a),
        Command::Render(a) if !a.json => {
            return print_table(render(&a).map(|(v, name)| render_summary(&v, &name, &a.out)))
        }
        Command::Render(a) => render(&a).map(|(v, _)| v),
        Command::LightsDemo(a) => return lights_demo(&a),
        Command::IsdReport(a) => return isd_report(&a),
        Command::BenchError(a) => bench_error(&a),
        Command::ExportMitsuba(a) => export_mitsuba(&a),
        Command::Figures(a) => return figures(&a),
        Command::PolygonLightsDemo(a) => return polygon_lights_demo(&a),
    };
    match result {
        Ok(v) => {
            outln!("{v}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(1)
        }
    }
}

fn isd_report(a: &LightsDemoArgs) -> ExitCode {
    print_table(
        psh::apps::isd_report::write_isd_report(
            &a.out,
            psh::apps::isd_report::PAPER_TOP,
            &TerminalProgress::new(),
        )
        .map(|r| r.markdown_table()),
    )
}

fn polygon_lights_demo(a: &LightsDemoArgs) -> ExitCode {
    print_table(
        psh::apps::polygon_lights_demo::write_polygon_lights_demo(
            &a.out,
            psh::apps::polygon_lights_demo::PAPER_FINEST,
            &TerminalProgress::new(),
        )
        .map(|r| r.markdown_table()),
    )
}

fn lights_demo(a: &LightsDemoArgs) -> ExitCode {
    print_table(psh::apps::lights_demo::write_lights_demo(&a.out).map(|r| r.markdown_table()))
}

fn figures(a: &FiguresArgs) -> ExitCode {
    use psh::figures;
    let options = figures::FigureOptions {
        quick: a.quick,
        mitsuba: a.mitsuba.clone(),
    };
    let done = |r: &figures::FigureReport| {
        let verdict = r.comparison.as_ref().map_or(String::new(), |c| {
            let holds = if c.holds { "holds" } else { "DOES NOT HOLD" };
            format!(": {} ({holds})", c.measured)
        });
        outln!("{} in {:.2} s{verdict}", r.id, r.seconds);
    };
    let table = figures::select(&a.only)
        .and_then(|f| figures::run(&f, &a.out, &options, &TerminalProgress::new(), &done))
        .map(|_| format!("figures and figures.md written to {}\n", a.out.display()));
    print_table(table)
}

/// Prints a report's Markdown table, or the error.
fn print_table(table: psh::Result<String>) -> ExitCode {
    match table {
        Ok(t) => {
            out!("{t}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(1)
        }
    }
}

fn filter_report(a: &FilterReportArgs) -> ExitCode {
    let report = match psh::apps::filter_report::write_filter_report(&a.out) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(1);
        }
    };
    if a.markdown {
        out!("{}", report.markdown_table());
    } else {
        let errors: Vec<serde_json::Value> = report
            .errors
            .iter()
            .map(|e| {
                json!({
                    "material": e.material.name(),
                    "channel": format!("{:?}", e.channel),
                    "r0_ior": e.r0_ior,
                    "r0_table": e.r0_printed,
                    "max_error_60deg": e.from_ior[0].abs,
                    "max_error_89deg": e.from_ior[1].abs,
                    "max_error_table_r0_60deg": e.printed[0].abs,
                    "max_error_table_r0_89deg": e.printed[1].abs,
                })
            })
            .collect();
        outln!(
            "{}",
            json!({"out": a.out, "files": report.files, "max_error": errors})
        );
    }
    ExitCode::SUCCESS
}

fn verify(json: bool, filter: Option<&str>) -> ExitCode {
    let results = psh::verify::run(filter);
    if let (true, Some(f)) = (results.is_empty(), filter) {
        eprintln!(
            "error: no check id contains {:?} (`psh verify` without --filter lists them all)",
            psh::error::clip(f)
        );
        return ExitCode::from(2);
    }
    let ok = results.iter().all(|r| r.passed);
    if json {
        outln!(
            "{}",
            serde_json::to_string_pretty(&results).expect("plain data")
        );
    } else {
        outln!(
            "{:<36} {:<16} {:>10} {:>10}  result",
            "check",
            "source",
            "max error",
            "tolerance"
        );
        for r in &results {
            outln!(
                "{:<36} {:<16} {:>10.2e} {:>10.1e}  {}",
                r.id,
                r.source,
                r.max_error,
                r.tolerance,
                match (r.passed, &r.skipped) {
                    (_, Some(_)) => "skip",
                    (true, None) => "pass",
                    (false, None) => "FAIL",
                }
            );
            if let Some(e) = &r.error {
                outln!("    error: {e}");
            }
            if let Some(s) = &r.skipped {
                outln!("    skipped: {s}");
            }
        }
        let failed = results.iter().filter(|r| !r.passed).count();
        let skipped = results.iter().filter(|r| r.skipped.is_some()).count();
        outln!(
            "{} passed, {} failed, {} skipped",
            results.len() - failed - skipped,
            failed,
            skipped
        );
    }
    if ok {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}

fn pairs(v: impl IntoIterator<Item = Complex64>) -> Vec<[f64; 2]> {
    v.into_iter().map(|z| [z.re, z.im]).collect()
}

/// Bytes a printed number holds: its JSON value and its text.
const JSON_NUMBER_BYTES: usize = 64;

fn eval_sh(args: &ShArgs) -> psh::Result<serde_json::Value> {
    let a = &args.at;
    psh::sh::check_lmax(a.lmax)?;
    let n = psh::sh::num_coeffs(a.lmax);
    psh::budget::check("the printed SH values (JSON)", &[n, 2], JSON_NUMBER_BYTES)?;
    let values = match args.kind {
        Kind::Real => pairs(
            sh_real(a.lmax, a.theta, a.phi)?
                .into_iter()
                .map(|x| Complex64::new(x, 0.0)),
        ),
        Kind::Complex => pairs(sh_complex(a.lmax, a.theta, a.phi)?),
    };
    Ok(
        json!({"lmax": a.lmax, "theta": a.theta, "phi": a.phi, "kind": args.kind.name(), "values": values}),
    )
}

fn eval_swsh(args: &SwshArgs) -> psh::Result<serde_json::Value> {
    let a = &args.at;
    if a.lmax > MAX_SWSH_EVAL_DEGREE {
        return Err(Error::DegreeOutOfRange {
            name: "lmax",
            value: a.lmax as i128,
            reason: format!("psh eval swsh evaluates at most lmax = {MAX_SWSH_EVAL_DEGREE}"),
        });
    }
    let values = pairs(psh::swsh::swsh(args.spin, a.lmax, a.theta, a.phi)?);
    Ok(json!({"lmax": a.lmax, "spin": args.spin, "theta": a.theta, "phi": a.phi, "values": values}))
}

/// A rotation vector `X,Y,Z`.
fn parse_rotvec(text: &str) -> psh::Result<[f64; 3]> {
    let parts: Vec<&str> = text.split(',').collect();
    let bad = |reason: &str| Error::InvalidRotation {
        value: text.to_string(),
        reason: reason.into(),
    };
    if parts.len() != 3 {
        return Err(bad("expected three comma-separated numbers X,Y,Z"));
    }
    let mut v = [0.0; 3];
    for (c, p) in v.iter_mut().zip(&parts) {
        *c = p.trim().parse().map_err(|_| bad("not a number"))?;
    }
    Ok(v)
}

/// Runs `body`, whose files appear together or not at all and never over one of
/// `inputs`; `output`, known in advance, is checked before any work.
fn writing<T>(
    inputs: &[PathBuf],
    output: &Path,
    body: impl FnOnce() -> psh::Result<T>,
) -> psh::Result<T> {
    psh::io::refuse_input(inputs, output)?;
    psh::io::all_or_nothing(inputs, body)
}

fn project(a: &ProjectArgs) -> psh::Result<serde_json::Value> {
    let codomain = a.codomain.codomain();
    psh::sh::check_lmax(a.lmax)?;
    let inputs = psh::io::stokes_map_files(&a.input)?;
    let (map, v) = writing(&inputs, &a.output, || {
        let map = psh::io::read_stokes_map(&a.input)?;
        let mut v = map.project(codomain, a.lmax)?;
        v.apply_window(a.window);
        psh::io::write_psh_npz(&a.output, &v)?;
        Ok((map, v))
    })?;
    Ok(json!({
        "input": a.input, "layout": [map.layout().height(), map.layout().width()],
        "channels": v.channels(), "lmax": v.lmax(), "codomain": codomain.name(),
        "window": a.window.name(), "output": a.output,
    }))
}

fn rotate(a: &RotateArgs) -> psh::Result<serde_json::Value> {
    let rotvec = a.rotvec;
    let r = rotation_from_rotvec(rotvec)?;
    let v = writing(std::slice::from_ref(&a.input), &a.output, || {
        let v = psh::io::read_psh_npz(&a.input)?;
        psh::io::write_psh_npz(&a.output, &v.rotated(&r)?)?;
        Ok(v)
    })?;
    Ok(json!({"input": a.input, "rotvec": rotvec, "lmax": v.lmax(), "output": a.output}))
}

fn apply(a: &ApplyArgs) -> psh::Result<serde_json::Value> {
    writing(&[a.matrix.clone(), a.input.clone()], &a.output, || {
        apply_files(a)
    })
}

fn apply_files(a: &ApplyArgs) -> psh::Result<serde_json::Value> {
    let m = psh::io::read_isotropic_npz(&a.matrix)?;
    let v = psh::io::read_psh_npz(&a.input)?;
    let cut = v.truncated(m.lmax()).map_err(|e| Error::MalformedFile {
        path: a.input.clone(),
        reason: format!(
            "the matrix {} needs l <= {}: {e}",
            a.matrix.display(),
            m.lmax()
        ),
    })?;
    let out = m.apply(&cut)?;
    psh::io::write_psh_npz(&a.output, &out)?;
    Ok(json!({
        "matrix": a.matrix, "input": a.input, "lmax": m.lmax(), "channels": out.channels(),
        "output": a.output,
    }))
}

fn convolve(a: &ConvolveArgs) -> psh::Result<serde_json::Value> {
    let inputs: Vec<PathBuf> = std::iter::once(a.input.clone())
        .chain(a.kernel_table.clone())
        .collect();
    writing(&inputs, &a.output, || convolve_files(a))
}

fn convolve_files(a: &ConvolveArgs) -> psh::Result<serde_json::Value> {
    let v = psh::io::read_psh_npz(&a.input)?;
    let (kernel, name) = match (&a.kernel, &a.kernel_table) {
        (Some(KernelName::LinearZenith), _) => (
            psh::polarized::ConvolutionKernel::linear_zenith(),
            "linear-zenith".to_string(),
        ),
        (None, Some(path)) => (psh::io::read_kernel_csv(path)?, path.display().to_string()),
        (None, None) => unreachable!("clap requires --kernel or --kernel-table"),
    };
    let k = psh::polarized::kernel_coefficients(&kernel, v.lmax())?;
    let out = k.convolve(&v)?.windowed(a.window);
    psh::io::write_psh_npz(&a.output, &out)?;
    Ok(json!({
        "input": a.input, "kernel": name, "lmax": v.lmax(), "window": a.window.name(),
        "quadrature_error_estimate": k.error_estimate(), "output": a.output,
    }))
}

/// Runs `psh render`: the report as JSON and the scene's name.
fn render(a: &RenderArgs) -> psh::Result<(serde_json::Value, String)> {
    let (w, h) = (a.size.width, a.size.height);
    let polarizers = &a.polarizer;
    let (scene, settings, name) = psh::apps::render_job::job_scene(
        a.scene.as_deref(),
        (w, h),
        &psh::apps::render_job::SceneOverrides {
            l_low: a.l_low,
            l_high: a.l_high,
            rays: a.rays,
            shadows: !a.no_shadows,
            window: a.window,
            sun: a.sun,
        },
    )?;
    eprintln!(
        "rendering {name} ({} triangles, l_low {}, l_high {}, {} rays per vertex) into {}",
        scene.triangle_count(),
        settings.l_low,
        settings.l_high,
        settings.rays,
        a.out.display()
    );
    if let Some(samples) = a.reference {
        let (report, _) = psh::apps::render_job::reference_job(
            &scene,
            samples,
            a.pixel_grid,
            polarizers,
            &a.out,
        )?;
        return Ok((to_json(&report)?, name));
    }
    if a.ablation {
        let report = psh::apps::render_job::ablation_job(
            &scene,
            settings,
            polarizers,
            &a.out,
            &TerminalProgress::new(),
        )?;
        return Ok((to_json(&report)?, name));
    }
    let planning = if a.no_plan {
        psh::pprt::Planning::Full
    } else {
        psh::pprt::Planning::Tolerance(a.tolerance)
    };
    let (report, _) = psh::apps::render_job::render_job(
        &scene,
        settings,
        planning,
        polarizers,
        &a.out,
        !a.no_valid_range,
        &TerminalProgress::new(),
    )?;
    if a.plan {
        outln!("plan (tolerance {:e}):", a.tolerance);
        for r in &report.plan.reasons {
            outln!("  - {r}");
        }
    }
    Ok((to_json(&report)?, name))
}

/// A render's report (or an ablation's) in a few lines for a person: the scene and
/// settings, the times, the pixels that break PSH (70), where the pictures are.
fn render_summary(v: &serde_json::Value, name: &str, out: &Path) -> String {
    let f = |x: &serde_json::Value| x.as_f64().unwrap_or(0.0);
    let mut text = String::new();
    let mut line = |l: String| {
        text.push_str(&l);
        text.push('\n');
    };
    if let Some(samples) = v["samples_per_pixel"].as_u64() {
        let image = &v["image"];
        line(format!(
            "rendered {name}, {} x {}, by the reference renderer at {samples} directions per pixel in {:.2} s; pictures and reference.json in {}",
            image[0],
            image[1],
            f(&v["seconds"]),
            out.display()
        ));
        return text;
    }
    if let Some(variants) = v["variants"].as_array() {
        line(format!(
            "ablation of {name} (PSH Figs. 20, 21) in {}:",
            out.display()
        ));
        for var in variants {
            let t = &var["times_s"];
            line(format!(
                "  {}: precompute {:.2} s, frame {:.3} s",
                var["variant"].as_str().unwrap_or("?"),
                f(&t["precompute"]),
                f(&t["frame"])
            ));
        }
        line("  side by side: ablation_{s0,s1,s2,s3,dop,aop}.png; times in ablation.json".into());
        return text;
    }
    let st = &v["settings"];
    let image = &st["image"];
    line(format!(
        "rendered {name}, {} x {}: l_low {}, l_high {}, {} rays per vertex, shadows {}, sun {}, window {}",
        image[0],
        image[1],
        st["l_low"],
        st["l_high"],
        st["rays_per_vertex"],
        if st["shadows"].as_bool() == Some(true) { "on" } else { "off" },
        st["sun"].as_str().unwrap_or("none (not the analytic sky)"),
        st["window"].as_str().unwrap_or("none"),
    ));
    let t = &v["times_s"];
    line(format!(
        "  time: plan {:.2} s, precompute {:.2} s, per camera {:.2} s, frame {:.3} s, pictures {:.2} s",
        f(&t["plan"]),
        f(&t["precompute"]),
        f(&t["primary_visibility_and_direct_light"]),
        f(&t["frame"]),
        f(&t["pictures"])
    ));
    let u = &v["unphysical_pixels"];
    let pixels = (f(&image[0]) * f(&image[1])).max(1.0);
    let count = |key: &str| -> (String, f64) {
        let c: Vec<f64> = (0..3).map(|i| f(&u[key][i])).collect();
        let worst = c.iter().fold(0.0f64, |a, &b| a.max(b));
        (
            format!("{} / {} / {}", c[0], c[1], c[2]),
            100.0 * worst / pixels,
        )
    };
    let projected = st["valid_range_projection"].as_bool() == Some(true);
    for (place, neg, dop) in [
        (
            "on surfaces",
            "surface_s0_negative",
            "surface_dop_above_one",
        ),
        ("in the sky", "sky_s0_negative", "sky_dop_above_one"),
    ] {
        let ((n, np), (d, dp)) = (count(neg), count(dop));
        line(format!(
            "  pixels breaking PSH (70) {place}{} (R / G / B): s0 < 0 {n} ({np:.2}%), DoP > 1 {d} ({dp:.2}%){}",
            if projected { " before the projection" } else { "" },
            if projected {
                ", none in the pictures (projected onto the valid range; --no-valid-range keeps them)"
            } else if np + dp > 0.0 {
                ", magenta in the pictures"
            } else {
                ""
            }
        ));
    }
    let pictures = v["pictures"].as_array().map_or(0, Vec::len);
    line(format!(
        "  {pictures} pictures in {}: render_s0.png (intensity), render_dop.png, render_aop.png, polarizer_*.png, render_s{{0,1,2,3}}.exr",
        out.display()
    ));
    line(format!(
        "  report: {} (or --json)",
        out.join("report.json").display()
    ));
    text
}

/// A report as JSON.
fn to_json(report: &impl serde::Serialize) -> psh::Result<serde_json::Value> {
    serde_json::to_value(report).map_err(|e| Error::InvalidArgument {
        name: "JSON report",
        value: e.to_string(),
        reason: "a report serializable as JSON".into(),
    })
}

/// An image size `WxH`.
#[derive(Clone, Copy, Debug)]
struct ImageSize {
    width: usize,
    height: usize,
}

/// `WxH` with positive sizes.
fn parse_size(size: &str) -> psh::Result<ImageSize> {
    size.split_once('x')
        .and_then(|(w, h)| Some((w.trim().parse().ok()?, h.trim().parse().ok()?)))
        .filter(|&(w, h): &(usize, usize)| w > 0 && h > 0)
        .map(|(width, height)| ImageSize { width, height })
        .ok_or_else(|| Error::InvalidArgument {
            name: "--size",
            value: size.to_string(),
            reason: "expected WxH, e.g. 480x360".into(),
        })
}

/// A window by name ([`psh::sh::Window::from_name`]).
fn parse_window(x: &str) -> psh::Result<psh::sh::Window> {
    psh::sh::Window::from_name(x.trim())
}

/// A sun model by name ([`psh::pprt::Sun::from_name`]).
fn parse_sun(x: &str) -> psh::Result<psh::pprt::Sun> {
    psh::pprt::Sun::from_name(x.trim())
}

/// A finite angle in degrees.
fn parse_angle(x: &str) -> psh::Result<f64> {
    x.trim()
        .parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| Error::InvalidArgument {
            name: "--polarizer",
            value: x.to_string(),
            reason: "angles in degrees, comma-separated".into(),
        })
}

/// A positive sample count (`--spp`, `--reference`).
fn parse_spp(x: &str) -> psh::Result<usize> {
    x.trim()
        .parse::<usize>()
        .ok()
        .filter(|&n| n > 0)
        .ok_or_else(|| Error::InvalidArgument {
            name: "sample count",
            value: x.to_string(),
            reason: "a positive number of samples (--spp: comma-separated)".into(),
        })
}

fn export_mitsuba(a: &ExportMitsubaArgs) -> psh::Result<serde_json::Value> {
    let overrides = psh::apps::render_job::SceneOverrides {
        sun: a.sun,
        ..Default::default()
    };
    let (scene, _, name) = psh::apps::render_job::job_scene(
        a.scene.as_deref(),
        (a.size.width, a.size.height),
        &overrides,
    )?;
    let export = psh::io::export_mitsuba(&scene, &a.out, a.spp, a.env_rows)?;
    Ok(json!({
        "scene": name,
        "files": export.files,
        "differences": export.differences,
    }))
}

fn bench_error(a: &BenchErrorArgs) -> psh::Result<serde_json::Value> {
    let (w, h) = (a.size.width, a.size.height);
    let spp = a.spp.clone();
    let (mut scene, name) = match &a.scene {
        Some(path) => (
            psh::io::load_scene(path, a.lmax)?.0,
            path.display().to_string(),
        ),
        None => (
            psh::pprt::builtin_scene(a.lmax, w, h)?,
            "the built-in scene".to_string(),
        ),
    };
    if let Some(sun) = a.sun {
        scene = scene.with_sun(sun)?;
    }
    let mut scene = scene.windowed(a.window);
    let cam = scene.camera().clone();
    scene.set_camera(psh::pprt::Camera {
        width: w,
        height: h,
        ..cam
    });
    eprintln!(
        "bench-error on {} ({} triangles, {w} x {h}): ground truth at {} spp, then PPRT l = 2..{} \
         and the reference at {spp:?} spp, into {}",
        name,
        scene.triangle_count(),
        a.ground_truth_spp,
        a.lmax,
        a.out.display()
    );
    let options = psh::apps::bench_error::BenchErrorOptions {
        l_max: a.lmax,
        rays: a.rays,
        spp,
        ground_truth_spp: a.ground_truth_spp,
        ground_truth: a
            .ground_truth
            .as_ref()
            .map(|p| {
                psh::io::read_stokes_image(p)
                    .and_then(|image| psh::apps::bench_error::ground_truth_image(&scene, image))
            })
            .transpose()?,
    };
    to_json(&psh::apps::bench_error::bench_error(
        &scene,
        &options,
        &a.out,
        &TerminalProgress::new(),
    )?)
}

/// An equirectangular size `H,W` (rows, columns).
#[derive(Clone, Copy)]
struct EquirectSize(usize, usize);

/// `H,W` with `W = 2H > 0`.
fn parse_equirect(size: &str) -> psh::Result<EquirectSize> {
    let hw: Option<Vec<usize>> = size.split(',').map(|x| x.trim().parse().ok()).collect();
    match hw.as_deref() {
        Some(&[h, w]) if h > 0 && w == 2 * h => Ok(EquirectSize(h, w)),
        _ => Err(Error::InvalidArgument {
            name: "--equirect",
            value: size.to_string(),
            reason: "expected H,W with W = 2H (rows, columns)".into(),
        }),
    }
}

fn reconstruct(a: &ReconstructArgs) -> psh::Result<serde_json::Value> {
    let layout = match (a.equirect, a.cube) {
        (Some(EquirectSize(h, w)), _) => MapLayout::from_image_size(h, w)?,
        (None, Some(e)) => MapLayout::CubeCross(psh::geometry::CubeCross::new(e)?),
        (None, None) => unreachable!("clap requires --equirect or --cube"),
    };
    let v = psh::io::read_psh_npz(&a.input)?;
    // The map with its files and pictures, before the map is made.
    psh::io::check_stokes_output(layout.width().saturating_mul(layout.height()), v.channels())?;
    // A map is indexed by the direction towards the source.
    let map = StokesMap::reconstruct(
        &v.converted(FieldArgument::TowardsSource).windowed(a.window),
        layout,
    )?;
    let written = psh::io::all_or_nothing(std::slice::from_ref(&a.input), || {
        let mut written = psh::io::write_stokes_map(&map, format!("{}_s%d.exr", a.output))?;
        written.extend(psh::io::write_map_pngs(&map, &a.output)?);
        Ok(written)
    })?;
    Ok(json!({"input": a.input, "lmax": v.lmax(), "window": a.window.name(), "written": written}))
}

fn eval_wigner(a: &WignerArgs) -> psh::Result<serde_json::Value> {
    let v = a.rotvec;
    if a.lmax > MAX_WIGNER_EVAL_DEGREE.min(MAX_DEGREE) {
        return Err(Error::DegreeOutOfRange {
            name: "lmax",
            value: a.lmax as i128,
            reason: format!("psh eval wigner prints at most lmax = {MAX_WIGNER_EVAL_DEGREE}"),
        });
    }
    let r = rotation_from_rotvec(v)?;
    let mut blocks = Vec::new();
    let mut real = Vec::new();
    for_each_block(&r, a.lmax, |l, b| match a.kind {
        Kind::Complex => blocks.push(pairs(b.iter().copied())),
        Kind::Real => {
            real_block(l, b, &mut real);
            blocks.push(pairs(real.iter().map(|&x| Complex64::new(x, 0.0))));
        }
    })?;
    Ok(json!({"lmax": a.lmax, "kind": a.kind.name(), "rotvec": v, "blocks": blocks}))
}

// ---- `psh eval` on .npy files (the external cross-validation suite, validation/) ----

/// Largest degree of `psh eval wigner-block` (the recursion costs l^3).
const MAX_WIGNER_BLOCK_DEGREE: usize = 1024;

/// Largest number of values `psh eval swsh-points` and `sh-derivatives` write.
const MAX_EVAL_VALUES: usize = 1 << 27;

/// A float64 `.npy` file in C order: its shape and data.
fn read_npy(path: &std::path::Path) -> psh::Result<(Vec<u64>, Vec<f64>)> {
    let bytes = std::fs::read(path).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let bad = |reason: String| Error::MalformedFile {
        path: path.to_path_buf(),
        reason,
    };
    let npy = npyz::NpyFile::new(&bytes[..]).map_err(|e| bad(format!("not a .npy file: {e}")))?;
    if npy.order() != npyz::Order::C && npy.shape().len() > 1 {
        return Err(bad("expected a C-order array".into()));
    }
    let shape = npy.shape().to_vec();
    let data: Vec<f64> = npy
        .into_vec()
        .map_err(|e| bad(format!("expected float64 data: {e}")))?;
    Ok((shape, data))
}

/// A `.npy` file whose shape must be `want`.
fn read_npy_shaped(path: &std::path::Path, want: &[u64]) -> psh::Result<Vec<f64>> {
    let (shape, data) = read_npy(path)?;
    if shape != want {
        return Err(Error::MalformedFile {
            path: path.to_path_buf(),
            reason: format!("expected an array of shape {want:?}, got {shape:?}"),
        });
    }
    Ok(data)
}

/// A `.npy` file of `rows` x `width` with any number of rows (at least one).
fn read_npy_rows(path: &std::path::Path, width: u64) -> psh::Result<(usize, Vec<f64>)> {
    let (shape, data) = read_npy(path)?;
    match shape[..] {
        [n, w] if w == width && n > 0 => Ok((n as usize, data)),
        _ => Err(Error::MalformedFile {
            path: path.to_path_buf(),
            reason: format!("expected an array of shape [n, {width}] with n >= 1, got {shape:?}"),
        }),
    }
}

/// `[re, im]` pairs to complex numbers.
fn complex_of_pairs(data: &[f64]) -> Vec<Complex64> {
    data.chunks_exact(2)
        .map(|p| Complex64::new(p[0], p[1]))
        .collect()
}

/// Complex numbers to a flat `[re, im, re, im, ...]` stream.
fn pairs_flat(v: &[Complex64]) -> impl Iterator<Item = f64> + '_ {
    v.iter().flat_map(|z| [z.re, z.im])
}

/// Errors when `count` values exceed [`MAX_EVAL_VALUES`].
fn check_output_size(name: &'static str, count: usize) -> psh::Result<()> {
    if count > MAX_EVAL_VALUES {
        return Err(Error::InvalidArgument {
            name,
            value: count.to_string(),
            reason: format!("at most {MAX_EVAL_VALUES} output values"),
        });
    }
    Ok(())
}

fn eval_wigner_block(a: &WignerBlockArgs) -> psh::Result<serde_json::Value> {
    let v = a.rotvec;
    if a.l > MAX_WIGNER_BLOCK_DEGREE {
        return Err(Error::DegreeOutOfRange {
            name: "l",
            value: a.l as i128,
            reason: format!("psh eval wigner-block computes at most l = {MAX_WIGNER_BLOCK_DEGREE}"),
        });
    }
    let r = rotation_from_rotvec(v)?;
    let n = (2 * a.l + 1) as u64;
    let mut block = Vec::new();
    for_each_block(&r, a.l, |l, b| {
        if l == a.l {
            block = b.to_vec();
        }
    })?;
    let shape = match a.kind {
        Kind::Complex => {
            psh::io::write_npy(&a.output, &[n, n, 2], pairs_flat(&block))?;
            vec![n, n, 2]
        }
        Kind::Real => {
            let mut real = Vec::new();
            real_block(a.l, &block, &mut real);
            psh::io::write_npy(&a.output, &[n, n], real)?;
            vec![n, n]
        }
    };
    Ok(json!({"l": a.l, "kind": a.kind.name(), "rotvec": v, "output": a.output, "shape": shape}))
}

fn eval_swsh_points(a: &SwshPointsArgs) -> psh::Result<serde_json::Value> {
    if a.lmax > MAX_SWSH_EVAL_DEGREE {
        return Err(Error::DegreeOutOfRange {
            name: "lmax",
            value: a.lmax as i128,
            reason: format!("psh eval swsh-points evaluates at most lmax = {MAX_SWSH_EVAL_DEGREE}"),
        });
    }
    let (count, points) = read_npy_rows(&a.points, 2)?;
    let n = psh::sh::num_coeffs(a.lmax);
    check_output_size("number of points", count.saturating_mul(n))?;
    let work = count as u128 * (a.lmax as u128 + 1).pow(3);
    if work > MAX_SWSH_POINTS_WORK {
        return Err(Error::InvalidArgument {
            name: "points x (lmax+1)^3",
            value: work.to_string(),
            reason: format!(
                "psh eval swsh-points evaluates at most {MAX_SWSH_POINTS_WORK} (about a minute)"
            ),
        });
    }
    let mut out = Vec::with_capacity(count * n);
    for p in points.chunks_exact(2) {
        out.extend(psh::swsh::swsh(a.spin, a.lmax, p[0], p[1])?);
    }
    let shape = [count as u64, n as u64, 2];
    psh::io::write_npy(&a.output, &shape, pairs_flat(&out))?;
    Ok(json!({"spin": a.spin, "lmax": a.lmax, "points": count, "output": a.output, "shape": shape}))
}

fn eval_sh_derivatives(a: &ShDerivativesArgs) -> psh::Result<serde_json::Value> {
    let sh = psh::sh::SolidHarmonics::new(a.lmax)?;
    let (count, points) = read_npy_rows(&a.points, 3)?;
    let n = sh.len();
    check_output_size(
        "number of points",
        count.saturating_mul(n).saturating_mul(10),
    )?;
    let dirs: Vec<[f64; 3]> = points.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect();
    let mut values = vec![0.0; count * n];
    let mut gradients = vec![[0.0; 3]; count * n];
    let mut hessians = vec![[0.0; 6]; count * n];
    sh.eval_batch(&dirs, &mut values, &mut gradients, &mut hessians)?;
    let rows = (0..count * n).flat_map(|i| {
        std::iter::once(values[i])
            .chain(gradients[i])
            .chain(hessians[i])
    });
    let shape = [count as u64, n as u64, 10];
    psh::io::write_npy(&a.output, &shape, rows)?;
    Ok(json!({
        "lmax": a.lmax, "points": count, "output": a.output, "shape": shape,
        "hessian_entries": ["xx", "xy", "xz", "yy", "yz", "zz"],
    }))
}

fn eval_grid(a: &GridArgs) -> psh::Result<serde_json::Value> {
    // At most the rings of the largest band limit; checked before the O(n^2) Newton
    // iterations.
    if a.n > psh::sh::MAX_DEGREE + 1 {
        return Err(Error::InvalidArgument {
            name: "n",
            value: a.n.to_string(),
            reason: format!(
                "at most {} rings (the grid of band limit {})",
                psh::sh::MAX_DEGREE + 1,
                psh::sh::MAX_DEGREE
            ),
        });
    }
    let g = psh::sh::GaussLegendre::new(a.n)?;
    Ok(json!({"n": a.n, "theta": g.theta, "weights": g.weights}))
}

fn eval_legendre(a: &LegendreArgs) -> psh::Result<serde_json::Value> {
    use psh::sh::{for_each_column_accurate, Legendre, Polar};
    psh::sh::check_lmax(a.l)?;
    psh::geometry::check_theta(a.theta)?;
    let mut values = vec![0.0; a.l + 1];
    let mut keep = |m: usize, col: &[f64]| values[m] = col[a.l - m];
    let path = if a.fast {
        Legendre::new(a.l)?.for_each_column(Polar::from_theta(a.theta), &mut keep);
        "fast"
    } else {
        for_each_column_accurate(a.l, Polar::from_theta_accurate(a.theta), &mut keep);
        "accurate"
    };
    Ok(json!({"l": a.l, "theta": a.theta, "path": path, "values": values}))
}

/// The grid of a transform as JSON: its size and polar angles.
fn grid_json(grid: &psh::sh::SphereGrid) -> serde_json::Value {
    json!({"n_theta": grid.rings.len(), "n_phi": grid.n_phi, "theta": grid.rings.theta})
}

/// Errors when the exact grid of band `lmax` (`lmax + 1` rings of `2 lmax + 2` points)
/// would hold more than [`MAX_EVAL_VALUES`] values, before any table is built.
fn check_grid_size(lmax: usize) -> psh::Result<()> {
    psh::sh::check_lmax(lmax)?;
    check_output_size("grid values", (lmax + 1) * (2 * lmax + 2))
}

fn eval_sht(a: &ShtArgs) -> psh::Result<serde_json::Value> {
    check_grid_size(a.lmax)?;
    let t = psh::sh::ShTransform::new(a.lmax)?;
    let grid = t.grid();
    let n = psh::sh::num_coeffs(a.lmax) as u64;
    let (nt, np) = (grid.rings.len() as u64, grid.n_phi as u64);
    let shape = match (a.kind, a.op) {
        (Kind::Real, TransformOp::Synthesis) => {
            let c = read_npy_shaped(&a.input, &[n])?;
            let mut out = vec![0.0; grid.len()];
            t.synthesis_real(&c, &mut out)?;
            psh::io::write_npy(&a.output, &[nt, np], out)?;
            vec![nt, np]
        }
        (Kind::Real, TransformOp::Analysis) => {
            let v = read_npy_shaped(&a.input, &[nt, np])?;
            let mut out = vec![0.0; n as usize];
            t.analysis_real(&v, &mut out)?;
            psh::io::write_npy(&a.output, &[n], out)?;
            vec![n]
        }
        (Kind::Complex, TransformOp::Synthesis) => {
            let c = complex_of_pairs(&read_npy_shaped(&a.input, &[n, 2])?);
            let mut out = vec![Complex64::default(); grid.len()];
            t.synthesis_complex(&c, &mut out)?;
            psh::io::write_npy(&a.output, &[nt, np, 2], pairs_flat(&out))?;
            vec![nt, np, 2]
        }
        (Kind::Complex, TransformOp::Analysis) => {
            let v = complex_of_pairs(&read_npy_shaped(&a.input, &[nt, np, 2])?);
            let mut out = vec![Complex64::default(); n as usize];
            t.analysis_complex(&v, &mut out)?;
            psh::io::write_npy(&a.output, &[n, 2], pairs_flat(&out))?;
            vec![n, 2]
        }
    };
    Ok(json!({
        "kind": a.kind.name(), "lmax": a.lmax, "output": a.output, "shape": shape,
        "grid": grid_json(grid),
    }))
}

fn eval_spin_sht(a: &SpinShtArgs) -> psh::Result<serde_json::Value> {
    check_grid_size(a.lmax)?;
    let t = psh::swsh::SpinTransform::new(a.spin, a.lmax)?;
    let grid = t.grid();
    let n = psh::sh::num_coeffs(a.lmax) as u64;
    let (nt, np) = (grid.rings.len() as u64, grid.n_phi as u64);
    let shape = match a.op {
        TransformOp::Synthesis => {
            let c = complex_of_pairs(&read_npy_shaped(&a.input, &[n, 2])?);
            let mut out = vec![Complex64::default(); grid.len()];
            t.synthesis(&c, &mut out)?;
            psh::io::write_npy(&a.output, &[nt, np, 2], pairs_flat(&out))?;
            vec![nt, np, 2]
        }
        TransformOp::Analysis => {
            let v = complex_of_pairs(&read_npy_shaped(&a.input, &[nt, np, 2])?);
            let mut out = vec![Complex64::default(); n as usize];
            t.analysis(&v, &mut out)?;
            psh::io::write_npy(&a.output, &[n, 2], pairs_flat(&out))?;
            vec![n, 2]
        }
    };
    Ok(json!({
        "spin": a.spin, "lmax": a.lmax, "output": a.output, "shape": shape, "grid": grid_json(grid),
    }))
}

/// A Mueller matrix as rows of JSON numbers.
fn mueller_rows(m: &psh::stokes::MuellerMatrix) -> Vec<[f64; 4]> {
    let m = m.matrix();
    (0..4)
        .map(|i| [m[(i, 0)], m[(i, 1)], m[(i, 2)], m[(i, 3)]])
        .collect()
}

fn eval_fresnel(a: &FresnelArgs) -> psh::Result<serde_json::Value> {
    let ior = psh::optics::ComplexIor::new(a.n, a.k)?;
    let results = a
        .cos_i
        .iter()
        .map(|&c| {
            let f = psh::optics::fresnel(c, &ior)?;
            Ok(json!({
                "cos_i": c,
                "r_s": [f.r_s().re, f.r_s().im],
                "r_p": [f.r_p().re, f.r_p().im],
                "total_internal_reflection": f.is_total_internal_reflection(),
                "mueller_travel": mueller_rows(&f.mueller_travel()),
                "mueller": mueller_rows(&f.mueller()),
            }))
        })
        .collect::<psh::Result<Vec<_>>>()?;
    Ok(json!({"n": a.n, "k": a.k, "results": results}))
}

fn eval_microfacet(a: &MicrofacetArgs) -> psh::Result<serde_json::Value> {
    use psh::stokes::MuellerField;
    let model =
        psh::optics::MicrofacetSpecular::new(a.alpha, psh::optics::ComplexIor::new(a.n, a.k)?)?
            .with_masking(psh::optics::Masking::from_name(&a.masking)?);
    let three = |name, v: &[f64]| -> psh::Result<[f64; 3]> {
        v.try_into().map_err(|_| Error::InvalidArgument {
            name,
            value: format!("{v:?}"),
            reason: "three comma-separated numbers X,Y,Z".into(),
        })
    };
    let t = model.transform(three("--wi", &a.wi)?, three("--wo", &a.wo)?)?;
    let axis = |f: &psh::geometry::Frame| {
        let x = f.x();
        [x[0], x[1], x[2]]
    };
    Ok(json!({
        "masking": a.masking,
        "mueller": mueller_rows(&t.matrix()),
        "frame_in_x": axis(t.frame_in()),
        "frame_out_x": axis(t.frame_out()),
    }))
}

fn eval_polarizer(a: &PolarizerArgs) -> psh::Result<serde_json::Value> {
    let p = psh::optics::LinearPolarizer::new(a.angle)?;
    Ok(json!({"angle": a.angle, "mueller": mueller_rows(&p.mueller())}))
}
