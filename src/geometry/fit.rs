//! Least-squares line and parabola fits (nalgebra).
