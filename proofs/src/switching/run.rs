//! Replaying a sequence of inputs through the real machine under the monitor.

use fieldguide::supervisor::switching::{Input, Switching, SwitchingConfig};

use super::{Monitor, Property, Spec};

/// A property that failed, the tick at which it failed (0-based) and the
/// monitor's history at that point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Violation<const K: usize> {
    /// Index of the tick after which the property failed.
    pub tick: usize,
    /// The failed property.
    pub property: Property,
    /// The history after that tick.
    pub monitor: Monitor<K>,
}

/// Runs `inputs` through a fresh machine built from `config`, checking every
/// property against `spec` after each tick.
///
/// # Errors
/// The first violated property, with its tick.
pub fn check_run<const K: usize>(
    config: SwitchingConfig<K>,
    spec: &Spec<K>,
    inputs: impl IntoIterator<Item = Input<K>>,
) -> Result<(), Violation<K>> {
    let mut machine = Switching::new(config);
    let mut monitor = Monitor::new(spec);
    for (tick, input) in inputs.into_iter().enumerate() {
        let output = machine.step(&input);
        monitor.observe(spec, &input, &output);
        if let Some(property) = monitor.first_violation(spec) {
            return Err(Violation {
                tick,
                property,
                monitor,
            });
        }
    }
    Ok(())
}
