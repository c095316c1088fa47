//! The run's plots (`plots/*.svg`, linked from `report.md`): accuracy per scenario and setting
//! against RND, FRQ and the paper's ContPRO and human rows; failed units by stage and kind; the
//! scene API's work per unit, per family (from the predictions).
//!
//! Input: [`Scores`], the questions and the predictions. Output: SVG text, drawn with plotters' SVG backend. Every bar is labelled
//! with its value as printed (one decimal), so a plot can be checked against `results.json`;
//! the bytes depend only on the scores (no fonts are read, no ids or dates are written).

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use std::collections::BTreeMap;

use super::table::table2_rows;
use crate::dataset::{Category, Scenario};
use crate::scene_api::WorkCounters;
use crate::score::{EvalQuestion, Prediction, Scores};

/// A plot that could not be drawn.
#[derive(Debug, thiserror::Error)]
#[error("cannot draw the plot `{plot}`: {message}")]
pub struct PlotError {
    /// The plot's file name.
    plot: String,
    /// What plotters reported.
    message: String,
}

/// One plot of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct Plot {
    /// Its file name under `plots/` (`accuracy-rope.svg`).
    pub file_name: String,
    /// What it shows, for the report's link.
    pub caption: String,
    /// The SVG document.
    pub svg: String,
}

/// A grouped bar chart: one group per category, one bar per series.
struct Bars {
    file_name: String,
    title: String,
    y_label: &'static str,
    categories: Vec<String>,
    /// Series name and one value per category (`None`: no bar, e.g. FRQ without priors).
    series: Vec<(String, Vec<Option<f64>>)>,
}

/// The series' colours: the model first, in a colour the baselines do not use.
const COLOURS: [RGBColor; 5] = [
    RGBColor(0x1f, 0x77, 0xb4),
    RGBColor(0xa0, 0xa0, 0xa0),
    RGBColor(0x60, 0x60, 0x60),
    RGBColor(0xff, 0x7f, 0x0e),
    RGBColor(0x2c, 0xa0, 0x2c),
];

/// The run's plots: one accuracy plot per scenario evaluated, the failures and the work.
pub fn run_plots(
    model_name: &str,
    scores: &Scores,
    questions: &[EvalQuestion],
    predictions: &[Prediction],
) -> Result<Vec<Plot>, PlotError> {
    let mut plots = Vec::new();
    for bars in accuracy_bars(model_name, scores) {
        let caption = bars.title.clone();
        plots.push(draw(&bars, caption)?);
    }
    // Without failures the report's table says so; an empty chart would say nothing more.
    let failures = failure_bars(scores);
    if !failures.categories.is_empty() {
        let caption = failures.title.clone();
        plots.push(draw(&failures, caption)?);
    }
    let work = work_bars(questions, predictions);
    let caption = work.title.clone();
    plots.push(draw(&work, caption)?);
    Ok(plots)
}

/// Accuracy, %, per setting of each scenario: the model, RND, FRQ, and the paper's rows.
fn accuracy_bars(model_name: &str, scores: &Scores) -> Vec<Bars> {
    let rows = table2_rows(scores);
    let mut plots = Vec::new();
    for scenario in Scenario::ALL {
        let rows: Vec<_> = rows.iter().filter(|row| row.scenario == scenario).collect();
        if rows.is_empty() {
            continue;
        }
        let paper = |pick: fn(&crate::dataset::PaperRow) -> f64| {
            rows.iter()
                .map(|row| scenario.paper_row(&row.setting).map(pick))
                .collect::<Vec<_>>()
        };
        plots.push(Bars {
            file_name: format!("accuracy-{}.svg", scenario.name()),
            title: format!("{}: accuracy (%) per setting", scenario.label()),
            y_label: "accuracy (%)",
            categories: rows.iter().map(|row| row.setting.clone()).collect(),
            series: vec![
                (
                    model_name.to_string(),
                    rows.iter().map(|row| Some(row.model)).collect(),
                ),
                ("RND".into(), rows.iter().map(|row| Some(row.rnd)).collect()),
                ("FRQ".into(), rows.iter().map(|row| row.frq).collect()),
                ("ContPRO (paper)".into(), paper(|row| row.contpro)),
                ("Human (paper)".into(), paper(|row| row.human)),
            ],
        });
    }
    plots
}

