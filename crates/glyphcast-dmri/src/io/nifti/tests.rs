//! The reader on files built here byte by byte or by the writer: every data type in both
//! byte orders, scaling, vox_offset, and broken gzip streams (NIfTI-2 and the CLI:
//! tests/nifti_input.rs).
use std::io::Write;

use flate2::Compression;
use flate2::write::GzEncoder;
use ndarray::{ArrayD, Dimension, IxDyn, ShapeBuilder};

use super::write::{encode_nifti1, nifti1_bytes};
use super::*;
use crate::io::datatype::{DataType, Number};

fn sample(shape: &[usize]) -> ArrayD<f64> {
    ArrayD::from_shape_fn(IxDyn(shape), |i| {
        i.slice()
            .iter()
            .enumerate()
            .map(|(a, &x)| (x * (a + 2)) as f64)
            .sum::<f64>()
            - 3.5
    })
}

fn gzip(bytes: &[u8]) -> Vec<u8> {
    let mut encoder = GzEncoder::new(Vec::new(), Compression::default());
    encoder.write_all(bytes).unwrap();
    encoder.finish().unwrap()
}

fn error(bytes: &[u8], name: &str) -> String {
    read_nifti_bytes(bytes, name).unwrap_err().to_string()
}

/// A NIfTI-1 file of `header` followed by `data` at vox_offset (at 352 when vox_offset
/// is not a valid place).
fn nifti1_file(header: &NiftiHeader, data: &[u8]) -> Vec<u8> {
    let mut bytes = encode_nifti1(header).to_vec();
    bytes.resize((header.vox_offset as usize).max(352), 0);
    bytes.extend_from_slice(data);
    bytes
}

/// `values` stored as `datatype`, little- or big-endian.
fn stored(values: &[f64], number: Number, big_endian: bool) -> Vec<u8> {
    let mut out = Vec::new();
    for &v in values {
        let mut word: Vec<u8> = match number {
            Number::U8 => vec![v as u8],
            Number::I8 => (v as i8).to_le_bytes().to_vec(),
            Number::I16 => (v as i16).to_le_bytes().to_vec(),
            Number::U16 => (v as u16).to_le_bytes().to_vec(),
            Number::I32 => (v as i32).to_le_bytes().to_vec(),
            Number::U32 => (v as u32).to_le_bytes().to_vec(),
            Number::I64 => (v as i64).to_le_bytes().to_vec(),
            Number::U64 => (v as u64).to_le_bytes().to_vec(),
            Number::F32 => (v as f32).to_le_bytes().to_vec(),
            Number::F64 => v.to_le_bytes().to_vec(),
            Number::Bit => unreachable!("NIfTI has no packed bit type glyphcast reads"),
        };
        if big_endian {
            word.reverse();
        }
        out.extend(word);
    }
    out
}

/// Swaps every multi-byte field of a little-endian NIfTI-1 header to big-endian.
fn swap_nifti1(header: &mut [u8]) {
    let mut swap = |at: usize, size: usize, count: usize| {
        for i in 0..count {
            header[at + i * size..at + (i + 1) * size].reverse();
        }
    };
    swap(0, 4, 1);
    swap(32, 4, 1);
    swap(36, 2, 1);
    swap(40, 2, 8);
    swap(56, 4, 3);
    swap(68, 2, 4);
    swap(76, 4, 11);
    swap(120, 2, 1);
    swap(124, 4, 4);
    swap(140, 4, 2);
    swap(252, 2, 2);
    swap(256, 4, 18);
}

