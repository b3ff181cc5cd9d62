//! Tractograms other tools wrote (tests/data/tracks, made by tools/tracks_fixtures.py),
//! read and compared point by point with what those tools' own readers give (nibabel
//! for .trk and .tck, trx-python for .trx), in RAS+ millimetres; and hostile files made
//! from them, each refused with an error naming the file and the field.
use std::io::{Read, Write};
use std::path::{Path, PathBuf};

use glyphcast_dmri::io::tracks::{Tractogram, read_tractogram};

/// The largest difference allowed from the reference, per coordinate, in millimetres.
/// The references are float32 (the files' own type); nibabel applies the TrackVis
/// affine in float32, this reader in float64, so they differ by float32 rounding of
/// coordinates up to about 200 mm (about 1.5e-5).
const TOLERANCE_MM: f32 = 1e-4;

fn data() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/tracks")
}

struct Reference {
    points: Vec<f32>,
    offsets: Vec<u64>,
    point_values: serde_json::Map<String, serde_json::Value>,
}

fn reference(name: &str) -> Reference {
    let (shape, points) =
        glyphcast::io::npy::read_npy_f32(&data().join(format!("{name}.points.npy"))).unwrap();
    assert_eq!(shape.get(1), Some(&3), "{name}");
    let text = std::fs::read_to_string(data().join(format!("{name}.json"))).unwrap();
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    let offsets = json["offsets"]
        .as_array()
        .unwrap()
        .iter()
        .map(|o| o.as_u64().unwrap())
        .collect();
    let point_values = json["point_values"].as_object().unwrap().clone();
    Reference {
        points,
        offsets,
        point_values,
    }
}

fn compare(name: &str) -> Tractogram {
    let tractogram = read_tractogram(&data().join(name)).unwrap();
    let expected = reference(name);
    assert_eq!(tractogram.offsets, expected.offsets, "{name}: offsets");
    assert_eq!(tractogram.points.len() * 3, expected.points.len(), "{name}");
    for (index, (point, want)) in tractogram
        .points
        .iter()
        .zip(expected.points.chunks_exact(3))
        .enumerate()
    {
        for axis in 0..3 {
            assert!(
                (point[axis] - want[axis]).abs() <= TOLERANCE_MM,
                "{name}: point {index} is {point:?}, the reference {want:?}"
            );
        }
    }
    assert_eq!(
        tractogram.point_values.len(),
        expected.point_values.len(),
        "{name}: {:?}",
        tractogram
            .point_values
            .iter()
            .map(|q| &q.name)
            .collect::<Vec<_>>()
    );
    for quantity in &tractogram.point_values {
        let rows = expected.point_values[&quantity.name].as_array().unwrap();
        let want: Vec<f64> = rows
            .iter()
            .flat_map(|row| row.as_array().unwrap().iter().map(|v| v.as_f64().unwrap()))
            .collect();
        assert_eq!(
            want.len(),
            quantity.values.len(),
            "{name}: {}",
            quantity.name
        );
        for (have, want) in quantity.values.iter().zip(&want) {
            assert!(
                (f64::from(*have) - want).abs() <= 1e-5,
                "{name}: {}",
                quantity.name
            );
        }
    }
    tractogram
}

#[test]
fn dipy_trackvis_files_match_nibabel() {
    assert_eq!(compare("tracks300.trk").len(), 300);
    compare("EuDX_small_25.trk");
}

#[test]
fn nibabel_trackvis_files_big_endian_and_lps_match_nibabel() {
    let complex = compare("complex_big_endian.trk");
    let names: Vec<&str> = complex
        .point_values
        .iter()
        .map(|q| q.name.as_str())
        .collect();
    assert_eq!(names, ["colors", "fa"]);
    compare("standard.LPS.trk");
}

