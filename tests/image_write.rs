//! The one image writer (`glyphcast_dmri::io::image::write_image`): each format it
//! writes (.nii, .nii.gz, .mif, .mif.gz) reads back through `read_image` and through a
//! reader that shares no code with glyphcast (the `nifti` crate for NIfTI, a parser of
//! this test's own for MRtrix) with the same values, geometry and description; a NIfTI
//! output keeps its reference header's qform and sform; bad outputs are errors naming
//! the file, with nothing written.
use crate::common;

use common::dipy_data;

use glam::{DMat3, DMat4, DVec3};
use glyphcast_dmri::io::image::{ImageHeader, ImageWrite, read_image, write_image};
use glyphcast_dmri::io::nifti::write::nifti_header_for;
use glyphcast_dmri::io::nifti::{AffineSource, NiftiHeader, VoxelToWorld};
use ndarray::{ArrayD, IxDyn, ShapeBuilder};
use nifti::{IntoNdArray, NiftiObject, ReaderOptions};
use std::io::Read;
use std::path::{Path, PathBuf};

/// A fresh folder for one test of this file.
fn fresh_dir(name: &str) -> PathBuf {
    common::fresh_dir(&format!("image_write/{name}"))
}

/// An oblique voxel-to-world map with unequal voxel sizes and a negative determinant
/// (a left-handed voxel grid, as radiological NIfTI files have).
fn oblique_affine() -> DMat4 {
    let rotation = DMat3::from_axis_angle(DVec3::new(1.0, 2.0, 0.5).normalize(), 0.4);
    let linear = rotation * DMat3::from_diagonal(DVec3::new(-2.0, 1.5, 2.5));
    let mut affine = DMat4::from_mat3(linear);
    affine.w_axis = glam::DVec4::new(-30.25, 12.5, 7.75, 1.0);
    affine
}

/// DIPY's func_coef values (SH band 8, [2, 3, 4, 45], float32 on file), and a NIfTI
/// header with the oblique map as its sform (code 2, aligned) and a different qform
/// (code 1, scanner): a header whose two transforms a writer could confuse.
fn source() -> (ArrayD<f64>, NiftiHeader, VoxelToWorld) {
    let image = read_image(&dipy_data("func_coef.nii.gz")).expect("reading func_coef");
    let map = VoxelToWorld::new(oblique_affine(), AffineSource::Sform, "test", "sform")
        .expect("an invertible affine");
    let mut header = nifti_header_for(&map);
    header.sform_code = 2;
    header.qform_code = 1;
    (header.quatern_b, header.quatern_c, header.quatern_d) = (0.1, -0.2, 0.3);
    (header.quatern_x, header.quatern_y, header.quatern_z) = (1.0, 2.0, 3.0);
    let read_back = VoxelToWorld::from_header(&header, "test").expect("the sform");
    assert!(read_back.affine.abs_diff_eq(map.affine, 1e-12));
    (image.data, header, map)
}

const DESCRIPTION: &str = "glyphcast test: two lines\nthe second";

fn assert_affine_eq(found: DMat4, expected: DMat4, tolerance: f64, what: &str) {
    assert!(
        found.abs_diff_eq(expected, tolerance),
        "{what}: affine\n{found:?}\nexpected\n{expected:?}"
    );
}

fn assert_values_eq(found: &ArrayD<f64>, expected: &ArrayD<f64>, what: &str) {
    assert_eq!(found.shape(), expected.shape(), "{what}: shape");
    for ((index, a), b) in found.indexed_iter().zip(expected.iter()) {
        assert_eq!(*a, *b as f32 as f64, "{what}: voxel {index:?}");
    }
}

/// A file's bytes, gunzipped when its name ends in `.gz`.
fn plain_bytes(path: &Path) -> Vec<u8> {
    let bytes = std::fs::read(path).expect("reading the output");
    if path.extension().is_some_and(|e| e == "gz") {
        let mut out = Vec::new();
        flate2::read::GzDecoder::new(&bytes[..])
            .read_to_end(&mut out)
            .expect("a gzip stream");
        out
    } else {
        bytes
    }
}

/// An MRtrix `.mif` read by this test alone, for what `write_image` promises: its keys
/// (every line up to `END`, in order), float32 little-endian values in layout
/// `+0,+1,...` (first axis fastest) from the `file: . OFFSET` offset, and the affine from
/// `transform` (unit columns, the offset) times `vox`.
struct PlainMif {
    keys: Vec<(String, String)>,
    values: ArrayD<f64>,
    affine: DMat4,
}

