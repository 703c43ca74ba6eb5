//! SVG charts for reports: time series with shaded intervals, and ground tracks.
//!
//! Built on plotters' SVG backend without system fonts: text is written as SVG
//! `<text>` elements and laid out by the viewer. Non-finite points are skipped and
//! break a line (a gap); empty series are allowed and still get a legend entry.

use std::fmt;
use std::path::Path;

use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;

/// Canvas of a time-series chart, pixels.
const LINE_CHART_SIZE: (u32, u32) = (1200, 600);
/// Canvas of a track chart, pixels.
const TRACK_CHART_SIZE: (u32, u32) = (900, 900);
/// Space around the plot, pixels.
const MARGIN_PX: u32 = 16;
/// Space for the x-axis tick labels and description, pixels.
const X_LABEL_AREA_PX: u32 = 50;
/// Space for the y-axis tick labels and description, pixels.
const Y_LABEL_AREA_PX: u32 = 70;
/// Fraction of the data span added on each side of an axis.
const RANGE_MARGIN: f64 = 0.05;
/// Opacity of shaded bands.
const BAND_ALPHA: f64 = 0.3;

const FONT: &str = "sans-serif";
const TITLE_FONT_PX: u32 = 24;
const LABEL_FONT_PX: u32 = 15;

/// Default series colours (Tableau 10: distinct, colour-blind friendly in order).
pub const PALETTE: [(u8, u8, u8); 10] = [
    (31, 119, 180),
    (255, 127, 14),
    (44, 160, 44),
    (214, 39, 40),
    (148, 103, 189),
    (140, 86, 75),
    (227, 119, 194),
    (127, 127, 127),
    (188, 189, 34),
    (23, 190, 207),
];

/// How a series is drawn.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Style {
    /// Connected line; non-finite points break it.
    #[default]
    Line,
    /// One dot per point.
    Points,
}

/// One named data series.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    /// Legend text (no legend entry when empty).
    pub name: String,
    /// (x, y) points; points with a non-finite coordinate are skipped.
    pub points: Vec<(f64, f64)>,
    /// RGB colour; `None` takes the next colour of [`PALETTE`] by series index.
    pub color: Option<(u8, u8, u8)>,
    pub style: Style,
}

/// A shaded x-interval (GNSS disturbance zone, outage, stop, ...), drawn under the data.
#[derive(Clone, Debug, PartialEq)]
pub struct Band {
    pub start: f64,
    pub end: f64,
    /// Legend text; bands sharing a label share one legend entry (none when empty).
    pub label: String,
    pub color: (u8, u8, u8),
}

/// A time-series chart.
#[derive(Clone, Copy, Debug)]
pub struct Chart<'a> {
    pub title: &'a str,
    pub x_label: &'a str,
    pub y_label: &'a str,
    pub series: &'a [Series],
    pub bands: &'a [Band],
    /// Fixed y range (min, max); `None` fits the data.
    pub y_range: Option<(f64, f64)>,
    /// How the y tick labels read.
    pub y_format: YFormat,
}

/// Tick labels of the y axis.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum YFormat {
    /// Plain numbers.
    #[default]
    Number,
    /// Minutes as m:ss (pace in min/km).
    MinSec,
}

/// A tick label: at most three decimals, trailing zeros dropped.
fn tick(v: f64) -> String {
    let t = format!("{v:.3}");
    let t = t.trim_end_matches('0').trim_end_matches('.');
    if t == "-0" {
        "0".into()
    } else {
        t.into()
    }
}

/// `m:ss` of a value in minutes (5.5 → "5:30").
pub fn min_sec(minutes: f64) -> String {
    if !minutes.is_finite() {
        return String::new();
    }
    let s = (minutes * 60.0).round() as i64;
    format!("{}:{:02}", s / 60, (s % 60).abs())
}

