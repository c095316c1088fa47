//! The static viewer site (`contphy-eval view RUN... --out DIR`): a leaderboard of the runs in
//! the paper's Table-2 layout, and per run its facts, table, plots and every unit, filterable by
//! scenario, family, correctness and failed stage, with each unit's question, options, program
//! (source, text, completion and every attempt), value, answer, truth, error, work and usage.
//!
//! Input: the runs' scores, questions and predictions ([`SiteRun`]) and a lookup of program
//! texts by program-cache key. Output: the site's files ([`SiteFile`], paths relative to its
//! root, `/`-separated), byte-stable for the same inputs. The pages need no server and make no
//! external request: data travel as `<script src>` files (browsers refuse `fetch` under
//! `file://`), the unit list as one compact index and the units' details in chunks of
//! [`CHUNK_UNITS`] loaded when a unit is opened, so a run of 10⁵ units opens without reading its
//! programs. Every text from a run reaches the page through `textContent` or escaped HTML, never
//! as markup: programs and completions are model output.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use serde_json::{Value, json};

use super::plots::Plot;
use super::table::{Table2Row, cell, table2_rows};
use crate::dataset::{Category, Scenario};
use crate::score::{EvalQuestion, Prediction, Scores};

/// Units per detail chunk (`runs/<k>/units/<chunk>.js`).
pub const CHUNK_UNITS: usize = 500;

/// The viewer's script and style sheet, written under `assets/`.
const VIEWER_JS: &str = include_str!("viewer.js");
const STYLE_CSS: &str = include_str!("style.css");

/// The file that marks a folder as written by `view` (so a later `view` may replace it).
pub const SITE_MARKER: &str = ".contphy-view";

/// One run (or the merged shards of one) as the site shows it.
pub struct SiteRun<'a> {
    /// The leaderboard column's name.
    pub name: String,
    /// Facts for the run's header: label and value (program source, backends, questions, ...).
    pub facts: Vec<(String, String)>,
    /// The run's scores.
    pub scores: &'a Scores,
    /// The evaluated questions, in run order.
    pub questions: &'a [EvalQuestion],
    /// The run's predictions.
    pub predictions: &'a [Prediction],
    /// Its plots.
    pub plots: Vec<Plot>,
    /// Per video (`<scenario>/<video>`), the frames perception read with its detections drawn:
    /// the run's `frames/<scenario>/<video>/detections.json` list (`frame`, `image`,
    /// `detections`), its images copied by the caller to `runs/<k>/frames/<scenario>/<video>/`.
    pub frames: BTreeMap<String, Value>,
}

/// A program's text as the program cache holds it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ProgramText {
    /// The source that made it (`builtin`, `openai`, ...).
    pub source: String,
    /// The program.
    pub program: String,
    /// The raw completion it was extracted from (LLM sources).
    pub completion: Option<String>,
}

/// One file of the site.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SiteFile {
    /// Relative to the site's root, `/`-separated.
    pub path: String,
    /// Its content.
    pub bytes: Vec<u8>,
}

impl SiteFile {
    fn text(path: String, text: String) -> SiteFile {
        SiteFile {
            path,
            bytes: text.into_bytes(),
        }
    }
}

/// The site of `runs`: `index.html` (the leaderboard), `assets/`, and `runs/<k>/` per run.
/// `programs` finds a program's text by its cache key; `notes` are shown on the leaderboard.
pub fn build_site(
    runs: &[SiteRun],
    programs: &dyn Fn(&str) -> Option<ProgramText>,
    notes: &[String],
) -> Vec<SiteFile> {
    build_site_chunked(runs, programs, notes, CHUNK_UNITS)
}

