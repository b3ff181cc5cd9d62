//! `glyphcast fit` on real DWI data (DIPY's small_64D: 10x10x10 voxels, one b=0 volume
//! and 64 directions at b ~ 1000): the order-2 fit is classic DTI, higher orders fit
//! the measured ADCs better, the SH fit reproduces the signal to within its noise, the
//! output is a NIfTI with the input's geometry, and bad input fails cleanly.
use glam::DVec3;
use glyphcast::glyph::polynomial::GlyphPolynomial;
use glyphcast::glyph::{Symmetry, TensorLayout};
use glyphcast::scene::ShBasis;
use glyphcast_dmri::fit::voxel::SIGNAL_FLOOR;
use glyphcast_dmri::fit::{FitFiles, FitInputs, FitModel, VoxelFitter, fit};
use nalgebra::{DMatrix, DVector};
use ndarray::{Array4, Ix4};
use nifti::{IntoNdArray, NiftiObject, ReaderOptions};
use std::path::{Path, PathBuf};

fn data(name: &str) -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .join("tests/data/dipy")
        .join(name)
}

fn files() -> FitFiles {
    FitFiles {
        dwi: data("small_64D.nii"),
        bval: Some(data("small_64D.bval")),
        bvec: Some(data("small_64D.bvec")),
        mask: None,
    }
}

fn fitted(model: FitModel) -> Array4<f64> {
    let inputs = FitInputs::load(files()).expect("loading small_64D");
    fit(&inputs, &model, &mut |_| {}).expect("fitting")
}

/// The data as the test reads it, without the library: signal [x, y, z, volume],
/// b-values and unit directions of the weighted volumes.
struct Measured {
    signal: Array4<f64>,
    bvals: Vec<f64>,
    directions: Vec<DVec3>,
}

impl Measured {
    fn read() -> Self {
        let object = ReaderOptions::new()
            .read_file(data("small_64D.nii"))
            .unwrap();
        let signal = object.into_volume().into_ndarray::<f64>().unwrap();
        let signal = signal.into_dimensionality::<Ix4>().unwrap();
        let numbers = |name: &str| -> Vec<f64> {
            std::fs::read_to_string(data(name))
                .unwrap()
                .split_whitespace()
                .map(|t| t.parse().unwrap())
                .collect()
        };
        let bvals = numbers("small_64D.bval");
        let bvecs = numbers("small_64D.bvec"); // 65 rows of 3, the first `nan nan nan`
        assert_eq!(bvals.len(), 65);
        assert_eq!(bvals[0], 0.0, "volume 0 is the only b=0 volume");
        assert!(bvals[1..].iter().all(|&b| b > 900.0));
        let directions = (1..65)
            .map(|v| DVec3::new(bvecs[3 * v], bvecs[3 * v + 1], bvecs[3 * v + 2]).normalize())
            .collect();
        Measured {
            signal,
            bvals: bvals[1..].to_vec(),
            directions,
        }
    }

    fn voxels(&self) -> impl Iterator<Item = [usize; 3]> + use<> {
        let s = self.signal.shape().to_vec();
        (0..s[2]).flat_map(move |z| {
            let s = s.clone();
            (0..s[1]).flat_map(move |y| (0..s[0]).map(move |x| [x, y, z]))
        })
    }

    /// S/S0 at the weighted volumes, clamped as documented; None where S0 <= 0.
    fn ratio(&self, [x, y, z]: [usize; 3]) -> Option<Vec<f64>> {
        let s0 = self.signal[[x, y, z, 0]];
        (s0 > 0.0).then(|| {
            (1..65)
                .map(|v| self.signal[[x, y, z, v]].max(SIGNAL_FLOOR * s0) / s0)
                .collect()
        })
    }

    fn adc(&self, voxel: [usize; 3]) -> Option<Vec<f64>> {
        let ratio = self.ratio(voxel)?;
        Some(
            ratio
                .iter()
                .zip(&self.bvals)
                .map(|(r, b)| -r.ln() / b)
                .collect(),
        )
    }
}

fn coefficients(volume: &Array4<f64>, [x, y, z]: [usize; 3]) -> Vec<f64> {
    volume.slice(ndarray::s![x, y, z, ..]).to_vec()
}

