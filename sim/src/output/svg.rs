//! A small hand-written SVG plotter: a framed plot area with nice ticks, grid,
//! axis labels with units, polylines, shaded polygons and bands, a legend.
//! Enough for the papers' figures, with no dependency.

use std::fmt::Write as _;

/// Margins around the plot area, pixels: left, right, top, bottom.
const MARGIN: (f64, f64, f64, f64) = (70.0, 20.0, 40.0, 55.0);
const FONT: &str = "DejaVu Sans, Helvetica, Arial, sans-serif";

/// Data ranges and the pixel box they map to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Axes {
    /// Data range on x.
    pub x: (f64, f64),
    /// Data range on y.
    pub y: (f64, f64),
    /// Plot area: left, top, width, height in pixels.
    area: (f64, f64, f64, f64),
}

impl Axes {
    /// Axes filling a `width` × `height` picture (pixels) with independent scales.
    #[must_use]
    pub fn new(x: (f64, f64), y: (f64, f64), width: f64, height: f64) -> Self {
        let (l, r, t, b) = MARGIN;
        Self {
            x: widen(x),
            y: widen(y),
            area: (l, t, width - l - r, height - t - b),
        }
    }

    /// Axes with one scale on both axes (a metre is as long on x as on y),
    /// the picture at most `max_width` × `max_height` pixels; the data ranges
    /// are extended about their centres to fill the plot area.
    #[must_use]
    pub fn equal(x: (f64, f64), y: (f64, f64), max_width: f64, max_height: f64) -> Self {
        let (l, r, t, b) = MARGIN;
        let (x, y) = (widen(x), widen(y));
        let (aw, ah) = (max_width - l - r, max_height - t - b);
        let scale = (aw / (x.1 - x.0)).min(ah / (y.1 - y.0));
        let (w, h) = ((x.1 - x.0) * scale, (y.1 - y.0) * scale);
        Self {
            x,
            y,
            area: (l, t, w, h),
        }
    }

    /// Width and height of the whole picture, pixels.
    #[must_use]
    pub fn picture_size(&self) -> (f64, f64) {
        let (l, r, t, b) = MARGIN;
        (self.area.2 + l + r, self.area.3 + t + b)
    }

    /// Pixel position of a data point.
    #[must_use]
    pub fn px(&self, x: f64, y: f64) -> (f64, f64) {
        let (l, t, w, h) = self.area;
        (
            l + (x - self.x.0) / (self.x.1 - self.x.0) * w,
            t + h - (y - self.y.0) / (self.y.1 - self.y.0) * h,
        )
    }
}

/// A range made non-empty and padded by 5 % on each side.
fn widen((lo, hi): (f64, f64)) -> (f64, f64) {
    let (lo, hi) = if hi - lo > 1e-9 {
        (lo, hi)
    } else {
        (lo - 0.5, hi + 0.5)
    };
    let pad = 0.05 * (hi - lo);
    (lo - pad, hi + pad)
}

/// Tick values in `[lo, hi]` at a 1-2-5 step giving about `target` ticks.
#[must_use]
pub fn nice_ticks(lo: f64, hi: f64, target: u32) -> Vec<f64> {
    let span = hi - lo;
    if span.is_nan() || span <= 0.0 || !span.is_finite() {
        return vec![lo];
    }
    let raw = span / f64::from(target.max(1));
    let mag = 10_f64.powf(raw.log10().floor());
    // The 1-2-5 step nearest to the raw step, on a log scale.
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .min_by(|a, b| (a / raw).ln().abs().total_cmp(&(b / raw).ln().abs()))
        .unwrap_or(mag);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    (first..=last).map(|k| k as f64 * step).collect()
}

/// Text of a tick value: as few decimals as the step needs.
fn tick_label(v: f64, step: f64) -> String {
    let decimals = if step >= 1.0 {
        0
    } else {
        (-step.log10()).ceil() as usize
    };
    let s = format!("{v:.decimals$}");
    if s.starts_with('-') && s.trim_start_matches(['-', '0', '.']).is_empty() {
        s.trim_start_matches('-').to_owned()
    } else {
        s
    }
}

/// Escapes text for SVG.
fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// An SVG picture being drawn.
#[derive(Debug, Clone, PartialEq)]
pub struct Svg {
    width: f64,
    height: f64,
    body: String,
}

