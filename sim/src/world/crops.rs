//! Crop plots: plants with position, radius and height, laid out in rows.
//!
//! A plot is a bundle of parallel rows along a centre line that may bend
//! slightly (a sinusoidal lateral offset), with irregular plant spacing,
//! missing plants, stretches with no plant at all, and grass tufts in the
//! headlands. Generation is seeded: the caller passes the random generator.
//! The maize and bean plots follow Pierre 2022, section 4.2: maize in two rows
//! 0.75 m apart, about 0.5 m high; beans in three rows 0.375 m apart, about
//! 0.3 m high.

use core::f64::consts::TAU;

use fieldguide::{Point2, World};
use rand::Rng;
use rand_distr::{Distribution, Normal};

use super::curve::Curve;
use super::{Plant, PlantKind};

/// Where a point lies relative to a plot's true centre line ([`PlotSpec::project`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlotPosition {
    /// Abscissa along the plot, m (the parameter of [`PlotSpec::centre_line`]).
    pub s: f64,
    /// Signed distance to the centre line, m, positive to its left.
    pub lateral: f64,
}

/// A mean value with a standard deviation, for a generated quantity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spread {
    /// Mean value.
    pub mean: f64,
    /// Standard deviation (0 for an exact value).
    pub std_dev: f64,
}

impl Spread {
    /// `mean` with a standard deviation of `std_dev`.
    #[must_use]
    pub const fn new(mean: f64, std_dev: f64) -> Self {
        Self { mean, std_dev }
    }

    /// A draw, clamped to `[min, max]`; the mean itself when the spread is not a valid normal law.
    fn draw(&self, rng: &mut impl Rng, min: f64, max: f64) -> f64 {
        let v = Normal::new(self.mean, self.std_dev)
            .map(|n| n.sample(rng))
            .unwrap_or(self.mean);
        v.clamp(min, max)
    }
}

/// The layout of one crop plot.
#[derive(Debug, Clone, PartialEq)]
pub struct PlotSpec {
    /// Start of the plot's centre line, world frame, m.
    pub start: Point2<World>,
    /// Heading of the centre line at the start, rad (counter-clockwise from east).
    pub heading: f64,
    /// Length of the rows along the centre line, m.
    pub length: f64,
    /// Number of rows.
    pub rows: usize,
    /// Lateral distance between neighbouring rows, m.
    pub row_spacing: f64,
    /// Distance between neighbouring plants along a row, m.
    pub plant_spacing: Spread,
    /// Plant radius, m.
    pub plant_radius: Spread,
    /// Plant height, m.
    pub plant_height: Spread,
    /// Lateral scatter of plants about their row, m (standard deviation).
    pub lateral_scatter: f64,
    /// Probability that a plant is missing.
    pub missing: f64,
    /// Stretches `[from, to)` along the centre line, m, where no plant grew.
    pub bare: Vec<(f64, f64)>,
    /// Lateral amplitude of the rows' bend, m (0 for straight rows).
    pub bend_amplitude: f64,
    /// Wavelength of the bend along the centre line, m.
    pub bend_wavelength: f64,
    /// The centre line as a rounded polyline (`None`: straight from `start`
    /// along `heading`, with the bend). With it, `start`, `heading` and
    /// `length` are its start, its initial heading and its length, and the
    /// bend is 0.
    pub centre: Option<Curve>,
}

impl PlotSpec {
    /// A maize plot (Pierre 2022, 4.2): two rows 0.75 m apart, plants about
    /// 0.5 m high, every 0.2 m, 5 % missing, rows bent by 5 cm over 40 m.
    ///
    /// The radius, 0.05 m (σ 0.01 m), is that of the opaque core a laser sees
    /// in a young maize plant: a stem of 2-3 cm with long thin leaves that
    /// most rays pass between. A solid cylinder of 0.1 m radius every 0.2 m
    /// would be a continuous wall 0.5 m high; the inclined scan then sees its
    /// inner face and its top as two bumps per row, both matching the plant
    /// model, and pairs from the inner face of one row and the top of the
    /// other (0.65-0.7 m apart) pass the 0.66-0.9 m test: open loop, the
    /// error of the detected centre line is then 4 cm on average and up to
    /// 13 cm, against 1 cm and 3 cm with the 0.05 m core
    /// (`sim/scenarios/README.md`, "Furrow pursuing").
    #[must_use]
    pub fn maize(start: Point2<World>, heading: f64, length: f64) -> Self {
        Self {
            start,
            heading,
            length,
            rows: 2,
            row_spacing: 0.75,
            plant_spacing: Spread::new(0.2, 0.04),
            plant_radius: Spread::new(0.05, 0.01),
            plant_height: Spread::new(0.5, 0.05),
            lateral_scatter: 0.01,
            missing: 0.05,
            bare: Vec::new(),
            bend_amplitude: 0.05,
            bend_wavelength: 40.0,
            centre: None,
        }
    }

