//! Fuzz targets (bolero) for the scenario loader: any bytes as a scenario
//! file, and the built-in scenarios edited line by line (a number replaced
//! by NaN, ±∞, 1e−300, 1e300, −0, a negative or a huge integer; a line
//! deleted, duplicated or swapped with another; a table header dropped).
//!
//! The loader's claims checked: it never panics; a refusal is a
//! `ScenarioError` whose message names the file and, for a value, the field;
//! every count a file implies is bounded (the capacities of
//! `fieldguide_sim::capacity`), so an accepted file is run for a few control
//! ticks, and that run gives finite values only.
//!
//! `cargo test` runs each for bolero's default budget (one second of random
//! inputs); `.ci/fuzz` runs each as a coverage-guided libFuzzer target
//! (README.md, "Fuzzing").
#![allow(clippy::panic, clippy::unwrap_used)]

use std::sync::OnceLock;

use bolero::{check, produce_with, TypeGenerator};
use fieldguide_sim::capacity::{EDGE_CHAIN, EDGE_RAYS, FURROW_SCANS};
use fieldguide_sim::rng::SimRng;
use fieldguide_sim::runner::{self, RunEnd};
use fieldguide_sim::scenario::{build, Setup, Source, BUILTIN};
use fieldguide_sim::ScenarioError;

/// How the edited files are called in messages.
const ORIGIN: &str = "fuzzed.toml";

/// Control ticks run from an accepted file.
const TICKS: f64 = 5.0;

/// `text` as a scenario file without a folder (no waypoint CSV can be read).
fn source(text: String) -> Source {
    Source {
        origin: ORIGIN.to_owned(),
        text,
        base_dir: None,
    }
}

/// A refusal names the file, and the field when it is about one (LIB: the
/// simulator's errors, `sim/src/error.rs`).
fn check_refusal(e: &ScenarioError) {
    let message = e.to_string();
    match e {
        ScenarioError::Syntax { origin, .. } => assert_eq!(origin, ORIGIN),
        ScenarioError::Field { origin, field, .. } => {
            assert_eq!(origin, ORIGIN);
            assert!(!field.is_empty(), "{message}");
            assert!(message.contains(field.as_str()), "{message}");
        }
        ScenarioError::Read { file, .. } => {
            assert!(message.contains(&file.display().to_string()), "{message}");
        }
        ScenarioError::Table(t) => {
            assert_eq!(t.origin, ORIGIN);
            assert!(message.contains(&t.file) && t.line >= 1, "{message}");
        }
        ScenarioError::NotFound { .. } => panic!("a text is never looked up: {message}"),
    }
    if !matches!(e, ScenarioError::Read { .. }) {
        assert!(message.contains(ORIGIN), "{message}");
    }
}

/// What an accepted file implies stays within the simulator's capacities,
/// and a short run of it gives finite values only.
fn check_accepted(mut setup: Setup) {
    assert!(setup.control.period_s.is_finite() && setup.control.period_s > 0.0);
    assert!(setup.run.duration_s.is_finite() && setup.run.duration_s >= 0.0);
    if let Some(l) = &setup.horizontal_lidar {
        assert!(l.lidar.spec().rays <= EDGE_RAYS && l.scan_every >= 1);
    }
    if let Some(l) = &setup.lidar {
        assert!(l.scan_every >= 1);
    }
    if let Some(e) = &setup.edge {
        assert!(e.detector.min_points() <= EDGE_CHAIN);
    }
    if let Some(f) = &setup.furrow {
        assert!(f.detector.params().averaged_scans <= FURROW_SCANS);
    }
    setup.run.duration_s = setup.run.duration_s.min(TICKS * setup.control.period_s);
    let out = runner::run(&setup, &mut SimRng::from_seed(setup.seed));
    assert!(out.trace.len() <= TICKS as usize + 1);
    for r in &out.trace {
        for v in [
            r.t_s,
            r.s_m,
            r.lateral_error_m,
            r.angular_error_rad,
            r.curvature,
            r.steering_rad,
            r.distance_m,
            r.sideslip_rad.0,
            r.sideslip_rad.1,
            r.command.speed().get(),
        ] {
            assert!(v.is_finite(), "{r:?}");
        }
    }
    if let RunEnd::Aborted(why) = &out.end {
        assert!(!why.is_empty());
    }
}

