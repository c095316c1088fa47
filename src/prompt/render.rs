//! [`PromptSet`]: the templates and the api_spec, loaded once, rendered per unit of work.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;
use std::sync::{Arc, Mutex};

use minijinja::value::{Object, Serde, Value};
use minijinja::{AutoEscape, Environment, ErrorKind, State, UndefinedBehavior};
use serde::{Deserialize, Serialize};

use super::context::{PromptContext, PromptMode, SceneWords, unit_of};
use super::error::PromptError;
use super::example::Example;
use super::files::{embedded_files, read_dir_files};
use crate::dataset::{ChoiceOption, Question};
use crate::util::content_hash_json;

/// The template of the user message.
const USER_TEMPLATE: &str = "base.jinja";
/// The template of the system message (optional: a set without it has no system message).
const SYSTEM_TEMPLATE: &str = "system.jinja";
/// The API listing every prompt shows.
const API_SPEC_PATH: &str = "api_spec/scene_api.pyi";
/// The api_spec version (part of program-cache keys).
const VERSION_PATH: &str = "api_spec/VERSION";
/// The context variable through which `example()` records the examples a render used.
const USED_EXAMPLES_VARIABLE: &str = "used_examples";

/// A rendered prompt: the chat messages of one unit of work, and what identifies the prompt
/// machinery that produced them (both enter program-cache keys, `docs/architecture.md`, program
/// cache).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct RenderedPrompt {
    /// The system message, if the set has one.
    pub system: Option<String>,
    /// The user message: API, instruction, guidelines, examples, query.
    pub user: String,
    /// blake3 (hex) over every template and the api_spec files this render used (the API
    /// listing, `VERSION` and the examples shown), with their paths.
    pub template_hash: String,
    /// The api_spec version (`api_spec/VERSION`).
    pub api_spec_version: String,
}

/// One chat message.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct ChatMessage {
    /// `system` or `user`.
    pub role: String,
    /// The text.
    pub content: String,
}

impl RenderedPrompt {
    /// The chat messages: the system message (if any), then the user message.
    pub fn messages(&self) -> Vec<ChatMessage> {
        let mut messages = Vec::with_capacity(2);
        if let Some(system) = &self.system {
            messages.push(ChatMessage {
                role: "system".to_string(),
                content: system.clone(),
            });
        }
        messages.push(ChatMessage {
            role: "user".to_string(),
            content: self.user.clone(),
        });
        messages
    }

    /// Characters over all messages.
    pub fn char_count(&self) -> usize {
        self.system.as_deref().map_or(0, |s| s.chars().count()) + self.user.chars().count()
    }
}

/// Templates (`prompts/`) and the api_spec (`api_spec/`), parsed and checked once.
pub struct PromptSet {
    /// Every file of the set, by path.
    files: BTreeMap<String, String>,
    environment: Environment<'static>,
    /// Parsed examples by name (`rope/mass`).
    examples: BTreeMap<String, Example>,
    api_spec_version: String,
    /// Where the set came from, for messages: `embedded`, or the override directory.
    origin: String,
    /// Every scenario's words, as the guidelines list them.
    scenes: Vec<SceneWords>,
}

impl std::fmt::Debug for PromptSet {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PromptSet")
            .field("origin", &self.origin)
            .field("files", &self.files.len())
            .field("api_spec_version", &self.api_spec_version)
            .finish_non_exhaustive()
    }
}

impl PromptSet {
    /// The set compiled into the binary; `scenes` are the scenarios' words the guidelines list.
    pub fn embedded(scenes: &[SceneWords]) -> Result<PromptSet, PromptError> {
        PromptSet::from_files(embedded_files(), "embedded".to_string(), scenes)
    }

    /// The embedded set with the files under `dir` in place of (or added to) the embedded ones.
    ///
    /// `dir` mirrors the repository's layout: `dir/prompts/base.jinja`,
    /// `dir/prompts/partials/...`, `dir/api_spec/scene_api.pyi`, `dir/api_spec/VERSION`,
    /// `dir/api_spec/examples/<scenario>/<name>.py`. A user who edits one template copies just
    /// that file; the repository root itself is a valid `dir`.
    pub fn load(dir: &Path, scenes: &[SceneWords]) -> Result<PromptSet, PromptError> {
        let mut files = embedded_files();
        files.extend(read_dir_files(dir)?);
        PromptSet::from_files(files, dir.display().to_string(), scenes)
    }