/// A line of report text as HTML: `&`, `<`, `>` escaped, `` `code` `` as `<code>`,
/// `**bold**` as `<strong>` (the two inline marks the reports' Markdown uses).
pub fn inline_html(text: &str) -> String {
    let escaped = text
        .replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;");
    let mut out = String::with_capacity(escaped.len());
    let (mut code, mut bold) = (false, false);
    let mut rest = escaped.as_str();
    while let Some(c) = rest.chars().next() {
        if !code && rest.starts_with("**") {
            out.push_str(if bold { "</strong>" } else { "<strong>" });
            bold = !bold;
            rest = &rest[2..];
            continue;
        }
        if c == '`' {
            out.push_str(if code { "</code>" } else { "<code>" });
            code = !code;
        } else {
            out.push(c);
        }
        rest = &rest[c.len_utf8()..];
    }
    // An unpaired mark is closed rather than left open.
    if code {
        out.push_str("</code>");
    }
    if bold {
        out.push_str("</strong>");
    }
    out
}

/// Why a chart could not be written.
#[derive(Debug)]
pub enum ReportError {
    /// A fixed range is not finite or not increasing.
    InvalidRange {
        what: &'static str,
        min: f64,
        max: f64,
    },
    /// Drawing or writing the file failed.
    Draw(String),
}

impl fmt::Display for ReportError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ReportError::InvalidRange { what, min, max } => {
                write!(f, "invalid {what} range {min}..{max}")
            }
            ReportError::Draw(e) => write!(f, "cannot draw chart: {e}"),
        }
    }
}

impl std::error::Error for ReportError {}

fn draw_err(e: impl fmt::Display) -> ReportError {
    ReportError::Draw(e.to_string())
}

/// Write a time-series chart (lines or points, legend, shaded bands) as SVG.
pub fn line_chart(path: &Path, chart: &Chart) -> Result<(), ReportError> {
    let mut x = Extent::default();
    let mut y = Extent::default();
    for s in chart.series {
        for &(px, py) in finite_points(&s.points) {
            x.add(px);
            y.add(py);
        }
    }
    for b in chart.bands {
        if let Some((s, e)) = band_span(b) {
            x.add(s);
            x.add(e);
        }
    }
    let x_range = x.padded();
    let y_range = match chart.y_range {
        Some((min, max)) => {
            if !(min.is_finite() && max.is_finite() && min < max) {
                return Err(ReportError::InvalidRange {
                    what: "y",
                    min,
                    max,
                });
            }
            (min, max)
        }
        None => y.padded(),
    };

    let mut entries: Vec<Entry> = Vec::new();
    for b in chart.bands {
        if !b.label.is_empty() && !entries.iter().any(|e| e.text == b.label) {
            entries.push(Entry {
                text: b.label.clone(),
                swatch: Swatch::Band(b.color),
            });
        }
    }
    entries.extend(series_entries(chart.series));
    let root = SVGBackend::new(path, LINE_CHART_SIZE).into_drawing_area();
    root.fill(&WHITE).map_err(draw_err)?;
    let area = root
        .margin(MARGIN_PX / 2, 0, 0, 0)
        .titled(chart.title, (FONT, TITLE_FONT_PX))
        .map_err(draw_err)?;
    let area = legend_strip(&area, &entries)?;
    let mut ctx = ChartBuilder::on(&area)
        .margin(MARGIN_PX)
        .x_label_area_size(X_LABEL_AREA_PX)
        .y_label_area_size(Y_LABEL_AREA_PX)
        .build_cartesian_2d(x_range.0..x_range.1, y_range.0..y_range.1)
        .map_err(draw_err)?;
    let y_fmt = chart.y_format;
    ctx.configure_mesh()
        .x_desc(chart.x_label)
        .y_desc(chart.y_label)
        .y_label_formatter(&move |v: &f64| match y_fmt {
            YFormat::Number => tick(*v),
            YFormat::MinSec => min_sec(*v),
        })
        .label_style((FONT, LABEL_FONT_PX))
        .light_line_style(RGBColor(236, 236, 236))
        .draw()
        .map_err(draw_err)?;

    // Bands first, so the data is drawn over them.
    for b in chart.bands {
        let Some((s, e)) = band_span(b) else {
            continue;
        };
        let color = rgb(b.color);
        let style = color.mix(BAND_ALPHA).filled();
        ctx.draw_series(std::iter::once(Rectangle::new(
            [(s, y_range.0), (e, y_range.1)],
            style,
        )))
        .map_err(draw_err)?;
    }

    draw_series(&mut ctx, chart.series)?;
    root.present().map_err(draw_err)
}

