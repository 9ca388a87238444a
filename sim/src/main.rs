//! The `fieldguide` program: runs simulator scenarios and writes their traces,
//! summaries and plots.
//!
//! - `fieldguide` (no command) runs every built-in scenario and prints a
//!   summary table, its columns explained and each failure's reason;
//! - `fieldguide list` lists the built-in scenarios;
//! - `fieldguide run <name or file.toml> [--out DIR]` runs one scenario;
//! - `fieldguide sweep <name or file.toml> --seeds FIRST..=LAST [--out DIR]`
//!   runs one scenario once per seed from FIRST to LAST, both included
//!   (`--seeds 1..=20`: twenty runs; `--seeds 7..=7`: seed 7 alone), each
//!   seed replacing the file's `seed` (another field, other noise).
//!
//! Each run writes `DIR/<scenario>/{trace.csv, summary.json, trajectory.svg,
//! lateral_error.svg}` (`DIR` defaults to `out`). A sweep prints one row of
//! metrics per seed as it goes, then a "worst" row (the largest value of
//! each metric over the seeds, with the seed it came from, on the line
//! below) and the seeds whose run failed, and writes the rows to
//! `DIR/<scenario>/sweep.csv`; it writes no per-seed trace or plot. A
//! vine-row run's sweep has the vine-row figures for columns.
//!
//! A crop drive of Guyonneau 2022 (`[crop_drive]`, `guyonneau-crop*`), a
//! guided mission of Emmi 2024 (`[guiding]`, `welaser-*`) and a vine-row run
//! of Iberraken 2022 (`[vineyard]`, `vineyard-*`) write their own files and
//! print their own table (`sim/scenarios/README.md`);
//! `fieldguide campaign guyonneau2022 [--runs N]` runs that paper's test
//! plan.
//!
//! `fieldguide evidence` writes `<out>/evidence/{index.html, evidence.json}`:
//! the requirement matrix, the proofs' records, every built-in scenario and
//! the sweeps against their bounds, the last benchmarks and the provenance;
//! it exits with 1 when a section is incomplete (README.md, "Evidence for a
//! safety assessor").
//!
//! An unusable scenario stops the program with a message naming the file and
//! the field, and exit code 2; so do an unknown scenario and a malformed or
//! empty seed range (`--seeds 5..=4`).

use std::io::IsTerminal as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand};

use fieldguide_sim::crop_drive::file::CropDriveFile;
use fieldguide_sim::crop_drive::{self, campaign, CropRun};
use fieldguide_sim::guiding::{self, file::GuidingFile, mission, GuidingRun};
use fieldguide_sim::metrics::{summarize, Summary};
use fieldguide_sim::scenario::{Source, BUILTIN};
use fieldguide_sim::sweep::{self, Cell, Seeds};
use fieldguide_sim::vineyard::file::VineyardFile;
use fieldguide_sim::vineyard::{self, VineyardRun};
use fieldguide_sim::{evidence, output, runner, stress, SimError};

