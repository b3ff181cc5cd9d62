//! Streamlines drawn with the glyphs (`--tracks`): each streamline a tube of one radius,
//! ray-cast in the glyphs' depth buffer, so that tubes and lobes hide each other where
//! they are in front (one picture, one depth test, where two renderers' images composited
//! could not agree).
//!
//! A tube is the chain of capsules of its segments: the points within the radius of the
//! polyline. Consecutive capsules share the sphere about their common point, so the tube
//! has no gap and no bulge at a bend (the union is exactly the polyline swept by a ball).
//! The capsules are the fibre peaks' (`glyphcast::render::peaks`, whose float64
//! reference is `glyphcast::glyph::capsule`): one pass, one shader, one reference.
//!
//! The tractogram is in scanner RAS+ millimetres (`crate::io::tracks`), the frame the
//! glyphs of NIfTI and MRtrix volumes are placed in. On a slice view only the parts
//! within `slab` millimetres of a slice's plane are drawn (as mrview crops tracks to a
//! slab); a block view draws them whole.
use std::str::FromStr;
use std::sync::Arc;

use glam::DVec3;
use glyphcast::error::quoted;
use glyphcast::glyph::capsule::Capsule;
use glyphcast::render::peaks::{PeakSegment, PeakSet};
use glyphcast::{Error, Result};

use super::peaks::PeaksColor;
use crate::io::nifti::VoxelToWorld;
use crate::io::tracks::Tractogram;
use crate::io::tracks::select::{Plane, slab};
use crate::setting::DmriSetting;
use crate::volume::SliceRegion;

/// The tubes' radius when none is given, in millimetres: thin beside a 2 mm voxel's
/// glyph, a few pixels wide in a slice of a brain.
pub const DEFAULT_TRACKS_RADIUS_MM: f64 = 0.15;

/// How the tubes are coloured.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum TracksColor {
    /// By the local direction of each segment, |x|, |y|, |z| as red, green, blue (the
    /// colouring of mrview, TrackVis and DIPY).
    #[default]
    Direction,
    /// One sRGB colour, each channel 0 to 1.
    Uniform([f64; 3]),
}

impl FromStr for TracksColor {
    type Err = Error;

    /// `direction`, a colour name, `#rrggbb` or `r,g,b` (0-255), as the peaks' colour.
    fn from_str(text: &str) -> Result<Self> {
        match text.parse::<PeaksColor>() {
            Ok(PeaksColor::Direction) => Ok(TracksColor::Direction),
            Ok(PeaksColor::Uniform(rgb)) => Ok(TracksColor::Uniform(rgb)),
            Err(_) => Err(Error::setting_value(
                DmriSetting::TracksColor,
                format!("'{}'", quoted(text)),
                "expected direction, a colour name, #rrggbb or r,g,b (0-255)",
            )),
        }
    }
}

/// What a streamline is drawn as.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum TrackShape {
    /// Tubes ray-cast exactly: capsules whose surfaces and the glyphs' hide each other
    /// pixel by pixel.
    #[default]
    Tubes,
    /// Lines: flat ribbons of the tubes' width on the screen (at least a pixel), at the
    /// depth of the streamline, unlit; depth-tested before shading, the affordable way
    /// to draw a whole brain's overlapping streamlines on a CPU driver.
    Lines,
}

impl FromStr for TrackShape {
    type Err = Error;

    fn from_str(text: &str) -> Result<Self> {
        match text {
            "tubes" => Ok(TrackShape::Tubes),
            "lines" => Ok(TrackShape::Lines),
            _ => Err(Error::setting_value(
                DmriSetting::TracksStyle,
                format!("'{}'", quoted(text)),
                "expected tubes or lines",
            )),
        }
    }
}

/// How a view draws its tractogram.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrackStyle {
    /// The tubes' radius, millimetres (the lines' width on the screen is the tubes').
    pub radius: f64,
    /// Tubes or lines.
    pub shape: TrackShape,
    /// Their colour.
    pub color: TracksColor,
    /// On a slice view, the distance from a slice's plane within which parts of
    /// streamlines are drawn, millimetres; `None` draws them whole.
    pub slab: Option<f64>,
}

impl Default for TrackStyle {
    fn default() -> Self {
        TrackStyle {
            radius: DEFAULT_TRACKS_RADIUS_MM,
            shape: TrackShape::Tubes,
            color: TracksColor::Direction,
            slab: None,
        }
    }
}

impl TrackStyle {
    /// Checks the radius and the slab.
    pub fn validate(&self) -> Result<()> {
        if !(self.radius.is_finite() && self.radius > 0.0) {
            return Err(Error::setting_value(
                DmriSetting::TracksRadius,
                self.radius,
                "must be a positive number of millimetres",
            ));
        }
        if let Some(slab) = self.slab
            && !(slab.is_finite() && slab > 0.0)
        {
            return Err(Error::setting_value(
                DmriSetting::Slab,
                slab,
                "must be a positive number of millimetres",
            ));
        }
        Ok(())
    }
}

/// A tractogram a view draws, and how.
#[derive(Clone, Debug)]
pub struct ViewTracks {
    /// The streamlines (already subsampled), shared by a montage's panels.
    pub tractogram: Arc<Tractogram>,
    /// Radius, colour and slab.
    pub style: TrackStyle,
}

