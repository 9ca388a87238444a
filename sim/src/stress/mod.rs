//! The stress campaign: fields that differ from the built-in scenarios the
//! way real farms do (speeds from 0.3 to 3 m/s, a slow steering, tight
//! U-turns, slip patches, rows off the path, outages at a plot's end,
//! ragged hedges, trunk rows), each run over a range of seeds and held to
//! stated bounds ([`Bound`]). `fieldguide stress` runs it, prints the worst
//! figure of every bound with the seed it came from, writes `stress.md` and
//! `stress.json`, and keeps the trace and plots of each run's worst seed.
//!
//! A class's runs are built-in scenarios or files of `sim/scenarios/stress/`
//! (read from the source tree, so that their CSV and waypoint files resolve
//! beside them). A claim about a class is a claim about its worst seed.

pub mod bounds;
pub mod envelope;
pub mod face_plot;
mod report;

use std::path::{Path, PathBuf};

use serde::Serialize;

pub use self::bounds::{Bound, Judged};
pub use self::report::{table_md, write};
use crate::error::SimError;
use crate::metrics::summarize;
use crate::runner;
use crate::scenario::Source;
use crate::sweep::Seeds;

/// One scenario of a class and the bounds each of its runs is held to.
#[derive(Debug, Clone, Copy)]
pub struct Case {
    /// A built-in scenario's name, or a file name in `sim/scenarios/stress/`.
    pub scenario: &'static str,
    /// The bounds of every seed's run.
    pub bounds: &'static [Bound],
    /// Why the case is known to break a bound (an open finding the README
    /// states); `None` for a case that must hold. A known failure that
    /// starts to hold fails the campaign's test until this is updated.
    pub known_failure: Option<Known>,
}

/// A finding a case is known to show: why, and on which seeds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Known {
    /// Why the case breaks a bound.
    pub why: &'static str,
    /// The seeds that break it, when the finding is a few seeds' (the others
    /// must hold); `None` when it is seen on most seeds (at least one of any
    /// seeds run must break a bound).
    pub seeds: Option<&'static [u64]>,
}

impl Known {
    /// A finding seen on most seeds.
    #[must_use]
    pub const fn most_seeds(why: &'static str) -> Option<Self> {
        Some(Self { why, seeds: None })
    }

    /// A finding of exactly `seeds`: run over a range without them, the
    /// case must hold; with them, exactly they must break a bound.
    #[must_use]
    pub const fn on_seeds(seeds: &'static [u64], why: &'static str) -> Option<Self> {
        Some(Self {
            why,
            seeds: Some(seeds),
        })
    }
}

/// A class of stress fields: what it stresses and its cases.
#[derive(Debug, Clone, Copy)]
pub struct Class {
    /// Short name (`speed-offset`).
    pub name: &'static str,
    /// What the fields stress, one line.
    pub stresses: &'static str,
    /// The scenarios and their bounds.
    pub cases: &'static [Case],
    /// The odometry heading its runs use.
    pub heading: Heading,
}

/// The odometry heading of a class's runs: the stress fields' own (a yaw
/// gyro, `sim/scenarios/stress/README.md`), or the wheels' with the
/// built-in scenarios' per-tick errors, the evidence of what a vehicle
/// without a gyro gets.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum Heading {
    /// As the scenario file says.
    AsFile,
    /// From the wheels: a yaw-rate bias, degrees per second, and a σ on
    /// each tick's heading increment, degrees (the file's gyro dropped).
    Wheels {
        /// Bias of the yaw rate, °/s.
        bias_deg_s: f64,
        /// σ of each tick's heading increment, °.
        noise_deg: f64,
    },
}

/// The odometry aid's time constant with the wheels' heading, s
/// (GD-ODOMETRY-AID: a dual-antenna heading's noise is correlated over a
/// fraction of a second to a second).
pub const AID_TIME_CONSTANT_S: f64 = 1.0;

/// The odometry aid's largest rate with the wheels' heading, °/s: ten times
/// the wheels' bias.
pub const AID_MAX_RATE_DEG_S: f64 = 0.5;

impl Heading {
    /// The built-in scenarios' wheel heading: 0.05 °/s and 0.02 ° a tick
    /// (at 100 Hz, 180 °/h and 12 °/√h).
    pub const BUILTIN_WHEELS: Self = Self::Wheels {
        bias_deg_s: 0.05,
        noise_deg: 0.02,
    };