/// Failed units per stage and kind (and units without a prediction).
fn failure_bars(scores: &Scores) -> Bars {
    let mut categories = Vec::new();
    let mut counts = Vec::new();
    for (stage, kinds) in &scores.failures {
        for (kind, count) in kinds {
            categories.push(format!("{stage}: {kind}"));
            counts.push(Some(*count as f64));
        }
    }
    if scores.missing_units > 0 {
        categories.push("missing prediction".into());
        counts.push(Some(scores.missing_units as f64));
    }
    let failed = scores.failed_units();
    Bars {
        file_name: "failures.svg".into(),
        title: format!(
            "failed units by stage ({} of {})",
            failed + scores.missing_units,
            scores.units
        ),
        y_label: "units",
        categories,
        series: vec![("failed units".into(), counts)],
    }
}

/// The scene API's work summed over one family's predicted units.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct FamilyWork {
    /// Units with a prediction.
    pub units: u64,
    /// Their work counters, summed.
    pub work: WorkCounters,
}

/// Work per family (scenario, category, family; in that order), from the predictions of
/// `questions`' units. Not part of `results.json`: a scene is loaded once per worker, so who
/// pays for a load depends on how units were scheduled (sharded, resumed), not on the answers.
pub fn family_work(
    questions: &[EvalQuestion],
    predictions: &[Prediction],
) -> BTreeMap<(Scenario, Category, String), FamilyWork> {
    let category: BTreeMap<&str, Category> = questions
        .iter()
        .map(|question| (question.id.as_str(), question.category))
        .collect();
    let mut families: BTreeMap<(Scenario, Category, String), FamilyWork> = BTreeMap::new();
    for prediction in predictions {
        let Some(category) = category.get(prediction.question_id.as_str()) else {
            continue;
        };
        let entry = families
            .entry((prediction.scenario, *category, prediction.family.clone()))
            .or_default();
        entry.units += 1;
        entry.work.add(&prediction.work);
    }
    families
}

/// The scene API's work per predicted unit, per family.
fn work_bars(questions: &[EvalQuestion], predictions: &[Prediction]) -> Bars {
    let families: Vec<_> = family_work(questions, predictions)
        .into_iter()
        .filter(|(_, family)| family.units > 0)
        .collect();
    let per_unit = |pick: fn(&WorkCounters) -> u64| {
        families
            .iter()
            .map(|(_, family)| Some(pick(&family.work) as f64 / family.units as f64))
            .collect::<Vec<_>>()
    };
    Bars {
        file_name: "work.svg".into(),
        title: "scene API work per unit, per family".into(),
        y_label: "per unit",
        categories: families
            .iter()
            .map(|((scenario, _, name), _)| {
                if name.starts_with(scenario.name()) {
                    name.clone()
                } else {
                    format!("{} {name}", scenario.name())
                }
            })
            .collect(),
        series: vec![
            (
                "frames decoded".into(),
                per_unit(|work| work.frames_decoded),
            ),
            ("detections".into(), per_unit(|work| work.detections)),
            ("simulations".into(), per_unit(|work| work.sim_runs)),
            ("API calls".into(), per_unit(|work| work.api_calls)),
        ],
    }
}

/// The value label of a bar, as the plot prints it.
pub fn bar_label(value: f64) -> String {
    format!("{value:.1}")
}

