//! `glyphcast fit --odf msmt`: multi-shell multi-tissue CSD (see `glyphcast_dmri::fit::msmt`).
//! The WM fODF goes to -o, GM and CSF (band 0) to --gm and --csf or beside -o
//! (`NAME_gm.EXT`, `NAME_csf.EXT`); the three are written as one set, all or none.
use std::path::{Path, PathBuf};

use glyphcast::error::Relation;
use glyphcast::glyph::tensor_order::TensorOrder;
use glyphcast::{Error, Result, Setting};
use glyphcast_dmri::fit::gradients::BvecConvention;
use glyphcast_dmri::fit::msmt::{MsmtFitter, MsmtProblem, Shells, TISSUES, fit_msmt};
use glyphcast_dmri::fit::output::{check_output_basis, output_bytes};
use glyphcast_dmri::fit::response::DEFAULT_RESPONSE_FA;
use glyphcast_dmri::fit::response_msmt::{
    CSF_MIN_MD, GM_MAX_MD, ISO_FA, estimate_responses, read_responses,
};
use glyphcast_dmri::fit::{FitInputs, FitModel, OdfMethod, OdfModel};
use glyphcast_dmri::io::image::check_output_path;
use glyphcast_dmri::setting::DmriSetting;

use super::{FitArgs, load_inputs, progress_bar};

/// Flags that belong to one ODF model only: Err (usage) naming the first given with
/// another.
pub(super) fn check_flags(args: &FitArgs, method: OdfMethod) -> Result<()> {
    let msmt = method == OdfMethod::Msmt;
    let csd = method == OdfMethod::Csd;
    let owned = [
        (
            "--response",
            args.response.is_some(),
            csd || msmt,
            "csd or msmt",
        ),
        ("--tau", args.tau.is_some(), csd, "csd"),
        ("--csd-algorithm", args.csd_algorithm.is_some(), csd, "csd"),
        (
            "--response-fa",
            args.response_fa != DEFAULT_RESPONSE_FA,
            csd || msmt,
            "csd or msmt",
        ),
        ("--response-gm", args.response_gm.is_some(), msmt, "msmt"),
        ("--response-csf", args.response_csf.is_some(), msmt, "msmt"),
        ("--gm", args.gm.is_some(), msmt, "msmt"),
        ("--csf", args.csf.is_some(), msmt, "msmt"),
        (
            "--lambda",
            args.lambda.is_some() && msmt,
            false,
            "csd, csa or qball",
        ),
    ];
    if let Some((flag, _, _, owner)) = owned.iter().find(|(_, given, ok, _)| *given && !ok) {
        return Err(Error::conflict(
            *flag,
            Relation::Requires,
            DmriSetting::Odf.with(owner),
        ));
    }
    if msmt && args.response.is_some() && args.response_gm.is_none() {
        // --odf msmt takes the three responses together, or none (it estimates them).
        return Err(Error::conflict(
            "--response WM.txt",
            Relation::Requires,
            "--response-gm GM.txt --response-csf CSF.txt with --odf msmt (or no --response, \
             to estimate the three)",
        ));
    }
    Ok(())
}

/// `path` with `_tissue` before its extension (.nii, .nii.gz, .mif, .mif.gz).
fn beside(path: &Path, tissue: &str) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let lower = name.to_ascii_lowercase();
    let ending = [".nii.gz", ".mif.gz", ".nii", ".mif"]
        .into_iter()
        .find(|e| lower.ends_with(e))
        .map_or(0, str::len);
    let (stem, ext) = name.split_at(name.len() - ending);
    path.with_file_name(format!("{stem}_{tissue}{ext}"))
}

