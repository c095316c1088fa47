//! Synthetic ContPhy videos in the release format: `contphy-eval generate`.
//!
//! The framework is shared by the scenarios: a [`ScenarioSynth`] samples a random scene with the
//! release's randomisation and simulates it (returning the annotations, the 4-D data and what
//! each frame shows); [`write_video`] renders every frame with the software rasterizer
//! ([`raster`]) under the release camera, derives the per-frame boxes and instance masks from the
//! rendered id image ([`annotate`]), and writes the folder atomically (`outputs.json`,
//! `outputs4D.json`, frames as PNG folders and/or mp4 through ffmpeg, [`video`]); [`generate`]
//! runs many videos on `jobs` threads, each from its own seed, so the output does not depend on
//! scheduling. Questions are then made by the question engine from the written folders, through
//! the same loader as the real data (in `app`).
//!
//! Input: a [`GenerateOptions`]. Output: `OUT/<scenario folder>/<index>/` folders and a
//! [`GenerateReport`]. Layer 2 (`docs/architecture.md`, layers): uses `util`, `dataset`, `physics`,
//! `perception`.
//!
//! * [`rope`]: rope–pulley scenes (`docs/data/rope.md`).
//! * [`fluid`]: fluids on sticks into containers (`docs/data/fluid.md`).
//! * [`ball`]: soft balls dropping past floating walls into pits (`docs/data/ball.md`).
//! * [`cloth`]: cloths dragged over pillars and plates (`docs/data/cloth.md`).

pub mod annotate;
pub mod appearance;
pub mod background;
pub mod ball;
pub mod camera;
pub mod cloth;
mod error;
pub mod fluid;
pub mod mesh;
pub use crate::perception::palette;
pub mod raster;
pub mod rope;
pub mod shadow;
pub mod unity;
pub mod video;

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, PoisonError};
use std::time::Instant;

use serde_json::{Map, Value};

pub use error::SynthError;

use self::annotate::{LabelledObject, capture_record, segmentation_rgb};
use self::appearance::{Appearance, FrameFinish, randomize};
use self::background::{Wall, render_wall};
use self::mesh::{Mesh, Pose};
use self::raster::{Drawable, Light, Stripes, render};
use self::shadow::Shadow;
use self::video::{FrameOutput, FrameSink};
use crate::dataset::Scenario;
use crate::perception::camera::CameraModel;
use crate::util::{derive_seed, write_atomic};

/// One thing a frame shows.
#[derive(Debug, Clone)]
pub struct Item {
    /// Its mesh (shared between frames).
    pub mesh: Arc<Mesh>,
    /// Where it is in this frame.
    pub pose: Pose,
    /// Colour, sRGB in `[0, 1]`.
    pub color: [f64; 3],
    /// Instance id (0: drawn, not labelled).
    pub instance: u32,
    /// Stripes painted along the mesh's pattern coordinate (ropes), if any.
    pub stripes: Option<Stripes>,
}

/// A generated video before rendering: everything the folder holds but the pixels and the
/// per-frame annotations derived from them.
#[derive(Debug, Clone)]
pub struct SynthesizedVideo {
    /// `outputs.json` keys before `imgAnnotationDescriptions`, in the release's order.
    pub annotations: Map<String, Value>,
    /// `outputs.json` keys after it (`CounterFactualAnnotations`).
    pub trailing: Map<String, Value>,
    /// `outputs4D.json`.
    pub four_d: Value,
    /// The camera.
    pub camera: CameraModel,
    /// The light.
    pub light: Light,
    /// The background wall.
    pub wall: Wall,
    /// The objects' drop shadow on the wall.
    pub shadow: Shadow,
    /// Labelled objects (instance ids, names, labels).
    pub labels: Vec<LabelledObject>,
    /// `Id2ObjectNameDict`: every labelled name, including objects never drawn (`Solver`).
    pub id_to_name: Vec<(u32, String)>,
    /// Solo step number of frame 0 (`perFrameAnnotations` keys start here).
    pub first_step: usize,
    /// What each frame shows.
    pub frames: Vec<Vec<Item>>,
    /// Simulated trials rejected before this one was kept (the release's validity checks).
    pub rejected_trials: u32,
    /// Simulator steps taken, all runs included.
    pub simulation_steps: u64,
}

/// A scenario's scene sampler and simulator.
pub trait ScenarioSynth: Sync {
    /// The scenario.
    fn scenario(&self) -> Scenario;
    /// Samples, simulates and describes one video from `seed` (deterministic), at the given
    /// image size.
    fn synthesize(
        &self,
        seed: u64,
        width: u32,
        height: u32,
    ) -> Result<SynthesizedVideo, SynthError>;
}

