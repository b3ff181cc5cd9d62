//! NIfTI `datatype` codes (`nifti1.h`, shared by NIfTI-2): the real integer and float
//! types are read as f64; complex, RGB, float128, binary and unknown codes are refused,
//! since glyph coefficients, DWI signals and masks are real numbers one per voxel.
use crate::{Error, Result};

/// A voxel type glyphcast reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DataType {
    U8,
    I8,
    I16,
    U16,
    I32,
    U32,
    I64,
    U64,
    F32,
    F64,
}

/// (code, type) of every readable code.
const READABLE: [(i16, DataType); 10] = [
    (2, DataType::U8),
    (256, DataType::I8),
    (4, DataType::I16),
    (512, DataType::U16),
    (8, DataType::I32),
    (768, DataType::U32),
    (1024, DataType::I64),
    (1280, DataType::U64),
    (16, DataType::F32),
    (64, DataType::F64),
];

/// (code, name) of the codes the standard defines but glyphcast refuses.
const REFUSED: [(i16, &str); 7] = [
    (1, "binary (1 bit per voxel)"),
    (32, "complex64"),
    (128, "RGB24"),
    (1536, "float128"),
    (1792, "complex128"),
    (2048, "complex256"),
    (2304, "RGBA32"),
];

impl DataType {
    /// The type of `code` with `bitpix` checked against it; Err naming `datatype` (or
    /// `bitpix`) and what the type is.
    pub fn from_header(code: i16, bitpix: i16, file: &str) -> Result<Self> {
        let Some(&(_, datatype)) = READABLE.iter().find(|(c, _)| *c == code) else {
            let message = match REFUSED.iter().find(|(c, _)| *c == code) {
                Some((_, name)) => format!(
                    "{name} data (code {code}) cannot be drawn as glyph coefficients or read \
                     as signals: one real number per voxel is needed"
                ),
                None => format!("{code} is not a NIfTI data type code"),
            };
            return Err(Error::input(file, "datatype", message));
        };
        let bits = 8 * datatype.size() as i16;
        if bitpix != bits {
            return Err(Error::input(
                file,
                "bitpix",
                format!(
                    "{bitpix} does not match datatype {} ({bits} bits per voxel)",
                    datatype.name()
                ),
            ));
        }
        Ok(datatype)
    }

    /// The NIfTI code.
    pub fn code(self) -> i16 {
        READABLE
            .iter()
            .find(|(_, t)| *t == self)
            .map_or(0, |(code, _)| *code)
    }

    /// Bytes per voxel.
    pub fn size(self) -> usize {
        match self {
            DataType::U8 | DataType::I8 => 1,
            DataType::I16 | DataType::U16 => 2,
            DataType::I32 | DataType::U32 | DataType::F32 => 4,
            DataType::I64 | DataType::U64 | DataType::F64 => 8,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            DataType::U8 => "uint8",
            DataType::I8 => "int8",
            DataType::I16 => "int16",
            DataType::U16 => "uint16",
            DataType::I32 => "int32",
            DataType::U32 => "uint32",
            DataType::I64 => "int64",
            DataType::U64 => "uint64",
            DataType::F32 => "float32",
            DataType::F64 => "float64",
        }
    }

    /// Appends the values of `bytes` (whole voxels) to `out` as f64.
    pub fn decode_into(self, bytes: &[u8], big_endian: bool, out: &mut Vec<f64>) {
        let size = self.size();
        for raw in bytes.chunks_exact(size) {
            let mut word = [0u8; 8];
            word[..size].copy_from_slice(raw);
            if big_endian {
                word[..size].reverse();
            }
            out.push(self.value(word));
        }
    }

    /// The value of one voxel's little-endian bytes (in the low `size` bytes of `word`).
    fn value(self, word: [u8; 8]) -> f64 {
        let [a, b, c, d, ..] = word;
        match self {
            DataType::U8 => a.into(),
            DataType::I8 => (a as i8).into(),
            DataType::I16 => i16::from_le_bytes([a, b]).into(),
            DataType::U16 => u16::from_le_bytes([a, b]).into(),
            DataType::I32 => i32::from_le_bytes([a, b, c, d]).into(),
            DataType::U32 => u32::from_le_bytes([a, b, c, d]).into(),
            DataType::F32 => f32::from_le_bytes([a, b, c, d]).into(),
            DataType::I64 => i64::from_le_bytes(word) as f64,
            DataType::U64 => u64::from_le_bytes(word) as f64,
            DataType::F64 => f64::from_le_bytes(word),
        }
    }
}