#[test]
fn trackvis_file_with_an_oblique_vox_to_ras_matches_nibabel() {
    // vox_to_ras permutes, flips, scales (2, 1.5, 3 mm) and rotates the voxel axes.
    let oblique = compare("tracks30_oblique.trk");
    let tck = read_tractogram(&data().join("tracks30.tck")).unwrap();
    assert_eq!(oblique.offsets, tck.offsets);
    for (a, b) in oblique.points.iter().zip(&tck.points) {
        assert!((0..3).all(|axis| (a[axis] - b[axis]).abs() <= TOLERANCE_MM));
    }
}

#[test]
fn nibabel_tck_matches_nibabel() {
    assert_eq!(compare("tracks30.tck").len(), 30);
}

#[test]
fn trx_python_files_match_trx_python() {
    let stored = compare("tracks30.trx");
    assert_eq!(stored.point_values[0].name, "along");
    // float16 positions, uint64 offsets, deflated.
    compare("tracks30_f16.trx");
    // The same streamlines in every format, to the formats' precision.
    let tck = read_tractogram(&data().join("tracks30.tck")).unwrap();
    assert_eq!(stored.points, tck.points);
}

// ---- hostile files ----------------------------------------------------------------

fn scratch() -> PathBuf {
    let folder = std::env::temp_dir().join(format!("glyphcast-tracks-{}", std::process::id()));
    std::fs::create_dir_all(&folder).unwrap();
    folder
}

/// `name` from the fixtures, its bytes edited, written into a scratch folder as
/// `new_name`; the error message of reading it.
fn refused(name: &str, new_name: &str, edit: impl FnOnce(&mut Vec<u8>)) -> String {
    let mut bytes = std::fs::read(data().join(name)).unwrap();
    edit(&mut bytes);
    let path = scratch().join(new_name);
    std::fs::write(&path, bytes).unwrap();
    let message = read_tractogram(&path).unwrap_err().to_string();
    assert!(message.contains(new_name), "{message}");
    message
}

fn replace(bytes: &mut [u8], from: &str, to: &str) {
    assert_eq!(from.len(), to.len());
    let at = bytes
        .windows(from.len())
        .position(|w| w == from.as_bytes())
        .unwrap();
    bytes[at..at + to.len()].copy_from_slice(to.as_bytes());
}

#[test]
fn tck_truncated_before_its_end_marker() {
    let message = refused("tracks30.tck", "truncated.tck", |b| {
        b.truncate(b.len() - 12)
    });
    assert!(message.contains(": data: truncated"), "{message}");
}

#[test]
fn tck_count_that_disagrees() {
    let message = refused("tracks30.tck", "count.tck", |b| {
        replace(b, "count: 0000000030", "count: 0000000031")
    });
    assert!(
        message.contains(": count: 31 streamlines declared, but the data hold 30"),
        "{message}"
    );
}

#[test]
fn tck_nan_inside_a_streamline() {
    let message = refused("tracks30.tck", "nan.tck", |b| {
        // The y of the fifth point.
        let at = 67 + 4 * 3 * 4 + 4;
        b[at..at + 4].copy_from_slice(&f32::NAN.to_le_bytes());
    });
    assert!(
        message.contains(": data: the triplet at byte 115"),
        "{message}"
    );
}

#[test]
fn tck_unknown_or_missing_datatype() {
    let message = refused("tracks30.tck", "datatype.tck", |b| {
        replace(b, "datatype: Float32LE", "datatype: Float16LE")
    });
    assert!(message.contains(": datatype: 'Float16LE'"), "{message}");
    let message = refused("tracks30.tck", "no-datatype.tck", |b| {
        replace(b, "datatype: Float32LE", "datatypo: Float32LE")
    });
    assert!(message.contains(": datatype: missing"), "{message}");
}