    /// Sets `file`'s odometry heading to this one; the wheels' comes with
    /// the odometry aid a vehicle without a gyro is configured with
    /// (GD-ODOMETRY-AID: [`AID_TIME_CONSTANT_S`], [`AID_MAX_RATE_DEG_S`]).
    pub fn apply(self, file: &mut crate::scenario::ScenarioFile) {
        if let Self::Wheels {
            bias_deg_s,
            noise_deg,
        } = self
        {
            let s = file.switching.get_or_insert_with(Default::default);
            s.odometry_aid_time_constant_s = Some(AID_TIME_CONSTANT_S);
            s.odometry_aid_max_rate_deg_s = Some(AID_MAX_RATE_DEG_S);
            let n = &mut file.noise;
            n.odometry_heading = crate::scenario::schema::HeadingName::Wheels;
            n.odometry_yaw_bias_deg_s = bias_deg_s;
            n.odometry_yaw_noise_deg = noise_deg;
            n.gyro_random_walk_deg_sqrt_h = None;
            n.gyro_bias_deg_h = None;
            n.gyro_bias_instability_deg_h = None;
            n.gyro_bias_time_constant_s = None;
        }
    }
}

use Bound::{
    ConvergesInTime, CurvatureStep, EnvelopeTowards, FollowedMax, FollowedMean, InPlotMax, MaxFrom,
    NoPlantCrushed, Overshoot, ScenarioChecks, SettledBefore, SettledInBand, SlipStep,
    SwitchesAtMost,
};

const STRAIGHT_FROM_0_8: &[Bound] = &[ConvergesInTime, Overshoot(0.10), SettledInBand];
const STRAIGHT_FROM_1_5: &[Bound] = &[ConvergesInTime, Overshoot(0.12), SettledInBand];
const CROPS: &[Bound] = &[ScenarioChecks, NoPlantCrushed];
/// Rows off the recorded path: the error to the path is the offset, by
/// design; the rows' centre line is what the robot must hold.
const ROWS_OFF: &[Bound] = &[NoPlantCrushed, InPlotMax(0.1)];
/// A ragged hedge: the switches, the distance to its followed line and how
/// near it comes to its envelope ([`envelope`]).
const HEDGE_ENVELOPE: &[Bound] = &[
    ScenarioChecks,
    SwitchesAtMost(2),
    FollowedMean(0.05),
    FollowedMax(0.15),
    EnvelopeTowards(0.15),
];

/// The cases run with both headings (the class `wheel-heading` sets its
/// own known failures on them).
const RANDOM_WALK: Case = Case {
    scenario: "gnss-drift-random-walk.toml",
    bounds: CROPS,
    known_failure: None,
};
const OFFSET_ENTRY: Case = Case {
    scenario: "rows-offset-entry.toml",
    bounds: ROWS_OFF,
    known_failure: None,
};
const BEANS_FAST: Case = Case {
    scenario: "rows-offset-beans-fast.toml",
    bounds: ROWS_OFF,
    known_failure: None,
};

