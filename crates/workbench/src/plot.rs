//! PNG figures with plotters. Text is drawn with the DejaVu Sans font bundled by the `dejavu`
//! crate (plotters' `ab_glyph` backend), so no system fonts are needed.

use crate::error::{Result, output};
use ndarray::Array2;
use plotters::prelude::*;
use std::path::Path;
use std::sync::Once;

const FONT: &str = "sans-serif";

fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        plotters::style::register_font(FONT, FontStyle::Normal, dejavu::sans::regular())
            .map_err(|_| ())
            .expect("the bundled DejaVu font loads");
    });
}

/// How a series is drawn.
#[derive(Clone, Copy, Debug)]
pub enum Mark {
    /// A line through the points.
    Line,
    /// Markers only.
    Points,
    /// A line with markers.
    LinePoints,
    /// Consecutive pairs of points as separate segments (arrows, ticks).
    Segments,
}

/// One named curve.
#[derive(Clone, Debug)]
pub struct Series {
    /// The legend's text.
    pub label: String,
    /// `(x, y)` pairs.
    pub points: Vec<(f64, f64)>,
    /// How it is drawn.
    pub mark: Mark,
    /// A dashed line: a curve that lies on or near another stays visible through it.
    pub dashed: bool,
}

impl Series {
    /// A series named `label`.
    pub fn new(label: impl Into<String>, points: Vec<(f64, f64)>, mark: Mark) -> Self {
        Self { label: label.into(), points, mark, dashed: false }
    }
    /// The same series dashed.
    pub fn dashed(mut self) -> Self {
        self.dashed = true;
        self
    }
}

/// One panel of an x–y chart.
pub struct Panel {
    /// Title above the panel.
    pub title: String,
    /// `x` axis label.
    pub x_label: String,
    /// `y` axis label.
    pub y_label: String,
    /// The curves.
    pub series: Vec<Series>,
    /// Logarithmic `x` axis.
    pub log_x: bool,
    /// Logarithmic `y` axis.
    pub log_y: bool,
    /// Where the legend goes; `None`: the corner the data leaves emptiest.
    pub legend: Option<SeriesLabelPosition>,
    /// The `y` axis when the data's own range leaves the legend no room.
    pub y_range: Option<(f64, f64)>,
    /// Vertical lines at `x` with their labels (an event: the stop, the start).
    pub marks: Vec<(f64, String)>,
}

impl Panel {
    /// Linear axes, legend upper right.
    pub fn new(title: &str, x_label: &str, y_label: &str, series: Vec<Series>) -> Self {
        Self {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            series,
            log_x: false,
            log_y: false,
            legend: None,
            y_range: None,
            marks: vec![],
        }
    }
    /// The same panel with a vertical line at `x`, labelled.
    pub fn mark_x(mut self, x: f64, label: impl Into<String>) -> Self {
        self.marks.push((x, label.into()));
        self
    }
    /// Whether the panel has anything to draw: a finite point.
    pub fn has_data(&self) -> bool {
        self.series.iter().any(|s| {
            s.points.iter().any(|p| {
                p.0.is_finite()
                    && p.1.is_finite()
                    && (!self.log_x || p.0 > 0.0)
                    && (!self.log_y || p.1 > 0.0)
            })
        })
    }
    /// The same panel with its `y` axis from `lo` to `hi`.
    pub fn y_range(mut self, lo: f64, hi: f64) -> Self {
        self.y_range = Some((lo, hi));
        self
    }
    /// The same panel on log–log axes.
    pub fn log_log(mut self) -> Self {
        self.log_x = true;
        self.log_y = true;
        self
    }
    /// The same panel with a logarithmic `x` axis.
    pub fn log_x(mut self) -> Self {
        self.log_x = true;
        self
    }
    /// The same panel with a logarithmic `y` axis.
    pub fn log_y(mut self) -> Self {
        self.log_y = true;
        self
    }
    /// The same panel with its legend at `at`.
    pub fn legend(mut self, at: SeriesLabelPosition) -> Self {
        self.legend = Some(at);
        self
    }
}

