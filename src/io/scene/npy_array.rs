//! The NumPy arrays a scene file may name in place of its longest lists (`centers`,
//! `scales`, `coeffs`: docs/scene-format.md, "Arrays beside the scene"), so that a
//! million glyphs never pass through JSON text. Reading goes through the `npyz` crate
//! (every `.npy` version, either byte order, C or Fortran order); glyphcast writes
//! version 1.0, little-endian float64 in C order, the layout `numpy.save` gives a
//! C-contiguous float64 array.
use std::io::BufReader;
use std::path::Path;

/// A float array read from a `.npy` file, as rows along its first axis.
pub(super) struct NpyArray {
    /// The array's shape.
    pub shape: Vec<usize>,
    /// The values, a row per index of the first axis.
    pub rows: Vec<Vec<f64>>,
}

/// Why an array file cannot be read, for a message that names the file and field.
#[derive(Debug)]
pub(super) struct ArrayError(String);

impl std::fmt::Display for ArrayError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

/// Reads a float32 or float64 `.npy` file as rows of `columns` values (the last axis,
/// or one value per row for a 1-d array), streaming a C-order file straight into its
/// rows so that no second copy of a large array is held.
pub(super) fn read_rows(path: &Path, columns: usize) -> std::result::Result<NpyArray, ArrayError> {
    // The header's shape is checked against the file's length before anything is sized
    // from it: a shape the data does not fill is a damaged or mislabelled file.
    check_data_length(path)?;
    let file = std::fs::File::open(path).map_err(|e| ArrayError(e.to_string()))?;
    let npy = npyz::NpyFile::new(BufReader::with_capacity(1 << 20, file))
        .map_err(|e| ArrayError(format!("not a NumPy .npy file ({e})")))?;
    let shape: Vec<usize> = npy.shape().iter().map(|&d| d as usize).collect();
    let fortran = npy.order() == npyz::Order::Fortran && shape.len() > 1;
    let dtype = npy.dtype().descr();
    let columns = columns.max(1);
    let values: Box<dyn Iterator<Item = std::io::Result<f64>>> = match npy.try_data::<f64>() {
        Ok(reader) => Box::new(reader),
        Err(npy) => match npy.try_data::<f32>() {
            Ok(reader) => Box::new(reader.map(|v| v.map(f64::from))),
            Err(_) => {
                return Err(ArrayError(format!(
                    "dtype {dtype} is not supported; expected float32 or float64"
                )));
            }
        },
    };
    let truncated = |e: std::io::Error| ArrayError(format!("the data ends early ({e})"));
    let count: usize = shape.iter().product();
    let rows = if fortran {
        // Column after column: gathered whole, then turned into rows.
        let flat: Vec<f64> = values.collect::<std::io::Result<_>>().map_err(truncated)?;
        let n = shape[0];
        let width = count / n.max(1);
        (0..n)
            .map(|r| (0..width).map(|c| flat[c * n + r]).collect())
            .collect()
    } else {
        let mut rows = Vec::with_capacity(count / columns);
        let mut row = Vec::with_capacity(columns);
        for value in values {
            row.push(value.map_err(truncated)?);
            if row.len() == columns {
                rows.push(std::mem::replace(&mut row, Vec::with_capacity(columns)));
            }
        }
        if !row.is_empty() {
            rows.push(row);
        }
        rows
    };
    Ok(NpyArray { shape, rows })
}

/// Refuses a `.npy` file whose data after the header is not exactly its header's shape
/// of its dtype's items: a shape too large for the file (or for any file), data that
/// ends early, or bytes after the array. Read from the header's text, before the header
/// is interpreted, so that no size is ever computed from an unchecked shape. Headers
/// that are not `.npy` headers are left to the reader to refuse.
fn check_data_length(path: &Path) -> std::result::Result<(), ArrayError> {
    let io = |e: std::io::Error| ArrayError(e.to_string());
    let mut file = std::fs::File::open(path).map_err(io)?;
    let file_length = file.metadata().map_err(io)?.len();
    let mut start = [0u8; 12];
    if std::io::Read::read_exact(&mut file, &mut start).is_err() || &start[..6] != b"\x93NUMPY" {
        return Ok(());
    }
    // Version (2 bytes), then the header's length: 2 bytes in version 1, 4 in 2 and 3.
    let (header_start, header_length) = match start[6] {
        1 => (10, u64::from(u16::from_le_bytes([start[8], start[9]]))),
        _ => (
            12,
            u64::from(u32::from_le_bytes([
                start[8], start[9], start[10], start[11],
            ])),
        ),
    };
    let mut header = vec![0u8; header_length.min(1 << 20) as usize];
    std::io::Seek::seek(&mut file, std::io::SeekFrom::Start(header_start)).map_err(io)?;
    if std::io::Read::read_exact(&mut file, &mut header).is_err() {
        return Ok(());
    }
    let header = String::from_utf8_lossy(&header);
    let entry = |key: &str| {
        let at = header.find(&format!("'{key}'"))? + key.len() + 2;
        Some(
            header[at..]
                .trim_start()
                .strip_prefix(':')?
                .trim_start()
                .to_string(),
        )
    };
    let (Some(descr), Some(shape)) = (entry("descr"), entry("shape")) else {
        return Ok(());
    };
    // 'descr': '<f8' -> 8 bytes an item.
    let item: Option<u64> = descr
        .strip_prefix('\'')
        .and_then(|d| d.split('\'').next())
        .map(|d| d.trim_start_matches(['<', '>', '=', '|']))
        .and_then(|d| d.get(1..))
        .and_then(|size| size.parse().ok());
    let dims: Option<Vec<u64>> = shape
        .strip_prefix('(')
        .and_then(|s| s.split(')').next())
        .map(|s| {
            s.split(',')
                .map(str::trim)
                .filter(|d| !d.is_empty())
                .map(|d| d.parse().ok())
                .collect()
        })
        .and_then(|dims: Vec<Option<u64>>| dims.into_iter().collect());
    let (Some(item), Some(dims)) = (item, dims) else {
        return Ok(());
    };
    let expected = dims.iter().try_fold(item, |bytes, &d| bytes.checked_mul(d));
    let found = file_length.saturating_sub(header_start + header_length);
    let described = format!(
        "shape {dims:?} of {}",
        descr.split(',').next().unwrap_or("")
    );
    match expected {
        Some(bytes) if bytes == found => Ok(()),
        Some(bytes) if bytes > found => Err(ArrayError(format!(
            "the data ends early: {described} needs {bytes} bytes after the header, the file \
             holds {found}"
        ))),
        Some(bytes) => Err(ArrayError(format!(
            "{} bytes follow the array ({described}, {bytes} bytes): not a file numpy.save \
             wrote",
            found - bytes
        ))),
        None => Err(ArrayError(format!("{described} is larger than any file"))),
    }
}

