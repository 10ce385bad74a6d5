//! Small chart helpers on top of `plotters`: line charts (linear or log axes), labelled scatter
//! plots, heatmaps with a colour bar, and polar plots, written as PNG (encoded with `image`) or
//! SVG. Used by `luz brdf --plot`; meant for later charts too (speed against accuracy).
//!
//! Text is drawn with `ab_glyph` from a TrueType font read at run time: `$LUZ_FONT` if set, else
//! [`DEFAULT_FONT`] from the Debian package [`FONT_PACKAGE`]. [`init_font`] (called by every
//! `save`/`render` function) fails with a message naming both when the font is missing.
//!
//! Every chart is plain data ([`LineChart`], [`ScatterChart`], [`Heatmap`], [`PolarChart`],
//! wrapped in [`Chart`]); [`save`] picks PNG or SVG by the file extension, [`save_png_svg`] writes
//! both, [`render_rgb`] returns the RGB8 pixels.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use anyhow::{anyhow, bail, Context as _, Result};
use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::FontStyle;

pub use plotters::style::RGBColor;

/// The font read when `$LUZ_FONT` is not set.
pub const DEFAULT_FONT: &str = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
/// The Debian package that installs [`DEFAULT_FONT`].
pub const FONT_PACKAGE: &str = "fonts-dejavu-core";
/// The environment variable that overrides [`DEFAULT_FONT`] (a `.ttf` or `.otf` file).
pub const FONT_ENV: &str = "LUZ_FONT";

const FAMILY: &str = "sans-serif";

/// Loads the chart font once per process (see the module docs). Idempotent; the error, if any,
/// is the same on every call.
pub fn init_font() -> Result<()> {
    static FONT: OnceLock<std::result::Result<(), String>> = OnceLock::new();
    FONT.get_or_init(|| {
        let (path, from_env) = match std::env::var_os(FONT_ENV) {
            Some(p) if !p.is_empty() => (PathBuf::from(p), true),
            _ => (PathBuf::from(DEFAULT_FONT), false),
        };
        let bytes = std::fs::read(&path).map_err(|e| {
            if from_env {
                format!(
                    "cannot read the chart font {} (from ${FONT_ENV}): {e}",
                    path.display()
                )
            } else {
                format!(
                    "cannot read the chart font {}: {e}; install the Debian package {FONT_PACKAGE} \
                     (apt-get install {FONT_PACKAGE}) or set ${FONT_ENV} to a .ttf file",
                    path.display()
                )
            }
        })?;
        // plotters keeps `&'static` font data: the one font of the process is leaked once.
        let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
        for family in [FAMILY, "serif", "monospace"] {
            plotters::style::register_font(family, FontStyle::Normal, bytes)
                .map_err(|_| format!("{} is not a TrueType/OpenType font", path.display()))?;
        }
        Ok(())
    })
    .clone()
    .map_err(|e| anyhow!(e))
}

// ---------------------------------------------------------------------------------------------
// Chart descriptions
// ---------------------------------------------------------------------------------------------

/// One axis: its label, an optional fixed range (otherwise fitted to the data) and log scale.
#[derive(Debug, Clone, Default)]
pub struct Axis {
    pub label: String,
    pub range: Option<(f64, f64)>,
    /// Base-10 logarithmic scale; values ≤ 0 are left out.
    pub log: bool,
}

impl Axis {
    /// A linear axis fitted to the data.
    pub fn new(label: impl Into<String>) -> Self {
        Axis {
            label: label.into(),
            range: None,
            log: false,
        }
    }
    /// With a fixed range.
    pub fn range(mut self, lo: f64, hi: f64) -> Self {
        self.range = Some((lo, hi));
        self
    }
    /// Logarithmic.
    pub fn log(mut self) -> Self {
        self.log = true;
        self
    }
}

/// Where a legend goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Legend {
    #[default]
    UpperRight,
    UpperLeft,
    LowerRight,
    LowerLeft,
    None,
}

/// A polyline with a legend entry.
#[derive(Debug, Clone, Default)]
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    /// `None`: the next colour of [`palette`].
    pub color: Option<RGBColor>,
    pub dashed: bool,
    /// Draw a small circle at every point as well.
    pub markers: bool,
}

impl Series {
    pub fn new(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Series {
            label: label.into(),
            points,
            ..Default::default()
        }
    }
    pub fn color(mut self, c: RGBColor) -> Self {
        self.color = Some(c);
        self
    }
    pub fn dashed(mut self) -> Self {
        self.dashed = true;
        self
    }
    pub fn markers(mut self) -> Self {
        self.markers = true;
        self
    }
}

