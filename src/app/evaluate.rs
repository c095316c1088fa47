//! The evaluation rounds of a run: obtain programs, run them in the sandbox, repair what failed,
//! vote over samples, and turn every task into predictions.
//!
//! Each round first obtains the programs every unfinished sample needs (for an LLM source: many
//! requests at once, each completion cached as it arrives), then runs them in the sandbox pool in
//! a fixed order (by video, then task, then sample). The fixed order keeps the sandbox's work
//! (which unit loaded a video's annotations) independent of network timing, so replays give the
//! same predictions. A program that failed with a syntax error or a scene-API misuse gets a
//! repair turn when the source allows it (`--repair K`). A task is finished when each of its
//! samples has an outcome; its predictions are handed to `on_task_done` at once, while the
//! sandbox still runs other programs, so a kill loses only the tasks in flight (the builtin
//! writer's runs included, whose programs are all obtained in one round).

use serde_json::Value;

use super::error::{AppError, Classify as _};
use super::pipeline::{SandboxOutcome, outcome_from, sandbox_budgets, start_pool};
use super::settings::Budgets;
use super::source::{Obtained, ProgramRequest, ProgramSource, RepairTurn};
use crate::answer::{interpret, interpret_letters, is_correct};
use crate::dataset::{ChoiceOption, Question};
use crate::program::{Program, ProgramOrigin};
use crate::sandbox::{Pool, Unit, scene_host_spec};
use crate::scene_api::{VideoSpec, WorkCounters};
use crate::score::{Attempt, Prediction, Stage, UnitError, Usage};

/// One program's worth of work: an open question, one option of a choice question, or (in
/// per-question mode) a whole choice question, and the prediction units it answers.
#[derive(Debug, Clone)]
pub(crate) struct Task {
    /// Index of the question in the run's list.
    pub(crate) question_index: usize,
    /// The option, for a per-option unit.
    pub(crate) option: Option<ChoiceOption>,
    /// One program answers every option (per-question mode).
    pub(crate) whole_question: bool,
    /// The prediction units it answers, with their options.
    pub(crate) units: Vec<(String, Option<ChoiceOption>)>,
    /// The video bound as the scene.
    pub(crate) video: VideoSpec,
}

/// How programs are drawn and run.
#[derive(Debug, Clone, Copy)]
pub(crate) struct EvaluationSettings {
    /// Sandbox worker processes.
    pub(crate) workers: usize,
    /// Sandbox budgets.
    pub(crate) budgets: Budgets,
    /// Programs drawn per task; the majority answer wins.
    pub(crate) samples: u32,
    /// Repair turns allowed per sample.
    pub(crate) repair: u32,
}

/// The state of one sample of one task.
#[derive(Debug, Default)]
struct Sample {
    repairs: Vec<RepairTurn>,
    attempts: Vec<Attempt>,
    pending: Option<Obtained>,
    /// The final program and its outcome.
    outcome: Option<(Option<Program>, Result<Value, UnitError>)>,
    usage: Usage,
    work: WorkCounters,
    own_ms: u64,
    api_ms: u64,
    wall_ms: u64,
}

impl Sample {
    fn finish(&mut self, program: Option<Program>, result: Result<Value, UnitError>) {
        self.outcome = Some((program, result));
    }
}

/// Whether a failed program is worth a repair turn: the model can fix syntax errors and
/// scene-API misuse from the message; timeouts or memory blow-ups it usually cannot.
fn repairable(error: &UnitError) -> bool {
    matches!(
        (error.stage, error.kind.as_str()),
        (
            Stage::Sandbox,
            "syntax" | "forbidden" | "no_result" | "NameError" | "TypeError" | "AttributeError"
        ) | (Stage::SceneApi, "misuse")
            | (Stage::Extract, _)
    )
}