/// Draws `bars` as SVG.
fn draw(bars: &Bars, caption: String) -> Result<Plot, PlotError> {
    let error = |message: String| PlotError {
        plot: bars.file_name.clone(),
        message,
    };
    let top = bars
        .series
        .iter()
        .flat_map(|(_, values)| values.iter().flatten())
        .copied()
        .filter(|value| value.is_finite())
        .fold(0.0_f64, f64::max);
    // Headroom above the tallest bar for its label and the legend.
    let y_max = if top > 0.0 { top * 1.6 } else { 1.0 };
    let group_width = 0.8;
    let bar_width = group_width / bars.series.len().max(1) as f64;
    let categories = bars.categories.len();
    let width = u32::try_from(160 + 28 * bars.series.len().max(1) * categories.max(1))
        .unwrap_or(u32::MAX)
        .clamp(480, 4000);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (width, 420)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| error(e.to_string()))?;
        let x_range = -0.5_f64..(categories.max(1) as f64 - 0.5);
        let mut chart = ChartBuilder::on(&root)
            .caption(&bars.title, ("sans-serif", 20))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(55)
            .build_cartesian_2d(x_range, 0.0_f64..y_max)
            .map_err(|e| error(e.to_string()))?;
        // The category names are drawn below the axis at each group's centre: the mesh's own x
        // labels fall on "nice" numbers, not on every category.
        chart
            .configure_mesh()
            .disable_x_mesh()
            .x_label_formatter(&|_| String::new())
            .y_desc(bars.y_label)
            .draw()
            .map_err(|e| error(e.to_string()))?;
        for (category, name) in bars.categories.iter().enumerate() {
            let (x, y) = chart.backend_coord(&(category as f64, 0.0));
            root.draw(&Text::new(
                name.as_str(),
                (x, y + 8),
                ("sans-serif", 11)
                    .into_font()
                    .color(&BLACK)
                    .pos(Pos::new(HPos::Center, VPos::Top)),
            ))
            .map_err(|e| error(e.to_string()))?;
        }
        for (index, (name, values)) in bars.series.iter().enumerate() {
            let colour = COLOURS[index % COLOURS.len()];
            let left = move |category: usize| {
                category as f64 - group_width / 2.0 + index as f64 * bar_width
            };
            let present: Vec<(usize, f64)> = values
                .iter()
                .enumerate()
                .filter_map(|(category, value)| value.map(|v| (category, v)))
                .filter(|(_, value)| value.is_finite())
                .collect();
            chart
                .draw_series(present.iter().map(|&(category, value)| {
                    Rectangle::new(
                        [
                            (left(category), 0.0),
                            (left(category) + 0.9 * bar_width, value),
                        ],
                        colour.filled(),
                    )
                }))
                .map_err(|e| error(e.to_string()))?
                .label(name.as_str())
                .legend(move |(x, y)| {
                    Rectangle::new([(x, y - 5), (x + 10, y + 5)], colour.filled())
                });
            chart
                .draw_series(present.iter().map(|&(category, value)| {
                    Text::new(
                        bar_label(value),
                        (left(category) + 0.45 * bar_width, value + y_max * 0.005),
                        ("sans-serif", 10)
                            .into_font()
                            .color(&BLACK)
                            .pos(Pos::new(HPos::Center, VPos::Bottom)),
                    )
                }))
                .map_err(|e| error(e.to_string()))?;
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(|e| error(e.to_string()))?;
        root.present().map_err(|e| error(e.to_string()))?;
    }
    Ok(Plot {
        file_name: bars.file_name.clone(),
        caption,
        svg,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::score::{Priors, score};

    fn svg_texts(svg: &str) -> Vec<String> {
        svg.split("<text")
            .skip(1)
            .filter_map(|part| {
                let start = part.find('>')? + 1;
                let end = part.find("</text>")?;
                Some(part[start..end].trim().to_string())
            })
            .collect()
    }

    #[test]
    fn every_bar_is_labelled_with_its_value_and_the_bytes_repeat() {
        let (questions, predictions) = crate::report::site::tests::fixture_run();
        let scores = score(&questions, &predictions, &Priors::default());
        let plots = run_plots("model", &scores, &questions, &predictions).unwrap();
        let names: Vec<&str> = plots.iter().map(|p| p.file_name.as_str()).collect();
        assert_eq!(names, ["accuracy-rope.svg", "failures.svg", "work.svg"]);
        let texts = svg_texts(&plots[0].svg);
        // The fixture's property question is right and its counterfactual question has one
        // option of two right: 100.0 (Prop.), 50.0 (C-Opt.), 0.0 (C-Ques.) in a row.
        let model: Vec<String> = [100.0, 50.0, 0.0].map(bar_label).to_vec();
        assert!(
            texts.windows(3).any(|window| window == model.as_slice()),
            "{texts:?}"
        );
        // The paper's ContPRO row for rope: 71.4, 75.6, 48.8.
        let contpro: Vec<String> = [71.4, 75.6, 48.8].map(bar_label).to_vec();
        assert!(texts.windows(3).any(|window| window == contpro.as_slice()));
        let failures = svg_texts(&plots[1].svg);
        assert!(failures.iter().any(|text| text == "sandbox: NameError"));
        assert_eq!(
            run_plots("model", &scores, &questions, &predictions).unwrap(),
            plots
        );
    }
}