fn read_plain_mif(path: &Path) -> PlainMif {
    let bytes = plain_bytes(path);
    let end = bytes
        .windows(4)
        .position(|w| w == b"END\n")
        .expect("an END line");
    let text = std::str::from_utf8(&bytes[..end]).expect("an ASCII header");
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("mrtrix image"));
    let keys: Vec<(String, String)> = lines
        .map(|line| {
            let (key, value) = line.split_once(": ").expect("key: value");
            (key.to_string(), value.to_string())
        })
        .collect();
    let one = |key: &str| -> &str {
        let found: Vec<&str> = keys
            .iter()
            .filter(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
            .collect();
        assert_eq!(found.len(), 1, "one {key} line");
        found[0]
    };
    let numbers = |value: &str| -> Vec<f64> {
        value
            .split(',')
            .map(|n| n.trim().parse().expect("a number"))
            .collect()
    };
    let dim: Vec<usize> = one("dim").split(',').map(|n| n.parse().unwrap()).collect();
    let vox = numbers(one("vox"));
    let layout: Vec<String> = (0..dim.len()).map(|axis| format!("+{axis}")).collect();
    assert_eq!(one("layout"), layout.join(","));
    assert_eq!(one("datatype"), "Float32LE");
    let offset: usize = one("file")
        .strip_prefix(". ")
        .expect("data in this file")
        .parse()
        .unwrap();
    assert_eq!(offset % 16, 0, "the data offset is 16-byte aligned");
    let count: usize = dim.iter().product();
    assert_eq!(
        bytes.len(),
        offset + 4 * count,
        "header, data and nothing else"
    );
    let stored: Vec<f64> = bytes[offset..]
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes(c.try_into().unwrap()) as f64)
        .collect();
    // First axis fastest: Fortran order.
    let values = ArrayD::from_shape_vec(IxDyn(&dim).f(), stored).unwrap();
    let rows: Vec<Vec<f64>> = keys
        .iter()
        .filter(|(k, _)| k == "transform")
        .map(|(_, v)| numbers(v))
        .collect();
    assert_eq!(rows.len(), 3, "three transform rows");
    let mut affine = DMat4::IDENTITY;
    for (r, row) in rows.iter().enumerate() {
        for c in 0..3 {
            affine.col_mut(c)[r] = row[c] * vox[c];
        }
        affine.w_axis[r] = row[3];
    }
    PlainMif {
        keys,
        values,
        affine,
    }
}