#[derive(Debug, Parser)]
#[command(
    name = "fieldguide",
    version,
    about = "Closed-loop simulations of fieldguide's guidance laws",
    long_about = "Closed-loop simulations of fieldguide's guidance laws.\n\n\
        With no command, runs every built-in scenario, writes each one's trace, \
        summary and plots to <out>/<scenario>/ and prints a summary table."
)]
struct Cli {
    /// Folder receiving one sub-folder per scenario.
    #[arg(long, global = true, default_value = "out")]
    out: PathBuf,
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// List the built-in scenarios.
    List,
    /// Run one scenario: a built-in name or a TOML file.
    Run {
        /// Built-in scenario name or path to a scenario file.
        scenario: String,
    },
    /// Run a paper's test plan: `guyonneau2022` (Algorithm 5: every
    /// line-finding variant on crops 1-4, `--runs` runs each), writing
    /// `<out>/guyonneau2022/{runs.csv, tables.json, tables.md}` and a
    /// successful and a failed drive as SVG.
    Campaign {
        /// The plan: `guyonneau2022`, or `emmi2024` (farm missions of the
        /// mission supervisor with random obstacles, seeds 1 to `--runs`,
        /// `<out>/emmi2024/runs.csv`).
        plan: String,
        /// Runs per variant and crop (the paper: 5).
        #[arg(long, default_value_t = 5)]
        runs: u32,
    },
    /// Run one scenario once per seed of a range; print and write
    /// `<out>/<scenario>/sweep.csv`, one row of metrics per seed.
    Sweep {
        /// Built-in scenario name or path to a scenario file.
        scenario: String,
        /// The seeds, FIRST..=LAST with both included (`1..=20`).
        #[arg(long, value_name = "FIRST..=LAST")]
        seeds: Seeds,
    },
    /// Write the evidence report for a safety assessor to
    /// `<out>/evidence/{index.html, evidence.json}`: the requirement matrix
    /// (from duvet's JSON report), the proofs' records (written by `cargo
    /// test -p fieldguide-proofs` into $FIELDGUIDE_EVIDENCE_DIR, default
    /// target/evidence), every built-in scenario and the sweeps against their
    /// bounds, the last criterion run, and the commit, toolchain and
    /// dependencies with licences. Exits with 1, the report marked
    /// incomplete in red, when a requirement lacks an implementation or a
    /// test, duvet is missing, a proof record is missing, failed or from
    /// another commit, a run breaks a bound it is not known to break
    /// (closed_loop::EXPECTED_TO_BREAK), a sweep's worst figure is beyond its
    /// bound, there are no benchmark results
    /// (unless --no-benchmarks), or the tree has uncommitted changes.
    Evidence {
        /// The project's root (spec/, .duvet/, proofs/tests/).
        #[arg(long, default_value = ".")]
        root: PathBuf,
        /// The seeds of each sweep (hedge-following, furrow-pursuing).
        #[arg(long, value_name = "FIRST..=LAST", default_value = "1..=10")]
        sweep_seeds: Seeds,
        /// Skip the scenarios and the sweeps (shown as skipped).
        #[arg(long)]
        no_closed_loop: bool,
        /// Benchmarks deliberately skipped (shown as skipped, not red).
        #[arg(long)]
        no_benchmarks: bool,
        /// The duvet program.
        #[arg(long, default_value = "duvet")]
        duvet: PathBuf,
        /// Criterion's folder [default: $CARGO_TARGET_DIR/criterion, or else
        /// <root>/target/criterion].
        #[arg(long)]
        criterion: Option<PathBuf>,
    },
    /// Run the stress campaign: fields that differ from the built-ins the
    /// way real farms do, each over the seeds and held to its bounds; print
    /// the worst figure of every bound and the seed it came from, write
    /// `<out>/stress/{stress.md, stress.json}` and each case's worst seed's
    /// trace and plots. Exits with 1 when a case breaks a bound and is not
    /// a known failure, or a known failure holds.
    Stress {
        /// The seeds, FIRST..=LAST with both included.
        #[arg(long, value_name = "FIRST..=LAST", default_value = "1..=20")]
        seeds: Seeds,
        /// Only this class (`fieldguide stress --class speed-offset`).
        #[arg(long)]
        class: Option<String>,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Some(Command::List) => {
            list();
            Ok(())
        }
        Some(Command::Run { scenario }) => match mission_named(&scenario) {
            Ok(Some(run)) => run_obstacle_mission(&run, &cli.out).map(|row| print_missions(&[row])),
            Ok(None) => match guiding_named(&scenario) {
                Ok(Some(run)) => run_mission(&run, &cli.out).map(|row| print_missions(&[row])),
                Ok(None) => run_scenario(&scenario, &cli.out),
                Err(e) => Err(e),
            },
            Err(e) => Err(e),
        },
        Some(Command::Campaign { plan, runs }) => run_campaign(&plan, runs, &cli.out),
        Some(Command::Sweep { scenario, seeds }) => run_sweep(&scenario, seeds, &cli.out),
        Some(Command::Evidence {
            root,
            sweep_seeds,
            no_closed_loop,
            no_benchmarks,
            duvet,
            criterion,
        }) => {
            let mut options = evidence::Options::new(&root, &cli.out);
            options.sweep_seeds = (!no_closed_loop).then_some(sweep_seeds);
            options.skip_benchmarks = no_benchmarks;
            options.duvet = duvet;
            if let Some(dir) = criterion {
                options.criterion = dir;
            }
            return match run_evidence(&options) {
                Ok(true) => ExitCode::SUCCESS,
                Ok(false) => ExitCode::from(1),
                Err(e) => {
                    eprintln!("error: {e}");
                    ExitCode::from(2)
                }
            };
        }
        Some(Command::Stress { seeds, class }) => {
            return match run_stress(seeds, class.as_deref(), &cli.out) {
                Ok(true) => ExitCode::SUCCESS,
                Ok(false) => ExitCode::from(1),
                Err(e) => {
                    eprintln!("error: {e}");
                    ExitCode::from(2)
                }
            };
        }
        None => run_all(&cli.out),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

/// Writes the evidence report; `true` when it is complete (every section
/// passed, none skipped but those deliberately skipped).
/// Runs the stress campaign (every class, or `class`) over `seeds`; prints
/// each case's line as it is measured and the table; writes the files.
/// `Ok(false)` when a bound is broken.
fn run_stress(seeds: Seeds, class: Option<&str>, out: &Path) -> Result<bool, SimError> {
    let classes = stress::select(class)?;
    let started = std::time::Instant::now();
    let results = stress::campaign(&classes, seeds, |r| {
        let verdict = if r.pass() { "pass" } else { "FAIL" };
        eprintln!(
            "{} / {}: {verdict} (worst seed {})",
            r.class, r.scenario, r.worst_seed
        );
    })?;
    println!("{}", stress::table_md(&results));
    let dir = stress::write(out, &results)?;
    let failed = results.iter().filter(|r| !r.pass()).count();
    let known = results.iter().filter(|r| r.shows_known_failure()).count();
    let unexpected = results.iter().filter(|r| !r.as_expected()).count();
    println!(
        "{} cases over seeds {seeds}, {failed} failing ({known} known failures), \
         {unexpected} not as expected, in {:.1} s; wrote {}",
        results.len(),
        started.elapsed().as_secs_f64(),
        dir.display()
    );
    Ok(unexpected == 0)
}

fn run_evidence(options: &evidence::Options) -> Result<bool, SimError> {
    let started = std::time::Instant::now();
    let report = evidence::Report::gather(options)?;
    let dir = report.write(&options.out.join("evidence"))?;
    let sections = [
        (
            "provenance",
            report.provenance.status,
            &report.provenance.problems,
        ),
        (
            "requirements",
            report.requirements.status,
            &report.requirements.problems,
        ),
        ("proofs", report.proofs.status, &report.proofs.problems),
        (
            "closed loop",
            report.closed_loop.status,
            &report.closed_loop.problems,
        ),
        (
            "benchmarks",
            report.benchmarks.status,
            &report.benchmarks.problems,
        ),
    ];
    for (name, status, problems) in sections {
        println!("{name:14} {}", status.label());
        for p in problems {
            println!("    {p}");
        }
    }
    println!(
        "{} requirements, {} proofs, {} runs, {} sweeps, {} benchmarks in {:.1} s; wrote {}",
        report.requirements.requirements.len(),
        report.proofs.proofs.len(),
        report.closed_loop.runs.len(),
        report.closed_loop.sweeps.len(),
        report.benchmarks.benchmarks.len(),
        started.elapsed().as_secs_f64(),
        dir.display()
    );
    Ok(report.status != evidence::Status::Fail)
}

/// Runs a crop drive, a vine-row run or a scenario of the general runner.
fn run_scenario(scenario: &str, out: &Path) -> Result<(), SimError> {
    if let Some(run) = crop_drive_named(scenario)? {
        return run_drive(&run, out).map(|row| print_drives(&[row]));
    }
    if let Some(run) = vineyard_named(scenario)? {
        return run_vineyard(&run, out).map(|row| print_vineyards(&[row]));
    }
    run_one(scenario, out).map(|s| {
        print_table(&[s]);
    })
}

fn list() {
    for (name, text) in BUILTIN {
        let description = Source::builtin(name)
            .and_then(|s| s.parse().ok())
            .map_or_else(
                || text.lines().next().unwrap_or("").to_owned(),
                |f| f.description,
            );
        println!("{name:32} {description}");
    }
    for (name, text) in crop_drive::file::BUILTIN {
        let description =
            CropDriveFile::parse(text, name).map_or_else(|e| e.to_string(), |f| f.description);
        println!("{name:32} {description}");
    }
    for (name, text) in guiding::file::BUILTIN {
        let description =
            GuidingFile::parse(text, name).map_or_else(|e| e.to_string(), |f| f.description);
        println!("{name:32} {description}");
    }
    for (name, text) in vineyard::file::BUILTIN {
        let description =
            VineyardFile::parse(text, name).map_or_else(|e| e.to_string(), |f| f.description);
        println!("{name:32} {description}");
    }
}

/// Runs one scenario, writes its files, returns its summary.
fn run_one(scenario: &str, out: &Path) -> Result<Summary, SimError> {
    let source = Source::resolve(scenario)?;
    let (setup, mut rng) = runner::prepare(&source)?;
    if source.base_dir.is_some() && Source::builtin(&setup.name).is_some() {
        eprintln!(
            "warning: {} keeps the built-in name `{}`: its output replaces the built-in's in {}",
            source.origin,
            setup.name,
            out.join(&setup.name).display()
        );
    }
    let run = runner::run(&setup, &mut rng);
    let summary = summarize(&setup, &run);
    let dir = output::write_run(out, &setup, &run, &summary)?;
    println!("{}: wrote {}", setup.name, dir.display());
    if let Some(why) = &summary.aborted {
        eprintln!("{}: run stopped early: {why}", setup.name);
    }
    Ok(summary)
}

fn run_all(out: &Path) -> Result<(), SimError> {
    let mut summaries = Vec::with_capacity(BUILTIN.len());
    for (name, _) in BUILTIN {
        summaries.push(run_one(name, out)?);
    }
    print_table(&summaries);
    let mut drives = Vec::new();
    for run in crop_drives()? {
        drives.push(run_drive(&run, out)?);
    }
    println!();
    print_drives(&drives);
    let mut missions = Vec::new();
    for (name, _) in guiding::file::BUILTIN {
        if let Some(run) = guiding::file::builtin_mission(name) {
            missions.push(run_obstacle_mission(&run?, out)?);
        } else if let Some(run) = guiding::file::builtin(name) {
            missions.push(run_mission(&run?, out)?);
        }
    }
    println!();
    print_missions(&missions);
    let mut rows = Vec::new();
    for run in vineyards()? {
        rows.push(run_vineyard(&run, out)?);
    }
    println!();
    print_vineyards(&rows);
    Ok(())
}

/// The mission with obstacles `scenario` names: a built-in one, or a file
/// with `[guiding]` and `[[obstacle]]` tables; `None` for any other.
fn mission_named(scenario: &str) -> Result<Option<mission::MissionRun>, SimError> {
    if let Some(run) = guiding::file::builtin_mission(scenario) {
        return Ok(Some(run?));
    }
    if guiding::file::builtin(scenario).is_some() {
        return Ok(None);
    }
    match std::fs::read_to_string(Path::new(scenario)) {
        Ok(text) if guiding::file::is_guiding(&text) => {
            Ok(GuidingFile::parse(&text, scenario)?.mission(scenario)?)
        }
        _ => Ok(None),
    }
}

/// The guided mission `scenario` names: a built-in one, or a file with a
/// `[guiding]` table; `None` for any other scenario.
fn guiding_named(scenario: &str) -> Result<Option<GuidingRun>, SimError> {
    if let Some(run) = guiding::file::builtin(scenario) {
        return Ok(Some(run?));
    }
    match std::fs::read_to_string(Path::new(scenario)) {
        Ok(text) if guiding::file::is_guiding(&text) => {
            Ok(Some(GuidingFile::parse(&text, scenario)?.run(scenario)?))
        }
        _ => Ok(None),
    }
}

/// The built-in vine-row runs (`vineyard-*`).
fn vineyards() -> Result<Vec<VineyardRun>, SimError> {
    vineyard::file::BUILTIN
        .iter()
        .map(|(name, text)| {
            let origin = format!("built-in scenario `{name}`");
            Ok(VineyardFile::parse(text, &origin)?.run(&origin)?)
        })
        .collect()
}

/// The vine-row run `scenario` names: a built-in one, or a file with a
/// `[vineyard]` table; `None` for any other scenario.
fn vineyard_named(scenario: &str) -> Result<Option<VineyardRun>, SimError> {
    if let Some((name, text)) = vineyard::file::BUILTIN.iter().find(|(n, _)| *n == scenario) {
        let origin = format!("built-in scenario `{name}`");
        return Ok(Some(VineyardFile::parse(text, &origin)?.run(&origin)?));
    }
    match std::fs::read_to_string(Path::new(scenario)) {
        Ok(text) if vineyard::file::is_vineyard(&text) => {
            Ok(Some(VineyardFile::parse(&text, scenario)?.run(scenario)?))
        }
        _ => Ok(None),
    }
}

/// Drives the mission `run`, writes its files, returns its summary.
fn run_mission(run: &GuidingRun, out: &Path) -> Result<(String, guiding::Outcome), SimError> {
    let outcome = guiding::drive(run);
    let dir = guiding::write_mission(out, run, &outcome)?;
    println!("{}: wrote {}", run.name, dir.display());
    Ok((run.name.clone(), outcome))
}

/// The guided missions' table.
fn print_missions(rows: &[(String, guiding::Outcome)]) {
    println!(
        "{:24} {:>8} {:>7} {:>9} {:>10} {:>10} {:>10} {:>10} {:>8}",
        "guided mission",
        "time s",
        "goals",
        "reach",
        "lat line",
        "lat spiral",
        "ang line",
        "ang spiral",
        "crushed"
    );
    for (name, o) in rows {
        println!(
            "{:24} {:>8.1} {:>7} {:>9.4} {:>10.4} {:>10.4} {:>10.4} {:>10.4} {:>8}",
            name,
            o.ticks.last().map_or(0.0, |t| t.t_s),
            format!("{}/{}", o.reaches.len(), o.goals.len()),
            o.reach_error().mean_abs,
            o.lateral_line().mean_abs,
            o.lateral_spiral().mean_abs,
            o.angular_line().mean_abs,
            o.angular_spiral().mean_abs,
            o.crushed.len()
        );
    }
    println!(
        "\n  reach       m, mean distance from each goal to the robot's axis at rest (Emmi 2024, section 5.1)\n  \
         lat line    m, mean over the lines of each line's mean |lateral error| (ground truth)\n  \
         lat spiral  m, the same over the arcs, |distance to the centre - radius|\n  \
         ang line    rad, mean over the lines of each line's mean |heading error|\n  \
         ang spiral  rad, mean over the arcs of each arc's mean |alpha - alpha_d|"
    );
    for (name, o) in rows.iter().filter(|(_, o)| o.end != guiding::End::Done) {
        println!("  {name}: {}", guiding::end_label(&o.end));
    }
}

/// A vine-row run's row of the table.
struct VineRow {
    name: String,
    outcome: vineyard::VineOutcome,
    settled: Option<vineyard::Settled>,
}

/// Drives the vine-row run `run`, writes its files, returns its row.
fn run_vineyard(run: &VineyardRun, out: &Path) -> Result<VineRow, SimError> {
    let outcome = vineyard::drive(run);
    let dir = vineyard::write_drive(out, run, &outcome)?;
    println!("{}: wrote {}", run.name, dir.display());
    Ok(VineRow {
        name: run.name.clone(),
        settled: outcome.settled(run.settle_m),
        outcome,
    })
}

/// The vine-row runs' table.
fn print_vineyards(rows: &[VineRow]) {
    println!(
        "{:32} {:>8} {:>10} {:>10} {:>10} {:>10} {:>9} {:>8}",
        "vine row", "time s", "max |y|", "mean |θ|", "max |θ|", "max |δR|", "touched", "success"
    );
    let fig = |v: Option<f64>| v.map_or_else(|| "-".to_owned(), |v| format!("{v:.4}"));
    for r in rows {
        let o = &r.outcome;
        println!(
            "{:32} {:>8.1} {:>10} {:>10} {:>10} {:>10.3} {:>9} {:>8}",
            r.name,
            o.ticks.last().map_or(0.0, |t| t.t_s),
            fig(r.settled.map(|s| s.lateral_max_abs)),
            fig(r.settled.map(|s| s.angular_mean_abs)),
            fig(r.settled.map(|s| s.angular_max_abs)),
            o.rear_max_abs(),
            format!("{}/{}", o.touched_in_row, o.touched),
            if o.success() { "yes" } else { "NO" }
        );
    }
    println!(
        "\n  max |y|     m, the largest lateral deviation of R from the true row centre line\n              \
         once R is 10 m into the row\n  \
         |θ|         rad, the heading relative to the row, same stretch\n  \
         max |δR|    rad, the largest rear steering angle of the run\n  \
         touched     trunks and posts a wheel met past the entry (3 m) / in all\n  \
         success     the end of the row reached touching no vine from the start"
    );
    for r in rows.iter().filter(|r| !r.outcome.success()) {
        println!("  {}: {:?}", r.name, r.outcome.end);
    }
}

/// The built-in crop drives (`guyonneau-crop1` to `guyonneau-crop4`).
fn crop_drives() -> Result<Vec<CropRun>, SimError> {
    crop_drive::file::BUILTIN
        .iter()
        .map(|(name, text)| {
            let origin = format!("built-in scenario `{name}`");
            Ok(CropDriveFile::parse(text, &origin)?.run(&origin)?)
        })
        .collect()
}

/// The crop drive `scenario` names: a built-in one, or a file with a
/// `[crop_drive]` table; `None` for any other scenario.
fn crop_drive_named(scenario: &str) -> Result<Option<CropRun>, SimError> {
    if let Some((name, text)) = crop_drive::file::BUILTIN
        .iter()
        .find(|(n, _)| *n == scenario)
    {
        let origin = format!("built-in scenario `{name}`");
        return Ok(Some(CropDriveFile::parse(text, &origin)?.run(&origin)?));
    }
    let path = Path::new(scenario);
    match std::fs::read_to_string(path) {
        Ok(text) if crop_drive::file::is_crop_drive(&text) => {
            Ok(Some(CropDriveFile::parse(&text, scenario)?.run(scenario)?))
        }
        _ => Ok(None),
    }
}

/// Drives `run`, writes its files, returns its row.
fn run_drive(run: &CropRun, out: &Path) -> Result<campaign::RunRow, SimError> {
    let outcome = crop_drive::drive(run);
    let dir = crop_drive::write_drive(out, run, &outcome)?;
    println!("{}: wrote {}", run.name, dir.display());
    Ok(campaign::RunRow::of(run, run.crop.crop, 1, &outcome))
}

/// The crop drives' table.
fn print_drives(rows: &[campaign::RunRow]) {
    println!(
        "{:32} {:>8} {:>10} {:>11} {:>9} {:>8} {:>8}",
        "crop drive", "time s", "d / true", "offset mse", "max |o|", "crushed", "success"
    );
    let metres = |v: Option<f64>| v.map_or_else(|| "-".to_owned(), |v| format!("{v:.3}"));
    for r in rows {
        println!(
            "{:32} {:>8.1} {:>10} {:>11} {:>9} {:>8} {:>8}",
            r.name,
            r.duration_s,
            format!("{}/{:.2}", metres(r.row_distance_m.0), r.row_distance_m.1),
            r.mse_mm2
                .map_or_else(|| "-".to_owned(), |v| format!("{v:.0} mm²")),
            metres(r.max_offset_m),
            r.crushed,
            if r.success { "yes" } else { "NO" }
        );
    }
    println!(
        "\n  d / true    m, row distance the robot measured at rest / the crop's\n  \
         offset mse  mean squared offset of O from the middle of its inter-row while driving one\n              \
         inside the field (row changes excluded; ground truth)\n  \
         max |o|     m, the largest such offset\n  \
         success     the end of the fifth inter-row reached without running over a crop plant"
    );
    for r in rows.iter().filter(|r| !r.success) {
        println!(
            "  guyonneau-crop{}: {}",
            r.crop,
            campaign::end_label(&r.end)
        );
    }
}

/// Runs the test plan `plan` with `runs` runs per variant and crop.
/// A mission with obstacles (the supervisor on a farm): writes its folder
/// and prints its stops.
fn run_obstacle_mission(
    run: &mission::MissionRun,
    out: &Path,
) -> Result<(String, guiding::Outcome), SimError> {
    let outcome = mission::drive_mission(run);
    let dir = mission::write(out, run, &outcome)?;
    println!(
        "{}: {}, stops {:?}, {} re-plans, {} collisions; wrote {}",
        run.guiding.name,
        if outcome.complete() {
            "complete"
        } else {
            "not complete"
        },
        outcome.stops_by_reason(),
        outcome.replans.len(),
        outcome.collisions.len(),
        dir.display()
    );
    Ok((run.guiding.name.clone(), outcome.drive))
}

/// The campaign `emmi2024`: `runs` farm missions with random obstacles.
fn run_emmi_campaign(runs: u32, out: &Path) -> Result<(), SimError> {
    let started = std::time::Instant::now();
    let rows = mission::campaign(runs);
    let dir = out.join("emmi2024");
    fieldguide_sim::output::write_files(&dir, &[("runs.csv", mission::campaign_csv(&rows))])?;
    let complete = rows.iter().filter(|r| r.complete).count();
    let sum = |f: fn(&mission::CampaignRow) -> usize| rows.iter().map(f).sum::<usize>();
    println!(
        "emmi2024: {} missions, {} complete, {} stopped with a reason, {} without; \
         collisions {}, a walking person into the robot's side {}, crop plants run over {}, unjustified stops {}, re-plans {} ({} in a field, {} detour plans), stops {}",
        rows.len(),
        complete,
        rows.iter().filter(|r| !r.complete && r.reason.is_some()).count(),
        rows.iter().filter(|r| !r.complete && r.reason.is_none()).count(),
        sum(|r| r.collisions),
        sum(|r| r.walked_into),
        sum(|r| r.crushed),
        sum(|r| r.unjustified),
        sum(|r| r.replans),
        sum(|r| r.replans_in_field),
        sum(|r| r.detour_plans),
        sum(|r| r.stops),
    );
    println!(
        "{} runs in {:.1} s; wrote {}",
        rows.len(),
        started.elapsed().as_secs_f64(),
        dir.display()
    );
    Ok(())
}

fn run_campaign(plan: &str, runs: u32, out: &Path) -> Result<(), SimError> {
    if plan == "emmi2024" {
        return run_emmi_campaign(runs, out);
    }
    if plan != "guyonneau2022" {
        return Err(SimError::Setup {
            what: format!("campaign `{plan}` (the plans are `guyonneau2022` and `emmi2024`)"),
            source: fieldguide::Precondition::new("CAMPAIGN", "unknown plan"),
        });
    }
    let progress = std::io::stderr().is_terminal();
    let started = std::time::Instant::now();
    let result = campaign::campaign(runs, &campaign::VARIANTS, |done, total| {
        if progress {
            let bar = "#".repeat(done * 30 / total.max(1));
            eprint!("\r[{bar:30}] {done}/{total} runs");
        }
    });
    if progress {
        eprintln!();
    }
    let dir = campaign::write(out, &result)?;
    println!("{}", campaign::tables_md(&result.rows));
    println!(
        "{} runs in {:.1} s on {} cores; wrote {}",
        result.rows.len(),
        started.elapsed().as_secs_f64(),
        std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get),
        dir.display()
    );
    Ok(())
}

/// Runs `scenario` for each seed, printing a row per seed, then the worst
/// row and the failures; writes `sweep.csv`. A vine-row run sweeps through
/// `sweep::vine_sweep`, any other scenario through `sweep::sweep`.
fn run_sweep(scenario: &str, seeds: Seeds, out: &Path) -> Result<(), SimError> {
    if let Some(run) = vineyard_named(scenario)? {
        let mut table = SweepTable::<sweep::VineSummary>::new(seeds);
        let result = sweep::vine_sweep(&run, seeds, |s| table.row(s));
        return table.finish(out, &result);
    }
    let source = Source::resolve(scenario)?;
    let mut table = SweepTable::<Summary>::new(seeds);
    let result = sweep::sweep(&source, seeds, |s| table.row(s))?;
    table.finish(out, &result)?;
    // The worst seed of each column, run again with its trace and plots.
    let kept = sweep::keep_worst(&source, &result, out)?;
    if let Some((_, _, dir)) = kept.first() {
        let folder = dir.parent().unwrap_or(dir);
        println!(
            "{}: wrote the worst seeds' runs to {} ({})",
            result.scenario,
            folder.display(),
            kept.iter()
                .map(|(column, seed, _)| format!("{column}: {seed}"))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    Ok(())
}

/// The table a sweep prints as its rows come.
struct SweepTable<R> {
    widths: Vec<usize>,
    total: usize,
    done: usize,
    progress: bool,
    seeds: Seeds,
    rows: std::marker::PhantomData<R>,
}

impl<R: sweep::Row> SweepTable<R> {
    /// Prints the heading.
    fn new(seeds: Seeds) -> Self {
        let table = Self {
            widths: R::COLUMNS.iter().map(|c| c.name.len().max(8)).collect(),
            total: seeds.iter().count(),
            done: 0,
            progress: std::io::stderr().is_terminal(),
            seeds,
            rows: std::marker::PhantomData,
        };
        println!(
            "{}",
            table.line("seed", &mut R::COLUMNS.iter().map(|c| c.name.to_owned()))
        );
        table
    }

    fn line(&self, first: &str, cells: &mut dyn Iterator<Item = String>) -> String {
        let mut text = format!("{first:>10}");
        for (cell, width) in cells.zip(&self.widths) {
            text.push_str(&format!(" {cell:>width$}"));
        }
        text
    }

    /// Prints one seed's row.
    fn row(&mut self, s: &R) {
        self.done += 1;
        if self.progress {
            eprint!("\r{}/{} seeds\r", self.done, self.total);
        }
        let row = self.line(
            &s.seed().to_string(),
            &mut R::COLUMNS.iter().map(|c| show((c.cell)(s))),
        );
        println!("{row}");
        if let Some(why) = s.aborted() {
            eprintln!("seed {}: run stopped early: {why}", s.seed());
        }
    }

    /// Prints the worst row, the seeds it came from and the failures;
    /// writes `sweep.csv`.
    fn finish(&self, out: &Path, result: &sweep::Sweep<R>) -> Result<(), SimError> {
        let worst: Vec<Option<(u64, Cell)>> = R::COLUMNS
            .iter()
            .map(|c| sweep::worst(&result.rows, c))
            .collect();
        println!(
            "{}",
            self.line(
                "worst",
                &mut worst
                    .iter()
                    .map(|w| w.map_or_else(|| "-".to_owned(), |(_, c)| show(c)))
            )
        );
        println!(
            "{}",
            self.line(
                "at seed",
                &mut worst.iter().map(|w| match w {
                    // No seed is to blame for a column where every run did well.
                    None | Some((_, Cell::Flag(true) | Cell::Count(0))) => "-".to_owned(),
                    Some((seed, _)) => seed.to_string(),
                })
            )
        );
        let failed = sweep::failed_seeds(&result.rows);
        let failures = if failed.is_empty() {
            "none".to_owned()
        } else {
            failed
                .iter()
                .map(u64::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        };
        println!(
            "{}: {} seeds ({}), failed: {failures}",
            result.scenario,
            result.rows.len(),
            self.seeds
        );
        let file = output::write_sweep(out, result)?;
        println!("{}: wrote {}", result.scenario, file.display());
        Ok(())
    }
}

/// A cell of the sweep table as printed.
fn show(cell: Cell) -> String {
    match cell {
        Cell::Metres(None) | Cell::Radians(None) => "-".to_owned(),
        Cell::Metres(Some(v)) | Cell::Radians(Some(v)) => format!("{v:.4}"),
        Cell::Plain(v) => format!("{v:.2}"),
        Cell::Count(n) => n.to_string(),
        Cell::Flag(true) => "yes".to_owned(),
        Cell::Flag(false) => "NO".to_owned(),
    }
}

/// The summary table: one row per scenario, the columns explained below
/// it, and each failed run's broken bounds.
fn print_table(summaries: &[Summary]) {
    println!(
        "{:32} {:>8} {:>9} {:>10} {:>9} {:>10} {:>8}",
        "scenario", "distance", "converged", "mean |y|", "max |y|", "true line", "success"
    );
    let metres = |v: Option<f64>| v.map_or_else(|| "-".to_owned(), |v| format!("{v:.4}"));
    for s in summaries {
        let converged = s
            .converged_after_m
            .map_or_else(|| "never".to_owned(), |d| format!("{d:.2}"));
        let after = s.lateral_error_after_convergence_m;
        // The error to the true line a specialised behaviour follows: the
        // rows' centre line inside the plots, or a hedge's offset line
        // (after convergence) beside it.
        let true_line = s
            .in_plot_lateral_error_m
            .or(s.along_hedge_after_convergence_m)
            .map(|e| e.max_abs);
        println!(
            "{:32} {:>8.2} {:>9} {:>10} {:>9} {:>10} {:>8}",
            s.scenario,
            s.distance_m,
            converged,
            metres(after.map(|e| e.mean_abs)),
            metres(after.map(|e| e.max_abs)),
            metres(true_line),
            if s.success { "yes" } else { "NO" }
        );
    }
    println!(
        "\n  distance   m travelled by O (the rear axle's centre)\n  \
         converged  m travelled until |y| entered the band and stayed in it\n  \
         mean |y|, max |y|  m, error of O to the reference path from convergence on (ground truth)\n  \
         true line  m, max error to the line a behaviour follows: the rows' centre inside the plots,\n             \
         or a hedge's offset line after convergence\n  \
         success    every bound of the scenario's [metrics] held; otherwise the bounds broken:"
    );
    for s in summaries.iter().filter(|s| !s.success) {
        for why in &s.failures {
            println!("  {}: {why}", s.scenario);
        }
    }
}