/// A tick label on an axis spanning `span`: plain where that is short, else one significant
/// digit in `e` notation; a value within 1e-9 of the span from 0 is 0 (a tick placed at
/// `lo + k·step` lands at −2e-16 rather than at 0).
fn tick_on(v: f64, span: f64) -> String {
    let v = if v.abs() <= 1e-9 * span.abs() { 0.0 } else { v };
    let a = v.abs();
    if a == 0.0 || (1e-2..1e4).contains(&a) {
        let s = format!("{v:.3}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{v:.0e}")
    }
}

const PALETTE: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(23, 190, 207),
    RGBColor(140, 86, 75),
    RGBColor(127, 127, 127),
];

/// The most decades a log axis spans: the chart library builds its key points decade by decade
/// and never returned from 400 of them; values further below the top are drawn at the bottom.
const MAX_DECADES: f64 = 30.0;

fn range(vals: impl Iterator<Item = f64>, log: bool) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in vals.filter(|v| v.is_finite() && (!log || *v > 0.0)) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return (if log { 0.1 } else { 0.0 }, 1.0);
    }
    sane(if log { (lo / 1.5, hi * 1.5) } else { (lo, hi) }, log)
}

/// An axis range the chart library can draw: finite, not empty, within [`MAX_DECADES`] on a log
/// axis and without overflow on a linear one, padded by 5 % of its span on a linear axis.
fn sane((lo, hi): (f64, f64), log: bool) -> (f64, f64) {
    const BIG: f64 = 1e300;
    if log {
        let hi = if hi.is_finite() && hi > 0.0 { hi.clamp(1e-300, BIG) } else { 1.0 };
        let floor = hi * 10f64.powf(-MAX_DECADES);
        let lo = if lo.is_finite() && lo > 0.0 { lo.max(floor) } else { floor };
        return if lo < hi { (lo, hi) } else { (hi / 10.0, hi * 10.0) };
    }
    let (lo, hi) = (lo.clamp(-BIG, BIG), hi.clamp(-BIG, BIG));
    let (lo, hi) = if lo.is_nan() || hi.is_nan() || lo > hi { (0.0, 1.0) } else { (lo, hi) };
    let span = hi / 2.0 - lo / 2.0;
    let pad = (span * 0.1).max(1e-12 * hi.abs().max(lo.abs()).max(1.0));
    (lo - pad, hi + pad)
}

fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    panel: &Panel,
) -> Result<()>
where
    DB::ErrorType: 'static,
{
    // A log axis within one decade would carry one tick label at most: such an axis is drawn
    // linear (the ratio it shows is small anyway).
    let narrow = |log: bool, v: &mut dyn Iterator<Item = f64>| {
        log && {
            let r = range(v, true);
            r.1 / r.0 < 10.0
        }
    };
    let mut lin = None;
    let (lx, ly) = (
        narrow(panel.log_x, &mut panel.series.iter().flat_map(|s| s.points.iter().map(|p| p.0))),
        panel.y_range.is_none()
            && narrow(
                panel.log_y,
                &mut panel.series.iter().flat_map(|s| s.points.iter().map(|p| p.1)),
            ),
    );
    if lx || ly {
        lin = Some(Panel {
            title: panel.title.clone(),
            x_label: panel.x_label.clone(),
            y_label: panel.y_label.clone(),
            series: panel.series.clone(),
            log_x: panel.log_x && !lx,
            log_y: panel.log_y && !ly,
            legend: panel.legend.clone(),
            y_range: panel.y_range,
            marks: panel.marks.clone(),
        });
    }
    let panel = lin.as_ref().unwrap_or(panel);
    let xs = range(panel.series.iter().flat_map(|s| s.points.iter().map(|p| p.0)), panel.log_x);
    let ys = panel.y_range.map(|(a, b)| {
        let drawable = a.is_finite() && b.is_finite() && a < b && (!panel.log_y || a > 0.0);
        if drawable { (a, b) } else { sane((a, b), panel.log_y) }
    });
    let ys = ys.unwrap_or_else(|| {
        range(panel.series.iter().flat_map(|s| s.points.iter().map(|p| p.1)), panel.log_y)
    });
    let x_tick = |v: &f64| tick_on(*v, xs.1 - xs.0);
    let y_tick = |v: &f64| tick_on(*v, ys.1 - ys.0);
    let mut builder = ChartBuilder::on(area);
    builder
        .caption(&panel.title, (FONT, title_size(&panel.title, area.dim_in_pixel().0)))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(70);
    macro_rules! body {
        ($chart:expr) => {{
            let mut chart = $chart;
            let mut mesh = chart.configure_mesh();
            mesh.x_desc(panel.x_label.as_str())
                .y_desc(panel.y_label.as_str())
                .label_style((FONT, 14))
                .axis_desc_style((FONT, 16))
                .x_label_formatter(&x_tick)
                .y_label_formatter(&y_tick);
            if panel.log_x || panel.log_y {
                // On log axes the minor lines crowd into a dense band per decade.
                mesh.light_line_style(TRANSPARENT);
            }
            mesh.draw()?;
            for (k, s) in panel.series.iter().enumerate() {
                let color = PALETTE[k % PALETTE.len()];
                let pts: Vec<(f64, f64)> = s
                    .points
                    .iter()
                    .cloned()
                    .filter(|p| {
                        p.0.is_finite()
                            && p.1.is_finite()
                            && (!panel.log_x || p.0 > 0.0)
                            && (!panel.log_y || p.1 > 0.0)
                    })
                    .collect();
                let legend_color = color;
                let key_len = if s.dashed { 8 } else { 20 };
                let line_key = move |(x, y): (i32, i32)| {
                    PathElement::new(vec![(x, y), (x + key_len, y)], legend_color.stroke_width(2))
                };
                match s.mark {
                    Mark::Line => {
                        let a = if s.dashed {
                            chart.draw_series(DashedLineSeries::new(
                                pts,
                                9,
                                6,
                                color.stroke_width(2),
                            ))?
                        } else {
                            chart.draw_series(LineSeries::new(pts, color.stroke_width(2)))?
                        };
                        a.label(s.label.as_str()).legend(line_key);
                    }
                    Mark::Points => {
                        let a = chart.draw_series(
                            pts.into_iter().map(|p| Circle::new(p, 3, color.filled())),
                        )?;
                        a.label(s.label.as_str()).legend(move |(x, y)| {
                            Circle::new((x + 10, y), 3, legend_color.filled())
                        });
                    }
                    Mark::Segments => {
                        let segs: Vec<Vec<(f64, f64)>> =
                            pts.chunks_exact(2).map(|c| c.to_vec()).collect();
                        let style = color.stroke_width(1);
                        let a = chart.draw_series(
                            segs.into_iter().map(move |s| PathElement::new(s, style)),
                        )?;
                        a.label(s.label.as_str()).legend(move |(x, y)| {
                            PathElement::new(
                                vec![(x, y), (x + 20, y)],
                                legend_color.stroke_width(1),
                            )
                        });
                    }
                    Mark::LinePoints => {
                        chart.draw_series(LineSeries::new(pts.clone(), color.stroke_width(2)))?;
                        let a = chart.draw_series(
                            pts.into_iter().map(|p| Circle::new(p, 4, color.filled())),
                        )?;
                        a.label(s.label.as_str()).legend(line_key);
                    }
                };
            }
            for (x, label) in &panel.marks {
                let (lo, hi) = (ys.0, ys.1);
                chart.draw_series(DashedLineSeries::new(
                    vec![(*x, lo), (*x, hi)],
                    4,
                    4,
                    RGBColor(90, 90, 90).stroke_width(1),
                ))?;
                chart.draw_series(std::iter::once(Text::new(
                    label.clone(),
                    (*x, hi),
                    (FONT, 13).into_font().color(&RGBColor(60, 60, 60)),
                )))?;
            }
            let corner = panel.legend.clone().unwrap_or_else(|| emptiest_corner(panel, xs, ys));
            chart
                .configure_series_labels()
                .position(corner)
                .label_font((FONT, 14))
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .draw()?;
        }};
    }
    match (panel.log_x, panel.log_y) {
        (false, false) => body!(builder.build_cartesian_2d(xs.0..xs.1, ys.0..ys.1)?),
        (true, false) => body!(builder.build_cartesian_2d((xs.0..xs.1).log_scale(), ys.0..ys.1)?),
        (false, true) => body!(builder.build_cartesian_2d(xs.0..xs.1, (ys.0..ys.1).log_scale())?),
        (true, true) => {
            body!(builder.build_cartesian_2d((xs.0..xs.1).log_scale(), (ys.0..ys.1).log_scale())?)
        }
    }
    Ok(())
}

