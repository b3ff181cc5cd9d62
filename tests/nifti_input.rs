//! NIfTI input through the real binary: types that are not one real number per voxel,
//! vox_offset, NIfTI-2 in both byte orders, broken gzip streams, truncated and huge
//! declared volumes, bad header fields and Analyze files. Every failure must be exit 1
//! with one error line naming the file and the field, and no output written.
//!
//! The files are func_coef.nii.gz (DIPY, band 8 SH) as our writer writes it, edited or
//! rebuilt byte by byte here (`common::nifti`). Rendering runs on lavapipe:
//! `VK_DRIVER_FILES=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json cargo test -p glyphcast-cli --test integration nifti_input::`.
use crate::common;

use common::nifti::{gzip, nifti2_bytes, set_f32, set_i16, with_vox_offset};
use common::{expect_failure, glyphcast};
use glyphcast_dmri::io::image::read_image;
use glyphcast_dmri::io::nifti::read_nifti;
use glyphcast_dmri::io::nifti::write::nifti1_bytes;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

fn data(name: &str) -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .join("tests/data/dipy")
        .join(name)
}

fn text(path: &Path) -> &str {
    path.to_str().expect("utf-8 path")
}

/// A fresh folder with `in` and `out` inside.
fn folders(name: &str) -> (PathBuf, PathBuf) {
    let root = common::output_dir().join("nifti_input").join(name);
    let _ = std::fs::remove_dir_all(&root);
    let (inputs, outputs) = (root.join("in"), root.join("out"));
    std::fs::create_dir_all(&inputs).expect("inputs folder");
    std::fs::create_dir_all(&outputs).expect("outputs folder");
    (inputs, outputs)
}

/// func_coef.nii.gz as an uncompressed NIfTI-1 file written by our writer (data at 352).
fn func_coef_nii() -> Vec<u8> {
    let image = read_nifti(&data("func_coef.nii.gz")).expect("reading func_coef");
    nifti1_bytes(&image.header, image.data.view(), false, "func_coef.nii").expect("encoding")
}

/// The arguments of each command that reads `file` as NIfTI, writing into `out`:
/// `render --sh`, `render --tensor`, `render --mask`, `fit` and `fit --mask`.
fn every_reader(file: &str, out: &Path) -> Vec<Vec<String>> {
    let png = text(&out.join("out.png")).to_string();
    let fitted = text(&out.join("fit.nii.gz")).to_string();
    let (coef, dwi) = (data("func_coef.nii.gz"), data("small_64D.nii"));
    let (bval, bvec) = (data("small_64D.bval"), data("small_64D.bvec"));
    let render = |input: &[&str]| {
        let mut args = vec!["render"];
        args.extend(input);
        args.extend(["-o", &png, "--width", "16", "--height", "16"]);
        args.into_iter().map(String::from).collect::<Vec<_>>()
    };
    let fit = |input: &str, extra: &[&str]| {
        let mut args = vec!["fit", input, "--bval", text(&bval), "--bvec", text(&bvec)];
        args.extend(extra);
        args.extend(["--order", "2", "-o", &fitted]);
        args.into_iter().map(String::from).collect::<Vec<_>>()
    };
    vec![
        render(&["--sh", file, "--basis", "tournier07", "--legacy"]),
        render(&["--tensor", file, "--order", "2"]),
        render(&[
            "--sh",
            text(&coef),
            "--basis",
            "tournier07",
            "--legacy",
            "--mask",
            file,
        ]),
        fit(file, &[]),
        fit(text(&dwi), &["--mask", file]),
    ]
}

#[test]
fn complex_and_colour_data_fail_every_reading_path_naming_datatype() {
    let (inputs, outputs) = folders("refused-types");
    let base = func_coef_nii();
    let voxels = (base.len() - 352) / 4;
    for (code, bitpix, name) in [
        (32, 64, "complex64"),
        (128, 24, "RGB24"),
        (2304, 32, "RGBA32"),
    ] {
        let mut bytes = base[..352].to_vec();
        set_i16(&mut bytes, 70, code);
        set_i16(&mut bytes, 72, bitpix);
        bytes.resize(352 + voxels * bitpix as usize / 8, 1);
        let path = inputs.join(format!("{name}.nii"));
        std::fs::write(&path, &bytes).expect("writing");
        let file = text(&path);
        for args in every_reader(file, &outputs) {
            let args: Vec<&str> = args.iter().map(String::as_str).collect();
            expect_failure(&args, &outputs, &[file, "datatype", name]);
        }
    }
}

/// `render --sh FILE` into `out`; the depth map's bytes.
fn depth_map(file: &Path, out: &Path) -> Vec<u8> {
    let npy = out.join(format!(
        "{}.npy",
        file.file_name().unwrap().to_string_lossy()
    ));
    let run = glyphcast(&[
        "render",
        "--sh",
        text(file),
        "--basis",
        "tournier07",
        "--legacy",
        "-o",
        text(&out.join("out.png")),
        "--depth-out",
        text(&npy),
        "--width",
        "48",
        "--height",
        "48",
    ]);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{}: {stderr}", file.display());
    std::fs::read(&npy).expect("reading the depth map")
}