/// Runs `trial` on the seed's one random stream until it gives a video, at most `max_trials`
/// times (a trial fails only when its solver does): the video, with the failed attempts in
/// `rejected_trials`, or the last failure's reason.
pub(crate) fn first_valid_trial(
    seed: u64,
    max_trials: u32,
    mut trial: impl FnMut(&mut rand_chacha::ChaCha8Rng) -> Result<SynthesizedVideo, String>,
) -> Result<SynthesizedVideo, SynthError> {
    let mut rng = crate::util::seeded_rng(seed);
    let mut last = String::new();
    for attempt in 0..max_trials {
        match trial(&mut rng) {
            Ok(mut video) => {
                video.rejected_trials = attempt;
                return Ok(video);
            }
            Err(reason) => last = reason,
        }
    }
    Err(SynthError::NoValidScene {
        seed,
        attempts: max_trials,
        last,
    })
}

/// A static part of a generated scene as `outputs4D.json` records it: its name, its mesh in world
/// coordinates, and the end points of its centre line (x–y, units; the voxels lie along it).
pub(crate) struct StaticPart<'a> {
    /// Scene name.
    pub(crate) name: &'a str,
    /// The mesh, placed.
    pub(crate) mesh: Mesh,
    /// Centre line end points, units.
    pub(crate) line: ([f64; 2], [f64; 2]),
}

/// `outputs4D.json` for a scene of static parts and soft bodies (`docs/data/common.md`). Each
/// static part: staticity, no per-frame states, the first capture's mesh, and voxel rows
/// (position, Euler angles, then voxel centres every `voxel_size` units along the centre line).
/// Each soft body (name, tracked points per frame): its points, rounded, and an empty mesh per
/// frame (the meshes follow from the points; written per frame with their faces they made a
/// ball video's 4-D file ten times larger).
pub(crate) fn four_d_document(
    parts: &[StaticPart<'_>],
    voxel_size: f64,
    soft_bodies: Vec<(String, Vec<Vec<[f64; 3]>>)>,
) -> Value {
    let round = |v: f64| unity::round(v, 5);
    let mut tracked = Map::new();
    let mut empty_meshes = Map::new();
    for (name, frames) in soft_bodies {
        let count = frames.len();
        let frames: Vec<Value> = frames
            .into_iter()
            .map(|points| {
                let points: Vec<[f64; 3]> = points.iter().map(|p| p.map(round)).collect();
                serde_json::json!(points)
            })
            .collect();
        tracked.insert(name.clone(), Value::Array(frames));
        empty_meshes.insert(name, serde_json::json!(vec![serde_json::json!([]); count]));
    }
    serde_json::json!({
        "rigidbody4D": static_rigid_bodies(parts, voxel_size),
        "softbody4D": {
            "softbodyTrackedParticles": tracked,
            "softbodyMeshVertices": empty_meshes.clone(),
            "softbodyMeshFaces": empty_meshes,
        },
    })
}

/// The `rigidbody4D` part of [`four_d_document`].
fn static_rigid_bodies(parts: &[StaticPart<'_>], voxel_size: f64) -> Value {
    let round = |v: f64| unity::round(v, 5);
    let mut staticity = Map::new();
    let mut centroids = Map::new();
    let mut vertices = Map::new();
    let mut faces = Map::new();
    let mut voxels = Map::new();
    for part in parts {
        let name = part.name.to_string();
        staticity.insert(name.clone(), serde_json::json!(true));
        centroids.insert(name.clone(), serde_json::json!([]));
        let positions: Vec<[f64; 3]> = part.mesh.positions.iter().map(|p| p.map(round)).collect();
        vertices.insert(name.clone(), serde_json::json!(positions));
        let flat: Vec<u32> = part.mesh.triangles.iter().flatten().copied().collect();
        faces.insert(name.clone(), serde_json::json!(flat));
        let (a, b) = part.line;
        let angle = (b[1] - a[1])
            .atan2(b[0] - a[0])
            .to_degrees()
            .rem_euclid(360.0);
        let centre = [f64::midpoint(a[0], b[0]), f64::midpoint(a[1], b[1]), 0.0];
        let length = (b[0] - a[0]).hypot(b[1] - a[1]);
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "a part's length over the voxel size is a small count"
        )]
        let count = (length / voxel_size).ceil().max(1.0) as usize;
        let mut rows = vec![
            serde_json::json!(centre.map(round)),
            serde_json::json!([0.0, 0.0, round(angle)]),
        ];
        #[expect(clippy::cast_precision_loss, reason = "small counts")]
        rows.extend((0..count).map(|k| {
            let t = (k as f64 + 0.5) / count as f64;
            serde_json::json!([
                round(a[0] + t * (b[0] - a[0])),
                round(a[1] + t * (b[1] - a[1])),
                0.0
            ])
        }));
        voxels.insert(name, serde_json::json!(rows));
    }
    serde_json::json!({
        "rigidbodyStatesStaticity": staticity,
        "rigidbodyCentroidStates": centroids,
        "rigidbodyMeshVertices": vertices,
        "rigidbodyMeshFaces": faces,
        "rigidbodyVoxelPosition": voxels,
    })
}