#[test]
fn writer_output_reads_back_identically() {
    let data = sample(&[3, 4, 2, 5]);
    let mut reference = NiftiHeader {
        sform_code: 1,
        srow_x: [0.0, -3.0, 0.0, 10.0],
        srow_y: [2.0, 0.0, 0.0, -20.0],
        srow_z: [0.0, 0.0, 4.0, 30.5],
        pixdim: [-1.0, 2.0, 3.0, 4.0, 1.5, 1.0, 1.0, 1.0],
        qform_code: 2,
        quatern_d: 0.5,
        xyzt_units: 10,
        ..NiftiHeader::default()
    };
    reference.set_description("fit: sh order 8 (tournier07)");
    for (gz, name) in [(false, "w.nii"), (true, "w.nii.gz")] {
        let bytes = nifti1_bytes(&reference, data.view(), gz, name).unwrap();
        let image = read_nifti_bytes(&bytes, name).unwrap();
        assert_eq!(image.data, data, "{name}");
        assert!(image.data.is_standard_layout() || image.data.t().is_standard_layout());
        let h = &image.header;
        assert_eq!(h.dim, [4, 3, 4, 2, 5, 1, 1, 1]);
        assert_eq!((h.datatype, h.bitpix, h.vox_offset), (16, 32, 352.0));
        assert_eq!(
            (h.srow_x, h.srow_y, h.srow_z),
            (reference.srow_x, reference.srow_y, reference.srow_z)
        );
        assert_eq!(h.pixdim, reference.pixdim);
        assert_eq!((h.qform_code, h.sform_code, h.quatern_d), (2, 1, 0.5));
        assert_eq!(h.xyzt_units, 10);
        assert_eq!(h.description(), "fit: sh order 8 (tournier07)");
        assert_eq!(h.magic, b"n+1\0");
    }
    let plain = nifti1_bytes(&reference, data.view(), false, "w.nii").unwrap();
    assert_eq!(plain.len(), 352 + 4 * data.len());
}

#[test]
fn every_real_type_reads_in_both_byte_orders() {
    let values = [0.0, 1.0, 7.0, 100.0, 2.0, 55.0];
    let signed = [0.0, -1.0, 7.0, -100.0, 2.0, 55.0];
    let types = [
        (Number::U8, 2, &values),
        (Number::I8, 256, &signed),
        (Number::I16, 4, &signed),
        (Number::U16, 512, &values),
        (Number::I32, 8, &signed),
        (Number::U32, 768, &values),
        (Number::I64, 1024, &signed),
        (Number::U64, 1280, &values),
        (Number::F32, 16, &signed),
        (Number::F64, 64, &signed),
    ];
    for (number, code, values) in types {
        let width = DataType {
            number,
            big_endian: false,
        }
        .width();
        let header = NiftiHeader {
            dim: [3, 3, 2, 1, 1, 1, 1, 1],
            datatype: code,
            bitpix: 8 * width as i16,
            ..NiftiHeader::default()
        };
        for big_endian in [false, true] {
            let mut bytes = nifti1_file(&header, &stored(values, number, big_endian));
            if big_endian {
                swap_nifti1(&mut bytes[..348]);
            }
            let image = read_nifti_bytes(&bytes, "t.nii").unwrap();
            assert_eq!(image.header.big_endian, big_endian);
            let want = ArrayD::from_shape_vec(IxDyn(&[3, 2, 1]).f(), values.to_vec()).unwrap();
            assert_eq!(image.data, want, "{number:?} big-endian {big_endian}");
        }
    }
}

#[test]
fn refused_types_name_datatype_and_what_they_are() {
    for (code, bitpix, word) in [
        (32, 64, "complex64"),
        (128, 24, "RGB24"),
        (2304, 32, "RGBA32"),
        (1792, 128, "complex128"),
        (1536, 128, "float128"),
        (1, 1, "binary"),
        (0, 0, "0 is not"),
        (3, 8, "3 is not"),
    ] {
        let header = NiftiHeader {
            datatype: code,
            bitpix,
            ..NiftiHeader::default()
        };
        let err = error(&nifti1_file(&header, &[0; 64]), "c.nii");
        assert!(
            err.contains("c.nii: datatype:") && err.contains(word),
            "{err}"
        );
    }
    let header = NiftiHeader {
        bitpix: 64,
        ..NiftiHeader::default()
    };
    let err = error(&nifti1_file(&header, &[0; 8]), "b.nii");
    assert!(
        err.contains("bitpix") && err.contains("64") && err.contains("float32"),
        "{err}"
    );
}

