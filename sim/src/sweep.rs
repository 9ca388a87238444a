//! Seed sweeps: one scenario run once per seed of an inclusive range, each
//! seed replacing the scenario's own (the world's generation, the path's
//! recording noise and the sensors' noise all follow from it, see
//! [`runner::prepare_with_seed`]), and one row of metrics per seed.
//!
//! The `fieldguide sweep <scenario> --seeds FIRST..=LAST` command prints the
//! rows, a final "worst" row (the largest value of each metric over the
//! seeds, and the seed it came from), and writes them to
//! `OUT/<scenario>/sweep.csv` ([`sweep_csv`], one line per seed). It keeps
//! the trace and plots of the worst seed of each column ([`keep_worst`]):
//! each such seed is run again (a run is a pure function of its seed) and
//! written to `OUT/<scenario>/worst/seed-<N>/`, and
//! `OUT/<scenario>/worst/worst.csv` says which column each seed is the worst
//! of. A claim about a scenario is a claim about its worst seed, not about
//! one lucky run.
//!
//! A vine-row run (`[vineyard]`, `vineyard-*`) sweeps the same way through
//! [`vine_sweep`]: its rows are [`VineSummary`]s, its columns
//! [`VINE_COLUMNS`] (the figures of `vineyard::summary_json`).

use std::fmt;
use std::ops::RangeInclusive;
use std::path::{Path, PathBuf};
use std::str::FromStr;

use crate::error::SimError;
use crate::metrics::{summarize, ErrorStats, Summary};
use crate::runner;
use crate::scenario::Source;
use crate::vineyard::{drive, Settled, VineEnd, VineOutcome, VineyardRun, WHEELBASE_M};

/// A row of a sweep: one seed's figures.
pub trait Row: Sized + 'static {
    /// The columns after `seed`, in order.
    const COLUMNS: &'static [Column<Self>];
    /// The seed of the run.
    fn seed(&self) -> u64;
    /// Whether the run met its scenario's checks.
    fn success(&self) -> bool;
    /// Why the run stopped early, if it did.
    fn aborted(&self) -> Option<&str>;
}

impl Row for Summary {
    const COLUMNS: &'static [Column<Self>] = &COLUMNS;
    fn seed(&self) -> u64 {
        self.seed
    }
    fn success(&self) -> bool {
        self.success
    }
    fn aborted(&self) -> Option<&str> {
        self.aborted.as_deref()
    }
}

/// A non-empty inclusive range of seeds, written `FIRST..=LAST` (`1..=20`;
/// `7..=7` is the one seed 7).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Seeds {
    first: u64,
    last: u64,
}

impl Seeds {
    /// The seeds `first` to `last`, both included; an error when `last < first`.
    pub fn new(first: u64, last: u64) -> Result<Self, SeedsError> {
        if last < first {
            return Err(SeedsError {
                input: format!("{first}..={last}"),
                reason: "empty range: the last seed is smaller than the first",
            });
        }
        Ok(Self { first, last })
    }

    /// The first seed.
    #[must_use]
    pub const fn first(&self) -> u64 {
        self.first
    }

    /// The last seed (included).
    #[must_use]
    pub const fn last(&self) -> u64 {
        self.last
    }

    /// The seeds in increasing order.
    #[must_use]
    pub const fn iter(&self) -> RangeInclusive<u64> {
        self.first..=self.last
    }
}

impl FromStr for Seeds {
    type Err = SeedsError;

    /// Parses `FIRST..=LAST` (decimal, spaces around the numbers allowed).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let err = |reason| SeedsError {
            input: s.to_owned(),
            reason,
        };
        let (first, last) = s
            .split_once("..=")
            .ok_or_else(|| err("expected FIRST..=LAST, for example 1..=20"))?;
        let number = |t: &str| {
            t.trim()
                .parse::<u64>()
                .map_err(|_| err("the seeds must be whole numbers from 0 to 2^64 - 1"))
        };
        let (first, last) = (number(first)?, number(last)?);
        Self::new(first, last).map_err(|e| err(e.reason))
    }
}

impl fmt::Display for Seeds {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}..={}", self.first, self.last)
    }
}

/// Why a seed range was refused.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SeedsError {
    /// The text given.
    pub input: String,
    /// What is wrong with it.
    pub reason: &'static str,
}

impl fmt::Display for SeedsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "seeds `{}`: {}", self.input, self.reason)
    }
}

impl std::error::Error for SeedsError {}

