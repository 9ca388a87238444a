//! GoToGoal's Dubins paths against OMPL's Dubins state space, an
//! implementation independent of both this library and the `dubins_paths`
//! crate (`spec/emmi2024.md`, EM-DUBINS-SHORTEST): over 10 000 seeded pose
//! pairs the lengths agree to 1e-9 m and the same word is chosen except
//! where two words tie.
#![allow(
    clippy::unwrap_used,
    clippy::indexing_slicing,
    clippy::as_conversions,
    clippy::cast_precision_loss,
    clippy::arithmetic_side_effects,
    clippy::panic,
    missing_docs
)]

use core::f64::consts::PI;

use fieldguide::planning::dubins::{path_with_word, shortest, Turn, TurningRadius, Word};
use fieldguide::{Meters, Pose2, World};
use fieldguide_ompl::{Kind, OmplDubins};

/// Lengths equal to this, metres.
const TOLERANCE: f64 = 1e-9;

/// A fixed SplitMix64 sequence of uniform draws in [0, 1).
struct Draws(u64);

impl Draws {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1_u64 << 53) as f64
    }
}

fn word_of(kinds: [Kind; 3]) -> Word {
    let turn = |k: Kind| match k {
        Kind::Left => Turn::Left,
        Kind::Straight => Turn::Straight,
        Kind::Right => Turn::Right,
    };
    let turns = kinds.map(turn);
    *Word::ALL
        .iter()
        .find(|w| w.turns() == turns)
        .unwrap_or_else(|| panic!("OMPL answered {kinds:?}, not a Dubins word"))
}

fn length_of(a: &Pose2<World>, b: &Pose2<World>, r: TurningRadius, w: Word) -> Option<f64> {
    path_with_word(a, b, r, w).ok().map(|p| p.length().get())
}

//= spec/emmi2024.md#em-dubins-shortest-the-shortest-word
//= type=test
//# GoToGoal MUST return the path of least length among the words that exist;
//# among words of equal computed length it MUST return the first in the order
//# LSL, LSR, RSL, RSR, RLR, LRL.
#[test]
fn lengths_and_words_agree_with_ompl_over_ten_thousand_pairs() {
    let mut draws = Draws(2024);
    let mut worst = 0.0_f64;
    let mut ties = 0;
    let mut by_word = [0_usize; 6];
    // One OMPL state space per radius: a handful of radii, pairs spread
    // over them.
    let radii = [0.5, 0.75, 1.0, 1.48, 2.0, 3.5, 5.0];
    let mut spaces: Vec<OmplDubins> = radii.iter().map(|&r| OmplDubins::new(r).unwrap()).collect();
    for i in 0..10_000 {
        let k = i % radii.len();
        let r = TurningRadius::new(Meters::new(radii[k]).unwrap()).unwrap();
        let mut p = || {
            [
                40.0 * draws.next() - 20.0,
                40.0 * draws.next() - 20.0,
                2.0 * PI * draws.next() - PI,
            ]
        };
        let (s, g) = (p(), p());
        let a = Pose2::new(s[0], s[1], s[2]).unwrap();
        let b = Pose2::new(g[0], g[1], g[2]).unwrap();
        let ours = shortest(&a, &b, r).unwrap();
        let theirs = spaces[k].shortest(s, g).unwrap();
        let diff = (ours.length().get() - theirs.length).abs();
        worst = worst.max(diff);
        assert!(
            diff <= TOLERANCE,
            "pair {i}: ours {} m ({:?}), OMPL {} m ({:?})",
            ours.length().get(),
            ours.word(),
            theirs.length,
            theirs.kinds
        );
        let their_word = word_of(theirs.kinds);
        if their_word == ours.word() {
            by_word[Word::ALL.iter().position(|&w| w == their_word).unwrap()] += 1;
        } else {
            // A different word is only allowed for a tie: OMPL's word,
            // computed by this library, is as short.
            let alt = length_of(&a, &b, r, their_word).unwrap();
            assert!(
                (alt - ours.length().get()).abs() <= TOLERANCE,
                "pair {i}: OMPL chose {their_word:?} ({alt} m by ours), we chose {:?} ({} m)",
                ours.word(),
                ours.length().get()
            );
            ties += 1;
        }
    }
    // Non-vacuity: every word won somewhere, and ties stay rare.
    assert!(by_word.iter().all(|&n| n > 0), "words won: {by_word:?}");
    assert!(ties < 10, "{ties} ties");
    println!("worst length difference {worst:e} m, {ties} ties, words {by_word:?}");
}

/// The degenerate problems OMPL and this library both define: the same
/// pose (length 0) and a goal straight ahead (a straight line).
//= spec/emmi2024.md#em-dubins-degenerate-degenerate-problems
//= type=test
//# When the goal pose equals the start pose, GoToGoal MUST return a path of
//# length 0.
#[test]
fn degenerate_problems_agree_with_ompl() {
    let r = TurningRadius::new(Meters::new(1.5).unwrap()).unwrap();
    let mut space = OmplDubins::new(1.5).unwrap();
    for (s, g) in [
        ([1.0, 2.0, 0.3], [1.0, 2.0, 0.3]),
        ([0.0, 0.0, 0.0], [7.0, 0.0, 0.0]),
        ([0.0, 0.0, PI / 2.0], [0.0, -3.0, -PI / 2.0]),
    ] {
        let a = Pose2::new(s[0], s[1], s[2]).unwrap();
        let b = Pose2::new(g[0], g[1], g[2]).unwrap();
        let ours = shortest(&a, &b, r).unwrap().length().get();
        let theirs = space.shortest(s, g).unwrap().length;
        assert!(
            (ours - theirs).abs() <= TOLERANCE,
            "{s:?} -> {g:?}: {ours} vs {theirs}"
        );
    }
}
