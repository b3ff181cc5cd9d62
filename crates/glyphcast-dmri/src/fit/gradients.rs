//! FSL gradient tables: a `.bval` file of b-values (s/mm^2) and a `.bvec` file of
//! gradient directions, one of each per DWI volume.
//!
//! FSL writes both as rows (`.bval` one row, `.bvec` three rows of n), other tools as
//! columns (`.bval` one column, `.bvec` n rows of three); both layouts are read, and a
//! 3 x 3 table (three volumes) is taken in FSL's layout. Numbers are separated by
//! whitespace or commas; blank lines are skipped.
//!
//! A volume with b <= [`B0_THRESHOLD`] is a b=0 volume: its direction is ignored, since
//! scanners write anything there (DIPY's small_64D has `nan nan nan`). Every other
//! direction must be finite and non-zero and is normalised to unit length; the b-value
//! is kept as written (no rescaling by |g|^2). Volumes are counted from 0, as in FSL's
//! `fslroi` and nibabel.
//!
//! An MRtrix image may carry its table instead (`dw_scheme`, [`GradientTable::from_dw_scheme`]);
//! its directions are in scanner coordinates and are turned into voxel axes here.
//!
//! Whatever the source, the table ends up in the image's voxel axes, the frame of the
//! fitted coefficients (what `render --sh` takes a NIfTI's coefficients to be in). A
//! `.bvec` is read in a [`BvecConvention`], FSL's by default, as FSL and MRtrix read it:
//! FSL's voxel frame is the image's voxel axes with x reversed when the affine's
//! determinant is positive (FSL shows every image with a negative determinant, the
//! "radiological" storage, and flips the others in x to get there), so a direction's x
//! is negated on such images; on images with a negative determinant (what scanners and
//! dcm2niix usually write) FSL's and plain voxel axes agree.
use glam::{DMat3, DVec3};
use std::path::Path;
use std::str::FromStr;

use crate::io::nifti::VoxelToWorld;
use crate::setting::DmriSetting;
use glyphcast::error::quoted;
use glyphcast::{Error, Result};

/// The frame the directions of a `.bvec` file are written in.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BvecConvention {
    /// FSL's: voxel axes, x negated when the affine's determinant is positive.
    #[default]
    Fsl,
    /// The image's voxel axes as stored (what DIPY assumes).
    Voxel,
    /// Scanner (world) axes, as MRtrix's `dw_scheme`.
    World,
}

impl FromStr for BvecConvention {
    type Err = Error;

    /// `fsl`, `voxel` or `world`.
    fn from_str(text: &str) -> Result<Self> {
        match text {
            "fsl" => Ok(BvecConvention::Fsl),
            "voxel" => Ok(BvecConvention::Voxel),
            "world" => Ok(BvecConvention::World),
            _ => Err(Error::setting_value(
                DmriSetting::BvecConvention,
                format!("'{}'", quoted(text)),
                "expected fsl, voxel or world",
            )),
        }
    }
}

impl BvecConvention {
    /// The matrix that takes a direction in this convention to the voxel axes of an image
    /// mapped by `map`; `dwi` names the error when the affine has no rotation.
    pub fn to_voxel_axes(self, map: &VoxelToWorld, dwi: &str) -> Result<DMat3> {
        match self {
            BvecConvention::Voxel => Ok(DMat3::IDENTITY),
            BvecConvention::Fsl if map.linear().determinant() > 0.0 => {
                Ok(DMat3::from_diagonal(DVec3::new(-1.0, 1.0, 1.0)))
            }
            BvecConvention::Fsl => Ok(DMat3::IDENTITY),
            BvecConvention::World => {
                map.orthogonal_factor()
                    .map(|r| r.transpose())
                    .ok_or_else(|| {
                        Error::input(dwi, "affine", "no rotation can be taken from the affine")
                    })
            }
        }
    }
}

/// b-values at or below this (s/mm^2) count as b=0 volumes. Scanners report small
/// non-zero b-values for their unweighted volumes (b = 5 to 10 is common); 50 is the
/// threshold DIPY's `gradient_table` uses (`b0_threshold=50`).
pub const B0_THRESHOLD: f64 = 50.0;

/// Directions shorter than this are taken as zero vectors.
const MIN_DIRECTION_LENGTH: f64 = 1e-6;

