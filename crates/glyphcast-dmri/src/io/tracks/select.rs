//! Choosing what of a tractogram to draw: a uniform subsample of the streamlines, and the
//! parts of them within a slab about a plane (what a slice of glyphs shows).
//!
//! The slab clips each segment exactly to the slab (the line between two points is what
//! a renderer draws), so a streamline that leaves and comes back becomes two, and the
//! new end points lie on the slab's faces, their per-point values interpolated along the
//! segment. Points inside are kept as they are, bit for bit.
use glam::DVec3;

use super::{Tractogram, TractogramBuilder};

/// A plane in RAS+ millimetres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    origin: DVec3,
    unit_normal: DVec3,
}

impl Plane {
    /// The plane through `origin` perpendicular to `normal` (any length); None when the
    /// normal is zero or not finite.
    pub fn new(origin: DVec3, normal: DVec3) -> Option<Self> {
        let unit_normal = normal.try_normalize()?;
        origin.is_finite().then_some(Self {
            origin,
            unit_normal,
        })
    }

    /// Signed distance of `point` from the plane, in millimetres.
    pub fn distance(&self, point: [f32; 3]) -> f64 {
        (DVec3::from(point.map(f64::from)) - self.origin).dot(self.unit_normal)
    }
}

/// Every k-th streamline, k the smallest that leaves at most `max_streamlines`
/// (all of them when there are no more than that; none when it is 0).
pub fn subsample(tractogram: &Tractogram, max_streamlines: usize) -> Tractogram {
    let mut builder = builder_like(tractogram);
    if max_streamlines == 0 {
        return builder.finish();
    }
    let step = tractogram.len().div_ceil(max_streamlines).max(1);
    for index in (0..tractogram.len()).step_by(step) {
        builder.start();
        for point in tractogram.range(index) {
            builder.push(tractogram.points[point], &values_at(tractogram, point));
        }
    }
    builder.finish()
}

/// The parts of the streamlines within `half_width_mm` of `plane`, each segment clipped
/// to the slab; a streamline is split where it leaves the slab. A one-point streamline
/// is kept when its point is inside; a part that only touches a face (one point) is not.
pub fn slab(tractogram: &Tractogram, plane: &Plane, half_width_mm: f64) -> Tractogram {
    let mut builder = builder_like(tractogram);
    for index in 0..tractogram.len() {
        let range = tractogram.range(index);
        let inside = |point: usize| plane.distance(tractogram.points[point]).abs() <= half_width_mm;
        if range.len() == 1 {
            if inside(range.start) {
                builder.start();
                builder.push(
                    tractogram.points[range.start],
                    &values_at(tractogram, range.start),
                );
            }
            continue;
        }
        let mut run = Run::default();
        for a in range.start..range.end.saturating_sub(1) {
            let b = a + 1;
            let Some((lo, hi)) = clip(plane, tractogram, a, b, half_width_mm) else {
                run.close(&mut builder);
                continue;
            };
            let (lo, hi) = (
                if inside(a) { 0.0 } else { lo },
                if inside(b) { 1.0 } else { hi },
            );
            if !(run.open && lo == 0.0) {
                run.close(&mut builder);
                run.push(interpolate(tractogram, a, b, lo));
            }
            run.push(interpolate(tractogram, a, b, hi));
            if !inside(b) {
                run.close(&mut builder);
            }
        }
        run.close(&mut builder);
    }
    builder.finish()
}

/// The part of segment a-b within the slab, as the interval of t (0 at a, 1 at b).
fn clip(
    plane: &Plane,
    tractogram: &Tractogram,
    a: usize,
    b: usize,
    half_width: f64,
) -> Option<(f64, f64)> {
    let (da, db) = (
        plane.distance(tractogram.points[a]),
        plane.distance(tractogram.points[b]),
    );
    let change = db - da;
    if change == 0.0 {
        return (da.abs() <= half_width).then_some((0.0, 1.0));
    }
    let (enter, leave) = ((-half_width - da) / change, (half_width - da) / change);
    let lo = enter.min(leave).max(0.0);
    let hi = enter.max(leave).min(1.0);
    (lo <= hi).then_some((lo, hi))
}

/// The point at t along segment a-b and its values; t = 0 and 1 give a and b exactly.
fn interpolate(tractogram: &Tractogram, a: usize, b: usize, t: f64) -> ([f32; 3], Vec<f32>) {
    if t == 0.0 {
        return (tractogram.points[a], values_at(tractogram, a));
    }
    if t == 1.0 {
        return (tractogram.points[b], values_at(tractogram, b));
    }
    let mix = |x: f32, y: f32| (f64::from(x) + t * (f64::from(y) - f64::from(x))) as f32;
    let (pa, pb) = (tractogram.points[a], tractogram.points[b]);
    let point = [mix(pa[0], pb[0]), mix(pa[1], pb[1]), mix(pa[2], pb[2])];
    let values = values_at(tractogram, a)
        .into_iter()
        .zip(values_at(tractogram, b))
        .map(|(x, y)| mix(x, y))
        .collect();
    (point, values)
}

/// A part of a streamline being collected; written out when it holds two points or more.
#[derive(Default)]
struct Run {
    open: bool,
    points: Vec<([f32; 3], Vec<f32>)>,
}

