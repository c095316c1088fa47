//! Sampler v3 and the per-video split (the question-file format of `docs/data/questions.md`): from each video's engine output,
//! a few property and dynamics questions; then the videos split 50/20/30 into train, val and test.
//!
//! Input: per-video engine outputs ([`PerVideoQuestions`]) and a seed. Output: [`SampledSplits`],
//! one list of tagged records (`qtype`, `video_id`, `question_id`, `split`) per split, in
//! question-id order. The result depends only on the inputs and the seed: each video draws from
//! its own RNG stream (`sampler/<scenario>/<video_id>`), so adding a video does not change the
//! others' picks.
//!
//! Differences from the public `run_question_sampler_v3` + `split_dataset`, each deliberate:
//!
//! * Question ids follow numeric video-id order (the public sampler numbered files in
//!   `os.listdir` order).
//! * The val/test boundary is ⌊7N/10⌋ in integer arithmetic; the public `int(N*0.7)` (with
//!   `0.7 = 0.5 + 0.2`) is one less for some N, e.g. N = 90 gives 62 instead of 63.
//! * Topping up a pool that has fewer families than requested questions draws only questions
//!   not already picked; the public sampler drew from all of them and could repeat a question
//!   within one video. A video therefore yields `min(requested, available)` questions per pool.

use rand::Rng;
use rand::seq::index;

use crate::dataset::{
    Category, Family, PerVideoQuestions, QuestionRecord, Scenario, Split, VideoId,
};
use crate::util::{derive_seed, seeded_rng};

/// How many questions to draw per video.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SamplerConfig {
    /// Property questions per video (`fact_ques_num`).
    pub fact_per_video: usize,
    /// Dynamics questions (counterfactual, goal-driven, predictive) per video (`count_ques_num`).
    pub dynamics_per_video: usize,
}

impl Default for SamplerConfig {
    /// 2 + 2, as the paper states for rope (and the public sampler's defaults; its shell script
    /// passes 1 + 1).
    fn default() -> SamplerConfig {
        SamplerConfig {
            fact_per_video: 2,
            dynamics_per_video: 2,
        }
    }
}

/// The sampled questions of each split, in question-id order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SampledSplits {
    /// Videos `[0, ⌊N/2⌋)` in numeric id order.
    pub train: Vec<QuestionRecord>,
    /// Videos `[⌊N/2⌋, ⌊7N/10⌋)`.
    pub val: Vec<QuestionRecord>,
    /// Videos `[⌊7N/10⌋, N)`.
    pub test: Vec<QuestionRecord>,
}

impl SampledSplits {
    /// The records of one split.
    pub fn get(&self, split: Split) -> &[QuestionRecord] {
        match split {
            Split::Train => &self.train,
            Split::Val => &self.val,
            Split::Test => &self.test,
        }
    }

    /// All records in question-id order (the public `merge.json`, with `split` set).
    pub fn all(&self) -> impl Iterator<Item = &QuestionRecord> {
        self.train.iter().chain(&self.val).chain(&self.test)
    }
}

/// The split boundaries for `video_count` videos sorted by id: train is `[0, first)`, val
/// `[first, second)`, test `[second, video_count)`. Exact integer arithmetic, free of overflow.
pub fn split_boundaries(video_count: usize) -> (usize, usize) {
    let seven_tenths = video_count / 10 * 7 + video_count % 10 * 7 / 10;
    (video_count / 2, seven_tenths)
}

