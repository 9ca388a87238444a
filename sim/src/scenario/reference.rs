//! The reference path of a scenario: straight and arc segments sampled into
//! waypoints (as if recorded by driving), or waypoints read from a CSV file.

use std::path::Path;

use super::check::Checker;
use fieldguide::planning::dubins::{shortest, DubinsPath, TurningRadius};
use fieldguide::{Meters, Pose2, World};

use super::schema::{AlongPlots, JoinName, PathSection, Segment, StartPose};
use crate::error::ScenarioError;
use crate::rng::SimRng;
use crate::world::crops::PlotSpec;

/// What kind of nominal piece a stretch of the path is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PieceKind {
    /// A straight line.
    Straight,
    /// A circular arc of signed curvature (1/m, positive to the left).
    Arc {
        /// Signed curvature, 1/m.
        curvature: f64,
    },
}

/// One segment of the nominal path and the abscissa interval it covers.
///
/// [`waypoints`] gives nominal abscissas; [`crate::scenario::build`] replaces
/// them by the abscissas of the end points projected on the recorded path
/// (which the recording noise makes slightly longer).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Piece {
    /// Straight or arc.
    pub kind: PieceKind,
    /// Abscissa where it starts, metres.
    pub s_start: f64,
    /// Abscissa where it ends, metres.
    pub s_end: f64,
    /// Nominal start point `[x, y]`, world frame, metres.
    pub start: [f64; 2],
    /// Nominal end point `[x, y]`, world frame, metres.
    pub end: [f64; 2],
}

/// Waypoints of the reference path before it is built by the core, and the
/// nominal pieces they came from (empty for a CSV path).
#[derive(Debug, Clone, PartialEq)]
pub struct Waypoints {
    /// Waypoints `[x, y]` in the world frame, metres (noise included).
    pub points: Vec<[f64; 2]>,
    /// Nominal pieces, in order (segment paths only).
    pub pieces: Vec<Piece>,
}

/// The nominal abscissa intervals `(s_start, s_end)` of the straight pieces.
#[must_use]
pub fn straight_intervals(pieces: &[Piece]) -> Vec<(f64, f64)> {
    pieces
        .iter()
        .filter(|p| p.kind == PieceKind::Straight)
        .map(|p| (p.s_start, p.s_end))
        .collect()
}

/// The waypoints of `[path]`: sampled segments, or the centre lines of
/// `plots` (the world's plots, in order), plus recording noise; or the CSV
/// file (relative to `base_dir`, the scenario file's folder; none for a
/// built-in scenario); at most `capacity` of them.
pub fn waypoints(
    section: &PathSection,
    plots: &[PlotSpec],
    min_turn_radius: f64,
    capacity: usize,
    base_dir: Option<&Path>,
    check: &Checker<'_>,
    rng: &mut SimRng,
) -> Result<Waypoints, ScenarioError> {
    let step = check.positive("path.sample_step_m", section.sample_step_m)?;
    let noise = check.range(
        "path.recording_noise_m",
        section.recording_noise_m,
        0.0,
        1.0,
    )?;
    let mut w = match (&section.segments, &section.csv, &section.along_plots) {
        (Some(segments), None, None) => {
            let Some(start) = section.start else {
                return Err(check.error("path.start", "required with `path.segments`"));
            };
            sample_segments(start, segments, plots, step, capacity, check)?
        }
        (None, Some(csv), None) => {
            if section.start.is_some() {
                return Err(check.error("path.start", "not allowed with `path.csv`"));
            }
            let text = read_csv(csv, base_dir, check)?;
            let points = parse_csv(&text, check)?;
            if points.len() > capacity {
                return Err(check.error("path.csv", &format!("more than {capacity} waypoints")));
            }
            Waypoints {
                points,
                pieces: Vec::new(),
            }
        }
        (None, None, Some(along)) => {
            if section.start.is_some() {
                return Err(check.error("path.start", "not allowed with `path.along_plots`"));
            }
            sample_along_plots(along, plots, min_turn_radius, step, capacity, check)?
        }
        _ => {
            return Err(check.error(
                "path",
                "give exactly one of `segments`, `csv` and `along_plots`",
            ))
        }
    };
    for p in &mut w.points {
        p[0] += rng.gaussian(noise);
        p[1] += rng.gaussian(noise);
    }
    Ok(w)
}

