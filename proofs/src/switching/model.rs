//! The stateright model of the switching machine: its transitions call the
//! real `fieldguide::supervisor::switching::step`, its state is the machine's
//! state plus the [`Monitor`]'s history, and each property of
//! `spec/pierre2022.md` is an `always` check on that state.

use fieldguide::supervisor::switching::{
    step, Input, Mode, Report, SwitchingConfig, SwitchingState,
};
use fieldguide::Verdict;
use stateright::{Model, Property as StaterightProperty};

use super::{Monitor, Property, Spec};

/// What one behaviour reports in one tick, in the abstract alphabet the model
/// explores.
///
/// `Out` stands for both Exit and Absent, and a verdict that is not valid
/// carries no plan flag: every transition of the model checks that these
/// identifications change nothing (`abstraction_sound`). Continuous qualities
/// reach the machine only through the classifier, whose consistency with the
/// thresholds the classifier property test shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Sym {
    /// Enter, line consistent with the plan.
    Enter,
    /// Enter, line inconsistent with the plan.
    EnterInconsistent,
    /// Hold, line consistent with the plan.
    Hold,
    /// Hold, line inconsistent with the plan.
    HoldInconsistent,
    /// Exit or Absent: no valid estimate.
    Out,
}

impl Sym {
    /// The alphabet when plan consistency is not configured (flags are ignored).
    pub const WITHOUT_PLAN: [Self; 3] = [Self::Enter, Self::Hold, Self::Out];
    /// The alphabet when plan consistency is configured.
    pub const WITH_PLAN: [Self; 5] = [
        Self::Enter,
        Self::EnterInconsistent,
        Self::Hold,
        Self::HoldInconsistent,
        Self::Out,
    ];

    /// The concrete report the model feeds to the machine.
    #[must_use]
    pub const fn report(self) -> Report {
        let (verdict, plan_consistent) = match self {
            Self::Enter => (Verdict::Enter, true),
            Self::EnterInconsistent => (Verdict::Enter, false),
            Self::Hold => (Verdict::Hold, true),
            Self::HoldInconsistent => (Verdict::Hold, false),
            Self::Out => (Verdict::Exit, true),
        };
        Report {
            verdict,
            plan_consistent,
        }
    }
}

/// One tick of abstract input: a symbol per behaviour and the localisation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Tick<const K: usize> {
    /// The behaviours' symbols, index 0 (highest priority) first.
    pub behaviours: [Sym; K],
    /// Whether localisation is valid.
    pub localisation_valid: bool,
}

impl<const K: usize> Tick<K> {
    /// The concrete input of this tick.
    #[must_use]
    pub fn input(&self) -> Input<K> {
        Input {
            behaviours: self.behaviours.map(Sym::report),
            localisation_valid: self.localisation_valid,
        }
    }
}

/// The concrete reports one abstract symbol stands for: Exit or Absent with
/// either plan flag for an invalid estimate; either flag for a valid one when
/// plan consistency is off; itself otherwise. Returns the reports and how many
/// of the four slots are used.
fn report_variants(sym: Sym, plan_check: bool) -> ([Report; 4], usize) {
    let report = sym.report();
    let with_flag = |verdict: Verdict, plan_consistent: bool| Report {
        verdict,
        plan_consistent,
    };
    if !report.verdict.estimate_is_valid() {
        (
            [
                with_flag(Verdict::Exit, true),
                with_flag(Verdict::Exit, false),
                with_flag(Verdict::Absent, true),
                with_flag(Verdict::Absent, false),
            ],
            4,
        )
    } else if !plan_check {
        (
            [
                with_flag(report.verdict, true),
                with_flag(report.verdict, false),
                report,
                report,
            ],
            2,
        )
    } else {
        ([report; 4], 1)
    }
}

/// Calls `visit` with every concrete input the abstract tick stands for
/// (every combination of `report_variants` over the behaviours), until it
/// returns false; returns whether it never did. Allocates nothing.
pub fn all_concretisations<const K: usize>(
    tick: &Tick<K>,
    plan_check: bool,
    mut visit: impl FnMut(&Input<K>) -> bool,
) -> bool {
    let variants = tick.behaviours.map(|sym| report_variants(sym, plan_check));
    let total: usize = variants.iter().map(|(_, count)| *count).product();
    (0..total).all(|mut code| {
        let mut input = tick.input();
        for (slot, (reports, count)) in input.behaviours.iter_mut().zip(variants.iter()) {
            *slot = reports[code % count];
            code /= count;
        }
        visit(&input)
    })
}

/// Every abstract tick over `K` behaviours: each combination of symbols from
/// `alphabet`, with localisation valid and invalid.
#[must_use]
pub fn all_ticks<const K: usize>(alphabet: &[Sym]) -> Vec<Tick<K>> {
    let mut symbol_sets: Vec<[Sym; K]> = vec![[Sym::Out; K]];
    for i in 0..K {
        symbol_sets = symbol_sets
            .iter()
            .flat_map(|set| {
                alphabet.iter().map(move |&sym| {
                    let mut changed = *set;
                    changed[i] = sym;
                    changed
                })
            })
            .collect();
    }
    symbol_sets
        .into_iter()
        .flat_map(|behaviours| {
            [true, false].map(|localisation_valid| Tick {
                behaviours,
                localisation_valid,
            })
        })
        .collect()
}

/// A state of the model: the machine's state, the monitor's history, and
/// whether every concretisation of every tick so far gave the same result.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ModelState<const K: usize> {
    /// The real machine's state.
    pub machine: SwitchingState<K>,
    /// The history the properties read.
    pub monitor: Monitor<K>,
    /// False once a concretisation of an abstract tick changed the machine's
    /// state or output: the abstraction would then be unsound.
    pub abstraction_sound: bool,
}

