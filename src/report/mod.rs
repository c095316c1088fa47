//! Reports: the paper's Table-2 layout for one run, the per-family breakdown, the failure
//! taxonomy, the leaderboard over several runs, the run's plots, and the static viewer site.
//!
//! Input: [`Scores`](crate::score::Scores), the runs' questions and predictions, and run
//! metadata. Output: Markdown text, SVG and the viewer's files, byte-stable for the same inputs
//! (hand-written tables, fixed number formatting, no timestamps).

mod plots;
pub mod site;
mod table;

pub use plots::{FamilyWork, Plot, PlotError, bar_label, family_work, run_plots};
pub use table::{ReportMeta, Table2Row, render_leaderboard, render_run_report, table2_rows};