/// What the model is told about a failed program.
fn feedback(error: &UnitError) -> String {
    format!(
        "Running your program failed at the {} stage ({}): {}\nWrite a corrected program: only the function `def execute_command(video)`.",
        error.stage.name(),
        error.kind,
        error.message
    )
}

/// Runs every task to completion. `on_task_done` receives each finished task's predictions as
/// soon as its last sample has an outcome (while other programs still run), so a kill loses
/// only the tasks in flight.
pub(crate) fn evaluate(
    tasks: &[Task],
    questions: &[Question],
    source: &dyn ProgramSource,
    settings: EvaluationSettings,
    mut on_task_done: impl FnMut(Vec<Prediction>) -> Result<(), AppError>,
) -> Result<(), AppError> {
    let samples_per_task = settings.samples.max(1);
    let mut rounds = Rounds {
        tasks,
        questions,
        source,
        settings,
        states: tasks
            .iter()
            .map(|_| (0..samples_per_task).map(|_| Sample::default()).collect())
            .collect(),
        reported: vec![false; tasks.len()],
        pool: None,
    };
    loop {
        rounds.obtain_programs()?;
        rounds.run_pending(&mut on_task_done)?;
        if rounds.report_finished(&mut on_task_done)? == 0 {
            return Ok(());
        }
    }
}

/// The state of a run's evaluation rounds.
struct Rounds<'a> {
    tasks: &'a [Task],
    questions: &'a [Question],
    source: &'a dyn ProgramSource,
    settings: EvaluationSettings,
    /// Per task, its samples.
    states: Vec<Vec<Sample>>,
    /// Per task, whether its predictions were handed out.
    reported: Vec<bool>,
    /// The sandbox pool, started when the first program is ready to run.
    pool: Option<Pool>,
}

