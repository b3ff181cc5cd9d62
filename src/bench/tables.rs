//! Benchmark results as Markdown (for a person) and CSV (for a plot): the timings of
//! every configuration, then, where a sweep drew meshes or measured accuracy, the table
//! that sets cost against geometric error (the paper's Table 2 layout).
use super::{BenchAccuracy, BenchResult};
use std::fmt::Write as _;

/// How a column shows one result.
type Cell = fn(&BenchResult) -> String;

/// The timing table: each column's heading and cell, at the precision a person reads.
const TIMING: [(&str, Cell); 17] = [
    ("label", |r| r.label.clone()),
    ("path", |r| r.path.clone()),
    ("glyphs", |r| r.glyphs.to_string()),
    ("size", |r| format!("{}x{}", r.width, r.height)),
    ("GPU ms (median)", |r| format!("{:.3}", r.gpu_ms_median)),
    ("min", |r| format!("{:.3}", r.gpu_ms_min)),
    ("max", |r| format!("{:.3}", r.gpu_ms_max)),
    ("prepare ms", |r| format!("{:.1}", r.prepare_ms)),
    ("upload ms", |r| format!("{:.1}", r.upload_ms)),
    ("Mrays/s", |r| format!("{:.2}", r.rays_per_second * 1e-6)),
    ("glyphs/s", |r| format!("{:.0}", r.glyphs_per_second)),
    ("coeff bytes", |r| match r.mesh_bytes {
        Some(_) => "-".into(),
        None => r.coefficient_bytes.to_string(),
    }),
    ("instance bytes", |r| r.instance_bytes.to_string()),
    ("passes", |r| r.passes.to_string()),
    ("fragments/px", |r| {
        per_pixel(r, |w| w.fragments).map_or_else(|| "-".into(), |v| format!("{v:.2}"))
    }),
    ("evaluations/px", |r| {
        per_pixel(r, |w| w.evaluations).map_or_else(|| "-".into(), |v| format!("{v:.2}"))
    }),
    ("cull", |r| r.culling_report.clone()),
];

/// A work counter per covered pixel, where the frame counted its work.
fn per_pixel(
    r: &BenchResult,
    counter: fn(&crate::render::visibility::WorkCounts) -> u64,
) -> Option<f64> {
    let work = r.work.as_ref()?;
    Some(counter(work) as f64 / r.covered_pixels.max(1) as f64)
}

/// The cost-against-error table; "-" where a value was not measured.
const GEOMETRY: [(&str, Cell); 13] = [
    ("label", |r| r.label.clone()),
    ("method", |r| r.method.clone()),
    ("triangles", |r| optional(r.triangles, |t| t.to_string())),
    ("generate ms", |r| {
        optional(r.generate_ms, |ms| format!("{ms:.1}"))
    }),
    ("GPU ms", |r| format!("{:.3}", r.gpu_ms_median)),
    ("error px", |r| {
        accuracy(r, |a| format!("{:.3}", a.error_px))
    }),
    ("surface px (max)", |r| {
        accuracy(r, |a| format!("{:.3}", a.geometric.surface_max_px))
    }),
    ("(p99)", |r| {
        accuracy(r, |a| format!("{:.3}", a.geometric.surface_p99_px))
    }),
    ("silhouette px", |r| {
        accuracy(r, |a| format!("{:.3}", a.geometric.silhouette_mean_px))
    }),
    ("holes", |r| accuracy(r, |a| a.holes.to_string())),
    ("false hits", |r| accuracy(r, |a| a.false_hits.to_string())),
    ("median depth err", |r| {
        accuracy(r, |a| format!("{:.2e}", a.median_depth_error))
    }),
    ("bytes/glyph", |r| format!("{:.0}", r.bytes_per_glyph)),
];

