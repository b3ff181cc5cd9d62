//! `glyphcast peaks`: the largest maxima of each voxel's ODF (`glyphcast_dmri::fit::peaks`),
//! written in MRtrix `sh2peaks`' layout: 3 N values per voxel, each peak's unit
//! direction times its amplitude, highest first, NaN for missing peaks.
//!
//! The basis comes from the file's record (as `render --sh` takes it), or `--basis`.
//! The peaks are found in the frame of the coefficients (the voxel axes for a NIfTI file
//! written by `glyphcast fit` or DIPY, scanner axes for an MRtrix image unless its
//! `glyphcast_frame` key says voxel) and written in the frame the output's format is
//! read in: scanner axes in a `.mif` (as `sh2peaks` writes and mrview reads them), voxel
//! axes in a NIfTI file (DIPY's); the affine's orthogonal factor turns them from one to
//! the other where the two differ, so `render --peaks` and other readers take them as
//! meant.
use clap::Args;
use glyphcast::glyph::sh::parse_basis;
use glyphcast::glyph::sh::sh_count;
use glyphcast::{Error, Result, Setting};
use glyphcast_dmri::fit::peaks::{
    DEFAULT_MIN_SEPARATION, DEFAULT_PEAK_COUNT, DEFAULT_RELATIVE_THRESHOLD, PeakFinder,
    PeakOptions, peak_volume, rotate_peaks,
};
use glyphcast_dmri::io::image::{
    ImageHeader, ImageWrite, OutputFormat, check_output_path, read_image, write_image,
};
use glyphcast_dmri::volume::{
    CoefficientFrame, check_variant_named, recorded_basis, resolve_basis,
};
use ndarray::Array4;
use std::path::PathBuf;

#[derive(Args)]
pub struct PeaksArgs {
    /// 4D image of ODF SH coefficients, [x, y, z, (L+1)(L+2)/2] for an even L <= 12
    /// (glyphcast fit --odf, dwi2fod, DIPY): NIfTI or MRtrix.
    #[arg(value_name = "ODF")]
    odf: PathBuf,
    /// Output: 4D float32 image of 3 N values per voxel, NIfTI (.nii, .nii.gz) or MRtrix
    /// (.mif, .mif.gz).
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    output: PathBuf,
    /// SH basis of the ODF (as render --basis). Default: the one the file records,
    /// tournier07 for MRtrix images without a record.
    #[arg(long, value_name = "BASIS")]
    basis: Option<String>,
    /// The legacy variant of --basis.
    #[arg(long, requires = "basis")]
    legacy: bool,
    /// Use --basis even where the file records another basis.
    #[arg(long, requires = "basis")]
    force_basis: bool,
    /// Peaks per voxel (N).
    #[arg(long, default_value_t = DEFAULT_PEAK_COUNT)]
    count: usize,
    /// Peaks below this fraction of the voxel's largest are left out.
    #[arg(long, value_name = "FRACTION", default_value_t = DEFAULT_RELATIVE_THRESHOLD)]
    relative_threshold: f64,
    /// Peaks within this angle (degrees) of a larger one are left out.
    #[arg(long, value_name = "DEGREES", default_value_t = DEFAULT_MIN_SEPARATION)]
    min_separation: f64,
    /// No summary line.
    #[arg(long)]
    quiet: bool,
}

