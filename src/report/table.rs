//! Markdown tables in the layout of the paper's Table 2.

use std::fmt::Write as _;

use crate::dataset::{Category, Scenario};
use crate::score::{ExpectedTally, GroupScore, Scores, Tally};

/// One row of the Table-2 layout: a scenario and a setting (`Prop.`, `C-Opt.`, `C-Ques.`, ...).
#[derive(Debug, Clone, PartialEq)]
pub struct Table2Row {
    /// The scenario.
    pub scenario: Scenario,
    /// `Prop.`, `C-Opt.`, `C-Ques.`, `G-Opt.`, `G-Ques.`, `P-Opt.` or `P-Ques.`.
    pub setting: String,
    /// The model's accuracy, %.
    pub model: f64,
    /// RND's expected accuracy, %.
    pub rnd: f64,
    /// FRQ's accuracy, % (`None` without train priors).
    pub frq: Option<f64>,
    /// Questions (or options, for `-Opt.` rows) behind the numbers.
    pub n: u64,
}

/// What the report header says about the run.
#[derive(Debug, Clone, PartialEq)]
pub struct ReportMeta {
    /// A short name for the run (its folder name).
    pub run_name: String,
    /// The program source (`builtin`, a model name).
    pub program_source: String,
    /// The backends (`perception=annotation, dynamics=annotation`).
    pub backends: String,
    /// Which questions were evaluated (file names, split).
    pub questions: String,
    /// LLM tokens, cost and requests of the run (`None` without a model).
    pub usage: Option<crate::score::Usage>,
    /// The run's plots: file name under `plots/` and caption.
    pub plots: Vec<(String, String)>,
}

fn percent(correct: f64, total: u64) -> f64 {
    if total == 0 {
        0.0
    } else {
        100.0 * correct / total as f64
    }
}

fn rows_of(group: &GroupScore) -> Vec<Table2Row> {
    let option_row =
        |setting: String, model: &Tally, rnd: &ExpectedTally, frq: Option<&Tally>| Table2Row {
            scenario: group.scenario,
            setting,
            model: percent(model.options_correct as f64, model.options),
            rnd: percent(rnd.options_correct, rnd.options),
            frq: frq.map(|f| percent(f.options_correct as f64, f.options)),
            n: model.options,
        };
    let question_row =
        |setting: String, model: &Tally, rnd: &ExpectedTally, frq: Option<&Tally>| Table2Row {
            scenario: group.scenario,
            setting,
            model: percent(model.questions_correct as f64, model.questions),
            rnd: percent(rnd.questions_correct, rnd.questions),
            frq: frq.map(|f| percent(f.questions_correct as f64, f.questions)),
            n: model.questions,
        };
    match group.category {
        Category::Property => vec![question_row(
            "Prop.".into(),
            &group.model,
            &group.rnd,
            group.frq.as_ref(),
        )],
        other => vec![
            option_row(
                format!("{}-Opt.", other.letter()),
                &group.model,
                &group.rnd,
                group.frq.as_ref(),
            ),
            question_row(
                format!("{}-Ques.", other.letter()),
                &group.model,
                &group.rnd,
                group.frq.as_ref(),
            ),
        ],
    }
}

/// The Table-2 rows of a run, in the paper's order (scenario, then Prop., C, G, P).
pub fn table2_rows(scores: &Scores) -> Vec<Table2Row> {
    scores
        .categories
        .iter()
        .filter(|g| g.model.questions > 0)
        .flat_map(rows_of)
        .collect()
}

/// A percentage cell: one decimal, or `—` without a value.
pub(super) fn cell(value: Option<f64>) -> String {
    value.map_or_else(|| "—".to_string(), |v| format!("{v:.1}"))
}

