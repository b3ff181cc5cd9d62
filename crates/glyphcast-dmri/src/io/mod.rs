//! Image files: NIfTI-1/2 and MRtrix `.mif`/`.mih`, read and written, behind one
//! reader and one writer (`image::read_image`, `image::write_image`) that know each
//! format's conventions; tractograms (`.tck`, `.trk`, `.trx`) read into one type in the
//! same scanner frame (`tracks::read_tractogram`); the renderer's own files
//! (scene JSON, PNG, NumPy, atomic output sets) are `glyphcast::io`.
pub mod datatype;
pub mod gzip;
pub mod image;
pub mod input_limit;
pub mod mif;
pub mod nifti;
pub mod tracks;
