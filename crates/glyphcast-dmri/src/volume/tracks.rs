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
use glyphcast::render::compose::colorbar::viridis_srgb8;
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
    /// By a value stored per point (a TrackVis scalar, a TRX `dpv`), mapped through
    /// viridis over its range in the tractogram; resolved against the tractogram by
    /// [`ScalarColor::of`] (`scalar[:NAME]` as text).
    Scalar(ScalarColor),
}

/// A per-point value's colour map: which of the tractogram's point values, and the
/// range that viridis spans (its darkest blue at `low`, its yellow at `high`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScalarColor {
    /// Index into the tractogram's `point_values`.
    pub index: usize,
    /// The smallest finite value of the tractogram.
    pub low: f64,
    /// The largest.
    pub high: f64,
}

/// The name asked for by a colour's text `scalar` (`Some(None)`: the first per-point
/// value) or `scalar:NAME` (`Some(Some(NAME))`); None for any other text.
pub fn scalar_request(text: &str) -> Option<Option<&str>> {
    match text.split_once(':') {
        None if text == "scalar" => Some(None),
        Some(("scalar", name)) => Some(Some(name)),
        _ => None,
    }
}

impl ScalarColor {
    /// The colour map of the per-point value `name` of `tractogram` (the first value of
    /// one number per point when `name` is None), over its finite values' range. A
    /// tractogram without that value, one that stores several numbers per point, or
    /// one without a finite value is refused naming the setting and `file`.
    pub fn of(tractogram: &Tractogram, name: Option<&str>, file: &str) -> Result<ScalarColor> {
        let asked = name.map_or("scalar".to_owned(), |n| format!("scalar:{n}"));
        let refuse = |why: String| {
            Error::setting_value(
                DmriSetting::TracksColor,
                format!("'{}'", quoted(&asked)),
                format!("{file}: {why}"),
            )
        };
        let names: Vec<&str> = tractogram
            .point_values
            .iter()
            .map(|v| v.name.as_str())
            .collect();
        let found = match name {
            Some(name) => tractogram.point_values.iter().position(|v| v.name == name),
            None => tractogram.point_values.iter().position(|v| v.width == 1),
        };
        let Some(index) = found else {
            return Err(refuse(match names.is_empty() {
                true => "the tractogram stores no value per point (TrackVis scalars, TRX \
                         dpv)"
                    .to_owned(),
                false => format!(
                    "no per-point value of that name with one number per point; it has {}",
                    names.join(", ")
                ),
            }));
        };
        let values = &tractogram.point_values[index];
        if values.width != 1 {
            return Err(refuse(format!(
                "'{}' holds {} numbers per point, not one",
                values.name, values.width
            )));
        }
        let finite = values.values.iter().filter(|v| v.is_finite());
        let (low, high) = finite.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(f64::from(v)), hi.max(f64::from(v)))
        });
        if low > high {
            return Err(refuse(format!("'{}' has no finite value", values.name)));
        }
        Ok(ScalarColor { index, low, high })
    }

    /// The sRGB colour (0 to 1) of `value`: viridis at its place in the range (the
    /// middle when the range is one value); grey where it is not finite.
    pub fn color(&self, value: f64) -> [f64; 3] {
        if !value.is_finite() {
            return [0.5; 3];
        }
        let t = match self.high > self.low {
            true => (value - self.low) / (self.high - self.low),
            false => 0.5,
        };
        viridis_srgb8(t.clamp(0.0, 1.0) as f32).map(|c| f64::from(c) / 255.0)
    }
}

impl FromStr for TracksColor {
    type Err = Error;

    /// `direction`, a colour name, `#rrggbb` or `r,g,b` (0-255), as the peaks' colour
    /// (`scalar[:NAME]` needs the tractogram: [`ScalarColor::of`]).
    fn from_str(text: &str) -> Result<Self> {
        match text.parse::<PeaksColor>() {
            Ok(PeaksColor::Direction) => Ok(TracksColor::Direction),
            Ok(PeaksColor::Uniform(rgb)) => Ok(TracksColor::Uniform(rgb)),
            Err(_) => Err(Error::setting_value(
                DmriSetting::TracksColor,
                format!("'{}'", quoted(text)),
                "expected direction, scalar[:NAME], a colour name, #rrggbb or r,g,b (0-255)",
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
    // A segment's value: the mean of its ends' (a scalar colour's).
    let value = |k: usize, next: usize| match style.color {
        TracksColor::Scalar(scalar) => {
            tractogram
                .point_values
                .get(scalar.index)
                .map_or(f64::NAN, |v| {
                    let at = |i: usize| v.values.get(i).map_or(f64::NAN, |&x| f64::from(x));
                    0.5 * (at(k) + at(next))
                })
        }
        _ => f64::NAN,
    };
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
                color: color_of(style.color, DVec3::ZERO, value(range.start, range.start)),
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
                color: color_of(style.color, b - a, value(k, k + 1)),
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

fn color_of(color: TracksColor, step: DVec3, value: f64) -> [f64; 3] {
    match color {
        TracksColor::Uniform(rgb) => rgb,
        TracksColor::Scalar(scalar) => scalar.color(value),
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

    /// `scalar:NAME` maps each segment's mean value through viridis over the
    /// tractogram's range; a name not stored, a value of three numbers per point and a
    /// tractogram without values are refused naming the option and the file.
    #[test]
    fn scalar_colours_follow_the_values_over_their_range() {
        use crate::io::tracks::PointValues;
        let mut t = Tractogram::default();
        t.offsets.push(0);
        t.points = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]];
        t.point_values = vec![
            PointValues {
                name: "rgb".into(),
                width: 3,
                values: vec![0.0; 9],
            },
            PointValues {
                name: "fa".into(),
                width: 1,
                values: vec![0.2, 0.4, f32::NAN],
            },
        ];
        assert_eq!(scalar_request("scalar"), Some(None));
        assert_eq!(scalar_request("scalar:fa"), Some(Some("fa")));
        assert_eq!(scalar_request("direction"), None);
        let scalar = ScalarColor::of(&t, Some("fa"), "t.trk").expect("fa");
        assert_eq!((scalar.index, scalar.low), (1, 0.2f32 as f64));
        // `scalar` alone: the first value of one number per point.
        assert_eq!(ScalarColor::of(&t, None, "t.trk").expect("first").index, 1);
        let style = TrackStyle {
            color: TracksColor::Scalar(scalar),
            ..TrackStyle::default()
        };
        let tubes = tube_set(&t, &style);
        let viridis = |x: f32| viridis_srgb8(x).map(|c| f64::from(c) / 255.0);
        // The first segment's mean (0.3) is the middle of 0.2..0.4; the second has a
        // NaN end: grey.
        assert_eq!(tubes.segments[0].color, viridis(0.5));
        assert_eq!(tubes.segments[1].color, [0.5; 3]);
        assert_eq!(scalar.color(0.2f32 as f64), viridis(0.0));
        assert_eq!(scalar.color(0.4f32 as f64), viridis(1.0));
        for (name, words) in [
            (Some("md"), "no per-point value of that name"),
            (Some("rgb"), "3 numbers per point"),
        ] {
            let err = ScalarColor::of(&t, name, "t.trk").unwrap_err().to_string();
            assert!(
                err.contains("tracks colour") && err.contains("t.trk") && err.contains(words),
                "{err}"
            );
        }
        t.point_values.clear();
        let err = ScalarColor::of(&t, None, "t.tck").unwrap_err().to_string();
        assert!(err.contains("stores no value per point"), "{err}");
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
