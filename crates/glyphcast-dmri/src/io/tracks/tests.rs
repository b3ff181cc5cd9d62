//! The readers on small files written here byte by byte; the files other tools wrote
//! are the integration tests' (`tests/tracks.rs`).
use std::path::PathBuf;

use super::*;

fn scratch(name: &str, bytes: &[u8]) -> PathBuf {
    let folder = std::env::temp_dir().join(format!("glyphcast-tracks-unit-{}", std::process::id()));
    std::fs::create_dir_all(&folder).unwrap();
    let path = folder.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

/// A `.tck` with the header text given and float64 big-endian triplets.
fn tck_f64_be(keys: &str, triplets: &[[f64; 3]]) -> Vec<u8> {
    let mut header =
        format!("mrtrix tracks\n{keys}datatype: Float64BE\nfile: . 100\nEND\n").into_bytes();
    header.resize(100, 0);
    for triplet in triplets {
        for value in triplet {
            header.extend_from_slice(&value.to_be_bytes());
        }
    }
    header
}

#[test]
fn tck_in_float64_big_endian() {
    let nan = [f64::NAN; 3];
    let end = [f64::INFINITY; 3];
    let bytes = tck_f64_be(
        "count: 2\n",
        &[
            [1.0, 2.0, 3.0],
            [4.0, 5.0, 6.5],
            nan,
            nan,
            [-1.0, 0.0, 1e-3],
            nan,
            end,
        ],
    );
    let tractogram = read_tractogram(&scratch("f64be.tck", &bytes)).unwrap();
    assert_eq!(tractogram.offsets, [0, 2]);
    assert_eq!(
        tractogram.points,
        [[1.0, 2.0, 3.0], [4.0, 5.0, 6.5], [-1.0, 0.0, 1e-3]]
    );
}

#[test]
fn tck_points_must_not_be_partly_nan_or_infinite() {
    for bad in [[1.0, f64::NAN, 3.0], [f64::INFINITY, 1.0, 1.0]] {
        let bytes = tck_f64_be("", &[[0.0; 3], bad, [f64::NAN; 3], [f64::INFINITY; 3]]);
        let err = read_tractogram(&scratch("partial.tck", &bytes))
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("partial.tck: data:") && err.contains("byte 124"),
            "{err}"
        );
    }
}

#[test]
fn tck_streamline_without_its_nan_before_the_end_is_refused() {
    let bytes = tck_f64_be("", &[[0.0; 3], [f64::INFINITY; 3]]);
    let err = read_tractogram(&scratch("open.tck", &bytes))
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("open.tck: data:") && err.contains("no NaN triplet"),
        "{err}"
    );
}

#[test]
fn unknown_endings_are_refused_naming_the_file() {
    let err = read_tractogram(Path::new("bundle.vtk"))
        .unwrap_err()
        .to_string();
    assert!(err.contains("bundle.vtk") && err.contains(".tck"), "{err}");
    assert_eq!(TrackFormat::of(Path::new("A.TRK")), Some(TrackFormat::Trk));
}

#[test]
fn half_precision_decodes_exactly() {
    assert_eq!(f16_to_f32(0x3c00), 1.0);
    assert_eq!(f16_to_f32(0xc000), -2.0);
    assert_eq!(f16_to_f32(0x7bff), 65504.0);
    assert_eq!(f16_to_f32(0x0001), 2f32.powi(-24));
    assert_eq!(f16_to_f32(0x8001), -(2f32.powi(-24)));
    assert_eq!(f16_to_f32(0x3555), 0.333_251_95);
    assert!(f16_to_f32(0x7c00).is_infinite() && f16_to_f32(0x7e00).is_nan());
}

#[test]
fn tck_written_reads_back_point_for_point() {
    let mut tractogram = Tractogram::default();
    for (start, count) in [(0.0f32, 3usize), (10.0, 1), (-5.5, 40)] {
        tractogram.offsets.push(tractogram.points.len() as u64);
        tractogram
            .points
            .extend((0..count).map(|k| [start + k as f32, 0.25 * k as f32, -1e3 + start]));
    }
    let bytes = tck::encode_tck(&tractogram);
    let header = tck::TckHeader::parse(&bytes, "written.tck").unwrap();
    assert_eq!(header.count, Some(3));
    assert_eq!(header.offset % 4, 0);
    assert!(header.offset as usize >= header.length, "{header:?}");
    let path = scratch("written.tck", &[]);
    tck::write_tck(&tractogram, &path).unwrap();
    assert_eq!(read_tractogram(&path).unwrap(), tractogram);
}