/// Samples `config`'s questions from every video and splits the videos (see the module docs).
/// Videos without any question are not counted in N, as in the public split, which only saw
/// sampled records.
pub fn sample_and_split(
    scenario: Scenario,
    per_video: &[PerVideoQuestions],
    config: &SamplerConfig,
    seed: u64,
) -> SampledSplits {
    let mut videos: Vec<&PerVideoQuestions> = per_video.iter().collect();
    videos.sort_by(|first, second| {
        let (first, second) = (
            VideoId(first.video_id.clone()),
            VideoId(second.video_id.clone()),
        );
        first.sort_key().cmp(&second.sort_key())
    });
    let sampled: Vec<Vec<QuestionRecord>> = videos
        .iter()
        .map(|video| sample_video(scenario, video, config, seed))
        .filter(|records| !records.is_empty())
        .collect();
    let (val_start, test_start) = split_boundaries(sampled.len());
    let mut splits = SampledSplits::default();
    let mut next_question_id = 0_usize;
    for (video_position, records) in sampled.into_iter().enumerate() {
        let split = if video_position < val_start {
            Split::Train
        } else if video_position < test_start {
            Split::Val
        } else {
            Split::Test
        };
        for mut record in records {
            record.question_id = Some(format!("{next_question_id:05}"));
            next_question_id += 1;
            // A legacy answer of older engines, kept from the public sampler.
            if record.answer == "No answer." {
                record.positive.clear();
            }
            record.split = Some(split.as_str().to_string());
            match split {
                Split::Train => splits.train.push(record),
                Split::Val => splits.val.push(record),
                Split::Test => splits.test.push(record),
            }
        }
    }
    splits
}

/// One video's picks: property questions first, then dynamics questions.
fn sample_video(
    scenario: Scenario,
    video: &PerVideoQuestions,
    config: &SamplerConfig,
    seed: u64,
) -> Vec<QuestionRecord> {
    let mut rng = seeded_rng(derive_seed(
        seed,
        &format!("sampler/{}/{}", scenario.name(), video.video_id),
    ));
    let mut fact = Pool::default();
    let mut dynamics = Pool::default();
    for (family, records) in &video.question_dict {
        if records.is_empty() {
            continue;
        }
        let pool = match Family(family.clone()).category() {
            Category::Property => &mut fact,
            Category::Counterfactual | Category::GoalDriven | Category::Predictive => &mut dynamics,
        };
        let first = pool.records.len();
        pool.records
            .extend(records.iter().cloned().map(|mut record| {
                record.qtype = Some(family.clone());
                record.video_id = Some(video.video_id.clone());
                record
            }));
        pool.family_picks
            .push(first + rng.random_range(0..records.len()));
    }
    let mut picked = fact.draw(config.fact_per_video, &mut rng);
    picked.extend(dynamics.draw(config.dynamics_per_video, &mut rng));
    picked
}

/// The questions of one category of a video, and one pick per family.
#[derive(Default)]
struct Pool {
    records: Vec<QuestionRecord>,
    family_picks: Vec<usize>,
}