/// Lines in x-y with optional log axes.
#[derive(Debug, Clone, Default)]
pub struct LineChart {
    pub title: String,
    pub x: Axis,
    pub y: Axis,
    pub series: Vec<Series>,
    pub legend: Legend,
}

/// A point of a [`ScatterChart`]: drawn in its group's colour, with its label beside it.
#[derive(Debug, Clone, Default)]
pub struct LabeledPoint {
    pub x: f64,
    pub y: f64,
    pub label: String,
    /// Index into [`ScatterChart::groups`] (colour and legend entry).
    pub group: usize,
}

/// Labelled points (e.g. one per model: time against error), optional log axes.
#[derive(Debug, Clone, Default)]
pub struct ScatterChart {
    pub title: String,
    pub x: Axis,
    pub y: Axis,
    pub points: Vec<LabeledPoint>,
    /// Legend names of the groups; may be empty (no legend).
    pub groups: Vec<String>,
    pub legend: Legend,
}

/// A grid of values drawn as coloured cells, with a colour bar.
#[derive(Debug, Clone, Default)]
pub struct Heatmap {
    pub title: String,
    /// Label and range (required) of the x axis; `log` is ignored.
    pub x: Axis,
    /// Label and range (required) of the y axis; `log` is ignored.
    pub y: Axis,
    pub nx: usize,
    pub ny: usize,
    /// Row-major, `ny` rows of `nx` values; row 0 is at the bottom (lowest y). Non-finite
    /// values, and values ≤ 0 on a log scale, are drawn in grey ([`Heatmap::empty_label`]).
    pub values: Vec<f64>,
    /// Logarithmic colour scale.
    pub log_color: bool,
    /// Colour range; `None`: min to max of the data (on a log scale at most
    /// [`Heatmap::log_decades`] decades below the max).
    pub color_range: Option<(f64, f64)>,
    /// Decades shown on an automatic log colour range (default 4 when 0).
    pub log_decades: f64,
    pub color_label: String,
    /// What grey cells mean (shown under the colour bar when any exist; `\n` breaks lines).
    pub empty_label: String,
}

/// One curve of a [`PolarChart`]: `(angle in degrees, radius ≥ 0)`.
#[derive(Debug, Clone, Default)]
pub struct PolarSeries {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub color: Option<RGBColor>,
    /// Directions (degrees) drawn as dashed rays to the outer ring in the series colour, e.g. the
    /// incident light.
    pub rays: Vec<f64>,
}

/// A polar plot. Angles are in degrees from the vertical (0° up), positive to the right; with
/// `half` only the upper half-plane (−90° … 90°) is drawn, as for a hemisphere above a surface.
#[derive(Debug, Clone, Default)]
pub struct PolarChart {
    pub title: String,
    pub series: Vec<PolarSeries>,
    /// Outer radius; `None`: the largest radius of the data.
    pub r_max: Option<f64>,
    pub half: bool,
    /// What the radius is (written under the plot).
    pub r_label: String,
}

/// Any chart.
#[derive(Debug, Clone)]
pub enum Chart {
    Line(LineChart),
    Scatter(ScatterChart),
    Heatmap(Heatmap),
    Polar(PolarChart),
}

impl Chart {
    /// The chart's title.
    pub fn title(&self) -> &str {
        match self {
            Chart::Line(c) => &c.title,
            Chart::Scatter(c) => &c.title,
            Chart::Heatmap(c) => &c.title,
            Chart::Polar(c) => &c.title,
        }
    }
}

/// `impl From<Kind> for Chart` for each kind of chart, so that each can be passed where a
/// `Chart` is expected.
macro_rules! chart_from {
    ($($variant:ident($kind:ty)),* $(,)?) => {
        $(
            impl From<$kind> for Chart {
                fn from(c: $kind) -> Self {
                    Chart::$variant(c)
                }
            }
        )*
    };
}

chart_from!(
    Line(LineChart),
    Scatter(ScatterChart),
    Heatmap(Heatmap),
    Polar(PolarChart),
);

// ---------------------------------------------------------------------------------------------
// Output
// ---------------------------------------------------------------------------------------------

/// An output format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    Png,
    Svg,
}

impl Format {
    /// From a file extension (`png`, `svg`, case-insensitive).
    pub fn from_path(path: &Path) -> Result<Format> {
        match crate::files::lowercase_extension(path).as_deref() {
            Some("png") => Ok(Format::Png),
            Some("svg") => Ok(Format::Svg),
            _ => bail!("{}: chart files must end in .png or .svg", path.display()),
        }
    }
}

