//! The types of stored values both image formats share, with their MRtrix names: `Bit`, `Int8`, `UInt8`, and 16, 32 and 64-bit integers and 32 and
//! 64-bit floats with an `LE` or `BE` suffix (none: this machine's byte order). Names are
//! matched without regard to case, as MRtrix does. `Bit` packs eight voxels per byte,
//! the first in the most significant bit. Complex types are refused: glyph coefficients
//! and DWI signals are real.
use glyphcast::error::quoted;
use glyphcast::{Error, Result};

/// How one stored value is encoded, apart from its byte order; shared by the NIfTI reader.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Number {
    /// `Bit`: one bit per voxel, eight voxels per byte, the first in the most significant bit.
    Bit,
    /// Signed 8-bit integer (`Int8`).
    I8,
    /// Unsigned 8-bit integer (`UInt8`).
    U8,
    /// Signed 16-bit integer (`Int16`).
    I16,
    /// Unsigned 16-bit integer (`UInt16`).
    U16,
    /// Signed 32-bit integer (`Int32`).
    I32,
    /// Unsigned 32-bit integer (`UInt32`).
    U32,
    /// Signed 64-bit integer (`Int64`).
    I64,
    /// Unsigned 64-bit integer (`UInt64`).
    U64,
    /// IEEE 754 single precision (`Float32`).
    F32,
    /// IEEE 754 double precision (`Float64`).
    F64,
}

/// A number type and its byte order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DataType {
    /// The kind of number stored.
    pub number: Number,
    /// Most significant byte first (`BE`); without meaning for the single-byte types.
    pub big_endian: bool,
}

const NAMES: [(&str, Number); 11] = [
    ("bit", Number::Bit),
    ("int8", Number::I8),
    ("uint8", Number::U8),
    ("int16", Number::I16),
    ("uint16", Number::U16),
    ("int32", Number::I32),
    ("uint32", Number::U32),
    ("int64", Number::I64),
    ("uint64", Number::U64),
    ("float32", Number::F32),
    ("float64", Number::F64),
];

impl DataType {
    /// `Float32LE`, the type glyphcast writes.
    pub const FLOAT32_LE: DataType = DataType {
        number: Number::F32,
        big_endian: false,
    };

    /// The type named by an MRtrix `datatype` value (`Float32LE`, `uint16be`, `Bit`, ...); a
    /// multi-byte name without `LE`/`BE` takes this machine's byte order. Err naming `file`
    /// and `datatype` for complex and unknown names.
    pub fn parse(text: &str, file: &str) -> Result<Self> {
        let lower = text.trim().to_ascii_lowercase();
        if lower.starts_with("cfloat") {
            return Err(Error::input(
                file,
                "datatype",
                format!(
                    "{}: complex values cannot be read as real coefficients or signals",
                    quoted(text)
                ),
            ));
        }
        let (stem, big_endian) = if let Some(stem) = lower.strip_suffix("le") {
            (stem, Some(false))
        } else if let Some(stem) = lower.strip_suffix("be") {
            (stem, Some(true))
        } else {
            (lower.as_str(), None)
        };
        let number = NAMES
            .iter()
            .find(|(name, _)| *name == stem)
            .map(|&(_, number)| number);
        let single_byte = matches!(number, Some(Number::Bit | Number::I8 | Number::U8));
        match number {
            Some(number) if !(single_byte && big_endian.is_some()) => Ok(Self {
                number,
                big_endian: big_endian.unwrap_or(cfg!(target_endian = "big")),
            }),
            _ => Err(Error::input(
                file,
                "datatype",
                format!(
                    "unknown data type '{}'; expected Bit, Int8, UInt8, (U)Int16/32/64 or \
                     Float32/64, with LE or BE for the multi-byte ones",
                    quoted(text)
                ),
            )),
        }
    }

    /// The header spelling (`Float32LE`).
    pub fn name(&self) -> String {
        let stem = match self.number {
            Number::Bit => return "Bit".into(),
            Number::I8 => return "Int8".into(),
            Number::U8 => return "UInt8".into(),
            Number::I16 => "Int16",
            Number::U16 => "UInt16",
            Number::I32 => "Int32",
            Number::U32 => "UInt32",
            Number::I64 => "Int64",
            Number::U64 => "UInt64",
            Number::F32 => "Float32",
            Number::F64 => "Float64",
        };
        format!("{stem}{}", if self.big_endian { "BE" } else { "LE" })
    }