#[test]
fn scaling_follows_the_standard_and_bad_values_are_named() {
    let data = stored(&[1.0, 2.0], Number::I16, false);
    let read = |slope: f64, inter: f64| {
        let header = NiftiHeader {
            dim: [1, 2, 1, 1, 1, 1, 1, 1],
            datatype: 4,
            bitpix: 16,
            scl_slope: slope,
            scl_inter: inter,
            ..NiftiHeader::default()
        };
        read_nifti_bytes(&nifti1_file(&header, &data), "s.nii")
    };
    let values = |r: Result<NiftiImage>| r.unwrap().data.iter().copied().collect::<Vec<_>>();
    assert_eq!(values(read(2.0, -1.0)), [1.0, 3.0]);
    assert_eq!(values(read(0.0, 5.0)), [1.0, 2.0], "slope 0: no scaling");
    assert_eq!(values(read(1.0, 0.0)), [1.0, 2.0]);
    for (slope, inter, field) in [
        (f64::NAN, 0.0, "scl_slope"),
        (f64::INFINITY, 0.0, "scl_slope"),
        (1.0, f64::NAN, "scl_inter"),
    ] {
        let err = read(slope, inter).unwrap_err().to_string();
        assert!(err.contains(&format!("s.nii: {field}:")), "{err}");
    }
}

#[test]
fn header_problems_name_the_field_and_show_the_numbers() {
    let cases: [(NiftiHeader, &str, &[&str]); 5] = [
        (
            NiftiHeader {
                dim: [9, 2, 2, 2, 1, 1, 1, 1],
                ..NiftiHeader::default()
            },
            "dim",
            &["dim[0] = 9", "[9, 2, 2, 2"],
        ),
        (
            NiftiHeader {
                dim: [4, 2, 0, 2, 3, 1, 1, 1],
                ..NiftiHeader::default()
            },
            "dim",
            &["dim[2] = 0", "[4, 2, 0, 2, 3"],
        ),
        (
            NiftiHeader {
                dim: [3, 2, -7, 2, 1, 1, 1, 1],
                ..NiftiHeader::default()
            },
            "dim",
            &["dim[2] = -7"],
        ),
        (
            NiftiHeader {
                vox_offset: 100.0,
                ..NiftiHeader::default()
            },
            "vox_offset",
            &["100", "352"],
        ),
        (
            NiftiHeader {
                vox_offset: 352.5,
                ..NiftiHeader::default()
            },
            "vox_offset",
            &["352.5"],
        ),
    ];
    for (header, field, words) in cases {
        let err = error(&nifti1_file(&header, &[0; 64]), "h.nii");
        assert!(err.contains(&format!("h.nii: {field}:")), "{err}");
        for word in words {
            assert!(err.contains(word), "{word}: {err}");
        }
    }
}

#[test]
fn vox_offset_is_honoured_without_extensions() {
    let data = stored(&[1.0, 2.0, 3.0, 4.0], Number::F32, false);
    let at = |offset: f64| {
        let header = NiftiHeader {
            dim: [2, 2, 2, 1, 1, 1, 1, 1],
            vox_offset: offset,
            ..NiftiHeader::default()
        };
        let mut bytes = nifti1_file(&header, &data);
        // Garbage where a reader ignoring vox_offset would look.
        bytes[352..header.vox_offset as usize].fill(0x7f);
        bytes
    };
    let near = read_nifti_bytes(&at(352.0), "a.nii").unwrap();
    let far = read_nifti_bytes(&at(1024.0), "b.nii").unwrap();
    assert_eq!(near.data, far.data);
    assert_eq!(
        far.data.t().iter().copied().collect::<Vec<_>>(),
        [1.0, 2.0, 3.0, 4.0]
    );
    let far_gz = read_nifti_bytes(&gzip(&at(1024.0)), "b.nii.gz").unwrap();
    assert_eq!(far_gz.data, near.data);
    // An offset past the end of the file.
    let mut beyond = at(1024.0);
    beyond.truncate(900);
    let err = error(&beyond, "c.nii");
    assert!(
        err.contains("c.nii: vox_offset:") && err.contains("900"),
        "{err}"
    );
    let err = error(&gzip(&beyond), "c.nii.gz");
    assert!(err.contains("c.nii.gz: vox_offset:"), "{err}");
}