/// The switching machine as a stateright model.
#[derive(Debug, Clone)]
pub struct SwitchingModel<const K: usize> {
    /// The configuration the real `step` runs with.
    pub config: SwitchingConfig<K>,
    /// The specified delays the properties are checked against.
    pub spec: Spec<K>,
    /// The abstract ticks explored from every state.
    pub ticks: Vec<Tick<K>>,
}

impl<const K: usize> SwitchingModel<K> {
    /// A model of `config` checked against `spec`, over the full abstract
    /// alphabet (with plan symbols when `spec` configures plan consistency).
    #[must_use]
    pub fn new(config: SwitchingConfig<K>, spec: Spec<K>) -> Self {
        let alphabet: &[Sym] = if spec.plan.is_some() {
            &Sym::WITH_PLAN
        } else {
            &Sym::WITHOUT_PLAN
        };
        Self {
            config,
            spec,
            ticks: all_ticks(alphabet),
        }
    }
}

/// The `always` check of one monitor property.
fn holds<const K: usize>(
    model: &SwitchingModel<K>,
    state: &ModelState<K>,
    property: Property,
) -> bool {
    state.monitor.holds(&model.spec, property)
}

impl<const K: usize> Model for SwitchingModel<K> {
    type State = ModelState<K>;
    type Action = Tick<K>;

    fn init_states(&self) -> Vec<Self::State> {
        vec![ModelState {
            machine: SwitchingState::initial(),
            monitor: Monitor::new(&self.spec),
            abstraction_sound: true,
        }]
    }

    fn actions(&self, _state: &Self::State, actions: &mut Vec<Self::Action>) {
        actions.extend(self.ticks.iter().copied());
    }

    fn next_state(&self, last: &Self::State, tick: Self::Action) -> Option<Self::State> {
        let input = tick.input();
        let (machine, output) = step(&self.config, &last.machine, &input);
        let abstraction_sound = last.abstraction_sound
            && all_concretisations(&tick, self.spec.plan.is_some(), |other| {
                step(&self.config, &last.machine, other) == (machine, output)
            });
        let mut monitor = last.monitor;
        monitor.observe(&self.spec, &input, &output);
        Some(ModelState {
            machine,
            monitor,
            abstraction_sound,
        })
    }

    fn properties(&self) -> Vec<StaterightProperty<Self>> {
        let mut properties = vec![
            StaterightProperty::always("SW-S1 no chattering", |m, s| {
                holds(m, s, Property::S1NoChattering)
            }),
            StaterightProperty::always("SW-S2 entry needs its delay of evidence", |m, s| {
                holds(m, s, Property::S2EntryNeedsEvidence)
            }),
            StaterightProperty::always("SW-S3 commands only from valid estimates", |m, s| {
                holds(m, s, Property::S3CommandsValid)
            }),
            StaterightProperty::always("SW-COMMAND-VALID source rule", |m, s| {
                holds(m, s, Property::CommandSourceRule)
            }),
            StaterightProperty::always("SW-S4 stop exactly after the stop delay", |m, s| {
                holds(m, s, Property::S4StopExactly)
            }),
            StaterightProperty::always("SW-L1 enter verdicts bring the mode", |m, s| {
                holds(m, s, Property::L1EnterBringsMode)
            }),
            StaterightProperty::always("SW-L2 exit verdicts bring path tracking", |m, s| {
                holds(m, s, Property::L2ExitBringsPathTracking)
            }),
            StaterightProperty::always("SW-P1 an inconsistent line is left", |m, s| {
                holds(m, s, Property::P1InconsistentLineLeft)
            }),
            StaterightProperty::always(
                "abstraction: Exit = Absent, flags of invalid estimates ignored",
                |_, s: &ModelState<K>| s.abstraction_sound,
            ),
            // Non-vacuity: the interesting situations are reached.
            StaterightProperty::sometimes(
                "reaches the highest-priority mode",
                |_, s: &ModelState<K>| s.machine.mode() == Mode::Behaviour(0),
            ),
            StaterightProperty::sometimes(
                "reaches the lowest-priority mode",
                |_, s: &ModelState<K>| s.machine.mode() == Mode::Behaviour(K.saturating_sub(1)),
            ),
            StaterightProperty::sometimes("reaches Stop", |_, s: &ModelState<K>| {
                s.machine.mode() == Mode::Stop
            }),
            StaterightProperty::sometimes(
                "path tracking steers during an exit delay",
                |_, s: &ModelState<K>| {
                    matches!(s.monitor.mode, Mode::Behaviour(_))
                        && s.monitor.source
                            == fieldguide::supervisor::switching::CommandSource::PathTracking
                },
            ),
            StaterightProperty::sometimes(
                "leaves a specialised mode for path tracking",
                |_, s: &ModelState<K>| {
                    matches!(s.monitor.prev_mode, Mode::Behaviour(_))
                        && s.monitor.mode == Mode::PathTracking
                },
            ),
        ];
        if K >= 2 {
            properties.push(StaterightProperty::sometimes(
                "hands over between two specialised modes",
                |_, s: &ModelState<K>| {
                    matches!(
                        (s.monitor.prev_mode, s.monitor.mode),
                        (Mode::Behaviour(a), Mode::Behaviour(b)) if a != b
                    )
                },
            ));
        }
        if self.spec.plan.is_some() {
            properties.push(StaterightProperty::sometimes(
                "leaves a valid but inconsistent line",
                |_, s: &ModelState<K>| {
                    matches!(s.monitor.prev_mode, Mode::Behaviour(i)
                        if s.monitor.mode != Mode::Behaviour(i)
                            && s.monitor.valid.get(i).copied().unwrap_or(false))
                },
            ));
        }
        properties
    }
}