/// Line style.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stroke<'a> {
    /// CSS colour.
    pub colour: &'a str,
    /// Width, pixels.
    pub width: f64,
    /// Dash pattern (`"6 4"`), or `None` for a solid line.
    pub dash: Option<&'a str>,
}

impl Svg {
    /// A white picture of the size of `axes`.
    #[must_use]
    pub fn new(axes: &Axes) -> Self {
        let (width, height) = axes.picture_size();
        let mut s = Self {
            width,
            height,
            body: String::new(),
        };
        s.raw(&format!(
            r#"<rect x="0" y="0" width="{width:.1}" height="{height:.1}" fill="white"/>"#
        ));
        s
    }

    fn raw(&mut self, element: &str) {
        self.body.push_str(element);
        self.body.push('\n');
    }

    /// The finished document.
    #[must_use]
    pub fn finish(self) -> String {
        format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w:.0}\" height=\"{h:.0}\" viewBox=\"0 0 {w:.1} {h:.1}\" font-family=\"{FONT}\">\n{body}</svg>\n",
            w = self.width,
            h = self.height,
            body = self.body
        )
    }

    /// Grid, frame, ticks and labels of `axes`, and a title above.
    pub fn frame(&mut self, axes: &Axes, x_label: &str, y_label: &str, title: &str) {
        let (l, t, w, h) = axes.area;
        let xt = nice_ticks(axes.x.0, axes.x.1, (w / 80.0).max(2.0) as u32);
        let yt = nice_ticks(axes.y.0, axes.y.1, (h / 60.0).max(2.0) as u32);
        let xstep = step_of(&xt);
        let ystep = step_of(&yt);
        for &v in &xt {
            let (px, _) = axes.px(v, axes.y.0);
            self.raw(&format!(
                r##"<line x1="{px:.1}" y1="{t:.1}" x2="{px:.1}" y2="{:.1}" stroke="#e6e6e6" stroke-width="1"/>"##,
                t + h
            ));
            self.raw(&format!(
                r##"<line x1="{px:.1}" y1="{:.1}" x2="{px:.1}" y2="{:.1}" stroke="black" stroke-width="1"/>"##,
                t + h,
                t + h - 5.0
            ));
            self.text(px, t + h + 16.0, &tick_label(v, xstep), "middle", 11.0);
        }
        for &v in &yt {
            let (_, py) = axes.px(axes.x.0, v);
            self.raw(&format!(
                r##"<line x1="{l:.1}" y1="{py:.1}" x2="{:.1}" y2="{py:.1}" stroke="#e6e6e6" stroke-width="1"/>"##,
                l + w
            ));
            self.raw(&format!(
                r##"<line x1="{l:.1}" y1="{py:.1}" x2="{:.1}" y2="{py:.1}" stroke="black" stroke-width="1"/>"##,
                l + 5.0
            ));
            self.text(l - 6.0, py + 4.0, &tick_label(v, ystep), "end", 11.0);
        }
        self.raw(&format!(
            r#"<rect x="{l:.1}" y="{t:.1}" width="{w:.1}" height="{h:.1}" fill="none" stroke="black" stroke-width="1.2"/>"#
        ));
        self.text(l + w / 2.0, t + h + 38.0, x_label, "middle", 13.0);
        let (yx, yy) = (l - 52.0, t + h / 2.0);
        self.raw(&format!(
            r#"<text x="{yx:.1}" y="{yy:.1}" font-size="13" text-anchor="middle" transform="rotate(-90 {yx:.1} {yy:.1})">{}</text>"#,
            escape(y_label)
        ));
        self.text(l + w / 2.0, t - 14.0, title, "middle", 14.0);
    }

    /// A text at pixel `(x, y)`; `anchor` is `start`, `middle` or `end`.
    pub fn text(&mut self, x: f64, y: f64, s: &str, anchor: &str, size: f64) {
        self.raw(&format!(
            r#"<text x="{x:.1}" y="{y:.1}" font-size="{size}" text-anchor="{anchor}">{}</text>"#,
            escape(s)
        ));
    }

    /// A polyline through data points, clipped to the plot area.
    pub fn polyline(&mut self, axes: &Axes, points: &[(f64, f64)], stroke: Stroke<'_>) {
        if points.len() < 2 {
            return;
        }
        let mut d = String::with_capacity(points.len().saturating_mul(16));
        for (i, &(x, y)) in points.iter().enumerate() {
            let (px, py) = axes.px(x, y);
            let _ = write!(d, "{}{px:.1},{py:.1} ", if i == 0 { "M" } else { "L" });
        }
        let dash = stroke
            .dash
            .map_or(String::new(), |p| format!(r#" stroke-dasharray="{p}""#));
        self.raw(&format!(
            r#"<path d="{}" fill="none" stroke="{}" stroke-width="{}" stroke-linejoin="round"{dash} clip-path="url(#plot)"/>"#,
            d.trim_end(),
            stroke.colour,
            stroke.width
        ));
    }

    /// A filled polygon through data points, clipped to the plot area.
    pub fn polygon(&mut self, axes: &Axes, points: &[(f64, f64)], fill: &str, opacity: f64) {
        let pts: Vec<String> = points
            .iter()
            .map(|&(x, y)| {
                let (px, py) = axes.px(x, y);
                format!("{px:.1},{py:.1}")
            })
            .collect();
        self.raw(&format!(
            r#"<polygon points="{}" fill="{fill}" fill-opacity="{opacity}" stroke="none" clip-path="url(#plot)"/>"#,
            pts.join(" ")
        ));
    }

    /// Filled discs of `radius` pixels at data points, clipped to the plot area.
    pub fn dots(&mut self, axes: &Axes, points: &[(f64, f64)], radius: f64, fill: &str) {
        if points.is_empty() {
            return;
        }
        let mut g = format!(r#"<g fill="{fill}" stroke="none" clip-path="url(#plot)">"#);
        for &(x, y) in points {
            let (px, py) = axes.px(x, y);
            let _ = write!(g, r#"<circle cx="{px:.1}" cy="{py:.1}" r="{radius:.1}"/>"#);
        }
        g.push_str("</g>");
        self.raw(&g);
    }

    /// Circles of their own radius in metres, outlined in `colour`, clipped
    /// to the plot area: `(x, y, radius)` each.
    pub fn circles(&mut self, axes: &Axes, circles: &[(f64, f64, f64)], colour: &str) {
        if circles.is_empty() {
            return;
        }
        let mut g =
            format!(r#"<g fill="none" stroke="{colour}" stroke-width="1" clip-path="url(#plot)">"#);
        for &(x, y, r) in circles {
            let (px, py) = axes.px(x, y);
            let pr = (axes.px(x + r, y).0 - px).abs().max(1.0);
            let _ = write!(g, r#"<circle cx="{px:.1}" cy="{py:.1}" r="{pr:.1}"/>"#);
        }
        g.push_str("</g>");
        self.raw(&g);
    }

    /// A cross (×) of `size` pixels at each data point, in `colour`, clipped
    /// to the plot area, grouped under `class` (to find them in the file).
    pub fn crosses(
        &mut self,
        axes: &Axes,
        points: &[(f64, f64)],
        size: f64,
        colour: &str,
        class: &str,
    ) {
        if points.is_empty() {
            return;
        }
        let mut g = format!(
            r#"<g class="{class}" stroke="{colour}" stroke-width="2" fill="none" clip-path="url(#plot)">"#
        );
        let h = size / 2.0;
        for &(x, y) in points {
            let (px, py) = axes.px(x, y);
            let _ = write!(
                g,
                r#"<path d="M{:.1},{:.1} L{:.1},{:.1} M{:.1},{:.1} L{:.1},{:.1}"/>"#,
                px - h,
                py - h,
                px + h,
                py + h,
                px - h,
                py + h,
                px + h,
                py - h
            );
        }
        g.push_str("</g>");
        self.raw(&g);
    }

    /// The clip path of the plot area; call before drawing clipped elements.
    pub fn clip_to(&mut self, axes: &Axes) {
        let (l, t, w, h) = axes.area;
        self.raw(&format!(
            r#"<defs><clipPath id="plot"><rect x="{l:.1}" y="{t:.1}" width="{w:.1}" height="{h:.1}"/></clipPath></defs>"#
        ));
    }

    /// A legend box in the corner of the plot area that covers the fewest of
    /// `avoid` (data points): `(swatch, filled, label)` where the swatch is a
    /// line stroke or, with `filled`, a filled square.
    pub fn legend(
        &mut self,
        axes: &Axes,
        entries: &[(Stroke<'_>, bool, &str)],
        avoid: &[(f64, f64)],
    ) {
        let (l, t, w, h) = axes.area;
        let longest = entries
            .iter()
            .map(|e| e.2.chars().count())
            .max()
            .unwrap_or(0);
        let bw = 40.0 + 6.5 * longest as f64;
        let bh = 8.0 + 18.0 * entries.len() as f64;
        let corners = [
            (l + w - bw - 8.0, t + 8.0),
            (l + w - bw - 8.0, t + h - bh - 8.0),
            (l + 8.0, t + 8.0),
            (l + 8.0, t + h - bh - 8.0),
        ];
        let covered = |&(cx, cy): &(f64, f64)| {
            avoid
                .iter()
                .map(|&(x, y)| axes.px(x, y))
                .filter(|&(px, py)| {
                    px >= cx - 6.0 && px <= cx + bw + 6.0 && py >= cy - 6.0 && py <= cy + bh + 6.0
                })
                .count()
        };
        let (x0, y0) = corners
            .iter()
            .copied()
            .min_by_key(covered)
            .unwrap_or(corners[0]);
        self.raw(&format!(
            r##"<rect x="{x0:.1}" y="{y0:.1}" width="{bw:.1}" height="{bh:.1}" fill="white" fill-opacity="0.9" stroke="#999" stroke-width="0.8"/>"##
        ));
        for (i, (stroke, filled, label)) in entries.iter().enumerate() {
            let y = y0 + 16.0 + 18.0 * i as f64;
            if *filled {
                self.raw(&format!(
                    r#"<rect x="{:.1}" y="{:.1}" width="22" height="10" fill="{}" fill-opacity="0.35"/>"#,
                    x0 + 8.0,
                    y - 8.0,
                    stroke.colour
                ));
            } else {
                let dash = stroke
                    .dash
                    .map_or(String::new(), |p| format!(r#" stroke-dasharray="{p}""#));
                self.raw(&format!(
                    r#"<line x1="{:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="{}" stroke-width="{}"{dash}/>"#,
                    x0 + 8.0,
                    y - 3.0,
                    x0 + 30.0,
                    y - 3.0,
                    stroke.colour,
                    stroke.width
                ));
            }
            self.text(x0 + 36.0, y + 1.0, label, "start", 11.0);
        }
    }
}

fn step_of(ticks: &[f64]) -> f64 {
    match ticks {
        [a, b, ..] => b - a,
        _ => 1.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_round_and_inside() {
        assert_eq!(
            nice_ticks(0.0, 10.0, 5),
            vec![0.0, 2.0, 4.0, 6.0, 8.0, 10.0]
        );
        assert_eq!(nice_ticks(0.0, 1.05, 5).len(), 6);
        let t = nice_ticks(-0.83, 0.12, 5);
        assert!(t.iter().all(|v| *v >= -0.83 && *v <= 0.12));
        assert!((t[1] - t[0] - 0.2).abs() < 1e-12);
        assert_eq!(nice_ticks(1.0, 1.0, 5), vec![1.0]);
        assert_eq!(tick_label(-0.0, 0.2), "0.0");
        assert_eq!(tick_label(0.05, 0.05), "0.05");
        assert_eq!(tick_label(40.0, 20.0), "40");
    }

    #[test]
    fn equal_axes_keep_one_scale() {
        let a = Axes::equal((0.0, 40.0), (0.0, 10.0), 900.0, 700.0);
        let (x0, y0) = a.px(0.0, 0.0);
        let (x1, _) = a.px(1.0, 0.0);
        let (_, y1) = a.px(0.0, 1.0);
        assert!(((x1 - x0) - (y0 - y1)).abs() < 1e-9);
        let (w, h) = a.picture_size();
        assert!(w <= 900.0 + 1e-9 && h <= 700.0 + 1e-9);
    }

    #[test]
    fn document_is_well_formed_enough() {
        let a = Axes::new((0.0, 1.0), (0.0, 1.0), 400.0, 300.0);
        let mut s = Svg::new(&a);
        s.clip_to(&a);
        s.frame(&a, "s (m)", "y (m)", "a <title> & more");
        s.polyline(
            &a,
            &[(0.0, 0.0), (1.0, 1.0)],
            Stroke {
                colour: "red",
                width: 1.0,
                dash: None,
            },
        );
        let doc = s.finish();
        assert!(doc.starts_with("<svg") && doc.trim_end().ends_with("</svg>"));
        assert!(doc.contains("a &lt;title&gt; &amp; more"));
        assert!(doc.contains("M"));
    }
}