/// A path down the true centre line of each plot, sampled every `step`
/// metres, joined by straight lines (or Dubins paths of the turning radius,
/// `min_turn_radius` by default: the vehicle's least), with a straight lead-in before the first
/// plot and a run-out after the last, along their headings. Every piece is
/// `Straight` (the rows' bend is slight). The plots must follow one another:
/// each starts ahead of where the previous one ends.
fn sample_along_plots(
    along: &AlongPlots,
    plots: &[PlotSpec],
    min_turn_radius: f64,
    step: f64,
    capacity: usize,
    check: &Checker<'_>,
) -> Result<Waypoints, ScenarioError> {
    let lead_in = check.range("path.along_plots.lead_in_m", along.lead_in_m, 0.0, 1000.0)?;
    let run_out = check.range("path.along_plots.run_out_m", along.run_out_m, 0.0, 1000.0)?;
    let radius = match (along.join, along.turning_radius_m) {
        (JoinName::Dubins, Some(r)) => Some(check.range(
            "path.along_plots.turning_radius_m",
            r,
            min_turn_radius,
            1000.0,
        )?),
        (JoinName::Dubins, None) => Some(min_turn_radius),
        (JoinName::Straight, Some(_)) => {
            return Err(check.error(
                "path.along_plots.turning_radius_m",
                "only with `join = \"dubins\"`",
            ))
        }
        (JoinName::Straight, None) => None,
    };
    let (Some(first), Some(last)) = (plots.first(), plots.last()) else {
        return Err(check.error("path.along_plots", "needs at least one `[[world.plots]]`"));
    };
    let mut points: Vec<[f64; 2]> = Vec::new();
    let mut pieces = Vec::new();
    let mut s_total = 0.0;
    let too_many = || {
        check.error(
            "path.sample_step_m",
            &format!(
                "the plots need more than {capacity} waypoints at this spacing; use a larger step"
            ),
        )
    };
    // Appends the straight from the last point to `to` (or starts at `to`);
    // `false` when its samples would pass the capacity (nothing appended).
    let straight =
        |points: &mut Vec<[f64; 2]>, pieces: &mut Vec<Piece>, s: &mut f64, to: [f64; 2]| {
            let Some(&from) = points.last() else {
                points.push(to);
                return true;
            };
            let length = (to[0] - from[0]).hypot(to[1] - from[1]);
            if length <= 0.0 {
                return true;
            }
            let n = samples_for(length, step);
            if points.len().saturating_add(n as usize) > capacity {
                return false;
            }
            for k in 1..=n {
                let t = f64::from(k) / f64::from(n);
                points.push([
                    from[0] + t * (to[0] - from[0]),
                    from[1] + t * (to[1] - from[1]),
                ]);
            }
            pieces.push(Piece {
                kind: PieceKind::Straight,
                s_start: *s,
                s_end: *s + length,
                start: from,
                end: to,
            });
            *s += length;
            true
        };
    let (x0, y0, h0) = first.centre_line(0.0);
    if !straight(
        &mut points,
        &mut pieces,
        &mut s_total,
        [x0 - lead_in * h0.cos(), y0 - lead_in * h0.sin()],
    ) {
        return Err(too_many());
    }
    for (i, plot) in plots.iter().enumerate() {
        let (x, y, _) = plot.centre_line(0.0);
        if let Some(&prev) = points.last() {
            let (_, _, h) = plot.centre_line(0.0);
            let ahead = (x - prev[0]) * h.cos() + (y - prev[1]) * h.sin();
            if i > 0 && ahead < 0.0 {
                return Err(check.error(
                    &format!("world.plots[{i}].start"),
                    "with `path.along_plots`, each plot must start ahead of where the previous one ends",
                ));
            }
        }
        let joined = match (radius, i) {
            (Some(r), 1..) => {
                let join = dubins_join(plots.get(i - 1), plot, lead_in, r).map_err(|e| {
                    check.error(
                        &format!("world.plots[{i}].start"),
                        &format!("no Dubins join from the previous plot: {e}"),
                    )
                })?;
                // An arc beyond a half turn is a loop: the plots are too
                // close for the turning radius.
                if join.segments().iter().any(|g| {
                    g.curvature.get() != 0.0 && g.length.get() > core::f64::consts::PI * r + 1e-9
                }) {
                    return Err(check.error(
                        &format!("world.plots[{i}].start"),
                        &format!("the Dubins join of radius {r} m from the previous plot would loop: move the plot further on or use a smaller `turning_radius_m`"),
                    ));
                }
                append_dubins(
                    &join,
                    &mut points,
                    &mut pieces,
                    &mut s_total,
                    step,
                    capacity,
                ) && straight(&mut points, &mut pieces, &mut s_total, [x, y])
            }
            _ => straight(&mut points, &mut pieces, &mut s_total, [x, y]),
        };
        if !joined {
            return Err(too_many());
        }
        let n = samples_for(plot.length, step);
        if points.len().saturating_add(n as usize) > capacity {
            return Err(too_many());
        }
        let s_start = s_total;
        let mut previous = [x, y];
        for k in 1..=n {
            let (px, py, _) = plot.centre_line(plot.length * f64::from(k) / f64::from(n));
            s_total += (px - previous[0]).hypot(py - previous[1]);
            previous = [px, py];
            points.push(previous);
        }
        pieces.push(Piece {
            kind: PieceKind::Straight,
            s_start,
            s_end: s_total,
            start: [x, y],
            end: previous,
        });
    }
    let (xe, ye, he) = last.centre_line(last.length);
    if !straight(
        &mut points,
        &mut pieces,
        &mut s_total,
        [xe + run_out * he.cos(), ye + run_out * he.sin()],
    ) {
        return Err(too_many());
    }
    if points.len() < 2 {
        return Err(check.error("path.along_plots", "the path needs at least two waypoints"));
    }
    Ok(Waypoints { points, pieces })
}