impl Rounds<'_> {
    /// Step 1: a program for every sample that has neither an outcome nor a program to run
    /// (for an LLM source, many requests at once, each completion cached as it arrives).
    fn obtain_programs(&mut self) -> Result<(), AppError> {
        let mut wanted: Vec<(usize, usize)> = Vec::new();
        for (task_index, samples) in self.states.iter().enumerate() {
            for (sample_index, sample) in samples.iter().enumerate() {
                if sample.outcome.is_none() && sample.pending.is_none() {
                    wanted.push((task_index, sample_index));
                }
            }
        }
        if wanted.is_empty() {
            return Ok(());
        }
        let requests: Vec<ProgramRequest<'_>> = wanted
            .iter()
            .filter_map(|&(task_index, sample_index)| {
                let task = self.tasks.get(task_index)?;
                Some(ProgramRequest {
                    question: self.questions.get(task.question_index)?,
                    option: task.option.as_ref(),
                    whole_question: task.whole_question,
                    sample: u32::try_from(sample_index).unwrap_or(u32::MAX),
                    repairs: &self.states[task_index][sample_index].repairs,
                    unit: task.units.first().map_or("", |(unit, _)| unit.as_str()),
                })
            })
            .collect();
        let obtained = self.source.obtain_batch(&requests)?;
        drop(requests);
        for ((task_index, sample_index), result) in wanted.into_iter().zip(obtained) {
            let can_repair = self.source.can_repair();
            let repair_turns = self.settings.repair as usize;
            let sample = &mut self.states[task_index][sample_index];
            let attempt = u32::try_from(sample.attempts.len()).unwrap_or(u32::MAX);
            match result {
                Ok(obtained) => {
                    if let Some(usage) = &obtained.usage {
                        sample.usage.add(usage);
                    }
                    sample.pending = Some(obtained);
                }
                Err(failed) => {
                    if let Some(usage) = &failed.usage {
                        sample.usage.add(usage);
                    }
                    let error = failed.error;
                    sample.attempts.push(Attempt {
                        sample: u32::try_from(sample_index).unwrap_or(u32::MAX),
                        attempt,
                        program_hash: None,
                        program_key: failed.key,
                        error: Some(error.clone()),
                    });
                    let retry = error.stage == Stage::Extract
                        && can_repair
                        && sample.attempts.len() <= repair_turns;
                    if retry {
                        sample.repairs.push(RepairTurn {
                            completion: failed.completion.unwrap_or_default(),
                            feedback: feedback(&error),
                        });
                    } else {
                        sample.finish(None, Err(error));
                    }
                }
            }
        }
        Ok(())
    }

    /// Step 2: runs the pending programs in the sandbox pool, submitted in a fixed order (by
    /// video, then task, then sample: which unit loads a video's annotations does not depend on
    /// network timing); each result is recorded as it arrives, and a task whose samples all
    /// have outcomes is reported at once.
    fn run_pending(
        &mut self,
        on_task_done: &mut impl FnMut(Vec<Prediction>) -> Result<(), AppError>,
    ) -> Result<(), AppError> {
        let mut runnable: Vec<(usize, usize)> = Vec::new();
        for (task_index, samples) in self.states.iter().enumerate() {
            for (sample_index, sample) in samples.iter().enumerate() {
                if sample.pending.is_some() {
                    runnable.push((task_index, sample_index));
                }
            }
        }
        if runnable.is_empty() {
            return Ok(());
        }
        let tasks = self.tasks;
        runnable.sort_by(|a, b| {
            let key = |(task_index, sample_index): (usize, usize)| {
                let video = &tasks[task_index].video;
                (
                    video.scenario,
                    video.video_id.clone(),
                    task_index,
                    sample_index,
                )
            };
            key(*a).cmp(&key(*b))
        });
        if self.pool.is_none() {
            let videos: std::collections::BTreeSet<&str> =
                tasks.iter().map(|t| t.video.video_id.as_str()).collect();
            self.pool = Some(start_pool(
                self.settings.workers.min(videos.len().max(1)),
                self.settings.budgets,
            )?);
        }
        let Some(pool) = self.pool.take() else {
            return Ok(());
        };
        let budgets = sandbox_budgets(self.settings.budgets);
        for (id, &(task_index, sample_index)) in runnable.iter().enumerate() {
            let task = &tasks[task_index];
            let Some(pending) = self.states[task_index][sample_index].pending.as_ref() else {
                continue;
            };
            pool.submit(Unit {
                id: id as u64,
                key: format!("{}/{}", task.video.scenario, task.video.video_id),
                host: scene_host_spec(&task.video),
                source: pending.program.source.clone(),
                budgets: budgets.clone(),
            })
            .internal()?;
        }
        for result in pool.results() {
            if let Some(&(task_index, sample_index)) = usize::try_from(result.unit_id)
                .ok()
                .and_then(|id| runnable.get(id))
            {
                self.record(task_index, sample_index, outcome_from(&result));
                self.report_task(task_index, on_task_done)?;
            }
        }
        // A unit the pool never answered (its worker lost with it) still ends.
        for (task_index, sample_index) in runnable {
            if self.states[task_index][sample_index].pending.is_some() {
                self.record(task_index, sample_index, SandboxOutcome::lost());
                self.report_task(task_index, on_task_done)?;
            }
        }
        self.pool = Some(pool);
        Ok(())
    }

    /// Records a sandbox outcome for one sample: its work and times, the attempt, and either a
    /// repair turn (when the source can repair and the error is worth one) or its final outcome.
    fn record(&mut self, task_index: usize, sample_index: usize, outcome: SandboxOutcome) {
        let can_repair = self.source.can_repair();
        let repair_turns = self.settings.repair as usize;
        let sample = &mut self.states[task_index][sample_index];
        let Some(obtained) = sample.pending.take() else {
            return;
        };
        sample.work = add_work(&sample.work, &outcome.work);
        sample.own_ms += outcome.own_ms;
        sample.api_ms += outcome.api_ms;
        sample.wall_ms += outcome.wall_ms;
        sample.attempts.push(Attempt {
            sample: u32::try_from(sample_index).unwrap_or(u32::MAX),
            attempt: u32::try_from(sample.attempts.len()).unwrap_or(u32::MAX),
            program_hash: Some(obtained.program.hash()),
            program_key: obtained.program.key.clone(),
            error: outcome.result.as_ref().err().cloned(),
        });
        match outcome.result {
            Err(error)
                if repairable(&error) && can_repair && sample.attempts.len() <= repair_turns =>
            {
                let completion = obtained
                    .completion
                    .clone()
                    .unwrap_or_else(|| obtained.program.source.clone());
                sample.repairs.push(RepairTurn {
                    completion,
                    feedback: feedback(&error),
                });
            }
            result => sample.finish(Some(obtained.program), result),
        }
    }

    /// Hands out task `task_index`'s predictions when every sample has an outcome and it was
    /// not reported yet; returns whether it is finished.
    fn report_task(
        &mut self,
        task_index: usize,
        on_task_done: &mut impl FnMut(Vec<Prediction>) -> Result<(), AppError>,
    ) -> Result<bool, AppError> {
        if self.reported[task_index] {
            return Ok(true);
        }
        let samples = &mut self.states[task_index];
        if samples.iter().any(|s| s.outcome.is_none()) {
            return Ok(false);
        }
        let task = &self.tasks[task_index];
        if let Some(question) = self.questions.get(task.question_index) {
            on_task_done(task_predictions(task, question, samples))?;
        }
        self.reported[task_index] = true;
        // Free what is no longer needed.
        for sample in samples.iter_mut() {
            sample.repairs.clear();
        }
        Ok(true)
    }

    /// Step 3: reports the tasks finished without a sandbox run (a program that could not be
    /// obtained); returns how many tasks are still unfinished.
    fn report_finished(
        &mut self,
        on_task_done: &mut impl FnMut(Vec<Prediction>) -> Result<(), AppError>,
    ) -> Result<usize, AppError> {
        let mut unfinished = 0;
        for task_index in 0..self.tasks.len() {
            if !self.report_task(task_index, on_task_done)? {
                unfinished += 1;
            }
        }
        Ok(unfinished)
    }
}

