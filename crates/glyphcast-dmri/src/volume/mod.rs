//! Volume input: a slice (or three orthogonal ones, or a 3D block of voxels) of a 4D NIfTI
//! volume of SH or tensor coefficients as a scene.
//!
//! The pipeline, one file per step: `input` reads the volume (and a mask) and checks the
//! coefficient count against what the user says the file holds; `selection` picks the
//! voxels (slice, index ranges, mask; a block is every voxel of the ranges); `reorient`
//! turns each glyph from voxel axes into world axes with the orthogonal polar factor R of
//! the affine, g(u) = f(R^T u) (only for coefficients in the voxel frame; world-frame
//! ones, MRtrix's, are drawn as stored);
//! `recorded` reads the SH basis a file records;
//! `amplitude` measures glyphs for normalisation; `framing` places the camera in the
//! radiological or neurological convention; `build` puts it together into a [`Scene`](glyphcast::scene::Scene) and a [`VolumeReport`].
//! `request` and `figure` are the front ends' way in: a [`VolumeRequest`] holds the
//! options as the CLI's flags and the Python module's keywords give them, parses and
//! checks each once (errors name the [`Setting`](glyphcast::Setting)), reads or adopts the
//! volume, and makes the [`VolumeFigure`]: one view with its underlay, or a montage's
//! panels.
//!
//! Glyph centres are the affine applied to the voxel indices (NIfTI-1's sform, else
//! qform, else pixdim: [`crate::io::nifti::affine`]); voxel-frame glyph shapes use only
//! the affine's orthogonal factor, so anisotropic voxels do not stretch the glyphs, but a
//! rotated or reflected grid turns them with it; world-frame shapes ignore the affine.

mod amplitude;
mod build;
mod figure;
mod framing;
mod input;
mod peaks;
mod recorded;
mod reorient;
mod request;
mod selection;
mod tracks;
mod underlay;

pub use build::{
    DEFAULT_SCALE_FRACTION, MAX_BLOCK_GLYPHS, Normalisation, ROBUST_FACTOR, ROBUST_PERCENTILE,
    SQRT_PERCENTILE, VolumeOptions, VolumeReport, VolumeScene, percentile, robust_reference,
    slice_framing, volume_scene, volume_scene_with_progress,
};
pub use figure::{MontagePlan, VolumeFigure, VolumeMontage, VolumeView};
pub use framing::{
    DEFAULT_LONG_SIDE, Framing, ImageRequest, Orientation, PERSPECTIVE_FOV_DEG, ViewProjection,
    frame_block, frame_region, frame_volume, view_axis, view_directions,
};
pub use input::{CoefficientFrame, MAX_ORDER, Mask, Volume, VolumeKind, load_mask, load_volume};
pub use peaks::{
    DEFAULT_PEAKS_SCALE_FRACTION, DEFAULT_PEAKS_WIDTH, PeakArray, PeakStyle, PeakVolume,
    PeaksColor, PeaksNorm, ViewPeaks, load_peaks, peak_set, pixel_size,
};
#[cfg(test)]
pub(crate) use recorded::commented_image;
pub use recorded::{
    RecordedBasis, RecordedContent, TENSOR_PREFIX, check_content, check_variant_named,
    recorded_basis, recorded_content, resolve_basis, tensor_description,
};
pub use reorient::Reorientation;
pub use request::{Coefficients, ImageSource, MAX_PANELS, VolumeRequest, parse_views};
pub use selection::{Slice, SliceAxis, SliceRegion, Slices, VoxelRanges, show_block};
pub use tracks::{
    DEFAULT_TRACKS_RADIUS_MM, ScalarColor, TrackShape, TrackStyle, TracksColor, ViewTracks,
    scalar_request, tube_set, view_tubes,
};
pub use underlay::{
    UnderlayPlacement, load_underlay, plane_behind, slice_plane, slice_planes, turned_away,
    underlay_of_image, view_underlay,
};
