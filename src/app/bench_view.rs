//! `bench view`: the viewer site of a large synthetic run (10⁵ units by default), as JSON: files,
//! bytes and time to write, and in a headless browser the time for the run page to load, to
//! filter and to open a unit. The peer, measured beside it in the same run, is the same site with
//! every unit's detail in one file, which a unit's page must read whole.
//!
//! Input: the unit count, the output folder and optionally the browser. Output: JSON on stdout,
//! the two sites under the output folder (`chunked/`, `one-file/`).

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};
use std::time::Instant;

use rand::{Rng as _, SeedableRng as _};
use rand_chacha::ChaCha8Rng;
use serde_json::{Value, json};

use super::error::{AppError, Classify as _, user_error};
use crate::dataset::{AnswerType, Category, ChoiceOption, Scenario};
use crate::report::run_plots;
use crate::report::site::{CHUNK_UNITS, ProgramText, SiteRun, build_site_chunked};
use crate::scene_api::WorkCounters;
use crate::score::{EvalQuestion, Prediction, Priors, Stage, UnitError, Usage, score};
use crate::util::write_atomic;

/// `bench view` settings.
#[derive(Debug, Clone)]
pub struct BenchViewSettings {
    /// Units in the synthetic run.
    pub units: usize,
    /// Where the two sites are written.
    pub out: PathBuf,
    /// The headless browser; `None`: `chromium-headless-shell` or `chromium` on the `PATH`.
    pub browser: Option<PathBuf>,
}

/// Options per synthetic question (the unit count is rounded up to a multiple).
const OPTIONS: usize = 4;

pub(crate) fn bench_view(settings: &BenchViewSettings) -> Result<ExitCode, AppError> {
    if settings.units == 0 {
        return Err(user_error("bench view: --units must be at least 1"));
    }
    if settings.out.exists() && !settings.out.is_dir() {
        return Err(user_error(format!(
            "bench view: --out `{}` is a file",
            settings.out.display()
        )));
    }
    let mut stderr = std::io::stderr().lock();
    let (questions, predictions) = synthetic_run(settings.units);
    let scores = score(&questions, &predictions, &Priors::default());
    let runs = [SiteRun {
        name: "synthetic".into(),
        facts: vec![("program source".into(), "synthetic".into())],
        scores: &scores,
        questions: &questions,
        predictions: &predictions,
        plots: run_plots("synthetic", &scores, &questions, &predictions).internal()?,
        frames: std::collections::BTreeMap::new(),
    }];
    let browser = settings.browser.clone().or_else(find_browser);
    if browser.is_none() {
        let _ = writeln!(
            stderr,
            "bench view: no chromium-headless-shell or chromium on the PATH; writing only"
        );
    }
    let last_unit = predictions
        .last()
        .map(|p| p.unit.clone())
        .unwrap_or_default();
    let mut variants = Vec::new();
    for (name, chunk_units) in [("chunked", CHUNK_UNITS), ("one-file", usize::MAX)] {
        let _ = writeln!(stderr, "bench view: writing the {name} site...");
        let folder = settings.out.join(name);
        if folder.is_dir() {
            fs_err::remove_dir_all(&folder).user()?;
        }
        let started = Instant::now();
        let files =
            build_site_chunked(&runs, &|key| Some(synthetic_program(key)), &[], chunk_units);
        let mut bytes = 0_usize;
        for file in &files {
            bytes += file.bytes.len();
            write_atomic(&folder.join(&file.path), &file.bytes).user()?;
        }
        let write_ms = started.elapsed().as_secs_f64() * 1000.0;
        let largest = files.iter().map(|file| file.bytes.len()).max().unwrap_or(0);
        let mut variant = json!({
            "site": name,
            "units_per_chunk": chunk_units.min(questions.len() * OPTIONS),
            "files": files.len(),
            "bytes": bytes,
            "largest_file_bytes": largest,
            "write_ms": round(write_ms),
        });
        if let Some(browser) = &browser {
            let _ = writeln!(
                stderr,
                "bench view: opening the {name} site in the browser..."
            );
            let page = folder.join("runs/1/index.html").canonicalize().user()?;
            variant["browser"] = json!({
                "load": browse(browser, &page, "", "status", "data-load-ms")?,
                "filter": browse(browser, &page, "#correct=0&stage=sandbox", "status", "data-filter-ms")?,
                "open_unit": browse(browser, &page, &format!("#unit={last_unit}"), "detail", "data-detail-ms")?,
            });
        }
        variants.push(variant);
    }
    let report = json!({
        "benchmark": "view",
        "units": predictions.len(),
        "browser": browser.as_ref().map(|b| b.display().to_string()),
        "sites": variants,
    });
    let mut stdout = std::io::stdout().lock();
    let _ = writeln!(
        stdout,
        "{}",
        serde_json::to_string_pretty(&report).unwrap_or_default()
    );
    Ok(ExitCode::SUCCESS)
}

fn round(ms: f64) -> f64 {
    (ms * 10.0).round() / 10.0
}

/// `chromium-headless-shell` or `chromium` on the `PATH`.
fn find_browser() -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    ["chromium-headless-shell", "chromium"]
        .iter()
        .flat_map(|name| std::env::split_paths(&path).map(move |dir| dir.join(name)))
        .find(|candidate| candidate.is_file())
}