/// The outcome of a sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct Sweep<R = Summary> {
    /// The scenario's name (the folder the sweep is written to).
    pub scenario: String,
    /// One summary per seed, in increasing seed order.
    pub rows: Vec<R>,
}

/// Runs `source` once per seed of `seeds` (the closed loop of
/// [`runner::run`], summarised by [`summarize`]), the seeds shared out over
/// every core, and calls `each` with every summary in seed order, as soon as
/// it and every earlier seed's are measured (the rows are the same, in the
/// same order, whatever the number of cores). A run the core stops early is a row
/// like any other (its `aborted` and `success` say so); a seed whose world
/// or path cannot be built stops the sweep with [`SimError::AtSeed`].
pub fn sweep(
    source: &Source,
    seeds: Seeds,
    mut each: impl FnMut(&Summary),
) -> Result<Sweep, SimError> {
    let scenario = source.parse()?.name;
    let all: Vec<u64> = seeds.iter().collect();
    // Rows are handed on in seed order up to the first seed that could not
    // be built.
    let mut failed = false;
    let results = crate::parallel::map_in_order(
        &all,
        |&seed| {
            runner::prepare_with_seed(source, seed)
                .map(|(setup, mut rng)| {
                    let run = runner::run(&setup, &mut rng);
                    summarize(&setup, &run)
                })
                .map_err(|source| SimError::AtSeed { seed, source })
        },
        |_, result| match result {
            Ok(summary) if !failed => each(summary),
            _ => failed = true,
        },
    );
    let rows = results.into_iter().collect::<Result<Vec<_>, _>>()?;
    Ok(Sweep { scenario, rows })
}

/// One cell of a sweep row.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Cell {
    /// A distance or error in metres; `None` when the scenario has no such
    /// figure (no plot, no hedge) or the run never reached it (never converged).
    Metres(Option<f64>),
    /// A figure with no better or worse side (the distance driven): it has
    /// no worst.
    Plain(f64),
    /// An angle or angular error in radians, as [`Cell::Metres`].
    Radians(Option<f64>),
    /// A count.
    Count(usize),
    /// A yes/no outcome, `true` being good.
    Flag(bool),
}

/// A column of the sweep table and of `sweep.csv`.
#[derive(Debug, Clone, Copy)]
pub struct Column<R = Summary> {
    /// Its name: the CSV header and the table's heading.
    pub name: &'static str,
    /// Its cell in the row of a summary.
    pub cell: fn(&R) -> Cell,
}

fn mean(e: Option<ErrorStats>) -> Cell {
    Cell::Metres(e.map(|e| e.mean_abs))
}

fn max(e: Option<ErrorStats>) -> Cell {
    Cell::Metres(e.map(|e| e.max_abs))
}

/// The columns after `seed`, in order. Errors are against ground truth
/// (`metrics`): |y| to the reference path over the whole run; in-plot, to the
/// true centre line of the rows followed while O is inside a plot; along the
/// hedge, to the hedge's true offset line from the first tick within
/// `metrics.along_hedge_band_m` of it on.
pub const COLUMNS: [Column; 14] = [
    Column {
        name: "success",
        cell: |s| Cell::Flag(s.success),
    },
    Column {
        name: "reached_end",
        cell: |s| Cell::Flag(s.reached_end),
    },
    Column {
        name: "distance_m",
        cell: |s| Cell::Plain(s.distance_m),
    },
    Column {
        name: "mean_abs_y_m",
        cell: |s| Cell::Metres(Some(s.lateral_error_m.mean_abs)),
    },
    Column {
        name: "max_abs_y_m",
        cell: |s| Cell::Metres(Some(s.lateral_error_m.max_abs)),
    },
    Column {
        name: "converged_after_m",
        cell: |s| Cell::Metres(s.converged_after_m),
    },
    Column {
        name: "in_plot_mean_abs_m",
        cell: |s| mean(s.in_plot_lateral_error_m),
    },
    Column {
        name: "in_plot_max_abs_m",
        cell: |s| max(s.in_plot_lateral_error_m),
    },
    Column {
        name: "hedge_converged_after_m",
        cell: |s| Cell::Metres(s.along_hedge_converged_after_m),
    },
    Column {
        name: "hedge_mean_abs_m",
        cell: |s| mean(s.along_hedge_after_convergence_m),
    },
    Column {
        name: "hedge_max_abs_m",
        cell: |s| max(s.along_hedge_after_convergence_m),
    },
    Column {
        name: "plants_crushed",
        cell: |s| Cell::Count(s.plants_crushed),
    },
    Column {
        name: "mode_switches",
        cell: |s| Cell::Count(s.mode_switches),
    },
    Column {
        name: "steering_saturated_fraction",
        cell: |s| Cell::Metres(Some(s.steering_saturated_fraction)),
    },
];