#[test]
fn order_two_fit_equals_classic_dti_least_squares() {
    let ours = fitted(FitModel::Tensor { order: 2 });
    let measured = Measured::read();
    // Classic DTI design: ADC = [gx^2, gy^2, gz^2, 2gxgy, 2gxgz, 2gygz] . [Dxx, Dyy,
    // Dzz, Dxy, Dxz, Dyz], solved by the normal equations and Cholesky (the library
    // uses the SVD pseudo-inverse of its monomial design).
    let rows: Vec<f64> = measured
        .directions
        .iter()
        .flat_map(|g| {
            let (x, y, z) = (g.x, g.y, g.z);
            [x * x, y * y, z * z, 2.0 * x * y, 2.0 * x * z, 2.0 * y * z]
        })
        .collect();
    let a = DMatrix::from_row_slice(64, 6, &rows);
    let normal = (a.transpose() * &a)
        .cholesky()
        .expect("A^T A is positive definite");
    let (mut compared, mut left_out) = (0, 0);
    for voxel in measured.voxels() {
        let got = coefficients(&ours, voxel);
        let Some(adc) = measured.adc(voxel) else {
            assert!(got.iter().all(|&c| c == 0.0), "left-out voxel {voxel:?}");
            left_out += 1;
            continue;
        };
        let d = normal.solve(&(a.transpose() * DVector::from_vec(adc)));
        // Scene order xx, xy, xz, yy, yz, zz.
        let want = [d[0], d[3], d[4], d[1], d[5], d[2]];
        let scale = want.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (g, w) in got.iter().zip(want) {
            assert!(
                (g - w).abs() <= 1e-6 * scale,
                "voxel {voxel:?}: {got:?} vs {want:?}"
            );
        }
        compared += 1;
    }
    eprintln!("compared {compared} voxels, {left_out} left out (S0 <= 0)");
    assert!(compared > 900);
}

/// sum over voxels and directions of (D(g_i) - ADC_i)^2, D evaluated independently of
/// the library's design matrix.
fn adc_residual(order: u32, measured: &Measured) -> f64 {
    let volume = fitted(FitModel::Tensor { order });
    let layout = TensorLayout {
        order,
        symmetry: Symmetry::Symmetric,
    };
    measured
        .voxels()
        .filter_map(|voxel| {
            let adc = measured.adc(voxel)?;
            let f = GlyphPolynomial::from_tensor(layout, &coefficients(&volume, voxel)).unwrap();
            let sum: f64 = measured
                .directions
                .iter()
                .zip(&adc)
                .map(|(&g, a)| (f.eval(g) - a).powi(2))
                .sum();
            Some(sum)
        })
        .sum()
}

#[test]
fn higher_orders_reproduce_the_adcs_better() {
    let measured = Measured::read();
    let residuals: Vec<f64> = [2, 4, 6]
        .iter()
        .map(|&order| adc_residual(order, &measured))
        .collect();
    eprintln!("ADC residual sums, orders 2, 4, 6: {residuals:?}");
    assert!(residuals[1] < residuals[0], "{residuals:?}");
    assert!(residuals[2] < residuals[1], "{residuals:?}");
    assert!(residuals[2] > 0.0);
}

#[test]
fn sh_fit_matches_the_signal_to_within_noise() {
    let measured = Measured::read();
    // Noise of S/S0 from pairs of nearest directions: S(g) - S(h) has variance 2 sigma^2
    // plus the (positive) true signal difference, so sigma_nn^2 = mean((S(g) - S(h))^2)
    // / 2 over every direction and its nearest neighbour (antipodes identified) is an
    // upper estimate of the noise.
    let neighbours: Vec<usize> = (0..64)
        .map(|i| {
            let g = measured.directions[i];
            (0..64)
                .filter(|&j| j != i)
                .max_by(|&j, &k| {
                    let dj = g.dot(measured.directions[j]).abs();
                    dj.total_cmp(&g.dot(measured.directions[k]).abs())
                })
                .unwrap()
        })
        .collect();
    let inputs = FitInputs::load(files()).unwrap();
    for band in [4, 6, 8] {
        let model = FitModel::Sh {
            band,
            basis: ShBasis::Descoteaux07,
            legacy: false,
            lambda: 0.006,
        };
        let volume = fit(&inputs, &model, &mut |_| {}).unwrap();
        let fitter = VoxelFitter::new(&inputs, &model).unwrap();
        let (mut residual, mut noise, mut count) = (0.0, 0.0, 0usize);
        for voxel in measured.voxels() {
            let Some(ratio) = measured.ratio(voxel) else {
                continue;
            };
            let predicted = fitter
                .fitted_signal(&coefficients(&volume, voxel))
                .expect("an SH fit predicts the signal");
            residual += ratio
                .iter()
                .zip(&predicted)
                .map(|(r, p)| (r - p).powi(2))
                .sum::<f64>();
            noise += (0..64)
                .map(|i| (ratio[i] - ratio[neighbours[i]]).powi(2))
                .sum::<f64>()
                / 2.0;
            count += 64;
        }
        let (rms, sigma) = (
            (residual / count as f64).sqrt(),
            (noise / count as f64).sqrt(),
        );
        let dof = (1.0 - model.coefficient_count() as f64 / 64.0).sqrt();
        eprintln!(
            "band {band}: RMS residual {rms:.4} of S0, nearest-neighbour noise {sigma:.4}, sqrt((m-p)/m) = {dof:.3}"
        );
        // Within the noise: below the (upper) noise estimate. And not fitting the noise
        // itself: an unregularised fit of p coefficients to m samples leaves
        // sigma sqrt((m - p) / m) (0.55 sigma at band 8); regularisation leaves more.
        // Measured: 0.86, 0.79, 0.75 sigma_nn for bands 4, 6, 8.
        assert!(rms < sigma, "band {band}: {rms} vs {sigma}");
        assert!(rms > 0.5 * sigma, "band {band}: {rms} vs {sigma}");
    }
}