/// The shortest Dubins path of `radius` from the end of plot `from` (its
/// true centre line's end pose) to `lead_in` m before the start of plot `to`
/// along its heading (the vehicle is straight when it reaches the rows).
fn dubins_join(
    from: Option<&PlotSpec>,
    to: &PlotSpec,
    lead_in: f64,
    radius: f64,
) -> Result<DubinsPath, fieldguide::Precondition> {
    let (xe, ye, he) = from.map_or((f64::NAN, f64::NAN, f64::NAN), |p| p.centre_line(p.length));
    let (xs, ys, hs) = to.centre_line(0.0);
    let (xs, ys) = (xs - lead_in * hs.cos(), ys - lead_in * hs.sin());
    let radius = TurningRadius::new(Meters::new(radius)?)?;
    shortest(
        &Pose2::<World>::new(xe, ye, he)?,
        &Pose2::<World>::new(xs, ys, hs)?,
        radius,
    )
}

/// Appends the Dubins path `join` (which starts at the last point) sampled
/// about every `step` m, one piece per arc or straight; `false` when its
/// samples would pass the capacity (nothing appended).
fn append_dubins(
    join: &DubinsPath,
    points: &mut Vec<[f64; 2]>,
    pieces: &mut Vec<Piece>,
    s: &mut f64,
    step: f64,
    capacity: usize,
) -> bool {
    let length = join.length().get();
    if length <= 0.0 {
        return true;
    }
    let n = samples_for(length, step);
    if points.len().saturating_add(n as usize) > capacity {
        return false;
    }
    for k in 1..=n {
        let at = length * f64::from(k) / f64::from(n);
        if let Ok(p) = Meters::new(at).and_then(|m| join.pose_at(m)) {
            points.push([p.position.x(), p.position.y()]);
        }
    }
    for segment in join.segments() {
        let l = segment.length.get();
        if l <= 0.0 {
            continue;
        }
        let start = [segment.start.position.x(), segment.start.position.y()];
        let (h, c) = (segment.start.heading.get(), segment.curvature.get());
        let end = advance(start[0], start[1], h, c, l);
        pieces.push(Piece {
            kind: if c == 0.0 {
                PieceKind::Straight
            } else {
                PieceKind::Arc { curvature: c }
            },
            s_start: *s,
            s_end: *s + l,
            start,
            end,
        });
        *s += l;
    }
    true
}

