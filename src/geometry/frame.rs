//! Frames, frame-typed points and poses, and rigid transforms between frames.
//!
//! Every frame is x forward (or east), y left (or north), z up, angles
//! counter-clockwise positive (`spec/library.md`, LIB-FRAMES). The frame is a
//! type parameter, so a robot-frame point cannot be mixed with a world-frame one.

use core::fmt::Debug;
use core::marker::PhantomData;

use super::units::{wrap_raw, Meters, Radians};
use crate::error::{finite, Precondition};

//= spec/library.md#lib-frames-frames-and-sign-conventions
//# Frames MUST be right-handed with x forward, y left and z up; world frames are
//# x east and y north.
/// A coordinate frame marker. Implemented by the uninhabited frame types below.
pub trait Frame: Copy + Debug + PartialEq + 'static {
    /// Short name of the frame, for messages.
    const NAME: &'static str;
}

macro_rules! frame {
    ($(#[$doc:meta])* $name:ident, $label:literal) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq)]
        pub enum $name {}
        impl Frame for $name {
            const NAME: &'static str = $label;
        }
    };
}

frame!(
    /// The fixed world frame (local tangent plane: x east, y north), where the
    /// reference path and GNSS poses live.
    World,
    "world"
);
frame!(
    /// The odometry frame: fixed to the ground, drifting with wheel odometry.
    Odom,
    "odom"
);
frame!(
    /// The robot frame, at the middle of the rear axle (the controlled point O of
    /// Pierre 2022, Fig. 2): x forward, y left.
    Robot,
    "robot"
);
frame!(
    /// A sensor frame (a LiDAR's own frame), placed on the robot by a mount pose.
    Sensor,
    "sensor"
);

/// A finite 2D point in frame `F`, in metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Point2<F: Frame> {
    x: f64,
    y: f64,
    frame: PhantomData<F>,
}

impl<F: Frame> Point2<F> {
    /// The point `(x, y)` in metres; non-finite coordinates are the `LIB-FINITE` error.
    pub fn new(x: f64, y: f64) -> Result<Self, Precondition> {
        Ok(Self {
            x: finite(x, "point x must be finite")?,
            y: finite(y, "point y must be finite")?,
            frame: PhantomData,
        })
    }

    /// The origin of frame `F`.
    #[must_use]
    pub const fn origin() -> Self {
        Self {
            x: 0.0,
            y: 0.0,
            frame: PhantomData,
        }
    }

    /// The point from typed coordinates (always finite, so infallible).
    #[must_use]
    pub const fn from_meters(x: Meters, y: Meters) -> Self {
        Self {
            x: x.get(),
            y: y.get(),
            frame: PhantomData,
        }
    }

    /// x coordinate in metres.
    #[must_use]
    pub const fn x(self) -> f64 {
        self.x
    }

    /// y coordinate in metres.
    #[must_use]
    pub const fn y(self) -> f64 {
        self.y
    }

    /// Euclidean distance to `other`, in metres (`hypot`, so no intermediate
    /// overflow). Errors with `LIB-FINITE` when the distance itself overflows
    /// (points near `±f64::MAX` apart).
    pub fn distance_to(self, other: Self) -> Result<Meters, Precondition> {
        Meters::new(libm::hypot(other.x - self.x, other.y - self.y))
    }

    /// The mirror image about the x axis (left and right swapped).
    #[must_use]
    pub fn mirrored(self) -> Self {
        Self {
            x: self.x,
            y: -self.y,
            frame: PhantomData,
        }
    }
}

/// A finite pose (position and heading) in frame `F`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose2<F: Frame> {
    /// Position, in metres.
    pub position: Point2<F>,
    /// Heading of the body's x axis, counter-clockwise from the frame's x axis.
    pub heading: Radians,
}

