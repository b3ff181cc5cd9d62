//! `glyphcast fit`: tensor, SH or fibre-ODF coefficients from a DWI series (see
//! `glyphcast_dmri::fit`).
//!
//! Flags are checked first, then every input file, and only then is anything fitted or
//! written, so a bad input costs no time and leaves no file.
use clap::{ArgGroup, Args};
use glyphcast::glyph::sh::parse_basis;
use glyphcast::glyph::tensor_order::TensorOrder;
use glyphcast::{Error, Result};
use glyphcast_dmri::fit::csd::{DEFAULT_CSD_LAMBDA, DEFAULT_CSD_TAU};
use glyphcast_dmri::fit::csd_mrtrix::{self, CsdAlgorithm};
use glyphcast_dmri::fit::gradients::BvecConvention;
use glyphcast_dmri::fit::output::{check_output_basis, output_tensor_order, write_output};
use glyphcast_dmri::fit::response::{DEFAULT_RESPONSE_FA, estimate_response};
use glyphcast_dmri::fit::{
    DEFAULT_LAMBDA, FitFiles, FitInputs, FitModel, OdfMethod, OdfModel, Response, fit_with_response,
};
use glyphcast_dmri::io::image::check_output_path;
use glyphcast_dmri::setting::DmriSetting;
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::path::PathBuf;

#[path = "fit_msmt.rs"]
mod msmt;