/// Write ground tracks as SVG: x = east (m), y = north (m), one metre the same length
/// on both axes.
pub fn track_chart(path: &Path, title: &str, series: &[Series]) -> Result<(), ReportError> {
    let mut x = Extent::default();
    let mut y = Extent::default();
    for s in series {
        for &(px, py) in finite_points(&s.points) {
            x.add(px);
            y.add(py);
        }
    }
    let (mut x_range, mut y_range) = (x.padded(), y.padded());

    let root = SVGBackend::new(path, TRACK_CHART_SIZE).into_drawing_area();
    root.fill(&WHITE).map_err(draw_err)?;
    let area = root
        .margin(MARGIN_PX / 2, 0, 0, 0)
        .titled(title, (FONT, TITLE_FONT_PX))
        .map_err(draw_err)?;
    let area = legend_strip(&area, &series_entries(series))?;
    // Plot size in pixels once margins and label areas are taken off; widen the
    // narrower range so that metres per pixel match on both axes.
    let (w, h) = area.dim_in_pixel();
    let plot_w = f64::from(w.saturating_sub(2 * MARGIN_PX + Y_LABEL_AREA_PX).max(1));
    let plot_h = f64::from(h.saturating_sub(2 * MARGIN_PX + X_LABEL_AREA_PX).max(1));
    let m_per_px = ((x_range.1 - x_range.0) / plot_w).max((y_range.1 - y_range.0) / plot_h);
    x_range = widen(x_range, m_per_px * plot_w);
    y_range = widen(y_range, m_per_px * plot_h);

    let mut ctx = ChartBuilder::on(&area)
        .margin(MARGIN_PX)
        .x_label_area_size(X_LABEL_AREA_PX)
        .y_label_area_size(Y_LABEL_AREA_PX)
        .build_cartesian_2d(x_range.0..x_range.1, y_range.0..y_range.1)
        .map_err(draw_err)?;
    ctx.configure_mesh()
        .x_desc("east (m)")
        .y_desc("north (m)")
        .label_style((FONT, LABEL_FONT_PX))
        .light_line_style(RGBColor(236, 236, 236))
        .draw()
        .map_err(draw_err)?;
    draw_series(&mut ctx, series)?;
    root.present().map_err(draw_err)
}

type Ctx<'a> = ChartContext<'a, SVGBackend<'a>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

fn draw_series(ctx: &mut Ctx, series: &[Series]) -> Result<(), ReportError> {
    for (i, s) in series.iter().enumerate() {
        let color = rgb(s.color.unwrap_or(PALETTE[i % PALETTE.len()]));
        match s.style {
            Style::Line => {
                for seg in segments(&s.points) {
                    ctx.draw_series(LineSeries::new(seg.iter().copied(), color.stroke_width(2)))
                        .map_err(draw_err)?;
                }
            }
            Style::Points => {
                ctx.draw_series(
                    finite_points(&s.points).map(|&p| Circle::new(p, 2, color.filled())),
                )
                .map_err(draw_err)?;
            }
        }
    }
    Ok(())
}

/// What a legend entry shows beside its text.
#[derive(Clone, Copy, Debug)]
enum Swatch {
    Line((u8, u8, u8)),
    Dot((u8, u8, u8)),
    Band((u8, u8, u8)),
}

/// One legend entry.
#[derive(Clone, Debug)]
struct Entry {
    text: String,
    swatch: Swatch,
}

/// Height of one row of the legend strip, pixels.
const LEGEND_ROW_PX: u32 = 24;
/// Width of a swatch and the gaps around an entry, pixels.
const SWATCH_PX: i32 = 22;
const ENTRY_GAP_PX: i32 = 22;

fn series_entries(series: &[Series]) -> Vec<Entry> {
    series
        .iter()
        .enumerate()
        .filter(|(_, s)| !s.name.is_empty())
        .map(|(i, s)| {
            let c = s.color.unwrap_or(PALETTE[i % PALETTE.len()]);
            Entry {
                text: s.name.clone(),
                swatch: match s.style {
                    Style::Line => Swatch::Line(c),
                    Style::Points => Swatch::Dot(c),
                },
            }
        })
        .collect()
}

