//! Question files in both engine forms (`docs/data/questions.md`):
//!
//! * per video: `{"video_id": "0", "question_dict": {"mass": [record, ...], ...}}`, as the engine
//!   writes `DATA/pulley_group/0.json`;
//! * sampled: a list of records carrying `question_id`, `qtype`, `video_id` and `split`, as the
//!   sampler writes `DATA/pulley_group_test.json`.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use indexmap::IndexMap;
use serde::{Deserialize, Serialize};
use serde_json::Value;

use super::fields::read_json;
use super::{
    DataRoot, DatasetError, Question, QuestionError, QuestionId, QuestionRecord, Scenario, Split,
    VideoId,
};

/// The per-video engine output.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PerVideoQuestions {
    /// The video folder name.
    pub video_id: String,
    /// Records per family, in generation order.
    pub question_dict: IndexMap<String, Vec<QuestionRecord>>,
}

/// The questions of one file, validated.
#[derive(Debug, Clone)]
pub struct QuestionSource {
    /// The file they came from.
    pub path: PathBuf,
    /// The scenario of every question in it.
    pub scenario: Scenario,
    /// The questions in file order.
    pub questions: Vec<Question>,
}

/// `pulley_group_test.json`: the sampled file name of a scenario and split.
pub fn questions_file_name(scenario: Scenario, split: Split) -> String {
    format!("{}_{}.json", scenario.folder_name(), split.as_str())
}

/// Where the sampled file of a scenario and split sits in a data root.
pub fn sampled_file_path(root: &DataRoot, scenario: Scenario, split: Split) -> PathBuf {
    root.dir().join(questions_file_name(scenario, split))
}

/// Each scenario's family keys (the scenario table's engines), to tell a question file's
/// scenario from its records.
pub type FamilyIndex<'a> = &'a [(Scenario, &'static [&'static str])];

/// Loads a question file of either form. `scenario` overrides detection from the file name, its
/// folder, or its families (the one scenario of `families` that has every family in the file).
pub fn load_question_file(
    path: &Path,
    scenario: Option<Scenario>,
    families: FamilyIndex<'_>,
) -> Result<QuestionSource, DatasetError> {
    let value = read_json(path)?;
    let records = match &value {
        Value::Object(map) if map.contains_key("question_dict") => {
            let per_video: PerVideoQuestions =
                serde_json::from_value(value.clone()).map_err(|source| DatasetError::Json {
                    path: path.to_path_buf(),
                    source,
                })?;
            let video_id = per_video.video_id;
            per_video
                .question_dict
                .into_iter()
                .flat_map(|(family, records)| {
                    let video_id = video_id.clone();
                    records.into_iter().enumerate().map(move |(index, record)| {
                        let id = QuestionId(format!("{video_id}/{family}/{index}"));
                        (id, VideoId(video_id.clone()), record)
                    })
                })
                .collect::<Vec<_>>()
        }
        Value::Array(items) => {
            let mut out = Vec::with_capacity(items.len());
            for (index, item) in items.iter().enumerate() {
                let record: QuestionRecord =
                    serde_json::from_value(item.clone()).map_err(|error| DatasetError::Field {
                        path: path.to_path_buf(),
                        field: index.to_string(),
                        problem: format!("is not a question record: {error}"),
                    })?;
                let field_error = |field: &str| DatasetError::Field {
                    path: path.to_path_buf(),
                    field: format!("{index}.{field}"),
                    problem: "is missing (sampled question files carry question_id and video_id)"
                        .to_string(),
                };
                let id = record
                    .question_id
                    .clone()
                    .ok_or_else(|| field_error("question_id"))?;
                let video = record
                    .video_id
                    .clone()
                    .ok_or_else(|| field_error("video_id"))?;
                out.push((QuestionId(id), VideoId(video), record));
            }
            out
        }
        _ => {
            return Err(DatasetError::Field {
                path: path.to_path_buf(),
                field: "<root>".to_string(),
                problem: "must be a list of sampled questions or an object with `video_id` and `question_dict`"
                    .to_string(),
            });
        }
    };
    let scenario = match scenario {
        Some(scenario) => scenario,
        None => detect_scenario(
            path,
            records.iter().map(|(_, _, r)| r.question_family.as_str()),
            families,
        )
        .ok_or_else(|| DatasetError::UnknownScenario {
            path: path.to_path_buf(),
        })?,
    };
    let mut seen = BTreeSet::new();
    let mut questions = Vec::with_capacity(records.len());
    for (id, video_id, record) in records {
        if !seen.insert(id.clone()) {
            return Err(DatasetError::Question {
                path: path.to_path_buf(),
                question_id: id.0,
                problem: QuestionError::DuplicateId,
            });
        }
        let question =
            Question::from_record(id.clone(), video_id, scenario, record).map_err(|problem| {
                DatasetError::Question {
                    path: path.to_path_buf(),
                    question_id: id.0,
                    problem,
                }
            })?;
        questions.push(question);
    }
    Ok(QuestionSource {
        path: path.to_path_buf(),
        scenario,
        questions,
    })
}