/// Opens `page` with `hash` in the browser and reads the time the page wrote into `attribute`
/// of the element `id`, with the browser process's wall time.
fn browse(
    browser: &Path,
    page: &Path,
    hash: &str,
    id: &str,
    attribute: &str,
) -> Result<Value, AppError> {
    let started = Instant::now();
    let output = Command::new(browser)
        .args([
            "--no-sandbox",
            "--disable-gpu",
            "--log-level=3",
            "--virtual-time-budget=20000",
            "--dump-dom",
        ])
        .arg(format!("file://{}{hash}", page.display()))
        .output()
        .map_err(|error| {
            user_error(format!(
                "bench view: cannot run the browser `{}`: {error}",
                browser.display()
            ))
        })?;
    let wall_ms = started.elapsed().as_secs_f64() * 1000.0;
    let dom = String::from_utf8_lossy(&output.stdout);
    let page_ms = dom
        .find(&format!("id=\"{id}\""))
        .and_then(|at| {
            let tag_end = at + dom[at..].find('>')?;
            let tag = &dom[at..tag_end];
            let start = tag.find(&format!("{attribute}=\""))? + attribute.len() + 2;
            let end = start + tag[start..].find('"')?;
            tag[start..end].parse::<f64>().ok()
        })
        .ok_or_else(|| {
            user_error(format!(
                "bench view: the page `{}{hash}` did not report `{attribute}` on #{id} (did its script fail?)",
                page.display()
            ))
        })?;
    Ok(json!({"page_ms": page_ms, "browser_wall_ms": round(wall_ms)}))
}

/// A synthetic run of at least `units` units: four-option questions over the four scenarios and
/// seven families each, 80% of options right, a tenth of the units failed at a stage.
fn synthetic_run(units: usize) -> (Vec<EvalQuestion>, Vec<Prediction>) {
    let mut rng = ChaCha8Rng::seed_from_u64(19);
    let stages = [Stage::Sandbox, Stage::SceneApi, Stage::Llm, Stage::Answer];
    let mut questions = Vec::new();
    let mut predictions = Vec::new();
    for index in 0..units.div_ceil(OPTIONS) {
        let scenario = Scenario::ALL[index % Scenario::ALL.len()];
        let family = format!("family_{}", index % 7);
        let options: Vec<ChoiceOption> = (0..OPTIONS)
            .map(|option| ChoiceOption {
                letter: char::from(b'A' + u8::try_from(option).unwrap_or(0)),
                text: format!("Synthetic outcome {option} of question {index}"),
                correct: rng.random_bool(0.5),
            })
            .collect();
        let question = EvalQuestion {
            id: format!("{}/{family}/{index}", index / 40),
            scenario,
            family: family.clone(),
            category: Category::Counterfactual,
            answer_type: AnswerType::MultipleChoice,
            video_id: (index / 40).to_string(),
            text: format!(
                "Synthetic question {index}: if the third object were removed, which of the following would happen?"
            ),
            answer: options
                .iter()
                .filter(|option| option.correct)
                .map(|option| option.letter)
                .collect(),
            options,
        };
        for option in &question.options {
            let unit = format!("{}:{}", question.id, option.letter);
            let failed = rng.random_bool(0.1);
            let right = !failed && rng.random_bool(0.8);
            let said_yes = option.correct == right;
            predictions.push(Prediction {
                program_hash: Some(crate::util::content_hash(unit.as_bytes())),
                program_key: Some(unit.clone()),
                unit,
                question_id: question.id.clone(),
                option: Some(option.letter),
                scenario,
                family: family.clone(),
                video_id: question.video_id.clone(),
                program_origin: Some("cache".into()),
                value: (!failed).then(|| Value::Bool(said_yes)),
                answer: (!failed).then(|| if said_yes { "yes" } else { "no" }.to_string()),
                correct: right,
                error: failed.then(|| UnitError {
                    stage: stages[rng.random_range(0..stages.len())],
                    kind: "SyntheticError".into(),
                    message: "a synthetic failure".into(),
                }),
                attempts: Vec::new(),
                votes: Vec::new(),
                usage: Some(Usage {
                    prompt_tokens: 1800,
                    completion_tokens: 240,
                    cost_usd: Some(0.0612),
                    requests: 1,
                }),
                work: WorkCounters {
                    api_calls: 4,
                    annotation_loads: 1,
                    ..WorkCounters::default()
                },
                own_ms: 2,
                api_ms: 5,
                wall_ms: 8,
            });
        }
        questions.push(question);
    }
    (questions, predictions)
}

/// A program and completion of an LLM's usual size (about 0.6 and 0.9 kB) for a synthetic unit.
fn synthetic_program(key: &str) -> ProgramText {
    let program = format!(
        "def execute_command(video):\n    # unit {key}\n    scene = SoftScene(video, 'synthetic')\n    \
         objects = scene.filter_objects(color='red')\n    if not objects:\n        return 'no'\n    \
         event = scene.register_event(objects, 'remove', '')\n    dynamic = scene.init_dyn_simulation(event)\n    \
         for other in scene.filter_objects():\n        if dynamic.happen(other, 'falling', ''):\n            \
         return 'yes'\n    return bool_to_yesno(dynamic.happen(objects[0], 'moving', ''))\n"
    );
    let completion = format!(
        "Here is a program that answers the question by simulating the scene without the object.\n\n\
         ```python\n{program}```\n\nIt registers the removal, runs the dynamics and checks each object."
    );
    ProgramText {
        source: "openai".into(),
        program,
        completion: Some(completion),
    }
}