/// The corner of the plot area whose legend box covers the fewest points of the panel's
/// curves (their points and the midpoints between them), the box's size estimated from the
/// labels: a legend never sits on the data it describes when a corner is free.
fn emptiest_corner(panel: &Panel, xs: (f64, f64), ys: (f64, f64)) -> SeriesLabelPosition {
    use SeriesLabelPosition::*;
    let unit = |v: f64, r: (f64, f64), log: bool| {
        if log {
            (v.max(1e-300).ln() - r.0.ln()) / (r.1.ln() - r.0.ln())
        } else {
            (v - r.0) / (r.1 - r.0)
        }
    };
    // The legend's box as a share of a panel's plot area (≈ 550 × 390 px): a line of 20 px per
    // series, 8 px a character and 40 px of key and margins.
    let longest = panel.series.iter().map(|s| s.label.chars().count()).max().unwrap_or(0);
    let (w, h) = (
        ((longest * 8 + 40) as f64 / 550.0).min(0.9),
        ((panel.series.len() * 20 + 12) as f64 / 390.0).min(0.9),
    );
    let mut pts = vec![];
    for s in &panel.series {
        let u: Vec<(f64, f64)> = s
            .points
            .iter()
            .filter(|p| p.0.is_finite() && p.1.is_finite())
            .map(|p| (unit(p.0, xs, panel.log_x), unit(p.1, ys, panel.log_y)))
            .collect();
        pts.extend(u.windows(2).map(|w| (0.5 * (w[0].0 + w[1].0), 0.5 * (w[0].1 + w[1].1))));
        pts.extend(u);
    }
    let corners = [
        (UpperRight, 1.0 - w, 1.0 - h),
        (UpperLeft, 0.0, 1.0 - h),
        (LowerRight, 1.0 - w, 0.0),
        (LowerLeft, 0.0, 0.0),
    ];
    let covered = |x0: f64, y0: f64| {
        pts.iter().filter(|p| p.0 >= x0 && p.0 <= x0 + w && p.1 >= y0 && p.1 <= y0 + h).count()
    };
    corners.into_iter().min_by_key(|c| covered(c.1, c.2)).map_or(UpperRight, |c| c.0)
}

/// Panels side by side (one row), with an optional footnote line (conditions, laws).
/// The history chart of the time-stepping models: films (central, minimum) [nm] beside pressures
/// (maximum, central) [p_h], against one abscissa (time or a feature's position).
pub fn history_chart(
    path: &Path,
    x_label: &str,
    film_title: &str,
    films: [(&str, Vec<(f64, f64)>); 2],
    pressure_title: &str,
    pressures: [(&str, Vec<(f64, f64)>); 2],
    footnote: &str,
) -> Result<()> {
    let series = |v: [(&str, Vec<(f64, f64)>); 2]| -> Vec<Series> {
        v.into_iter().map(|(label, pts)| Series::new(label, pts, Mark::Line)).collect()
    };
    charts(
        path,
        &[
            Panel::new(film_title, x_label, "[nm]", series(films)),
            Panel::new(pressure_title, x_label, "p / p_h", series(pressures)),
        ],
        footnote,
    )
}

/// Rows and columns for `n` panels: one row up to three, two by two for four, then rows of
/// three.
fn layout(n: usize) -> (usize, usize) {
    // Four panels make a square rather than a row of three and a lone fourth.
    let cols = if n == 4 { 2 } else { n.clamp(1, 3) };
    (n.div_ceil(cols).max(1), cols)
}

/// Line charts, side by side (rows of three beyond three), with a footnote.
pub fn charts(path: &Path, panels: &[Panel], footnote: &str) -> Result<()> {
    register_font();
    let (rows, cols) = layout(panels.len());
    let (width, height) = (640 * cols as u32, 490 * rows as u32);
    figure(path, width, height, footnote, |main| {
        for (area, panel) in main.split_evenly((rows, cols)).iter().zip(panels) {
            draw_panel(area, panel)?;
        }
        Ok(())
    })
}

/// A footnote's lines for a figure `width` px wide: broken between words so that none runs off
/// the figure (DejaVu Sans at 14 px: about 7.6 px a character).
fn footnote_lines(text: &str, width: u32) -> Vec<String> {
    let most = ((width.saturating_sub(24)) as f64 / 7.6).max(20.0) as usize;
    let mut lines = vec![];
    let mut line = String::new();
    for word in text.split_whitespace() {
        if !line.is_empty() && line.chars().count() + 1 + word.chars().count() > most {
            lines.push(std::mem::take(&mut line));
        }
        if !line.is_empty() {
            line.push(' ');
        }
        line.push_str(word);
    }
    if !line.is_empty() || lines.is_empty() {
        lines.push(line);
    }
    lines
}