/// Draw the legend as rows of entries in a strip above the plot (so it never covers
/// the data) and return the area left for the plot. Text widths are estimated (the
/// SVG has no font metrics): 0.5 em per character.
fn legend_strip<'a>(
    area: &DrawingArea<SVGBackend<'a>, Shift>,
    entries: &[Entry],
) -> Result<DrawingArea<SVGBackend<'a>, Shift>, ReportError> {
    if entries.is_empty() {
        return Ok(area.clone());
    }
    let (w, _) = area.dim_in_pixel();
    let left = (MARGIN_PX + Y_LABEL_AREA_PX) as i32;
    let right = w as i32 - MARGIN_PX as i32;
    let mut rows: Vec<Vec<(i32, &Entry)>> = vec![Vec::new()];
    let mut x = left;
    for e in entries {
        let width =
            SWATCH_PX + 6 + (0.5 * LABEL_FONT_PX as f64 * e.text.chars().count() as f64) as i32;
        if x + width > right && x > left {
            rows.push(Vec::new());
            x = left;
        }
        rows.last_mut().expect("a row").push((x, e));
        x += width + ENTRY_GAP_PX;
    }
    let strip = LEGEND_ROW_PX * rows.len() as u32 + 6;
    let (top, rest) = area.split_vertically(strip);
    let font = (FONT, LABEL_FONT_PX).into_font();
    for (r, row) in rows.iter().enumerate() {
        let y = (LEGEND_ROW_PX * r as u32 + LEGEND_ROW_PX / 2) as i32;
        for &(x, e) in row {
            match e.swatch {
                Swatch::Line(c) => top.draw(&PathElement::new(
                    vec![(x, y), (x + SWATCH_PX - 4, y)],
                    rgb(c).stroke_width(3),
                )),
                Swatch::Dot(c) => {
                    top.draw(&Circle::new((x + SWATCH_PX / 2 - 2, y), 4, rgb(c).filled()))
                }
                Swatch::Band(c) => top.draw(&Rectangle::new(
                    [(x, y - 7), (x + SWATCH_PX - 4, y + 7)],
                    rgb(c).mix(BAND_ALPHA * 2.0).filled(),
                )),
            }
            .map_err(draw_err)?;
            top.draw(&Text::new(
                e.text.as_str(),
                (x + SWATCH_PX + 4, y - LABEL_FONT_PX as i32 / 2),
                font.clone(),
            ))
            .map_err(draw_err)?;
        }
    }
    Ok(rest)
}

fn rgb((r, g, b): (u8, u8, u8)) -> RGBColor {
    RGBColor(r, g, b)
}

/// Points with both coordinates finite.
fn finite_points(points: &[(f64, f64)]) -> impl Iterator<Item = &(f64, f64)> {
    points
        .iter()
        .filter(|(x, y)| x.is_finite() && y.is_finite())
}

/// Runs of consecutive finite points (a non-finite point ends a run).
fn segments(points: &[(f64, f64)]) -> impl Iterator<Item = &[(f64, f64)]> {
    points
        .split(|(x, y)| !(x.is_finite() && y.is_finite()))
        .filter(|s| !s.is_empty())
}

/// A band's (start, end) in increasing order, `None` if not finite.
fn band_span(b: &Band) -> Option<(f64, f64)> {
    (b.start.is_finite() && b.end.is_finite()).then(|| (b.start.min(b.end), b.start.max(b.end)))
}

/// Min and max of the values seen.
#[derive(Clone, Copy, Debug)]
struct Extent {
    min: f64,
    max: f64,
}

impl Default for Extent {
    fn default() -> Self {
        Self {
            min: f64::INFINITY,
            max: f64::NEG_INFINITY,
        }
    }
}

impl Extent {
    fn add(&mut self, v: f64) {
        self.min = self.min.min(v);
        self.max = self.max.max(v);
    }

    /// The range with a margin on each side; (0, 1) without data, ±1 around a
    /// single value (or ±5 % of it, whichever is larger).
    fn padded(&self) -> (f64, f64) {
        if self.min > self.max {
            return (0.0, 1.0);
        }
        let span = self.max - self.min;
        if span <= 0.0 {
            let d = (0.05 * self.min.abs()).max(1.0);
            return (self.min - d, self.max + d);
        }
        (
            self.min - RANGE_MARGIN * span,
            self.max + RANGE_MARGIN * span,
        )
    }
}