/// Draws `chart` into `width × height` RGB8 pixels (row-major, white background).
pub fn render_rgb(chart: &Chart, width: u32, height: u32) -> Result<Vec<u8>> {
    init_font()?;
    check_size(width, height)?;
    let mut buf = vec![255u8; width as usize * height as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (width, height)).into_drawing_area();
        draw(chart, &root)?;
        root.present().map_err(de)?;
    }
    Ok(buf)
}

/// Writes `chart` to `path`, PNG or SVG by its extension, `width × height` pixels, with the
/// base provenance ([`save_with`]).
pub fn save(chart: &Chart, path: &Path, width: u32, height: u32) -> Result<()> {
    save_with(
        chart,
        path,
        width,
        height,
        &crate::imageio::Provenance::base(),
    )
}

/// [`save`] recording `meta` (plus `luz.chart`, the title, `luz.size` and `luz.encoding`): PNG
/// iTXt chunks as every PNG luz writes, or an SVG `<metadata id="luz-provenance">` element of
/// `key: value` lines (`luz info` reads both).
pub fn save_with(
    chart: &Chart,
    path: &Path,
    width: u32,
    height: u32,
    meta: &crate::imageio::Provenance,
) -> Result<()> {
    let mut meta = meta.clone();
    meta.set("luz.chart", chart.title());
    meta.set("luz.size", format!("{width}x{height}"));
    match Format::from_path(path)? {
        Format::Png => {
            let buf = render_rgb(chart, width, height)?;
            meta.set("luz.encoding", "8-bit sRGB chart");
            crate::imageio::save_png_rgb8_with(path, width, height, &buf, &meta)
                .with_context(|| format!("writing {}", path.display()))?;
        }
        Format::Svg => {
            init_font()?;
            check_size(width, height)?;
            let mut svg = String::new();
            {
                let root = SVGBackend::with_string(&mut svg, (width, height)).into_drawing_area();
                draw(chart, &root)?;
                root.present().map_err(de)?;
            }
            meta.set("luz.encoding", "SVG chart");
            let svg = crate::imageio::provenance::svg_with_metadata(&svg, &meta);
            std::fs::write(path, svg).with_context(|| format!("writing {}", path.display()))?;
        }
    }
    Ok(())
}

/// [`save_png_svg`] recording `meta` ([`save_with`]).
pub fn save_png_svg_with(
    chart: &Chart,
    stem: &Path,
    (width, height): (u32, u32),
    meta: &crate::imageio::Provenance,
) -> Result<[PathBuf; 2]> {
    let png = stem.with_extension("png");
    let svg = stem.with_extension("svg");
    save_with(chart, &png, width, height, meta)?;
    save_with(chart, &svg, width, height, meta)?;
    Ok([png, svg])
}

/// Writes `stem.png` and `stem.svg` (any extension of `stem` is replaced); returns both paths.
pub fn save_png_svg(chart: &Chart, stem: &Path, width: u32, height: u32) -> Result<[PathBuf; 2]> {
    let base = crate::imageio::Provenance::base();
    save_png_svg_with(chart, stem, (width, height), &base)
}

fn check_size(width: u32, height: u32) -> Result<()> {
    if !(64..=16384).contains(&width) || !(64..=16384).contains(&height) {
        bail!("chart size {width}x{height}: each side must be 64 to 16384 pixels");
    }
    Ok(())
}

fn de<E: std::fmt::Debug>(e: E) -> anyhow::Error {
    anyhow!("drawing the chart: {e:?}")
}

/// Draws any chart on a drawing area (of any plotters backend).
pub fn draw<DB: DrawingBackend>(chart: &Chart, root: &DrawingArea<DB, Shift>) -> Result<()> {
    root.fill(&WHITE).map_err(de)?;
    match chart {
        Chart::Line(c) => draw_line(c, root),
        Chart::Scatter(c) => draw_scatter(c, root),
        Chart::Heatmap(c) => draw_heatmap(c, root),
        Chart::Polar(c) => draw_polar(c, root),
    }
}

// ---------------------------------------------------------------------------------------------
// Colours and numbers
// ---------------------------------------------------------------------------------------------

/// A colour-blind-friendly qualitative palette (Okabe-Ito, without yellow), cycling.
pub fn palette(i: usize) -> RGBColor {
    const P: [RGBColor; 7] = [
        RGBColor(0, 114, 178),
        RGBColor(213, 94, 0),
        RGBColor(0, 158, 115),
        RGBColor(204, 121, 167),
        RGBColor(86, 180, 233),
        RGBColor(230, 159, 0),
        RGBColor(0, 0, 0),
    ];
    P[i % P.len()]
}

