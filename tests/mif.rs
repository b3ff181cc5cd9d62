//! MRtrix images (.mif, .mif.gz, .mih) on real data: DIPY's func_coef (an SH band-8
//! volume) and small_64D (a DWI) are written here as MRtrix files byte by byte, in
//! several layouts and data types, by a writer of the test's own (storage offsets from
//! the format's stride rules, not from the library), and must read back as the NIfTI
//! does: the same voxel values at the same voxel indices and the same affine. `fit`
//! reads an MRtrix DWI with or without its dw_scheme and writes .mif; bad files fail
//! with one line naming the file and the field.
use crate::common;

use common::{dipy_data, expect_failure, glyphcast, text};

use glam::{DMat3, DMat4, DVec3};
use glyphcast::scene::{GlyphKind, ShBasis};
use glyphcast_dmri::io::image::{ImageHeader, read_image};
use glyphcast_dmri::io::mif::read_mif;
use glyphcast_dmri::io::nifti::{AffineSource, VoxelToWorld};
use glyphcast_dmri::volume::{Reorientation, VolumeKind, load_mask, load_volume};
use ndarray::{Array3, ArrayD, IxDyn};
use std::io::Write;
use std::path::{Path, PathBuf};

/// A fresh folder for one test of this file.
fn fresh_dir(name: &str) -> PathBuf {
    common::fresh_dir(&format!("mif/{name}"))
}

/// How a fixture stores its values.
#[derive(Clone)]
struct Storage {
    layout: &'static str,
    datatype: &'static str,
    /// (offset, scale): stored v reads as offset + scale v.
    scaling: Option<(f64, f64)>,
}

/// The MRtrix transform rows and vox of a voxel-to-world affine: unit columns and the
/// column lengths (the format's split of the affine).
fn transform_of(affine: DMat4) -> ([[f64; 4]; 3], [f64; 3]) {
    let linear = DMat3::from_mat4(affine);
    let sizes = [
        linear.x_axis.length(),
        linear.y_axis.length(),
        linear.z_axis.length(),
    ];
    let mut rows = [[0.0; 4]; 3];
    for (r, row) in rows.iter_mut().enumerate() {
        for (c, size) in sizes.iter().enumerate() {
            row[c] = linear.col(c)[r] / size;
        }
        row[3] = affine.w_axis[r];
    }
    (rows, sizes)
}

fn encode(value: f64, storage: &Storage) -> Vec<u8> {
    let stored = match storage.scaling {
        Some((offset, scale)) => ((value - offset) / scale).round(),
        None => value,
    };
    match storage.datatype {
        "Float64LE" => stored.to_le_bytes().to_vec(),
        "Float64BE" => stored.to_be_bytes().to_vec(),
        "Float32LE" => (stored as f32).to_le_bytes().to_vec(),
        "Float32BE" => (stored as f32).to_be_bytes().to_vec(),
        "Int16LE" => (stored as i16).to_le_bytes().to_vec(),
        "UInt16BE" => (stored as u16).to_be_bytes().to_vec(),
        "Int32LE" => (stored as i32).to_le_bytes().to_vec(),
        "UInt8" => vec![stored as u8],
        other => panic!("the test writer has no {other}"),
    }
}

/// The voxel data in file order: each voxel's place from the layout (rank = order of
/// the strides, sign = direction), worked out here voxel by voxel.
fn data_bytes(values: &ArrayD<f64>, storage: &Storage) -> Vec<u8> {
    let dims = values.shape();
    let entries: Vec<(usize, bool)> = storage
        .layout
        .split(',')
        .map(|t| (t[1..].parse().unwrap(), t.starts_with('-')))
        .collect();
    let mut strides = vec![0; dims.len()];
    let mut stride = 1;
    for rank in 0..dims.len() {
        let axis = entries.iter().position(|e| e.0 == rank).unwrap();
        strides[axis] = stride;
        stride *= dims[axis];
    }
    if storage.datatype == "Bit" {
        let mut bytes = vec![0u8; values.len().div_ceil(8)];
        for (index, &v) in values.indexed_iter() {
            let place = place(&index, dims, &entries, &strides);
            if v != 0.0 {
                bytes[place / 8] |= 0x80 >> (place % 8);
            }
        }
        return bytes;
    }
    let width = encode(0.0, storage).len();
    let mut bytes = vec![0u8; values.len() * width];
    for (index, &v) in values.indexed_iter() {
        let place = place(&index, dims, &entries, &strides);
        bytes[place * width..(place + 1) * width].copy_from_slice(&encode(v, storage));
    }
    bytes
}