#[test]
fn broken_gzip_streams_are_errors_naming_the_file() {
    let image = nifti1_bytes(
        &NiftiHeader::default(),
        sample(&[4, 4, 4]).view(),
        false,
        "g",
    )
    .unwrap();
    let good = gzip(&image);
    assert!(read_nifti_bytes(&good, "g.nii.gz").is_ok());
    let n = good.len();
    let mut bad_crc = good.clone();
    bad_crc[n - 8] ^= 0x01;
    let mut bad_size = good.clone();
    bad_size[n - 1] ^= 0x01;
    let no_trailer = good[..n - 8].to_vec();
    let mut corrupt = good.clone();
    for byte in &mut corrupt[20..40] {
        *byte ^= 0x5a;
    }
    let mut garbage = good.clone();
    garbage.extend_from_slice(b"trailing garbage");
    let truncated = good[..n / 2].to_vec();
    for (bytes, what) in [
        (bad_crc, "bad CRC"),
        (bad_size, "bad length"),
        (no_trailer, "no trailer"),
        (corrupt, "corrupt deflate"),
        (garbage, "trailing garbage"),
        (truncated, "truncated"),
    ] {
        let err = error(&bytes, "g.nii.gz");
        assert!(err.starts_with("g.nii.gz: "), "{what}: {err}");
        eprintln!("{what}: {err}");
    }
    // Two members, as gzip(1) writes when files are concatenated, are one stream.
    let mut two = gzip(&image[..500]);
    two.extend(gzip(&image[500..]));
    assert_eq!(
        read_nifti_bytes(&two, "g.nii.gz").unwrap().data,
        sample(&[4, 4, 4])
    );
}

#[test]
fn declared_sizes_are_checked_before_allocating() {
    let huge = NiftiHeader {
        dim: [3, 4096, 4096, 4096, 1, 1, 1, 1],
        datatype: 64,
        bitpix: 64,
        ..NiftiHeader::default()
    };
    let bytes = nifti1_file(&huge, &[0; 64]);
    let start = std::time::Instant::now();
    let err = error(&gzip(&bytes), "huge.nii.gz");
    assert!(
        err.contains("huge.nii.gz: data: truncated") && err.contains("4096x4096x4096"),
        "{err}"
    );
    let err = error(&bytes, "huge.nii");
    assert!(
        err.contains("huge.nii: data: truncated") && err.contains("only 64 follow"),
        "{err}"
    );
    assert!(start.elapsed().as_secs_f64() < 1.0);
    // Overflowing products.
    let overflow = NiftiHeader {
        dim: [7, 32767, 32767, 32767, 32767, 32767, 32767, 32767],
        ..NiftiHeader::default()
    };
    let err = error(&nifti1_file(&overflow, &[0; 64]), "o.nii");
    assert!(
        err.contains("o.nii: dim:") && err.contains("too many"),
        "{err}"
    );
}

#[test]
fn non_nifti_files_are_named_as_such() {
    let err = error(b"tiny", "t.nii");
    assert!(err.contains("t.nii: sizeof_hdr: not a NIfTI file"), "{err}");
    let err = error(&gzip(&[0u8; 400]), "t.nii");
    assert!(
        err.contains("t.nii: sizeof_hdr:") && err.contains("gzip"),
        "{err}"
    );
    let err = error(&[0u8; 2], "t.nii");
    assert!(err.contains("ends after 2 bytes"), "{err}");
    let mut analyze = nifti1_file(&NiftiHeader::default(), &[0; 4]);
    analyze[344..348].fill(0);
    let err = error(&analyze, "a.nii");
    assert!(
        err.contains("a.nii: magic: Analyze 7.5, not NIfTI"),
        "{err}"
    );
    let mut pair_magic = nifti1_file(&NiftiHeader::default(), &[0; 4]);
    pair_magic[344..348].copy_from_slice(b"ni1\0");
    let err = error(&pair_magic, "p.nii");
    assert!(
        err.contains("p.nii: magic:") && err.contains(".hdr"),
        "{err}"
    );
}
