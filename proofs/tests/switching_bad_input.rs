//! Bad input for the switching machine: verdicts that flip every
//! tick, localisation lost in the middle of a plot, both detectors reporting
//! at once, and configurations that must be refused. In every run the machine
//! stays in a defined mode and the monitor checks every property after every
//! tick; the tests also pin the exact tick of each change, computed by hand
//! from Tables 1-2 at 100 Hz (edge 40 / 26 ticks, furrow 50 / 30, Stop 20).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use fieldguide::perception::{Better, QualityThresholds};
use fieldguide::supervisor::switching::{
    BehaviourConfig, CommandSource, Input, Mode, Output, Report, Switching, SwitchingConfig,
    MAX_BEHAVIOURS,
};
use fieldguide::{Meters, Radians, Seconds, Verdict};
use fieldguide_proofs::switching::{Monitor, Spec, EDGE_MS, FURROW_MS};

/// A machine and its monitor, stepped together; every property is asserted
/// after every tick.
struct Run<const K: usize> {
    machine: Switching<K>,
    monitor: Monitor<K>,
    spec: Spec<K>,
    ticks: usize,
}

impl<const K: usize> Run<K> {
    fn new(behaviours: [(BehaviourConfig, (u32, u32)); K]) -> Self {
        let config = SwitchingConfig::new(
            Seconds::new(0.01).unwrap(),
            behaviours.map(|(b, _)| b),
            Seconds::new(0.2).unwrap(),
            None,
        )
        .unwrap();
        let spec = Spec::from_millis(10, behaviours.map(|(_, ms)| ms), 200, None);
        Self {
            machine: Switching::new(config),
            monitor: Monitor::new(&spec),
            spec,
            ticks: 0,
        }
    }

    fn step(&mut self, verdicts: [Verdict; K], localisation_valid: bool) -> Output {
        let input = Input {
            behaviours: verdicts.map(Report::consistent),
            localisation_valid,
        };
        let output = self.machine.step(&input);
        self.monitor.observe(&self.spec, &input, &output);
        self.ticks += 1;
        assert_eq!(
            self.monitor.first_violation(&self.spec),
            None,
            "tick {}: {:?}",
            self.ticks,
            self.monitor
        );
        match output.mode {
            Mode::Behaviour(i) => assert!(i < K, "undefined mode {:?}", output.mode),
            Mode::PathTracking | Mode::Stop => {}
        }
        output
    }

    /// Steps `n` times with the same input; returns the outputs.
    fn repeat(&mut self, n: usize, verdicts: [Verdict; K], localisation: bool) -> Vec<Output> {
        (0..n).map(|_| self.step(verdicts, localisation)).collect()
    }
}

fn edge() -> (BehaviourConfig, (u32, u32)) {
    (BehaviourConfig::edge_following().unwrap(), EDGE_MS)
}

fn furrow() -> (BehaviourConfig, (u32, u32)) {
    (BehaviourConfig::furrow_pursuing().unwrap(), FURROW_MS)
}

use Verdict::{Absent, Enter, Exit, Hold};

//= spec/pierre2022.md#sw-enter-entering-a-specialised-mode
//= type=test
//# A tick MUST count as entry evidence for a behaviour only when its verdict is
//# Enter and, when plan consistency is configured, its line is consistent with
//# the planned path; any other verdict, Hold included, MUST restart the count.
#[test]
fn verdicts_flipping_every_tick_never_enter() {
    // Enter, Exit, Enter, ...: the entry run never exceeds 1 tick.
    let mut run = Run::new([edge()]);
    for tick in 0..1_000 {
        let verdict = if tick % 2 == 0 { Enter } else { Exit };
        let out = run.step([verdict], true);
        assert_eq!(out.mode, Mode::PathTracking);
        assert_eq!(out.source, CommandSource::PathTracking);
    }
    // Enter and Hold alternating: Hold restarts the count (SW-ENTER).
    for tick in 0..1_000 {
        let verdict = if tick % 2 == 0 { Enter } else { Hold };
        assert_eq!(run.step([verdict], true).mode, Mode::PathTracking);
    }
}