    /// Bytes per value (Bit: 0, see [`DataType::byte_count`]).
    pub fn width(&self) -> usize {
        match self.number {
            Number::Bit => 0,
            Number::I8 | Number::U8 => 1,
            Number::I16 | Number::U16 => 2,
            Number::I32 | Number::U32 | Number::F32 => 4,
            Number::I64 | Number::U64 | Number::F64 => 8,
        }
    }

    /// Bytes that `count` values take.
    pub fn byte_count(&self, count: usize) -> Option<usize> {
        match self.number {
            Number::Bit => Some(count.div_ceil(8)),
            _ => count.checked_mul(self.width()),
        }
    }

    /// The first `count` values of `bytes` (which holds at least `byte_count(count)`), in
    /// file order, as offset + scale v.
    pub fn decode(&self, bytes: &[u8], count: usize, (offset, scale): (f64, f64)) -> Vec<f64> {
        let scaled = |v: f64| offset + scale * v;
        if self.number == Number::Bit {
            return (0..count)
                .map(|i| scaled(f64::from((bytes[i / 8] >> (7 - i % 8)) & 1)))
                .collect();
        }
        let width = self.width();
        bytes[..count * width]
            .chunks_exact(width)
            .map(|chunk| scaled(self.value(chunk)))
            .collect()
    }

    /// Appends the unscaled values of `bytes` to `out`, one per `width` bytes (not for
    /// `Bit`; the NIfTI reader decodes its data in chunks with this).
    pub fn decode_into(&self, bytes: &[u8], out: &mut Vec<f64>) {
        out.extend(
            bytes
                .chunks_exact(self.width().max(1))
                .map(|c| self.value(c)),
        );
    }

    fn value(&self, chunk: &[u8]) -> f64 {
        macro_rules! read {
            ($t:ty) => {{
                let bytes = chunk.try_into().unwrap_or_default();
                if self.big_endian {
                    <$t>::from_be_bytes(bytes)
                } else {
                    <$t>::from_le_bytes(bytes)
                }
            }};
        }
        match self.number {
            Number::Bit => 0.0,
            Number::I8 => f64::from(chunk[0] as i8),
            Number::U8 => f64::from(chunk[0]),
            Number::I16 => f64::from(read!(i16)),
            Number::U16 => f64::from(read!(u16)),
            Number::I32 => f64::from(read!(i32)),
            Number::U32 => f64::from(read!(u32)),
            Number::I64 => read!(i64) as f64,
            Number::U64 => read!(u64) as f64,
            Number::F32 => f64::from(read!(f32)),
            Number::F64 => read!(f64),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_and_print() {
        for name in ["Int16BE", "UInt32LE", "Float64BE", "Float32LE", "Int64LE"] {
            assert_eq!(DataType::parse(name, "f").unwrap().name(), name);
        }
        assert_eq!(
            DataType::parse("float32le", "f").unwrap(),
            DataType::FLOAT32_LE
        );
        assert_eq!(DataType::parse("Bit", "f").unwrap().name(), "Bit");
        for bad in ["CFloat32LE", "Float16", "Int8LE", "", "Float32XE"] {
            let err = DataType::parse(bad, "f.mif").unwrap_err().to_string();
            assert!(err.contains("f.mif: datatype"), "{bad}: {err}");
        }
    }

    #[test]
    fn values_decode_in_both_byte_orders_with_scaling() {
        let be = DataType::parse("Int16BE", "f").unwrap();
        assert_eq!(
            be.decode(&[0xff, 0xfe, 0, 3], 2, (0.0, 1.0)),
            vec![-2.0, 3.0]
        );
        let le = DataType::parse("UInt16LE", "f").unwrap();
        assert_eq!(le.decode(&[1, 1], 1, (1.0, 2.0)), vec![515.0]);
        let bits = DataType::parse("Bit", "f").unwrap();
        assert_eq!(
            bits.decode(&[0b1010_0000, 0b1000_0000], 9, (0.0, 1.0)),
            vec![1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0]
        );
        assert_eq!(bits.byte_count(9), Some(2));
    }
}
