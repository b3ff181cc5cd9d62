//! PNG plots of a benchmark run (plotters, bitmap backend, text by ab_glyph with the
//! system's DejaVu Sans: Debian's fonts-dejavu-core, installed by tools/install-deps.sh).
//! `gpu_time.png`: GPU time of every configuration in run order, one colour per method.
//! `error_vs_time.png` (sweeps that compare with the reference): geometric error in
//! pixels against GPU time, log-log, one colour per method: the accuracy/cost trade-off.
use glyphcast::bench::BenchResult;
use glyphcast::{Error, Result};
use plotters::prelude::*;
use std::path::Path;
use std::sync::OnceLock;

/// Registers the font (`render::compose::labels::dejavu_sans`) once; an error names the paths
/// tried.
fn register_font() -> Result<()> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let bytes = glyphcast::render::compose::labels::dejavu_sans()?;
    let ok = *REGISTERED.get_or_init(|| {
        plotters::style::register_font("sans-serif", FontStyle::Normal, bytes).is_ok()
    });
    if ok {
        Ok(())
    } else {
        Err(Error::Setup {
            missing: "DejaVu Sans font registered with plotters, which the plots need",
            found: None,
        })
    }
}

fn plot_error(e: impl std::fmt::Display) -> Error {
    Error::Io {
        path: "a benchmark plot".into(),
        message: e.to_string(),
    }
}

fn methods(results: &[BenchResult]) -> Vec<&str> {
    let mut names: Vec<&str> = Vec::new();
    for r in results {
        if !names.contains(&r.method.as_str()) {
            names.push(&r.method);
        }
    }
    names
}

/// Writes the plots of `results` into `dir`; returns the files written.
pub fn write_plots(dir: &Path, title: &str, results: &[BenchResult]) -> Result<Vec<String>> {
    register_font()?;
    let mut written = Vec::new();
    if !results.is_empty() {
        gpu_time(&dir.join("gpu_time.png"), title, results)?;
        written.push("gpu_time.png".to_owned());
    }
    let measured: Vec<&BenchResult> = results.iter().filter(|r| r.accuracy.is_some()).collect();
    if !measured.is_empty() {
        error_vs_time(&dir.join("error_vs_time.png"), title, &measured)?;
        written.push("error_vs_time.png".to_owned());
    }
    Ok(written)
}

fn gpu_time(path: &Path, title: &str, results: &[BenchResult]) -> Result<()> {
    let root = BitMapBackend::new(path, (900, 500)).into_drawing_area();
    root.fill(&WHITE).map_err(plot_error)?;
    let max = results.iter().map(|r| r.gpu_ms_max).fold(1e-3, f64::max) * 2.0;
    let min = results
        .iter()
        .map(|r| r.gpu_ms_min)
        .fold(f64::INFINITY, f64::min)
        .max(1e-3)
        / 2.0;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!("{title}: GPU time per configuration"),
            ("sans-serif", 18),
        )
        .margin(12)
        .x_label_area_size(32)
        .y_label_area_size(56)
        .build_cartesian_2d(0f64..results.len() as f64, (min..max).log_scale())
        .map_err(plot_error)?;
    chart
        .configure_mesh()
        .x_desc("configuration (run order; see results.md)")
        .y_desc("GPU ms (median, min-max)")
        .draw()
        .map_err(plot_error)?;
    for (k, method) in methods(results).into_iter().enumerate() {
        let color = Palette99::pick(k).to_rgba();
        let points: Vec<(f64, &BenchResult)> = results
            .iter()
            .enumerate()
            .filter(|(_, r)| r.method == method)
            .map(|(i, r)| (i as f64 + 0.5, r))
            .collect();
        chart
            .draw_series(points.iter().map(|(x, r)| {
                PathElement::new(vec![(*x, r.gpu_ms_min), (*x, r.gpu_ms_max)], color)
            }))
            .map_err(plot_error)?;
        chart
            .draw_series(
                points
                    .iter()
                    .map(|(x, r)| Circle::new((*x, r.gpu_ms_median), 4, color.filled())),
            )
            .map_err(plot_error)?
            .label(method.to_owned())
            .legend(move |(x, y)| Circle::new((x + 8, y), 4, color.filled()));
    }
    finish(&mut chart, &root)
}

fn error_vs_time(path: &Path, title: &str, results: &[&BenchResult]) -> Result<()> {
    let error = |r: &BenchResult| r.accuracy.map_or(0.0, |a| a.error_px).max(1e-4);
    let root = BitMapBackend::new(path, (900, 500)).into_drawing_area();
    root.fill(&WHITE).map_err(plot_error)?;
    let (tmin, tmax) = results.iter().fold((f64::INFINITY, 0f64), |(a, b), r| {
        (a.min(r.gpu_ms_median), b.max(r.gpu_ms_median))
    });
    let emax = results.iter().map(|r| error(r)).fold(1.0, f64::max) * 2.0;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!("{title}: geometric error against GPU time"),
            ("sans-serif", 18),
        )
        .margin(12)
        .x_label_area_size(32)
        .y_label_area_size(56)
        .build_cartesian_2d(
            ((tmin / 2.0).max(1e-3)..tmax * 2.0).log_scale(),
            (1e-4..emax).log_scale(),
        )
        .map_err(plot_error)?;
    chart
        .configure_mesh()
        .x_desc("GPU ms (median)")
        .y_desc("geometric error, px")
        .draw()
        .map_err(plot_error)?;
    let owned: Vec<BenchResult> = results.iter().map(|r| (*r).clone()).collect();
    for (k, method) in methods(&owned).into_iter().enumerate() {
        let color = Palette99::pick(k).to_rgba();
        chart
            .draw_series(
                results
                    .iter()
                    .filter(|r| r.method == method)
                    .map(|r| Circle::new((r.gpu_ms_median, error(r)), 5, color.filled())),
            )
            .map_err(plot_error)?
            .label(method.to_owned())
            .legend(move |(x, y)| Circle::new((x + 8, y), 4, color.filled()));
    }
    finish(&mut chart, &root)
}

/// Draws the legend of the series and writes the plot: how every plot ends.
fn finish<'a, CT: CoordTranslate>(
    chart: &mut ChartContext<'a, BitMapBackend<'a>, CT>,
    root: &DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>,
) -> Result<()> {
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(plot_error)?;
    root.present().map_err(plot_error)
}