/// Every class of the campaign, in the order of the README's table.
pub const CLASSES: &[Class] = &[
    Class {
        name: "speed-offset",
        stresses: "path tracking at 0.3, 1, 2 and 3 m/s from 0.8 m off a straight",
        heading: Heading::AsFile,
        cases: &[
            Case {
                scenario: "tracking-v0_3-offset",
                bounds: STRAIGHT_FROM_0_8,
                known_failure: None,
            },
            Case {
                scenario: "tracking-v1-offset",
                bounds: STRAIGHT_FROM_0_8,
                known_failure: None,
            },
            Case {
                scenario: "tracking-v2-offset",
                bounds: STRAIGHT_FROM_0_8,
                known_failure: None,
            },
            Case {
                scenario: "tracking-v3-offset",
                bounds: STRAIGHT_FROM_0_8,
                known_failure: None,
            },
        ],
    },
    Class {
        name: "speed-heading",
        stresses: "path tracking at 0.3, 1, 2 and 3 m/s from 1.5 m off, heading 20° away",
        heading: Heading::AsFile,
        cases: &[
            Case {
                scenario: "tracking-v0_3-heading",
                bounds: STRAIGHT_FROM_1_5,
                known_failure: None,
            },
            Case {
                scenario: "tracking-v1-heading",
                bounds: STRAIGHT_FROM_1_5,
                known_failure: None,
            },
            Case {
                scenario: "tracking-v2-heading",
                bounds: STRAIGHT_FROM_1_5,
                known_failure: None,
            },
            Case {
                scenario: "tracking-v3-heading",
                bounds: STRAIGHT_FROM_1_5,
                known_failure: None,
            },
        ],
    },
    Class {
        name: "s-bends",
        stresses: "8 m S-bends (curvature reverses) at 1.5 and 3 m/s",
        heading: Heading::AsFile,
        cases: &[
            Case {
                scenario: "tracking-sbend-v1_5",
                bounds: &[CurvatureStep(0.25)],
                known_failure: None,
            },
            Case {
                scenario: "tracking-sbend-v3",
                bounds: &[CurvatureStep(0.25)],
                known_failure: None,
            },
        ],
    },
    Class {
        name: "tight-u-turn",
        stresses: "a 4.5 m U-turn at 1.5 m/s",
        heading: Heading::AsFile,
        cases: &[Case {
            scenario: "tracking-uturn",
            bounds: &[CurvatureStep(1.0 / 4.5)],
            known_failure: None,
        }],
    },
    Class {
        name: "slip-patches",
        stresses: "slip patches (β_F −4°, β_R −6°) on a straight and a curve at 2 m/s",
        heading: Heading::AsFile,
        cases: &[Case {
            scenario: "tracking-slip",
            bounds: &[SlipStep(6.0, 0.5)],
            known_failure: None,
        }],
    },
    Class {
        name: "steering-lag-2s",
        stresses: "a steering that settles in 2 s, at 2 m/s, from 0.8 m off, then an S-bend",
        heading: Heading::AsFile,
        // The first straight ends at s = 40 m; the S-bend's 0.15 m is measured, not derived.
        cases: &[Case {
            scenario: "tracking-lag-2s",
            bounds: &[SettledBefore(40.0), MaxFrom(40.0, 0.15)],
            known_failure: None,
        }],
    },
    Class {
        name: "crops",
        stresses: "the Pierre 2022 crop scenarios over more seeds: plots, volunteers, outages",
        heading: Heading::AsFile,
        cases: &[
            Case {
                scenario: "furrow-pursuing",
                bounds: CROPS,
                known_failure: None,
            },
            Case {
                scenario: "exp1-hedge-maize",
                bounds: CROPS,
                known_failure: None,
            },
            Case {
                scenario: "exp2-acre",
                bounds: CROPS,
                known_failure: None,
            },
            Case {
                scenario: "exp3-acre-curved",
                bounds: CROPS,
                known_failure: None,
            },
            Case {
                scenario: "gnss-outage",
                bounds: CROPS,
                known_failure: None,
            },
        ],
    },
    Class {
        name: "outage-at-plot-end",
        stresses: "GNSS lost 1, 2.6 or 5 s before a plot ends, volunteers past it, a U-turn after",
        heading: Heading::AsFile,
        cases: &[
            Case {
                scenario: "outage-1s.toml",
                bounds: CROPS,
                known_failure: None,
            },
            Case {
                scenario: "outage-2_6s.toml",
                bounds: CROPS,
                known_failure: None,
            },
            Case {
                scenario: "outage-5s.toml",
                bounds: CROPS,
                known_failure: None,
            },
            Case {
                scenario: "outage-maize-fast.toml",
                bounds: CROPS,
                known_failure: None,
            },
        ],
    },
    Class {
        name: "gnss-drift-outages",
        stresses: "a fix drifting 0.1 m (20 s random walk) and float over the headland, lost by distance in the plots (at 0.7 and 0.5 m/s), lost at a bean plot's entry at 1 m/s, float across a U-turn (0.5 m jump at 0.8 m/s, 0.8 m at 1 m/s)",
        heading: Heading::AsFile,
        cases: &[
            RANDOM_WALK,
            Case {
                scenario: "gnss-outage-distance.toml",
                bounds: CROPS,
                known_failure: None,
            },
            Case {
                scenario: "gnss-outage-distance-slow.toml",
                bounds: CROPS,
                known_failure: None,
            },
            Case {
                scenario: "outage-entry-beans.toml",
                bounds: CROPS,
                known_failure: None,
            },
            Case {
                scenario: "gnss-float-uturn.toml",
                bounds: CROPS,
                known_failure: None,
            },
            Case {
                scenario: "gnss-float-uturn-fast.toml",
                bounds: CROPS,
                known_failure: None,
            },
        ],
    },
    Class {
        name: "rows-off-the-path",
        stresses: "crop rows 0.1-0.3 m beside a straight path and bending 0.25-0.3 m from it, hand-over rule on; entry rule on but in rows-offset-handover",
        heading: Heading::AsFile,
        cases: &[
            Case {
                scenario: "rows-offset-handover.toml",
                bounds: ROWS_OFF,
                known_failure: None,
            },
            Case {
                scenario: "rows-offset-maize-beans.toml",
                bounds: ROWS_OFF,
                known_failure: None,
            },
            OFFSET_ENTRY,
            Case {
                scenario: "rows-offset-right-slow.toml",
                bounds: ROWS_OFF,
                known_failure: None,
            },
            BEANS_FAST,
        ],
    },
    Class {
        name: "hedges-and-trunks",
        stresses: "a row of 0.1 m trunks every metre (a thin hedge, and posts), posts along a bent hedge, ragged hedges with 1-3 m and 0.5-1 m gaps, and with 2-4 m gaps at 1.2 m/s; of our own, a hedge at 35 deg followed on the right, and coarse bushes driven westwards 1 m off",
        heading: Heading::AsFile,
        cases: &[
            Case { scenario: "trunks-row.toml", bounds: &[ScenarioChecks, SwitchesAtMost(2)], known_failure: None },
            Case { scenario: "trunks-posts-hedge.toml", bounds: &[ScenarioChecks], known_failure: None },
            Case { scenario: "trunks-posts.toml", bounds: &[ScenarioChecks, SwitchesAtMost(2)], known_failure: None },
            Case {
                scenario: "hedge-gappy.toml",
                bounds: HEDGE_ENVELOPE,
                known_failure: None,
            },
            Case {
                scenario: "hedge-sparse-fast.toml",
                bounds: HEDGE_ENVELOPE,
                known_failure: None,
            },
            Case {
                scenario: "hedge-ragged.toml",
                bounds: HEDGE_ENVELOPE,
                known_failure: None,
            },
            Case {
                scenario: "hedge-turned-right.toml",
                bounds: HEDGE_ENVELOPE,
                known_failure: None,
            },
            Case {
                scenario: "hedge-bushes-west.toml",
                bounds: HEDGE_ENVELOPE,
                known_failure: None,
            },
        ],
    },
    Class {
        name: "field-shapes",
        stresses: "rows along polylines, plots joined by Dubins paths, a field read from CSV",
        heading: Heading::AsFile,
        cases: &[
            Case { scenario: "rows-polyline-maize.toml", bounds: CROPS, known_failure: None },
            Case { scenario: "rows-polyline-dubins.toml", bounds: CROPS, known_failure: None },
            Case { scenario: "field-csv-maize.toml", bounds: CROPS, known_failure: None },
        ],
    },
    Class {
        name: "speed-segments",
        stresses: "a path whose segments set their own speeds, through a U-turn",
        heading: Heading::AsFile,
        cases: &[Case {
            scenario: "speed-segments-uturn.toml",
            bounds: &[ScenarioChecks],
            known_failure: None,
        }],
    },
    Class {
        name: "wheel-heading",
        stresses: "the fields above that a drifting heading breaks, with the heading from the wheels at the built-ins' 0.05 deg/s and 0.02 deg a tick instead of a gyro, aided by the fix's heading (GD-ODOMETRY-AID, 1 s, 0.5 deg/s)",
        heading: Heading::BUILTIN_WHEELS,
        cases: &[
            RANDOM_WALK,
            OFFSET_ENTRY,
            BEANS_FAST,
            Case {
                scenario: "hedge-ragged.toml",
                bounds: HEDGE_ENVELOPE,
                known_failure: None,
            },
        ],
    },
];

