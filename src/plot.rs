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

impl From<LineChart> for Chart {
    fn from(c: LineChart) -> Self {
        Chart::Line(c)
    }
}
impl From<ScatterChart> for Chart {
    fn from(c: ScatterChart) -> Self {
        Chart::Scatter(c)
    }
}
impl From<Heatmap> for Chart {
    fn from(c: Heatmap) -> Self {
        Chart::Heatmap(c)
    }
}
impl From<PolarChart> for Chart {
    fn from(c: PolarChart) -> Self {
        Chart::Polar(c)
    }
}

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
        match path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .as_deref()
        {
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

/// Writes `chart` to `path`, PNG or SVG by its extension, `width × height` pixels.
pub fn save(chart: &Chart, path: &Path, width: u32, height: u32) -> Result<()> {
    match Format::from_path(path)? {
        Format::Png => {
            let buf = render_rgb(chart, width, height)?;
            let img = image::RgbImage::from_raw(width, height, buf)
                .ok_or_else(|| anyhow!("internal: chart buffer size"))?;
            img.save_with_format(path, image::ImageFormat::Png)
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
            std::fs::write(path, svg).with_context(|| format!("writing {}", path.display()))?;
        }
    }
    Ok(())
}

/// Writes `stem.png` and `stem.svg` (any extension of `stem` is replaced); returns both paths.
pub fn save_png_svg(chart: &Chart, stem: &Path, width: u32, height: u32) -> Result<[PathBuf; 2]> {
    let png = stem.with_extension("png");
    let svg = stem.with_extension("svg");
    save(chart, &png, width, height)?;
    save(chart, &svg, width, height)?;
    Ok([png, svg])
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

fn font_size(root_h: u32, base: f64) -> f64 {
    (base * root_h as f64 / 600.0).clamp(9.0, 48.0)
}

// ---------------------------------------------------------------------------------------------
// Line and scatter charts
// ---------------------------------------------------------------------------------------------

macro_rules! with_axes {
    ($xa:expr, $xr:expr, $ya:expr, $yr:expr, |$xs:ident, $ys:ident| $body:expr) => {{
        let (x0, x1) = $xr;
        let (y0, y1) = $yr;
        match ($xa.log, $ya.log) {
            (false, false) => {
                let $xs = x0..x1;
                let $ys = y0..y1;
                $body
            }
            (true, false) => {
                let $xs = (x0..x1).log_scale();
                let $ys = y0..y1;
                $body
            }
            (false, true) => {
                let $xs = x0..x1;
                let $ys = (y0..y1).log_scale();
                $body
            }
            (true, true) => {
                let $xs = (x0..x1).log_scale();
                let $ys = (y0..y1).log_scale();
                $body
            }
        }
    }};
}

fn draw_line<DB: DrawingBackend>(c: &LineChart, root: &DrawingArea<DB, Shift>) -> Result<()> {
    let keep = |a: &Axis, v: f64| v.is_finite() && (!a.log || v > 0.0);
    let xr = fit(
        &c.x,
        c.series.iter().flat_map(|s| s.points.iter().map(|p| p.0)),
    );
    let yr = fit(
        &c.y,
        c.series.iter().flat_map(|s| s.points.iter().map(|p| p.1)),
    );
    let h = root.dim_in_pixel().1;
    let fs = font_size(h, 16.0);
    with_axes!(c.x, xr, c.y, yr, |xs, ys| {
        let mut chart = ChartBuilder::on(root)
            .caption(&c.title, (FAMILY, font_size(h, 22.0)))
            .margin(font_size(h, 14.0) as u32)
            .x_label_area_size((fs * 3.0) as u32)
            .y_label_area_size((fs * 4.5) as u32)
            .build_cartesian_2d(xs, ys)
            .map_err(de)?;
        chart
            .configure_mesh()
            .x_desc(c.x.label.as_str())
            .y_desc(c.y.label.as_str())
            .label_style((FAMILY, fs))
            .axis_desc_style((FAMILY, fs))
            .x_label_formatter(&|v| format_number(*v))
            .y_label_formatter(&|v| format_number(*v))
            .light_line_style(RGBColor(235, 235, 235))
            .draw()
            .map_err(de)?;
        let mut any_label = false;
        for (i, s) in c.series.iter().enumerate() {
            let color = s.color.unwrap_or_else(|| palette(i));
            let style = ShapeStyle::from(color).stroke_width(2);
            let pts: Vec<(f64, f64)> = s
                .points
                .iter()
                .copied()
                .filter(|&(x, y)| keep(&c.x, x) && keep(&c.y, y))
                .collect();
            let anno = if s.dashed {
                chart
                    .draw_series(DashedLineSeries::new(pts.clone(), 8, 5, style))
                    .map_err(de)?
            } else {
                chart
                    .draw_series(LineSeries::new(pts.clone(), style))
                    .map_err(de)?
            };
            if !s.label.is_empty() {
                any_label = true;
                anno.label(s.label.as_str())
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
            }
            if s.markers {
                chart
                    .draw_series(pts.iter().map(|&p| Circle::new(p, 3, color.filled())))
                    .map_err(de)?;
            }
        }
        if let (true, Some(pos)) = (any_label, legend_pos(c.legend)) {
            chart
                .configure_series_labels()
                .position(pos)
                .label_font((FAMILY, fs))
                .background_style(WHITE.mix(0.85))
                .border_style(RGBColor(160, 160, 160))
                .draw()
                .map_err(de)?;
        }
        Ok(())
    })
}

fn draw_scatter<DB: DrawingBackend>(c: &ScatterChart, root: &DrawingArea<DB, Shift>) -> Result<()> {
    let keep = |a: &Axis, v: f64| v.is_finite() && (!a.log || v > 0.0);
    let mut xr = fit(&c.x, c.points.iter().map(|p| p.x));
    let yr = fit(&c.y, c.points.iter().map(|p| p.y));
    if c.x.range.is_none() {
        // Room for the labels right of the rightmost points.
        xr.1 = if c.x.log {
            xr.1 * (xr.1 / xr.0).powf(0.15)
        } else {
            xr.1 + (xr.1 - xr.0) * 0.15
        };
    }
    let h = root.dim_in_pixel().1;
    let fs = font_size(h, 16.0);
    with_axes!(c.x, xr, c.y, yr, |xs, ys| {
        let mut chart = ChartBuilder::on(root)
            .caption(&c.title, (FAMILY, font_size(h, 22.0)))
            .margin(font_size(h, 14.0) as u32)
            .x_label_area_size((fs * 3.0) as u32)
            .y_label_area_size((fs * 4.5) as u32)
            .build_cartesian_2d(xs, ys)
            .map_err(de)?;
        chart
            .configure_mesh()
            .x_desc(c.x.label.as_str())
            .y_desc(c.y.label.as_str())
            .label_style((FAMILY, fs))
            .axis_desc_style((FAMILY, fs))
            .x_label_formatter(&|v| format_number(*v))
            .y_label_formatter(&|v| format_number(*v))
            .light_line_style(RGBColor(235, 235, 235))
            .draw()
            .map_err(de)?;
        let groups = c
            .points
            .iter()
            .map(|p| p.group + 1)
            .max()
            .unwrap_or(0)
            .max(c.groups.len());
        for g in 0..groups {
            let color = palette(g);
            let pts: Vec<&LabeledPoint> = c
                .points
                .iter()
                .filter(|p| p.group == g && keep(&c.x, p.x) && keep(&c.y, p.y))
                .collect();
            let anno = chart
                .draw_series(
                    pts.iter()
                        .map(|p| Circle::new((p.x, p.y), 5, color.filled())),
                )
                .map_err(de)?;
            if let Some(name) = c.groups.get(g) {
                anno.label(name.as_str())
                    .legend(move |(x, y)| Circle::new((x + 10, y), 5, color.filled()));
            }
            let label_style = TextStyle::from((FAMILY, fs * 0.85).into_font()).color(&BLACK);
            chart
                .draw_series(pts.iter().filter(|p| !p.label.is_empty()).map(|p| {
                    EmptyElement::at((p.x, p.y))
                        + Text::new(p.label.clone(), (8, -(fs as i32) / 2), label_style.clone())
                }))
                .map_err(de)?;
        }
        if let (false, Some(pos)) = (c.groups.is_empty(), legend_pos(c.legend)) {
            chart
                .configure_series_labels()
                .position(pos)
                .label_font((FAMILY, fs))
                .background_style(WHITE.mix(0.85))
                .border_style(RGBColor(160, 160, 160))
                .draw()
                .map_err(de)?;
        }
        Ok(())
    })
}

// ---------------------------------------------------------------------------------------------
// Heatmap
// ---------------------------------------------------------------------------------------------

const EMPTY_GREY: RGBColor = RGBColor(150, 150, 150);

fn draw_heatmap<DB: DrawingBackend>(c: &Heatmap, root: &DrawingArea<DB, Shift>) -> Result<()> {
    let (Some((x0, x1)), Some((y0, y1))) = (c.x.range, c.y.range) else {
        bail!("heatmap: the x and y ranges are required");
    };
    if c.nx == 0 || c.ny == 0 || c.values.len() != c.nx * c.ny {
        bail!(
            "heatmap: {} values for {} × {} cells",
            c.values.len(),
            c.nx,
            c.ny
        );
    }
    let valid = |v: f64| v.is_finite() && (!c.log_color || v > 0.0);
    let (mut lo, mut hi) = match c.color_range {
        Some(r) => r,
        None => {
            let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
            for &v in c.values.iter().filter(|v| valid(**v)) {
                lo = lo.min(v);
                hi = hi.max(v);
            }
            if lo > hi {
                (lo, hi) = if c.log_color { (0.1, 1.0) } else { (0.0, 1.0) };
            }
            if c.log_color {
                let decades = if c.log_decades > 0.0 {
                    c.log_decades
                } else {
                    4.0
                };
                lo = lo.max(hi * 10f64.powf(-decades));
            }
            (lo, hi)
        }
    };
    if c.log_color {
        lo = lo.max(f64::MIN_POSITIVE);
        if hi <= lo * 1.01 {
            (lo, hi) = (lo / 1.5, hi.max(lo) * 1.5);
        }
    } else if hi <= lo {
        (lo, hi) = (lo - 0.5, hi + 0.5);
    }
    let to_t = |v: f64| -> f64 {
        if c.log_color {
            (v.log10() - lo.log10()) / (hi.log10() - lo.log10())
        } else {
            (v - lo) / (hi - lo)
        }
    };
    let (w, h) = root.dim_in_pixel();
    let fs = font_size(h, 16.0);
    // ab_glyph draws glyphs about a quarter of the size above the requested top: leave room.
    let root = root.margin((font_size(h, 22.0) * 0.35) as u32, 0, 0, 0);
    let root = root
        .titled(&c.title, (FAMILY, font_size(h, 22.0)))
        .map_err(de)?;
    let bar_w = ((w as f64) * 0.17).max(fs * 6.0) as u32;
    let (left, right) = root.split_horizontally(w.saturating_sub(bar_w));
    let mut chart = ChartBuilder::on(&left)
        .margin(font_size(h, 12.0) as u32)
        .x_label_area_size((fs * 3.0) as u32)
        .y_label_area_size((fs * 4.0) as u32)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(de)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc(c.x.label.as_str())
        .y_desc(c.y.label.as_str())
        .label_style((FAMILY, fs))
        .axis_desc_style((FAMILY, fs))
        .x_label_formatter(&|v| format_number(*v))
        .y_label_formatter(&|v| format_number(*v))
        .draw()
        .map_err(de)?;
    let (dx, dy) = ((x1 - x0) / c.nx as f64, (y1 - y0) / c.ny as f64);
    let mut any_empty = false;
    // Runs of equal colour along a row become one rectangle (keeps the SVG small).
    let mut rects = Vec::new();
    for j in 0..c.ny {
        let row = &c.values[j * c.nx..(j + 1) * c.nx];
        let mut i = 0;
        while i < c.nx {
            let colour = |v: f64| {
                if valid(v) {
                    viridis(to_t(v))
                } else {
                    EMPTY_GREY
                }
            };
            let col = colour(row[i]);
            any_empty |= !valid(row[i]);
            let mut k = i + 1;
            while k < c.nx && colour(row[k]) == col {
                any_empty |= !valid(row[k]);
                k += 1;
            }
            rects.push(Rectangle::new(
                [
                    (x0 + i as f64 * dx, y0 + j as f64 * dy),
                    (x0 + k as f64 * dx, y0 + (j + 1) as f64 * dy),
                ],
                col.filled(),
            ));
            i = k;
        }
    }
    chart.draw_series(rects).map_err(de)?;

    // Colour bar: a strip of cells on a linear axis of v (or log10 v), ticks drawn here so that
    // ranges under a decade are labelled too.
    let tr = |v: f64| if c.log_color { v.log10() } else { v };
    let (b0, b1) = (tr(lo), tr(hi));
    let mut bar = ChartBuilder::on(&right)
        .margin_top(font_size(h, 12.0) as u32)
        .margin_bottom((fs * 3.0 + font_size(h, 12.0)) as u32)
        .margin_left((fs * 2.0) as u32)
        .margin_right((fs * 4.5) as u32)
        .build_cartesian_2d(0.0..1.0, b0..b1)
        .map_err(de)?;
    let steps = 128;
    bar.draw_series((0..steps).map(|s| {
        let a = b0 + (b1 - b0) * s as f64 / steps as f64;
        let b = b0 + (b1 - b0) * (s + 1) as f64 / steps as f64;
        Rectangle::new(
            [(0.0, a), (1.0, b)],
            viridis((s as f64 + 0.5) / steps as f64).filled(),
        )
    }))
    .map_err(de)?;
    bar.draw_series(std::iter::once(Rectangle::new(
        [(0.0, b0), (1.0, b1)],
        BLACK.stroke_width(1),
    )))
    .map_err(de)?;
    let tick_style = TextStyle::from((FAMILY, fs * 0.9).into_font()).color(&BLACK);
    bar.draw_series(color_ticks(lo, hi, c.log_color).into_iter().map(|t| {
        EmptyElement::at((1.0, tr(t)))
            + PathElement::new(vec![(0, 0), (5, 0)], BLACK.stroke_width(1))
            + Text::new(
                format_number(t),
                (8, -(fs * 0.45) as i32),
                tick_style.clone(),
            )
    }))
    .map_err(de)?;
    {
        let (rw, rh) = right.dim_in_pixel();
        let style = TextStyle::from((FAMILY, fs).into_font())
            .transform(FontTransform::Rotate270)
            .color(&BLACK);
        let tw = (c.color_label.chars().count() as f64 * fs * 0.55) as i32;
        let _ = rw;
        right
            .draw(&Text::new(
                c.color_label.clone(),
                (
                    (fs * 0.3) as i32,
                    (rh as i32 - (fs * 3.0) as i32) / 2 + tw / 2,
                ),
                style,
            ))
            .map_err(de)?;
    }
    let empty_note = (any_empty && !c.empty_label.is_empty()).then(|| c.empty_label.clone());
    if let Some(note) = empty_note {
        // A grey square, then the note's lines (split at '\n') beside and under it.
        let (rw, rh) = right.dim_in_pixel();
        let lines: Vec<&str> = note.lines().collect();
        let lh = (fs * 1.05) as i32;
        let y = rh as i32 - (fs * 0.6) as i32 - lh * lines.len() as i32;
        let x = (rw as f64 * 0.04) as i32;
        let sq = (fs * 0.8) as i32;
        right
            .draw(&Rectangle::new(
                [(x, y + 2), (x + sq, y + 2 + sq)],
                EMPTY_GREY.filled(),
            ))
            .map_err(de)?;
        for (k, line) in lines.iter().enumerate() {
            right
                .draw(&Text::new(
                    line.to_string(),
                    (x + sq + 4, y + k as i32 * lh),
                    (FAMILY, fs * 0.8),
                ))
                .map_err(de)?;
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Polar plot
// ---------------------------------------------------------------------------------------------

/// Tick values for a colour bar over `lo … hi`: 1, 2, 5 × 10^k on a log scale (only powers of
/// ten when there are many), else (or when fewer than 2 fit) about 5 evenly spaced nice values.
fn color_ticks(lo: f64, hi: f64, log: bool) -> Vec<f64> {
    let inside = |t: &f64| *t >= lo * (1.0 - 1e-9) && *t <= hi * (1.0 + 1e-9);
    if log && lo > 0.0 {
        let (k0, k1) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
        let mut t: Vec<f64> = (k0..=k1)
            .flat_map(|k| [1.0, 2.0, 5.0].map(|m| m * 10f64.powi(k)))
            .filter(inside)
            .collect();
        if t.len() > 10 {
            t = (k0..=k1).map(|k| 10f64.powi(k)).filter(inside).collect();
            while t.len() > 10 {
                t = t.into_iter().step_by(2).collect();
            }
        }
        if t.len() >= 2 {
            return t;
        }
    }
    let raw = (hi - lo) / 5.0;
    if !(raw > 0.0 && raw.is_finite()) {
        return vec![lo];
    }
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 2.5, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    (first..=last).map(|k| k as f64 * step).collect()
}

/// "Nice" ring radii (1, 2, 2.5, 5 × 10^k), about 4 of them, the last one ≥ `r_max`.
fn ring_ticks(r_max: f64) -> Vec<f64> {
    if !(r_max > 0.0 && r_max.is_finite()) {
        return vec![1.0];
    }
    // The tightest outer ring over steps 1, 2, 2.5, 5 × 10^k giving 3 to 6 rings.
    let mag = 10f64.powf((r_max / 4.0).log10().floor());
    let mut best: Option<(f64, usize)> = None;
    for k in [-1, 0, 1] {
        for m in [1.0, 2.0, 2.5, 5.0] {
            let step = m * mag * 10f64.powi(k);
            let n = ((r_max / step) * (1.0 - 1e-9)).ceil().max(1.0) as usize;
            if !(3..=6).contains(&n) {
                continue;
            }
            let outer = n as f64 * step;
            let better = match best {
                None => true,
                Some((s, bn)) => {
                    let bo = bn as f64 * s;
                    outer < bo * (1.0 - 1e-9) || ((outer - bo).abs() <= bo * 1e-9 && n < bn)
                }
            };
            if better {
                best = Some((step, n));
            }
        }
    }
    let (step, n) = best.unwrap_or((r_max, 1));
    (1..=n).map(|k| k as f64 * step).collect()
}

fn draw_polar<DB: DrawingBackend>(c: &PolarChart, root: &DrawingArea<DB, Shift>) -> Result<()> {
    let (_, h0) = root.dim_in_pixel();
    let fs = font_size(h0, 16.0);
    // ab_glyph draws glyphs about a quarter of the size above the requested top: leave room.
    let root = root.margin((font_size(h0, 22.0) * 0.35) as u32, 0, 0, 0);
    let root = root
        .titled(&c.title, (FAMILY, font_size(h0, 22.0)))
        .map_err(de)?;
    let (w, h) = root.dim_in_pixel();
    let (w, h) = (w as f64, h as f64);
    let data_max = c
        .series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p.1))
        .filter(|r| r.is_finite())
        .fold(0.0f64, f64::max);
    let r_max = c
        .r_max
        .filter(|r| *r > 0.0 && r.is_finite())
        .unwrap_or(if data_max > 0.0 { data_max } else { 1.0 });
    let rings = ring_ticks(r_max);
    let r_outer = rings.last().copied().unwrap_or(r_max).max(r_max);
    // Pixel geometry: margins for angle labels around, the radius label and legend below.
    let (m, mx) = (fs * 2.2, fs * 3.5);
    let bottom = if c.r_label.is_empty() { m } else { fs * 3.5 };
    // Centred vertically in the space left over.
    let (cx, cy, rp) = if c.half {
        let rp = ((w - 2.0 * mx) / 2.0).min(h - m - bottom).max(10.0);
        let spare = (h - m - bottom - rp).max(0.0) / 2.0;
        (w / 2.0, m + spare + rp, rp)
    } else {
        let rp = ((w - 2.0 * mx) / 2.0).min((h - m - bottom) / 2.0).max(10.0);
        let spare = (h - m - bottom - 2.0 * rp).max(0.0) / 2.0;
        (w / 2.0, m + spare + rp, rp)
    };
    let to_px = |deg: f64, r: f64| -> (i32, i32) {
        let a = deg.to_radians();
        let s = (r / r_outer) * rp;
        (
            (cx + s * a.sin()).round() as i32,
            (cy - s * a.cos()).round() as i32,
        )
    };
    let (a0, a1) = if c.half {
        (-90.0, 90.0)
    } else {
        (-180.0, 180.0)
    };
    let grid = ShapeStyle::from(RGBColor(200, 200, 200)).stroke_width(1);
    let axis = ShapeStyle::from(RGBColor(90, 90, 90)).stroke_width(1);
    // Rings with their radius labels (along +90°).
    for (k, &r) in rings.iter().enumerate() {
        let n = 180;
        let pts: Vec<(i32, i32)> = (0..=n)
            .map(|i| to_px(a0 + (a1 - a0) * i as f64 / n as f64, r))
            .collect();
        let last = k + 1 == rings.len();
        root.draw(&PathElement::new(pts, if last { axis } else { grid }))
            .map_err(de)?;
        let (x, y) = to_px(90.0, r);
        root.draw(&Text::new(
            format_number(r),
            (x - (fs * 0.8) as i32, y + (fs * 0.25) as i32),
            (FAMILY, fs * 0.8),
        ))
        .map_err(de)?;
    }
    // Spokes every 15° (labels every 30°).
    let mut deg = a0;
    while deg <= a1 + 1e-9 {
        if !(c.half || deg > -180.0) {
            deg += 15.0;
            continue;
        }
        root.draw(&PathElement::new(
            vec![to_px(deg, 0.0), to_px(deg, r_outer)],
            grid,
        ))
        .map_err(de)?;
        if (deg as i64) % 30 == 0 {
            let (x, y) = to_px(deg, r_outer * 1.0 + r_outer * (fs * 1.1) / rp);
            let text = format!("{}°", deg as i64);
            let tw = (text.chars().count() as f64 * fs * 0.55) as i32;
            root.draw(&Text::new(
                text,
                (x - tw / 2, y - (fs * 0.5) as i32),
                (FAMILY, fs * 0.9),
            ))
            .map_err(de)?;
        }
        deg += 15.0;
    }
    if c.half {
        root.draw(&PathElement::new(
            vec![to_px(-90.0, r_outer), to_px(90.0, r_outer)],
            axis,
        ))
        .map_err(de)?;
    }
    // Curves and rays.
    for (i, s) in c.series.iter().enumerate() {
        let color = s.color.unwrap_or_else(|| palette(i));
        let style = ShapeStyle::from(color).stroke_width(2);
        for &ray in &s.rays {
            root.draw(&DashedPathElement::new(
                vec![to_px(ray, 0.0), to_px(ray, r_outer)],
                6,
                4,
                ShapeStyle::from(color).stroke_width(1),
            ))
            .map_err(de)?;
        }
        let pts: Vec<(i32, i32)> = s
            .points
            .iter()
            .filter(|p| p.0.is_finite() && p.1.is_finite())
            .map(|&(a, r)| to_px(a, r.clamp(0.0, r_outer)))
            .collect();
        root.draw(&PathElement::new(pts, style)).map_err(de)?;
    }
    // Legend (top left) and the radius label (bottom).
    let mut y = (fs * 0.3) as i32;
    for (i, s) in c
        .series
        .iter()
        .enumerate()
        .filter(|(_, s)| !s.label.is_empty())
    {
        let color = s.color.unwrap_or_else(|| palette(i));
        let x = (fs * 0.5) as i32;
        let ym = y + (fs * 0.5) as i32;
        root.draw(&PathElement::new(
            vec![(x, ym), (x + (fs * 1.5) as i32, ym)],
            ShapeStyle::from(color).stroke_width(2),
        ))
        .map_err(de)?;
        root.draw(&Text::new(
            s.label.clone(),
            (x + (fs * 2.0) as i32, y),
            (FAMILY, fs * 0.9),
        ))
        .map_err(de)?;
        y += (fs * 1.2) as i32;
    }
    if !c.r_label.is_empty() {
        let base = if c.half { cy } else { cy + rp };
        let tw = (c.r_label.chars().count() as f64 * fs * 0.5) as i32;
        root.draw(&Text::new(
            c.r_label.clone(),
            (
                (w / 2.0) as i32 - tw / 2,
                (base + bottom - fs * 1.8).min(h - fs * 1.6) as i32,
            ),
            (FAMILY, fs),
        ))
        .map_err(de)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_and_ticks() {
        assert_eq!(format_number(0.0), "0");
        assert_eq!(format_number(0.25), "0.25");
        assert_eq!(format_number(1.0), "1");
        assert_eq!(format_number(1234.4), "1234");
        assert_eq!(format_number(1e-5), "1e-5");
        assert_eq!(ring_ticks(1.0), vec![0.25, 0.5, 0.75, 1.0]);
        assert_eq!(ring_ticks(44.0), vec![10.0, 20.0, 30.0, 40.0, 50.0]);
        assert_eq!(*ring_ticks(0.31).last().unwrap(), 0.4);
        assert_eq!(viridis(0.0), RGBColor(68, 1, 84));
        assert_eq!(viridis(1.0), RGBColor(253, 231, 37));
    }

    fn non_white(rgb: &[u8]) -> usize {
        rgb.chunks(3).filter(|p| *p != [255, 255, 255]).count()
    }

    /// Every chart kind renders (log axes, labels, full polar, linear heatmap). Needs the font.
    #[test]
    fn every_chart_kind_renders() {
        let line = LineChart {
            title: "line".into(),
            x: Axis::new("x").log(),
            y: Axis::new("y").log(),
            series: vec![
                Series::new("a", (1..50).map(|i| (i as f64, (i * i) as f64)).collect()).markers(),
                Series::new("b", vec![(1.0, 1.0), (0.0, 5.0), (50.0, 10.0)]).dashed(),
            ],
            legend: Legend::UpperLeft,
        };
        let scatter = ScatterChart {
            title: "speed against accuracy".into(),
            x: Axis::new("ms").log(),
            y: Axis::new("error"),
            points: vec![
                LabeledPoint {
                    x: 0.5,
                    y: 0.1,
                    label: "split sum".into(),
                    group: 0,
                },
                LabeledPoint {
                    x: 4.0,
                    y: 0.01,
                    label: "128 samples".into(),
                    group: 1,
                },
            ],
            groups: vec!["a".into(), "b".into()],
            legend: Legend::UpperRight,
        };
        let heat = Heatmap {
            title: "heat".into(),
            x: Axis::new("x").range(0.0, 1.0),
            y: Axis::new("y").range(-1.0, 1.0),
            nx: 3,
            ny: 2,
            values: vec![0.0, 1.0, 2.0, f64::NAN, 4.0, 5.0],
            color_label: "v".into(),
            empty_label: "none".into(),
            ..Default::default()
        };
        let polar = PolarChart {
            title: "polar".into(),
            series: vec![PolarSeries {
                label: "circle".into(),
                points: (0..=360).map(|a| (a as f64 - 180.0, 2.0)).collect(),
                color: None,
                rays: vec![45.0],
            }],
            r_max: None,
            half: false,
            r_label: "r".into(),
        };
        for chart in [line.into(), scatter.into(), heat.into(), polar.into()] {
            let rgb = render_rgb(&chart, 400, 300).unwrap();
            assert_eq!(rgb.len(), 400 * 300 * 3);
            assert!(non_white(&rgb) > 400 * 300 / 50, "{chart:?}");
        }
        assert!(Format::from_path(Path::new("a.jpg")).is_err());
        assert_eq!(Format::from_path(Path::new("a.SVG")).unwrap(), Format::Svg);
    }
}