#[test]
fn trk_with_a_bad_magic_header_size_count_or_truncation() {
    let message = refused("tracks300.trk", "magic.trk", |b| b[4] = b'X');
    assert!(message.contains(": id_string:"), "{message}");
    let message = refused("tracks300.trk", "hdr_size.trk", |b| {
        b[996..1000].copy_from_slice(&999i32.to_le_bytes())
    });
    assert!(
        message.contains(": hdr_size: 999 (little-endian)"),
        "{message}"
    );
    let message = refused("tracks300.trk", "n_count.trk", |b| {
        b[988..992].copy_from_slice(&301i32.to_le_bytes())
    });
    assert!(
        message.contains(": n_count: 301 streamlines declared, but the data hold 300"),
        "{message}"
    );
    let message = refused("tracks300.trk", "fewer.trk", |b| {
        b[988..992].copy_from_slice(&299i32.to_le_bytes())
    });
    assert!(
        message.contains(": n_count: 299 streamlines declared, but the data hold more"),
        "{message}"
    );
    let message = refused("tracks300.trk", "truncated.trk", |b| {
        b.truncate(b.len() - 10)
    });
    assert!(
        message.contains(": data: truncated: the file ends inside streamline 299"),
        "{message}"
    );
    // Big-endian files are told by hdr_size, as nibabel tells them.
    let message = refused("complex_big_endian.trk", "big.trk", |b| {
        b.truncate(b.len() - 2)
    });
    assert!(message.contains(": data: truncated"), "{message}");
}

/// The fixture `tracks30.trx` rewritten (stored) with `edit` applied to its entries.
fn rewrite_trx(
    edit: impl Fn(&str, Vec<u8>) -> Option<(String, Vec<u8>)>,
) -> impl FnOnce(&mut Vec<u8>) {
    move |bytes: &mut Vec<u8>| {
        let mut archive = zip::ZipArchive::new(std::io::Cursor::new(bytes.clone())).unwrap();
        let mut out = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
        let options = zip::write::SimpleFileOptions::default()
            .compression_method(zip::CompressionMethod::Stored);
        for index in 0..archive.len() {
            let mut entry = archive.by_index(index).unwrap();
            let name = entry.name().unwrap().into_owned();
            let mut content = Vec::new();
            entry.read_to_end(&mut content).unwrap();
            if let Some((name, content)) = edit(&name, content) {
                out.start_file(name, options).unwrap();
                out.write_all(&content).unwrap();
            }
        }
        *bytes = out.finish().unwrap().into_inner();
    }
}

#[test]
fn trx_without_offsets_or_with_unknown_dtypes_or_sizes_that_disagree() {
    let message = refused(
        "tracks30.trx",
        "no-offsets.trx",
        rewrite_trx(|name, content| {
            (!name.starts_with("offsets")).then(|| (name.to_string(), content))
        }),
    );
    assert!(
        message.contains(": offsets: the archive has no offsets.* entry"),
        "{message}"
    );
    let message = refused(
        "tracks30.trx",
        "float128.trx",
        rewrite_trx(|name, content| Some((name.replace("float32", "float128"), content))),
    );
    assert!(
        message.contains(": positions.3.float128: unknown dtype 'float128'"),
        "{message}"
    );
    let message = refused(
        "tracks30.trx",
        "vertices.trx",
        rewrite_trx(|name, content| {
            if name != "header.json" {
                return Some((name.to_string(), content));
            }
            let mut header: serde_json::Value = serde_json::from_slice(&content).unwrap();
            let vertices = header["NB_VERTICES"].as_u64().unwrap();
            header["NB_VERTICES"] = (vertices + 1).into();
            Some((name.to_string(), serde_json::to_vec(&header).unwrap()))
        }),
    );
    assert!(
        message.contains(": positions.3.float32: 18336 bytes, but the header"),
        "{message}"
    );
    let message = refused(
        "tracks30.trx",
        "streamlines.trx",
        rewrite_trx(|name, content| {
            if name != "header.json" {
                return Some((name.to_string(), content));
            }
            let mut header: serde_json::Value = serde_json::from_slice(&content).unwrap();
            header["NB_STREAMLINES"] = 40.into();
            Some((name.to_string(), serde_json::to_vec(&header).unwrap()))
        }),
    );
    assert!(message.contains(": offsets.uint32: 124 bytes"), "{message}");
}