#[derive(Args)]
#[command(group(ArgGroup::new("series").args(["sh", "odf"])))]
pub struct FitArgs {
    /// Diffusion-weighted series: 4D NIfTI (.nii, .nii.gz) or MRtrix image (.mif,
    /// .mif.gz, .mih).
    #[arg(value_name = "DWI")]
    dwi: PathBuf,
    /// b-values, FSL format (one row or one column, s/mm^2). Leave out --bval and --bvec
    /// for an MRtrix DWI that carries its table (dw_scheme, scanner coordinates).
    #[arg(long, value_name = "FILE", requires = "bvec")]
    bval: Option<PathBuf>,
    /// Gradient directions, FSL format (3 rows of n, or n rows of 3), in the frame of
    /// --bvec-convention.
    #[arg(long, value_name = "FILE", requires = "bval")]
    bvec: Option<PathBuf>,
    /// Frame of --bvec: fsl (voxel axes with x negated when the affine's determinant is
    /// positive, as FSL and MRtrix read bvecs), voxel (voxel axes as stored) or world
    /// (scanner axes). Default: fsl (with a note where it negates x, which DIPY does not).
    #[arg(long, value_name = "CONVENTION", requires = "bvec")]
    bvec_convention: Option<String>,
    /// Tensor order (even, 2 to 12), or the highest SH band with --sh or --odf (even,
    /// 0 to 12).
    #[arg(long, visible_alias = "lmax")]
    order: u32,
    /// Output: 4D float32 image of coefficients, NIfTI (.nii, .nii.gz) or MRtrix (.mif,
    /// .mif.gz, with the basis in its header).
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    output: PathBuf,
    /// Fit real spherical harmonics to S/S0 instead of a tensor to the ADCs.
    #[arg(long)]
    sh: bool,
    /// Fit a fibre ODF as SH: csd (constrained spherical deconvolution, single shell),
    /// msmt (multi-shell multi-tissue CSD: WM fODF to -o, GM and CSF beside it), csa
    /// (constant solid angle) or qball.
    #[arg(long, value_name = "MODEL", conflicts_with = "sh")]
    odf: Option<String>,
    /// SH basis: tournier07 or descoteaux07, or the aliases mrtrix (tournier07), dipy
    /// (descoteaux07 legacy, DIPY's default) and dipy-new (descoteaux07).
    #[arg(long, requires = "series", default_value = "tournier07")]
    basis: String,
    /// The legacy variant of the SH basis (DIPY's legacy=True; implied by --basis dipy).
    #[arg(long, requires = "series")]
    legacy: bool,
    /// Regularisation weight: Laplace-Beltrami for --sh, csa and qball (default 0.006),
    /// the non-negativity constraint's for csd (default 1; MRtrix's -neg_lambda with
    /// --csd-algorithm mrtrix).
    #[arg(long, requires = "series")]
    lambda: Option<f64>,
    /// CSD: which algorithm: mrtrix (MRtrix3's dwi2fod csd, the default) or dipy (DIPY's
    /// ConstrainedSphericalDeconvModel).
    #[arg(long, value_name = "NAME", requires = "odf")]
    csd_algorithm: Option<String>,
    /// CSD: directions where the fODF is below the threshold are constrained. With
    /// --csd-algorithm mrtrix an fODF amplitude (dwi2fod -threshold, default 0); with
    /// dipy a fraction of the mean fODF (default 0.1).
    #[arg(long, requires = "odf")]
    tau: Option<f64>,
    /// CSD: the single-fibre response, MRtrix's text format (one row of zonal SH
    /// coefficients, as dwi2response writes). Default: estimated from the voxels with
    /// FA above --response-fa in the centre of the volume. With msmt: the WM response,
    /// one row per shell (b=0 first), with --response-gm and --response-csf.
    #[arg(long, value_name = "FILE", requires = "odf")]
    response: Option<PathBuf>,
    /// CSD: FA threshold of the voxels the response is estimated from.
    #[arg(long, value_name = "FA", requires = "odf", conflicts_with = "response", default_value_t = DEFAULT_RESPONSE_FA)]
    response_fa: f64,
    /// Stored order of a DTI fit's six entries in a NIfTI output: glyphcast (xx, xy, xz,
    /// yy, yz, zz, the default; FSL's dtifit order), fsl, dipy (xx, xy, yy, xz, yz, zz) or
    /// mrtrix (xx, yy, zz, xy, xz, yz). A .mif output is always in MRtrix's order. The
    /// order is recorded in the file's description.
    #[arg(long, value_name = "ORDER")]
    tensor_order: Option<String>,
    /// msmt: the GM response, MRtrix's multi-shell format (one row per shell, b=0 first,
    /// one column); with --response (WM, one row per shell) and --response-csf.
    /// Default: all three estimated from the data.
    #[arg(long, value_name = "FILE", requires_all = ["odf", "response", "response_csf"])]
    response_gm: Option<PathBuf>,
    /// msmt: the CSF response, as --response-gm.
    #[arg(long, value_name = "FILE", requires_all = ["odf", "response", "response_gm"])]
    response_csf: Option<PathBuf>,
    /// msmt: the GM image (band 0). Default: beside -o, its name with _gm before the
    /// extension (wm.nii.gz: wm_gm.nii.gz).
    #[arg(long, value_name = "FILE", requires = "odf")]
    gm: Option<PathBuf>,
    /// msmt: the CSF image (band 0). Default: -o's name with _csf.
    #[arg(long, value_name = "FILE", requires = "odf")]
    csf: Option<PathBuf>,
    /// Fit only where this 3D NIfTI or MRtrix image is non-zero (same spatial shape as
    /// the DWI).
    #[arg(long, value_name = "IMAGE")]
    mask: Option<PathBuf>,
    /// No progress bar and no summary line.
    #[arg(long)]
    quiet: bool,
}

