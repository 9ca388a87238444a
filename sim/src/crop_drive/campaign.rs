//! The paper's test plan (Guyonneau 2022, Algorithm 5): every line-finding
//! variant on every crop, several runs each (another seed each: another
//! crop of the same kind, other noise), and its Tables 2-6: the share of
//! successful runs, the mean squared offset from the middle of the rows,
//! and the detector's time and points per tick over the first 500 ticks.
//!
//! Runs are shared out over every core; the rows come in the plan's order.
//! The same seeds serve every variant, so the variants drive the same crops.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use fieldguide::perception::rows::ruby::Variant;
use serde_json::json;

use super::{drive, plot, CropEnd, CropOutcome, CropRun};
use crate::error::SimError;

/// The variants of the plan, in the paper's order (Pearl is not offered:
/// RUBY-VARIANT).
pub const VARIANTS: [Variant; 5] = [
    Variant::Ruby,
    Variant::Rg,
    Variant::Rgop,
    Variant::Rgoppn,
    Variant::Rgoppni,
];

/// The paper's crops.
pub const CROPS: [u8; 4] = [1, 2, 3, 4];

/// The paper's runs per variant and crop.
pub const PAPER_RUNS: u32 = 5;

/// A variant's name as the paper writes it.
#[must_use]
pub const fn variant_name(v: Variant) -> &'static str {
    match v {
        Variant::Ruby => "Ruby",
        Variant::Rg => "RG",
        Variant::Rgop => "RGOP",
        Variant::Rgoppn => "RGOPPN",
        Variant::Rgoppni => "RGOPPNI",
    }
}

/// The seed of run `run` (from 1) on crop `crop`: the same for every variant.
#[must_use]
pub const fn seed(crop: u8, run: u32) -> u64 {
    1000 * crop as u64 + run as u64
}

/// One run of the plan.
#[derive(Debug, Clone, PartialEq)]
pub struct RunRow {
    /// The run's name.
    pub name: String,
    /// The line finder.
    pub variant: Variant,
    /// The crop, 1-4.
    pub crop: u8,
    /// The run, from 1.
    pub run: u32,
    /// Its seed.
    pub seed: u64,
    /// Whether it reached the end of the last inter-row without running over
    /// a crop plant.
    pub success: bool,
    /// Why it ended.
    pub end: CropEnd,
    /// Crop plants run over.
    pub crushed: usize,
    /// Mean squared offset from the middle of the rows, mm².
    pub mse_mm2: Option<f64>,
    /// Largest |offset|, m.
    pub max_offset_m: Option<f64>,
    /// The row distance measured, m, and the true one.
    pub row_distance_m: (Option<f64>, f64),
    /// Mean navigator time per detector tick over the first 500, µs.
    pub detector_us: Option<f64>,
    /// Mean points per tick over the first 500.
    pub points: Option<f64>,
    /// Time driven, s.
    pub duration_s: f64,
}

impl RunRow {
    /// The row of run `k` of `run` on crop `crop`.
    #[must_use]
    pub fn of(run: &CropRun, crop: u8, k: u32, outcome: &CropOutcome) -> Self {
        let (detector_us, points) = outcome.timing();
        Self {
            name: run.name.clone(),
            variant: run.variant,
            crop,
            run: k,
            seed: run.seed,
            success: outcome.success(),
            end: outcome.end.clone(),
            crushed: outcome.crushed,
            mse_mm2: outcome.mse_mm2(),
            max_offset_m: outcome.max_offset_m(),
            row_distance_m: (outcome.row_distance_m, run.crop.spacing),
            detector_us,
            points,
            duration_s: outcome.ticks.last().map_or(0.0, |t| t.t_s),
        }
    }
}

/// The plan's result: one row per run, and one successful and one failed
/// drive, when there are, for the figures.
#[derive(Debug, Clone)]
pub struct Campaign {
    /// The rows, variant by variant, crop by crop, run by run.
    pub rows: Vec<RunRow>,
    /// The first successful run and its drive.
    pub success: Option<(CropRun, CropOutcome)>,
    /// The first failed run and its drive.
    pub failure: Option<(CropRun, CropOutcome)>,
}