impl<F: Frame> Pose2<F> {
    /// A pose from raw values; non-finite values are the `LIB-FINITE` error.
    /// The heading is wrapped to (−π, π].
    pub fn new(x: f64, y: f64, heading: f64) -> Result<Self, Precondition> {
        Ok(Self {
            position: Point2::new(x, y)?,
            heading: Radians::new(heading)?.wrapped(),
        })
    }

    /// The transform taking points of the body `B` placed at this pose into frame `F`.
    #[must_use]
    pub fn body_to_frame<B: Frame>(self) -> Transform2<B, F> {
        Transform2::from_parts(self.position.x, self.position.y, self.heading.get())
    }
}

/// A rigid transform taking points expressed in frame `A` into frame `B`:
/// `p_B = R(θ) p_A + t`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transform2<A: Frame, B: Frame> {
    cos: f64,
    sin: f64,
    tx: f64,
    ty: f64,
    frames: PhantomData<(A, B)>,
}

impl<A: Frame, B: Frame> Transform2<A, B> {
    /// The transform rotating by `angle` (radians) then translating by `(tx, ty)` metres.
    fn from_parts(tx: f64, ty: f64, angle: f64) -> Self {
        Self {
            cos: libm::cos(angle),
            sin: libm::sin(angle),
            tx,
            ty,
            frames: PhantomData,
        }
    }

    /// The transform of origin `(tx, ty)` and rotation `angle`; non-finite input is an error.
    pub fn new(tx: f64, ty: f64, angle: f64) -> Result<Self, Precondition> {
        Ok(Self::from_parts(
            finite(tx, "transform translation x must be finite")?,
            finite(ty, "transform translation y must be finite")?,
            finite(angle, "transform angle must be finite")?,
        ))
    }

    /// The rotation angle, wrapped to (−π, π].
    #[must_use]
    pub fn angle(&self) -> Radians {
        Radians(wrap_raw(libm::atan2(self.sin, self.cos)))
    }

    /// The image in `B` of a point of `A`. Errors only if the result overflows.
    pub fn apply(&self, p: Point2<A>) -> Result<Point2<B>, Precondition> {
        Point2::new(
            self.cos * p.x - self.sin * p.y + self.tx,
            self.sin * p.x + self.cos * p.y + self.ty,
        )
    }

    /// The image in `B` of a heading expressed in `A`, wrapped to (−π, π].
    #[must_use]
    pub fn apply_heading(&self, heading: Radians) -> Radians {
        Radians(wrap_raw(heading.get() + libm::atan2(self.sin, self.cos)))
    }

    /// The image in `B` of a pose of `A`. Errors only if the position overflows.
    pub fn apply_pose(&self, pose: Pose2<A>) -> Result<Pose2<B>, Precondition> {
        Ok(Pose2 {
            position: self.apply(pose.position)?,
            heading: self.apply_heading(pose.heading),
        })
    }

    /// The inverse transform, from `B` back to `A`. Errors only on overflow.
    pub fn inverse(&self) -> Result<Transform2<B, A>, Precondition> {
        Ok(Transform2 {
            cos: self.cos,
            sin: -self.sin,
            tx: finite(
                -(self.cos * self.tx + self.sin * self.ty),
                "inverse translation x overflows",
            )?,
            ty: finite(
                self.sin * self.tx - self.cos * self.ty,
                "inverse translation y overflows",
            )?,
            frames: PhantomData,
        })
    }

    /// `other ∘ self`: first `self` (A → B), then `other` (B → C).
    pub fn then<C: Frame>(
        &self,
        other: &Transform2<B, C>,
    ) -> Result<Transform2<A, C>, Precondition> {
        Ok(Transform2 {
            cos: other.cos * self.cos - other.sin * self.sin,
            sin: other.sin * self.cos + other.cos * self.sin,
            tx: finite(
                other.cos * self.tx - other.sin * self.ty + other.tx,
                "composed translation x overflows",
            )?,
            ty: finite(
                other.sin * self.tx + other.cos * self.ty + other.ty,
                "composed translation y overflows",
            )?,
            frames: PhantomData,
        })
    }
}