impl Pool {
    /// `wanted` questions: a random subset (in random order) of the per-family picks, or all of
    /// them topped up with random other questions of the pool.
    fn draw(self, wanted: usize, rng: &mut impl Rng) -> Vec<QuestionRecord> {
        let chosen: Vec<usize> = if self.family_picks.len() >= wanted {
            index::sample(rng, self.family_picks.len(), wanted)
                .into_iter()
                .filter_map(|position| self.family_picks.get(position).copied())
                .collect()
        } else {
            // Top up without repeating a question (the public sampler could repeat one).
            let others: Vec<usize> = (0..self.records.len())
                .filter(|index| !self.family_picks.contains(index))
                .collect();
            let top_up = (wanted - self.family_picks.len()).min(others.len());
            let extra = index::sample(rng, others.len(), top_up)
                .into_iter()
                .filter_map(|p| others.get(p).copied());
            self.family_picks.iter().copied().chain(extra).collect()
        };
        chosen
            .into_iter()
            .filter_map(|index| self.records.get(index).cloned())
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use indexmap::IndexMap;

    use super::*;

    #[test]
    fn split_boundaries_are_exact_where_the_float_version_is_not() {
        // (N, end of train, end of val); N = 90 is where int(N * (0.5 + 0.2)) gives 62.
        let cases = [
            (0, 0, 0),
            (1, 0, 0),
            (2, 1, 1),
            (3, 1, 2),
            (10, 5, 7),
            (90, 45, 63),
            (170, 85, 119),
            (2000, 1000, 1400),
        ];
        for (video_count, train_end, val_end) in cases {
            assert_eq!(
                split_boundaries(video_count),
                (train_end, val_end),
                "N = {video_count}"
            );
        }
        for video_count in 0..5000 {
            assert_eq!(split_boundaries(video_count).1, video_count * 7 / 10);
        }
    }

    fn record(family: &str, index: usize) -> QuestionRecord {
        QuestionRecord {
            question: format!("{family} question {index}?"),
            answer: "yes".into(),
            question_family: family.into(),
            positive: vec!["yes".into()],
            negative: vec![],
            program: None,
            answer_type: "open_ended".into(),
            qtype: None,
            video_id: None,
            question_id: None,
            split: None,
            extra: IndexMap::new(),
        }
    }

    fn video(video_id: &str, families: &[(&str, usize)]) -> PerVideoQuestions {
        PerVideoQuestions {
            video_id: video_id.into(),
            question_dict: families
                .iter()
                .map(|&(family, count)| {
                    (
                        family.to_string(),
                        (0..count).map(|i| record(family, i)).collect(),
                    )
                })
                .collect(),
        }
    }

    const ROPE_FAMILIES: [(&str, usize); 8] = [
        ("mass", 3),
        ("tension", 0),
        ("shape", 7),
        ("color", 12),
        ("existence", 72),
        ("rope_counterfactual", 17),
        ("rope_counterfactual2", 66),
        ("rope_goaldriven", 5),
    ];

    #[test]
    fn videos_split_in_numeric_order_with_ids_in_that_order() {
        // Given out of order, with ids that sort differently as text ("10" < "2").
        let ids = ["10", "2", "0", "7", "1", "3", "9", "4", "8", "5", "6"];
        let per_video: Vec<PerVideoQuestions> =
            ids.iter().map(|id| video(id, &ROPE_FAMILIES)).collect();
        let splits = sample_and_split(Scenario::Rope, &per_video, &SamplerConfig::default(), 3);
        let video_order = |records: &[QuestionRecord]| -> Vec<String> {
            let mut order: Vec<String> = Vec::new();
            for record in records {
                let id = record.video_id.clone().unwrap();
                if order.last() != Some(&id) {
                    order.push(id);
                }
            }
            order
        };
        // N = 11: train [0, 5), val [5, 7), test [7, 11).
        assert_eq!(video_order(&splits.train), ["0", "1", "2", "3", "4"]);
        assert_eq!(video_order(&splits.val), ["5", "6"]);
        assert_eq!(video_order(&splits.test), ["7", "8", "9", "10"]);
        let all: Vec<&QuestionRecord> = splits.all().collect();
        assert_eq!(all.len(), 44);
        for (position, record) in all.iter().enumerate() {
            assert_eq!(
                record.question_id.as_deref(),
                Some(format!("{position:05}").as_str())
            );
        }
        for split in Split::ALL {
            assert!(
                splits
                    .get(split)
                    .iter()
                    .all(|r| r.split.as_deref() == Some(split.as_str()))
            );
        }
    }

    #[test]
    fn each_video_gives_facts_then_dynamics_one_per_family() {
        let per_video = vec![video("0", &ROPE_FAMILIES)];
        for seed in 0..100 {
            let splits =
                sample_and_split(Scenario::Rope, &per_video, &SamplerConfig::default(), seed);
            assert!(
                splits.train.is_empty() && splits.val.is_empty(),
                "N = 1 puts the only video in test"
            );
            let records = &splits.test;
            let families: Vec<&str> = records
                .iter()
                .map(|r| r.qtype.as_deref().unwrap())
                .collect();
            assert_eq!(families.len(), 4);
            let category = |family: &str| Family(family.to_string()).category();
            assert!(
                families[..2]
                    .iter()
                    .all(|f| category(f) == Category::Property),
                "{families:?}"
            );
            assert!(
                families[2..]
                    .iter()
                    .all(|f| category(f) != Category::Property),
                "{families:?}"
            );
            assert_ne!(families[0], families[1]);
            assert_ne!(families[2], families[3]);
            assert!(
                !families.contains(&"tension"),
                "an empty family is never picked"
            );
            for record in records {
                assert_eq!(
                    record.qtype.as_deref(),
                    Some(record.question_family.as_str())
                );
                assert_eq!(record.video_id.as_deref(), Some("0"));
            }
        }
    }

    #[test]
    fn counts_per_video_follow_the_config_and_top_up_without_repeats() {
        // (families, fact wanted, dynamics wanted, facts expected, dynamics expected)
        type Families<'a> = &'a [(&'a str, usize)];
        let cases: [(Families<'_>, usize, usize, usize, usize); 5] = [
            (&ROPE_FAMILIES, 1, 1, 1, 1),
            (&ROPE_FAMILIES, 3, 3, 3, 3),
            (&[("mass", 4), ("rope_goaldriven", 1)], 3, 3, 3, 1),
            (&[("mass", 2), ("rope_counterfactual", 9)], 5, 4, 2, 4),
            (&[("color", 12)], 0, 2, 0, 0),
        ];
        for (families, fact_per_video, dynamics_per_video, facts, dynamics) in cases {
            let config = SamplerConfig {
                fact_per_video,
                dynamics_per_video,
            };
            for seed in 0..30 {
                let records =
                    sample_and_split(Scenario::Rope, &[video("0", families)], &config, seed).test;
                let fact_count = records
                    .iter()
                    .filter(|r| Family(r.question_family.clone()).category() == Category::Property)
                    .count();
                assert_eq!(
                    (fact_count, records.len() - fact_count),
                    (facts, dynamics),
                    "{families:?}"
                );
                let mut questions: Vec<&str> =
                    records.iter().map(|r| r.question.as_str()).collect();
                questions.sort_unstable();
                questions.dedup();
                assert_eq!(
                    questions.len(),
                    records.len(),
                    "a question repeats: {records:?}"
                );
            }
        }
    }

    #[test]
    fn sampling_is_deterministic_and_per_video_independent() {
        let per_video: Vec<PerVideoQuestions> = (0..6)
            .map(|id| video(&id.to_string(), &ROPE_FAMILIES))
            .collect();
        let config = SamplerConfig::default();
        assert_eq!(
            sample_and_split(Scenario::Rope, &per_video, &config, 11),
            sample_and_split(Scenario::Rope, &per_video, &config, 11)
        );
        assert_ne!(
            sample_and_split(Scenario::Rope, &per_video, &config, 11),
            sample_and_split(Scenario::Rope, &per_video, &config, 12)
        );
        // Dropping video 5 changes no other video's questions (only splits and ids move).
        let questions = |splits: &SampledSplits, video_id: &str| -> Vec<String> {
            splits
                .all()
                .filter(|r| r.video_id.as_deref() == Some(video_id))
                .map(|r| r.question.clone())
                .collect()
        };
        let full = sample_and_split(Scenario::Rope, &per_video, &config, 11);
        let fewer = sample_and_split(Scenario::Rope, &per_video[..5], &config, 11);
        for video_id in ["0", "1", "2", "3", "4"] {
            assert_eq!(questions(&full, video_id), questions(&fewer, video_id));
        }
    }

    #[test]
    fn legacy_no_answer_has_no_positive() {
        let mut per_video = video("0", &[("mass", 1), ("rope_goaldriven", 1)]);
        if let Some(records) = per_video.question_dict.get_mut("mass") {
            records[0].answer = "No answer.".into();
        }
        let records =
            sample_and_split(Scenario::Rope, &[per_video], &SamplerConfig::default(), 0).test;
        let mass = records
            .iter()
            .find(|r| r.question_family == "mass")
            .unwrap();
        assert!(mass.positive.is_empty());
        let goal = records
            .iter()
            .find(|r| r.question_family == "rope_goaldriven")
            .unwrap();
        assert_eq!(goal.positive, ["yes"]);
    }
}