#[test]
fn the_same_data_at_another_offset_or_as_nifti2_renders_the_same_depth_map() {
    let (inputs, outputs) = folders("same-data");
    let base = func_coef_nii();
    let image = read_nifti(&data("func_coef.nii.gz")).expect("reading func_coef");
    let files = [
        ("at352.nii", base.clone()),
        ("at1024.nii", with_vox_offset(&base, 1024)),
        ("at1024.nii.gz", gzip(&with_vox_offset(&base, 1024))),
        ("v2le.nii", nifti2_bytes(&image.header, &image.data, false)),
        (
            "v2be.nii.gz",
            gzip(&nifti2_bytes(&image.header, &image.data, true)),
        ),
    ];
    let mut maps = Vec::new();
    for (name, bytes) in &files {
        let path = inputs.join(name);
        std::fs::write(&path, bytes).expect("writing");
        let read = read_image(&path).expect(name);
        assert_eq!(read.data, image.data, "{name}: voxels");
        assert_eq!(read.voxel_to_world, image.voxel_to_world, "{name}: affine");
        assert_eq!(read.description(), None, "{name}");
        maps.push((name, depth_map(&path, &outputs)));
    }
    let hits = maps[0]
        .1
        .chunks_exact(4)
        .skip(32)
        .filter(|w| !f32::from_le_bytes([w[0], w[1], w[2], w[3]]).is_nan())
        .count();
    assert!(
        hits > 100,
        "the reference render shows glyphs ({hits} pixels)"
    );
    for (name, map) in &maps[1..] {
        assert!(
            map == &maps[0].1,
            "{name}: depth map differs from the NIfTI-1 one at 352"
        );
    }
}

#[test]
fn broken_files_fail_with_exit_1_naming_file_and_field() {
    let (inputs, outputs) = folders("broken");
    let base = func_coef_nii();
    let packed = gzip(&base);
    let n = packed.len();
    let edit = |f: &dyn Fn(&mut Vec<u8>)| {
        let mut bytes = base.clone();
        f(&mut bytes);
        bytes
    };
    let mut bad_crc = packed.clone();
    bad_crc[n - 8] ^= 0x10;
    let mut corrupt = packed.clone();
    corrupt[n / 2..n / 2 + 16]
        .iter_mut()
        .for_each(|b| *b ^= 0xa5);
    let mut analyze = base.clone();
    analyze[344..348].fill(0);
    let cases: Vec<(&str, Vec<u8>, Vec<&str>)> = vec![
        ("bad_crc.nii.gz", bad_crc, vec!["gzip", "checksum"]),
        (
            "no_trailer.nii.gz",
            packed[..n - 8].to_vec(),
            vec!["gzip", "trailer"],
        ),
        ("corrupt.nii.gz", corrupt, vec!["gzip", "corrupt"]),
        (
            "truncated.nii",
            base[..base.len() - 10].to_vec(),
            vec!["data: truncated"],
        ),
        (
            // One more volume declared than the data holds.
            "short.nii.gz",
            gzip(&edit(&|b| set_i16(b, 48, 46))),
            vec!["data: truncated", "2x3x4x46"],
        ),
        (
            "nan_slope.nii",
            edit(&|b| set_f32(b, 112, f32::NAN)),
            vec!["scl_slope", "NaN"],
        ),
        (
            "inf_inter.nii",
            edit(&|b| set_f32(b, 116, f32::INFINITY)),
            vec!["scl_inter", "inf"],
        ),
        (
            "zero_dim.nii",
            edit(&|b| set_i16(b, 44, 0)),
            vec!["dim", "dim[2] = 0", "[4, 2, 0, 4, 45"],
        ),
        (
            "rank9.nii",
            edit(&|b| set_i16(b, 40, 9)),
            vec!["dim", "dim[0] = 9"],
        ),
        (
            "far_offset.nii",
            edit(&|b| set_f32(b, 108, 1e6)),
            vec!["vox_offset", "1000000"],
        ),
        (
            "analyze.nii",
            analyze.clone(),
            vec!["magic", "Analyze 7.5, not NIfTI"],
        ),
        (
            "analyze.hdr",
            analyze[..348].to_vec(),
            vec!["magic", "Analyze 7.5, not NIfTI"],
        ),
        ("pair.img", base[352..].to_vec(), vec!["file", ".hdr"]),
    ];
    std::fs::write(inputs.join("analyze.img"), &base[352..]).expect("writing");
    for (name, bytes, words) in &cases {
        let path = inputs.join(name);
        std::fs::write(&path, bytes).expect("writing");
        let args = &every_reader(text(&path), &outputs)[0];
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let mut words = words.clone();
        words.push(text(&path));
        expect_failure(&args, &outputs, &words);
    }
}

