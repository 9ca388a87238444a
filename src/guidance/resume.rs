//! Steering before moving after a Stop (`spec/guidance.md`, GD-RESUME).
//!
//! In Stop the steering is held (GD-STOP). The first command after it may
//! want another angle: a robot stopped where the path turns, its wheels
//! straight, would roll on while a rate-limited actuator turns them, and
//! swing off the turn. Instead the wheels turn at standstill first, for path
//! tracking only: a behaviour's line, fitted from scans taken at standstill,
//! is not steered to before moving.

use crate::geometry::units::Seconds;
use crate::model::{Command, Saturated, Vehicle};

/// The wheels turning at standstill: where a rate-limited actuator started
/// from the held angle has got to, and the ticks left to settle once it has
/// reached the command.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Turning {
    steering: f64,
    settle: u16,
}

/// The command of a tick with path tracking as its source, `command`, after
/// the tick's mode changes: while turning, the command stopped (every speed zero, the
/// source's steering); `turning` starts when the previous tick was in Stop
/// and ends once the modelled steering has reached the command and settled.
//= spec/guidance.md#gd-resume-steering-before-moving-after-a-stop
//# When steering before resuming is configured and the vehicle is a bicycle
//# with a known steering rate limit, the commands of path tracking after a Stop
//# MUST keep the speed zero, with path tracking's steering angle, while an angle
//# moved from the held one towards each tick's commanded angle by the rate
//# limit times the period per tick is farther than that step from the
//# commanded angle, and for ⌈3 τ / period⌉ ticks more; the next command, and
//# every command of a behaviour, MUST be the source's as it is.
pub(super) fn command(
    turning: &mut Option<Turning>,
    was_stopped: bool,
    held: &Command,
    command: Saturated,
    vehicle: &Vehicle,
    period: Seconds,
    settle_ticks: u16,
) -> Saturated {
    let Vehicle::Bicycle(bicycle) = vehicle else {
        return command;
    };
    let (Some(rate), Some(target)) = (bicycle.max_steering_rate, command.command.steering()) else {
        return command;
    };
    if was_stopped {
        *turning = held.steering().map(|s| Turning {
            steering: s.get(),
            settle: settle_ticks,
        });
    }
    let Some(t) = turning.as_mut() else {
        return command;
    };
    let step = rate.get() * period.get();
    let gap = target.get() - t.steering;
    if gap.abs() > step {
        t.steering += step.copysign(gap);
    } else if t.settle > 0 {
        // Within one tick's step: reached (a noisy command moves a little
        // every tick); then settle.
        t.steering = target.get();
        t.settle = t.settle.saturating_sub(1);
    } else {
        *turning = None;
        return command;
    }
    Saturated {
        command: command.command.stopped(),
        saturated: command.saturated,
    }
}
