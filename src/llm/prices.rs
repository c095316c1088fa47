//! `Prices`: what a completion cost, from a table of USD per million input and output tokens.
//!
//! Inputs: the built-in table (`eval/prices.toml`, embedded at compile time) and optionally a
//! file of the same layout from the caller, whose entries replace the built-in ones model by
//! model. Output: [`Prices::cost`] of a model's [`TokenUsage`], or `None` for a model the table
//! does not know (a cost is never guessed). The built-in table is a snapshot the user must check.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::types::TokenUsage;

/// The built-in table.
const BUILTIN_PRICES: &str = include_str!("../../eval/prices.toml");

/// A price table that cannot be used, naming the file.
#[derive(Debug, thiserror::Error)]
pub enum PricesError {
    /// The file cannot be read.
    #[error("cannot read the price table `{path}`")]
    Read {
        /// The file.
        path: PathBuf,
        /// The cause.
        #[source]
        source: std::io::Error,
    },
    /// The file is not valid TOML of the expected layout.
    #[error("price table `{path}` is not valid")]
    Parse {
        /// The file.
        path: PathBuf,
        /// The parser's message, with line and column.
        #[source]
        source: toml::de::Error,
    },
    /// A price is negative or not a number.
    #[error("price table `{path}`: model `{model}` has an invalid price {price}")]
    InvalidPrice {
        /// The file.
        path: PathBuf,
        /// The model of the entry.
        model: String,
        /// The offending value.
        price: f64,
    },
}

/// The price of one model.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelPrice {
    /// USD per one million prompt tokens.
    pub input_per_million: f64,
    /// USD per one million completion tokens.
    pub output_per_million: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PriceFile {
    snapshot: Option<String>,
    #[serde(default)]
    models: BTreeMap<String, ModelPrice>,
}

/// A price table.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Prices {
    /// When the prices were taken, as the file says.
    pub snapshot: Option<String>,
    /// Prices by model id.
    pub models: BTreeMap<String, ModelPrice>,
}

impl Prices {
    /// The built-in table (`eval/prices.toml`).
    pub fn builtin() -> Prices {
        Prices::parse(BUILTIN_PRICES, Path::new("eval/prices.toml"))
            .expect("the embedded eval/prices.toml parses (checked by a unit test)")
    }

    /// A table read from `path`.
    pub fn load(path: &Path) -> Result<Prices, PricesError> {
        #[expect(clippy::disallowed_methods, reason = "the error names the path itself")]
        let text = std::fs::read_to_string(path).map_err(|source| PricesError::Read {
            path: path.to_path_buf(),
            source,
        })?;
        Prices::parse(&text, path)
    }

    /// The built-in table, with the entries of `override_path` (if any) replacing its own.
    pub fn resolve(override_path: Option<&Path>) -> Result<Prices, PricesError> {
        let builtin = Prices::builtin();
        match override_path {
            Some(path) => Ok(builtin.overridden_by(Prices::load(path)?)),
            None => Ok(builtin),
        }
    }

    /// A table parsed from TOML text; `origin` names it in errors.
    pub fn parse(text: &str, origin: &Path) -> Result<Prices, PricesError> {
        let file: PriceFile = toml::from_str(text).map_err(|source| PricesError::Parse {
            path: origin.to_path_buf(),
            source,
        })?;
        for (model, price) in &file.models {
            for value in [price.input_per_million, price.output_per_million] {
                if !value.is_finite() || value < 0.0 {
                    return Err(PricesError::InvalidPrice {
                        path: origin.to_path_buf(),
                        model: model.clone(),
                        price: value,
                    });
                }
            }
        }
        Ok(Prices {
            snapshot: file.snapshot,
            models: file.models,
        })
    }

    /// This table with `other`'s entries replacing (or adding to) its own.
    #[must_use]
    pub fn overridden_by(mut self, other: Prices) -> Prices {
        if other.snapshot.is_some() {
            self.snapshot = other.snapshot;
        }
        self.models.extend(other.models);
        self
    }

    /// The price of `model`: its own entry, else the entry of its base name when `model` is a
    /// dated snapshot of it (`gpt-4o-2024-08-06` → `gpt-4o`, `gpt-4-0613` → `gpt-4`).
    pub fn price(&self, model: &str) -> Option<ModelPrice> {
        if let Some(price) = self.models.get(model) {
            return Some(*price);
        }
        let base = strip_date_suffix(model)?;
        self.models.get(base).copied()
    }