/// The drawing area of a figure's panels.
type Area<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;

/// A figure `width` × `height` px of panels, which `draw` puts in the area it is given, with
/// `footnote` below them (as many lines as it needs), written to `path` as PNG.
fn figure(
    path: &Path,
    width: u32,
    height: u32,
    footnote: &str,
    draw: impl FnOnce(&Area) -> Result<()>,
) -> Result<()> {
    let lines = footnote_lines(footnote, width);
    let size = (width, height + 10 + 20 * lines.len() as u32);
    let mut rgb = vec![0; 3 * size.0 as usize * size.1 as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area();
        root.fill(&WHITE)?;
        let (main, foot) = root.split_vertically(height);
        for (k, line) in lines.into_iter().enumerate() {
            let at = (12, 6 + 20 * k as i32);
            foot.draw(&Text::new(line, at, (FONT, 14).into_font().color(&BLACK)))?;
        }
        draw(&main)?;
        root.present().map_err(output("drawing the figure"))?;
    }
    write_png(path, &rgb, size).map_err(output(format!("writing {}", path.display())))
}

/// `rgb` (8-bit RGB rows, top first) of `size` px as a PNG file at `path`.
fn write_png(
    path: &Path,
    rgb: &[u8],
    size: (u32, u32),
) -> std::result::Result<(), png::EncodingError> {
    let file = std::io::BufWriter::new(std::fs::File::create(path)?);
    let mut png = png::Encoder::new(file, size.0, size.1);
    png.set_color(png::ColorType::Rgb);
    png.set_depth(png::BitDepth::Eight);
    let mut writer = png.write_header()?;
    writer.write_image_data(rgb)?;
    writer.finish()
}

/// A title's font size for a panel `width` px wide: 20 px, smaller for a long title so that
/// it does not run into the next panel's (DejaVu Sans: about 0.56 em a character).
fn title_size(title: &str, width: u32) -> u32 {
    let chars = title.chars().count().max(1) as f64;
    ((width.saturating_sub(30)) as f64 / (0.56 * chars)).clamp(11.0, 20.0) as u32
}

/// Colour for `t ∈ [0, 1]`: a perceptually ordered blue–green–yellow ramp (viridis-like).
fn ramp(t: f64) -> RGBColor {
    blend(
        &[(68., 1., 84.), (59., 82., 139.), (33., 145., 140.), (94., 201., 98.), (253., 231., 37.)],
        t,
    )
}

/// The colour at `t ∈ [0, 1]` along five evenly spaced `stops`, linear between them.
fn blend(stops: &[(f64, f64, f64); 5], t: f64) -> RGBColor {
    let t = t.clamp(0.0, 1.0) * 4.0;
    let k = (t.floor() as usize).min(3);
    let f = t - k as f64;
    let (a, b) = (stops[k], stops[k + 1]);
    let mix = |x: f64, y: f64| (x + (y - x) * f).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// Colour for `t ∈ [0, 1]` of a signed quantity: blue below the middle, white at it, red above.
fn diverging(t: f64) -> RGBColor {
    blend(
        &[
            (33., 102., 172.),
            (146., 197., 222.),
            (247., 247., 247.),
            (244., 165., 130.),
            (178., 24., 43.),
        ],
        t,
    )
}

/// One heat-map panel.
pub struct MapPanel<'a> {
    /// The field `[[j, i]]` on the grid.
    pub field: &'a Array2<f64>,
    /// Title above the map.
    pub title: String,
    /// Title of the colour bar (the quantity and its unit).
    pub bar_label: String,
    /// A signed quantity (a difference): a diverging colour map, white at zero, its range
    /// symmetric about zero.
    pub diverging: bool,
}