//= spec/pierre2022.md#sw-exit-leaving-a-specialised-mode
//= type=test
//# In a specialised mode, a tick MUST count as exit evidence when the active
//# behaviour's verdict is Exit or Absent, and any Enter or Hold verdict MUST
//# restart that count.
#[test]
fn verdicts_flipping_every_tick_inside_a_plot_never_leave() {
    let mut run = Run::new([edge()]);
    let entered = run.repeat(40, [Enter], true);
    assert_eq!(entered[38].mode, Mode::PathTracking);
    assert_eq!(entered[39].mode, Mode::Behaviour(0));
    // Hold, Absent, Hold, ...: the exit run never exceeds 1 tick, the mode
    // stays; the command alternates between edge following and path tracking.
    for tick in 0..1_000 {
        let (verdict, source) = if tick % 2 == 0 {
            (Hold, CommandSource::Behaviour(0))
        } else {
            (Absent, CommandSource::PathTracking)
        };
        let out = run.step([verdict], true);
        assert_eq!(out.mode, Mode::Behaviour(0));
        assert_eq!(out.source, source);
    }
}

//= spec/pierre2022.md#sw-stop-stop-without-a-valid-source
//= type=test
//# The machine MUST stay in Stop until localisation is valid, then go to path
//# tracking, or until a behaviour's entry evidence has lasted its entry delay,
//# then go to its mode.
#[test]
fn localisation_lost_in_the_middle_of_a_plot() {
    let mut run = Run::new([furrow()]);
    run.repeat(50, [Enter], true);
    assert_eq!(run.machine.mode(), Mode::Behaviour(0));
    // GNSS lost for 10 s while the rows are seen: furrow pursuing steers.
    for out in run.repeat(1_000, [Hold], false) {
        assert_eq!(out.mode, Mode::Behaviour(0));
        assert_eq!(out.source, CommandSource::Behaviour(0));
    }
    // Then the rows end too: no source; Stop at the 20th tick (0.2 s),
    // before the 30-tick exit delay has elapsed.
    let lost = run.repeat(20, [Absent], false);
    assert!(lost[..19]
        .iter()
        .all(|o| o.mode == Mode::Behaviour(0) && o.source == CommandSource::None));
    assert_eq!(lost[19].mode, Mode::Stop);
    // Stop holds while nothing returns, even with the rows held again (Hold
    // does not restart from a stop, SW-STOP).
    for out in run.repeat(100, [Hold], false) {
        assert_eq!(
            out,
            Output {
                mode: Mode::Stop,
                source: CommandSource::None
            }
        );
    }
    // GNSS returns: path tracking at once.
    assert_eq!(
        run.step([Absent], true),
        Output {
            mode: Mode::PathTracking,
            source: CommandSource::PathTracking
        }
    );
}

#[test]
fn localisation_lost_in_a_plot_then_the_rows_resume_from_stop() {
    let mut run = Run::new([edge()]);
    run.repeat(40, [Enter], true);
    run.repeat(20, [Absent], false);
    assert_eq!(run.machine.mode(), Mode::Stop);
    // Without GNSS, only a complete entry ends the Stop: 40 Enter ticks.
    let back = run.repeat(40, [Enter], false);
    assert!(back[..39].iter().all(|o| o.mode == Mode::Stop));
    assert_eq!(
        back[39],
        Output {
            mode: Mode::Behaviour(0),
            source: CommandSource::Behaviour(0)
        }
    );
}

