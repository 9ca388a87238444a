//! Bolero harness over Emmi 2024's linear speed controller
//! (`control::speed_profile`): every sequence of 8 ticks over five moves
//! (standing, creeping 2 cm, 10 cm, 0.5 m, and 10 cm back, as a GNSS jump)
//! along a 3 m path, checked exhaustively here (`check!().exhaustive()`),
//! and a Kani proof wherever Kani is installed
//! (`cargo kani -p fieldguide-proofs --tests`). After every tick: the speed
//! lies within [v_th, v_d], braking never speeds up beyond where it started,
//! Stop comes exactly when the remaining distance is within the reach
//! distance or after an earlier Stop, and never ends.
#![allow(clippy::unwrap_used, clippy::panic, clippy::float_cmp)]

use std::sync::atomic::{AtomicU64, Ordering};

use bolero::{check, generator::TypeGenerator};
use fieldguide::control::speed_profile::{Braking, SpeedCommand, SpeedProfile, SpeedState};
use fieldguide::{Meters, MetersPerSecond};
use fieldguide_proofs::evidence::{self, Kind};

/// Ticks per sequence.
const DEPTH: usize = 8;
/// The path's length, metres.
const LENGTH: f64 = 3.0;

/// How far the robot moves along the path in one tick.
#[derive(Clone, Copy, Debug, TypeGenerator)]
enum Move {
    Stand,
    Creep,
    Step,
    Stride,
    Back,
}

impl Move {
    const fn metres(self) -> f64 {
        match self {
            Self::Stand => 0.0,
            Self::Creep => 0.02,
            Self::Step => 0.1,
            Self::Stride => 0.5,
            Self::Back => -0.1,
        }
    }
}

fn profile(braking: Braking) -> SpeedProfile {
    SpeedProfile::new(
        MetersPerSecond::new(0.1).unwrap(),
        MetersPerSecond::new(0.5).unwrap(),
        Meters::new(1.0).unwrap(),
        braking,
        Meters::new(0.05).unwrap(),
    )
    .unwrap()
}

fn run(p: &SpeedProfile, moves: &[Move; DEPTH]) {
    let (mut state, mut travelled, mut stopped) = (SpeedState::Moving, 0.0_f64, false);
    for m in moves {
        travelled += m.metres();
        let remaining = LENGTH - travelled;
        let before = state;
        let (next, command) = p.step(
            state,
            Meters::new(travelled).unwrap(),
            Meters::new(remaining).unwrap(),
        );
        state = next;
        match command {
            SpeedCommand::Stop => {
                assert!(stopped || remaining <= 0.05, "{moves:?}");
                assert_eq!(state, SpeedState::Reached);
                stopped = true;
            }
            SpeedCommand::Go(v) => {
                assert!(!stopped && remaining > 0.05, "{moves:?}");
                assert!((0.1..=0.5).contains(&v.get()), "{moves:?}: {v:?}");
                if let SpeedState::Braking { from, .. } = before {
                    assert!(v.get() <= from.get(), "{moves:?}");
                }
                if state == SpeedState::Moving {
                    assert_eq!(v, p.ramp_speed(Meters::new(travelled).unwrap()));
                }
            }
        }
    }
}

//= spec/emmi2024.md#em-speed-reach-goal-reached
//= type=test
//# The goal MUST count as reached, and the command MUST be Stop from then on,
//# once the remaining distance is at most the reach distance (0.05 m by
//# default), which includes being level with the goal or past it.
//= spec/emmi2024.md#em-speed-brake-braking-ramp
//= type=test
//# Once the remaining distance is at most the braking distance d_b of the
//# current speed v_c, the speed MUST be v_th + (v_c − v_th) min(max(r / d_b,
//# 0), 1) for a remaining distance r, with v_c and d_b those of the tick
//# braking started.
#[test]
#[cfg_attr(kani, kani::proof, kani::unwind(9))]
fn every_move_sequence_keeps_the_speed_profile_safe() {
    let fixed = profile(Braking::Fixed(Meters::new(1.0).unwrap()));
    let proportional = profile(Braking::Proportional(
        fieldguide::Seconds::new(3.0).unwrap(),
    ));
    let record = evidence::start("speed profile, every move sequence", Kind::Harness);
    let count = AtomicU64::new(0);
    check!()
        .with_type::<[Move; DEPTH]>()
        .exhaustive()
        .for_each(|moves| {
            count.fetch_add(1, Ordering::Relaxed);
            run(&fixed, moves);
            run(&proportional, moves);
        });
    record.finish(&evidence::harness(
        &["EM-SPEED-REACH", "EM-SPEED-BRAKE"],
        count.into_inner(),
        u64::try_from(DEPTH).ok(),
    ));
}