/// b-value and unit gradient direction of every DWI volume.
#[derive(Clone, Debug, PartialEq)]
pub struct GradientTable {
    /// One b-value per volume, s/mm^2.
    pub bvals: Vec<f64>,
    /// `None` for the b=0 volumes.
    pub directions: Vec<Option<DVec3>>,
}

impl GradientTable {
    /// Reads both files; `volumes` is the DWI's fourth dimension and `dwi` its name,
    /// both used in the count errors.
    pub fn read(bval: &Path, bvec: &Path, volumes: usize, dwi: &str) -> Result<Self> {
        let bvals = read_bvals(bval, volumes, dwi)?;
        let vectors = read_bvecs(bvec, volumes, dwi)?;
        let directions = bvals
            .iter()
            .zip(vectors)
            .enumerate()
            .map(|(volume, (&b, v))| {
                unit_direction(
                    &bvec.display().to_string(),
                    format!("volume {volume}"),
                    b,
                    v,
                )
            })
            .collect::<Result<Vec<_>>>()?;
        Self::checked(bvals, directions, &bval.display().to_string(), "b-values")
    }

    /// The table of an MRtrix `dw_scheme` (gx, gy, gz, b per volume, the direction in
    /// scanner coordinates) of the image `dwi` with `volumes` volumes, the directions
    /// turned into the image's voxel axes: d_voxel = R^T d_world, R the orthogonal factor
    /// of its voxel-to-world affine ([`crate::io::nifti::VoxelToWorld::orthogonal_factor`]). That is the
    /// frame `.bvec` directions are taken in, so both give coefficients in voxel axes.
    pub fn from_dw_scheme(
        rows: &[[f64; 4]],
        volumes: usize,
        rotation: DMat3,
        dwi: &str,
    ) -> Result<Self> {
        if rows.len() != volumes {
            return Err(Error::input(
                dwi,
                "dw_scheme",
                format!("{} rows, but the image has {volumes} volumes", rows.len()),
            ));
        }
        let bvals: Vec<f64> = rows.iter().map(|row| row[3]).collect();
        if let Some((i, b)) = bvals
            .iter()
            .enumerate()
            .find(|(_, b)| !b.is_finite() || **b < 0.0)
        {
            return Err(Error::input(
                dwi,
                "dw_scheme",
                format!("volume {i}: b-value {b} is not a finite number >= 0"),
            ));
        }
        let world_to_voxel = rotation.transpose();
        let directions = rows
            .iter()
            .enumerate()
            .map(|(volume, &[x, y, z, b])| {
                let field = format!("dw_scheme: volume {volume}");
                let direction = unit_direction(dwi, field, b, [x, y, z])?;
                Ok(direction.map(|d| world_to_voxel * d))
            })
            .collect::<Result<Vec<_>>>()?;
        Self::checked(bvals, directions, dwi, "dw_scheme")
    }

    /// The table, or an error naming `file` and `field` when it has no b=0 volume.
    fn checked(
        bvals: Vec<f64>,
        directions: Vec<Option<DVec3>>,
        file: &str,
        field: &str,
    ) -> Result<Self> {
        let table = GradientTable { bvals, directions };
        if table.b0_volumes().is_empty() {
            return Err(Error::input(
                file,
                field,
                format!(
                    "no b=0 volume (b <= {B0_THRESHOLD} s/mm^2); S0 is needed to normalise the signal"
                ),
            ));
        }
        Ok(table)
    }

    /// The table with every direction d replaced by `to_voxel` d (see
    /// [`BvecConvention::to_voxel_axes`]).
    pub fn transformed(self, to_voxel: DMat3) -> Self {
        let directions = self
            .directions
            .into_iter()
            .map(|d| d.map(|d| to_voxel * d))
            .collect();
        GradientTable {
            bvals: self.bvals,
            directions,
        }
    }

    /// Indices of the b=0 volumes.
    pub fn b0_volumes(&self) -> Vec<usize> {
        (0..self.bvals.len())
            .filter(|&i| self.directions[i].is_none())
            .collect()
    }

    /// Indices of the diffusion-weighted volumes, with their b-values and directions.
    pub fn weighted(&self) -> Vec<(usize, f64, DVec3)> {
        self.directions
            .iter()
            .enumerate()
            .filter_map(|(i, d)| d.map(|d| (i, self.bvals[i], d)))
            .collect()
    }
}