#[test]
fn both_detectors_reporting_at_once() {
    // Edge (index 0) has priority over furrow (index 1).
    let mut run = Run::new([edge(), furrow()]);
    let both = run.repeat(60, [Enter, Enter], true);
    assert!(both[..39].iter().all(|o| o.mode == Mode::PathTracking));
    assert!(both[39..]
        .iter()
        .all(|o| o.mode == Mode::Behaviour(0) && o.source == CommandSource::Behaviour(0)));
    // The edge is lost while the furrow is still seen: after the 26-tick exit
    // delay the furrow, whose entry is complete, takes over directly.
    let edge_lost = run.repeat(26, [Exit, Enter], true);
    assert!(edge_lost[..25]
        .iter()
        .all(|o| o.mode == Mode::Behaviour(0) && o.source == CommandSource::PathTracking));
    assert_eq!(
        edge_lost[25],
        Output {
            mode: Mode::Behaviour(1),
            source: CommandSource::Behaviour(1)
        }
    );
    // The edge reappears: it takes the mode back after its full entry delay.
    let edge_back = run.repeat(40, [Enter, Hold], true);
    assert!(edge_back[..39].iter().all(|o| o.mode == Mode::Behaviour(1)));
    assert_eq!(edge_back[39].mode, Mode::Behaviour(0));
}

#[test]
fn a_higher_priority_entry_under_way_makes_a_faster_lower_one_wait() {
    // Furrow first (index 0, 50 ticks), edge second (index 1, 40 ticks).
    let mut run = Run::new([furrow(), edge()]);
    let both = run.repeat(50, [Enter, Enter], true);
    // The edge's entry completes at tick 40 but the furrow's is under way.
    assert!(both[..49].iter().all(|o| o.mode == Mode::PathTracking));
    assert_eq!(both[49].mode, Mode::Behaviour(0));

    // Had the furrow stopped at tick 45, the edge enters in that tick.
    let mut run = Run::new([furrow(), edge()]);
    run.repeat(44, [Enter, Enter], true);
    assert_eq!(run.machine.mode(), Mode::PathTracking);
    assert_eq!(run.step([Hold, Enter], true).mode, Mode::Behaviour(1));
}

//= spec/pierre2022.md#sw-modes-modes-and-priority
//= type=test
//# The switching machine MUST have exactly these modes: path tracking, one
//# specialised mode per configured specialised behaviour, and Stop; it MUST
//# start in path tracking.
#[test]
fn every_mode_stays_defined_under_arbitrary_noise() {
    // A deterministic pseudo-random walk: segments of 1 to 80 ticks, each with
    // its own verdicts and localisation, 200 000 ticks in all.
    let mut run = Run::new([edge(), furrow()]);
    assert_eq!(run.machine.mode(), Mode::PathTracking);
    let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut next = move || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        x
    };
    let verdicts = [Enter, Hold, Exit, Absent];
    let mut visits = [0usize; 4];
    while run.ticks < 200_000 {
        let r = next();
        let pick = |shift: u32| verdicts[usize::try_from((r >> shift) & 3).unwrap()];
        let v = [pick(0), pick(2)];
        let localisation = (r >> 4) % 4 != 0;
        let length = 1 + (r >> 8) % 80;
        for _ in 0..length {
            let out = run.step(v, localisation);
            let slot = match out.mode {
                Mode::PathTracking => 0,
                Mode::Behaviour(i) => 1 + i,
                Mode::Stop => 3,
            };
            visits[slot] += 1;
        }
    }
    // The walk is not vacuous: every mode is visited.
    assert!(visits.iter().all(|&n| n > 1_000), "{visits:?}");
}

#[test]
fn misordered_thresholds_are_refused() {
    // Exit threshold above the entry one for a residual (smaller is better)...
    let error = QualityThresholds::new(0.5, 0.15, Better::Lower).unwrap_err();
    assert_eq!(error.requirement, "SW-THRESHOLDS");
    // ... below it for a correlation (larger is better), equal, or NaN.
    for (enter, exit, better) in [
        (0.2, 0.4, Better::Higher),
        (0.3, 0.3, Better::Lower),
        (0.3, 0.3, Better::Higher),
        (f64::NAN, 0.5, Better::Lower),
        (0.15, f64::INFINITY, Better::Lower),
    ] {
        let error = QualityThresholds::new(enter, exit, better).unwrap_err();
        assert_eq!(error.requirement, "SW-THRESHOLDS");
    }
}