    fn from_files(
        files: BTreeMap<String, String>,
        origin: String,
        scenes: &[SceneWords],
    ) -> Result<PromptSet, PromptError> {
        let api_spec_version = files
            .get(VERSION_PATH)
            .map(|text| text.trim().to_string())
            .filter(|version| !version.is_empty() && !version.contains(char::is_whitespace))
            .ok_or_else(|| PromptError::Spec {
                path: VERSION_PATH.to_string(),
                problem: "must hold the api_spec version, one word such as `1`".to_string(),
            })?;
        if !files.contains_key(API_SPEC_PATH) {
            return Err(PromptError::Spec {
                path: API_SPEC_PATH.to_string(),
                problem: "is missing".to_string(),
            });
        }
        let template_path = format!("prompts/{USER_TEMPLATE}");
        if !files.contains_key(&template_path) {
            return Err(PromptError::Spec {
                path: template_path,
                problem: "is missing".to_string(),
            });
        }
        let mut examples = BTreeMap::new();
        for (path, text) in &files {
            if path.starts_with("api_spec/examples/") {
                let example = Example::parse(path, text)?;
                examples.insert(example.name.clone(), example);
            }
        }
        let texts: Arc<BTreeMap<String, (String, String)>> = Arc::new(
            examples
                .values()
                .map(|e| (e.name.clone(), (e.path.clone(), e.prompt_text.clone())))
                .collect(),
        );
        let mut environment = Environment::new();
        environment.set_undefined_behavior(UndefinedBehavior::Strict);
        // Errors name the undefined variable in release builds too: minijinja keeps the debug
        // info that names it only under debug assertions unless asked.
        environment.set_debug(true);
        environment.set_auto_escape_callback(|_| AutoEscape::None);
        let syntax = minijinja::syntax::SyntaxConfig::builder()
            .trim_blocks(true)
            .lstrip_blocks(true)
            // Partials end with a newline, so an include is a whole line of the prompt.
            .keep_trailing_newline(true)
            .build()
            .map_err(|source| PromptError::Syntax {
                template: "(syntax configuration)".to_string(),
                line: 0,
                source,
            })?;
        environment.set_syntax(syntax);
        environment.add_function("example", move |state: &State, name: String| {
            example_text(&texts, state, &name)
        });
        for (path, text) in &files {
            if let Some(name) = path.strip_prefix("prompts/") {
                environment
                    .add_template_owned(name.to_string(), text.clone())
                    .map_err(|source| PromptError::Syntax {
                        template: name.to_string(),
                        line: source.line().unwrap_or(0),
                        source,
                    })?;
            }
        }
        Ok(PromptSet {
            files,
            environment,
            examples,
            api_spec_version,
            origin,
            scenes: scenes.to_vec(),
        })
    }

    /// The api_spec version (`api_spec/VERSION`).
    pub fn api_spec_version(&self) -> &str {
        &self.api_spec_version
    }

    /// blake3 (hex) over every file of the set with its path: what identifies the whole set (for
    /// a run manifest). A render's own [`RenderedPrompt::template_hash`] covers only the files
    /// it used.
    pub fn hash(&self) -> String {
        hash_files(self.files.iter())
    }

    /// Every file of the set, `(path, text)`, by path.
    pub fn files(&self) -> impl Iterator<Item = (&str, &str)> {
        self.files.iter().map(|(p, t)| (p.as_str(), t.as_str()))
    }

    /// The worked examples, by name.
    pub fn examples(&self) -> impl Iterator<Item = &Example> {
        self.examples.values()
    }

    /// Renders the prompt of one unit of work: `option` is the unit's option in per-option mode,
    /// and `None` for open questions and for choice questions asked per question.
    pub fn render(
        &self,
        question: &Question,
        option: Option<&ChoiceOption>,
        mode: PromptMode,
    ) -> Result<RenderedPrompt, PromptError> {
        let unit = unit_of(question, option, mode).map_err(|problem| PromptError::Unit {
            question_id: question.id.0.clone(),
            problem,
        })?;
        let api_spec = self
            .files
            .get(API_SPEC_PATH)
            .map_or("", String::as_str)
            .trim_end();
        let context = PromptContext::new(
            question,
            unit,
            mode,
            (api_spec, &self.api_spec_version),
            &self.scenes,
        );
        let used = Arc::new(UsedExamples::default());
        let context = minijinja::context! {
            used_examples => Value::from_dyn_object(Arc::clone(&used)),
            ..Value::from(Serde(&context))
        };
        let system = match self.environment.get_template(SYSTEM_TEMPLATE) {
            Ok(template) => {
                let text = template
                    .render(&context)
                    .map_err(|error| render_error(&self.environment, error))?;
                Some(normalise(&text)).filter(|text| !text.is_empty())
            }
            Err(error) if error.kind() == ErrorKind::TemplateNotFound => None,
            Err(error) => return Err(render_error(&self.environment, error)),
        };
        let user = self
            .environment
            .get_template(USER_TEMPLATE)
            .and_then(|template| template.render(&context))
            .map_err(|error| render_error(&self.environment, error))?;
        let used_paths: BTreeSet<String> = used
            .paths
            .lock()
            .map(|paths| paths.clone())
            .unwrap_or_default();
        let hashed = self.files.iter().filter(|(path, _)| {
            path.starts_with("prompts/")
                || path.as_str() == API_SPEC_PATH
                || path.as_str() == VERSION_PATH
                || used_paths.contains(path.as_str())
        });
        Ok(RenderedPrompt {
            system,
            user: normalise(&user),
            template_hash: hash_files(hashed),
            api_spec_version: self.api_spec_version.clone(),
        })
    }
}

