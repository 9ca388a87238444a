//! OMPL's Dubins state space (`ompl::base::DubinsStateSpace`, Shkel and
//! Lumelsky 2001) as an independent oracle for fieldguide's Dubins planner
//! and as a peer in its benchmark (Emmi 2024, section 3.3.1; EM-DUBINS-*).
//!
//! Test and benchmark code only: the core does not depend on it. It needs
//! Debian's `libompl-dev`.

use core::ffi::{c_double, c_int};
use core::ptr::NonNull;

/// The handle the C++ shim allocates.
#[repr(C)]
struct Shim {
    _private: [u8; 0],
}

extern "C" {
    fn fg_ompl_dubins_new(radius: c_double) -> *mut Shim;
    fn fg_ompl_dubins_free(d: *mut Shim);
    #[allow(clippy::too_many_arguments)]
    fn fg_ompl_dubins_shortest(
        d: *mut Shim,
        x0: c_double,
        y0: c_double,
        h0: c_double,
        x1: c_double,
        y1: c_double,
        h1: c_double,
        kinds: *mut c_int,
        lengths: *mut c_double,
    ) -> c_double;
}

/// One segment kind of a Dubins path, as OMPL names them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// A left (counter-clockwise) arc.
    Left,
    /// A straight line.
    Straight,
    /// A right (clockwise) arc.
    Right,
}

/// The shortest path OMPL finds between two poses.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OmplPath {
    /// The three segments' kinds, in driving order.
    pub kinds: [Kind; 3],
    /// The three segments' lengths, metres.
    pub lengths: [f64; 3],
    /// The total length, metres.
    pub length: f64,
}

/// Why OMPL gave no answer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OmplError {
    /// The state space could not be created.
    Create,
    /// OMPL threw an exception, or named a segment kind it does not define.
    Failed,
}

/// OMPL's Dubins state space for one turning radius.
pub struct OmplDubins {
    shim: NonNull<Shim>,
}

impl OmplDubins {
    /// A state space with this turning radius, metres.
    ///
    /// # Errors
    /// [`OmplError::Create`] when the shim could not allocate it.
    pub fn new(radius: f64) -> Result<Self, OmplError> {
        // SAFETY: the shim's constructor takes a plain double and returns an
        // owned pointer or null; it catches every C++ exception.
        let raw = unsafe { fg_ompl_dubins_new(radius) };
        NonNull::new(raw)
            .map(|shim| Self { shim })
            .ok_or(OmplError::Create)
    }

    /// The shortest path from `start` to `goal`, each (x, y, heading) in
    /// metres and radians.
    ///
    /// # Errors
    /// [`OmplError::Failed`] when OMPL threw or answered a kind outside 0-2.
    pub fn shortest(&mut self, start: [f64; 3], goal: [f64; 3]) -> Result<OmplPath, OmplError> {
        let mut kinds: [c_int; 3] = [0; 3];
        let mut lengths = [0.0_f64; 3];
        let [x0, y0, h0] = start;
        let [x1, y1, h1] = goal;
        // SAFETY: `self.shim` came from `fg_ompl_dubins_new` and is not freed
        // before `drop`; `&mut self` makes this the only call on it now; the
        // two out-pointers address arrays of three elements, as the shim
        // writes.
        let length = unsafe {
            fg_ompl_dubins_shortest(
                self.shim.as_ptr(),
                x0,
                y0,
                h0,
                x1,
                y1,
                h1,
                kinds.as_mut_ptr(),
                lengths.as_mut_ptr(),
            )
        };
        if length < 0.0 {
            return Err(OmplError::Failed);
        }
        let kind = |k: c_int| match k {
            0 => Ok(Kind::Left),
            1 => Ok(Kind::Straight),
            2 => Ok(Kind::Right),
            _ => Err(OmplError::Failed),
        };
        let [a, b, c] = kinds;
        Ok(OmplPath {
            kinds: [kind(a)?, kind(b)?, kind(c)?],
            lengths,
            length,
        })
    }
}

impl Drop for OmplDubins {
    fn drop(&mut self) {
        // SAFETY: the pointer came from `fg_ompl_dubins_new` and is freed
        // once, here.
        unsafe { fg_ompl_dubins_free(self.shim.as_ptr()) }
    }
}