fn unit_direction(file: &str, field: String, b: f64, v: [f64; 3]) -> Result<Option<DVec3>> {
    if b <= B0_THRESHOLD {
        return Ok(None);
    }
    let v = DVec3::from_array(v);
    if !v.is_finite() {
        return Err(Error::input(
            file,
            field,
            format!(
                "direction {v} is not finite, and b = {b} s/mm^2 is above the b=0 threshold {B0_THRESHOLD}"
            ),
        ));
    }
    let length = v.length();
    if length < MIN_DIRECTION_LENGTH {
        return Err(Error::input(
            file,
            field,
            format!("zero-length direction for b = {b} s/mm^2"),
        ));
    }
    Ok(Some(v / length))
}

fn read_bvals(path: &Path, volumes: usize, dwi: &str) -> Result<Vec<f64>> {
    let file = path.display().to_string();
    let rows = read_table(path)?;
    let bvals: Vec<f64> = match (rows.len(), rows.first().map_or(0, Vec::len)) {
        (1, _) => rows.into_iter().flatten().collect(),
        (_, 1) => rows.into_iter().flatten().collect(),
        (r, c) => {
            return Err(Error::input(
                file,
                "layout",
                format!("expected one row or one column of b-values, got {r} rows of {c}"),
            ));
        }
    };
    if bvals.len() != volumes {
        return Err(Error::input(
            file,
            "count",
            format!("{} b-values, but {dwi} has {volumes} volumes", bvals.len()),
        ));
    }
    if let Some((i, b)) = bvals
        .iter()
        .enumerate()
        .find(|(_, b)| !b.is_finite() || **b < 0.0)
    {
        return Err(Error::input(
            file,
            format!("volume {i}"),
            format!("b-value {b} is not a finite number >= 0"),
        ));
    }
    Ok(bvals)
}

fn read_bvecs(path: &Path, volumes: usize, dwi: &str) -> Result<Vec<[f64; 3]>> {
    let file = path.display().to_string();
    let rows = read_table(path)?;
    let columns = rows.first().map_or(0, Vec::len);
    let count = match (rows.len(), columns) {
        (3, n) => n,
        (n, 3) => n,
        (r, c) => {
            return Err(Error::input(
                file,
                "layout",
                format!("expected 3 rows of n numbers or n rows of 3, got {r} rows of {c}"),
            ));
        }
    };
    if count != volumes {
        return Err(Error::input(
            file,
            "count",
            format!("{count} directions, but {dwi} has {volumes} volumes"),
        ));
    }
    if rows.len() == 3 {
        Ok((0..count)
            .map(|i| [rows[0][i], rows[1][i], rows[2][i]])
            .collect())
    } else {
        Ok(rows.iter().map(|r| [r[0], r[1], r[2]]).collect())
    }
}