    /// A bean plot (Pierre 2022, 4.2): three rows 0.375 m apart, plants about
    /// 0.3 m high, 0.07 m in radius, every 0.15 m, 5 % missing, rows bent by
    /// 5 cm over 40 m.
    #[must_use]
    pub fn beans(start: Point2<World>, heading: f64, length: f64) -> Self {
        Self {
            start,
            heading,
            length,
            rows: 3,
            row_spacing: 0.375,
            plant_spacing: Spread::new(0.15, 0.03),
            plant_radius: Spread::new(0.07, 0.015),
            plant_height: Spread::new(0.3, 0.04),
            lateral_scatter: 0.01,
            missing: 0.05,
            bare: Vec::new(),
            bend_amplitude: 0.05,
            bend_wavelength: 40.0,
            centre: None,
        }
    }

    /// The lateral offset of the bent centre line at distance `s` along it, m.
    #[must_use]
    pub fn bend(&self, s: f64) -> f64 {
        if self.bend_wavelength > 0.0 {
            self.bend_amplitude * (TAU * s / self.bend_wavelength).sin()
        } else {
            0.0
        }
    }

    /// The true centre line at `s` m from the start: position and heading
    /// (world frame). This is the ground truth a run's lateral error is
    /// measured against.
    #[must_use]
    pub fn centre_line(&self, s: f64) -> (f64, f64, f64) {
        if let Some(curve) = &self.centre {
            return curve.pose_at(s);
        }
        let (c, sn) = (self.heading.cos(), self.heading.sin());
        let d = self.bend(s);
        let slope = if self.bend_wavelength > 0.0 {
            self.bend_amplitude * TAU / self.bend_wavelength
                * (TAU * s / self.bend_wavelength).cos()
        } else {
            0.0
        };
        let x = self.start.x() + s * c - d * sn;
        let y = self.start.y() + s * sn + d * c;
        (x, y, self.heading + slope.atan())
    }

    /// The true centre line's projection of the world point `(x, y)`: the
    /// abscissa `s` along the plot (the parameter of [`Self::centre_line`])
    /// and the signed distance to the centre line, m, positive when the
    /// point is left of it (`spec/library.md`, LIB-FRAMES). `None` when the
    /// projection falls outside `[0, length]` (the point is not beside the
    /// plot) or the plot is degenerate.
    ///
    /// Newton's method on the bent centre line, started at the point's
    /// abscissa along the plot heading; the bend's slope is small (5 cm over
    /// 40 m gives at most 0.008), so a few iterations reach rounding.
    #[must_use]
    pub fn project(&self, x: f64, y: f64) -> Option<PlotPosition> {
        if let Some(curve) = &self.centre {
            return curve
                .project(x, y)
                .map(|(s, lateral)| PlotPosition { s, lateral });
        }
        let (c, sn) = (self.heading.cos(), self.heading.sin());
        let (dx, dy) = (x - self.start.x(), y - self.start.y());
        let mut s = dx * c + dy * sn;
        for _ in 0..4 {
            let (cx, cy, h) = self.centre_line(s);
            let along = (x - cx) * h.cos() + (y - cy) * h.sin();
            // ds/d(arc length) = cos of the bend's slope angle.
            s += along * (h - self.heading).cos();
        }
        let (cx, cy, h) = self.centre_line(s);
        let lateral = -(x - cx) * h.sin() + (y - cy) * h.cos();
        let inside = s >= 0.0 && s <= self.length;
        (inside && lateral.is_finite()).then_some(PlotPosition { s, lateral })
    }

