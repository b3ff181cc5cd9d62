//! MRtrix image input and output: `.mif` (header and data in one file), `.mif.gz` (the
//! same, gzip-compressed) and `.mih` (header only, the data in the file its `file` key
//! names, beside it).
//!
//! Conventions, as MRtrix3's documentation states them ("Images and other data"):
//! - `layout` gives, per axis, the rank of its stride (0 = fastest varying on file) and
//!   its direction: `-` means voxel index 0 of that axis is stored last. Voxel indices are
//!   always those of the header's axes; the layout only says where each voxel lies on
//!   file. `+1,+2,+3,+0` is volume-contiguous storage.
//! - `transform` holds the first three rows of a 4x4 matrix that maps *image coordinates
//!   in millimetres* (voxel index times `vox`, per axis) to scanner coordinates in
//!   millimetres; its 3x3 part has unit columns. So voxel (i, j, k) is at
//!   T[:, :3] diag(vox) (i, j, k) + T[:, 3], and the voxel-to-world affine of this crate
//!   is T[:, :3] diag(vox) with T[:, 3] as offset. A header without `transform` is given
//!   the identity: voxel (0, 0, 0) at the origin, the axes along x, y and z.
//! - `scaling: offset,scale` turns a stored value v into offset + scale v.
//! - `dw_scheme` lines are gx,gy,gz,b per volume, the direction in scanner (world)
//!   coordinates, b in s/mm^2.
//!
//! MRtrix itself realigns an image on loading (permuting and flipping axes so that the
//! transform is closest to the identity); this reader does not: its voxel axes are the
//! header's, as the NIfTI reader's are the file's. Images split over several data files,
//! and complex data, are refused with an error naming the key.
use std::io::{Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

use glam::{DMat3, DMat4, DVec3};
use ndarray::{ArrayD, Axis, IxDyn, ShapeBuilder};

use crate::io::input_limit::{check_input_size, max_input_bytes};
use crate::io::nifti::{AffineSource, VoxelToWorld};
use glyphcast::{Error, Result};

pub mod header;
pub mod write;

pub use crate::io::datatype::DataType;
pub use header::MifHeader;
pub use write::{MifWrite, mif_file_bytes, write_mif};

/// Which MRtrix file a name is, by its ending.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MifKind {
    /// `.mif`: the header and the data in one file.
    Mif,
    /// `.mif.gz`: a `.mif`, gzip-compressed.
    MifGz,
    /// `.mih`: the header alone; its `file` key names the data file.
    Mih,
}

impl MifKind {
    /// `.mif`, `.mif.gz` or `.mih` (any case), else None.
    pub fn of(path: &Path) -> Option<Self> {
        let name = path.file_name()?.to_string_lossy().to_ascii_lowercase();
        [
            (".mif.gz", MifKind::MifGz),
            (".mif", MifKind::Mif),
            (".mih", MifKind::Mih),
        ]
        .into_iter()
        .find(|(ending, _)| name.len() > ending.len() && name.ends_with(ending))
        .map(|(_, kind)| kind)
    }
}

/// One MRtrix image in memory.
#[derive(Clone, Debug)]
pub struct MifImage {
    /// The path as given, for messages.
    pub file: String,
    /// The header as read, for copying its keys and geometry into outputs.
    pub header: MifHeader,
    /// Voxel values with scaling applied, shape `dim` in the header's axis order.
    pub data: ArrayD<f64>,
    /// Voxel indices to scanner coordinates, from `transform` and `vox`.
    pub voxel_to_world: VoxelToWorld,
}

/// Reads `path` as an MRtrix image (`.mif`, `.mif.gz` or `.mih` by its ending; any other
/// name is read as an uncompressed `.mif`).
pub fn read_mif(path: &Path) -> Result<MifImage> {
    let file = path.display().to_string();
    let mut bytes = Vec::new();
    let opened = std::fs::File::open(path).map_err(|err| Error::io(path, err))?;
    if MifKind::of(path) == Some(MifKind::MifGz) {
        // Decompressed no further than the input cap allows (a small file can expand
        // a thousandfold).
        let limit = max_input_bytes()?;
        flate2::read::MultiGzDecoder::new(opened)
            .take(limit.saturating_add(1))
            .read_to_end(&mut bytes)
            .map_err(|err| Error::input(&file, "gzip", format!("not readable: {err}")))?;
        check_input_size(&file, bytes.len() as u64, "the decompressed file")?;
    } else {
        let mut opened = opened;
        opened
            .read_to_end(&mut bytes)
            .map_err(|err| Error::io(path, err))?;
    }
    let header = MifHeader::parse(&bytes, &file)?;
    let count = header
        .voxel_count()
        .ok_or_else(|| Error::input(&file, "dim", "too many voxels to address"))?;
    let needed = header
        .datatype
        .byte_count(count)
        .ok_or_else(|| Error::input(&file, "dim", "too many voxels to address"))?;
    check_input_size(
        &file,
        (count as u64).saturating_mul(8),
        "the voxels as float64",
    )?;
    let values = if header.file.name == "." {
        let offset = header.file.offset;
        if offset < header.length as u64 {
            return Err(Error::input(
                &file,
                "file",
                format!(
                    "offset {offset} points inside the header, which ends at byte {}",
                    header.length
                ),
            ));
        }
        let data = usize::try_from(offset)
            .ok()
            .and_then(|start| bytes.get(start..))
            .unwrap_or(&[]);
        check_length(&file, data.len(), needed, offset, count, &header)?;
        header.datatype.decode(data, count, header.scaling)
    } else {
        let data = read_data_file(path, &header, needed, count)?;
        header.datatype.decode(&data, count, header.scaling)
    };
    drop(bytes);
    let data = arrange(values, &header);
    let voxel_to_world = voxel_to_world(&header, &file)?;
    Ok(MifImage {
        file,
        header,
        data,
        voxel_to_world,
    })
}