/// The CSV: each column's name and cell at full precision; empty where a value was not
/// measured.
const CSV: [(&str, Cell); 33] = [
    ("label", |r| r.label.clone()),
    ("glyphs", |r| r.glyphs.to_string()),
    ("width", |r| r.width.to_string()),
    ("height", |r| r.height.to_string()),
    ("gpu_ms_median", |r| format!("{:.6}", r.gpu_ms_median)),
    ("gpu_ms_min", |r| format!("{:.6}", r.gpu_ms_min)),
    ("gpu_ms_max", |r| format!("{:.6}", r.gpu_ms_max)),
    ("prepare_ms", |r| format!("{:.3}", r.prepare_ms)),
    ("upload_ms", |r| format!("{:.3}", r.upload_ms)),
    ("covered_pixels", |r| r.covered_pixels.to_string()),
    ("rays_per_second", |r| format!("{:.1}", r.rays_per_second)),
    ("glyphs_per_second", |r| {
        format!("{:.1}", r.glyphs_per_second)
    }),
    ("coefficient_bytes", |r| r.coefficient_bytes.to_string()),
    ("instance_bytes", |r| r.instance_bytes.to_string()),
    ("draws", |r| r.draws.to_string()),
    ("passes", |r| r.passes.to_string()),
    ("fragments", |r| work_cell(r, |w| w.fragments)),
    ("evaluations", |r| work_cell(r, |w| w.evaluations)),
    ("scene", |r| r.scene.clone()),
    ("method", |r| r.method.clone()),
    ("path", |r| r.path.clone()),
    ("triangles", |r| {
        r.triangles.map_or_else(String::new, |t| t.to_string())
    }),
    ("generate_ms", |r| {
        r.generate_ms
            .map_or_else(String::new, |ms| format!("{ms:.3}"))
    }),
    ("mesh_bytes", |r| {
        r.mesh_bytes.map_or_else(String::new, |b| b.to_string())
    }),
    ("bytes_per_glyph", |r| format!("{:.1}", r.bytes_per_glyph)),
    ("holes", |r| csv_accuracy(r, |a| a.holes.to_string())),
    ("false_hits", |r| {
        csv_accuracy(r, |a| a.false_hits.to_string())
    }),
    ("median_depth_error", |r| {
        csv_accuracy(r, |a| format!("{:e}", a.median_depth_error))
    }),
    ("surface_error_px", |r| {
        csv_accuracy(r, |a| format!("{:e}", a.geometric.surface_max_px))
    }),
    ("silhouette_error_px", |r| {
        csv_accuracy(r, |a| format!("{:e}", a.geometric.silhouette_mean_px))
    }),
    ("error_px", |r| {
        csv_accuracy(r, |a| format!("{:e}", a.error_px))
    }),
    ("culling", |r| r.culling.clone()),
    ("cull_asked", |r| r.cull_asked.clone()),
];

fn header(columns: &[&str]) -> String {
    format!(
        "| {} |\n|{}\n",
        columns.join(" | "),
        "---|".repeat(columns.len())
    )
}

fn optional<T>(value: Option<T>, show: impl Fn(T) -> String) -> String {
    value.map_or_else(|| "-".into(), show)
}

/// An accuracy value for a Markdown cell, "-" when accuracy was not measured.
fn accuracy(r: &BenchResult, show: impl Fn(&BenchAccuracy) -> String) -> String {
    optional(r.accuracy.as_ref(), show)
}

/// A work counter for a CSV cell, empty where the frame did not count.
fn work_cell(
    r: &BenchResult,
    counter: fn(&crate::render::visibility::WorkCounts) -> u64,
) -> String {
    r.work
        .as_ref()
        .map_or_else(String::new, |w| counter(w).to_string())
}

/// An accuracy value for a CSV cell, empty when accuracy was not measured.
fn csv_accuracy(r: &BenchResult, show: impl Fn(&BenchAccuracy) -> String) -> String {
    r.accuracy.as_ref().map_or_else(String::new, show)
}

/// A Markdown table of `columns`, one row per result.
fn markdown_table(columns: &[(&str, Cell)], results: &[BenchResult]) -> String {
    let headings: Vec<&str> = columns.iter().map(|(heading, _)| *heading).collect();
    let mut out = header(&headings);
    for r in results {
        let cells: Vec<String> = columns.iter().map(|(_, cell)| cell(r)).collect();
        let _ = writeln!(out, "| {} |", cells.join(" | "));
    }
    out
}

/// A readable Markdown table, with the geometry table below it when there is one.
pub fn markdown(results: &[BenchResult]) -> String {
    let mut out = markdown_table(&TIMING, results);
    if results
        .iter()
        .any(|r| r.triangles.is_some() || r.accuracy.is_some())
    {
        out.push_str(
            "\nCost against geometric error (error px: the larger of the largest distance \
             of a drawn point from the true surface and the mean distance between the \
             silhouettes, in pixels; depth errors in units of the largest glyph's bounding \
             radius):\n\n",
        );
        out.push_str(&markdown_table(&GEOMETRY, results));
    }
    out
}

/// One row per configuration; columns that do not apply are empty.
pub fn csv(results: &[BenchResult]) -> String {
    let names: Vec<&str> = CSV.iter().map(|(name, _)| *name).collect();
    let mut out = format!("{}\n", names.join(","));
    for r in results {
        let cells: Vec<String> = CSV.iter().map(|(_, cell)| cell(r)).collect();
        let _ = writeln!(out, "{}", cells.join(","));
    }
    out
}

