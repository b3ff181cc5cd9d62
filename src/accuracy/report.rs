//! `glyphcast accuracy`: every requested method and setting on every suite scene, each
//! depth map compared with the float64 reference (computed once per scene), with the
//! geometric error in pixels and the GPU time of the glyph pass; printed as Markdown and
//! CSV.
use super::compare::{DepthComparison, compare_depth};
use super::geometric::{GeometricError, geometric_error};
use super::suite::SuiteScene;
use crate::Result;
use crate::glyph::reference::reference_depth;
use crate::render::glyph_data::prepare_scene;
use crate::render::headless::HeadlessRenderer;
use crate::render::{Method, Refinement, RenderSettings};
use crate::vk::Gpu;
use std::fmt::Write as _;

/// One measured combination.
#[derive(Clone, Debug)]
pub struct AccuracyRow {
    /// The suite scene's name.
    pub scene: String,
    /// The ray-casting method.
    pub method: Method,
    /// March step in units of the glyph's bounding radius.
    pub step: f32,
    /// How the hit was refined after the march.
    pub refinement: Refinement,
    /// Holes, false hits and depth errors against the float64 reference.
    pub comparison: DepthComparison,
    /// Surface distance and coverage errors against the reference.
    pub geometric: GeometricError,
    /// GPU time of the glyph pass, None when the queue has no timestamps.
    pub gpu_ms: Option<f64>,
}

/// Renders every scene with every settings variant and compares with the reference.
/// `progress` is told each finished row.
pub fn run(
    gpu: &Gpu,
    scenes: &[SuiteScene],
    variants: &[RenderSettings],
    mut progress: impl FnMut(&AccuracyRow),
) -> Result<Vec<AccuracyRow>> {
    let mut renderer = HeadlessRenderer::new(gpu)?;
    let mut rows = Vec::new();
    for suite_scene in scenes {
        let scene = &suite_scene.scene;
        let (w, h) = (scene.image.width, scene.image.height);
        let sets = prepare_scene(scene, 0.0)?;
        let world: Vec<_> = sets.iter().flat_map(|s| s.world.iter().cloned()).collect();
        let reference = reference_depth(&world, &scene.camera, w, h);
        let scale = world.iter().map(|g| g.scale * g.bound).fold(0.0, f64::max);
        for settings in variants {
            let image = renderer.render_view(
                gpu,
                &sets,
                &crate::render::headless::FrameView::new(&scene.camera, w, h),
                settings,
            )?;
            let comparison =
                compare_depth(&image.distance, &reference, w as usize, h as usize, scale);
            let geometric =
                geometric_error(&image.distance, &reference, &world, &scene.camera, w, h);
            let row = AccuracyRow {
                scene: suite_scene.name.to_owned(),
                method: settings.method,
                step: settings.step,
                refinement: settings.refinement,
                comparison,
                geometric,
                gpu_ms: image.gpu_ms,
            };
            progress(&row);
            rows.push(row);
        }
    }
    Ok(rows)
}

/// The method as `--method` spells it.
pub(crate) fn method_name(method: Method) -> String {
    method.to_string()
}

/// The refinement as `--refine` spells it (`none`, `bisect:K`, `interp`, `secant:K`).
pub fn refinement_name(r: Refinement) -> String {
    match r {
        Refinement::None => "none".into(),
        Refinement::Bisect(k) => format!("bisect:{k}"),
        Refinement::Interpolate => "interp".into(),
        Refinement::Secant(k) => format!("secant:{k}"),
    }
}

/// Step and refinement mean something only for methods that march.
fn march_cell(row: &AccuracyRow, value: String) -> String {
    if row.method.marches() {
        value
    } else {
        "-".into()
    }
}

fn cells(row: &AccuracyRow) -> [String; 10] {
    let c = &row.comparison;
    [
        row.scene.clone(),
        method_name(row.method),
        march_cell(row, format!("{}", row.step)),
        march_cell(row, refinement_name(row.refinement)),
        c.holes.to_string(),
        c.false_hits.to_string(),
        format!("{:.2e}", c.median_error),
        format!("{:.2e}", c.p99_error),
        format!("{:.3}", row.geometric.pixels()),
        row.gpu_ms
            .map_or_else(|| "n/a".into(), |ms| format!("{ms:.2}")),
    ]
}

const HEADER: [&str; 10] = [
    "scene",
    "method",
    "step",
    "refine",
    "holes",
    "false hits",
    "median err",
    "p99 err",
    "error px",
    "GPU ms",
];

/// A Markdown table; depth errors are in units of the glyph scale, the geometric error
/// (see `accuracy::geometric`) in pixels.
pub fn markdown(rows: &[AccuracyRow]) -> String {
    let mut out = format!("| {} |\n", HEADER.join(" | "));
    let _ = writeln!(out, "|{}", "---|".repeat(HEADER.len()));
    for row in rows {
        let _ = writeln!(out, "| {} |", cells(row).join(" | "));
    }
    out
}

/// The rows as CSV with a header line, one line per row.
pub fn csv(rows: &[AccuracyRow]) -> String {
    let mut out = String::from(
        "scene,method,step,refine,holes,false_hits,median_error,p99_error,gpu_ms,covered,band,error_px\n",
    );
    for row in rows {
        let c = &row.comparison;
        let _ = writeln!(
            out,
            "{},{},{},{},{},{},{:e},{:e},{},{},{},{:e}",
            row.scene,
            method_name(row.method),
            march_cell(row, row.step.to_string()),
            march_cell(row, refinement_name(row.refinement)),
            c.holes,
            c.false_hits,
            c.median_error,
            c.p99_error,
            row.gpu_ms.map_or_else(String::new, |ms| format!("{ms:.4}")),
            c.covered,
            c.band,
            row.geometric.pixels()
        );
    }
    out
}

/// One line per settings over the whole suite: total holes and false hits, the worst
/// median and 99th-percentile depth errors, and the total GPU time, fastest first.
pub fn summary_markdown(rows: &[AccuracyRow]) -> String {
    let mut groups: Vec<(String, String, String, Vec<&AccuracyRow>)> = Vec::new();
    for row in rows {
        let key = (
            method_name(row.method),
            march_cell(row, row.step.to_string()),
            march_cell(row, refinement_name(row.refinement)),
        );
        match groups
            .iter_mut()
            .find(|g| (&g.0, &g.1, &g.2) == (&key.0, &key.1, &key.2))
        {
            Some(group) => group.3.push(row),
            None => groups.push((key.0, key.1, key.2, vec![row])),
        }
    }
    let total_ms = |g: &[&AccuracyRow]| g.iter().filter_map(|r| r.gpu_ms).sum::<f64>();
    groups.sort_by(|a, b| total_ms(&a.3).total_cmp(&total_ms(&b.3)));
    let mut out = String::from(
        "| method | step | refine | scenes | holes | false hits | worst median err | worst p99 err | total GPU ms |\n\
         |---|---|---|---|---|---|---|---|---|\n",
    );
    for (method, step, refine, g) in &groups {
        let worst = |f: fn(&AccuracyRow) -> f64| g.iter().map(|r| f(r)).fold(0.0, f64::max);
        let _ = writeln!(
            out,
            "| {method} | {step} | {refine} | {} | {} | {} | {:.2e} | {:.2e} | {:.1} |",
            g.len(),
            g.iter().map(|r| r.comparison.holes).sum::<usize>(),
            g.iter().map(|r| r.comparison.false_hits).sum::<usize>(),
            worst(|r| r.comparison.median_error),
            worst(|r| r.comparison.p99_error),
            total_ms(g)
        );
    }
    out
}
