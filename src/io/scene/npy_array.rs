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