fn place(index: &IxDyn, dims: &[usize], entries: &[(usize, bool)], strides: &[usize]) -> usize {
    (0..dims.len())
        .map(|a| {
            let i = if entries[a].1 {
                dims[a] - 1 - index[a]
            } else {
                index[a]
            };
            i * strides[a]
        })
        .sum()
}

/// The header lines (without `file` and `END`).
fn header_lines(values: &ArrayD<f64>, affine: DMat4, storage: &Storage) -> String {
    let (rows, sizes) = transform_of(affine);
    let dims: Vec<String> = values.shape().iter().map(usize::to_string).collect();
    let mut vox: Vec<String> = sizes.iter().map(f64::to_string).collect();
    vox.resize(dims.len(), "nan".into());
    let mut text = format!(
        "mrtrix image\ndim: {}\nvox: {}\nlayout: {}\ndatatype: {}\n",
        dims.join(","),
        vox.join(","),
        storage.layout,
        storage.datatype
    );
    for row in rows {
        let row: Vec<String> = row.iter().map(f64::to_string).collect();
        text += &format!("transform: {}\n", row.join(","));
    }
    if let Some((offset, scale)) = storage.scaling {
        text += &format!("scaling: {offset},{scale}\n");
    }
    text
}

/// A single-file image: header, `file: . OFFSET`, `END`, padding, data.
fn mif_bytes(values: &ArrayD<f64>, affine: DMat4, storage: &Storage, extra: &str) -> Vec<u8> {
    let mut text = header_lines(values, affine, storage) + extra;
    // A fixed, generous offset keeps the arithmetic out of the test.
    let offset = text.len() + 64;
    text += &format!("file: . {offset}\nEND\n");
    let mut bytes = text.into_bytes();
    bytes.resize(offset, b'#');
    bytes.extend(data_bytes(values, storage));
    bytes
}

fn gzip(bytes: &[u8]) -> Vec<u8> {
    let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    encoder.write_all(bytes).unwrap();
    encoder.finish().unwrap()
}

/// Writes `values` as `name` (.mif, .mif.gz, or .mih with NAME.dat beside it).
fn write_image(
    dir: &Path,
    name: &str,
    values: &ArrayD<f64>,
    affine: DMat4,
    storage: &Storage,
    extra: &str,
) -> PathBuf {
    let path = dir.join(name);
    if name.ends_with(".mih") {
        let data_name = format!("{name}.dat");
        let text =
            header_lines(values, affine, storage) + extra + &format!("file: {data_name} 8\nEND\n");
        std::fs::write(&path, text).unwrap();
        let mut bytes = b"padding!".to_vec();
        bytes.extend(data_bytes(values, storage));
        std::fs::write(dir.join(data_name), bytes).unwrap();
    } else {
        let bytes = mif_bytes(values, affine, storage, extra);
        let bytes = if name.ends_with(".gz") {
            gzip(&bytes)
        } else {
            bytes
        };
        std::fs::write(&path, bytes).unwrap();
    }
    path
}

fn assert_affines_match(got: DMat4, want: DMat4, what: &str) {
    let diff = (got - want).to_cols_array();
    assert!(
        diff.iter().all(|d| d.abs() < 1e-9),
        "{what}: affine {got} vs {want}"
    );
}