/// Loads `text` as `Source::setup` does (parse, then build), once.
fn load(text: &str) {
    let setup = fieldguide_sim::scenario::parse(text, ORIGIN)
        .and_then(|file| build(&file, ORIGIN, None, &mut SimRng::from_seed(1)));
    match setup {
        Ok(setup) => check_accepted(setup),
        Err(e) => check_refusal(&e),
    }
}

/// Any bytes, read as UTF-8 (invalid sequences replaced), as a scenario.
#[test]
fn fuzz_loader_bytes() {
    check!().for_each(|bytes: &[u8]| {
        load(&String::from_utf8_lossy(bytes));
    });
}

// ------------------------------------------------- structure-aware edits --

/// A number written into a file.
#[derive(Debug, Clone, Copy, TypeGenerator)]
enum Number {
    Nan,
    Infinity,
    NegInfinity,
    Tiny,
    Huge,
    NegZero,
    Zero,
    /// −k / 100.
    Negative(u16),
    /// k / 100.
    Ordinary(u16),
    Max,
    Subnormal,
    /// Any integer, i64::MIN and i64::MAX included.
    Integer(i64),
    /// Past the range of i64.
    TooLarge,
    /// Any bit pattern, written as a float.
    Bits(u64),
}

impl Number {
    /// The TOML text of the number.
    fn text(self) -> String {
        let float = |v: f64| {
            if v.is_nan() {
                "nan".to_owned()
            } else if v.is_infinite() {
                if v > 0.0 { "inf" } else { "-inf" }.to_owned()
            } else {
                // Debug keeps a decimal point or an exponent: a TOML float.
                format!("{v:?}")
            }
        };
        match self {
            Self::Nan => "nan".to_owned(),
            Self::Infinity => "inf".to_owned(),
            Self::NegInfinity => "-inf".to_owned(),
            Self::Tiny => "1e-300".to_owned(),
            Self::Huge => "1e300".to_owned(),
            Self::NegZero => "-0.0".to_owned(),
            Self::Zero => "0".to_owned(),
            Self::Negative(k) => float(-f64::from(k) / 100.0),
            Self::Ordinary(k) => float(f64::from(k) / 100.0),
            Self::Max => float(f64::MAX),
            Self::Subnormal => float(f64::from_bits(1)),
            Self::Integer(k) => k.to_string(),
            Self::TooLarge => "99999999999999999999".to_owned(),
            Self::Bits(b) => float(f64::from_bits(b)),
        }
    }
}

/// One edit of a scenario's text; lines and tokens are chosen modulo their
/// count.
#[derive(Debug, Clone, Copy, TypeGenerator)]
enum Edit {
    /// The `token`-th number of line `line` replaced.
    Number {
        line: u16,
        token: u8,
        value: Number,
    },
    Delete(u16),
    Duplicate(u16),
    Swap(u16, u16),
    /// The `n`-th table header (`[section]`, `[[array]]`) removed.
    DropHeader(u8),
}

/// The byte ranges of the numbers of `line` (outside strings and comments).
fn numbers(line: &str) -> Vec<(usize, usize)> {
    let bytes = line.as_bytes();
    let mut out = Vec::new();
    let mut in_string = false;
    let mut i = 0;
    while i < bytes.len() {
        let c = bytes[i];
        if c == b'"' {
            in_string = !in_string;
        } else if c == b'#' && !in_string {
            break;
        } else if !in_string && (c.is_ascii_digit() || c == b'-' || c == b'+') {
            // A number starts after `=`, `[`, `,`, `{` or a space, never inside a name.
            let starts = i == 0 || matches!(bytes[i - 1], b' ' | b'=' | b'[' | b',' | b'{');
            let mut j = i + 1;
            while j < bytes.len()
                && matches!(
                    bytes[j],
                    b'0'..=b'9' | b'.' | b'e' | b'E' | b'-' | b'+' | b'_'
                )
            {
                j += 1;
            }
            if starts && bytes[i..j].iter().any(u8::is_ascii_digit) {
                out.push((i, j));
            }
            i = j;
            continue;
        }
        i += 1;
    }
    out
}

