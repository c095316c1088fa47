//! `bench physics --reference-cache DIR`: the reference runs of `bench physics`, stored so a
//! later sweep over the same cases compares with them instead of running them again (the cloth
//! reference is about 94% of an invocation's run time at fifteen runs a point).
//!
//! An entry is keyed by the executable's digest (the simulator's code), the scenario, the
//! case's name and inputs (its video's annotation) and the reference point, so a rebuilt binary
//! or a changed video never reuses a stale reference. Its quantities are stored as their f64
//! bits: a cached reference is the run's, bit for bit. An unreadable entry is reported and run
//! again (by the caller); an entry is written whole or not at all.
//!
//! Input: a case and the reference point. Output: the reference's quantities, work and the run
//! time it took when it ran.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::error::{AppError, Classify as _, user_error};
use crate::physics::bench::{BenchCase, CaseOutput};
use crate::util::content_hash_json;

/// The folder of stored reference runs of one scenario, for this executable.
#[derive(Debug)]
pub(crate) struct ReferenceCache {
    folder: PathBuf,
    scenario: String,
    /// The digest of the running executable: its simulator's code.
    executable: String,
}

/// A reference run as stored.
#[derive(Debug, Serialize, Deserialize)]
struct StoredReference {
    scenario: String,
    case: String,
    reference_point: Vec<f64>,
    /// The wall time the run took, ms.
    run_time_ms: f64,
    work: Option<u64>,
    /// Per error measure, its quantities' f64 bits.
    quantity_bits: Vec<Vec<u64>>,
}

/// A reference the cache gave back.
#[derive(Debug)]
pub(crate) struct CachedReference {
    pub(crate) output: CaseOutput,
    /// The wall time it took when it ran, ms.
    pub(crate) run_time_ms: f64,
}

impl ReferenceCache {
    /// The cache in `folder` (created if missing) for `scenario`'s references run by this
    /// executable.
    pub(crate) fn open(folder: &Path, scenario: &str) -> Result<ReferenceCache, AppError> {
        fs_err::create_dir_all(folder)
            .map_err(|error| user_error(format!("bench physics: --reference-cache: {error}")))?;
        let executable = std::env::current_exe().map_err(|error| {
            user_error(format!("bench physics: the running executable: {error}"))
        })?;
        let bytes = fs_err::read(&executable).user()?;
        Ok(ReferenceCache {
            folder: folder.to_path_buf(),
            scenario: scenario.to_string(),
            executable: crate::util::content_hash(&bytes),
        })
    }

    /// The file of `case`'s reference run at `point`.
    fn entry(&self, case: &BenchCase, point: &[f64]) -> PathBuf {
        let key = content_hash_json(&serde_json::json!({
            "executable": self.executable,
            "scenario": self.scenario,
            "case": case.name,
            "inputs": case.inputs,
            "reference_point": point.iter().map(|value| value.to_bits()).collect::<Vec<_>>(),
        }));
        self.folder.join(format!("{key}.json"))
    }

    /// `case`'s stored reference run at `point`: `Ok(None)` when none is stored, `Err` with
    /// the reason when the stored one is unusable (the caller runs it again, and says so).
    pub(crate) fn load(
        &self,
        case: &BenchCase,
        point: &[f64],
    ) -> Result<Option<CachedReference>, String> {
        let path = self.entry(case, point);
        let Ok(text) = fs_err::read_to_string(&path) else {
            return Ok(None);
        };
        let stored = match serde_json::from_str::<StoredReference>(&text) {
            Ok(stored) if stored.case == case.name && stored.scenario == self.scenario => stored,
            Ok(_) => {
                return Err(format!(
                    "{}: a stored reference of another case",
                    path.display()
                ));
            }
            Err(error) => {
                return Err(format!(
                    "{}: unreadable stored reference ({error})",
                    path.display()
                ));
            }
        };
        let quantities = stored
            .quantity_bits
            .iter()
            .map(|bits| bits.iter().copied().map(f64::from_bits).collect())
            .collect();
        Ok(Some(CachedReference {
            output: CaseOutput {
                quantities,
                work: stored.work,
            },
            run_time_ms: stored.run_time_ms,
        }))
    }