fn check_length(
    file: &str,
    have: usize,
    needed: usize,
    offset: u64,
    count: usize,
    header: &MifHeader,
) -> Result<()> {
    if have < needed {
        return Err(Error::input(
            file,
            "data",
            format!(
                "truncated: {count} {} values need {needed} bytes from offset {offset}, but \
                 only {have} follow",
                header.datatype.name()
            ),
        ));
    }
    Ok(())
}

/// The data of a `.mih` (or a `.mif` naming another file): `needed` bytes from the
/// offset of the file its `file` key names, relative to the header's folder.
fn read_data_file(path: &Path, header: &MifHeader, needed: usize, count: usize) -> Result<Vec<u8>> {
    let name = Path::new(&header.file.name);
    let data_path: PathBuf = match path.parent() {
        Some(folder) if name.is_relative() => folder.join(name),
        _ => name.to_path_buf(),
    };
    let mut data_file = std::fs::File::open(&data_path).map_err(|err| {
        Error::input(
            path.display().to_string(),
            "file",
            format!("data file {}: {err}", data_path.display()),
        )
    })?;
    let length = data_file
        .metadata()
        .map_err(|err| Error::io(&data_path, err))?
        .len();
    let offset = header.file.offset;
    let have = usize::try_from(length.saturating_sub(offset)).unwrap_or(usize::MAX);
    check_length(
        &data_path.display().to_string(),
        have,
        needed,
        offset,
        count,
        header,
    )?;
    let mut data = vec![0; needed];
    data_file
        .seek(SeekFrom::Start(offset))
        .and_then(|_| data_file.read_exact(&mut data))
        .map_err(|err| Error::io(&data_path, err))?;
    Ok(data)
}

/// The values in file order as an array indexed by the header's axes: the file order is
/// the axes sorted by layout rank (fastest first); a reversed axis is flipped.
fn arrange(values: Vec<f64>, header: &MifHeader) -> ArrayD<f64> {
    let axes = header.dims.len();
    // storage[r] = the header axis whose stride has rank r.
    let mut storage = vec![0; axes];
    for (axis, entry) in header.layout.iter().enumerate() {
        storage[entry.rank] = axis;
    }
    let shape: Vec<usize> = storage.iter().map(|&axis| header.dims[axis]).collect();
    let stored = ArrayD::from_shape_vec(IxDyn(&shape).f(), values)
        .unwrap_or_else(|_| unreachable!("the value count is the product of dim"));
    let ranks: Vec<usize> = header.layout.iter().map(|entry| entry.rank).collect();
    let mut data = stored.permuted_axes(IxDyn(&ranks));
    for (axis, entry) in header.layout.iter().enumerate() {
        if entry.reversed {
            data.invert_axis(Axis(axis));
        }
    }
    data
}

/// The affine T[:, :3] diag(vox) with offset T[:, 3] (the identity transform if none).
fn voxel_to_world(header: &MifHeader, file: &str) -> Result<VoxelToWorld> {
    let rows = header.transform.unwrap_or([
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
    ]);
    let column = |c: usize| DVec3::new(rows[0][c], rows[1][c], rows[2][c]);
    let size = |axis: usize| header.vox.get(axis).copied().unwrap_or(1.0);
    let linear = DMat3::from_cols(
        column(0) * size(0),
        column(1) * size(1),
        column(2) * size(2),
    );
    let affine = DMat4::from_cols(
        linear.x_axis.extend(0.0),
        linear.y_axis.extend(0.0),
        linear.z_axis.extend(0.0),
        column(3).extend(1.0),
    );
    VoxelToWorld::new(affine, AffineSource::MrtrixTransform, file, "transform")
}