fn apply(lines: &mut Vec<String>, edit: Edit) {
    let n = lines.len();
    if n == 0 {
        return;
    }
    let at = |k: u16| usize::from(k) % n;
    match edit {
        Edit::Number { line, token, value } => {
            let l = &mut lines[at(line)];
            let spans = numbers(l);
            if let Some(&(a, b)) = spans.get(usize::from(token) % spans.len().max(1)) {
                l.replace_range(a..b, &value.text());
            }
        }
        Edit::Delete(k) => {
            lines.remove(at(k));
        }
        Edit::Duplicate(k) => {
            let l = lines[at(k)].clone();
            lines.insert(at(k), l);
        }
        Edit::Swap(a, b) => lines.swap(at(a), at(b)),
        Edit::DropHeader(k) => {
            let headers: Vec<usize> = (0..n)
                .filter(|&i| lines[i].trim_start().starts_with('['))
                .collect();
            if !headers.is_empty() {
                lines.remove(headers[usize::from(k) % headers.len()]);
            }
        }
    }
}

/// The built-in scenarios made cheaper to set up and run for fuzzing, each
/// still accepted: the path sampled every 0.5 m instead of 0.1 m and the
/// grass 10 times sparser.
fn bases() -> &'static [(String, Vec<String>)] {
    static BASES: OnceLock<Vec<(String, Vec<String>)>> = OnceLock::new();
    BASES.get_or_init(|| {
        BUILTIN
            .iter()
            .map(|(name, text)| {
                let lines = text.lines().map(compact).collect::<Vec<_>>();
                let compacted = lines.join("\n");
                if let Err(e) = source(compacted).setup(&mut SimRng::from_seed(1)) {
                    panic!("the compacted `{name}` is refused: {e}");
                }
                ((*name).to_owned(), lines)
            })
            .collect()
    })
}

/// One line of a built-in scenario, made cheaper (see [`bases`]).
fn compact(line: &str) -> String {
    let key = line.split('=').next().unwrap_or("").trim();
    match key {
        "sample_step_m" => "sample_step_m = 0.5".to_owned(),
        "density_per_m2" => "density_per_m2 = 0.3".to_owned(),
        _ => line.to_owned(),
    }
}

#[derive(Debug, Clone, TypeGenerator)]
struct EditedScenario {
    base: u8,
    #[generator(produce_with::<Vec<Edit>>().len(1usize..=4))]
    edits: Vec<Edit>,
}

/// A built-in scenario with a few edits, set up and, when accepted, run
/// for a few ticks.
#[test]
fn fuzz_loader_edits() {
    check!().with_type::<EditedScenario>().for_each(|case| {
        let bases = bases();
        let (_, lines) = &bases[usize::from(case.base) % bases.len()];
        let mut lines = lines.clone();
        for edit in &case.edits {
            apply(&mut lines, *edit);
        }
        let mut text = lines.join("\n");
        text.push('\n');
        load(&text);
    });
}

/// The edits do what they say: a number is found and replaced in each form.
#[test]
fn edits_replace_numbers_and_lines() {
    assert_eq!(numbers("x = 1.5 # 2"), vec![(4, 7)]);
    assert_eq!(
        numbers("start = { x_m = -1.0, y_m = 2 }"),
        vec![(16, 20), (28, 29)]
    );
    assert_eq!(numbers("name = \"exp2-acre\""), vec![]);
    assert_eq!(numbers("polygon = [[15.0, -3.0]]").len(), 2);
    let mut lines = vec!["[vehicle]".to_owned(), "wheelbase_m = 2.0".to_owned()];
    apply(
        &mut lines,
        Edit::Number {
            line: 1,
            token: 0,
            value: Number::Nan,
        },
    );
    assert_eq!(lines[1], "wheelbase_m = nan");
    apply(&mut lines, Edit::DropHeader(0));
    assert_eq!(lines, vec!["wheelbase_m = nan".to_owned()]);
    for (value, text) in [
        (Number::NegZero, "-0.0"),
        (Number::Tiny, "1e-300"),
        (Number::Integer(i64::MIN), "-9223372036854775808"),
        (Number::Max, "1.7976931348623157e308"),
        (Number::Ordinary(250), "2.5"),
    ] {
        assert_eq!(value.text(), text);
    }
    // Every compacted built-in is accepted (asserted while building them).
    assert_eq!(bases().len(), BUILTIN.len());
}