/// [`build_site`] with `chunk_units` units per detail chunk (`bench view` measures one chunk for
/// all units beside the default).
pub fn build_site_chunked(
    runs: &[SiteRun],
    programs: &dyn Fn(&str) -> Option<ProgramText>,
    notes: &[String],
    chunk_units: usize,
) -> Vec<SiteFile> {
    let chunk_units = chunk_units.max(1);
    let mut files = vec![
        SiteFile::text("assets/viewer.js".into(), VIEWER_JS.into()),
        SiteFile::text("assets/style.css".into(), STYLE_CSS.into()),
        SiteFile::text(SITE_MARKER.into(), "written by contphy-eval view\n".into()),
        SiteFile::text("index.html".into(), leaderboard_page(runs, notes)),
    ];
    for (index, run) in runs.iter().enumerate() {
        let folder = format!("runs/{}", index + 1);
        files.push(SiteFile::text(
            format!("{folder}/index.html"),
            run_page(run),
        ));
        for plot in &run.plots {
            files.push(SiteFile::text(
                format!("{folder}/plots/{}", plot.file_name),
                plot.svg.clone(),
            ));
        }
        if !run.frames.is_empty() {
            files.push(SiteFile::text(
                format!("{folder}/frames.js"),
                format!(
                    "window.CONTPHY_FRAMES = {};\n",
                    serde_json::to_string(&run.frames).unwrap_or_else(|_| "{}".into())
                ),
            ));
        }
        let units = unit_rows(run);
        files.push(SiteFile::text(
            format!("{folder}/units.js"),
            format!(
                "window.CONTPHY_INDEX = {};\n",
                index_json(run, &units, chunk_units)
            ),
        ));
        for (chunk, rows) in units.chunks(chunk_units).enumerate() {
            let details: Vec<Value> = rows.iter().map(|row| detail_json(row, programs)).collect();
            files.push(SiteFile::text(
                format!("{folder}/units/{chunk}.js"),
                format!("window.contphyChunk({chunk}, {});\n", Value::Array(details)),
            ));
        }
    }
    files
}

/// Text escaped for HTML content and attribute values.
pub fn escape_html(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            other => out.push(other),
        }
    }
    out
}

/// The page's head and the opening of its body. `root` leads back to the site's root.
fn page_start(title: &str, root: &str) -> String {
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <title>{}</title>\n<link rel=\"stylesheet\" href=\"{root}assets/style.css\">\n</head>\n<body>\n",
        escape_html(title)
    )
}

/// The settings of the Table-2 layout, in the paper's order.
fn settings_in_order() -> Vec<String> {
    let mut settings = vec!["Prop.".to_string()];
    for category in Category::ALL.into_iter().skip(1) {
        settings.push(format!("{}-Opt.", category.letter()));
        settings.push(format!("{}-Ques.", category.letter()));
    }
    settings
}

/// `index.html`: the leaderboard, one column per run, with RND and FRQ (of the first run that
/// has the row) and the paper's ContPRO and human rows.
fn leaderboard_page(runs: &[SiteRun], notes: &[String]) -> String {
    let mut out = page_start("contphy-eval leaderboard", "");
    let _ = writeln!(out, "<h1>Leaderboard</h1>");
    let per_run: Vec<Vec<Table2Row>> = runs.iter().map(|run| table2_rows(run.scores)).collect();
    let _ = writeln!(
        out,
        "<p>Accuracy (%) in the layout of the paper's Table 2: <em>-Opt.</em> rows count options, \
         <em>-Ques.</em> rows questions. RND is uniform guessing's expectation, FRQ the most frequent \
         train answer; the last two columns are the paper's (ContPhy, ICML 2024).</p>"
    );
    let _ = write!(
        out,
        "<table id=\"leaderboard\" class=\"scores\">\n<thead><tr><th>Subset</th><th>Setting</th><th>RND</th><th>FRQ</th>"
    );
    for (index, run) in runs.iter().enumerate() {
        let _ = write!(
            out,
            "<th><a href=\"runs/{}/index.html\">{}</a></th>",
            index + 1,
            escape_html(&run.name)
        );
    }
    let _ = writeln!(
        out,
        "<th>ContPRO (paper)</th><th>Human (paper)</th></tr></thead>\n<tbody>"
    );
    for scenario in Scenario::ALL {
        let mut first_row = true;
        for setting in settings_in_order() {
            let found: Vec<Option<&Table2Row>> = per_run
                .iter()
                .map(|rows| {
                    rows.iter()
                        .find(|row| row.scenario == scenario && row.setting == setting)
                })
                .collect();
            let Some(baseline) = found.iter().flatten().next() else {
                continue;
            };
            let subset = if first_row { scenario.label() } else { "" };
            first_row = false;
            let paper = scenario.paper_row(&setting);
            let _ = write!(
                out,
                "<tr><td>{subset}</td><td>{}</td><td>{:.1}</td><td>{}</td>",
                escape_html(&setting),
                baseline.rnd,
                cell(baseline.frq)
            );
            for row in &found {
                let _ = write!(
                    out,
                    "<td class=\"model\">{}</td>",
                    cell(row.map(|r| r.model))
                );
            }
            let _ = writeln!(
                out,
                "<td>{}</td><td>{}</td></tr>",
                cell(paper.map(|p| p.contpro)),
                cell(paper.map(|p| p.human))
            );
        }
    }
    let _ = writeln!(out, "</tbody>\n</table>");
    if !notes.is_empty() {
        let _ = writeln!(out, "<h2>Notes</h2>\n<ul id=\"notes\">");
        for note in notes {
            let _ = writeln!(out, "<li>{}</li>", escape_html(note));
        }
        let _ = writeln!(out, "</ul>");
    }
    let _ = writeln!(out, "<h2>Runs</h2>\n<ul id=\"runs\">");
    for (index, run) in runs.iter().enumerate() {
        let _ = writeln!(
            out,
            "<li><a href=\"runs/{}/index.html\">{}</a>: {} units</li>",
            index + 1,
            escape_html(&run.name),
            run.scores.units
        );
    }
    let _ = writeln!(out, "</ul>\n</body>\n</html>");
    out
}