/// The tubes of `tractogram`: one capsule per segment (a one-point streamline is a
/// ball), coloured as `style` asks; with [`TrackShape::Lines`] the same capsules as the
/// set's lines.
pub fn tube_set(tractogram: &Tractogram, style: &TrackStyle) -> PeakSet {
    let point = |k: usize| DVec3::from(tractogram.points[k].map(f64::from));
    let mut segments = Vec::with_capacity(tractogram.points.len());
    for index in 0..tractogram.len() {
        let range = tractogram.range(index);
        if range.len() == 1 {
            let p = point(range.start);
            segments.push(PeakSegment {
                capsule: Capsule {
                    a: p,
                    b: p,
                    radius: style.radius,
                },
                color: color_of(style.color, DVec3::ZERO),
            });
        }
        for k in range.start..range.end.saturating_sub(1) {
            let (a, b) = (point(k), point(k + 1));
            segments.push(PeakSegment {
                capsule: Capsule {
                    a,
                    b,
                    radius: style.radius,
                },
                color: color_of(style.color, b - a),
            });
        }
    }
    match style.shape {
        TrackShape::Tubes => PeakSet {
            segments,
            lines: Vec::new(),
        },
        TrackShape::Lines => PeakSet {
            segments: Vec::new(),
            lines: segments,
        },
    }
}

fn color_of(color: TracksColor, step: DVec3) -> [f64; 3] {
    match color {
        TracksColor::Uniform(rgb) => rgb,
        TracksColor::Direction => step
            .try_normalize()
            .map_or([1.0, 1.0, 1.0], |d| d.abs().to_array()),
    }
}

/// The tubes a view draws: on a slice view with a slab, the parts within the slab of
/// any of its slices' planes (`regions`, placed by `map`); else every streamline.
pub fn view_tubes(
    tracks: &ViewTracks,
    regions: &[SliceRegion],
    block: bool,
    map: &VoxelToWorld,
) -> Result<PeakSet> {
    tracks.style.validate()?;
    let slab_mm = match tracks.style.slab {
        Some(slab_mm) if !block => slab_mm,
        _ => return Ok(tube_set(&tracks.tractogram, &tracks.style)),
    };
    let mut tubes = PeakSet::default();
    for region in regions {
        let axis = region.slice.voxel_axis();
        let mut index = DVec3::ZERO;
        index[axis] = region.index as f64;
        let origin = map.voxel_center(index);
        // The plane's normal: perpendicular to the slice's two in-plane voxel axes.
        let linear = map.linear();
        let (u, v) = (linear.col((axis + 1) % 3), linear.col((axis + 2) % 3));
        let plane = Plane::new(origin, u.cross(v)).ok_or_else(|| {
            Error::setting_value(
                DmriSetting::Slab,
                slab_mm,
                "needs a slice plane, and the volume's affine gives none",
            )
        })?;
        let part = slab(&tracks.tractogram, &plane, slab_mm);
        tubes.extend(tube_set(&part, &tracks.style));
    }
    Ok(tubes)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tractogram(lines: &[&[[f32; 3]]]) -> Tractogram {
        let mut points = Vec::new();
        let mut offsets = Vec::new();
        for line in lines {
            offsets.push(points.len() as u64);
            points.extend_from_slice(line);
        }
        Tractogram {
            points,
            offsets,
            point_values: Vec::new(),
        }
    }

    #[test]
    fn each_segment_is_a_capsule_coloured_by_its_direction() {
        let t = tractogram(&[
            &[[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [2.0, 3.0, 0.0]],
            &[[5.0, 5.0, 5.0]],
        ]);
        let tubes = tube_set(&t, &TrackStyle::default());
        assert_eq!(tubes.segments.len(), 3);
        let first = tubes.segments[0];
        assert_eq!(first.capsule.b, DVec3::new(2.0, 0.0, 0.0));
        assert_eq!(first.capsule.radius, DEFAULT_TRACKS_RADIUS_MM);
        assert_eq!(first.color, [1.0, 0.0, 0.0]);
        assert_eq!(tubes.segments[1].color, [0.0, 1.0, 0.0]);
        // Consecutive capsules share their end: the tube is closed at the bend.
        assert_eq!(tubes.segments[0].capsule.b, tubes.segments[1].capsule.a);
        // A one-point streamline is a ball.
        let ball = tubes.segments[2].capsule;
        assert_eq!(ball.a, ball.b);
        let uniform = TrackStyle {
            color: "1,2,3".parse().expect("a colour"),
            ..TrackStyle::default()
        };
        assert!(
            tube_set(&t, &uniform)
                .segments
                .iter()
                .all(|s| s.color == tubes_uniform())
        );
        fn tubes_uniform() -> [f64; 3] {
            [1.0 / 255.0, 2.0 / 255.0, 3.0 / 255.0]
        }
    }

    #[test]
    fn bad_styles_are_refused_naming_the_setting() {
        let radius = TrackStyle {
            radius: 0.0,
            ..TrackStyle::default()
        };
        assert!(
            radius
                .validate()
                .unwrap_err()
                .to_string()
                .contains("tracks radius")
        );
        let slab = TrackStyle {
            slab: Some(f64::NAN),
            ..TrackStyle::default()
        };
        assert!(slab.validate().unwrap_err().to_string().contains("slab"));
        let color = "purple-ish".parse::<TracksColor>().unwrap_err();
        assert!(color.to_string().contains("tracks colour"), "{color}");
    }
}