/// Samples the segments every `step` metres (at least once per segment), from `start`.
fn sample_segments(
    start: StartPose,
    segments: &[Segment],
    plots: &[PlotSpec],
    step: f64,
    capacity: usize,
    check: &Checker<'_>,
) -> Result<Waypoints, ScenarioError> {
    let mut x = check.finite("path.start.x_m", start.x_m)?;
    let mut y = check.finite("path.start.y_m", start.y_m)?;
    let mut heading = check
        .finite("path.start.heading_deg", start.heading_deg)?
        .to_radians();
    if segments.is_empty() {
        return Err(check.error("path.segments", "needs at least one segment"));
    }
    let mut points = vec![[x, y]];
    let mut pieces = Vec::with_capacity(segments.len());
    let mut s = 0.0;
    for (i, seg) in segments.iter().enumerate() {
        let field = |name: &str| format!("path.segments[{i}].{name}");
        if let Some(index) = seg.along_plot {
            if seg.straight_m.is_some() || seg.arc_radius_m.is_some() || seg.arc_angle_deg.is_some()
            {
                return Err(check.error(
                    &format!("path.segments[{i}]"),
                    "`along_plot` takes no other field",
                ));
            }
            let Some(plot) = plots.get(index) else {
                return Err(check.error(
                    &field("along_plot"),
                    &format!("no plot {index} in `[[world.plots]]`"),
                ));
            };
            let (x0, y0, _) = plot.centre_line(0.0);
            let join = (x0 - x).hypot(y0 - y);
            let n = samples_for(plot.length, step).saturating_add(samples_for(join, step));
            if points.len().saturating_add(n as usize) > capacity {
                return Err(check.error(
                    "path.sample_step_m",
                    &format!(
                        "the segments need more than {capacity} waypoints at this spacing; use a larger step"
                    ),
                ));
            }
            if join > 0.0 {
                let m = samples_for(join, step);
                for k in 1..=m {
                    let t = f64::from(k) / f64::from(m);
                    points.push([x + t * (x0 - x), y + t * (y0 - y)]);
                }
                pieces.push(Piece {
                    kind: PieceKind::Straight,
                    s_start: s,
                    s_end: s + join,
                    start: [x, y],
                    end: [x0, y0],
                });
                s += join;
            }
            let m = samples_for(plot.length, step);
            let s_start = s;
            let mut previous = [x0, y0];
            for k in 1..=m {
                let (px, py, _) = plot.centre_line(plot.length * f64::from(k) / f64::from(m));
                s += (px - previous[0]).hypot(py - previous[1]);
                previous = [px, py];
                points.push(previous);
            }
            pieces.push(Piece {
                kind: PieceKind::Straight,
                s_start,
                s_end: s,
                start: [x0, y0],
                end: previous,
            });
            let (_, _, h) = plot.centre_line(plot.length);
            x = previous[0];
            y = previous[1];
            heading = h;
            continue;
        }
        let (length, curvature) = match (seg.straight_m, seg.arc_radius_m, seg.arc_angle_deg) {
            (Some(l), None, None) => (check.positive(&field("straight_m"), l)?, 0.0),
            (None, Some(r), Some(a)) => {
                let r = check.positive(&field("arc_radius_m"), r)?;
                let a = check.range(&field("arc_angle_deg"), a, -360.0, 360.0)?;
                if a == 0.0 {
                    return Err(check.error(&field("arc_angle_deg"), "must not be 0"));
                }
                (r * a.to_radians().abs(), a.signum() / r)
            }
            _ => {
                return Err(check.error(
                    &format!("path.segments[{i}]"),
                    "give either `straight_m` or both `arc_radius_m` and `arc_angle_deg`",
                ))
            }
        };
        let n = samples_for(length, step);
        let total = points.len().saturating_add(n as usize);
        if total > capacity {
            return Err(check.error(
                "path.sample_step_m",
                &format!(
                    "the segments need more than {capacity} waypoints at this spacing; use a larger step"
                ),
            ));
        }
        for k in 1..=n {
            let d = length * f64::from(k) / f64::from(n);
            points.push(advance(x, y, heading, curvature, d));
        }
        let end = advance(x, y, heading, curvature, length);
        pieces.push(Piece {
            kind: if curvature == 0.0 {
                PieceKind::Straight
            } else {
                PieceKind::Arc { curvature }
            },
            s_start: s,
            s_end: s + length,
            start: [x, y],
            end,
        });
        x = end[0];
        y = end[1];
        heading += curvature * length;
        s += length;
    }
    Ok(Waypoints { points, pieces })
}