pub fn run(args: PeaksArgs) -> Result<()> {
    let options = PeakOptions {
        count: args.count,
        relative_threshold: args.relative_threshold,
        min_separation_degrees: args.min_separation,
    };
    options.validate()?;
    let given = args
        .basis
        .as_deref()
        .map(|name| parse_basis(name, args.legacy))
        .transpose()?;
    check_output_path(&args.output, "-o/--output")?;
    glyphcast::io::atomic::check_outputs(&[&args.output], &[&args.odf])?;
    let image = read_image(&args.odf)?;
    glyphcast_dmri::volume::check_content(&image, glyphcast_dmri::volume::RecordedContent::Sh)?;
    let shape = image.shape(4);
    if shape.len() != 4 {
        return Err(Error::input(
            &image.file,
            "dim",
            format!("expected a 4D image of SH coefficients, found shape {shape:?}"),
        ));
    }
    // Trailing axes of size 1 are indexed at 0.
    let rank = image.data.ndim();
    let coeffs = Array4::from_shape_fn((shape[0], shape[1], shape[2], shape[3]), |(x, y, z, t)| {
        let mut index = vec![0; rank];
        for (slot, i) in index.iter_mut().zip([x, y, z, t]) {
            *slot = i;
        }
        image.data[index.as_slice()]
    });
    let count = shape[3];
    let band = (0..=glyphcast_dmri::fit::MAX_ORDER)
        .step_by(2)
        .find(|&l| sh_count(l) == count)
        .ok_or_else(|| {
            Error::input(
                &image.file,
                "dim",
                format!(
                    "{count} coefficients per voxel is not (L+1)(L+2)/2 for an even L up to {}",
                    glyphcast_dmri::fit::MAX_ORDER
                ),
            )
        })?;
    if given.is_none()
        && recorded_basis(&image)?.is_none()
        && matches!(image.header, ImageHeader::Nifti(_))
    {
        return Err(Error::setting(
            Setting::Basis,
            format!(
                "{} records no SH basis: give one of tournier07, descoteaux07, mrtrix, dipy or \
                 dipy-new",
                image.file
            ),
        ));
    }
    check_variant_named(
        args.basis.as_deref(),
        args.legacy.then_some(true),
        args.force_basis,
        Some(&image),
        &image.file,
    )?;
    if band == 0 {
        eprintln!(
            "note: {}: band 0 only (an isotropic tissue ODF, as multi-tissue CSD writes for \
             grey matter and CSF): the same value in every direction, no peak; every voxel \
             is NaN",
            image.file
        );
    }
    let (basis, legacy) = resolve_basis(&image, given, args.force_basis)?;
    let finder = PeakFinder::new(band, basis, legacy, options)?;
    let mut peaks = peak_volume(&coeffs, &finder)?;
    let mif = OutputFormat::of(&args.output, "-o/--output")?.is_mrtrix();
    let written = if mif {
        CoefficientFrame::World
    } else {
        CoefficientFrame::Voxel
    };
    if CoefficientFrame::of_image(&image)? != written {
        let r = image.voxel_to_world.orthogonal_factor().ok_or_else(|| {
            Error::input(
                &image.file,
                "affine",
                "the polar decomposition of the affine did not converge",
            )
        })?;
        // Voxel-frame directions reach the world through R, world ones go back by R^T.
        rotate_peaks(&mut peaks, if mif { r } else { r.transpose() });
    }
    let description = format!(
        "glyphcast peaks: {} per voxel, xyz times amplitude, NaN if none",
        options.count
    );
    // A NIfTI input's own header goes into a NIfTI output (its qform and sform as they
    // were); an MRtrix input's geometry is the voxel-to-world map.
    let nifti_reference = match &image.header {
        ImageHeader::Nifti(header) => Some(&**header),
        ImageHeader::Mrtrix(_) => None,
    };
    write_image(
        &args.output,
        &ImageWrite {
            data: peaks.view().into_dyn(),
            voxel_to_world: &image.voxel_to_world,
            nifti_reference,
            description: &description,
            mrtrix_keys: &[],
        },
    )?;
    if !args.quiet {
        let found = peaks
            .lanes(ndarray::Axis(3))
            .into_iter()
            .filter(|lane| lane[0].is_finite())
            .count();
        eprintln!(
            "wrote {}: up to {} peaks in {found} voxels (band {band})",
            args.output.display(),
            options.count
        );
    }
    Ok(())
}
