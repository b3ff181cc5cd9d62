//! Benchmark results as Markdown (for a person) and CSV (for a plot): the timings of
//! every configuration, then, where a sweep drew meshes or measured accuracy, the table
//! that sets cost against geometric error (the paper's Table 2 layout).
use super::BenchResult;
use std::fmt::Write as _;

const COLUMNS: [&str; 12] = [
    "label",
    "glyphs",
    "size",
    "GPU ms (median)",
    "min",
    "max",
    "prepare ms",
    "upload ms",
    "Mrays/s",
    "glyphs/s",
    "coeff bytes",
    "instance bytes",
];

const GEOMETRY_COLUMNS: [&str; 13] = [
    "label",
    "method",
    "triangles",
    "generate ms",
    "GPU ms",
    "error px",
    "surface px (max)",
    "(p99)",
    "silhouette px",
    "holes",
    "false hits",
    "median depth err",
    "bytes/glyph",
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

/// A readable Markdown table, with the geometry table below it when there is one.
pub fn markdown(results: &[BenchResult]) -> String {
    let mut out = header(&COLUMNS);
    for r in results {
        let _ = writeln!(
            out,
            "| {} | {} | {}x{} | {:.3} | {:.3} | {:.3} | {:.1} | {:.1} | {:.2} | {:.0} | {} | {} |",
            r.label,
            r.glyphs,
            r.width,
            r.height,
            r.gpu_ms_median,
            r.gpu_ms_min,
            r.gpu_ms_max,
            r.prepare_ms,
            r.upload_ms,
            r.rays_per_second * 1e-6,
            r.glyphs_per_second,
            r.coefficient_bytes,
            r.instance_bytes
        );
    }
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
        out.push_str(&header(&GEOMETRY_COLUMNS));
        for r in results {
            let a = r.accuracy.as_ref();
            let _ = writeln!(
                out,
                "| {} | {} | {} | {} | {:.3} | {} | {} | {} | {} | {} | {} | {} | {:.0} |",
                r.label,
                r.method,
                optional(r.triangles, |t| t.to_string()),
                optional(r.generate_ms, |ms| format!("{ms:.1}")),
                r.gpu_ms_median,
                optional(a, |a| format!("{:.3}", a.error_px)),
                optional(a, |a| format!("{:.3}", a.geometric.surface_max_px)),
                optional(a, |a| format!("{:.3}", a.geometric.surface_p99_px)),
                optional(a, |a| format!("{:.3}", a.geometric.silhouette_mean_px)),
                optional(a, |a| a.holes.to_string()),
                optional(a, |a| a.false_hits.to_string()),
                optional(a, |a| format!("{:.2e}", a.median_depth_error)),
                r.bytes_per_glyph
            );
        }
    }
    out
}

/// One row per configuration; columns that do not apply are empty.
pub fn csv(results: &[BenchResult]) -> String {
    let mut out = String::from(
        "label,glyphs,width,height,gpu_ms_median,gpu_ms_min,gpu_ms_max,prepare_ms,upload_ms,\
         covered_pixels,rays_per_second,glyphs_per_second,coefficient_bytes,instance_bytes,\
         draws,scene,method,triangles,generate_ms,mesh_bytes,bytes_per_glyph,holes,false_hits,\
         median_depth_error,surface_error_px,silhouette_error_px,error_px\n",
    );
    let empty = String::new;
    for r in results {
        let a = r.accuracy.as_ref();
        let _ = writeln!(
            out,
            "{},{},{},{},{:.6},{:.6},{:.6},{:.3},{:.3},{},{:.1},{:.1},{},{},{},{},{},{},{},{},{:.1},{},{},{},{},{},{}",
            r.label,
            r.glyphs,
            r.width,
            r.height,
            r.gpu_ms_median,
            r.gpu_ms_min,
            r.gpu_ms_max,
            r.prepare_ms,
            r.upload_ms,
            r.covered_pixels,
            r.rays_per_second,
            r.glyphs_per_second,
            r.coefficient_bytes,
            r.instance_bytes,
            r.draws,
            r.scene,
            r.method,
            r.triangles.map_or_else(empty, |t| t.to_string()),
            r.generate_ms.map_or_else(empty, |ms| format!("{ms:.3}")),
            r.mesh_bytes.map_or_else(empty, |b| b.to_string()),
            r.bytes_per_glyph,
            a.map_or_else(empty, |a| a.holes.to_string()),
            a.map_or_else(empty, |a| a.false_hits.to_string()),
            a.map_or_else(empty, |a| format!("{:e}", a.median_depth_error)),
            a.map_or_else(empty, |a| format!("{:e}", a.geometric.surface_max_px)),
            a.map_or_else(empty, |a| format!("{:e}", a.geometric.silhouette_mean_px)),
            a.map_or_else(empty, |a| format!("{:e}", a.error_px)),
        );
    }
    out
}

/// Median GPU milliseconds with one row per field and image size and one column per
/// method (as [`BenchResult::method`] spells it), "-" where a configuration was not
/// measured; the last column gives the frames per second of the first method's time.
pub fn pivot(results: &[BenchResult]) -> String {
    let mut methods: Vec<&str> = Vec::new();
    let mut rows: Vec<(usize, u32, u32)> = Vec::new();
    for r in results {
        if !methods.contains(&r.method.as_str()) {
            methods.push(&r.method);
        }
        if !rows.contains(&(r.glyphs, r.width, r.height)) {
            rows.push((r.glyphs, r.width, r.height));
        }
    }
    let Some(first) = methods.first().copied() else {
        return String::new();
    };
    let fps = format!("{first} fps");
    let mut columns = vec!["glyphs", "size"];
    columns.extend(methods.iter().copied());
    columns.push(&fps);
    let mut out = header(&columns);
    for &(glyphs, width, height) in &rows {
        let time = |method: &str| {
            results
                .iter()
                .find(|r| {
                    r.method == method && (r.glyphs, r.width, r.height) == (glyphs, width, height)
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