/// The header line of `sweep.csv`.
#[must_use]
pub fn csv_header<R: Row>() -> String {
    std::iter::once("seed")
        .chain(R::COLUMNS.iter().map(|c| c.name))
        .chain(std::iter::once("aborted"))
        .collect::<Vec<_>>()
        .join(",")
}

/// The CSV line of one summary (no line break): the seed, the [`COLUMNS`]
/// (numbers in their shortest exact form, an empty cell for none, `1`/`0`
/// for flags), and why the run stopped early (empty if it did not).
#[must_use]
pub fn csv_row<R: Row>(s: &R) -> String {
    let aborted = s
        .aborted()
        .map_or_else(String::new, |why| why.replace([',', '\n'], ";"));
    std::iter::once(s.seed().to_string())
        .chain(R::COLUMNS.iter().map(|c| match (c.cell)(s) {
            Cell::Metres(v) | Cell::Radians(v) => v.map_or_else(String::new, |v| v.to_string()),
            Cell::Plain(v) => v.to_string(),
            Cell::Count(n) => n.to_string(),
            Cell::Flag(b) => u8::from(b).to_string(),
        }))
        .chain(std::iter::once(aborted))
        .collect::<Vec<_>>()
        .join(",")
}

/// `sweep.csv`: the header, then one line per row.
#[must_use]
pub fn sweep_csv<R: Row>(rows: &[R]) -> String {
    let mut out = csv_header::<R>();
    out.push('\n');
    for r in rows {
        out.push_str(&csv_row(r));
        out.push('\n');
    }
    out
}

/// The worst cell of a column over the rows, with the seed it came from:
/// the largest figure or count (the first seed on a tie), or the first
/// `false` flag; `None` when no row has a figure in that column or the
/// column has no worse side ([`Cell::Plain`]).
#[must_use]
pub fn worst<R: Row>(rows: &[R], column: &Column<R>) -> Option<(u64, Cell)> {
    let mut found: Option<(u64, Cell)> = None;
    for r in rows {
        let cell = (column.cell)(r);
        let worse = match (found.map(|(_, c)| c), cell) {
            (_, Cell::Metres(None) | Cell::Radians(None) | Cell::Plain(_)) => false,
            (None, _) => true,
            (Some(Cell::Metres(Some(a))), Cell::Metres(Some(b)))
            | (Some(Cell::Radians(Some(a))), Cell::Radians(Some(b))) => b > a,
            (Some(Cell::Count(a)), Cell::Count(b)) => b > a,
            (Some(Cell::Flag(a)), Cell::Flag(b)) => a && !b,
            _ => false,
        };
        if worse {
            found = Some((r.seed(), cell));
        }
    }
    found
}

/// The worst seed of each column that has one to blame, `(column, seed)` in
/// the columns' order: not a [`Cell::Plain`] column, and not a column where
/// every run did well (every flag `true`, every count 0).
#[must_use]
pub fn worst_seeds<R: Row>(rows: &[R]) -> Vec<(&'static str, u64)> {
    R::COLUMNS
        .iter()
        .filter_map(|c| match worst(rows, c)? {
            (_, Cell::Flag(true) | Cell::Count(0)) => None,
            (seed, _) => Some((c.name, seed)),
        })
        .collect()
}

/// The folder of the worst seeds' runs under `OUT/<scenario>/`.
pub const WORST_DIR: &str = "worst";

/// The index of the worst seeds' runs in [`WORST_DIR`].
pub const WORST_FILE: &str = "worst.csv";