/// Heat maps of `field[[j, i]]` over the grid (axes in units of `a`), side by side, each with a
/// colour bar.
pub fn heat_maps(
    path: &Path,
    panels: &[MapPanel],
    grid: &ehl_core::Grid,
    footnote: &str,
) -> Result<()> {
    register_font();
    let width = 760 * panels.len() as u32;
    figure(path, width, 610, footnote, |main| {
        for (area, panel) in main.split_evenly((1, panels.len())).iter().zip(panels) {
            draw_map(
                area,
                panel,
                (grid.x_min, grid.x_max),
                (grid.y_min, grid.y_max),
                "x / a",
                "y / a",
            )?;
        }
        Ok(())
    })
}

fn draw_map<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    panel: &MapPanel,
    xr: (f64, f64),
    yr: (f64, f64),
    x_label: &str,
    y_label: &str,
) -> Result<()>
where
    DB::ErrorType: 'static,
{
    let field = panel.field;
    let (ny, nx) = field.dim();
    let lo = field.iter().cloned().filter(|v| v.is_finite()).fold(f64::INFINITY, f64::min);
    let hi = field.iter().cloned().filter(|v| v.is_finite()).fold(f64::NEG_INFINITY, f64::max);
    let (lo, hi) = if panel.diverging {
        let m = lo.abs().max(hi.abs()).max(f64::MIN_POSITIVE);
        (-m, m)
    } else {
        (lo, hi)
    };
    let span = if hi > lo { hi - lo } else { 1.0 };
    let colour = |t: f64| if panel.diverging { diverging(t) } else { ramp(t) };
    let (left, right) = area.split_horizontally(630);
    let mut chart = ChartBuilder::on(&left)
        .caption(&panel.title, (FONT, title_size(&panel.title, 630)))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .label_style((FONT, 14))
        .axis_desc_style((FONT, 16))
        .draw()?;
    let (dx, dy) = ((xr.1 - xr.0) / (nx - 1).max(1) as f64, (yr.1 - yr.0) / (ny - 1).max(1) as f64);
    chart.draw_series(field.indexed_iter().map(|((j, i), &v)| {
        let (x, y) = (xr.0 + i as f64 * dx, yr.0 + j as f64 * dy);
        Rectangle::new(
            [(x - 0.5 * dx, y - 0.5 * dy), (x + 0.5 * dx, y + 0.5 * dy)],
            colour((v - lo) / span).filled(),
        )
    }))?;
    // Tick labels to the right of the bar, left-aligned from its edge: drawn on the left they
    // were right-aligned by an estimated text width and ran into the bar. The bar's title is
    // its caption, above it, in the map's caption font (so the bar's top lines up with the
    // map's): as a rotated axis description on the right it was drawn at the next panel's edge,
    // and mirrored on the last.
    let bar_tick = |v: &f64| tick_on(*v, span);
    let mut bar = ChartBuilder::on(&right)
        .caption(&panel.bar_label, (FONT, 20))
        .margin_top(12)
        .margin_bottom(57)
        .margin_right(4)
        .margin_left(8)
        .right_y_label_area_size(80)
        .build_cartesian_2d(0.0..1.0, lo..lo + span)?;
    bar.configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_label_formatter(&bar_tick)
        .label_style((FONT, 13))
        .axis_desc_style((FONT, 14))
        .draw()?;
    let steps = 100;
    bar.draw_series((0..steps).map(|k| {
        let v0 = lo + span * k as f64 / steps as f64;
        let v1 = lo + span * (k + 1) as f64 / steps as f64;
        Rectangle::new([(0.0, v0), (1.0, v1)], colour((k as f64 + 0.5) / steps as f64).filled())
    }))?;
    Ok(())
}

/// One panel of a map over two sweep parameters: `values[row][col]` (`row` the second
/// parameter, `col` the first); `None` is drawn blank (a failed point).
pub struct CellPanel {
    /// Title above the map.
    pub title: String,
    /// `values[row][col]`: `None` where there is no value (a failed point).
    pub values: Vec<Vec<Option<f64>>>,
    /// Cells drawn with a heavy border (e.g. where two models agree).
    pub outline: Vec<Vec<bool>>,
    /// Colour by the logarithm (values over decades, e.g. wall times).
    pub log_colour: bool,
    /// Significant digits of the value printed in each cell.
    pub digits: usize,
    /// Categories instead of values (a map of outcomes): per cell a label and its colour;
    /// empty for a map of values.
    pub labels: Vec<Vec<Option<(String, Category)>>>,
}