    /// The signed lateral offset of row `i` (0 = rightmost) from the centre line, m.
    #[must_use]
    pub fn row_offset(&self, i: usize) -> f64 {
        let rows = self.rows.max(1) as f64;
        (i as f64 - (rows - 1.0) / 2.0) * self.row_spacing
    }

    /// Whether `s` lies in a bare stretch.
    fn is_bare(&self, s: f64) -> bool {
        self.bare.iter().any(|&(a, b)| s >= a && s < b)
    }

    /// The plants of the plot, drawn with `rng`.
    pub fn generate(&self, rng: &mut impl Rng) -> Vec<Plant> {
        let mut plants = Vec::new();
        let (c, sn) = (self.heading.cos(), self.heading.sin());
        let scatter = Spread::new(0.0, self.lateral_scatter);
        for i in 0..self.rows {
            let offset = self.row_offset(i);
            let mut s =
                self.plant_spacing.draw(rng, 0.0, self.plant_spacing.mean) * rng.random::<f64>();
            while s < self.length {
                let lateral = offset + self.bend(s) + scatter.draw(rng, -0.05, 0.05);
                let radius = self.plant_radius.draw(rng, 0.01, 1.0);
                let height = self.plant_height.draw(rng, 0.02, 3.0);
                let present = rng.random::<f64>() >= self.missing && !self.is_bare(s);
                if present {
                    let [x, y] = match &self.centre {
                        Some(curve) => curve.offset(s, lateral),
                        None => [
                            self.start.x() + s * c - lateral * sn,
                            self.start.y() + s * sn + lateral * c,
                        ],
                    };
                    if let Ok(position) = Point2::new(x, y) {
                        plants.push(Plant {
                            position,
                            radius,
                            height,
                            kind: PlantKind::Crop,
                        });
                    }
                }
                s += self.plant_spacing.draw(
                    rng,
                    0.3 * self.plant_spacing.mean,
                    3.0 * self.plant_spacing.mean,
                );
            }
        }
        plants
    }
}

/// Grass tufts scattered uniformly over the rectangle `[x0, x1] × [y0, y1]`
/// (world frame), `density` tufts per m², each `radius` m wide and `height` m tall.
pub fn scatter_grass(
    corners: ((f64, f64), (f64, f64)),
    density: f64,
    radius: Spread,
    height: Spread,
    rng: &mut impl Rng,
) -> Vec<Plant> {
    let ((x0, y0), (x1, y1)) = corners;
    let area = ((x1 - x0) * (y1 - y0)).abs();
    let count = (area * density.max(0.0)).round() as usize;
    (0..count)
        .filter_map(|_| {
            let x = x0 + (x1 - x0) * rng.random::<f64>();
            let y = y0 + (y1 - y0) * rng.random::<f64>();
            Some(Plant {
                position: Point2::new(x, y).ok()?,
                radius: radius.draw(rng, 0.005, 0.5),
                height: height.draw(rng, 0.01, 1.0),
                kind: PlantKind::Grass,
            })
        })
        .collect()
}

/// A uniform grid over the plants' footprints, so that a query touches only
/// the plants near a rectangle (the ray caster uses a spatial index).
#[derive(Debug, Clone)]
pub struct PlantIndex {
    plants: Vec<Plant>,
    origin: (f64, f64),
    cell: f64,
    columns: usize,
    rows: usize,
    cells: Vec<Vec<u32>>,
    max_radius: f64,
    max_height: f64,
}

impl PlantIndex {
    /// Indexes `plants` in square cells of `cell` m (0.5 m when `cell` is not positive).
    #[must_use]
    pub fn new(plants: Vec<Plant>, cell: f64) -> Self {
        let cell = if cell > 0.0 && cell.is_finite() {
            cell
        } else {
            0.5
        };
        let (mut x0, mut y0, mut x1, mut y1) = (
            f64::INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        );
        let mut max_radius: f64 = 0.0;
        let mut max_height: f64 = 0.0;
        for p in &plants {
            x0 = x0.min(p.position.x());
            y0 = y0.min(p.position.y());
            x1 = x1.max(p.position.x());
            y1 = y1.max(p.position.y());
            max_radius = max_radius.max(p.radius);
            max_height = max_height.max(p.height);
        }
        if plants.is_empty() {
            (x0, y0, x1, y1) = (0.0, 0.0, 0.0, 0.0);
        }
        let columns = ((x1 - x0) / cell).floor() as usize + 1;
        let rows = ((y1 - y0) / cell).floor() as usize + 1;
        let mut cells = vec![Vec::new(); columns.saturating_mul(rows)];
        for (i, p) in plants.iter().enumerate() {
            let cx = ((p.position.x() - x0) / cell).floor() as usize;
            let cy = ((p.position.y() - y0) / cell).floor() as usize;
            if let Some(c) = cells.get_mut(cy.min(rows - 1) * columns + cx.min(columns - 1)) {
                c.push(i as u32);
            }
        }
        Self {
            plants,
            origin: (x0, y0),
            cell,
            columns,
            rows,
            cells,
            max_radius,
            max_height,
        }
    }