#[test]
fn func_coef_reads_the_same_in_every_layout_and_type() {
    let dir = fresh_dir("func-coef");
    let nifti = read_image(&dipy_data("func_coef.nii.gz")).expect("reading the NIfTI");
    let values = nifti.data.clone();
    assert_eq!(values.shape(), &[2, 3, 4, 45]);
    let affine = nifti.voxel_to_world.affine;
    let cases = [
        ("plain.mif", "+0,+1,+2,+3", "Float64LE", None),
        ("volume_first.mif", "+1,+2,+3,+0", "Float32BE", None),
        ("flipped.mif.gz", "-0,+1,-2,+3", "Float32LE", None),
        ("shuffled.mih", "+2,-3,+0,+1", "Int32LE", Some((-1.0, 1e-6))),
        ("reversed.mif", "+3,+2,+1,+0", "Float64BE", None),
    ];
    for (name, layout, datatype, scaling) in cases {
        let storage = Storage {
            layout,
            datatype,
            scaling,
        };
        let path = write_image(&dir, name, &values, affine, &storage, "");
        let image = read_image(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(matches!(image.header, ImageHeader::Mrtrix(_)), "{name}");
        assert_eq!(image.data.shape(), values.shape(), "{name}");
        for (index, &want) in values.indexed_iter() {
            let got = image.data[&index];
            // Float32 and scaled integers hold the value to their own precision.
            let tolerance = match datatype {
                "Int32LE" => 1e-6,
                "Float32BE" | "Float32LE" => want.abs() * 1e-7,
                _ => 0.0,
            };
            assert!(
                (got - want).abs() <= tolerance,
                "{name} {index:?}: {got} vs {want}"
            );
        }
        assert_affines_match(image.voxel_to_world.affine, affine, name);
        // The volume the renderer gets is the NIfTI's.
        let kind = VolumeKind::Sh {
            basis: ShBasis::Tournier07,
            legacy: false,
        };
        let volume = load_volume(&path, kind).expect("as a volume");
        let reference = load_volume(&dipy_data("func_coef.nii.gz"), kind).unwrap();
        assert_eq!(volume.kind, reference.kind, "{name}");
        assert_eq!(volume.dims, reference.dims, "{name}");
    }
}

/// An affine with a rotation (not axis-aligned), a reflection and unequal voxels: a
/// voxel index goes where the format says, T diag(vox) (i, j, k) + T[:, 3].
#[test]
fn the_transform_applies_to_voxel_indices_scaled_by_vox() {
    let dir = fresh_dir("transform");
    let values = ArrayD::from_shape_fn(IxDyn(&[3, 2, 2]), |i| (i[0] + 3 * i[1] + 6 * i[2]) as f64);
    let rotation = DMat3::from_axis_angle(DVec3::new(1.0, 2.0, 2.0) / 3.0, 0.6);
    let columns = DMat3::from_cols(rotation.x_axis, -rotation.y_axis, rotation.z_axis);
    let header = "mrtrix image\ndim: 3,2,2\nvox: 1.5,2,3\nlayout: -1,+0,+2\ndatatype: UInt8\n";
    let c = |r: usize| {
        format!(
            "transform: {},{},{},{}\n",
            columns.x_axis[r],
            columns.y_axis[r],
            columns.z_axis[r],
            [5.0, -6.0, 7.0][r]
        )
    };
    let storage = Storage {
        layout: "-1,+0,+2",
        datatype: "UInt8",
        scaling: None,
    };
    let text = format!("{header}{}{}{}file: . 1000\nEND\n", c(0), c(1), c(2));
    assert!(text.len() < 1000);
    let mut bytes = text.into_bytes();
    bytes.resize(1000, 0);
    bytes.extend(data_bytes(&values, &storage));
    let path = dir.join("oblique.mif");
    std::fs::write(&path, bytes).unwrap();
    let image = read_mif(&path).expect("reading");
    assert_eq!(image.data, values);
    let index = DVec3::new(2.0, 1.0, 1.0);
    let want = columns * (index * DVec3::new(1.5, 2.0, 3.0)) + DVec3::new(5.0, -6.0, 7.0);
    let got = image.voxel_to_world.voxel_center(index);
    assert!((got - want).length() < 1e-12, "{got} vs {want}");
    let sizes = image.voxel_to_world.voxel_sizes();
    assert!((sizes - DVec3::new(1.5, 2.0, 3.0)).length() < 1e-12);
}

#[test]
fn a_bit_mask_reads_as_the_nifti_mask_does() {
    let dir = fresh_dir("bit-mask");
    let keep = Array3::from_shape_fn((2, 3, 4), |(i, j, k)| {
        ((i + 2 * j + k) % 3 == 0) as u8 as f64
    });
    let affine = DMat4::IDENTITY;
    let bits = Storage {
        layout: "-0,+2,+1",
        datatype: "Bit",
        scaling: None,
    };
    let path = write_image(
        &dir,
        "mask.mif",
        &keep.clone().into_dyn(),
        affine,
        &bits,
        "",
    );
    let mask = load_mask(&path).expect("Bit mask");
    for ((i, j, k), &v) in keep.indexed_iter() {
        assert_eq!(mask.keeps([i, j, k]), v != 0.0, "{i} {j} {k}");
    }
}

/// small_64D as an MRtrix DWI: Int16 voxels (exact), its qfac -1 affine, and optionally
/// its gradient table as dw_scheme in scanner coordinates: d_world = R d_bvec, R the
/// orthogonal factor of the affine (the bvecs are in voxel axes).
fn small_64d_mif(dir: &Path, name: &str, layout: &'static str, with_scheme: bool) -> PathBuf {
    let nifti = read_image(&dipy_data("small_64D.nii")).unwrap();
    let storage = Storage {
        layout,
        datatype: "Int16LE",
        scaling: None,
    };
    let mut extra = String::new();
    if with_scheme {
        let rotation = nifti.voxel_to_world.orthogonal_factor().unwrap();
        let numbers = |name: &str| -> Vec<f64> {
            std::fs::read_to_string(dipy_data(name))
                .unwrap()
                .split_whitespace()
                .map(|t| t.parse().unwrap())
                .collect()
        };
        let bvals = numbers("small_64D.bval");
        let bvecs = numbers("small_64D.bvec"); // 65 rows of 3
        for (volume, b) in bvals.iter().enumerate() {
            let v = DVec3::new(
                bvecs[3 * volume],
                bvecs[3 * volume + 1],
                bvecs[3 * volume + 2],
            );
            let w = if v.is_finite() {
                rotation * v
            } else {
                DVec3::ZERO
            };
            extra += &format!("dw_scheme: {},{},{},{b}\n", w.x, w.y, w.z);
        }
    }
    write_image(
        dir,
        name,
        &nifti.data,
        nifti.voxel_to_world.affine,
        &storage,
        &extra,
    )
}

fn run_ok(args: &[&str]) {
    let out = glyphcast(args);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// fit output as values (f32 as written) and affine, read by the library.
fn read_back(path: &Path) -> (ArrayD<f64>, DMat4) {
    let image = read_image(path).unwrap_or_else(|e| panic!("{e}"));
    (image.data, image.voxel_to_world.affine)
}

#[test]
fn fit_reads_mrtrix_dwis_and_writes_mrtrix_output() {
    let dir = fresh_dir("fit");
    let (bval, bvec) = (dipy_data("small_64D.bval"), dipy_data("small_64D.bvec"));
    let nifti_out = dir.join("nifti.nii");
    let sh = ["--sh", "--order", "4", "--basis", "mrtrix", "--quiet"];
    let fit = |dwi: &Path, tables: bool, output: &Path| {
        let mut args = vec!["fit", text(dwi), "-o", text(output)];
        if tables {
            args.extend(["--bval", text(&bval), "--bvec", text(&bvec)]);
        }
        args.extend(sh);
        run_ok(&args);
    };
    fit(&dipy_data("small_64D.nii"), true, &nifti_out);
    let (want, nifti_affine) = read_back(&nifti_out);
    // A .mif holds the same glyphs in scanner axes (MRtrix's frame): each voxel's series
    // turned by the affine's orthogonal factor, as `render` turns a voxel-frame volume.
    let want_world = to_scanner_axes(&want, nifti_affine);
    let scale = want.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let assert_close = |got: &ArrayD<f64>, want: &ArrayD<f64>, what: &str| {
        assert_eq!(got.shape(), want.shape(), "{what}");
        for ((index, g), w) in got.indexed_iter().zip(want.iter()) {
            assert!(
                (g - w).abs() <= 1e-5 * scale,
                "{what} {index:?}: {g} vs {w}"
            );
        }
    };
    assert!(
        want.iter()
            .zip(want_world.iter())
            .any(|(v, w)| (v - w).abs() > 1e-3 * scale),
        "small_64D's affine turns the glyphs"
    );

    // The same fit written as .mif and .mif.gz reads back in scanner axes.
    for name in ["out.mif", "out.mif.gz"] {
        let output = dir.join(name);
        fit(&dipy_data("small_64D.nii"), true, &output);
        let (got, affine) = read_back(&output);
        assert_close(&got, &want_world, name);
        assert_affines_match(affine, nifti_affine, name);
        let image = read_mif(&output).unwrap();
        let keys = &image.header.other;
        assert!(
            keys.contains(&("glyphcast_sh_basis".into(), "tournier07".into())),
            "{name}: {keys:?}"
        );
        assert_eq!(image.header.datatype.name(), "Float32LE");
    }

    // An MRtrix DWI (volume-contiguous, x flipped on file) with the FSL tables...
    let dwi = small_64d_mif(&dir, "dwi.mif", "-1,+2,+3,+0", false);
    let output = dir.join("from_mif.nii");
    fit(&dwi, true, &output);
    assert_eq!(read_back(&output).0, want, "DWI read from .mif");
    let no_table = glyphcast(&[
        "fit",
        text(&dwi),
        "-o",
        text(&dir.join("x.nii")),
        "--order",
        "2",
    ]);
    let stderr = String::from_utf8_lossy(&no_table.stderr);
    assert!(
        !no_table.status.success() && stderr.contains("--bval"),
        "{stderr}"
    );

    // ...and with its own dw_scheme in scanner coordinates, no FSL tables: the same fit
    // up to the rounding of turning the directions there and back.
    let dwi = small_64d_mif(&dir, "dwi_scheme.mif.gz", "+0,+1,+2,+3", true);
    let output = dir.join("from_scheme.mif");
    fit(&dwi, false, &output);
    let (got, affine) = read_back(&output);
    assert_affines_match(affine, nifti_affine, "dw_scheme fit");
    assert_close(&got, &want_world, "dw_scheme fit");
}

/// Band-4 tournier07 coefficients [x, y, z, 15] in the voxel axes of `affine`, turned
/// into scanner axes with the library's reorientation.
fn to_scanner_axes(voxel: &ArrayD<f64>, affine: DMat4) -> ArrayD<f64> {
    let map = VoxelToWorld::new(affine, AffineSource::Sform, "test", "affine").unwrap();
    let rotation = map.orthogonal_factor().expect("a rotation");
    let kind = GlyphKind::Sh {
        band: 4,
        basis: ShBasis::Tournier07,
        legacy: false,
    };
    let turn = Reorientation::new(rotation).for_kind(kind).unwrap();
    let mut world = voxel.clone();
    for mut glyph in world.lanes_mut(ndarray::Axis(3)) {
        let series: Vec<f64> = glyph.iter().copied().collect();
        if series.iter().all(|&c| c == 0.0) {
            continue;
        }
        for (out, value) in glyph.iter_mut().zip(turn.apply(&series).unwrap()) {
            *out = value;
        }
    }
    world
}

#[test]
fn bad_mrtrix_files_fail_cleanly_naming_file_and_field() {
    let dir = fresh_dir("bad");
    let out_dir = dir.join("out");
    std::fs::create_dir_all(&out_dir).unwrap();
    let values = ArrayD::from_shape_fn(IxDyn(&[2, 2, 2, 6]), |i| 1.0 + i[3] as f64);
    let good = Storage {
        layout: "+0,+1,+2,+3",
        datatype: "Float32LE",
        scaling: None,
    };
    let good_bytes = mif_bytes(&values, DMat4::IDENTITY, &good, "");
    let good_text = String::from_utf8_lossy(&good_bytes).into_owned();
    let header_end = good_text.find("END\n").unwrap() + 4;
    let header = &good_text[..header_end];
    // (file, header edit, word of the field): each breaks one thing.
    let with = |from: &str, to: &str| {
        let edited = header.replace(from, to);
        assert_ne!(edited, header, "{from}");
        edited
    };
    let cases: Vec<(&str, String, &str)> = vec![
        ("datatype.mif", with("Float32LE", "Float16LE"), "datatype"),
        ("complex.mif", with("Float32LE", "CFloat32LE"), "datatype"),
        ("layout.mif", with("+0,+1,+2,+3", "+0,+1,+2"), "layout"),
        (
            "layout_repeat.mif",
            with("+0,+1,+2,+3", "+0,+1,+1,+3"),
            "layout",
        ),
        // vox may leave out sizes past the third axis (as MRtrix reads it); layout may not.
        ("dim.mif", with("dim: 2,2,2,6", "dim: 2,2,2,6,1"), "layout"),
        (
            "dim_word.mif",
            with("dim: 2,2,2,6", "dim: 2,two,2,6"),
            "dim",
        ),
        ("no_end.mif", with("END\n", "\n"), "END"),
        (
            "transform.mif",
            with("transform: 0,0,1,0", "transform: 0,0,1"),
            "transform",
        ),
        (
            "transform_nan.mif",
            with("transform: 0,0,1,0", "transform: 0,0,nan,0"),
            "transform",
        ),
        (
            "singular.mif",
            with("transform: 0,0,1,0", "transform: 0,0,0,0"),
            "transform",
        ),
        (
            "scaling.mif",
            with("END\n", "scaling: 0,inf\nEND\n"),
            "scaling",
        ),
        ("magic.mif", with("mrtrix image", "nrrd image"), "line 1"),
        ("vox.mif", with("vox: 1,1,1", "vox: 1,0,1"), "vox"),
    ];
    let render = |path: &Path| {
        vec![
            "render".to_string(),
            "--sh".into(),
            text(path).into(),
            "--basis".into(),
            "mrtrix".into(),
            "-o".into(),
            text(&out_dir.join("out.png")).into(),
            "--width".into(),
            "16".into(),
        ]
    };
    for (name, header, field) in &cases {
        let path = dir.join(name);
        let mut bytes = header.clone().into_bytes();
        // Keep the data where the offset says (the edits change the header's length).
        let offset: usize = header
            .lines()
            .find_map(|l| l.strip_prefix("file: . "))
            .unwrap()
            .parse()
            .unwrap();
        bytes.resize(offset.max(bytes.len()), b'#');
        bytes.extend_from_slice(&good_bytes[good_bytes.len() - 4 * 48..]);
        std::fs::write(&path, bytes).unwrap();
        let args = render(&path);
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        expect_failure(&args, &out_dir, &[name, field]);
    }
    // Data problems: truncated, an offset inside the header, a missing .mih data file,
    // an unreadable gzip stream.
    let truncated = dir.join("truncated.mif");
    std::fs::write(&truncated, &good_bytes[..good_bytes.len() - 5]).unwrap();
    let inside = dir.join("inside.mif");
    let offset_line = header.lines().find(|l| l.starts_with("file: . ")).unwrap();
    std::fs::write(&inside, header.replace(offset_line, "file: . 20")).unwrap();
    let mih = dir.join("lonely.mih");
    let mih_header = header_lines(&values, DMat4::IDENTITY, &good) + "file: lonely.dat 0\nEND\n";
    std::fs::write(&mih, mih_header).unwrap();
    let bad_gz = dir.join("bad.mif.gz");
    std::fs::write(&bad_gz, b"not gzip at all").unwrap();
    for (path, field) in [
        (&truncated, "data"),
        (&inside, "file"),
        (&mih, "file"),
        (&bad_gz, "gzip"),
    ] {
        let args = render(path);
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let name = path.file_name().unwrap().to_str().unwrap();
        expect_failure(&args, &out_dir, &[name, field]);
    }

    // fit: a dw_scheme that does not match the volumes.
    let scheme = "dw_scheme: 0,0,0,0\n".repeat(5);
    let dwi = write_image(
        &dir,
        "short_scheme.mif",
        &values,
        DMat4::IDENTITY,
        &good,
        &scheme,
    );
    let output = out_dir.join("fit.mif");
    expect_failure(
        &["fit", text(&dwi), "-o", text(&output), "--order", "2"],
        &out_dir,
        &["short_scheme.mif", "dw_scheme", "5 rows"],
    );
}

#[test]
fn render_takes_an_mrtrix_sh_volume_with_the_mrtrix_basis() {
    let dir = fresh_dir("render");
    let nifti = read_image(&dipy_data("func_coef.nii.gz")).unwrap();
    let storage = Storage {
        layout: "+1,+2,+3,+0",
        datatype: "Float32LE",
        scaling: None,
    };
    let path = write_image(
        &dir,
        "fod.mif",
        &nifti.data,
        nifti.voxel_to_world.affine,
        &storage,
        "",
    );
    let mask = Array3::from_shape_fn((2, 3, 4), |(i, j, _)| ((i + j) % 2) as f64).into_dyn();
    let bits = Storage {
        layout: "+0,+1,+2",
        datatype: "Bit",
        scaling: None,
    };
    let mask_path = write_image(
        &dir,
        "mask.mif",
        &mask,
        nifti.voxel_to_world.affine,
        &bits,
        "",
    );
    let scenes = ["mif.json", "nii.json"].map(|n| dir.join(n));
    for (input, scene) in [
        (&path, &scenes[0]),
        (&dipy_data("func_coef.nii.gz"), &scenes[1]),
    ] {
        let png = dir.join("out.png");
        run_ok(&[
            "render",
            "--sh",
            text(input),
            "--basis",
            "mrtrix",
            "--slice",
            "axial",
            "--mask",
            text(&mask_path),
            "-o",
            text(&png),
            "--width",
            "48",
            "--save-scene",
            text(scene),
        ]);
        assert!(png.exists());
    }
    // The same glyphs from either file (float32 either way).
    let read = |p: &Path| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
    };
    assert_eq!(read(&scenes[0]), read(&scenes[1]));
}