/// How a cell of a map of outcomes is coloured.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Category {
    /// Converged, checks passed.
    Good,
    /// Converged, flagged by a check.
    Doubtful,
    /// Failed.
    Bad,
}

/// Maps over two sweep parameters, one cell per point with its value printed, side by side.
pub fn cell_maps(
    path: &Path,
    panels: &[CellPanel],
    x_ticks: &[String],
    y_ticks: &[String],
    x_label: &str,
    y_label: &str,
    footnote: &str,
) -> Result<()> {
    register_font();
    let (rows, cols) = layout(panels.len());
    let (width, height) = (700 * cols as u32, 570 * rows as u32);
    figure(path, width, height, footnote, |main| {
        for (area, panel) in main.split_evenly((rows, cols)).iter().zip(panels) {
            let (nx, ny) = (x_ticks.len(), y_ticks.len());
            let key = |v: f64| if panel.log_colour { v.max(1e-300).ln() } else { v };
            let vals: Vec<f64> = panel.values.iter().flatten().flatten().map(|&v| key(v)).collect();
            let lo = vals.iter().cloned().fold(f64::INFINITY, f64::min);
            let hi = vals.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
            let span = if hi > lo { hi - lo } else { 1.0 };
            let xt = x_ticks.to_vec();
            let yt = y_ticks.to_vec();
            let mut chart = ChartBuilder::on(area)
                .caption(
                    &panel.title,
                    (FONT, title_size(&panel.title, area.dim_in_pixel().0).min(18)),
                )
                .margin(12)
                .x_label_area_size(45)
                .y_label_area_size(70)
                .build_cartesian_2d(-0.5..nx as f64 - 0.5, -0.5..ny as f64 - 0.5)?;
            chart
                .configure_mesh()
                .disable_mesh()
                .x_labels(nx)
                .y_labels(ny)
                .x_label_formatter(&|v: &f64| cell_label(&xt, *v))
                .y_label_formatter(&|v: &f64| cell_label(&yt, *v))
                .x_desc(x_label)
                .y_desc(y_label)
                .label_style((FONT, 13))
                .axis_desc_style((FONT, 15))
                .draw()?;
            for (j, row) in panel.labels.iter().enumerate() {
                for (i, c) in row.iter().enumerate() {
                    let Some((label, category)) = c else { continue };
                    let (x, y) = (i as f64, j as f64);
                    let cell = [(x - 0.5, y - 0.5), (x + 0.5, y + 0.5)];
                    let fill = match category {
                        Category::Good => RGBColor(120, 190, 120),
                        Category::Doubtful => RGBColor(240, 200, 90),
                        Category::Bad => RGBColor(220, 110, 100),
                    };
                    chart.draw_series(std::iter::once(Rectangle::new(cell, fill.filled())))?;
                    chart.draw_series(std::iter::once(Text::new(
                        label.clone(),
                        (x - 0.42, y + 0.1),
                        (FONT, 12).into_font().color(&BLACK),
                    )))?;
                }
            }
            for (j, row) in panel.values.iter().enumerate() {
                for (i, v) in row.iter().enumerate() {
                    let (x, y) = (i as f64, j as f64);
                    let cell = [(x - 0.5, y - 0.5), (x + 0.5, y + 0.5)];
                    match v {
                        Some(v) => {
                            let t = (key(*v) - lo) / span;
                            chart.draw_series(std::iter::once(Rectangle::new(
                                cell,
                                ramp(t).filled(),
                            )))?;
                            let ink = if t > 0.6 { BLACK } else { WHITE };
                            let label = format!("{:.*}", panel.digits, v);
                            chart.draw_series(std::iter::once(Text::new(
                                label,
                                (x - 0.3, y + 0.1),
                                (FONT, 13).into_font().color(&ink),
                            )))?;
                        }
                        None => {
                            chart.draw_series(std::iter::once(Rectangle::new(
                                cell,
                                RGBColor(230, 230, 230).filled(),
                            )))?;
                            chart.draw_series(std::iter::once(Text::new(
                                "failed".to_string(),
                                (x - 0.3, y + 0.1),
                                (FONT, 13).into_font().color(&BLACK),
                            )))?;
                        }
                    }
                    if panel.outline.get(j).and_then(|r| r.get(i)).copied().unwrap_or(false) {
                        let inset = [(x - 0.46, y - 0.46), (x + 0.46, y + 0.46)];
                        chart.draw_series(std::iter::once(Rectangle::new(
                            inset,
                            RED.stroke_width(3),
                        )))?;
                    }
                }
            }
        }
        Ok(())
    })
}