/// What to generate.
#[derive(Debug, Clone)]
pub struct GenerateOptions {
    /// The scenario.
    pub scenario: Scenario,
    /// Number of videos.
    pub videos: usize,
    /// Base seed; video `i` uses `derive_seed(seed, "synth/<scenario>/<i>")`.
    pub seed: u64,
    /// Data root to write into (`OUT/<scenario folder>/<i>/`).
    pub out: PathBuf,
    /// Worker threads.
    pub jobs: usize,
    /// Frame files to write.
    pub frames: FrameOutput,
    /// Image width, pixels.
    pub width: u32,
    /// Image height, pixels.
    pub height: u32,
    /// How the frames look (the release's look, or randomised for training perception).
    pub appearance: Appearance,
}

/// What one video cost.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct VideoReport {
    /// Folder name.
    pub id: String,
    /// `true` when the folder existed already and was kept (a resumed generation).
    pub reused: bool,
    /// Rejected trials before the kept one.
    pub rejected_trials: u32,
    /// Simulator steps.
    pub simulation_steps: u64,
    /// Time to sample and simulate, ms.
    pub simulate_ms: u64,
    /// Time to render, annotate and write, ms.
    pub write_ms: u64,
    /// Bytes on disk.
    pub bytes: u64,
}

/// The outcome of [`generate`].
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct GenerateReport {
    /// Per video, in index order.
    pub videos: Vec<VideoReport>,
    /// Wall time, ms.
    pub wall_ms: u64,
}

/// The seed of video `index`.
pub fn video_seed(seed: u64, scenario: Scenario, index: usize) -> u64 {
    derive_seed(seed, &format!("synth/{}/{index}", scenario.name()))
}

/// Generates `options.videos` videos with `synth` on `options.jobs` threads; `on_video` is
/// called as each finishes (for progress). Videos whose folder already holds an
/// `outputs.json` are kept as they are, so an interrupted generation resumes where it stopped.
pub fn generate(
    synth: &dyn ScenarioSynth,
    options: &GenerateOptions,
    on_video: &(dyn Fn(&VideoReport) + Sync),
) -> Result<GenerateReport, SynthError> {
    let started = Instant::now();
    let scenario_dir = options.out.join(options.scenario.folder_name());
    fs_err::create_dir_all(&scenario_dir).map_err(|source| SynthError::Io {
        path: scenario_dir.clone(),
        source,
    })?;
    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<Option<VideoReport>>> = Mutex::new(vec![None; options.videos]);
    let failure: Mutex<Option<SynthError>> = Mutex::new(None);
    let worker = || {
        loop {
            if failure
                .lock()
                .unwrap_or_else(PoisonError::into_inner)
                .is_some()
            {
                return;
            }
            let index = next.fetch_add(1, Ordering::Relaxed);
            if index >= options.videos {
                return;
            }
            match generate_one(synth, options, &scenario_dir, index) {
                Ok(report) => {
                    on_video(&report);
                    results.lock().unwrap_or_else(PoisonError::into_inner)[index] = Some(report);
                }
                Err(error) => {
                    failure
                        .lock()
                        .unwrap_or_else(PoisonError::into_inner)
                        .get_or_insert(error);
                    return;
                }
            }
        }
    };
    std::thread::scope(|scope| {
        for _ in 0..options.jobs.max(1) {
            scope.spawn(worker);
        }
    });
    if let Some(error) = failure.into_inner().unwrap_or_else(PoisonError::into_inner) {
        return Err(error);
    }
    let videos = results
        .into_inner()
        .unwrap_or_else(PoisonError::into_inner)
        .into_iter()
        .flatten()
        .collect();
    Ok(GenerateReport {
        videos,
        wall_ms: millis(started),
    })
}

fn millis(since: Instant) -> u64 {
    u64::try_from(since.elapsed().as_millis()).unwrap_or(u64::MAX)
}