/// Rows of numbers, all of the same length; `nan` is accepted (b=0 rows).
fn read_table(path: &Path) -> Result<Vec<Vec<f64>>> {
    let text = std::fs::read_to_string(path).map_err(|err| Error::io(path, err))?;
    let file = path.display().to_string();
    let mut rows: Vec<Vec<f64>> = Vec::new();
    for (index, line) in text.lines().enumerate() {
        let field = || format!("line {}", index + 1);
        let row = line
            .split(|c: char| c.is_whitespace() || c == ',')
            .filter(|token| !token.is_empty())
            .map(|token| {
                token.parse::<f64>().map_err(|_| {
                    Error::input(
                        &file,
                        field(),
                        format!("'{}' is not a number", quoted(token)),
                    )
                })
            })
            .collect::<Result<Vec<f64>>>()?;
        if row.is_empty() {
            continue;
        }
        if let Some(first) = rows.first()
            && first.len() != row.len()
        {
            return Err(Error::input(
                &file,
                field(),
                format!(
                    "{} numbers, but the first row has {}",
                    row.len(),
                    first.len()
                ),
            ));
        }
        rows.push(row);
    }
    if rows.is_empty() {
        return Err(Error::input(file, "content", "no numbers in the file"));
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    /// A fresh folder for one table's files (tests run in parallel).
    fn scratch_dir() -> std::path::PathBuf {
        static COUNTER: AtomicUsize = AtomicUsize::new(0);
        let dir = std::env::temp_dir().join(format!(
            "glyphcast-gradients-{}-{}",
            std::process::id(),
            COUNTER.fetch_add(1, Ordering::Relaxed)
        ));
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn table(bval: &str, bvec: &str, volumes: usize) -> Result<GradientTable> {
        let dir = scratch_dir();
        let (bval_path, bvec_path) = (dir.join("g.bval"), dir.join("g.bvec"));
        std::fs::write(&bval_path, bval).unwrap();
        std::fs::write(&bvec_path, bvec).unwrap();
        let table = GradientTable::read(&bval_path, &bvec_path, volumes, "dwi.nii");
        std::fs::remove_dir_all(&dir).unwrap();
        table
    }

    #[test]
    fn both_layouts_give_the_same_table() {
        let rows = table("0 1000 1000 5\n", "0 2 0 nan\n0 0 0 nan\n0 0 -0.5 nan\n", 4);
        let columns = table(
            "0\n1000\n1000\n5\n",
            "0 0 0\n2 0 0\n0,0,-0.5\nnan nan nan\n",
            4,
        );
        let rows = rows.unwrap();
        assert_eq!(rows, columns.unwrap());
        assert_eq!(rows.directions[1], Some(DVec3::X));
        assert_eq!(rows.directions[2], Some(-DVec3::Z));
        assert_eq!(rows.b0_volumes(), vec![0, 3]);
        assert_eq!(rows.weighted().len(), 2);
    }

    /// FSL's frame is the voxel frame flipped in x on images with a positive determinant
    /// only; the world convention undoes the affine's rotation.
    #[test]
    fn conventions_turn_directions_into_voxel_axes() {
        use crate::io::nifti::AffineSource;
        use glam::DMat4;
        let map = |linear: DMat3| {
            VoxelToWorld::new(DMat4::from_mat3(linear), AffineSource::Sform, "d", "s").unwrap()
        };
        let ras = map(DMat3::from_diagonal(DVec3::splat(2.0)));
        let las = map(DMat3::from_diagonal(DVec3::new(-2.0, 2.0, 2.0)));
        let d = DVec3::new(0.6, 0.8, 0.0);
        let voxel = |convention: BvecConvention, m: &VoxelToWorld| {
            convention.to_voxel_axes(m, "d").unwrap() * d
        };
        assert_eq!(voxel(BvecConvention::Fsl, &ras), DVec3::new(-0.6, 0.8, 0.0));
        assert_eq!(voxel(BvecConvention::Fsl, &las), d);
        assert_eq!(voxel(BvecConvention::Voxel, &ras), d);
        let world = voxel(BvecConvention::World, &las);
        assert!(
            (world - DVec3::new(-0.6, 0.8, 0.0)).length() < 1e-12,
            "{world}"
        );
        let t = table("0 1000", "0 0.6\n0 0.8\n0 0", 2).unwrap();
        let flipped = t.transformed(DMat3::from_diagonal(DVec3::new(-1.0, 1.0, 1.0)));
        assert_eq!(flipped.directions[1], Some(DVec3::new(-0.6, 0.8, 0.0)));
        assert!("radiological".parse::<BvecConvention>().is_err());
    }

    #[test]
    fn three_by_three_is_read_in_fsl_layout() {
        let t = table("0 1000 1000", "0 1 0\n0 0 0\n0 0 1\n", 3).unwrap();
        assert_eq!(t.directions[1], Some(DVec3::X));
        assert_eq!(t.directions[2], Some(DVec3::Z));
    }

    #[test]
    fn bad_tables_name_the_problem() {
        let err = |bval, bvec, n| table(bval, bvec, n).unwrap_err().to_string();
        assert!(err("0 1000", "0 1\n0 0\n0 0", 3).contains("2 b-values"));
        assert!(err("0 1000 1000", "0 1\n0 0\n0 0", 3).contains("2 directions"));
        assert!(err("0 x 1000", "", 3).contains("'x' is not a number"));
        assert!(err("0 1000 1000", "0 1 0\n0 0\n0 0 1", 3).contains("line 2"));
        assert!(err("1000 1000", "1 0\n0 1\n0 0", 2).contains("no b=0 volume"));
        assert!(err("0 1000", "0 0\n0 0\n0 0", 2).contains("zero-length"));
        assert!(err("0 1000", "0 nan\n0 0\n0 0", 2).contains("not finite"));
        assert!(err("0 -1", "0 1\n0 0\n0 0", 2).contains("volume 1"));
        assert!(err("0 1\n0 1", "0 1\n0 0\n0 0", 2).contains("one row or one column"));
        assert!(err("", "", 2).contains("no numbers"));
    }
}