    /// The cost in USD of `usage` on `model`, or `None` when the table has no price for it.
    pub fn cost(&self, model: &str, usage: &TokenUsage) -> Option<f64> {
        let price = self.price(model)?;
        Some(
            (usage.prompt_tokens as f64 * price.input_per_million
                + usage.completion_tokens as f64 * price.output_per_million)
                / 1e6,
        )
    }
}

/// `name` without a trailing `-YYYY-MM-DD` or `-MMDD` snapshot date.
fn strip_date_suffix(name: &str) -> Option<&str> {
    let digits = |text: &str, count: usize| {
        text.len() == count && text.bytes().all(|byte| byte.is_ascii_digit())
    };
    let mut parts: Vec<&str> = name.rsplitn(4, '-').collect();
    parts.reverse();
    // `gpt-4o-2024-08-06` → ["gpt-4o", "2024", "08", "06"]
    if let [base, year, month, day] = parts.as_slice()
        && digits(year, 4)
        && digits(month, 2)
        && digits(day, 2)
    {
        return Some(base);
    }
    let (base, date) = name.rsplit_once('-')?;
    digits(date, 4).then_some(base)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn usage(prompt_tokens: u64, completion_tokens: u64) -> TokenUsage {
        TokenUsage {
            prompt_tokens,
            completion_tokens,
            total_tokens: prompt_tokens + completion_tokens,
        }
    }

    #[test]
    fn builtin_table_parses_and_prices_the_common_models() {
        let prices = Prices::builtin();
        assert!(prices.snapshot.is_some());
        for model in ["gpt-4", "gpt-4-0125-preview", "gpt-4o", "gpt-4o-mini"] {
            assert!(prices.price(model).is_some(), "{model}");
        }
        // gpt-4: $30 in, $60 out per million.
        let cost = prices.cost("gpt-4", &usage(1_000_000, 500_000)).unwrap();
        assert!((cost - 60.0).abs() < 1e-9, "{cost}");
    }

    #[test]
    fn dated_snapshots_fall_back_to_their_base_name() {
        let prices = Prices::builtin();
        // (reported model, priced as)
        let cases = [
            ("gpt-4o-2024-08-06", Some("gpt-4o")),
            ("gpt-4o-2024-05-13", Some("gpt-4o-2024-05-13")),
            ("gpt-4o-mini-2024-07-18", Some("gpt-4o-mini")),
            ("gpt-4-0613", Some("gpt-4")),
            ("gpt-4-0125-preview", Some("gpt-4-0125-preview")),
            ("gpt-4o-audio-preview", None),
            ("llama-3-8b", None),
        ];
        for (model, expected) in cases {
            assert_eq!(
                prices.price(model),
                expected.map(|name| prices.models[name]),
                "{model}"
            );
        }
    }

    #[test]
    fn override_file_replaces_entries_model_by_model() {
        let directory = tempfile::tempdir().unwrap();
        let path = directory.path().join("prices.toml");
        fs_err::write(
            &path,
            "snapshot = \"mine\"\n[models.\"gpt-4o\"]\ninput_per_million = 1.0\noutput_per_million = 2.0\n\
             [models.\"local\"]\ninput_per_million = 0.0\noutput_per_million = 0.0\n",
        )
        .unwrap();
        let prices = Prices::resolve(Some(&path)).unwrap();
        assert_eq!(prices.snapshot.as_deref(), Some("mine"));
        assert_eq!(
            prices.cost("gpt-4o", &usage(1_000_000, 1_000_000)),
            Some(3.0)
        );
        assert_eq!(prices.cost("local", &usage(5, 5)), Some(0.0));
        assert!(prices.price("gpt-4").is_some(), "built-in entries stay");
    }

    #[test]
    fn bad_tables_name_the_file() {
        let origin = Path::new("mine.toml");
        let cases = [
            ("[models.\"m\"]\ninput_per_million = 1.0\n", "is not valid"),
            (
                "[models.\"m\"]\ninput_per_million = -1.0\noutput_per_million = 1.0\n",
                "invalid price",
            ),
            (
                "[models.\"m\"]\ninput_per_milion = 1.0\noutput_per_million = 1.0\n",
                "is not valid",
            ),
        ];
        for (text, expected) in cases {
            let error = Prices::parse(text, origin).unwrap_err();
            assert!(error.to_string().contains("`mine.toml`"), "{error}");
            assert!(error.to_string().contains(expected), "{error}");
        }
        let missing = Prices::load(Path::new("no/such/prices.toml")).unwrap_err();
        assert!(missing.to_string().contains("no/such/prices.toml"));
    }
}
