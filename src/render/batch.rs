//! Glyph sets grouped into draws. Every glyph set that shares a pipeline (tensor layout
//! and shape) and a negative mode is drawn by the same instanced draw from the same buffers, so a
//! scene of ten thousand one-glyph sets costs one draw, not ten thousand; a group larger
//! than one storage buffer is cut into several batches. The ray-casting pass and the
//! compute path both upload batches.
use std::borrow::Cow;
use std::ops::Range;

use crate::glyph::pieces::{PIECE_WORDS, polytope_piece_words};
use crate::glyph::{GlyphShape, NegativeMode, TensorLayout};
use crate::render::glyph_data::GlyphSetData;
use crate::{Error, Result};

/// Glyphs of one or more sets that share a layout and a negative mode, drawn together.
#[derive(Clone, Debug)]
pub(crate) struct Batch<'a> {
    /// The tensor layout every glyph of the batch shares.
    pub layout: TensorLayout,
    /// The negative mode every glyph of the batch shares.
    pub negative: NegativeMode,
    /// The shape every glyph of the batch shares: ellipsoids have their own shader.
    pub shape: GlyphShape,
    /// The glyph ranges of the sets this batch draws, in order.
    pieces: Vec<(&'a GlyphSetData, Range<usize>)>,
    len: usize,
}

impl<'a> Batch<'a> {
    /// Glyphs in the batch.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether the batch has no glyph.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Per glyph: centre and bounding-sphere radius ([`GlyphSetData::instances`]).
    pub fn instances(&self) -> Result<Cow<'a, [[f32; 4]]>> {
        self.gather(1, |d| &d.instances)
    }

    /// Per glyph: the oriented box ([`GlyphSetData::boxes`]).
    pub fn boxes(&self) -> Result<Cow<'a, [[f32; 8]]>> {
        self.gather(1, |d| &d.boxes)
    }

    /// Per glyph: the extents along the box's diagonals ([`GlyphSetData::hulls`]).
    pub fn hulls(&self) -> Result<Cow<'a, [[f32; 12]]>> {
        self.gather(1, |d| &d.hulls)
    }

    /// Per glyph: the pieces' words ([`GlyphSetData::pieces`]; for a set without them,
    /// its 26-sided polytopes cut by their boxes' octants).
    pub fn piece_words(&self) -> Result<Cow<'a, [[u32; PIECE_WORDS]]>> {
        if self.pieces.iter().all(|(d, _)| d.pieces.len() == d.len()) {
            return self.gather(1, |d| &d.pieces);
        }
        let mut values = Vec::new();
        values
            .try_reserve_exact(self.len)
            .map_err(|_| Error::OutOfMemory {
                what: "the glyphs of one draw",
                file: None,
                bytes: Some((self.len * 4 * PIECE_WORDS) as u64),
                settings: &[],
            })?;
        for (data, range) in &self.pieces {
            let own = data.pieces.len() == data.len();
            values.extend(range.clone().map(|i| match own {
                true => data.pieces[i],
                false => polytope_piece_words(&data.boxes[i], &data.hulls[i]),
            }));
        }
        Ok(Cow::Owned(values))
    }

    /// The glyphs' float32 coefficients, `layout.coefficient_count()` per glyph (a plane
    /// glyph's T's after them).
    pub fn coefficients(&self) -> Result<Cow<'a, [f32]>> {
        let per_glyph = self
            .shape
            .coefficient_count(self.layout.coefficient_count());
        self.gather(per_glyph, |d| &d.coefficients)
    }

    /// The batch's entries of one per-glyph array, `per_glyph` values each: borrowed when
    /// the batch is one piece of one set, else copied into one allocation (made fallibly,
    /// so that a lack of memory is an error).
    fn gather<T: Clone>(
        &self,
        per_glyph: usize,
        field: impl Fn(&'a GlyphSetData) -> &'a [T],
    ) -> Result<Cow<'a, [T]>> {
        let slice = |(data, range): &(&'a GlyphSetData, Range<usize>)| {
            &field(data)[range.start * per_glyph..range.end * per_glyph]
        };
        if let [piece] = self.pieces.as_slice() {
            return Ok(Cow::Borrowed(slice(piece)));
        }
        let mut values = Vec::new();
        values
            .try_reserve_exact(self.len * per_glyph)
            .map_err(|_| Error::OutOfMemory {
                what: "the glyphs of one draw",
                file: None,
                bytes: Some((self.len * size_of::<T>()) as u64),
                settings: &[],
            })?;
        for piece in &self.pieces {
            values.extend_from_slice(slice(piece));
        }
        Ok(Cow::Owned(values))
    }
}