/// The folder of the campaign's own scenario files.
#[must_use]
pub fn files_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenarios")
        .join("stress")
}

/// The source of a case: a built-in, else a file of [`files_dir`].
///
/// # Errors
/// When neither exists or the file cannot be read.
pub fn source(scenario: &str) -> Result<Source, SimError> {
    if let Some(builtin) = Source::builtin(scenario) {
        return Ok(builtin);
    }
    Ok(Source::file(&files_dir().join(scenario))?)
}

/// The worst figure of one bound over a case's seeds.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Worst {
    /// The bound's figure at its worst seed (largest value over limit).
    pub judged: Judged,
    /// The seed it came from.
    pub seed: u64,
    /// The seeds whose run broke the bound.
    pub failed_seeds: Vec<u64>,
}

/// The outcome of one case over the seeds.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CaseResult {
    /// Why the case is known to break a bound, if it is.
    pub known_failure: Option<Known>,
    /// The seeds the known failure is expected on in this run (the known
    /// seeds among those run, or every seed run for a finding of most seeds).
    pub expected_failures: Vec<u64>,
    /// The class's name.
    pub class: &'static str,
    /// The odometry heading its runs used.
    pub heading: Heading,
    /// The scenario.
    pub scenario: &'static str,
    /// The seeds run.
    pub seeds: String,
    /// One entry per bound, in the case's order.
    pub bounds: Vec<Worst>,
    /// The seed whose run came closest to (or went furthest past) a bound:
    /// its trace and plots are kept.
    pub worst_seed: u64,
}