// ---- The command line: written NIfTI files, and bad input.

fn glyphcast(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_glyphcast"))
        .args(args)
        .output()
        .expect("running glyphcast")
}

fn fresh_dir(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("fit")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("creating a test folder");
    dir
}

fn path_str(path: &Path) -> &str {
    path.to_str().expect("utf-8 path")
}

/// `fit` on small_64D with `extra` arguments, writing `output`.
fn run_fit(output: &Path, extra: &[&str]) -> std::process::Output {
    let (dwi, bval, bvec) = (
        data("small_64D.nii"),
        data("small_64D.bval"),
        data("small_64D.bvec"),
    );
    let mut args = vec![
        "fit",
        path_str(&dwi),
        "--bval",
        path_str(&bval),
        "--bvec",
        path_str(&bvec),
        "-o",
        path_str(output),
    ];
    args.extend(extra);
    glyphcast(&args)
}

fn read_nifti(path: &Path) -> (nifti::NiftiHeader, ndarray::ArrayD<f64>) {
    let object = ReaderOptions::new().read_file(path).expect("reading NIfTI");
    let header = object.header().clone();
    (header, object.into_volume().into_ndarray::<f64>().unwrap())
}

/// Writes `data` as NIfTI with small_64D's header (geometry), for masks and bad inputs.
fn write_nifti<D: ndarray::Dimension + ndarray::RemoveAxis>(
    path: &Path,
    values: &ndarray::Array<f32, D>,
) {
    let (header, _) = read_nifti(&data("small_64D.nii"));
    nifti::writer::WriterOptions::new(path)
        .reference_header(&header)
        .write_nifti(values)
        .expect("writing a test NIfTI");
}

#[test]
fn written_nifti_reads_back_with_the_inputs_geometry() {
    let dir = fresh_dir("round-trip");
    let (input, _) = read_nifti(&data("small_64D.nii"));
    let cases = [
        (
            "tensor4.nii.gz",
            FitModel::Tensor { order: 4 },
            vec!["--order", "4", "--quiet"],
        ),
        (
            "sh6.nii",
            FitModel::Sh {
                band: 6,
                basis: ShBasis::Tournier07,
                legacy: true,
                lambda: 0.01,
            },
            vec!["--order", "6", "--sh", "--legacy", "--lambda", "0.01"],
        ),
    ];
    for (name, model, args) in cases {
        let output = dir.join(name);
        let run = run_fit(&output, &args);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert!(run.status.success(), "{name}: {stderr}");
        let (header, values) = read_nifti(&output);
        let count = model.coefficient_count();
        assert_eq!(values.shape(), &[10, 10, 10, count], "{name}");
        assert_eq!(header.datatype, 16, "{name}: float32");
        assert_eq!(
            (header.srow_x, header.srow_y, header.srow_z),
            (input.srow_x, input.srow_y, input.srow_z),
            "{name}: sform"
        );
        assert_eq!(
            (header.sform_code, header.qform_code),
            (input.sform_code, input.qform_code)
        );
        let quaternion = |h: &nifti::NiftiHeader| {
            [
                h.quatern_b,
                h.quatern_c,
                h.quatern_d,
                h.quatern_x,
                h.quatern_y,
                h.quatern_z,
            ]
        };
        assert_eq!(quaternion(&header), quaternion(&input), "{name}: qform");
        assert_eq!(
            header.pixdim[..4],
            input.pixdim[..4],
            "{name}: qfac and voxel size"
        );
        let want = fitted(model);
        for (got, want) in values.iter().zip(want.iter()) {
            assert_eq!(*got, *want as f32 as f64, "{name}");
        }
        let entries: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
        assert!(entries.len() <= 2, "no temporary files left: {entries:?}");
    }
}