/// A `.npy` file (version 1.0) of little-endian float64 values in C order of `shape`.
pub(crate) fn encode_f64(shape: &[usize], values: impl Iterator<Item = f64>) -> Vec<u8> {
    let dims: Vec<String> = shape.iter().map(usize::to_string).collect();
    let dims = match dims.len() {
        1 => format!("{},", dims[0]),
        _ => dims.join(", "),
    };
    let mut header = format!("{{'descr': '<f8', 'fortran_order': False, 'shape': ({dims}), }}");
    // Magic (6), version (2), header length (2), then the header padded with spaces and
    // ended by a newline so that the data starts at a multiple of 64 bytes.
    let unpadded = 10 + header.len() + 1;
    header.extend(std::iter::repeat_n(
        ' ',
        unpadded.next_multiple_of(64) - unpadded,
    ));
    header.push('\n');
    let mut bytes = Vec::with_capacity(10 + header.len() + 8 * shape.iter().product::<usize>());
    bytes.extend_from_slice(b"\x93NUMPY\x01\x00");
    bytes.extend_from_slice(&(header.len() as u16).to_le_bytes());
    bytes.extend_from_slice(header.as_bytes());
    for value in values {
        bytes.extend_from_slice(&value.to_le_bytes());
    }
    bytes
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A header whose shape the data does not fill exactly is refused before anything
    /// is sized from it: a huge shape, data that ends early, float64 data labelled
    /// float32 (twice the bytes), bytes after the array.
    #[test]
    fn a_shape_the_data_does_not_fill_is_refused() {
        let dir = std::env::temp_dir().join(format!("glyphcast-npy-length-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        // A version 1.0 file with this header dictionary and these data bytes.
        let npy = |dict: &str, data: &[u8]| {
            let mut header = dict.to_string();
            let unpadded = 10 + header.len() + 1;
            header.extend(std::iter::repeat_n(
                ' ',
                unpadded.next_multiple_of(64) - unpadded,
            ));
            header.push('\n');
            let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
            bytes.extend_from_slice(&(header.len() as u16).to_le_bytes());
            bytes.extend_from_slice(header.as_bytes());
            bytes.extend_from_slice(data);
            bytes
        };
        let dict = |descr: &str, shape: &str| {
            format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': ({shape}), }}")
        };
        let data: Vec<u8> = (0..6).flat_map(|v| f64::from(v).to_le_bytes()).collect();
        let cases = [
            (
                "huge",
                npy(&dict("<f8", "99999999999, 2"), &data),
                "ends early",
            ),
            (
                "overflow",
                npy(&dict("<f8", "9223372036854775807, 9"), &data),
                "larger than any",
            ),
            (
                "short",
                npy(&dict("<f8", "3, 2"), &data[..40]),
                "ends early",
            ),
            ("f4", npy(&dict("<f4", "3, 2"), &data), "bytes follow"),
            (
                "trailing",
                npy(&dict("<f8", "3, 2"), &[&data[..], &[0; 8]].concat()),
                "bytes follow",
            ),
        ];
        assert!(
            read_rows(
                &{
                    let path = dir.join("good.npy");
                    std::fs::write(&path, npy(&dict("<f8", "3, 2"), &data)).expect("write");
                    path
                },
                2
            )
            .is_ok()
        );
        for (name, bytes, words) in cases {
            let path = dir.join(format!("{name}.npy"));
            std::fs::write(&path, &bytes).expect("write");
            match read_rows(&path, 2) {
                Ok(_) => panic!("{name}: read"),
                Err(e) => assert!(e.to_string().contains(words), "{name}: {e}"),
            }
        }
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn written_arrays_read_back_exactly() {
        let dir = std::env::temp_dir().join(format!("glyphcast-npy-array-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let values = [1.5, -2.25e-300, 3.0, f64::MAX, 0.1, 7.0];
        let path = dir.join("a.npy");
        std::fs::write(&path, encode_f64(&[3, 2], values.iter().copied())).expect("write");
        let array = read_rows(&path, 2).expect("read");
        assert_eq!(array.shape, vec![3, 2]);
        assert_eq!(
            array.rows,
            vec![vec![1.5, -2.25e-300], vec![3.0, f64::MAX], vec![0.1, 7.0]]
        );
        std::fs::write(&path, encode_f64(&[4], [1.0, 2.0, 3.0, 4.0].into_iter())).expect("write");
        let array = read_rows(&path, 1).expect("read");
        assert_eq!(array.shape, vec![4]);
        assert_eq!(array.rows, vec![vec![1.0], vec![2.0], vec![3.0], vec![4.0]]);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
