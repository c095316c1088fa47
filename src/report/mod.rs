//! Reports: the paper's Table-2 layout for one run, the per-family breakdown, the failure
//! taxonomy, and the leaderboard over several runs.
//!
//! Input: [`Scores`](crate::score::Scores) and run metadata. Output: Markdown text, byte-stable
//! for the same inputs (hand-written tables, fixed number formatting, no timestamps).

mod table;

pub use table::{ReportMeta, Table2Row, render_leaderboard, render_run_report, table2_rows};