/// The example paths one render used.
#[derive(Debug, Default)]
struct UsedExamples {
    paths: Mutex<BTreeSet<String>>,
}

impl Object for UsedExamples {}

/// `example(name)`: the example's prompt text, recording its path for the template hash.
fn example_text(
    examples: &BTreeMap<String, (String, String)>,
    state: &State,
    name: &str,
) -> Result<String, minijinja::Error> {
    let Some((path, text)) = examples.get(name) else {
        let known: Vec<&str> = examples.keys().map(String::as_str).collect();
        return Err(minijinja::Error::new(
            ErrorKind::InvalidOperation,
            format!(
                "unknown example `{name}` (no api_spec/examples/{name}.py); examples are {}",
                known.join(", ")
            ),
        ));
    };
    if let Some(used) = state
        .lookup(USED_EXAMPLES_VARIABLE)
        .and_then(|value| value.downcast_object::<UsedExamples>())
        && let Ok(mut paths) = used.paths.lock()
    {
        paths.insert(path.clone());
    }
    Ok(text.clone())
}

/// Trailing spaces dropped, runs of blank lines collapsed to one, no leading or trailing blank
/// lines, one final newline: template whitespace does not leak into prompts (or cache keys).
fn normalise(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut blank_run = 0;
    for line in text.lines() {
        let line = line.trim_end();
        if line.is_empty() {
            blank_run += 1;
            continue;
        }
        if !out.is_empty() && blank_run > 0 {
            out.push('\n');
        }
        blank_run = 0;
        out.push_str(line);
        out.push('\n');
    }
    out
}

/// blake3 over `(path, text)` pairs in path order.
fn hash_files<'a>(files: impl Iterator<Item = (&'a String, &'a String)>) -> String {
    let pairs: Vec<serde_json::Value> = files
        .map(|(path, text)| serde_json::json!([path, text]))
        .collect();
    content_hash_json(&serde_json::Value::Array(pairs))
}

/// A minijinja error as a [`PromptError`] naming the template, the line and, for undefined
/// values, the variable.
fn render_error(environment: &Environment<'static>, error: minijinja::Error) -> PromptError {
    // An error inside an include is wrapped; the innermost minijinja error names the template.
    let mut innermost = &error;
    while let Some(inner) = std::error::Error::source(innermost)
        .and_then(|source| source.downcast_ref::<minijinja::Error>())
    {
        innermost = inner;
    }
    let template = innermost
        .name()
        .or_else(|| error.name())
        .unwrap_or("(unknown template)")
        .to_string();
    let line = innermost.line().or_else(|| error.line()).unwrap_or(0);
    match innermost.kind() {
        ErrorKind::UndefinedError => {
            let variable = undefined_variable(environment, innermost, &template, line);
            PromptError::UndefinedVariable {
                template,
                line,
                variable,
                source: error,
            }
        }
        ErrorKind::SyntaxError => PromptError::Syntax {
            template,
            line,
            source: error,
        },
        kind => {
            let detail = innermost
                .detail()
                .map_or_else(|| kind.to_string(), str::to_string);
            PromptError::Render {
                template,
                line,
                detail,
                source: error,
            }
        }
    }
}

/// The undefined expression, as minijinja's debug info names it (`` `option.text` is
/// undefined``); failing that, the failing line of the template.
fn undefined_variable(
    environment: &Environment<'static>,
    error: &minijinja::Error,
    template: &str,
    line: usize,
) -> String {
    let named = error.detail().and_then(|detail| {
        let (before, _) = detail.split_once("` is undefined")?;
        let (_, name) = before.rsplit_once('`')?;
        Some(name.to_string())
    });
    named.unwrap_or_else(|| {
        environment
            .get_template(template)
            .ok()
            .and_then(|t| {
                t.source()
                    .lines()
                    .nth(line.saturating_sub(1))
                    .map(|l| l.trim().to_string())
            })
            .unwrap_or_else(|| "(unknown)".to_string())
    })
}

/// The error and its causes on one line, for the shared set's cached failure.
/// The message of `error` and its sources, joined by `: `.
pub fn error_chain(error: &PromptError) -> String {
    let mut message = error.to_string();
    let mut source = std::error::Error::source(error);
    while let Some(cause) = source {
        message.push_str(": ");
        message.push_str(&cause.to_string());
        source = cause.source();
    }
    message
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn whitespace_is_normalised() {
        assert_eq!(normalise("\n\na  \n\n\n\nb\n  \n"), "a\n\nb\n");
        assert_eq!(normalise(""), "");
    }
}