fn generate_one(
    synth: &dyn ScenarioSynth,
    options: &GenerateOptions,
    scenario_dir: &Path,
    index: usize,
) -> Result<VideoReport, SynthError> {
    let id = index.to_string();
    let dir = scenario_dir.join(&id);
    if dir.join("outputs.json").is_file() {
        return Ok(VideoReport {
            id,
            reused: true,
            rejected_trials: 0,
            simulation_steps: 0,
            simulate_ms: 0,
            write_ms: 0,
            bytes: folder_bytes(&dir),
        });
    }
    let started = Instant::now();
    let seed = video_seed(options.seed, options.scenario, index);
    let mut video = synth.synthesize(seed, options.width, options.height)?;
    let finish = match options.appearance {
        Appearance::Release => None,
        Appearance::Randomized => Some(randomize(&mut video, seed)),
    };
    let simulate_ms = millis(started);
    let started = Instant::now();
    write_video(&dir, &video, options.frames, finish.as_ref())?;
    Ok(VideoReport {
        id,
        reused: false,
        rejected_trials: video.rejected_trials,
        simulation_steps: video.simulation_steps,
        simulate_ms,
        write_ms: millis(started),
        bytes: folder_bytes(&dir),
    })
}

fn folder_bytes(dir: &Path) -> u64 {
    let mut total = 0;
    let mut pending = vec![dir.to_path_buf()];
    while let Some(current) = pending.pop() {
        let Ok(entries) = fs_err::read_dir(&current) else {
            continue;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            if path.is_dir() {
                pending.push(path);
            } else if let Ok(meta) = entry.metadata() {
                total += meta.len();
            }
        }
    }
    total
}

/// Renders and writes one video folder at `dir`, each frame passed through `finish` when one
/// is given (randomised appearance). The folder is assembled under a temporary name beside it
/// and renamed at the end, so a crash never leaves half a video.
pub fn write_video(
    dir: &Path,
    video: &SynthesizedVideo,
    output: FrameOutput,
    finish: Option<&FrameFinish>,
) -> Result<(), SynthError> {
    let parent = dir.parent().unwrap_or(Path::new("."));
    let name = dir
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let partial = parent.join(format!(".partial-{name}"));
    if partial.exists() {
        fs_err::remove_dir_all(&partial).map_err(|source| SynthError::Io {
            path: partial.clone(),
            source,
        })?;
    }
    fs_err::create_dir_all(&partial).map_err(|source| SynthError::Io {
        path: partial.clone(),
        source,
    })?;
    let camera = &video.camera;
    let background = render_wall(camera, &video.wall, &video.light);
    let mut sink = FrameSink::open(&partial, output, camera.width, camera.height)?;
    let max_instance = video.labels.iter().map(|l| l.instance).max().unwrap_or(0);
    let mut labelled = vec![false; max_instance as usize + 1];
    for label in &video.labels {
        labelled[label.instance as usize] = true;
    }
    let mut per_frame = Map::new();
    for (index, items) in video.frames.iter().enumerate() {
        let drawables: Vec<Drawable<'_>> = items
            .iter()
            .map(|item| Drawable {
                mesh: &item.mesh,
                pose: item.pose,
                color: item.color,
                instance: item.instance,
                stripes: item.stripes,
            })
            .collect();
        let mut frame = render(camera, &background, &video.light, &drawables);
        video.shadow.apply(&mut frame);
        let step = video.first_step + index;
        per_frame.insert(
            step.to_string(),
            capture_record(step, camera, &frame, &video.labels, index % 2 == 1),
        );
        let segmentation = segmentation_rgb(&frame, &labelled);
        let mut rgb = frame.rgb;
        if let Some(finish) = finish {
            finish.apply(index, camera.width, camera.height, &mut rgb);
        }
        sink.push(index, &rgb, &segmentation)?;
    }
    sink.finish()?;
    let mut outputs = video.annotations.clone();
    let id_to_name: Map<String, Value> = video
        .id_to_name
        .iter()
        .map(|(id, name)| (id.to_string(), Value::String(name.clone())))
        .collect();
    outputs.insert(
        "imgAnnotationDescriptions".into(),
        serde_json::json!({
            "perFrameAnnotations": per_frame,
            "Id2ObjectNameDict": id_to_name,
        }),
    );
    for (key, value) in &video.trailing {
        outputs.insert(key.clone(), value.clone());
    }
    let write_json = |file: &str, value: &Value| -> Result<(), SynthError> {
        let path = partial.join(file);
        let bytes = serde_json::to_vec(value).map_err(|error| SynthError::Encode {
            path: path.clone(),
            detail: error.to_string(),
        })?;
        write_atomic(&path, &bytes).map_err(SynthError::from)
    };
    write_json("outputs4D.json", &video.four_d)?;
    write_json("outputs.json", &Value::Object(outputs))?;
    if dir.exists() {
        fs_err::remove_dir_all(dir).map_err(|source| SynthError::Io {
            path: dir.to_path_buf(),
            source,
        })?;
    }
    fs_err::rename(&partial, dir).map_err(|source| SynthError::Io {
        path: dir.to_path_buf(),
        source,
    })
}
