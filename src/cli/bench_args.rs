//! `bench` subcommand arguments (split from `args` to keep files short). Doc comments are the
//! `--help` text.

use std::path::PathBuf;

use clap::{Args, Subcommand};

use super::args::FrameSelectionArgs;
use crate::dataset::Scenario;
use crate::physics::mpm::mpm88::Mpm88Material;

/// `bench` subcommands.
#[derive(Debug, Subcommand)]
pub enum BenchCommand {
    /// Sandbox cost: interpreter start-up, per-program time, programs/s through the worker pool,
    /// next to CPython running the same programs.
    Sandbox {
        /// Units pushed through the pool.
        #[arg(long, value_name = "N", default_value_t = 2000)]
        units: usize,
        /// Worker processes (default: the number of cores).
        #[arg(long, value_name = "N")]
        jobs: Option<usize>,
        /// The video whose programs are timed (default: the repository's demo video).
        #[arg(long, value_name = "DIR")]
        video: Option<PathBuf>,
    },
    /// Simulator accuracy: error against run time over a sweep of time steps (closed forms or a
    /// fine reference), as JSON, with an optional SVG plot.
    Physics(PhysicsArgs),
    /// The viewer (`view`) on a large synthetic run, as JSON: the site's files, bytes and time
    /// to write, and in a headless browser the time to load the run page, filter it and open a
    /// unit; beside it the same site with every unit's detail in one file.
    View {
        /// Units in the synthetic run.
        #[arg(long, value_name = "N", default_value_t = 100_000)]
        units: usize,
        /// Where the two sites are written (replaced when they exist).
        #[arg(long, value_name = "DIR", default_value = "runs/bench-view")]
        out: PathBuf,
        /// The headless browser (default: chromium-headless-shell or chromium on the PATH; none:
        /// the sites are written and not opened).
        #[arg(long, value_name = "FILE")]
        browser: Option<PathBuf>,
    },
    /// The MPM core on the exact configuration of Taichi's mpm88 example (8,192 or 32,768
    /// particles from a `(N, 2)` float32 `.npy`), as JSON: means, kinetic energy, particle
    /// substeps per second. `benches/mpm88.sh` runs Taichi beside it; `--material` swaps the
    /// liquid for an elastoplastic solid (`benches/mpm_materials.sh`).
    Mpm88 {
        /// Initial positions, an `(N, 2)` float32 or float64 `.npy` file.
        #[arg(long, value_name = "FILE.npy")]
        init: PathBuf,
        /// Substeps to time.
        #[arg(long, value_name = "N", default_value_t = 2000)]
        steps: u64,
        /// Worker threads.
        #[arg(long, value_name = "N", default_value_t = 1)]
        threads: usize,
        /// The particles' material: liquid (the example's), elastic (a fixed-corotated solid
        /// with the liquid's wave speed) or plastic (the same solid with a von Mises yield
        /// stress).
        #[arg(long, value_name = "MATERIAL", default_value = "liquid")]
        material: Mpm88Material,
    },
    /// Properties inferred from tracked motion (what `--dynamics simulate` answers property
    /// questions with) against the videos' values, as JSON: rope mass relations pair by pair;
    /// fluid density order, viscosity classes and density ranks.
    Inference {
        /// Data root holding `<scenario folder>/<video_id>/`.
        #[arg(long, value_name = "DIR")]
        data: PathBuf,
        /// Gaussian noise added to the tracked heights, standard deviations in units
        /// (comma-separated; one sweep each).
        #[arg(long, value_name = "SD,...", value_delimiter = ',', default_values_t = [0.0])]
        noise: Vec<f64>,
    },
    /// Perception: the Mask R-CNN's masks, classes, colours and tracks against the segmentation
    /// truth (AP@0.5, attribute accuracy, ID switches), and the time of decoding, inference and
    /// postprocessing per frame, as JSON.
    Perception {
        /// Data root holding `<scenario folder>/<video_id>/`.
        #[arg(long, value_name = "DIR")]
        data: PathBuf,
        #[command(flatten)]
        frames: FrameSelectionArgs,
        /// The scenario whose videos are scored (default: the one scenario with perception the
        /// data root holds).
        #[arg(long, value_name = "SCENARIO")]
        scenario: Option<Scenario>,
        /// The ONNX model (default: the scenario's committed model).
        #[arg(long, value_name = "FILE")]
        model: Option<PathBuf>,
        /// The colour model (default: the scenario's committed model).
        #[arg(long, value_name = "FILE")]
        colors: Option<PathBuf>,
        /// ONNX Runtime threads.
        #[arg(long, value_name = "N", default_value_t = 1)]
        threads: usize,
    },
    /// LLM client: throughput against concurrency, and whether --rpm holds, against a loopback
    /// mock server with a fixed latency.
    Llm {
        /// The mock server's latency per request, ms.
        #[arg(long, value_name = "MS", default_value_t = 50)]
        latency_ms: u64,
        /// Concurrency levels (comma-separated).
        #[arg(long, value_name = "N,...", value_delimiter = ',', default_values_t = [1, 8, 32, 128])]
        jobs: Vec<usize>,
        /// Requests-per-minute limits to check (comma-separated).
        #[arg(long, value_name = "N,...", value_delimiter = ',', default_values_t = [600, 3000])]
        rpm: Vec<u32>,
        /// Seconds each rate limit is measured over.
        #[arg(long, value_name = "SECONDS", default_value_t = 10.0)]
        rpm_seconds: f64,
    },
}