/// `runs/<k>/index.html`: the run's facts, its Table-2 rows, plots, and the unit browser (filled
/// by `viewer.js` from `units.js`).
fn run_page(run: &SiteRun) -> String {
    let mut out = page_start(&format!("contphy-eval run {}", run.name), "../../");
    let _ = writeln!(
        out,
        "<p><a href=\"../../index.html\">Leaderboard</a></p>\n<h1>Run {}</h1>\n<dl id=\"facts\">",
        escape_html(&run.name)
    );
    for (label, value) in &run.facts {
        let _ = writeln!(
            out,
            "<dt>{}</dt><dd>{}</dd>",
            escape_html(label),
            escape_html(value)
        );
    }
    let _ = writeln!(out, "</dl>\n<h2>Accuracy (%)</h2>");
    let _ = writeln!(
        out,
        "<table class=\"scores\"><thead><tr><th>Subset</th><th>Setting</th><th>RND</th><th>FRQ</th><th>{}</th><th>n</th><th>ContPRO (paper)</th><th>Human (paper)</th></tr></thead><tbody>",
        escape_html(&run.name)
    );
    for row in table2_rows(run.scores) {
        let paper = row.scenario.paper_row(&row.setting);
        let _ = writeln!(
            out,
            "<tr><td>{}</td><td>{}</td><td>{:.1}</td><td>{}</td><td class=\"model\">{:.1}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            row.scenario.label(),
            escape_html(&row.setting),
            row.rnd,
            cell(row.frq),
            row.model,
            row.n,
            cell(paper.map(|p| p.contpro)),
            cell(paper.map(|p| p.human))
        );
    }
    let _ = writeln!(out, "</tbody></table>");
    if !run.plots.is_empty() {
        let _ = writeln!(out, "<h2>Plots</h2>\n<div class=\"plots\">");
        for plot in &run.plots {
            let _ = writeln!(
                out,
                "<figure><img src=\"plots/{0}\" alt=\"{1}\"><figcaption>{1}</figcaption></figure>",
                escape_html(&plot.file_name),
                escape_html(&plot.caption)
            );
        }
        let _ = writeln!(out, "</div>");
    }
    let _ = writeln!(
        out,
        "<h2>Units</h2>\n<form id=\"filters\"></form>\n<p id=\"status\">Loading the units…</p>\n\
         <section id=\"detail\" hidden></section>\n<nav id=\"pager\"></nav>\n\
         <table id=\"units\" class=\"units\"><thead><tr><th>Unit</th><th>Scenario</th><th>Family</th>\
         <th>Correct</th><th>Failed stage</th></tr></thead><tbody></tbody></table>\n\
         <script src=\"units.js\"></script>\n{}<script src=\"../../assets/viewer.js\"></script>\n</body>\n</html>",
        if run.frames.is_empty() {
            ""
        } else {
            "<script src=\"frames.js\"></script>\n"
        }
    );
    out
}

/// One unit of the run, in question order, with its prediction if there is one.
struct UnitRow<'a> {
    unit: String,
    question: &'a EvalQuestion,
    option: Option<&'a crate::dataset::ChoiceOption>,
    prediction: Option<&'a Prediction>,
}

/// Every unit the run's questions ask for, with the first prediction of each.
fn unit_rows<'a>(run: &'a SiteRun) -> Vec<UnitRow<'a>> {
    let mut by_unit: BTreeMap<&str, &Prediction> = BTreeMap::new();
    for prediction in run.predictions {
        by_unit
            .entry(prediction.unit.as_str())
            .or_insert(prediction);
    }
    let mut rows = Vec::new();
    for question in run.questions {
        if question.options.is_empty() {
            rows.push(UnitRow {
                unit: question.id.clone(),
                question,
                option: None,
                prediction: by_unit.get(question.id.as_str()).copied(),
            });
        } else {
            for option in &question.options {
                let unit = format!("{}:{}", question.id, option.letter);
                let prediction = by_unit.get(unit.as_str()).copied();
                rows.push(UnitRow {
                    unit,
                    question,
                    option: Some(option),
                    prediction,
                });
            }
        }
    }
    rows
}