impl Run {
    /// Appends a point, unless it repeats the last (a part that only touches a face).
    fn push(&mut self, point: ([f32; 3], Vec<f32>)) {
        self.open = true;
        if self.points.last().is_none_or(|last| last.0 != point.0) {
            self.points.push(point);
        }
    }

    fn close(&mut self, builder: &mut TractogramBuilder) {
        if self.points.len() >= 2 {
            builder.start();
            for (point, values) in &self.points {
                builder.push(*point, values);
            }
        }
        self.points.clear();
        self.open = false;
    }
}

fn builder_like(tractogram: &Tractogram) -> TractogramBuilder {
    TractogramBuilder::with_point_values(
        tractogram
            .point_values
            .iter()
            .map(|quantity| (quantity.name.clone(), quantity.width)),
    )
}

/// Every quantity's values at `point`, concatenated in order.
fn values_at(tractogram: &Tractogram, point: usize) -> Vec<f32> {
    tractogram
        .point_values
        .iter()
        .flat_map(|quantity| {
            quantity.values[point * quantity.width..(point + 1) * quantity.width]
                .iter()
                .copied()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::tracks::PointValues;

    /// Streamlines given as lists of z values at x = y = 0, with z itself as a scalar.
    fn along_z(streamlines: &[&[f32]]) -> Tractogram {
        let mut builder = TractogramBuilder::with_point_values([("z".to_string(), 1)]);
        for streamline in streamlines {
            builder.start();
            for &z in *streamline {
                builder.push([0.0, 0.0, z], &[z]);
            }
        }
        builder.finish()
    }

    fn zs(tractogram: &Tractogram) -> Vec<Vec<f32>> {
        tractogram
            .streamlines()
            .map(|s| s.iter().map(|p| p[2]).collect())
            .collect()
    }

    #[test]
    fn subsample_keeps_every_kth_up_to_the_maximum() {
        let lines: Vec<Vec<f32>> = (0..10).map(|i| vec![i as f32, i as f32 + 0.5]).collect();
        let refs: Vec<&[f32]> = lines.iter().map(Vec::as_slice).collect();
        let tractogram = along_z(&refs);
        let firsts = |t: &Tractogram| zs(t).iter().map(|s| s[0]).collect::<Vec<_>>();
        assert_eq!(firsts(&subsample(&tractogram, 4)), [0.0, 3.0, 6.0, 9.0]);
        assert_eq!(
            firsts(&subsample(&tractogram, 5)),
            [0.0, 2.0, 4.0, 6.0, 8.0]
        );
        assert_eq!(subsample(&tractogram, 10), tractogram);
        assert_eq!(subsample(&tractogram, 100), tractogram);
        assert!(subsample(&tractogram, 0).is_empty());
        let three = subsample(&tractogram, 3);
        assert_eq!(firsts(&three), [0.0, 4.0, 8.0]);
        // Offsets and values follow the kept streamlines.
        assert_eq!(three.offsets, [0, 2, 4]);
        assert_eq!(three.point_values[0].values, [0.0, 0.5, 4.0, 4.5, 8.0, 8.5]);
    }

    #[test]
    fn slab_clips_segments_to_the_faces_and_splits_where_a_streamline_leaves() {
        let plane = Plane::new(DVec3::ZERO, DVec3::new(0.0, 0.0, 2.0)).unwrap();
        // In, out, back in: two parts, ends on the faces at z = +-1.
        let tractogram = along_z(&[&[-0.5, 0.5, 3.0, 0.0, -0.25]]);
        let cut = slab(&tractogram, &plane, 1.0);
        assert_eq!(zs(&cut), [vec![-0.5, 0.5, 1.0], vec![1.0, 0.0, -0.25]]);
        // The scalar is interpolated with the point (here it is z itself).
        assert_eq!(
            cut.point_values,
            [PointValues {
                name: "z".to_string(),
                width: 1,
                values: vec![-0.5, 0.5, 1.0, 1.0, 0.0, -0.25],
            }]
        );
        assert_eq!(cut.offsets, [0, 3]);
    }

    #[test]
    fn slab_keeps_crossings_and_drops_what_only_touches() {
        let plane = Plane::new(DVec3::new(0.0, 0.0, 10.0), DVec3::Z).unwrap();
        let tractogram = along_z(&[
            // Crosses the slab in one segment: the part between the faces.
            &[0.0, 20.0],
            // Wholly outside.
            &[12.0, 15.0],
            // Touches the face z = 11 at one point only.
            &[11.0, 14.0],
            // One point, inside: kept.
            &[10.5],
            // One point, outside: dropped.
            &[30.0],
            // Wholly inside: kept bit for bit.
            &[9.25, 10.0, 10.75],
        ]);
        let cut = slab(&tractogram, &plane, 1.0);
        assert_eq!(
            zs(&cut),
            [vec![9.0, 11.0], vec![10.5], vec![9.25, 10.0, 10.75]]
        );
    }

    #[test]
    fn a_plane_needs_a_direction() {
        assert!(Plane::new(DVec3::ZERO, DVec3::ZERO).is_none());
        assert!(Plane::new(DVec3::ZERO, DVec3::new(f64::NAN, 0.0, 1.0)).is_none());
    }
}