#[test]
fn mask_limits_the_fit_to_its_voxels() {
    let dir = fresh_dir("mask");
    // NaN counts as zero, as in every mask glyphcast reads (render's too).
    let mask = ndarray::Array3::<f32>::from_shape_fn((10, 10, 10), |(x, y, z)| {
        if x == 0 && y > 2 {
            f32::NAN
        } else if x < 5 && y > 2 && z != 7 {
            1.0
        } else {
            0.0
        }
    });
    let mask_path = dir.join("mask.nii.gz");
    write_nifti(&mask_path, &mask);
    let output = dir.join("masked.nii.gz");
    let run = run_fit(&output, &["--order", "2", "--mask", path_str(&mask_path)]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let (_, values) = read_nifti(&output);
    let full = fitted(FitModel::Tensor { order: 2 });
    for ((index, got), want) in values.indexed_iter().zip(full.iter()) {
        let value = mask[[index[0], index[1], index[2]]];
        let inside = value != 0.0 && !value.is_nan();
        let expected = if inside { *want as f32 as f64 } else { 0.0 };
        assert_eq!(*got, expected, "{index:?}");
    }
}

/// Runs `fit` with the given inputs and options; expects one `error:` line naming
/// `culprit`, a non-zero exit, and nothing in the output folder.
fn expect_failure(case: &str, inputs: [&Path; 3], options: &[&str], culprit: &str) {
    let out_dir = fresh_dir(&format!("bad-{case}-out"));
    let output = out_dir.join("out.nii.gz");
    let mut args = vec![
        "fit",
        path_str(inputs[0]),
        "--bval",
        path_str(inputs[1]),
        "--bvec",
        path_str(inputs[2]),
        "-o",
        path_str(&output),
    ];
    args.extend(options);
    let run = glyphcast(&args);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success(), "{case}: expected failure:\n{stderr}");
    assert!(!stderr.contains("panicked"), "{case}: panic:\n{stderr}");
    let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(
        errors.len(),
        1,
        "{case}: one error line expected:\n{stderr}"
    );
    assert!(
        errors[0].contains(culprit),
        "{case}: '{culprit}' not named: {}",
        errors[0]
    );
    let leftovers: Vec<_> = std::fs::read_dir(&out_dir).unwrap().collect();
    assert!(
        leftovers.is_empty(),
        "{case}: output left behind: {leftovers:?}"
    );
    eprintln!("{case}: {}", errors[0]);
}