//= spec/pierre2022.md#sw-modes-modes-and-priority
//= type=test
//# The specialised behaviours MUST be configured in priority order, index 0
//# being the highest priority, and a configuration with no specialised
//# behaviour or with more than `MAX_BEHAVIOURS` (8) MUST be refused at
//# construction with an error naming this requirement.
//= spec/pierre2022.md#sw-delays-transit-delays-in-control-ticks
//= type=test
//# A non-positive control period or delay, or a delay longer than 65 535
//# ticks, MUST be refused at construction with an error naming the
//# requirement that owns the delay.
#[test]
fn bad_configurations_are_refused_naming_the_requirement() {
    let s = |v: f64| Seconds::new(v).unwrap();
    let edge = BehaviourConfig::edge_following().unwrap();
    let requirement =
        |r: Result<SwitchingConfig<1>, fieldguide::Precondition>| r.unwrap_err().requirement;

    let none: [BehaviourConfig; 0] = [];
    assert_eq!(
        SwitchingConfig::new(s(0.01), none, s(0.2), None)
            .unwrap_err()
            .requirement,
        "SW-MODES"
    );
    let too_many = [edge; MAX_BEHAVIOURS + 1];
    assert_eq!(
        SwitchingConfig::new(s(0.01), too_many, s(0.2), None)
            .unwrap_err()
            .requirement,
        "SW-MODES"
    );
    assert!(SwitchingConfig::new(s(0.01), [edge; MAX_BEHAVIOURS], s(0.2), None).is_ok());

    for period in [0.0, -0.01] {
        assert_eq!(
            requirement(SwitchingConfig::new(s(period), [edge], s(0.2), None)),
            "SW-DELAYS"
        );
    }
    for delay in [0.0, -0.4] {
        let e = BehaviourConfig::new(s(delay), s(0.26)).unwrap_err();
        assert_eq!(
            (e.requirement, e.violated),
            ("SW-DELAYS", "enter_delay must be positive")
        );
        let e = BehaviourConfig::new(s(0.4), s(delay)).unwrap_err();
        assert_eq!(
            (e.requirement, e.violated),
            ("SW-DELAYS", "exit_delay must be positive")
        );
    }
    // 1000 s at 1 kHz is 10⁶ ticks: too long; a tiny period likewise.
    let slow = BehaviourConfig::new(s(1000.0), s(0.26)).unwrap();
    assert_eq!(
        requirement(SwitchingConfig::new(s(0.001), [slow], s(0.2), None)),
        "SW-DELAYS"
    );
    assert_eq!(
        requirement(SwitchingConfig::new(s(1e-300), [edge], s(0.2), None)),
        "SW-DELAYS"
    );
    assert_eq!(
        requirement(SwitchingConfig::new(s(0.01), [edge], s(0.0), None)),
        "SW-STOP"
    );
    assert_eq!(
        requirement(SwitchingConfig::new(s(0.01), [edge], s(1e6), None)),
        "SW-STOP"
    );
    assert_eq!(
        requirement(SwitchingConfig::new(s(0.01), [edge], s(0.2), Some(s(-1.0)))),
        "SW-PLAN-CONSISTENCY"
    );

    use fieldguide::supervisor::switching::PlanTolerance;
    let m = |v: f64| Meters::new(v).unwrap();
    let r = |v: f64| Radians::new(v).unwrap();
    for (offset, heading) in [(-0.1, 0.2), (0.3, -0.1), (0.3, 3.2)] {
        let e = PlanTolerance::new(m(offset), r(heading)).unwrap_err();
        assert_eq!(e.requirement, "SW-PLAN-CONSISTENCY");
    }
}