impl CaseResult {
    /// Whether every seed met every bound.
    #[must_use]
    pub fn pass(&self) -> bool {
        self.bounds.iter().all(|w| w.failed_seeds.is_empty())
    }

    /// The seeds that broke any bound, in order.
    #[must_use]
    pub fn failed_seeds(&self) -> Vec<u64> {
        let mut seeds: Vec<u64> = self
            .bounds
            .iter()
            .flat_map(|w| w.failed_seeds.iter().copied())
            .collect();
        seeds.sort_unstable();
        seeds.dedup();
        seeds
    }

    /// Whether the case came out as expected: holding where no failure is
    /// known; breaking a bound on some seed for a finding of most seeds;
    /// breaking one on exactly the known seeds run for a finding of a few.
    #[must_use]
    pub fn as_expected(&self) -> bool {
        match self.known_failure {
            None => self.pass(),
            Some(Known { seeds: None, .. }) => !self.pass(),
            Some(Known { seeds: Some(_), .. }) => self.failed_seeds() == self.expected_failures,
        }
    }

    /// Whether the run shows a known failure (some seed breaks a bound the
    /// case is known to break).
    #[must_use]
    pub fn shows_known_failure(&self) -> bool {
        self.known_failure.is_some() && !self.pass()
    }
}

/// How far a figure is into its limit: value / limit; against a zero
/// limit, the value itself scaled far above any ratio (so the worst of
/// several broken counts is the largest).
fn ratio(j: &Judged) -> f64 {
    if j.limit > 0.0 {
        j.value / j.limit
    } else {
        j.value * 1e9
    }
}

/// Runs one case over `seeds` (the seeds shared out over every core) and
/// calls `each` after every seed.
///
/// # Errors
/// When the scenario cannot be read or a seed's world cannot be built.
pub fn run_case(
    class: &'static str,
    heading: Heading,
    case: &Case,
    seeds: Seeds,
    mut each: impl FnMut(u64),
) -> Result<CaseResult, SimError> {
    let source = source(case.scenario)?;
    let all: Vec<u64> = seeds.iter().collect();
    let runs = crate::parallel::map_in_order(
        &all,
        |&seed| {
            let (setup, mut rng) = runner::prepare_edited(&source, seed, |f| heading.apply(f))
                .map_err(|source| SimError::AtSeed { seed, source })?;
            let run = runner::run(&setup, &mut rng);
            let summary = summarize(&setup, &run);
            Ok::<_, SimError>(
                case.bounds
                    .iter()
                    .map(|b| b.judge(&setup, &run, &summary))
                    .collect::<Vec<_>>(),
            )
        },
        |k, _| each(all.get(k).copied().unwrap_or_default()),
    );
    let per_seed: Vec<(u64, Vec<Judged>)> = all
        .iter()
        .copied()
        .zip(runs)
        .map(|(seed, r)| r.map(|j| (seed, j)))
        .collect::<Result<_, _>>()?;
    let mut bounds = Vec::with_capacity(case.bounds.len());
    for k in 0..case.bounds.len() {
        let figures = per_seed
            .iter()
            .filter_map(|(seed, judged)| judged.get(k).map(|j| (*seed, j)));
        let failed_seeds = figures
            .clone()
            .filter(|(_, j)| !j.pass())
            .map(|(seed, _)| seed)
            .collect();
        if let Some((seed, judged)) = figures.max_by(|a, b| ratio(a.1).total_cmp(&ratio(b.1))) {
            bounds.push(Worst {
                judged: judged.clone(),
                seed,
                failed_seeds,
            });
        }
    }
    let worst_seed = per_seed
        .iter()
        .map(|(seed, judged)| (*seed, judged.iter().map(ratio).fold(0.0, f64::max)))
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map_or(seeds.first(), |(seed, _)| seed);
    let expected_failures = match case.known_failure {
        None => Vec::new(),
        Some(Known { seeds: None, .. }) => all.clone(),
        Some(Known {
            seeds: Some(known), ..
        }) => all.iter().copied().filter(|s| known.contains(s)).collect(),
    };
    Ok(CaseResult {
        known_failure: case.known_failure,
        expected_failures,
        class,
        heading,
        scenario: case.scenario,
        seeds: seeds.to_string(),
        bounds,
        worst_seed,
    })
}