/// The failed stage a unit is filed under: the error's stage, `missing` without a prediction.
fn failed_stage(row: &UnitRow) -> Option<String> {
    match row.prediction {
        None => Some("missing".to_string()),
        Some(prediction) => prediction
            .error
            .as_ref()
            .map(|error| error.stage.name().to_string()),
    }
}

fn is_correct(row: &UnitRow) -> bool {
    row.prediction
        .is_some_and(|prediction| prediction.correct && prediction.error.is_none())
}

/// Position of `value` in `list`, appended when new.
fn intern(list: &mut Vec<String>, value: &str) -> usize {
    if let Some(index) = list.iter().position(|known| known == value) {
        index
    } else {
        list.push(value.to_string());
        list.len() - 1
    }
}

/// `units.js`'s object: the names of scenarios, families and stages, and per unit `[id,
/// scenario, family, correct, stage]` as indices (`-1`: no failure).
fn index_json(run: &SiteRun, rows: &[UnitRow], chunk_units: usize) -> Value {
    let (mut scenarios, mut families, mut stages) = (Vec::new(), Vec::new(), Vec::new());
    let units: Vec<Value> = rows
        .iter()
        .map(|row| {
            let scenario = intern(&mut scenarios, row.question.scenario.name());
            let family = intern(
                &mut families,
                &format!("{}/{}", row.question.scenario.name(), row.question.family),
            );
            let stage = failed_stage(row).map_or(-1, |stage| {
                i64::try_from(intern(&mut stages, &stage)).unwrap_or(-1)
            });
            json!([row.unit, scenario, family, u8::from(is_correct(row)), stage])
        })
        .collect();
    json!({
        "run": run.name,
        "chunk_units": chunk_units,
        "scenarios": scenarios,
        "families": families,
        "stages": stages,
        "units": units,
    })
}

/// A unit's detail, as the viewer shows it when the unit is opened.
fn detail_json(row: &UnitRow, programs: &dyn Fn(&str) -> Option<ProgramText>) -> Value {
    let question = row.question;
    let truth = row.option.map_or_else(
        || question.answer.clone(),
        |option| if option.correct { "yes" } else { "no" }.to_string(),
    );
    let program = |key: Option<&String>| -> Value {
        key.and_then(|key| programs(key))
            .map_or(Value::Null, |text| {
                json!({
                    "source": text.source,
                    "text": text.program,
                    "completion": text.completion,
                })
            })
    };
    let options: Vec<Value> = question
        .options
        .iter()
        .map(|option| json!({"letter": option.letter.to_string(), "text": option.text, "correct": option.correct}))
        .collect();
    let mut detail = json!({
        "unit": row.unit,
        "question_id": question.id,
        "video": question.video_id,
        "scenario": question.scenario.name(),
        "family": question.family,
        "question": question.text,
        "options": options,
        "option": row.option.map(|option| option.letter.to_string()),
        "truth": truth,
        "correct": is_correct(row),
    });
    let Some(prediction) = row.prediction else {
        detail["error"] = json!({"stage": "missing", "kind": "missing prediction", "message": "the run has no prediction for this unit (an unfinished run?)"});
        return detail;
    };
    let attempts: Vec<Value> = prediction
        .attempts
        .iter()
        .map(|attempt| {
            json!({
                "sample": attempt.sample,
                "attempt": attempt.attempt,
                "program_hash": attempt.program_hash,
                "error": attempt.error,
                "program": program(attempt.program_key.as_ref()),
            })
        })
        .collect();
    detail["origin"] = json!(prediction.program_origin);
    detail["program_hash"] = json!(prediction.program_hash);
    detail["program_key"] = json!(prediction.program_key);
    detail["program"] = program(prediction.program_key.as_ref());
    detail["attempts"] = Value::Array(attempts);
    detail["votes"] = json!(prediction.votes);
    detail["value"] = prediction.value.clone().unwrap_or(Value::Null);
    detail["answer"] = json!(prediction.answer);
    detail["error"] = json!(prediction.error);
    detail["work"] = json!(prediction.work);
    detail["usage"] = json!(prediction.usage);
    detail["timing_ms"] =
        json!({"own": prediction.own_ms, "api": prediction.api_ms, "wall": prediction.wall_ms});
    detail
}

#[cfg(test)]
pub(crate) mod tests;