/// Groups the glyphs of `sets` into batches: one per layout, shape and negative mode (in the
/// order the sets first use them), cut so that no batch holds more than
/// `limit / glyph_bytes(layout, shape)` glyphs. A glyph larger than `limit` is an error naming
/// its set.
pub(crate) fn batches<'a>(
    sets: &'a [GlyphSetData],
    limit: u64,
    glyph_bytes: impl Fn(TensorLayout, GlyphShape) -> u64,
) -> Result<Vec<Batch<'a>>> {
    let mut groups: Vec<Vec<(usize, &'a GlyphSetData)>> = Vec::new();
    for (index, data) in sets.iter().enumerate().filter(|(_, d)| !d.is_empty()) {
        let key = |d: &GlyphSetData| (d.layout, d.shape, d.negative);
        match groups.iter_mut().find(|group| key(group[0].1) == key(data)) {
            Some(group) => group.push((index, data)),
            None => groups.push(vec![(index, data)]),
        }
    }
    let mut batches = Vec::new();
    for group in groups {
        let (first_index, first) = group[0];
        let bytes = glyph_bytes(first.layout, first.shape);
        let per_batch = (limit / bytes.max(1)).min(u32::MAX as u64) as usize;
        if per_batch == 0 {
            return Err(Error::Item {
                what: "glyph set",
                index: first_index,
                error: Box::new(Error::Limit {
                    what: "bytes of one glyph in a storage buffer",
                    value: bytes,
                    limit,
                    settings: &[],
                }),
            });
        }
        let empty = Batch {
            layout: first.layout,
            negative: first.negative,
            shape: first.shape,
            pieces: Vec::new(),
            len: 0,
        };
        let mut current = empty.clone();
        for (_, data) in group {
            let mut start = 0;
            while start < data.len() {
                let end = data.len().min(start + per_batch - current.len);
                current.pieces.push((data, start..end));
                current.len += end - start;
                start = end;
                if current.len == per_batch {
                    batches.push(std::mem::replace(&mut current, empty.clone()));
                }
            }
        }
        if !current.is_empty() {
            batches.push(current);
        }
    }
    Ok(batches)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::glyph::Symmetry;

    fn set(order: u32, negative: NegativeMode, glyphs: usize, first: f32) -> GlyphSetData {
        let layout = TensorLayout {
            order,
            symmetry: Symmetry::Symmetric,
        };
        let n = layout.coefficient_count();
        GlyphSetData {
            layout,
            negative,
            shape: GlyphShape::Polynomial,
            instances: (0..glyphs)
                .map(|i| [first + i as f32, 0.0, 0.0, 1.0])
                .collect(),
            boxes: vec![[0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0, 0.0]; glyphs],
            hulls: vec![[1.0; 12]; glyphs],
            pieces: Vec::new(),
            coefficients: (0..glyphs * n).map(|i| first + i as f32).collect(),
            world: Vec::new(),
            largest_radius: 0.0,
        }
    }

    #[test]
    fn sets_sharing_a_layout_and_mode_share_a_batch_in_set_order() {
        let sets = [
            set(4, NegativeMode::Abs, 2, 0.0),
            set(2, NegativeMode::Abs, 1, 100.0),
            set(4, NegativeMode::Abs, 3, 10.0),
            set(4, NegativeMode::Hide, 1, 20.0),
            set(4, NegativeMode::Abs, 0, 30.0),
            GlyphSetData {
                shape: GlyphShape::Ellipsoid,
                ..set(2, NegativeMode::Abs, 2, 40.0)
            },
        ];
        let batches = batches(&sets, u64::MAX, |_, _| 4).unwrap();
        let shape: Vec<_> = batches
            .iter()
            .map(|b| (b.layout.order, b.shape, b.negative, b.len()))
            .collect();
        let polynomial = GlyphShape::Polynomial;
        assert_eq!(
            shape,
            [
                (4, polynomial, NegativeMode::Abs, 5),
                (2, polynomial, NegativeMode::Abs, 1),
                (4, polynomial, NegativeMode::Hide, 1),
                (2, GlyphShape::Ellipsoid, NegativeMode::Abs, 2),
            ]
        );
        let x: Vec<f32> = batches[0]
            .instances()
            .unwrap()
            .iter()
            .map(|i| i[0])
            .collect();
        assert_eq!(x, [0.0, 1.0, 10.0, 11.0, 12.0]);
        let coefficients = batches[0].coefficients().unwrap();
        assert_eq!(coefficients.len(), 5 * 15);
        assert_eq!(coefficients[30], 10.0);
        assert!(matches!(
            batches[1].coefficients().unwrap(),
            Cow::Borrowed(_)
        ));
    }

    #[test]
    fn batches_are_cut_at_the_buffer_limit_across_sets() {
        let sets = [
            set(2, NegativeMode::Abs, 5, 0.0),
            set(2, NegativeMode::Abs, 4, 50.0),
        ];
        // 6 glyphs of 24 bytes fit a 150-byte buffer.
        let batches = batches(&sets, 150, |l, _| 4 * l.coefficient_count() as u64).unwrap();
        let lengths: Vec<_> = batches.iter().map(Batch::len).collect();
        assert_eq!(lengths, [6, 3]);
        let x: Vec<f32> = batches
            .iter()
            .flat_map(|b| {
                b.instances()
                    .unwrap()
                    .iter()
                    .map(|i| i[0])
                    .collect::<Vec<_>>()
            })
            .collect();
        assert_eq!(x, [0.0, 1.0, 2.0, 3.0, 4.0, 50.0, 51.0, 52.0, 53.0]);
        let coefficients = batches[1].coefficients().unwrap();
        assert_eq!(coefficients.len(), 3 * 6);
        assert_eq!(coefficients[0], 50.0 + 6.0);
        let too_small = super::batches(&sets, 20, |l, _| 4 * l.coefficient_count() as u64);
        assert!(too_small.unwrap_err().to_string().contains("glyph set 0"));
    }
}