fn add_work(a: &WorkCounters, b: &WorkCounters) -> WorkCounters {
    WorkCounters {
        annotation_loads: a.annotation_loads + b.annotation_loads,
        frames_decoded: a.frames_decoded + b.frames_decoded,
        detections: a.detections + b.detections,
        sim_runs: a.sim_runs + b.sim_runs,
        sim_steps: a.sim_steps + b.sim_steps,
        api_calls: a.api_calls + b.api_calls,
    }
}

/// One sample's answer for one unit.
fn sample_answer(
    value: &Value,
    question: &Question,
    option: Option<&ChoiceOption>,
    whole_question: bool,
) -> Result<String, UnitError> {
    let answer_error = |error: crate::answer::AnswerError| UnitError {
        stage: Stage::Answer,
        kind: error.kind().to_string(),
        message: error.to_string(),
    };
    match option {
        Some(option) if whole_question => {
            let letters: Vec<char> = question.options.iter().map(|o| o.letter).collect();
            let chosen = interpret_letters(value, &letters).map_err(answer_error)?;
            Ok(if chosen.contains(&option.letter) {
                "yes"
            } else {
                "no"
            }
            .to_string())
        }
        _ => interpret(value, option).map_err(answer_error),
    }
}

/// One sample's program for a unit and its answer (the raw value and the interpreted answer), or
/// why it has none.
type SampleAnswer<'a> = (Option<&'a Program>, Result<(Value, String), UnitError>);