impl FitArgs {
    fn model(&self) -> Result<FitModel> {
        let model = if let Some(name) = &self.odf {
            let method = OdfMethod::parse(name)?;
            let (basis, legacy) = parse_basis(&self.basis, self.legacy)?;
            msmt::check_flags(self, method)?;
            if !(self.response_fa > 0.0 && self.response_fa < 1.0) {
                return Err(Error::setting_value(
                    DmriSetting::ResponseFa,
                    self.response_fa,
                    "an FA threshold must be between 0 and 1",
                ));
            }
            let csd = match &self.csd_algorithm {
                Some(name) => CsdAlgorithm::parse(name)?,
                None => CsdAlgorithm::default(),
            };
            let (default_lambda, default_tau) = match (method, csd) {
                (OdfMethod::Csd, CsdAlgorithm::Mrtrix) => (
                    csd_mrtrix::DEFAULT_NEG_LAMBDA,
                    csd_mrtrix::DEFAULT_THRESHOLD,
                ),
                (OdfMethod::Csd, CsdAlgorithm::Dipy) => (DEFAULT_CSD_LAMBDA, DEFAULT_CSD_TAU),
                _ => (DEFAULT_LAMBDA, DEFAULT_CSD_TAU),
            };
            FitModel::Odf(OdfModel {
                method,
                band: self.order,
                basis,
                legacy,
                lambda: self.lambda.unwrap_or(default_lambda),
                tau: self.tau.unwrap_or(default_tau),
                csd,
            })
        } else if self.sh {
            let (basis, legacy) = parse_basis(&self.basis, self.legacy)?;
            FitModel::Sh {
                band: self.order,
                basis,
                legacy,
                lambda: self.lambda.unwrap_or(DEFAULT_LAMBDA),
            }
        } else {
            FitModel::Tensor { order: self.order }
        };
        model.validate()?;
        Ok(model)
    }

    /// Every file the fit reads: the DWI, its gradient table, the responses and the mask
    /// (no output may name one of them).
    pub(super) fn input_paths(&self) -> Vec<&std::path::Path> {
        std::iter::once(self.dwi.as_path())
            .chain(self.bval.as_deref())
            .chain(self.bvec.as_deref())
            .chain(self.response.as_deref())
            .chain(self.response_gm.as_deref())
            .chain(self.response_csf.as_deref())
            .chain(self.mask.as_deref())
            .collect()
    }
}

pub fn run(args: FitArgs) -> Result<()> {
    let model = args.model()?;
    let convention: BvecConvention = args.bvec_convention.as_deref().unwrap_or("fsl").parse()?;
    if let FitModel::Odf(OdfModel {
        method: OdfMethod::Msmt,
        ..
    }) = model
    {
        return msmt::run(&args, &model, convention);
    }
    check_output_path(&args.output, "-o/--output")?;
    check_output_basis(&args.output, "-o/--output", &model)?;
    let given_order: Option<TensorOrder> =
        args.tensor_order.as_deref().map(str::parse).transpose()?;
    let stored = output_tensor_order(&args.output, &model, given_order)?;
    glyphcast::io::atomic::check_outputs(&[&args.output], &args.input_paths())?;
    let inputs = load_inputs(&args, convention)?;
    let response = csd_response(&args, &model, &inputs)?;
    let bar = progress_bar(inputs.voxel_count() as u64, args.quiet);
    let fitted = fit_with_response(&inputs, &model, response.as_ref(), &mut |done| {
        bar.inc(done)
    });
    bar.finish_and_clear();
    let (coeffs, report) = fitted?;
    // Data that was dropped or changed is reported even with --quiet.
    for line in report.warnings(&args.dwi.display().to_string()) {
        eprintln!("warning: {line}");
    }
    write_output(&args.output, &coeffs, &inputs.dwi, &model, stored)?;
    if !args.quiet {
        let [x, y, z] = inputs.dwi.spatial_shape();
        eprintln!(
            "wrote {}: {x}x{y}x{z} voxels x {} coefficients ({} voxels fitted, {} with no b=0 signal left at 0)",
            args.output.display(),
            model.coefficient_count(),
            report.fitted(),
            report.zero_s0
        );
    }
    Ok(())
}

