//! Crop rows from a horizontal LiDAR without GNSS (Guyonneau, Mercier,
//! Oliveira Freitas 2022, sections 2 and 3.1-3.2; `spec/guyonneau2022.md`).
//!
//! The data flow of one scan:
//!
//! 1. [`points`]: the scan's rays become robot-frame points through the
//!    sensor's mount (ROWS-POINTS); with the one-point refinement, runs of
//!    consecutive points closer than a merge distance become one (Alg. 2,
//!    RUBY-ONE-POINT);
//! 2. [`ruby`]: Ruby's energy minimisation (Alg. 1, eqs. 1-9) and its
//!    refinements RG, RGOP, RGOPPN, RGOPPNI (eq. 10, Algs. 2-3) fit a set of
//!    lines, seeded by the previous scan's set;
//! 3. [`spacing`]: before the robot moves, the distance between rows from
//!    the closest pair of lines either side of the robot (eqs. 13-14);
//! 4. [`filter`]: n expected rows kept from scan to scan, the missing ones
//!    computed from the found ones (Alg. 4, eqs. 15-17), and the verdict.
//!
//! Frames: the library's robot frame, x forward, y left (LIB-FRAMES); the
//! paper's eqs. 11-12 call y < 0 "left" (ROWS-FRAME).

pub mod filter;
pub mod points;
pub mod ruby;
pub mod spacing;