/// `bench physics` arguments.
#[derive(Debug, Args)]
pub struct PhysicsArgs {
    /// The scenario whose simulator is measured (default: the one scenario with a
    /// simulator benchmark).
    #[arg(long, value_name = "SCENARIO")]
    pub scenario: Option<Scenario>,
    /// Also write the plot of error against run time here.
    #[arg(long, value_name = "FILE")]
    pub svg: Option<PathBuf>,
    /// Time steps to sweep, s (comma-separated; rope default 0.02 down to 0.0001).
    #[arg(long = "dt", value_name = "S,...", value_delimiter = ',')]
    pub steps: Option<Vec<f64>>,
    /// Grid spacings to sweep, scene units (comma-separated; fluid, ball).
    #[arg(long = "grid-spacing", value_name = "DX,...", value_delimiter = ',')]
    pub grid_spacing: Option<Vec<f64>>,
    /// Particles per cell along each axis to sweep (comma-separated; fluid, ball).
    #[arg(
        long = "particles-per-cell",
        value_name = "N,...",
        value_delimiter = ','
    )]
    pub particles_per_cell: Option<Vec<u32>>,
    /// Shifts of every emitter along x to sweep, scene units (comma-separated; fluid: a
    /// shift at the reference's resolution measures the flow's chaos).
    #[arg(
        long = "emitter-shift",
        value_name = "UNITS,...",
        value_delimiter = ',',
        allow_negative_numbers = true
    )]
    pub emitter_shift: Option<Vec<f64>>,
    /// CFL numbers of the substep to sweep (comma-separated; ball).
    #[arg(long = "cfl", value_name = "C,...", value_delimiter = ',')]
    pub cfl: Option<Vec<f64>>,
    /// Shifts of every ball's start (ball) or the cloth's spawn (cloth) along x to sweep,
    /// scene units (comma-separated; a shift at the reference's setting measures the runs'
    /// chaos).
    #[arg(
        long = "start-shift",
        value_name = "UNITS,...",
        value_delimiter = ',',
        allow_negative_numbers = true
    )]
    pub start_shift: Option<Vec<f64>>,
    /// Cloth grid resolutions (particles along a side) to sweep (comma-separated; cloth).
    #[arg(long = "sheet-resolution", value_name = "N,...", value_delimiter = ',')]
    pub sheet_resolution: Option<Vec<u32>>,
    /// Solver substeps per update to sweep (comma-separated; cloth).
    #[arg(long = "substeps", value_name = "N,...", value_delimiter = ',')]
    pub substeps: Option<Vec<u32>>,
    /// Constraint iterations per substep to sweep (comma-separated; cloth).
    #[arg(long = "iterations", value_name = "N,...", value_delimiter = ',')]
    pub iterations: Option<Vec<u32>>,
    /// Runs in every point's ensemble, the reference's too, their spawns 1 mm apart (one
    /// value; cloth, default 5: more runs decide more labels and lower the chaos floor).
    #[arg(long = "ensemble-runs", value_name = "N")]
    pub ensemble_runs: Option<u32>,
    /// Cloth particles' radii per grid spacing to sweep (comma-separated; cloth, default
    /// 0.4, the video's: the cloth is twice as thick as the radius).
    #[arg(
        long = "radius-per-spacing",
        value_name = "R,...",
        value_delimiter = ','
    )]
    pub radius_per_spacing: Option<Vec<f64>>,
    /// A video the cases are built from (repeatable; fluid, ball, cloth; default: the demo
    /// video).
    #[arg(long = "video", value_name = "DIR")]
    pub videos: Vec<PathBuf>,
    /// Store reference runs in this folder and reuse them: a later sweep over the same cases
    /// runs only its own points (an entry is keyed by this executable, the case's video and
    /// the reference's setting).
    #[arg(long = "reference-cache", value_name = "DIR")]
    pub reference_cache: Option<PathBuf>,
    /// Count a label the reference's runs agree on only when a finer setting's runs repeat it
    /// too (cloth: twice the reference's substeps; stored with --reference-cache like the
    /// reference): the errors are then over the labels the physics settles
    #[arg(long = "confirm")]
    pub confirm: bool,
}
