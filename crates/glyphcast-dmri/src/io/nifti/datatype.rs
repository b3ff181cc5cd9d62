//! NIfTI `datatype` codes (`nifti1.h`, shared by NIfTI-2): the real integer and float
//! types are read as f64, decoded by the number types the MRtrix reader shares
//! (`io::datatype`); complex, RGB, float128, binary and unknown codes are refused,
//! since glyph coefficients, DWI signals and masks are real numbers one per voxel.
use crate::io::datatype::{DataType, Number};
use glyphcast::{Error, Result};

/// (code, number type, NIfTI name) of every readable code.
const READABLE: [(i16, Number, &str); 10] = [
    (2, Number::U8, "uint8"),
    (256, Number::I8, "int8"),
    (4, Number::I16, "int16"),
    (512, Number::U16, "uint16"),
    (8, Number::I32, "int32"),
    (768, Number::U32, "uint32"),
    (1024, Number::I64, "int64"),
    (1280, Number::U64, "uint64"),
    (16, Number::F32, "float32"),
    (64, Number::F64, "float64"),
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

/// The stored type of `code` in the header's byte order, with `bitpix` checked against
/// it; Err naming `datatype` (or `bitpix`) and saying what the type is.
pub fn voxel_type(code: i16, bitpix: i16, big_endian: bool, file: &str) -> Result<DataType> {
    let Some(&(_, number, name)) = READABLE.iter().find(|(c, ..)| *c == code) else {
        let message = match REFUSED.iter().find(|(c, _)| *c == code) {
            Some((_, name)) => format!(
                "{name} data (code {code}) cannot be drawn as glyph coefficients or read as \
                 signals: one real number per voxel is needed"
            ),
            None => format!("{code} is not a NIfTI data type code"),
        };
        return Err(Error::input(file, "datatype", message));
    };
    let datatype = DataType { number, big_endian };
    let bits = 8 * datatype.width() as i16;
    if bitpix != bits {
        return Err(Error::input(
            file,
            "bitpix",
            format!("{bitpix} does not match datatype {name} ({bits} bits per voxel)"),
        ));
    }
    Ok(datatype)
}

/// The NIfTI name of a readable type (`float32`).
pub fn name(datatype: DataType) -> &'static str {
    READABLE
        .iter()
        .find(|(_, number, _)| *number == datatype.number)
        .map_or("?", |(.., name)| name)
}