/// Number of sampling intervals for a segment of `length` at spacing `step` (≥ 1,
/// saturating at `u32::MAX`; the caller checks the total against the capacity).
fn samples_for(length: f64, step: f64) -> u32 {
    // A float-to-int `as` saturates and maps NaN to 0, so the clamp bounds the result.
    ((length / step).ceil() as u32).max(1)
}

/// The point at distance `d` along a piece of curvature `c` starting at `(x, y)`
/// with `heading`: a straight line for c = 0, a circular arc otherwise.
fn advance(x: f64, y: f64, heading: f64, c: f64, d: f64) -> [f64; 2] {
    if c == 0.0 {
        [x + d * heading.cos(), y + d * heading.sin()]
    } else {
        let h = heading + c * d;
        [
            x + (h.sin() - heading.sin()) / c,
            y - (h.cos() - heading.cos()) / c,
        ]
    }
}

fn read_csv(
    name: &str,
    base_dir: Option<&Path>,
    check: &Checker<'_>,
) -> Result<String, ScenarioError> {
    let Some(dir) = base_dir else {
        return Err(check.error(
            "path.csv",
            "a built-in scenario cannot refer to a file; use `path.segments`",
        ));
    };
    let file = dir.join(name);
    std::fs::read_to_string(&file).map_err(|source| ScenarioError::Read { file, source })
}