/// The Markdown report of one run.
pub fn render_run_report(meta: &ReportMeta, scores: &Scores) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "# contphy-eval report: {}\n", meta.run_name);
    let _ = writeln!(out, "- program source: {}", meta.program_source);
    if let Some(usage) = &meta.usage {
        let cost = usage.cost_usd.map_or_else(
            || "cost unknown (model not in the price table)".to_string(),
            |usd| format!("${usd:.4} at list prices"),
        );
        let _ = writeln!(
            out,
            "- LLM: {} requests in this run; {} prompt + {} completion tokens; {cost}",
            usage.requests, usage.prompt_tokens, usage.completion_tokens
        );
    }
    let _ = writeln!(out, "- backends: {}", meta.backends);
    let _ = writeln!(out, "- questions: {}", meta.questions);
    let failed = scores.failed_units();
    let _ = writeln!(
        out,
        "- units: {} ({} answered, {} failed, {} missing)\n",
        scores.units, scores.units_answered, failed, scores.missing_units
    );
    let _ = writeln!(
        out,
        "## Accuracy (%), in the layout of the paper's Table 2\n"
    );
    let _ = writeln!(
        out,
        "| Subset | Setting | RND | FRQ | {} | n |",
        meta.program_source
    );
    let _ = writeln!(out, "|---|---|---:|---:|---:|---:|");
    let mut previous: Option<Scenario> = None;
    for row in table2_rows(scores) {
        let subset = if previous == Some(row.scenario) {
            ""
        } else {
            row.scenario.label()
        };
        previous = Some(row.scenario);
        let _ = writeln!(
            out,
            "| {subset} | {} | {:.1} | {} | {:.1} | {} |",
            row.setting,
            row.rnd,
            cell(row.frq),
            row.model,
            row.n
        );
    }
    let _ = writeln!(
        out,
        "\nRND is the expected accuracy of uniform guessing; FRQ answers each family's most frequent train answer (— where the train split has none of that family). n counts questions (options for -Opt. rows).\n"
    );
    let _ = writeln!(out, "## Per family\n");
    let _ = writeln!(
        out,
        "| Subset | Family | Type | Ques. | Opt. | questions | options | failed units |"
    );
    let _ = writeln!(out, "|---|---|---|---:|---:|---:|---:|---:|");
    for family in &scores.families {
        let failed: u64 = family.failed_units.values().sum::<u64>() + family.missing_units;
        let _ = writeln!(
            out,
            "| {} | {} | {} | {:.1} | {:.1} | {} | {} | {} |",
            family.scenario.label(),
            family.family.as_deref().unwrap_or("?"),
            family.category.name(),
            percent(
                family.model.questions_correct as f64,
                family.model.questions
            ),
            percent(family.model.options_correct as f64, family.model.options),
            family.model.questions,
            family.model.options,
            failed
        );
    }
    let _ = writeln!(out, "\n## Failures by stage\n");
    if scores.failures.is_empty() && scores.missing_units == 0 {
        let _ = writeln!(out, "No unit failed.");
    } else {
        let _ = writeln!(out, "| Stage | Kind | Units |");
        let _ = writeln!(out, "|---|---|---:|");
        for (stage, kinds) in &scores.failures {
            for (kind, count) in kinds {
                let _ = writeln!(out, "| {stage} | {kind} | {count} |");
            }
        }
        if scores.missing_units > 0 {
            let _ = writeln!(
                out,
                "| (none) | missing prediction | {} |",
                scores.missing_units
            );
        }
    }
    if !meta.plots.is_empty() {
        let _ = writeln!(out, "\n## Plots\n");
        for (file_name, caption) in &meta.plots {
            let _ = writeln!(out, "- [{caption}](plots/{file_name})");
        }
    }
    out
}

/// One leaderboard table over several runs: Table-2 rows, one column per run, baselines from the
/// first run (the runs should share their questions; the caller warns otherwise).
pub fn render_leaderboard(runs: &[(String, Scores)]) -> String {
    let mut out = String::new();
    let Some((_, first)) = runs.first() else {
        return out;
    };
    let per_run: Vec<Vec<Table2Row>> = runs.iter().map(|(_, scores)| table2_rows(scores)).collect();
    let mut header = String::from("| Subset | Setting | RND | FRQ |");
    let mut rule = String::from("|---|---|---:|---:|");
    for (name, _) in runs {
        let _ = write!(header, " {name} |");
        rule.push_str("---:|");
    }
    let _ = writeln!(out, "{header}\n{rule}");
    let mut previous: Option<Scenario> = None;
    for baseline in table2_rows(first) {
        let subset = if previous == Some(baseline.scenario) {
            ""
        } else {
            baseline.scenario.label()
        };
        previous = Some(baseline.scenario);
        let _ = write!(
            out,
            "| {subset} | {} | {:.1} | {} |",
            baseline.setting,
            baseline.rnd,
            cell(baseline.frq)
        );
        for rows in &per_run {
            let value = rows
                .iter()
                .find(|r| r.scenario == baseline.scenario && r.setting == baseline.setting)
                .map(|r| r.model);
            let _ = write!(out, " {} |", cell(value));
        }
        out.push('\n');
    }
    out
}
