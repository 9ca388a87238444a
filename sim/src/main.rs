//! The `fieldguide` program: runs simulator scenarios and writes their traces,
//! summaries and plots.
//!
//! - `fieldguide` runs every built-in scenario and prints a summary table;
//! - `fieldguide list` lists the built-in scenarios;
//! - `fieldguide run <name or file.toml> [--out DIR]` runs one scenario.
//!
//! Each run writes `DIR/<scenario>/{trace.csv, summary.json, trajectory.svg,
//! lateral_error.svg}` (`DIR` defaults to `out`). An unusable scenario stops
//! the program with a message naming the file and the field, and exit code 2.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand};

use fieldguide_sim::metrics::{summarize, Summary};
use fieldguide_sim::scenario::{Source, BUILTIN};
use fieldguide_sim::{output, runner, SimError};

#[derive(Debug, Parser)]
#[command(
    name = "fieldguide",
    version,
    about = "Closed-loop simulations of fieldguide's guidance laws"
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
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Some(Command::List) => {
            list();
            Ok(())
        }
        Some(Command::Run { scenario }) => run_one(&scenario, &cli.out).map(|s| {
            print_table(&[s]);
        }),
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
}

/// Runs one scenario, writes its files, returns its summary.
fn run_one(scenario: &str, out: &Path) -> Result<Summary, SimError> {
    let source = Source::resolve(scenario)?;
    let (setup, mut rng) = runner::prepare(&source)?;
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
    Ok(())
}

fn print_table(summaries: &[Summary]) {
    println!(
        "{:32} {:>12} {:>12} {:>11} {:>19} {:>17} {:>8}",
        "scenario",
        "distance (m)",
        "mean |y| (m)",
        "max |y| (m)",
        "converged after (m)",
        "true-line max (m)",
        "success"
    );
    for s in summaries {
        let converged = s
            .converged_after_m
            .map_or_else(|| "never".to_owned(), |d| format!("{d:.2}"));
        // The error to the true line a specialised behaviour follows: the
        // rows' centre line inside the plots, or a hedge's offset line
        // (after convergence) beside it.
        let in_plot = s
            .in_plot_lateral_error_m
            .or(s.along_hedge_after_convergence_m)
            .map_or_else(|| "-".to_owned(), |e| format!("{:.4}", e.max_abs));
        println!(
            "{:32} {:>12.2} {:>12.4} {:>11.4} {:>19} {:>17} {:>8}",
            s.scenario,
            s.distance_m,
            s.lateral_error_m.mean_abs,
            s.lateral_error_m.max_abs,
            converged,
            in_plot,
            if s.success { "yes" } else { "NO" }
        );
    }
}