/// Runs `runs` runs of every variant on every crop, `progress` called with
/// the count done and the total after each run (in the plan's order).
#[must_use]
pub fn campaign(
    runs: u32,
    variants: &[Variant],
    mut progress: impl FnMut(usize, usize),
) -> Campaign {
    let mut plan = Vec::new();
    for &variant in variants {
        for crop in CROPS {
            for k in 1..=runs {
                if let Some(run) = CropRun::paper(crop, variant, seed(crop, k)) {
                    plan.push((run, crop, k));
                }
            }
        }
    }
    let total = plan.len();
    let (mut success, mut failure) = (None, None);
    let rows = crate::parallel::map_in_order(
        &plan,
        |(run, crop, k)| {
            let outcome = drive(run);
            (RunRow::of(run, *crop, *k, &outcome), outcome)
        },
        |i, _| progress(i + 1, total),
    );
    let mut out = Vec::with_capacity(rows.len());
    for ((row, outcome), (run, _, _)) in rows.into_iter().zip(plan) {
        let keep = if row.success {
            &mut success
        } else {
            &mut failure
        };
        if keep.is_none() {
            *keep = Some((run, outcome));
        }
        out.push(row);
    }
    Campaign {
        rows: out,
        success,
        failure,
    }
}

/// One of the paper's tables: a figure per variant and crop, and the mean
/// over the crops.
struct Table {
    title: &'static str,
    unit: &'static str,
    key: &'static str,
    figure: fn(&[&RunRow]) -> Option<f64>,
    decimals: usize,
}

fn mean(values: impl Iterator<Item = f64>) -> Option<f64> {
    let (s, n) = values.fold((0.0, 0_u32), |(s, n), v| (s + v, n + 1));
    (n > 0).then(|| s / f64::from(n))
}

const TABLES: [Table; 5] = [
    Table {
        title: "Table 2: ratio of successful runs",
        unit: "",
        key: "success_ratio",
        figure: |rows| mean(rows.iter().map(|r| f64::from(u8::from(r.success)))),
        decimals: 2,
    },
    Table {
        title: "Table 3: mean squared offset from the middle of the rows, row changes excluded",
        unit: "mm²",
        key: "mse_mm2",
        figure: |rows| mean(rows.iter().filter_map(|r| r.mse_mm2)),
        decimals: 0,
    },
    Table {
        title: "Table 4: detector and controller time per tick, first 500 ticks",
        unit: "µs",
        key: "time_per_tick_us",
        figure: |rows| mean(rows.iter().filter_map(|r| r.detector_us)),
        decimals: 1,
    },
    Table {
        title: "Table 5: points per tick, first 500 ticks",
        unit: "",
        key: "points_per_tick",
        figure: |rows| mean(rows.iter().filter_map(|r| r.points)),
        decimals: 1,
    },
    Table {
        title: "Table 6: time per 100 points, first 500 ticks",
        unit: "µs",
        key: "time_per_100_points_us",
        figure: |rows| {
            mean(
                rows.iter()
                    .filter_map(|r| r.detector_us.zip(r.points))
                    .filter(|(_, p)| *p > 0.0)
                    .map(|(t, p)| 100.0 * t / p),
            )
        },
        decimals: 1,
    },
];

/// The figure of `table` for `variant` on each crop, and their mean.
fn table_row(rows: &[RunRow], table: &Table, variant: Variant) -> (Vec<Option<f64>>, Option<f64>) {
    let per_crop: Vec<Option<f64>> = CROPS
        .iter()
        .map(|&c| {
            let of: Vec<&RunRow> = rows
                .iter()
                .filter(|r| r.variant == variant && r.crop == c)
                .collect();
            (table.figure)(&of)
        })
        .collect();
    let overall = mean(per_crop.iter().flatten().copied());
    (per_crop, overall)
}