    /// Every plant indexed.
    #[must_use]
    pub fn plants(&self) -> &[Plant] {
        &self.plants
    }

    /// The largest plant radius, m.
    #[must_use]
    pub fn max_radius(&self) -> f64 {
        self.max_radius
    }

    /// The tallest plant's height, m (0 without plants).
    #[must_use]
    pub fn max_height(&self) -> f64 {
        self.max_height
    }

    /// The plants whose stem lies in `[x0, x1] × [y0, y1]`, written to `out` (cleared first).
    pub fn query(&self, (x0, y0): (f64, f64), (x1, y1): (f64, f64), out: &mut Vec<usize>) {
        out.clear();
        if self.plants.is_empty() || !(x0 <= x1 && y0 <= y1) {
            return;
        }
        let to_cell = |v: f64, o: f64, n: usize| -> usize {
            let c = ((v - o) / self.cell).floor();
            if c <= 0.0 {
                0
            } else {
                (c as usize).min(n - 1)
            }
        };
        if x1 < self.origin.0 || y1 < self.origin.1 {
            return;
        }
        let (cx0, cx1) = (
            to_cell(x0, self.origin.0, self.columns),
            to_cell(x1, self.origin.0, self.columns),
        );
        let (cy0, cy1) = (
            to_cell(y0, self.origin.1, self.rows),
            to_cell(y1, self.origin.1, self.rows),
        );
        for cy in cy0..=cy1 {
            for cx in cx0..=cx1 {
                if let Some(cell) = self.cells.get(cy * self.columns + cx) {
                    for &i in cell {
                        let i = i as usize;
                        if let Some(p) = self.plants.get(i) {
                            let (x, y) = (p.position.x(), p.position.y());
                            if x >= x0 && x <= x1 && y >= y0 && y <= y1 {
                                out.push(i);
                            }
                        }
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::rngs::StdRng;
    use rand::SeedableRng;

    fn origin() -> Point2<World> {
        Point2::new(0.0, 0.0).unwrap()
    }

    #[test]
    fn maize_rows_lie_on_both_sides_of_the_centre_line() {
        let mut spec = PlotSpec::maize(origin(), 0.0, 30.0);
        spec.bend_amplitude = 0.0;
        let plants = spec.generate(&mut StdRng::seed_from_u64(7));
        let left = plants.iter().filter(|p| p.position.y() > 0.0).count();
        let right = plants.len() - left;
        // 30 m at 0.2 m: about 150 plants a row, 5 % missing.
        assert!(left > 120 && left < 170, "{left}");
        assert!(right > 120 && right < 170, "{right}");
        for p in &plants {
            assert!((p.position.y().abs() - 0.375).abs() < 0.06);
            assert!(p.height > 0.2 && p.height < 0.8);
            assert_eq!(p.kind, PlantKind::Crop);
        }
        let mean_height: f64 = plants.iter().map(|p| p.height).sum::<f64>() / plants.len() as f64;
        assert!((mean_height - 0.5).abs() < 0.02);
    }

    #[test]
    fn beans_have_three_rows_and_bare_stretches_are_bare() {
        let mut spec = PlotSpec::beans(origin(), core::f64::consts::FRAC_PI_2, 20.0);
        spec.bend_amplitude = 0.0;
        spec.bare = vec![(5.0, 6.5)];
        let plants = spec.generate(&mut StdRng::seed_from_u64(3));
        // Heading north: rows are at x = +0.375, 0, −0.375 (left of north is west, −x).
        for target in [-0.375, 0.0, 0.375] {
            assert!(
                plants
                    .iter()
                    .filter(|p| (p.position.x() - target).abs() < 0.06)
                    .count()
                    > 100
            );
        }
        assert!(plants
            .iter()
            .all(|p| !(p.position.y() >= 5.0 && p.position.y() < 6.5)));
        assert!(plants
            .iter()
            .any(|p| p.position.y() >= 6.5 && p.position.y() < 7.0));
    }

    #[test]
    fn generation_is_seeded_and_rows_bend() {
        let spec = PlotSpec::maize(origin(), 0.3, 25.0);
        let a = spec.generate(&mut StdRng::seed_from_u64(11));
        let b = spec.generate(&mut StdRng::seed_from_u64(11));
        let c = spec.generate(&mut StdRng::seed_from_u64(12));
        assert_eq!(a, b);
        assert_ne!(a, c);
        // The centre line bends by the amplitude a quarter wavelength in.
        assert!((spec.bend(10.0) - 0.05).abs() < 1e-12);
        let (x, y, h) = spec.centre_line(10.0);
        assert!((x - (10.0 * 0.3_f64.cos() - 0.05 * 0.3_f64.sin())).abs() < 1e-12);
        assert!((y - (10.0 * 0.3_f64.sin() + 0.05 * 0.3_f64.cos())).abs() < 1e-12);
        assert!((h - 0.3).abs() < 1e-12);
    }

    #[test]
    fn projection_on_the_bent_centre_line() {
        let spec = PlotSpec::maize(Point2::new(3.0, -2.0).unwrap(), 0.4, 30.0);
        let (c, s) = (0.4_f64.cos(), 0.4_f64.sin());
        for (at, offset) in [(0.5, 0.0), (7.3, 0.2), (10.0, -0.6), (29.0, 1.1)] {
            // A point `offset` m left of the centre line, perpendicular to it at `at`.
            let (x, y, h) = spec.centre_line(at);
            let p = spec
                .project(x - offset * h.sin(), y + offset * h.cos())
                .unwrap();
            assert!((p.s - at).abs() < 1e-9, "{} vs {at}", p.s);
            assert!(
                (p.lateral - offset).abs() < 1e-9,
                "{} vs {offset}",
                p.lateral
            );
        }
        // Before the start and past the end: not beside the plot.
        assert!(spec.project(3.0 - 0.5 * c, -2.0 - 0.5 * s).is_none());
        assert!(spec.project(3.0 + 31.0 * c, -2.0 + 31.0 * s).is_none());
    }

    #[test]
    fn grass_stays_in_its_headland_and_the_index_finds_what_brute_force_finds() {
        let mut rng = StdRng::seed_from_u64(5);
        let grass = scatter_grass(
            ((-5.0, -2.0), (0.0, 2.0)),
            10.0,
            Spread::new(0.02, 0.005),
            Spread::new(0.1, 0.03),
            &mut rng,
        );
        assert_eq!(grass.len(), 200);
        assert!(grass.iter().all(|g| g.kind == PlantKind::Grass
            && (-5.0..=0.0).contains(&g.position.x())
            && (-2.0..=2.0).contains(&g.position.y())
            && g.height < 0.3));
        let mut plants = PlotSpec::maize(origin(), 0.0, 20.0).generate(&mut rng);
        plants.extend(grass);
        let index = PlantIndex::new(plants.clone(), 0.5);
        let mut found = Vec::new();
        for (lo, hi) in [
            ((-1.0, -1.0), (3.0, 0.5)),
            ((10.0, 0.2), (12.5, 2.0)),
            ((-100.0, -100.0), (100.0, 100.0)),
            ((50.0, 50.0), (60.0, 60.0)),
        ] {
            index.query(lo, hi, &mut found);
            found.sort_unstable();
            let brute: Vec<usize> = plants
                .iter()
                .enumerate()
                .filter(|(_, p)| {
                    p.position.x() >= lo.0
                        && p.position.x() <= hi.0
                        && p.position.y() >= lo.1
                        && p.position.y() <= hi.1
                })
                .map(|(i, _)| i)
                .collect();
            assert_eq!(found, brute);
        }
    }
}