/// Runs again the worst seed of each column of `result`, a sweep of
/// `source` ([`worst_seeds`]; each seed once), and writes its trace,
/// summary and plots to `out_root/<scenario>/worst/seed-<N>/`, with
/// `worst.csv` (`column,seed,folder`) beside them; returns that index's
/// lines. A rerun whose summary differs from the sweep's row is an error
/// (the run would not be the one measured).
pub fn keep_worst(
    source: &Source,
    result: &Sweep,
    out_root: &Path,
) -> Result<Vec<(&'static str, u64, PathBuf)>, SimError> {
    let dir = out_root.join(&result.scenario).join(WORST_DIR);
    let _ = std::fs::remove_dir_all(&dir);
    let blamed = worst_seeds(&result.rows);
    let mut seeds: Vec<u64> = blamed.iter().map(|(_, s)| *s).collect();
    seeds.sort_unstable();
    seeds.dedup();
    for &seed in &seeds {
        let (setup, mut rng) = runner::prepare_with_seed(source, seed)
            .map_err(|source| SimError::AtSeed { seed, source })?;
        let run = runner::run(&setup, &mut rng);
        let summary = summarize(&setup, &run);
        if result.rows.iter().find(|r| r.seed == seed) != Some(&summary) {
            return Err(SimError::Write {
                file: dir.clone(),
                source: std::io::Error::other(format!(
                    "seed {seed} run again does not give the sweep's row"
                )),
            });
        }
        crate::output::write_run_to(&dir.join(format!("seed-{seed}")), &setup, &run, &summary)?;
    }
    let index: Vec<(&'static str, u64, PathBuf)> = blamed
        .into_iter()
        .map(|(column, seed)| (column, seed, dir.join(format!("seed-{seed}"))))
        .collect();
    let mut csv = "column,seed,folder\n".to_owned();
    for (column, seed, _) in &index {
        csv.push_str(&format!("{column},{seed},seed-{seed}\n"));
    }
    crate::output::write_files(&dir, &[(WORST_FILE, csv)])?;
    Ok(index)
}

/// The seeds whose run was not a success.
#[must_use]
pub fn failed_seeds<R: Row>(rows: &[R]) -> Vec<u64> {
    rows.iter()
        .filter(|r| !r.success())
        .map(Row::seed)
        .collect()
}

/// One seed's figures of a vine-row run (`vineyard::summary_json`'s):
/// errors against the true row once R is `settle_m` into it.
#[derive(Debug, Clone, PartialEq)]
pub struct VineSummary {
    /// The seed.
    pub seed: u64,
    /// The end of the row reached, no trunk or post touched from the start.
    pub success: bool,
    /// The end of the row reached.
    pub reached_end: bool,
    /// Trunks and posts a wheel met, from the start.
    pub touched: usize,
    /// Those of them past the row's entry.
    pub touched_past_entry: usize,
    /// The lateral (m) and angular (rad) errors after stabilisation.
    pub settled: Option<Settled>,
    /// The largest |rear steering angle|, rad.
    pub rear_max_abs_rad: f64,
    /// How far the front axle was into the row when the robot first
    /// followed the vines, m.
    pub locked_front_at_m: Option<f64>,
    /// Why the run stopped early.
    pub aborted: Option<String>,
}

impl VineSummary {
    /// The figures of `outcome`, the outcome of `run`.
    #[must_use]
    pub fn of(run: &VineyardRun, outcome: &VineOutcome) -> Self {
        Self {
            seed: run.seed,
            success: outcome.success(),
            reached_end: outcome.end == VineEnd::Done,
            touched: outcome.touched,
            touched_past_entry: outcome.touched_in_row,
            settled: outcome.settled(run.settle_m),
            rear_max_abs_rad: outcome.rear_max_abs(),
            locked_front_at_m: outcome
                .ticks
                .iter()
                .find(|t| t.following == Some(true))
                .map(|t| t.truth.position.x() + WHEELBASE_M),
            aborted: match &outcome.end {
                VineEnd::Done => None,
                VineEnd::Aborted(why) => Some(why.clone()),
            },
        }
    }
}

impl Row for VineSummary {
    const COLUMNS: &'static [Column<Self>] = &VINE_COLUMNS;
    fn seed(&self) -> u64 {
        self.seed
    }
    fn success(&self) -> bool {
        self.success
    }
    fn aborted(&self) -> Option<&str> {
        self.aborted.as_deref()
    }
}

/// The columns of a vine-row sweep after `seed`, in order.
pub const VINE_COLUMNS: [Column<VineSummary>; 10] = [
    Column {
        name: "success",
        cell: |s| Cell::Flag(s.success),
    },
    Column {
        name: "reached_end",
        cell: |s| Cell::Flag(s.reached_end),
    },
    Column {
        name: "vines_touched",
        cell: |s| Cell::Count(s.touched),
    },
    Column {
        name: "touched_past_entry",
        cell: |s| Cell::Count(s.touched_past_entry),
    },
    Column {
        name: "mean_abs_y_m",
        cell: |s| Cell::Metres(s.settled.map(|e| e.lateral_mean_abs)),
    },
    Column {
        name: "max_abs_y_m",
        cell: |s| Cell::Metres(s.settled.map(|e| e.lateral_max_abs)),
    },
    Column {
        name: "mean_abs_angular_rad",
        cell: |s| Cell::Radians(s.settled.map(|e| e.angular_mean_abs)),
    },
    Column {
        name: "max_abs_angular_rad",
        cell: |s| Cell::Radians(s.settled.map(|e| e.angular_max_abs)),
    },
    Column {
        name: "max_abs_rear_rad",
        cell: |s| Cell::Radians(Some(s.rear_max_abs_rad)),
    },
    Column {
        name: "locked_front_at_m",
        cell: |s| Cell::Metres(s.locked_front_at_m),
    },
];

/// Runs the vine-row run `run` once per seed of `seeds` (each seed
/// replacing the run's own), the seeds shared out over every core, and
/// calls `each` with every row in seed order as soon as it and every
/// earlier seed's are measured.
pub fn vine_sweep(
    run: &VineyardRun,
    seeds: Seeds,
    mut each: impl FnMut(&VineSummary),
) -> Sweep<VineSummary> {
    let all: Vec<u64> = seeds.iter().collect();
    let rows = crate::parallel::map_in_order(
        &all,
        |&seed| {
            let mut one = run.clone();
            one.seed = seed;
            VineSummary::of(&one, &drive(&one))
        },
        |_, row| each(row),
    );
    Sweep {
        scenario: run.name.clone(),
        rows,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seed_ranges_parse_inclusive_and_refuse_empty_or_malformed_ones() {
        let s: Seeds = "1..=20".parse().unwrap();
        assert_eq!((s.first(), s.last()), (1, 20));
        assert_eq!(s.iter().count(), 20);
        assert_eq!(s.to_string(), "1..=20");
        let one: Seeds = " 7 ..= 7 ".parse().unwrap();
        assert_eq!(one.iter().collect::<Vec<_>>(), vec![7]);
        assert!("0..=18446744073709551615".parse::<Seeds>().is_ok());
        for bad in [
            "5..=4",
            "20",
            "1..20",
            "1..=",
            "..=3",
            "a..=3",
            "-1..=3",
            "1..=18446744073709551616",
            "",
        ] {
            let e = bad.parse::<Seeds>().unwrap_err();
            assert_eq!(e.input, bad);
            assert!(e.to_string().contains(bad), "{e}");
        }
        assert!("5..=4"
            .parse::<Seeds>()
            .unwrap_err()
            .reason
            .contains("empty"));
        assert!(Seeds::new(3, 2).is_err());
    }

    #[test]
    fn the_csv_has_one_column_per_heading_and_the_worst_cell_names_its_seed() {
        let source = Source::builtin("path-tracking").unwrap();
        let (mut setup, mut rng) = runner::prepare_with_seed(&source, 3).unwrap();
        setup.run.duration_s = 3.0;
        let base = summarize(&setup, &runner::run(&setup, &mut rng));
        let row = |seed: u64, max_y: f64, crushed: usize, success: bool| {
            let mut s = base.clone();
            s.seed = seed;
            s.lateral_error_m.max_abs = max_y;
            s.plants_crushed = crushed;
            s.success = success;
            s.in_plot_lateral_error_m = None;
            s.aborted = Some("t = 1, core, said no".to_owned());
            s
        };
        let rows = [
            row(4, 0.2, 0, true),
            row(5, 0.7, 2, false),
            row(6, 0.7, 1, false),
        ];
        let text = sweep_csv(&rows);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 4);
        let width = COLUMNS.len() + 2;
        assert!(
            lines.iter().all(|l| l.split(',').count() == width),
            "{text}"
        );
        assert!(lines[2].starts_with("5,0,"), "{}", lines[2]);
        assert!(lines[2].ends_with("t = 1; core; said no"), "{}", lines[2]);
        let column = |name| COLUMNS.iter().find(|c| c.name == name).unwrap();
        assert_eq!(
            worst(&rows, column("max_abs_y_m")),
            Some((5, Cell::Metres(Some(0.7))))
        );
        assert_eq!(
            worst(&rows, column("plants_crushed")),
            Some((5, Cell::Count(2)))
        );
        assert_eq!(
            worst(&rows, column("success")),
            Some((5, Cell::Flag(false)))
        );
        assert_eq!(worst(&rows, column("in_plot_max_abs_m")), None);
        assert_eq!(worst(&rows, column("distance_m")), None);
        assert_eq!(failed_seeds(&rows), vec![5, 6]);
    }
}
