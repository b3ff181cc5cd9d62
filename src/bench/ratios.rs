//! The comparisons a sweep is run for, condensed from its results, per scene:
//!
//! - ray-cast time / impostor time: what the glyph function costs above the box proxies
//!   and a trivial fragment shader;
//! - tessellation time at equal geometric error / ray-cast time: the coarsest mesh (fewest
//!   triangles) whose geometric error is below [`EQUAL_ERROR_PX`] pixels, against the
//!   default ray caster (`RenderSettings::default().method`, `exact`), on GPU frame time
//!   (the CPU generation time is given beside it);
//! - memory per glyph of that mesh / of the ray caster (coefficients and instance).
use super::BenchResult;
use crate::render::RenderSettings;
use std::fmt::Write as _;

/// The geometric error (pixels) a tessellation must stay below to count as equal to the
/// ray caster, whose own error is a small fraction of a pixel.
pub const EQUAL_ERROR_PX: f64 = 0.5;

/// One ratio of one scene.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Ratio {
    /// The scene the ratio is of.
    pub scene: String,
    /// Which ratio: one of the `*_OVER_*` constants of this module.
    pub name: &'static str,
    /// None where the sweep has no configuration that qualifies.
    pub value: Option<f64>,
    /// The numbers behind the ratio.
    pub detail: String,
}

/// Name of the ratio of ray-cast to impostor GPU time.
pub(crate) const RAY_CAST_OVER_IMPOSTOR: &str = "ray-cast / impostor GPU time";
/// Name of the ratio of tessellation to ray-cast GPU time at equal geometric error.
pub(crate) const MESH_OVER_RAY_CAST: &str = "tessellation / ray-cast GPU time at equal error";
/// Name of the ratio of GPU memory per glyph, tessellation to ray cast.
pub(crate) const MESH_MEMORY_OVER_RAY_CAST: &str = "memory per glyph, tessellation / ray cast";

/// The ratios of every scene of `results` that has the rows they need.
pub fn ratios(results: &[BenchResult]) -> Vec<Ratio> {
    let mut scenes: Vec<&str> = Vec::new();
    for r in results {
        if !scenes.contains(&r.scene.as_str()) {
            scenes.push(&r.scene);
        }
    }
    let default_method = RenderSettings::default().method.to_string();
    let mut out = Vec::new();
    for scene in scenes {
        let rows: Vec<&BenchResult> = results.iter().filter(|r| r.scene == scene).collect();
        let find = |method: &str| rows.iter().copied().find(|r| r.method == method);
        let ratio = |name, value, detail| Ratio {
            scene: scene.to_owned(),
            name,
            value,
            detail,
        };
        let Some(ray_cast) = find(&default_method) else {
            continue;
        };
        if let Some(impostor) = find("impostor") {
            out.push(ratio(
                RAY_CAST_OVER_IMPOSTOR,
                Some(ray_cast.gpu_ms_median / impostor.gpu_ms_median),
                format!(
                    "{} {:.3} ms / {:.3} ms",
                    default_method, ray_cast.gpu_ms_median, impostor.gpu_ms_median
                ),
            ));
        }
        let meshes: Vec<&BenchResult> = rows
            .iter()
            .copied()
            .filter(|r| r.triangles.is_some() && r.accuracy.is_some())
            .collect();
        if meshes.is_empty() {
            continue;
        }
        let error = |r: &BenchResult| r.accuracy.map_or(f64::INFINITY, |a| a.error_px);
        let ray_cast_error = ray_cast
            .accuracy
            .map_or_else(String::new, |a| format!(", {:.3} px", a.error_px));
        let equal = meshes
            .iter()
            .filter(|r| error(r) < EQUAL_ERROR_PX)
            .min_by_key(|r| r.triangles);
        match equal {
            Some(mesh) => {
                out.push(ratio(
                    MESH_OVER_RAY_CAST,
                    Some(mesh.gpu_ms_median / ray_cast.gpu_ms_median),
                    format!(
                        "{}: {:.3} ms ({} triangles, {:.3} px; generation {:.1} ms) / {} {:.3} ms{}",
                        mesh.method,
                        mesh.gpu_ms_median,
                        mesh.triangles.unwrap_or(0),
                        error(mesh),
                        mesh.generate_ms.unwrap_or(0.0),
                        default_method,
                        ray_cast.gpu_ms_median,
                        ray_cast_error
                    ),
                ));
                out.push(ratio(
                    MESH_MEMORY_OVER_RAY_CAST,
                    Some(mesh.bytes_per_glyph / ray_cast.bytes_per_glyph),
                    format!(
                        "{}: {:.0} B / {} {:.0} B (coefficients, instance and box)",
                        mesh.method, mesh.bytes_per_glyph, default_method, ray_cast.bytes_per_glyph
                    ),
                ));
            }
            None => {
                let best = meshes.iter().min_by(|a, b| error(a).total_cmp(&error(b)));
                let detail = best.map_or_else(String::new, |b| {
                    format!(
                        "no mesh measured is below {EQUAL_ERROR_PX} px; the best, {}, has {:.3} px",
                        b.method,
                        error(b)
                    )
                });
                out.push(ratio(MESH_OVER_RAY_CAST, None, detail));
            }
        }
    }
    out
}

/// The ratios as a Markdown table (empty when there are none).
pub fn markdown(ratios: &[Ratio]) -> String {
    if ratios.is_empty() {
        return String::new();
    }
    let mut out = String::from("| scene | ratio | value | from |\n|---|---|---|---|\n");
    for r in ratios {
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} |",
            r.scene,
            r.name,
            r.value.map_or_else(|| "n/a".into(), |v| format!("{v:.3}")),
            r.detail
        );
    }
    out
}