/// Tables 2-6 in Markdown, laid out as the paper's.
#[must_use]
pub fn tables_md(rows: &[RunRow]) -> String {
    let mut md = String::from("# Guyonneau 2022, Algorithm 5 in the simulator\n");
    let runs = rows.iter().map(|r| r.run).max().unwrap_or(0);
    let _ = writeln!(
        md,
        "\n{} runs per variant and crop; `fieldguide campaign guyonneau2022 --runs {runs}`.",
        runs
    );
    for table in &TABLES {
        let unit = if table.unit.is_empty() {
            String::new()
        } else {
            format!(" ({})", table.unit)
        };
        let _ = writeln!(md, "\n## {}{unit}\n", table.title);
        md.push_str("| | Crop 1 | Crop 2 | Crop 3 | Crop 4 | Mean |\n| --- | --- | --- | --- | --- | --- |\n");
        for v in VARIANTS {
            if !rows.iter().any(|r| r.variant == v) {
                continue;
            }
            let (per_crop, overall) = table_row(rows, table, v);
            let cell =
                |x: Option<f64>| x.map_or("—".to_owned(), |x| format!("{x:.*}", table.decimals));
            let cells: Vec<String> = per_crop.into_iter().map(cell).collect();
            let _ = writeln!(
                md,
                "| {} | {} | {} |",
                variant_name(v),
                cells.join(" | "),
                cell(overall)
            );
        }
    }
    md
}

/// Tables 2-6 as JSON: `{table: {variant: {"crop1".."crop4", "mean"}}}`.
#[must_use]
pub fn tables_json(rows: &[RunRow]) -> serde_json::Value {
    let mut all = serde_json::Map::new();
    for table in &TABLES {
        let mut by_variant = serde_json::Map::new();
        for v in VARIANTS {
            if !rows.iter().any(|r| r.variant == v) {
                continue;
            }
            let (per_crop, overall) = table_row(rows, table, v);
            let mut cells = serde_json::Map::new();
            for (c, x) in CROPS.iter().zip(per_crop) {
                cells.insert(format!("crop{c}"), json!(x));
            }
            cells.insert("mean".to_owned(), json!(overall));
            by_variant.insert(variant_name(v).to_owned(), cells.into());
        }
        all.insert(table.key.to_owned(), by_variant.into());
    }
    all.into()
}

/// One line per run.
#[must_use]
pub fn runs_csv(rows: &[RunRow]) -> String {
    let mut csv = String::from(
        "variant,crop,run,seed,success,end,crushed,mse_mm2,max_offset_m,row_distance_m,true_row_distance_m,time_per_tick_us,points_per_tick,duration_s\n",
    );
    let opt = |x: Option<f64>| x.map_or(String::new(), |x| format!("{x:.6}"));
    for r in rows {
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{:.3}",
            variant_name(r.variant),
            r.crop,
            r.run,
            r.seed,
            r.success,
            end_label(&r.end),
            r.crushed,
            opt(r.mse_mm2),
            opt(r.max_offset_m),
            opt(r.row_distance_m.0),
            r.row_distance_m.1,
            opt(r.detector_us),
            opt(r.points),
            r.duration_s
        );
    }
    csv
}

/// A one-word end for tables.
#[must_use]
pub fn end_label(end: &CropEnd) -> String {
    match end {
        CropEnd::Done => "done".to_owned(),
        CropEnd::Timeout => "timeout".to_owned(),
        CropEnd::Stopped(why) => format!("stopped: {why}").replace(',', ";"),
        CropEnd::Aborted(why) => format!("aborted: {why}").replace(',', ";"),
    }
}

/// Writes `runs.csv`, `tables.json`, `tables.md` and the figures of
/// `campaign` into `out/guyonneau2022/`; returns the folder.
pub fn write(out: &Path, campaign: &Campaign) -> Result<PathBuf, SimError> {
    let dir = out.join("guyonneau2022");
    let mut files = vec![
        ("runs.csv", runs_csv(&campaign.rows)),
        (
            "tables.json",
            serde_json::to_string_pretty(&tables_json(&campaign.rows)).unwrap_or_default(),
        ),
        ("tables.md", tables_md(&campaign.rows)),
    ];
    if let Some((run, outcome)) = &campaign.success {
        files.push(("success.svg", plot::trajectory_svg(run, outcome)));
    }
    if let Some((run, outcome)) = &campaign.failure {
        files.push(("failure.svg", plot::trajectory_svg(run, outcome)));
    }
    crate::output::write_files(&dir, &files)?;
    Ok(dir)
}
