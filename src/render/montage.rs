//! Montages (`--views`, `--lightbox`): panels, each rendered on its own as a single view,
//! laid out in a grid of equal cells in reading order. The render command composes the
//! read-back panels here; the viewer draws each panel into the same cell of its window
//! ([`Grid::cell_origin`]) and composes its screenshots here, so both put every panel at
//! the same pixels.
//!
//! Panels share one magnitude range ([`shared_magnitude_range`]) so that colours compare
//! across them.
use crate::error::{Error, Result};
use crate::render::colorbar::srgb_byte;
use crate::render::glyph_data::GlyphSetData;
use crate::render::headless::RenderedImage;
use crate::render::settings::{ColorMode, RenderSettings};
use crate::volume::MAX_SIDE;

/// Cells of `cell` pixels, `columns` to a row, filled in reading order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Grid {
    /// Width and height of a cell.
    pub cell: (u32, u32),
    /// Cells per row (at least 1).
    pub columns: usize,
    /// Rows (at least 1).
    pub rows: usize,
}

impl Grid {
    /// The grid of `panels` panels, `columns` to a row (clamped to 1..=panels).
    pub fn new(cell: (u32, u32), columns: usize, panels: usize) -> Grid {
        let columns = columns.clamp(1, panels.max(1));
        Grid {
            cell,
            columns,
            rows: panels.max(1).div_ceil(columns),
        }
    }

    /// Width and height of the whole grid, each at most [`MAX_SIDE`] (a usage error
    /// otherwise).
    pub fn size(&self) -> Result<(u32, u32)> {
        let width = u64::from(self.cell.0) * self.columns as u64;
        let height = u64::from(self.cell.1) * self.rows as u64;
        if width > u64::from(MAX_SIDE) || height > u64::from(MAX_SIDE) {
            return Err(Error::Usage(format!(
                "the montage would be {width}x{height} pixels; at most {MAX_SIDE} a side: \
                 give a smaller --width/--height"
            )));
        }
        Ok((width as u32, height as u32))
    }

    /// The top-left pixel of cell `k`.
    pub fn cell_origin(&self, k: usize) -> (u32, u32) {
        (
            (k % self.columns) as u32 * self.cell.0,
            (k / self.columns) as u32 * self.cell.1,
        )
    }
}

/// The pixels and depth map of a montage being assembled: background with NaN depth
/// where no panel is placed.
pub struct Montage {
    grid: Grid,
    image: RenderedImage,
}

impl Montage {
    /// An image of `width` x `height` pixels (at least the grid's size, see
    /// [`Grid::size`]), all `background` (linear RGBA, as the renderer clears to it).
    pub fn new(grid: Grid, width: u32, height: u32, background: [f32; 4]) -> Montage {
        let clear = background_bytes(background);
        let pixels = width as usize * height as usize;
        Montage {
            grid,
            image: RenderedImage {
                width,
                height,
                rgba: clear.iter().copied().cycle().take(4 * pixels).collect(),
                distance: vec![f32::NAN; pixels],
                draws: 0,
                gpu_ms: None,
                mesh: None,
            },
        }
    }

    /// Copies `panel` into cell `k`, centred (a panel smaller than the cell keeps
    /// background margins; the part of one that does not fit the image is left out).
    pub fn place(&mut self, k: usize, panel: &RenderedImage) {
        let (cw, ch) = self.grid.cell;
        let (cell_x, cell_y) = self.grid.cell_origin(k);
        let x0 = (cell_x + (cw - panel.width.min(cw)) / 2) as usize;
        let y0 = (cell_y + (ch - panel.height.min(ch)) / 2) as usize;
        let out = &mut self.image;
        let (width, height) = (out.width as usize, out.height as usize);
        let w = (panel.width as usize).min(width.saturating_sub(x0));
        for row in 0..(panel.height as usize).min(height.saturating_sub(y0)) {
            let to = (y0 + row) * width + x0;
            let from = row * panel.width as usize;
            out.rgba[4 * to..4 * (to + w)].copy_from_slice(&panel.rgba[4 * from..4 * (from + w)]);
            out.distance[to..to + w].copy_from_slice(&panel.distance[from..from + w]);
        }
        out.draws += panel.draws;
    }

    /// The assembled image.
    pub fn finish(self) -> RenderedImage {
        self.image
    }
}

/// `settings` for every panel of a montage: `--color magnitude` without a range maps one
/// range, 0 to the largest glyph radius of all panels (`sets`, measured with
/// [`crate::render::glyph_data::measure_largest_radius`]), so that colours compare across
/// panels; other settings are returned as they are.
pub fn shared_magnitude_range<'a>(
    settings: &RenderSettings,
    sets: impl IntoIterator<Item = &'a GlyphSetData>,
) -> RenderSettings {
    if !settings.needs_largest_radius() {
        return *settings;
    }
    let largest = sets
        .into_iter()
        .map(|s| s.largest_radius)
        .fold(0.0, f64::max);
    RenderSettings {
        color: ColorMode::Magnitude {
            range: Some((0.0, largest as f32)),
        },
        ..*settings
    }
}

/// The PNG bytes of a background (linear RGBA), as the renderer clears to it.
pub fn background_bytes(background: [f32; 4]) -> [u8; 4] {
    let [r, g, b, a] = background;
    [
        srgb_byte(r),
        srgb_byte(g),
        srgb_byte(b),
        (a.clamp(0.0, 1.0) * 255.0).round() as u8,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn panel(width: u32, height: u32, value: u8) -> RenderedImage {
        let pixels = (width * height) as usize;
        RenderedImage {
            width,
            height,
            rgba: vec![value; 4 * pixels],
            distance: vec![f32::from(value); pixels],
            draws: 1,
            gpu_ms: None,
            mesh: None,
        }
    }

    #[test]
    fn panels_fill_their_cells_in_reading_order() {
        let grid = Grid::new((4, 3), 2, 3);
        assert_eq!((grid.columns, grid.rows), (2, 2));
        assert_eq!(grid.size().unwrap(), (8, 6));
        assert_eq!(grid.cell_origin(2), (0, 3));
        let mut montage = Montage::new(grid, 8, 6, [0.0; 4]);
        montage.place(1, &panel(4, 3, 9));
        // A smaller panel is centred in its cell.
        montage.place(2, &panel(2, 1, 7));
        let image = montage.finish();
        let at = |x: usize, y: usize| image.rgba[4 * (y * 8 + x)];
        assert_eq!((at(3, 0), at(4, 0), at(7, 2)), (0, 9, 9));
        assert_eq!((at(0, 4), at(1, 4), at(2, 4), at(3, 4)), (0, 7, 7, 0));
        assert!(image.distance[0].is_nan() && image.distance[5] == 9.0);
        assert_eq!(image.draws, 2);
    }

    #[test]
    fn too_large_a_grid_is_a_usage_error() {
        let grid = Grid::new((MAX_SIDE, 10), 2, 2);
        assert!(matches!(grid.size(), Err(Error::Usage(_))));
    }
}