/// The name of the cell at the axis position `v` (cells at whole numbers), none between cells.
fn cell_label(names: &[String], v: f64) -> String {
    let k = v.round();
    if (v - k).abs() < 1e-6 && k >= 0.0 {
        names.get(k as usize).cloned().unwrap_or_default()
    } else {
        String::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tick_at_zero_by_rounding_reads_zero() {
        assert_eq!(tick_on(-2.2e-16, 2.5), "0");
        assert_eq!(tick_on(0.25, 2.5), "0.25");
        // On an axis of nanometres a tick of 1e-12 is a tick, not rounding.
        assert_eq!(tick_on(1e-12, 1e-11), "1e-12");
    }

    #[test]
    fn a_figure_reads_back_as_a_png_of_its_size_with_its_panel_and_footnote_drawn() {
        // The figures are drawn into memory and encoded here, not by the chart library: a size
        // or row length the encoder misreads, or a buffer written before it was drawn, shows
        // as a file a decoder refuses, of another size, or blank.
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("f.png");
        let line = vec![(0.0, 0.0), (1.0, 2.0), (2.0, 1.0)];
        let panel = Panel::new("t", "x", "y", vec![Series::new("s", line, Mark::LinePoints)]);
        charts(&path, &[panel], "a footnote of one line").unwrap();
        let file = std::io::BufReader::new(std::fs::File::open(&path).unwrap());
        let mut reader = png::Decoder::new(file).read_info().unwrap();
        let mut rgb = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut rgb).unwrap();
        // One panel of 640 × 490 px, and below it 10 px and a line of footnote (20 px).
        assert_eq!((info.width, info.height), (640, 520));
        assert_eq!((info.color_type, info.bit_depth), (png::ColorType::Rgb, png::BitDepth::Eight));
        let row = info.line_size;
        let inked = |rows: std::ops::Range<usize>| {
            rgb[rows.start * row..rows.end * row]
                .chunks(3)
                .filter(|p| p.iter().any(|&c| c < 128))
                .count()
        };
        // The corner is the white background; the panel's axes, labels and line, and the
        // footnote's letters, are dark on it: measured 4377 and 281 dark pixels, where a blank
        // panel or a lost footnote counts none (bounds at about half the measured counts).
        assert_eq!(&rgb[..3], &[255, 255, 255]);
        assert!(inked(0..490) > 2000, "the panel: {} dark pixels", inked(0..490));
        assert!(inked(495..520) > 100, "the footnote: {} dark pixels", inked(495..520));
    }

    #[test]
    fn charts_of_extreme_values_draw_and_return() {
        // A sweep over 400 decades hung the chart library's log axis; extreme and non-finite
        // values on linear axes overflowed its range. Each is drawn in its own thread, and a
        // figure not done within 60 s (a few hundred ms is usual) is the hang come back.
        let dir = tempfile::tempdir().unwrap();
        let cases: Vec<(Vec<(f64, f64)>, bool)> = vec![
            (vec![(1e-200, 1e-200), (1e200, 1e200)], true),
            (vec![(1e-300, 5e-324), (1.7e308, 1.7e308)], true),
            (vec![(-1.7e308, -1e308), (1.7e308, 1.7e308)], false),
            (vec![(0.0, 0.0), (0.0, 0.0)], false),
            (vec![(f64::NAN, f64::INFINITY), (1.0, f64::NEG_INFINITY)], true),
        ];
        for (k, (points, log)) in cases.into_iter().enumerate() {
            let path = dir.path().join(format!("c{k}.png"));
            let (tx, rx) = std::sync::mpsc::channel();
            std::thread::spawn(move || {
                let mut p =
                    Panel::new("t", "x", "y", vec![Series::new("s", points, Mark::LinePoints)]);
                if log {
                    p = p.log_log();
                }
                let _ = tx.send(charts(&path, &[p], "footer").map_err(|e| e.to_string()));
            });
            let got = rx.recv_timeout(std::time::Duration::from_secs(60));
            assert!(matches!(got, Ok(Ok(()))), "case {k}: {got:?}");
        }
    }
}
