//! The content-addressed program cache (`docs/architecture.md`, program cache): `DIR/v1/<2
//! hex>/<key>.json`.
//!
//! A key is the blake3 hash of the canonical JSON of everything that determines a program (for
//! an LLM: model id, sampling parameters, rendered prompt, template hash, api_spec version; for
//! the builtin writer: writer version, question and option text). Entries are immutable and
//! written atomically; the first writer wins. The cache doubles as the replay log: `--offline`
//! reads programs from it and never calls a program source.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use serde_json::Value;

use crate::util::{FsError, content_hash_json, write_atomic};

/// Cache layout version (the folder under the cache root).
const LAYOUT: &str = "v1";

/// A cache failure, naming the file.
#[derive(Debug, thiserror::Error)]
pub enum CacheError {
    /// Reading an entry or listing the cache failed.
    #[error("cannot read the program cache at `{path}`")]
    Read {
        /// The file or folder.
        path: PathBuf,
        /// The cause.
        #[source]
        source: std::io::Error,
    },
    /// An entry is not valid JSON or lacks fields.
    #[error("cache entry `{path}` is corrupt")]
    Corrupt {
        /// The entry file.
        path: PathBuf,
        /// The cause.
        #[source]
        source: serde_json::Error,
    },
    /// An entry's stored key does not match its file name (tampering or a copy gone wrong).
    #[error("cache entry `{path}` holds key `{found}`, not the key of its file name")]
    KeyMismatch {
        /// The entry file.
        path: PathBuf,
        /// The key inside the entry.
        found: String,
    },
    /// Writing an entry failed.
    #[error(transparent)]
    Write(#[from] FsError),
}

/// One cached program.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CacheEntry {
    /// The content hash of `key_material`.
    pub key: String,
    /// What the key was computed from.
    pub key_material: Value,
    /// The program text.
    pub program: String,
    /// The raw LLM completion the program was extracted from (none for the builtin writer).
    pub raw_completion: Option<String>,
    /// The source that produced it (`builtin`, `openai`, ...).
    pub source: String,
    /// The unit that first used it (for `cache ls`).
    pub first_unit: String,
    /// Source-specific facts about how it was made (for an LLM: token usage, finish reason,
    /// the model the server reported).
    #[serde(default, skip_serializing_if = "Value::is_null")]
    pub details: Value,
}

/// The key of `key_material`.
pub fn cache_key(key_material: &Value) -> String {
    content_hash_json(key_material)
}

/// A program cache rooted at a folder.
#[derive(Debug, Clone)]
pub struct ProgramCache {
    root: PathBuf,
}

impl ProgramCache {
    /// A cache at `root` (created on first write).
    pub fn new(root: &Path) -> ProgramCache {
        ProgramCache {
            root: root.to_path_buf(),
        }
    }

    /// The cache folder.
    pub fn root(&self) -> &Path {
        &self.root
    }

    fn entry_path(&self, key: &str) -> PathBuf {
        let shard = key.get(..2).unwrap_or("xx");
        self.root
            .join(LAYOUT)
            .join(shard)
            .join(format!("{key}.json"))
    }

    /// The entry for `key`, if cached.
    pub fn get(&self, key: &str) -> Result<Option<CacheEntry>, CacheError> {
        let path = self.entry_path(key);
        if !path.is_file() {
            return Ok(None);
        }
        read_entry(&path).map(Some)
    }

    /// Stores an entry unless its key is already cached; returns the entry now in the cache.
    pub fn put(&self, entry: CacheEntry) -> Result<CacheEntry, CacheError> {
        if let Some(existing) = self.get(&entry.key)? {
            return Ok(existing);
        }
        let path = self.entry_path(&entry.key);
        let mut bytes = serde_json::to_vec_pretty(&entry).unwrap_or_default();
        bytes.push(b'\n');
        write_atomic(&path, &bytes)?;
        Ok(entry)
    }