#[test]
fn a_tiny_file_declaring_a_huge_volume_is_refused_without_allocating_it() {
    let (inputs, outputs) = folders("huge");
    let mut header = func_coef_nii()[..352].to_vec();
    for (axis, length) in [(1, 4096), (2, 4096), (3, 4096), (4, 1)] {
        set_i16(&mut header, 40 + 2 * axis, length);
    }
    set_i16(&mut header, 40, 3);
    set_i16(&mut header, 70, 64);
    set_i16(&mut header, 72, 64);
    header.resize(352 + 4096, 0);
    let compressed = inputs.join("huge.nii.gz");
    std::fs::write(&compressed, gzip(&header)).expect("writing");
    let plain = inputs.join("huge.nii");
    std::fs::write(&plain, &header).expect("writing");
    for path in [&compressed, &plain] {
        for args in every_reader(text(path), &outputs).into_iter().step_by(3) {
            // 1 GiB of address space: allocating the 512 GiB volume (or a third of it)
            // would fail, and an abort would show as a signal, not exit 1.
            let line = "ulimit -v 1048576; exec \"$0\" \"$@\"";
            let started = Instant::now();
            let run = Command::new("sh")
                .arg("-c")
                .arg(line)
                .arg(env!("CARGO_BIN_EXE_glyphcast"))
                .args(&args)
                .output()
                .expect("running glyphcast");
            let seconds = started.elapsed().as_secs_f64();
            let stderr = String::from_utf8_lossy(&run.stderr);
            assert_eq!(run.status.code(), Some(1), "{args:?}: {stderr}");
            assert!(
                stderr.contains("4096x4096x4096") && stderr.contains(text(path)),
                "{stderr}"
            );
            assert!(seconds < 3.0, "{args:?}: took {seconds} s");
        }
    }
    // Volumes that fit in their files but not under the memory cap (NIfTI, and MRtrix
    // plain and compressed).
    let corpus =
        Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("tests/fuzz/corpus/mif");
    for path in [
        data("func_coef.nii.gz"),
        corpus.join("func_coef.mif"),
        corpus.join("dwi_corner.mif.gz"),
    ] {
        let run = Command::new(env!("CARGO_BIN_EXE_glyphcast"))
            .args(&every_reader(text(&path), &outputs)[0])
            .env("GLYPHCAST_MAX_INPUT_BYTES", "1000")
            .output()
            .expect("running glyphcast");
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(1), "{stderr}");
        assert!(
            stderr.contains("GLYPHCAST_MAX_INPUT_BYTES")
                && stderr.contains(&format!("{}: dim", text(&path))),
            "{stderr}"
        );
    }
}

#[test]
fn a_hdr_img_pair_reads_like_the_single_file() {
    let (inputs, _) = folders("pair");
    let base = func_coef_nii();
    let mut header = base[..348].to_vec();
    header[344..348].copy_from_slice(b"ni1\0");
    set_f32(&mut header, 108, 0.0);
    let single = read_nifti(&data("func_coef.nii.gz")).expect("reading func_coef");
    for (hdr, img, header_bytes, image_bytes) in [
        ("p.hdr", "p.img", header.clone(), base[352..].to_vec()),
        ("q.hdr.gz", "q.img.gz", gzip(&header), gzip(&base[352..])),
    ] {
        std::fs::write(inputs.join(hdr), header_bytes).expect("writing");
        std::fs::write(inputs.join(img), image_bytes).expect("writing");
        let pair = read_nifti(&inputs.join(hdr)).expect(hdr);
        assert_eq!(pair.data, single.data, "{hdr}");
        assert_eq!(pair.voxel_to_world, single.voxel_to_world, "{hdr}");
        let err = read_nifti(&inputs.join(img)).unwrap_err().to_string();
        assert!(err.contains(img) && err.contains(".hdr"), "{err}");
    }
    std::fs::remove_file(inputs.join("p.img")).expect("removing");
    let err = read_nifti(&inputs.join("p.hdr")).unwrap_err().to_string();
    assert!(err.contains("p.hdr") && err.contains("p.img"), "{err}");
}

/// Our writer's files read back identically with our reader and with the `nifti` crate.
#[test]
fn written_files_read_back_identically() {
    use nifti::{IntoNdArray, NiftiObject, ReaderOptions};
    let (inputs, _) = folders("round-trip");
    let image = read_nifti(&data("func_coef.nii.gz")).expect("reading func_coef");
    for (name, gz) in [("w.nii", false), ("w.nii.gz", true)] {
        let path = inputs.join(name);
        let bytes = nifti1_bytes(&image.header, image.data.view(), gz, name).expect("encoding");
        std::fs::write(&path, bytes).expect("writing");
        let ours = read_nifti(&path).expect(name);
        assert_eq!(ours.data, image.data, "{name}");
        assert_eq!(ours.voxel_to_world, image.voxel_to_world, "{name}");
        let theirs = ReaderOptions::new().read_file(&path).expect(name);
        let h = theirs.header().clone();
        assert_eq!(
            theirs.into_volume().into_ndarray::<f64>().expect(name),
            image.data
        );
        assert_eq!(h.srow_x.map(f64::from), image.header.srow_x, "{name}");
        assert_eq!(h.pixdim.map(f64::from), image.header.pixdim, "{name}");
        assert_eq!(
            (i32::from(h.sform_code), i32::from(h.qform_code)),
            (image.header.sform_code, image.header.qform_code),
            "{name}"
        );
    }
}