/// A result's column in [`pivot`]: its method, or "METHOD (auto)" where `--path auto`
/// chose the ray caster (whichever it chose).
fn pivot_column(r: &BenchResult) -> String {
    match r.path.starts_with("auto") {
        true => format!("{} (auto)", r.method.trim_end_matches(" (compute)")),
        false => r.method.clone(),
    }
}

/// Median GPU milliseconds with one row per field and image size and one column per
/// method (as [`BenchResult::method`] spells it, "METHOD (auto)" where `--path auto`
/// chose the ray caster), "-" where a configuration was not measured; the last column
/// gives the frames per second of the first method's time. `columns` come first, in
/// their order, measured or not (so that tables of several runs line up), then any
/// other method the results hold.
pub fn pivot(results: &[BenchResult], columns: &[String]) -> String {
    let mut methods: Vec<String> = columns.to_vec();
    let mut rows: Vec<(usize, u32, u32)> = Vec::new();
    for r in results {
        let column = pivot_column(r);
        if !methods.contains(&column) {
            methods.push(column);
        }
        if !rows.contains(&(r.glyphs, r.width, r.height)) {
            rows.push((r.glyphs, r.width, r.height));
        }
    }
    let Some(first) = methods.first().map(String::as_str) else {
        return String::new();
    };
    let fps = format!("{first} fps");
    let mut columns = vec!["glyphs", "size"];
    columns.extend(methods.iter().map(String::as_str));
    columns.push(&fps);
    let mut out = header(&columns);
    for &(glyphs, width, height) in &rows {
        let time = |method: &str| {
            results
                .iter()
                .find(|r| {
                    pivot_column(r) == method
                        && (r.glyphs, r.width, r.height) == (glyphs, width, height)
                })
                .map(|r| r.gpu_ms_median)
        };
        let _ = write!(out, "| {glyphs} | {width}x{height} |");
        for method in &methods {
            let _ = write!(
                out,
                " {} |",
                optional(time(method), |ms| format!("{ms:.3}"))
            );
        }
        let _ = writeln!(
            out,
            " {} |",
            optional(time(first), |ms| format!("{:.0}", 1e3 / ms))
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn result(method: &str, glyphs: usize, ms: f64) -> BenchResult {
        BenchResult {
            label: format!("{glyphs} {method}"),
            scene: glyphs.to_string(),
            method: method.into(),
            path: "fragment".into(),
            glyphs,
            width: 64,
            height: 32,
            prepare_ms: 0.0,
            upload_ms: 0.0,
            generate_ms: None,
            triangles: None,
            mesh_bytes: None,
            gpu_ms_median: ms,
            gpu_ms_min: ms,
            gpu_ms_max: ms,
            covered_pixels: 0,
            rays_per_second: 0.0,
            glyphs_per_second: 0.0,
            coefficient_bytes: 0,
            instance_bytes: 0,
            bytes_per_glyph: 0.0,
            draws: 1,
            passes: 1,
            culling: "off".into(),
            cull_asked: "off".into(),
            culling_report: "off (1 pass)".into(),
            work: None,
            accuracy: None,
            tube_segments: 0,
            tube_bytes: 0,
        }
    }

    /// Two runs' tables line up column for column when one of them skipped a method.
    #[test]
    fn pivot_keeps_the_asked_columns_when_a_method_is_missing() {
        let columns: Vec<String> = ["exact", "mesh:5", "exact (compute)"]
            .map(String::from)
            .to_vec();
        let full = pivot(
            &[
                result("exact", 10, 2.0),
                result("mesh:5", 10, 4.0),
                result("exact (compute)", 10, 1.0),
            ],
            &columns,
        );
        let skipped = pivot(
            &[
                result("exact", 100, 2.5),
                result("exact (compute)", 100, 0.5),
            ],
            &columns,
        );
        let header = full.lines().next().unwrap();
        assert_eq!(header, skipped.lines().next().unwrap());
        assert_eq!(
            header,
            "| glyphs | size | exact | mesh:5 | exact (compute) | exact fps |"
        );
        assert_eq!(
            skipped.lines().nth(2).unwrap(),
            "| 100 | 64x32 | 2.500 | - | 0.500 | 400 |"
        );
        assert_eq!(
            full.lines().nth(2).unwrap(),
            "| 10 | 64x32 | 2.000 | 4.000 | 1.000 | 500 |"
        );
    }
}