    /// All entries, sorted by key.
    pub fn list(&self) -> Result<Vec<CacheEntry>, CacheError> {
        let layout = self.root.join(LAYOUT);
        if !layout.is_dir() {
            return Ok(Vec::new());
        }
        let mut paths = Vec::new();
        for shard in read_dir(&layout)? {
            if shard.is_dir() {
                paths.extend(
                    read_dir(&shard)?
                        .into_iter()
                        .filter(|p| p.extension().is_some_and(|e| e == "json")),
                );
            }
        }
        let mut entries = paths
            .iter()
            .map(|p| read_entry(p))
            .collect::<Result<Vec<_>, _>>()?;
        entries.sort_by(|a, b| a.key.cmp(&b.key));
        Ok(entries)
    }
}

fn read_dir(dir: &Path) -> Result<Vec<PathBuf>, CacheError> {
    let error = |source| CacheError::Read {
        path: dir.to_path_buf(),
        source,
    };
    #[expect(clippy::disallowed_methods, reason = "the error names the path itself")]
    let entries = std::fs::read_dir(dir).map_err(error)?;
    let mut paths = Vec::new();
    for entry in entries {
        paths.push(
            entry
                .map_err(|source| CacheError::Read {
                    path: dir.to_path_buf(),
                    source,
                })?
                .path(),
        );
    }
    paths.sort();
    Ok(paths)
}

fn read_entry(path: &Path) -> Result<CacheEntry, CacheError> {
    #[expect(clippy::disallowed_methods, reason = "the error names the path itself")]
    let bytes = std::fs::read(path).map_err(|source| CacheError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    let entry: CacheEntry =
        serde_json::from_slice(&bytes).map_err(|source| CacheError::Corrupt {
            path: path.to_path_buf(),
            source,
        })?;
    let expected = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    if entry.key != expected || cache_key(&entry.key_material) != entry.key {
        return Err(CacheError::KeyMismatch {
            path: path.to_path_buf(),
            found: entry.key,
        });
    }
    Ok(entry)
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn entry(material: Value, program: &str) -> CacheEntry {
        CacheEntry {
            key: cache_key(&material),
            key_material: material,
            program: program.to_string(),
            raw_completion: None,
            source: "builtin".to_string(),
            first_unit: "00001".to_string(),
            details: Value::Null,
        }
    }

    #[test]
    fn entries_are_immutable_and_listed_by_key() {
        let dir = tempfile::tempdir().unwrap();
        let cache = ProgramCache::new(dir.path());
        let first = entry(json!({"question": "a"}), "answer = 1");
        assert_eq!(cache.get(&first.key).unwrap(), None);
        cache.put(first.clone()).unwrap();
        let replaced = entry(json!({"question": "a"}), "answer = 2");
        assert_eq!(
            cache.put(replaced).unwrap().program,
            "answer = 1",
            "first writer wins"
        );
        cache
            .put(entry(json!({"question": "b"}), "answer = 3"))
            .unwrap();
        let listed = cache.list().unwrap();
        assert_eq!(listed.len(), 2);
        assert!(listed[0].key < listed[1].key);
        assert_eq!(
            cache.get(&first.key).unwrap().unwrap().program,
            "answer = 1"
        );
    }

    #[test]
    fn corrupt_or_tampered_entries_are_reported() {
        let dir = tempfile::tempdir().unwrap();
        let cache = ProgramCache::new(dir.path());
        let stored = entry(json!({"question": "a"}), "answer = 1");
        cache.put(stored.clone()).unwrap();
        let path = cache.entry_path(&stored.key);
        let mut tampered = stored.clone();
        tampered.key_material = json!({"question": "other"});
        fs_err::write(&path, serde_json::to_vec(&tampered).unwrap()).unwrap();
        assert!(matches!(
            cache.get(&stored.key),
            Err(CacheError::KeyMismatch { .. })
        ));
        fs_err::write(&path, b"{\"key\": ").unwrap();
        let error = cache.get(&stored.key).unwrap_err();
        assert!(error.to_string().contains("is corrupt"), "{error}");
    }
}