    /// Stores `case`'s reference run at `point`, which took `run_time_ms`.
    pub(crate) fn store(
        &self,
        case: &BenchCase,
        point: &[f64],
        output: &CaseOutput,
        run_time_ms: f64,
    ) -> Result<(), AppError> {
        let stored = StoredReference {
            scenario: self.scenario.clone(),
            case: case.name.clone(),
            reference_point: point.to_vec(),
            run_time_ms,
            work: output.work,
            quantity_bits: output
                .quantities
                .iter()
                .map(|values| values.iter().map(|value| value.to_bits()).collect())
                .collect(),
        };
        let text = serde_json::to_string(&stored)
            .map_err(|error| user_error(format!("bench physics: a reference run: {error}")))?;
        crate::util::write_atomic(&self.entry(case, point), text.as_bytes()).user()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn case(name: &str, inputs: &str) -> BenchCase {
        BenchCase {
            name: name.to_string(),
            exact: None,
            inputs: inputs.to_string(),
            label_names: Vec::new(),
            run: Box::new(|_| Err(crate::physics::bench::BenchError::new("case", "not run"))),
        }
    }

    #[test]
    fn a_stored_reference_comes_back_bit_for_bit_for_its_case_inputs_and_point_only() {
        let folder = tempfile::tempdir().expect("a temporary folder");
        let cache = ReferenceCache::open(folder.path(), "cloth").expect("the cache opens");
        let first = case("cloth_collision/0 left half", "digest-a");
        let output = CaseOutput {
            // A share with no short decimal and a negative zero: JSON numbers could lose them.
            quantities: vec![vec![1.0 / 3.0, -0.0], vec![0.1 + 0.2]],
            work: Some(42),
        };
        cache
            .store(&first, &[16.0, 20.0], &output, 1234.5)
            .expect("the reference is stored");
        let back = cache
            .load(&first, &[16.0, 20.0])
            .expect("readable")
            .expect("it comes back");
        let bits = |output: &CaseOutput| -> Vec<Vec<u64>> {
            output
                .quantities
                .iter()
                .map(|values| values.iter().map(|value| value.to_bits()).collect())
                .collect()
        };
        assert_eq!(bits(&back.output), bits(&output));
        assert_eq!(back.output.work, Some(42));
        assert_eq!(back.run_time_ms.to_bits(), 1234.5_f64.to_bits());
        // Another point, other inputs under the same name, another case: not stored.
        assert!(matches!(cache.load(&first, &[16.0, 21.0]), Ok(None)));
        for other in [
            case("cloth_collision/0 left half", "digest-b"),
            case("cloth_collision/0 right half", "digest-a"),
        ] {
            assert!(matches!(cache.load(&other, &[16.0, 20.0]), Ok(None)));
        }
        // Another scenario's cache in the same folder does not see it.
        let other = ReferenceCache::open(folder.path(), "ball").expect("the cache opens");
        assert!(matches!(other.load(&first, &[16.0, 20.0]), Ok(None)));
    }

    #[test]
    fn an_unreadable_entry_is_a_miss_and_is_overwritten() {
        let folder = tempfile::tempdir().expect("a temporary folder");
        let cache = ReferenceCache::open(folder.path(), "cloth").expect("the cache opens");
        let first = case("cloth_collision/0 left half", "digest-a");
        fs_err::write(cache.entry(&first, &[1.0]), "{ truncated").expect("written");
        let reason = cache.load(&first, &[1.0]).expect_err("unusable");
        assert!(reason.contains("unreadable stored reference"), "{reason}");
        let output = CaseOutput {
            quantities: vec![vec![0.5]],
            work: None,
        };
        cache
            .store(&first, &[1.0], &output, 2.0)
            .expect("the reference is stored");
        let back = cache
            .load(&first, &[1.0])
            .expect("readable")
            .expect("it comes back");
        assert_eq!(back.output.quantities, output.quantities);
    }
}