/// Every format, written by `write_image` and read back twice: by `read_image` and by a
/// reader independent of glyphcast. Values are float32, the geometry the map's (a NIfTI
/// file's header fields exactly the reference's), the description and MRtrix keys
/// come back, and each `.gz` file holds exactly the bytes of its uncompressed twin.
#[test]
fn every_format_reads_back_through_read_image_and_an_independent_reader() {
    let dir = fresh_dir("round-trip");
    let (data, reference, map) = source();
    let keys = [("glyphcast_sh_basis", "descoteaux07 legacy".to_string())];
    let image = ImageWrite {
        data: data.view(),
        voxel_to_world: &map,
        nifti_reference: Some(&reference),
        description: DESCRIPTION,
        mrtrix_keys: &keys,
    };
    for name in [
        "out.nii",
        "out.nii.gz",
        "out.mif",
        "out.mif.gz",
        "upper.MIF",
    ] {
        let path = dir.join(name);
        write_image(&path, &image).unwrap_or_else(|err| panic!("{name}: {err}"));
        let back = read_image(&path).unwrap_or_else(|err| panic!("{name}: {err}"));
        assert_values_eq(&back.data, &data, name);
        assert_affine_eq(back.voxel_to_world.affine, map.affine, 1e-5, name);
        assert_eq!(back.description().as_deref(), Some(DESCRIPTION), "{name}");
        match &back.header {
            ImageHeader::Nifti(header) => {
                assert!(name.contains(".nii"), "{name} read as NIfTI");
                assert_eq!(header.datatype, 16, "{name}: float32");
                assert_eq!((header.sform_code, header.qform_code), (2, 1), "{name}");
            }
            ImageHeader::Mrtrix(header) => {
                assert!(!name.contains(".nii"), "{name} read as MRtrix");
                let basis = header
                    .other
                    .iter()
                    .find(|(key, _)| key == "glyphcast_sh_basis");
                assert_eq!(
                    basis.map(|(_, v)| v.as_str()),
                    Some("descoteaux07 legacy"),
                    "{name}"
                );
            }
        }
    }

    // NIfTI through the `nifti` crate: the reference's geometry fields kept (as float32),
    // the data fields set, the values in Fortran order.
    for name in ["out.nii", "out.nii.gz"] {
        let object = ReaderOptions::new()
            .read_file(dir.join(name))
            .unwrap_or_else(|err| panic!("{name}: {err}"));
        let header = object.header().clone();
        assert_eq!(&header.magic, b"n+1\0", "{name}");
        assert_eq!((header.sform_code, header.qform_code), (2, 1), "{name}");
        assert_eq!(header.datatype, 16, "{name}");
        assert_eq!(header.bitpix, 32, "{name}");
        assert_eq!(header.dim[..5], [4, 2, 3, 4, 45], "{name}");
        assert_eq!((header.scl_slope, header.scl_inter), (1.0, 0.0), "{name}");
        let rows = [header.srow_x, header.srow_y, header.srow_z];
        let expected = [reference.srow_x, reference.srow_y, reference.srow_z];
        for (row, want) in rows.iter().zip(&expected) {
            for (a, b) in row.iter().zip(want) {
                assert_eq!(*a, *b as f32, "{name}: srow");
            }
        }
        let quaternion = [
            header.quatern_b,
            header.quatern_c,
            header.quatern_d,
            header.quatern_x,
            header.quatern_y,
            header.quatern_z,
        ];
        assert_eq!(quaternion, [0.1, -0.2, 0.3, 1.0, 2.0, 3.0], "{name}: qform");
        let sizes = map.voxel_sizes();
        for axis in 0..3 {
            assert!(
                (header.pixdim[axis + 1] as f64 - sizes[axis]).abs() < 1e-5,
                "{name}: pixdim"
            );
        }
        assert_eq!(header.pixdim[0], -1.0, "{name}: qfac of a left-handed grid");
        let descrip = String::from_utf8_lossy(&header.descrip);
        assert_eq!(descrip.trim_end_matches('\0'), DESCRIPTION, "{name}");
        let values = object.into_volume().into_ndarray::<f64>().unwrap();
        assert_values_eq(&values, &data, name);
    }

    // MRtrix through this test's own parser: comments a line each, then the keys.
    for name in ["out.mif", "out.mif.gz"] {
        let mif = read_plain_mif(&dir.join(name));
        assert_values_eq(&mif.values, &data, name);
        assert_affine_eq(mif.affine, map.affine, 1e-9, name);
        let extra: Vec<(&str, &str)> = mif
            .keys
            .iter()
            .map(|(k, v)| (k.as_str(), v.as_str()))
            .filter(|(k, _)| ["comments", "glyphcast_sh_basis"].contains(k))
            .collect();
        assert_eq!(
            extra,
            [
                ("comments", "glyphcast test: two lines"),
                ("comments", "the second"),
                ("glyphcast_sh_basis", "descoteaux07 legacy"),
            ],
            "{name}"
        );
    }
    assert_eq!(
        plain_bytes(&dir.join("out.nii.gz")),
        plain_bytes(&dir.join("out.nii"))
    );
    assert_eq!(
        plain_bytes(&dir.join("out.mif.gz")),
        plain_bytes(&dir.join("out.mif"))
    );
    assert_eq!(
        plain_bytes(&dir.join("upper.MIF")),
        plain_bytes(&dir.join("out.mif"))
    );
}