pub(super) fn run(args: &FitArgs, model: &FitModel, convention: BvecConvention) -> Result<()> {
    let FitModel::Odf(odf) = *model else {
        return Err(Error::Call {
            call: "fit_msmt::run",
            expected: "the msmt model",
        });
    };
    let gm_path = args
        .gm
        .clone()
        .unwrap_or_else(|| beside(&args.output, "gm"));
    let csf_path = args
        .csf
        .clone()
        .unwrap_or_else(|| beside(&args.output, "csf"));
    for (option, path) in [
        ("-o/--output", &args.output),
        ("--gm", &gm_path),
        ("--csf", &csf_path),
    ] {
        check_output_path(path, option)?;
        check_output_basis(path, option, model)?;
    }
    if args.tensor_order.is_some() {
        return Err(Error::conflict(
            Setting::TensorOrder,
            Relation::Excludes,
            DmriSetting::Odf.with("msmt"),
        ));
    }
    glyphcast::io::atomic::check_outputs(
        &[&args.output, &gm_path, &csf_path],
        &args.input_paths(),
    )?;
    let inputs = load_inputs(args, convention)?;
    let shells = Shells::group(&inputs.gradients.bvals);
    check_shells(&inputs, &shells)?;
    let responses = match (&args.response, &args.response_gm, &args.response_csf) {
        (Some(wm), Some(gm), Some(csf)) => read_responses(wm, gm, csf, &shells)?,
        _ => estimated(args, &inputs, &shells, odf.band)?,
    };
    let fitter = MsmtFitter::new(&MsmtProblem {
        band: odf.band,
        basis: (odf.basis, odf.legacy),
        gradients: &inputs.gradients,
        shells: &shells,
        responses: &responses,
    })?;
    let bar = progress_bar(inputs.voxel_count() as u64, args.quiet);
    let fitted = fit_msmt(&inputs, &fitter, &|done| bar.inc(done));
    bar.finish_and_clear();
    let volumes = fitted?;
    for line in volumes.report.warnings(&args.dwi.display().to_string()) {
        eprintln!("warning: {line}");
    }
    if volumes.unsolved > 0 {
        eprintln!(
            "warning: {}: the QP did not converge in {} voxel(s), left at 0",
            args.dwi.display(),
            volumes.unsolved
        );
    }
    let band0 = FitModel::Odf(OdfModel { band: 0, ..odf });
    let glyphcast_order = TensorOrder::Glyphcast;
    let basis_text = format!(
        "{}{}",
        odf.basis.name(),
        if odf.legacy { " legacy" } else { "" }
    );
    let tissue_description =
        |tissue: &str| format!("glyphcast fit: SH band 0 {basis_text} msmt {tissue} ODF");
    let files = [
        (
            &args.output,
            output_bytes(
                &args.output,
                &volumes.wm,
                &inputs.dwi,
                model,
                glyphcast_order,
                &model.description(),
            )?,
        ),
        (
            &gm_path,
            output_bytes(
                &gm_path,
                &volumes.gm,
                &inputs.dwi,
                &band0,
                glyphcast_order,
                &tissue_description("GM"),
            )?,
        ),
        (
            &csf_path,
            output_bytes(
                &csf_path,
                &volumes.csf,
                &inputs.dwi,
                &band0,
                glyphcast_order,
                &tissue_description("CSF"),
            )?,
        ),
    ];
    let set: Vec<(&Path, &[u8])> = files
        .iter()
        .map(|(p, b)| (p.as_path(), b.as_slice()))
        .collect();
    glyphcast::io::atomic::write_all_atomic(&set)?;
    if !args.quiet {
        let [x, y, z] = inputs.dwi.spatial_shape();
        eprintln!(
            "wrote {} (WM fODF, {} coefficients), {} (GM) and {} (CSF): {x}x{y}x{z} voxels, {} fitted, shells b = {} s/mm^2",
            args.output.display(),
            volumes.wm.shape()[3],
            gm_path.display(),
            csf_path.display(),
            volumes.report.fitted() - volumes.unsolved,
            shells.list()
        );
    }
    Ok(())
}

/// Three tissues need three distinct b-values (b=0 included) with signal in each.
fn check_shells(inputs: &FitInputs, shells: &Shells) -> Result<()> {
    let weighted = shells.len() - 1;
    if weighted >= 2 {
        return Ok(());
    }
    Err(Error::input(
        &inputs.origin.bvals,
        "b-values",
        format!(
            "multi-tissue CSD separates WM, GM and CSF by how their signals fall with b, so it needs at least two non-zero shells besides b=0; this DWI has {weighted} (b = {} s/mm^2, shells {} s/mm^2 apart or more): fit single-shell data with --odf csd",
            shells.list(),
            glyphcast_dmri::fit::msmt::SHELL_GAP
        ),
    ))
}

/// The responses estimated from the data, with the line that says from which voxels.
fn estimated(
    args: &FitArgs,
    inputs: &FitInputs,
    shells: &Shells,
    band: u32,
) -> Result<glyphcast_dmri::fit::msmt::TissueResponses> {
    let estimate = estimate_responses(inputs, shells, band, args.response_fa)?;
    if !args.quiet {
        let [wm, gm, csf] = estimate.voxels;
        let [s_wm, s_gm, s_csf] = estimate.s0;
        eprintln!(
            "responses (DTI on the b = {:.0} shell, among {} tissue voxels of the central region{}): \
             {} {wm} voxels with FA > {} (mean S0 {s_wm:.1}), {} {gm} voxels with FA < {ISO_FA} and MD < {GM_MAX_MD:e} (S0 {s_gm:.1}), \
             {} {csf} voxels with FA < {ISO_FA} and MD > {CSF_MIN_MD:e} (S0 {s_csf:.1})",
            estimate.dti_shell,
            estimate.tissue_voxels,
            if args.mask.is_some() {
                ", in the mask"
            } else {
                ""
            },
            TISSUES[0],
            args.response_fa,
            TISSUES[1],
            TISSUES[2],
        );
        let [wm_text, gm_text, csf_text] = estimate.responses.to_texts();
        for (tissue, text) in TISSUES.iter().zip([wm_text, gm_text, csf_text]) {
            eprintln!(
                "response {tissue} (rows b = {}):\n{}",
                shells.list(),
                text.trim_end()
            );
        }
    }
    Ok(estimate.responses)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tissue_outputs_go_beside_the_wm_output() {
        assert_eq!(
            beside(Path::new("out/wm.nii.gz"), "gm"),
            Path::new("out/wm_gm.nii.gz")
        );
        assert_eq!(
            beside(Path::new("fod.mif"), "csf"),
            Path::new("fod_csf.mif")
        );
        assert_eq!(beside(Path::new("a.b.NII"), "gm"), Path::new("a.b_gm.NII"));
        assert_eq!(
            beside(Path::new("x.mif.gz"), "csf"),
            Path::new("x_csf.mif.gz")
        );
    }
}