/// Parses `x_m,y_m` lines; an optional first header line; `#` comments and blank lines skipped.
fn parse_csv(text: &str, check: &Checker<'_>) -> Result<Vec<[f64; 2]>, ScenarioError> {
    let mut points = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = raw.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let mut cells = line.split(',').map(str::trim);
        let (Some(a), Some(b), None) = (cells.next(), cells.next(), cells.next()) else {
            return Err(check.error(
                "path.csv",
                &format!("line {}: expected two columns `x_m,y_m`", i + 1),
            ));
        };
        match (a.parse::<f64>(), b.parse::<f64>()) {
            (Ok(x), Ok(y)) if x.is_finite() && y.is_finite() => points.push([x, y]),
            _ if i == 0 => {} // header line
            _ => {
                return Err(check.error(
                    "path.csv",
                    &format!("line {}: `{line}` is not two finite numbers", i + 1),
                ))
            }
        }
    }
    if points.len() < 2 {
        return Err(check.error("path.csv", "needs at least two waypoints"));
    }
    Ok(points)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn checker() -> Checker<'static> {
        Checker::new("test")
    }

    #[test]
    fn sample_count_is_the_ceiling() {
        assert_eq!(samples_for(15.0, 0.1), 150);
        assert_eq!(samples_for(0.05, 0.1), 1);
        assert_eq!(samples_for(1.05, 0.1), 11);
        assert_eq!(samples_for(7.0, 1.0), 7);
    }

    #[test]
    fn quarter_arc_ends_where_geometry_says() {
        // Left quarter circle of radius 10 from the origin heading east ends at (10, 10).
        let p = advance(0.0, 0.0, 0.0, 0.1, 10.0 * std::f64::consts::FRAC_PI_2);
        assert!((p[0] - 10.0).abs() < 1e-9 && (p[1] - 10.0).abs() < 1e-9);
        // Right half circle of radius 5 heading north ends 10 m east.
        let q = advance(
            0.0,
            0.0,
            std::f64::consts::FRAC_PI_2,
            -0.2,
            5.0 * std::f64::consts::PI,
        );
        assert!((q[0] - 10.0).abs() < 1e-9 && q[1].abs() < 1e-9);
    }

    #[test]
    fn segments_give_pieces_and_evenly_spaced_points() {
        let start = StartPose {
            x_m: 1.0,
            y_m: 2.0,
            heading_deg: 90.0,
        };
        let segs = [
            Segment {
                straight_m: Some(3.0),
                arc_radius_m: None,
                arc_angle_deg: None,
                along_plot: None,
                speed_m_s: None,
            },
            Segment {
                straight_m: None,
                arc_radius_m: Some(2.0),
                arc_angle_deg: Some(-90.0),
                along_plot: None,
                speed_m_s: None,
            },
        ];
        let w = sample_segments(start, &segs, &[], 0.1, 4096, &checker()).unwrap();
        assert_eq!(w.points.len(), 1 + 30 + 32);
        for pair in w.points.windows(2) {
            let d = (pair[1][0] - pair[0][0]).hypot(pair[1][1] - pair[0][1]);
            assert!(d > 0.09 && d < 0.1001, "spacing {d}");
        }
        let last = w.points.last().unwrap();
        assert!((last[0] - 3.0).abs() < 1e-9 && (last[1] - 7.0).abs() < 1e-9);
        assert_eq!(w.pieces.len(), 2);
        assert!((w.pieces[1].s_start - 3.0).abs() < 1e-12);
        assert!((w.pieces[1].s_end - 3.0 - std::f64::consts::PI).abs() < 1e-9);
        assert_eq!(w.pieces[1].kind, PieceKind::Arc { curvature: -0.5 });
    }

    #[test]
    fn bad_segments_name_their_field() {
        let start = StartPose {
            x_m: 0.0,
            y_m: 0.0,
            heading_deg: 0.0,
        };
        let half = Segment {
            straight_m: None,
            arc_radius_m: Some(2.0),
            arc_angle_deg: None,
            along_plot: None,
            speed_m_s: None,
        };
        let e = sample_segments(start, &[half], &[], 0.1, 4096, &checker()).unwrap_err();
        assert_eq!(e.field(), Some("path.segments[0]"));
        let neg = Segment {
            straight_m: Some(-1.0),
            arc_radius_m: None,
            arc_angle_deg: None,
            along_plot: None,
            speed_m_s: None,
        };
        let e = sample_segments(start, &[neg], &[], 0.1, 4096, &checker()).unwrap_err();
        assert_eq!(e.field(), Some("path.segments[0].straight_m"));
    }

    #[test]
    fn csv_parses_header_comments_and_refuses_garbage() {
        let pts = parse_csv("x_m,y_m\n# a comment\n0,0\n1.5, 2\n\n3,4\n", &checker()).unwrap();
        assert_eq!(pts, vec![[0.0, 0.0], [1.5, 2.0], [3.0, 4.0]]);
        let e = parse_csv("0,0\n1,abc\n", &checker()).unwrap_err();
        assert_eq!(e.field(), Some("path.csv"));
        assert!(e.to_string().contains("line 2"));
        assert!(parse_csv("0,0,0\n", &checker()).is_err());
        assert!(parse_csv("0,0\n", &checker()).is_err());
    }
}