/// The classes whose name is `only`, or all of them.
///
/// # Errors
/// When `only` names no class.
pub fn select(only: Option<&str>) -> Result<Vec<&'static Class>, SimError> {
    match only {
        None => Ok(CLASSES.iter().collect()),
        Some(name) => CLASSES
            .iter()
            .find(|c| c.name == name)
            .map(|c| vec![c])
            .ok_or_else(|| SimError::Setup {
                what: format!(
                    "stress class `{name}` (the classes are {})",
                    CLASSES
                        .iter()
                        .map(|c| c.name)
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
                source: fieldguide::Precondition::new("STRESS", "unknown class"),
            }),
    }
}

/// Runs every case of `classes` over `seeds`, calling `each` with every
/// case's result as it is measured.
///
/// # Errors
/// As [`run_case`].
pub fn campaign(
    classes: &[&'static Class],
    seeds: Seeds,
    mut each: impl FnMut(&CaseResult),
) -> Result<Vec<CaseResult>, SimError> {
    let mut results = Vec::new();
    for class in classes {
        for case in class.cases {
            let result = run_case(class.name, class.heading, case, seeds, |_| {})?;
            each(&result);
            results.push(result);
        }
    }
    Ok(results)
}

/// Runs the worst seed of `result` again and writes its trace, summary and
/// plots to `dir/<scenario>-seed-<n>/`, with [`face_plot::FACE_FILE`] for
/// a case judged along a hedge's face; returns that folder.
///
/// # Errors
/// When the scenario cannot be built or the files cannot be written.
pub fn keep_worst(result: &CaseResult, dir: &Path) -> Result<PathBuf, SimError> {
    let source = source(result.scenario)?;
    let seed = result.worst_seed;
    let (mut setup, mut rng) = runner::prepare_edited(&source, seed, |f| result.heading.apply(f))
        .map_err(|source| SimError::AtSeed { seed, source })?;
    let wheels = match result.heading {
        Heading::AsFile => "",
        Heading::Wheels { .. } => "-wheels",
    };
    setup.name = format!("{}{wheels}-seed-{seed}", result.scenario);
    let run = runner::run(&setup, &mut rng);
    let summary = summarize(&setup, &run);
    let kept = crate::output::write_run(dir, &setup, &run, &summary)?;
    let limit = |what: &str| {
        result
            .bounds
            .iter()
            .find(|w| w.judged.what == what)
            .map(|w| w.judged.limit)
    };
    let bounds = face_plot::FaceBounds {
        followed: limit(bounds::FOLLOWED_MAX),
        towards: limit(bounds::TOWARDS),
    };
    let errors = envelope::face_errors(&setup, &run.trace);
    if let (Some(hedge), false, true) = (
        setup.world.hedges.first(),
        errors.is_empty(),
        bounds.followed.is_some() || bounds.towards.is_some(),
    ) {
        let svg = face_plot::face_svg(
            &setup.name,
            hedge.spec.length,
            &hedge.spec.gaps,
            &errors,
            bounds,
        );
        crate::output::write_files(&kept, &[(face_plot::FACE_FILE, svg)])?;
    }
    Ok(kept)
}