/// The scenario from the file name (`<scenario folder>_test.json`), its folder
/// (`<scenario folder>/0.json`), or the family names.
fn detect_scenario<'a>(
    path: &Path,
    file_families: impl Iterator<Item = &'a str>,
    families: FamilyIndex<'_>,
) -> Option<Scenario> {
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    if let Some(scenario) = Scenario::ALL
        .into_iter()
        .find(|s| stem.starts_with(s.folder_name()))
    {
        return Some(scenario);
    }
    let parent = path
        .parent()
        .and_then(Path::file_name)
        .map(|n| n.to_string_lossy().into_owned());
    if let Some(scenario) = parent.as_deref().and_then(Scenario::from_folder_name) {
        return Some(scenario);
    }
    // The families tell the scenario when exactly one scenario has all of them (several
    // scenarios share property family names, so a file of those alone stays undecided).
    let in_file: BTreeSet<&str> = file_families.collect();
    if in_file.is_empty() {
        return None;
    }
    let mut candidates = families
        .iter()
        .filter(|(_, known)| in_file.iter().all(|family| known.contains(family)))
        .map(|(scenario, _)| *scenario);
    match (candidates.next(), candidates.next()) {
        (Some(scenario), None) => Some(scenario),
        _ => None,
    }
}

/// Writes the per-video engine output (4-space indented, as the public engine's `json.dump`).
pub fn write_per_video_file(
    path: &Path,
    questions: &PerVideoQuestions,
) -> Result<(), crate::util::FsError> {
    crate::util::write_atomic(path, &to_pretty_json(questions))
}

/// Writes a sampled question list.
pub fn write_sampled_file(
    path: &Path,
    records: &[QuestionRecord],
) -> Result<(), crate::util::FsError> {
    crate::util::write_atomic(path, &to_pretty_json(&records))
}