/// The viridis colour map at `t` ∈ [0, 1] (clamped), piecewise linear through 9 samples.
pub fn viridis(t: f64) -> RGBColor {
    const V: [(f64, f64, f64); 9] = [
        (68.0, 1.0, 84.0),
        (71.0, 44.0, 122.0),
        (59.0, 81.0, 139.0),
        (44.0, 113.0, 142.0),
        (33.0, 144.0, 141.0),
        (39.0, 173.0, 129.0),
        (92.0, 200.0, 99.0),
        (170.0, 220.0, 50.0),
        (253.0, 231.0, 37.0),
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let x = t * (V.len() - 1) as f64;
    let i = (x.floor() as usize).min(V.len() - 2);
    let f = x - i as f64;
    let (a, b) = (V[i], V[i + 1]);
    let m = |p: f64, q: f64| (p + (q - p) * f).round().clamp(0.0, 255.0) as u8;
    RGBColor(m(a.0, b.0), m(a.1, b.1), m(a.2, b.2))
}

/// A short label for a number: up to 4 significant digits, exponent form outside 1e-3 … 1e5.
pub fn format_number(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    if !v.is_finite() {
        return format!("{v}");
    }
    let a = v.abs();
    if !(1e-3..1e5).contains(&a) {
        let s = format!("{v:.1e}");
        return s.replace(".0e", "e");
    }
    let digits = (3 - a.log10().floor() as i32).clamp(0, 6) as usize;
    let s = format!("{v:.digits$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

fn fit(axis: &Axis, values: impl Iterator<Item = f64>) -> (f64, f64) {
    if let Some((lo, hi)) = axis.range {
        return (lo, hi);
    }
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite() && (!axis.log || *v > 0.0)) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if lo > hi {
        return if axis.log { (0.1, 10.0) } else { (0.0, 1.0) };
    }
    if axis.log {
        let (l, h) = (lo.log10(), hi.log10());
        let pad = ((h - l) * 0.06).max(0.1);
        (10f64.powf(l - pad), 10f64.powf(h + pad))
    } else {
        let span = hi - lo;
        let pad = if span > 0.0 {
            span * 0.05
        } else {
            lo.abs().max(1.0) * 0.1
        };
        (lo - pad, hi + pad)
    }
}

fn legend_pos(l: Legend) -> Option<SeriesLabelPosition> {
    match l {
        Legend::UpperRight => Some(SeriesLabelPosition::UpperRight),
        Legend::UpperLeft => Some(SeriesLabelPosition::UpperLeft),
        Legend::LowerRight => Some(SeriesLabelPosition::LowerRight),
        Legend::LowerLeft => Some(SeriesLabelPosition::LowerLeft),
        Legend::None => None,
    }
}

/// The area of `root` below `title`, which this draws at its top.
fn titled<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
) -> Result<DrawingArea<DB, Shift>> {
    let h = root.dim_in_pixel().1;
    // ab_glyph draws glyphs about a quarter of the size above the requested top: leave room.
    let root = root.margin((font_size(h, 22.0) * 0.35) as u32, 0, 0, 0);
    root.titled(title, (FAMILY, font_size(h, 22.0))).map_err(de)
}

/// Draws a cartesian chart's axes as every chart here has them: the axes' labels, numbers by
/// [`format_number`], text at `fs` pixels; light grey grid lines when `grid`, else none.
fn draw_axes<DB, X, Y>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<X, Y>>,
    x: &Axis,
    y: &Axis,
    fs: f64,
    grid: bool,
) -> Result<()>
where
    DB: DrawingBackend,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let mut mesh = chart.configure_mesh();
    if grid {
        mesh.light_line_style(RGBColor(235, 235, 235));
    } else {
        mesh.disable_mesh();
    }
    mesh.x_desc(x.label.as_str())
        .y_desc(y.label.as_str())
        .label_style((FAMILY, fs))
        .axis_desc_style((FAMILY, fs))
        .x_label_formatter(&|v| format_number(*v))
        .y_label_formatter(&|v| format_number(*v))
        .draw()
        .map_err(de)
}

fn font_size(root_h: u32, base: f64) -> f64 {
    (base * root_h as f64 / 600.0).clamp(9.0, 48.0)
}

mod heatmap;
mod polar;
mod xy;

use heatmap::*;
use polar::*;
use xy::*;

pub mod brdf_charts;
#[cfg(test)]
mod tests;