/// `range` grown symmetrically to `span` (never shrunk).
fn widen(range: (f64, f64), span: f64) -> (f64, f64) {
    let grow = (span - (range.1 - range.0)).max(0.0) / 2.0;
    (range.0 - grow, range.1 + grow)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    #[test]
    fn inline_marks_become_html() {
        assert_eq!(
            inline_html("**Next** via `PaceTracker.calibration()` & <b>"),
            "<strong>Next</strong> via <code>PaceTracker.calibration()</code> &amp; &lt;b&gt;"
        );
        assert_eq!(inline_html("`a**b`"), "<code>a**b</code>");
        assert_eq!(inline_html("open `x"), "open <code>x</code>");
    }

    /// A fresh directory under the system temp dir, removed on drop.
    struct TempDir(PathBuf);

    impl TempDir {
        fn new(tag: &str) -> Self {
            let nanos = std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map(|d| d.as_nanos())
                .unwrap_or(0);
            let dir = std::env::temp_dir().join(format!(
                "stridekit-report-{tag}-{}-{nanos}",
                std::process::id()
            ));
            std::fs::create_dir_all(&dir).expect("create temp dir");
            Self(dir)
        }
    }

    impl Drop for TempDir {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }

    /// Minimal well-formedness check: one root `<svg>` element, every tag closed in
    /// order, nothing but whitespace after the root.
    fn assert_well_formed_svg(text: &str) {
        let mut rest = text.trim_start();
        if rest.starts_with("<?xml") {
            let end = rest.find("?>").expect("unterminated XML declaration");
            rest = rest[end + 2..].trim_start();
        }
        assert!(rest.starts_with("<svg"), "no <svg> root: {:.80}", rest);
        let mut stack: Vec<&str> = Vec::new();
        let mut seen_root = false;
        while let Some(open) = rest.find('<') {
            if stack.is_empty() && seen_root {
                panic!("content after the root element");
            }
            let close = rest[open..].find('>').expect("unterminated tag") + open;
            let tag = &rest[open + 1..close];
            assert!(!tag.contains('<'), "'<' inside a tag: {tag}");
            if let Some(name) = tag.strip_prefix('/') {
                assert_eq!(stack.pop(), Some(name.trim()), "mismatched </{name}>");
            } else if !tag.ends_with('/') && !tag.starts_with('!') {
                let name = tag.split_whitespace().next().expect("empty tag");
                stack.push(name);
            }
            seen_root = true;
            rest = &rest[close + 1..];
        }
        assert!(stack.is_empty(), "unclosed elements: {stack:?}");
        assert!(rest.trim().is_empty(), "trailing text: {rest:.80}");
    }

    /// The contents of all `<text>` elements, as written (escaped).
    fn texts(svg: &str) -> Vec<&str> {
        svg.split("<text")
            .skip(1)
            .filter_map(|t| {
                let start = t.find('>')? + 1;
                let end = t.find("</text>")?;
                Some(t[start..end].trim())
            })
            .collect()
    }

    fn assert_texts(svg: &str, expected: &[&str]) {
        let found = texts(svg);
        for e in expected {
            assert!(found.contains(e), "no text {e:?} in {found:?}");
        }
    }

    fn line(name: &str, points: Vec<(f64, f64)>) -> Series {
        Series {
            name: name.into(),
            points,
            color: None,
            style: Style::Line,
        }
    }

    fn dots(name: &str, points: Vec<(f64, f64)>) -> Series {
        Series {
            style: Style::Points,
            ..line(name, points)
        }
    }

    fn pace_series() -> Vec<Series> {
        let t: Vec<f64> = (0..600).map(f64::from).collect();
        let truth: Vec<(f64, f64)> = t
            .iter()
            .map(|&t| (t, 3.0 + 0.3 * (t / 60.0).sin()))
            .collect();
        let gnss: Vec<(f64, f64)> = t
            .iter()
            .map(|&t| {
                // A GNSS outage between 200 s and 260 s shows as a gap.
                let v = if (200.0..260.0).contains(&t) {
                    f64::NAN
                } else {
                    3.0 + 0.3 * (t / 60.0).sin() + 0.4 * (t * 1.7).sin()
                };
                (t, v)
            })
            .collect();
        vec![
            line("truth", truth),
            dots("GNSS speed", gnss),
            Series {
                color: Some((0, 0, 0)),
                ..line("fused <adaptive>", Vec::new())
            },
        ]
    }

    #[test]
    fn writes_line_and_track_charts() {
        let dir = TempDir::new("charts");

        let series = pace_series();
        let bands = [
            Band {
                start: 200.0,
                end: 260.0,
                label: "GNSS outage".into(),
                color: (214, 39, 40),
            },
            Band {
                start: 400.0,
                end: 380.0, // reversed: still drawn
                label: "stop".into(),
                color: (127, 127, 127),
            },
            Band {
                start: 500.0,
                end: 520.0,
                label: "GNSS outage".into(),
                color: (214, 39, 40),
            },
        ];
        let line_path = dir.0.join("speed.svg");
        line_chart(
            &line_path,
            &Chart {
                title: "Speed & pace — run 1",
                x_label: "time (s)",
                y_label: "speed (m/s)",
                series: &series,
                bands: &bands,
                y_range: None,
                y_format: YFormat::Number,
            },
        )
        .expect("line chart written");
        let svg = std::fs::read_to_string(&line_path).expect("read line chart");
        assert_well_formed_svg(&svg);
        assert_texts(
            &svg,
            &[
                "Speed &amp; pace — run 1",
                "time (s)",
                "speed (m/s)",
                "truth",
                "GNSS speed",
                "fused &lt;adaptive&gt;",
                "GNSS outage",
                "stop",
            ],
        );
        let outage_entries = texts(&svg).iter().filter(|t| **t == "GNSS outage").count();
        assert_eq!(outage_entries, 1, "one legend entry per band label");

        let track: Vec<(f64, f64)> = (0..400)
            .map(|i| {
                let a = f64::from(i) / 400.0 * std::f64::consts::TAU;
                (200.0 * a.cos(), 50.0 * a.sin())
            })
            .collect();
        let mut fixes = track.clone();
        fixes[10] = (f64::NAN, 0.0);
        let track_path = dir.0.join("track.svg");
        track_chart(
            &track_path,
            "Track",
            &[
                line("truth", track),
                dots("fixes", fixes),
                line("", Vec::new()),
            ],
        )
        .expect("track chart written");
        let svg = std::fs::read_to_string(&track_path).expect("read track chart");
        assert_well_formed_svg(&svg);
        assert_texts(&svg, &["Track", "east (m)", "north (m)", "truth", "fixes"]);
    }

    #[test]
    fn empty_chart_and_bad_range() {
        let dir = TempDir::new("empty");
        let path = dir.0.join("empty.svg");
        let chart = Chart {
            title: "Nothing",
            x_label: "x",
            y_label: "y",
            series: &[],
            bands: &[],
            y_range: None,
            y_format: YFormat::Number,
        };
        line_chart(&path, &chart).expect("empty chart written");
        assert_well_formed_svg(&std::fs::read_to_string(&path).unwrap());
        track_chart(&dir.0.join("empty-track.svg"), "Nothing", &[]).expect("empty track");

        let bad = Chart {
            y_range: Some((1.0, f64::NAN)),
            ..chart
        };
        assert!(matches!(
            line_chart(&path, &bad),
            Err(ReportError::InvalidRange { what: "y", .. })
        ));
        let missing = dir.0.join("no-such-dir").join("x.svg");
        assert!(matches!(
            line_chart(&missing, &chart),
            Err(ReportError::Draw(_))
        ));
    }

    #[test]
    fn ranges() {
        let mut e = Extent::default();
        assert_eq!(e.padded(), (0.0, 1.0));
        e.add(5.0);
        assert_eq!(e.padded(), (4.0, 6.0));
        e.add(15.0);
        assert_eq!(e.padded(), (4.5, 15.5));
        assert_eq!(widen((0.0, 10.0), 20.0), (-5.0, 15.0));
        assert_eq!(widen((0.0, 10.0), 5.0), (0.0, 10.0));
    }
}