#[test]
fn bad_inputs_fail_cleanly_naming_the_file() {
    let dir = fresh_dir("bad-inputs");
    let write = |name: &str, text: &str| {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        path
    };
    let (dwi, bval, bvec) = (
        data("small_64D.nii"),
        data("small_64D.bval"),
        data("small_64D.bvec"),
    );
    let bval_text = std::fs::read_to_string(&bval).unwrap();
    let bvec_text = std::fs::read_to_string(&bvec).unwrap();
    let values: Vec<&str> = bval_text.split_whitespace().collect();
    let bvec_rows: Vec<&str> = bvec_text.lines().collect();

    let short_bval = write("short.bval", &values[..64].join(" "));
    let short_bvec = write("short.bvec", &bvec_rows[..64].join("\n"));
    let word_bval = write("word.bval", &format!("0 oops {}", values[2..].join(" ")));
    let ragged_bvec = write(
        "ragged.bvec",
        &format!("{}\n1 0\n{}", bvec_rows[0], bvec_rows[2..].join("\n")),
    );
    let no_b0 = write("no_b0.bval", &format!("1000 {}", values[1..].join(" ")));
    let x_first = write(
        "x_first.bvec",
        &format!("1 0 0\n{}", bvec_rows[1..].join("\n")),
    );
    let zero_bvec = write(
        "zero.bvec",
        &format!("{}\n0 0 0\n{}", bvec_rows[0], bvec_rows[2..].join("\n")),
    );
    let volume_3d = dir.join("volume3d.nii");
    write_nifti(&volume_3d, &ndarray::Array3::<f32>::ones((10, 10, 10)));
    let small_mask = dir.join("small_mask.nii.gz");
    write_nifti(&small_mask, &ndarray::Array3::<f32>::ones((10, 10, 9)));
    // The DWI's shape, 50 mm away: another grid.
    let shifted_mask = dir.join("shifted_mask.nii");
    let (mut shifted, _) = read_nifti(&data("small_64D.nii"));
    shifted.srow_x[3] += 50.0;
    shifted.quatern_x += 50.0;
    nifti::writer::WriterOptions::new(&shifted_mask)
        .reference_header(&shifted)
        .write_nifti(&ndarray::Array3::<f32>::ones((10, 10, 10)))
        .expect("writing a test NIfTI");
    let missing = dir.join("missing.nii");
    let garbage = write("garbage.nii", "this is not a NIfTI file\n");

    let name = |p: &Path| p.file_name().unwrap().to_str().unwrap().to_owned();
    let good = [dwi.as_path(), bval.as_path(), bvec.as_path()];
    let cases: Vec<(&str, [&Path; 3], Vec<&str>, String)> = vec![
        (
            "bval-count",
            [&dwi, &short_bval, &bvec],
            vec!["--order", "2"],
            name(&short_bval),
        ),
        (
            "bvec-count",
            [&dwi, &bval, &short_bvec],
            vec!["--order", "2"],
            name(&short_bvec),
        ),
        (
            "bval-word",
            [&dwi, &word_bval, &bvec],
            vec!["--order", "2"],
            name(&word_bval),
        ),
        (
            "bvec-ragged",
            [&dwi, &bval, &ragged_bvec],
            vec!["--order", "2"],
            name(&ragged_bvec),
        ),
        (
            "no-b0",
            [&dwi, &no_b0, &x_first],
            vec!["--order", "2"],
            name(&no_b0),
        ),
        (
            "nan-direction",
            [&dwi, &no_b0, &bvec],
            vec!["--order", "2"],
            name(&bvec),
        ),
        (
            "zero-direction",
            [&dwi, &bval, &zero_bvec],
            vec!["--order", "2"],
            name(&zero_bvec),
        ),
        (
            "dwi-3d",
            [&volume_3d, &bval, &bvec],
            vec!["--order", "2"],
            name(&volume_3d),
        ),
        (
            "dwi-missing",
            [&missing, &bval, &bvec],
            vec!["--order", "2"],
            name(&missing),
        ),
        (
            "dwi-garbage",
            [&garbage, &bval, &bvec],
            vec!["--order", "2"],
            name(&garbage),
        ),
        (
            "mask-shape",
            good,
            vec!["--order", "2", "--mask", path_str(&small_mask)],
            name(&small_mask),
        ),
        (
            "mask-affine",
            good,
            vec!["--order", "2", "--mask", path_str(&shifted_mask)],
            name(&shifted_mask),
        ),
        // 91 unknowns of an order-12 tensor, 64 directions.
        (
            "too-few-directions",
            good,
            vec!["--order", "12"],
            name(&bvec),
        ),
        (
            "sh-too-few-directions",
            good,
            vec!["--order", "12", "--sh"],
            name(&bvec),
        ),
        (
            "odd-order-sh",
            good,
            vec!["--order", "3", "--sh"],
            "--order".into(),
        ),
        (
            "odd-order-tensor",
            good,
            vec!["--order", "5"],
            "--order".into(),
        ),
        (
            "unknown-basis",
            good,
            vec!["--order", "4", "--sh", "--basis", "fsl"],
            "--basis".into(),
        ),
        (
            "negative-lambda",
            good,
            vec!["--order", "4", "--sh", "--lambda=-1"],
            "--lambda".into(),
        ),
    ];
    for (case, inputs, options, culprit) in &cases {
        expect_failure(case, *inputs, options, culprit);
    }
    // An output that is not NIfTI is refused before anything is fitted.
    let out_dir = fresh_dir("bad-output-name");
    let run = run_fit(&out_dir.join("out.png"), &["--order", "2"]);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(
        run.status.code() == Some(2)
            && stderr.contains("-o/--output")
            && stderr.contains("out.png")
            && stderr.contains(".nii.gz"),
        "{stderr}"
    );
    assert_eq!(std::fs::read_dir(&out_dir).unwrap().count(), 0);
}