/// Without a NIfTI reference (an MRtrix input), a NIfTI output holds the map as its
/// sform (code 1, scanner), no qform, voxel sizes in pixdim; MRtrix -> NIfTI -> MRtrix
/// keeps the values and the map.
#[test]
fn a_nifti_output_without_a_reference_holds_the_map_as_its_sform() {
    let dir = fresh_dir("no-reference");
    let (data, _, map) = source();
    let mif = dir.join("in.mif");
    let nii = dir.join("out.nii.gz");
    let again = dir.join("again.mif");
    fn plain<'a>(data: &'a ArrayD<f64>, map: &'a VoxelToWorld) -> ImageWrite<'a> {
        ImageWrite {
            data: data.view(),
            voxel_to_world: map,
            nifti_reference: None,
            description: "",
            mrtrix_keys: &[],
        }
    }
    write_image(&mif, &plain(&data, &map)).unwrap();
    let from_mif = read_image(&mif).unwrap();
    write_image(&nii, &plain(&from_mif.data, &from_mif.voxel_to_world)).unwrap();
    let object = ReaderOptions::new().read_file(&nii).unwrap();
    let header = object.header();
    assert_eq!((header.sform_code, header.qform_code), (1, 0));
    assert_eq!(header.xyzt_units, 2, "millimetres");
    let rows = [header.srow_x, header.srow_y, header.srow_z];
    for (r, row) in rows.iter().enumerate() {
        for (c, value) in row.iter().enumerate() {
            let want = map.affine.col(c)[r];
            assert!((*value as f64 - want).abs() < 1e-5, "srow {r} {c}");
        }
    }
    assert_eq!(header.descrip.iter().filter(|&&b| b != 0).count(), 0);
    let from_nii = read_image(&nii).unwrap();
    assert_eq!(from_nii.description(), None);
    write_image(&again, &plain(&from_nii.data, &from_nii.voxel_to_world)).unwrap();
    let back = read_image(&again).unwrap();
    assert_values_eq(&back.data, &data, "again.mif");
    assert_affine_eq(back.voxel_to_world.affine, map.affine, 1e-5, "again.mif");
    assert!(
        !read_plain_mif(&again)
            .keys
            .iter()
            .any(|(k, _)| k == "comments")
    );
}

/// Bad outputs: an error that names the file (and the field where there is one), no
/// panic, and no file left behind; an earlier file at the path stays as it was.
#[test]
fn bad_outputs_are_errors_naming_the_file_and_leave_nothing() {
    let dir = fresh_dir("bad");
    let (data, reference, map) = source();
    let good = ImageWrite {
        data: data.view(),
        voxel_to_world: &map,
        nifti_reference: Some(&reference),
        description: "",
        mrtrix_keys: &[],
    };
    let eight = ArrayD::<f64>::zeros(IxDyn(&[1; 8]));
    let bad_key = [("bad:key", "value".to_string())];
    let bad_value = [("key", "two\nlines".to_string())];
    let other = VoxelToWorld::new(DMat4::IDENTITY, AffineSource::Pixdim, "test", "pixdim").unwrap();
    let cases: Vec<(&str, ImageWrite, &[&str])> = vec![
        ("out.png", good.clone(), &["out.png", ".nii", ".mif.gz"]),
        ("out.mih", good.clone(), &["out.mih", ".mif"]),
        ("missing/out.nii", good.clone(), &["missing/out.nii"]),
        (
            "eight.nii",
            ImageWrite {
                data: eight.view(),
                ..good.clone()
            },
            &["eight.nii", "dim", "[1, 1, 1, 1, 1, 1, 1, 1]"],
        ),
        (
            "key.mif",
            ImageWrite {
                mrtrix_keys: &bad_key,
                ..good.clone()
            },
            &["key.mif", "bad:key", "colon"],
        ),
        (
            "value.mif.gz",
            ImageWrite {
                mrtrix_keys: &bad_value,
                ..good.clone()
            },
            &["value.mif.gz", "newline"],
        ),
        (
            "geometry.nii",
            ImageWrite {
                voxel_to_world: &other,
                ..good.clone()
            },
            &["geometry.nii", "affine"],
        ),
    ];
    for (name, image, words) in &cases {
        let path = dir.join(name);
        let err = write_image(&path, image).expect_err(name).to_string();
        for word in *words {
            assert!(err.contains(word), "{name}: {word:?} not in: {err}");
        }
        assert!(!path.exists(), "{name}: a file was left");
    }
    let left: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
    assert!(left.is_empty(), "temporaries left: {left:?}");

    // A failed write over an earlier file leaves that file as it was.
    let path = dir.join("kept.nii");
    write_image(&path, &good).unwrap();
    let before = std::fs::read(&path).unwrap();
    let failing = ImageWrite {
        data: eight.view(),
        ..good.clone()
    };
    assert!(write_image(&path, &failing).is_err());
    assert_eq!(std::fs::read(&path).unwrap(), before);
}