/// The DWI, its gradient table in the voxel axes, and the mask.
fn load_inputs(args: &FitArgs, convention: BvecConvention) -> Result<FitInputs> {
    let mut inputs = FitInputs::load(FitFiles {
        dwi: args.dwi.clone(),
        bval: args.bval.clone(),
        bvec: args.bvec.clone(),
        mask: args.mask.clone(),
    })?;
    if args.bvec.is_some() {
        let map = inputs.dwi.voxel_to_world()?;
        let to_voxel = convention.to_voxel_axes(&map, &inputs.dwi.file)?;
        // The default convention turns the bvecs where DIPY, which takes them as they
        // are, would not: said, so that a fit that disagrees with DIPY's says why.
        if args.bvec_convention.is_none() && to_voxel != glam::DMat3::IDENTITY && !args.quiet {
            eprintln!(
                "note: {}: the affine's determinant is positive, so the bvecs are read in \
                 FSL's frame, x negated (as FSL and MRtrix read them); DIPY takes them as \
                 they are: give --bvec-convention voxel for DIPY's reading, or fsl to keep \
                 this one without the note",
                inputs.dwi.file
            );
        }
        inputs.gradients = inputs.gradients.transformed(to_voxel);
    }
    Ok(inputs)
}

/// CSD's response: read from --response (its bands checked against --order), or
/// estimated from the data and reported; `None` for the other models.
fn csd_response(args: &FitArgs, model: &FitModel, inputs: &FitInputs) -> Result<Option<Response>> {
    let FitModel::Odf(
        odf @ OdfModel {
            method: OdfMethod::Csd,
            band,
            ..
        },
    ) = *model
    else {
        return Ok(None);
    };
    if let Some(path) = &args.response {
        // Bands past the response's last are zero (as dwi2fod -lmax takes them): the
        // constraint alone shapes those bands of the fODF.
        let response = Response::read(path)?;
        if odf.csd == CsdAlgorithm::Mrtrix {
            csd_mrtrix::check_response(&response)
                .map_err(|why| Error::input(path.display().to_string(), "response", why))?;
        }
        if response.band() < band && !args.quiet {
            eprintln!(
                "note: {}: the response has bands up to {}; bands {} to {band} of the fODF \
                 are set by the non-negativity constraint alone (as dwi2fod -lmax {band} does)",
                path.display(),
                response.band(),
                response.band() + 2
            );
        }
        return Ok(Some(response));
    }
    let estimate = estimate_response(inputs, band, args.response_fa)?;
    if !args.quiet {
        let [l1, l2, _] = estimate.eigenvalues;
        let tissue = match estimate.threshold {
            Some(t) => format!("S0 above {t:.1} (Otsu's threshold of the b=0 image)"),
            None => "S0 > 0 (no background found in the b=0 image)".to_string(),
        };
        let [i, j, k] = estimate.bounds;
        eprintln!(
            "response: {} voxels with FA > {} among {} tissue voxels ({tissue}{}), in \
             i {}..{}, j {}..{}, k {}..{}, S0 {:.1} to {:.1} (mean {:.1}): eigenvalues \
             {l1:.3e} {l2:.3e} {l2:.3e}; zonal SH {}",
            estimate.voxels,
            args.response_fa,
            estimate.tissue_voxels,
            if args.mask.is_some() {
                ", in the mask"
            } else {
                ""
            },
            i[0],
            i[1],
            j[0],
            j[1],
            k[0],
            k[1],
            estimate.s0_range.0,
            estimate.s0_range.1,
            estimate.s0,
            estimate.response.to_text().trim()
        );
    }
    Ok(Some(estimate.response))
}

/// A bar on stderr when a person is watching; hidden with --quiet or when stderr is
/// redirected (tests, pipelines, logs).
fn progress_bar(voxels: u64, quiet: bool) -> ProgressBar {
    if quiet || !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(voxels);
    match ProgressStyle::with_template("fitting {wide_bar} {pos}/{len} voxels, {eta} left") {
        Ok(style) => bar.with_style(style),
        Err(_) => bar,
    }
}