fn to_pretty_json(value: &impl Serialize) -> Vec<u8> {
    let mut out = Vec::new();
    let formatter = serde_json::ser::PrettyFormatter::with_indent(b"    ");
    let mut serializer = serde_json::Serializer::with_formatter(&mut out, formatter);
    // Serialising plain records into memory cannot fail (no maps with non-string keys).
    if value.serialize(&mut serializer).is_err() {
        out.clear();
    }
    out.push(b'\n');
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const FAMILIES: FamilyIndex<'static> = &[
        (
            Scenario::Rope,
            &[
                "mass",
                "tension",
                "shape",
                "color",
                "existence",
                "rope_counterfactual",
            ],
        ),
        (Scenario::Cloth, &["elasticity", "bending", "shape"]),
    ];

    #[test]
    fn both_forms_load_and_scenario_is_detected() {
        let dir = tempfile::tempdir().unwrap();
        let per_video = dir.path().join("pulley_group/0.json");
        fs_err::create_dir_all(per_video.parent().unwrap()).unwrap();
        fs_err::write(
            &per_video,
            r#"{"video_id": "0", "question_dict": {"shape": [
                {"question": "How many cubes are there in the video?", "answer": "2",
                 "question_family": "shape", "positive": ["2"], "negative": [],
                 "program": ["cube"], "answer_type": "open_ended"}]}}"#,
        )
        .unwrap();
        let source = load_question_file(&per_video, None, FAMILIES).unwrap();
        assert_eq!(source.scenario, Scenario::Rope);
        assert_eq!(source.questions[0].id.0, "0/shape/0");
        assert_eq!(source.questions[0].answer, "2");

        let sampled = dir.path().join("pulley_group_test.json");
        fs_err::write(
            &sampled,
            r#"[{"question": "Is there any red cube in the video?", "answer": "no",
                "question_family": "existence", "answer_type": "open_ended",
                "qtype": "existence", "video_id": "7", "question_id": "00003", "split": "test"}]"#,
        )
        .unwrap();
        let source = load_question_file(&sampled, None, FAMILIES).unwrap();
        assert_eq!(source.questions[0].id.0, "00003");
        assert_eq!(source.questions[0].video_id.0, "7");
        assert_eq!(source.questions[0].split, Some(Split::Test));
    }

    #[test]
    fn families_tell_the_scenario_only_when_one_scenario_has_them_all() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("questions.json");
        let file = |families: &[&str]| {
            let records: Vec<String> = families
                .iter()
                .enumerate()
                .map(|(index, family)| {
                    format!(
                        r#"{{"question": "Q?", "answer": "no", "question_family": "{family}", "answer_type": "open_ended", "video_id": "0", "question_id": "{index}"}}"#
                    )
                })
                .collect();
            fs_err::write(&path, format!("[{}]", records.join(","))).unwrap();
        };
        file(&["mass", "existence"]);
        let source = load_question_file(&path, None, FAMILIES).unwrap();
        assert_eq!(source.scenario, Scenario::Rope);
        // `shape` is a family of two scenarios; `density` of none listed.
        for families in [&["shape"][..], &["mass", "density"][..]] {
            file(families);
            let error = load_question_file(&path, None, FAMILIES).unwrap_err();
            assert!(
                error.to_string().starts_with("cannot tell the scenario of"),
                "{families:?}: {error}"
            );
        }
        file(&["shape"]);
        let given = load_question_file(&path, Some(Scenario::Cloth), FAMILIES).unwrap();
        assert_eq!(given.scenario, Scenario::Cloth);
    }

    #[test]
    fn bad_files_name_the_problem() {
        let dir = tempfile::tempdir().unwrap();
        let cases = [
            (
                "pulley_group_test.json",
                r#"[{"question": "Q?"#,
                "is not valid JSON",
            ),
            (
                "pulley_group_val.json",
                r#"{"a": 1}"#,
                "must be a list of sampled questions",
            ),
            (
                "pulley_group_train.json",
                r#"[{"question": "Q?", "answer": "no", "question_family": "mass", "answer_type": "open_ended"}]"#,
                "field `0.question_id` is missing",
            ),
            ("questions.json", "[]", "cannot tell the scenario"),
            (
                "pulley_group_x.json",
                r#"[{"question": "Q?", "answer": "no", "question_family": "mass", "answer_type": "open_ended", "video_id": "0", "question_id": "1"},
                    {"question": "Q?", "answer": "no", "question_family": "mass", "answer_type": "open_ended", "video_id": "0", "question_id": "1"}]"#,
                "question `1`: the id appears more than once",
            ),
        ];
        for (name, text, expected) in cases {
            let path = dir.path().join(name);
            fs_err::write(&path, text).unwrap();
            let error = load_question_file(&path, None, FAMILIES)
                .unwrap_err()
                .to_string();
            assert!(
                error.contains(expected),
                "{name}: `{error}` lacks `{expected}`"
            );
            assert!(
                error.contains(name),
                "{name}: `{error}` does not name the file"
            );
        }
    }
}
