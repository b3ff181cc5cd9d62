//! Image files: NIfTI-1/2 and MRtrix `.mif`/`.mih`, read and written, behind one
//! reader (`image`) that knows each format's conventions; the renderer's own files
//! (scene JSON, PNG, NumPy, atomic output sets) are `glyphcast::io`.
pub mod datatype;
pub mod image;
pub mod input_limit;
pub mod mif;
pub mod nifti;