/// The predictions of a finished task: per unit, the majority answer over the samples (ties go
/// to the earliest sample), judged against the gold.
fn task_predictions(task: &Task, question: &Question, samples: &[Sample]) -> Vec<Prediction> {
    let mut usage = Usage::default();
    let mut work = WorkCounters::default();
    let (mut own_ms, mut api_ms, mut wall_ms) = (0, 0, 0);
    let mut attempts = Vec::new();
    for sample in samples {
        usage.add(&sample.usage);
        work = add_work(&work, &sample.work);
        own_ms += sample.own_ms;
        api_ms += sample.api_ms;
        wall_ms += sample.wall_ms;
        attempts.extend(sample.attempts.iter().cloned());
    }
    let used_llm = usage.requests > 0 || usage.prompt_tokens > 0;
    task.units
        .iter()
        .enumerate()
        .map(|(position, (unit, option))| {
            // Per sample: its answer for this unit, or why it has none.
            let answers: Vec<SampleAnswer<'_>> = samples
                .iter()
                .filter_map(|s| s.outcome.as_ref())
                .map(|(program, result)| {
                    let answer = result.clone().and_then(|value| {
                        sample_answer(&value, question, option.as_ref(), task.whole_question)
                            .map(|a| (value, a))
                    });
                    (program.as_ref(), answer)
                })
                .collect();
            let mut counts: Vec<(String, u32, usize)> = Vec::new();
            for (index, (_, answer)) in answers.iter().enumerate() {
                if let Ok((_, text)) = answer {
                    match counts.iter_mut().find(|(t, _, _)| t == text) {
                        Some(entry) => entry.1 += 1,
                        None => counts.push((text.clone(), 1, index)),
                    }
                }
            }
            let winner = counts
                .iter()
                .max_by(|a, b| a.1.cmp(&b.1).then(b.2.cmp(&a.2)))
                .map(|(_, _, index)| *index);
            let chosen = winner.or(if answers.is_empty() { None } else { Some(0) });
            let (program, value, answer, error) = match chosen.and_then(|i| answers.get(i)) {
                Some((program, Ok((value, text)))) => {
                    (*program, Some(value.clone()), Some(text.clone()), None)
                }
                Some((program, Err(error))) => {
                    let value = samples
                        .first()
                        .and_then(|s| s.outcome.as_ref())
                        .and_then(|(_, r)| r.as_ref().ok().cloned());
                    (*program, value, None, Some(error.clone()))
                }
                None => (None, None, None, None),
            };
            let correct = error.is_none()
                && answer
                    .as_deref()
                    .is_some_and(|a| is_correct(a, &question.answer, option.as_ref()));
            // Work, time and usage belong to the program: the first unit of a task carries them.
            let first = position == 0;
            Prediction {
                unit: unit.clone(),
                question_id: question.id.0.clone(),
                option: option.as_ref().map(|o| o.letter),
                scenario: question.scenario,
                family: question.family.0.clone(),
                video_id: question.video_id.0.clone(),
                program_hash: program.map(Program::hash),
                program_key: program.and_then(|p| p.key.clone()),
                program_origin: program.map(|p| origin_name(p.origin).to_string()),
                value,
                answer,
                correct,
                error,
                attempts: if samples.len() > 1 || attempts.len() > 1 {
                    attempts.clone()
                } else {
                    Vec::new()
                },
                votes: if samples.len() > 1 {
                    counts.iter().map(|(t, n, _)| (t.clone(), *n)).collect()
                } else {
                    Vec::new()
                },
                usage: (first && used_llm).then_some(usage),
                work: if first { work } else { WorkCounters::default() },
                own_ms: if first { own_ms } else { 0 },
                api_ms: if first { api_ms } else { 0 },
                wall_ms: if first { wall_ms } else { 0 },
            }
        })
        .collect()
}

/// The recorded name of a program's origin.
pub(crate) fn origin_name(origin: ProgramOrigin) -> &'static str {
    match origin {
        ProgramOrigin::Builtin => "builtin",
        ProgramOrigin::Cache => "cache",
        ProgramOrigin::File => "file",
        ProgramOrigin::Llm => "llm",
    }
}
