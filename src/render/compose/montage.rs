//! Montages (`--views`, `--lightbox`, the Python module's `views=`/`lightbox=`): panels,
//! each rendered on its own as a single view, laid out in a grid of equal cells (the
//! largest panel's size) in reading order, smaller panels centred, cells without a panel
//! background with NaN depth. The render command and the Python module prepare and draw
//! montages here ([`prepare_montage`]); the viewer draws each panel into the same cell of
//! its window ([`Grid::cell_origin`]) and composes its screenshots here ([`Montage`]), so
//! every front end puts every panel at the same pixels.
//!
//! Panels share one magnitude range ([`shared_magnitude_range`]) so that colours compare
//! across them.
use crate::Setting;
use crate::error::{Error, Result};
use crate::glyph::NegativeMode;
use crate::render::compose::colorbar::srgb_byte;
use crate::render::compose::figure::{Overlays, render_figure};
use crate::render::glyph_data::GlyphSetData;
use crate::render::headless::{FrameView, HeadlessRenderer, RenderedImage};
use crate::render::options::{PreparedScene, prepare_render};
use crate::render::settings::{ColorMode, RenderSettings};
use crate::render::underlay::Underlay;
use crate::scene::MAX_IMAGE_SIDE as MAX_SIDE;
use crate::scene::Scene;
use crate::vk::Gpu;

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
            return Err(Error::Limit {
                what: "montage side in pixels",
                value: width.max(height),
                limit: u64::from(MAX_SIDE),
                settings: &[Setting::Width, Setting::Height],
            });
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
                // Until a panel is placed: the path of an image no ray caster drew.
                path: crate::render::RenderPath::Fragment,
                passes: 1,
                culling: crate::render::Culling::Off,
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
        out.path = panel.path;
        out.passes = out.passes.max(panel.passes);
        if panel.culling != crate::render::Culling::Off {
            out.culling = panel.culling;
        }
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

/// The panels of a montage, prepared for rendering with one set of settings.
pub struct PreparedMontage {
    /// The panels, in reading order.
    pub panels: Vec<PreparedScene>,
    /// The settings every panel is drawn with (one magnitude range for all).
    pub settings: RenderSettings,
    /// Each panel's underlay, if any ([`PreparedMontage::with_underlays`]).
    underlays: Vec<Option<Underlay>>,
    /// Each panel's caption, if any ([`PreparedMontage::with_captions`]).
    captions: Vec<Option<String>>,
    grid: Grid,
}

/// Prepares the panels `scenes` (each sized already) for a grid of `columns` to a row,
/// drawn with `settings` and the negative-lobe mode `negative` if given (as
/// [`prepare_render`]); a usage error naming the size when the montage would be wider
/// or higher than an image can be.
pub fn prepare_montage(
    scenes: Vec<Scene>,
    columns: usize,
    settings: RenderSettings,
    negative: Option<NegativeMode>,
) -> Result<PreparedMontage> {
    let mut panels = scenes
        .into_iter()
        .map(|scene| prepare_render(scene, settings, negative))
        .collect::<Result<Vec<_>>>()?;
    let settings = shared_magnitude_range(&settings, panels.iter().flat_map(|p| &p.sets));
    for panel in &mut panels {
        panel.settings = settings;
    }
    let cell_w = panels.iter().map(|p| p.width).max().unwrap_or(1);
    let cell_h = panels.iter().map(|p| p.height).max().unwrap_or(1);
    let grid = Grid::new((cell_w, cell_h), columns, panels.len());
    grid.size()?;
    Ok(PreparedMontage {
        underlays: Vec::new(),
        captions: Vec::new(),
        panels,
        settings,
        grid,
    })
}

impl PreparedMontage {
    /// The size of each cell: the largest panel's.
    pub fn cell(&self) -> (u32, u32) {
        self.grid.cell
    }

    /// Panels to a row.
    pub fn columns(&self) -> usize {
        self.grid.columns
    }

    /// Draws `underlays[k]` (if any) in panel k's depth buffer.
    pub fn with_underlays(mut self, underlays: Vec<Option<Underlay>>) -> Self {
        self.underlays = underlays;
        self
    }

    /// Writes `captions[k]` (if any, the panel's slice) in panel k's top-left corner.
    pub fn with_captions(mut self, captions: Vec<Option<String>>) -> Self {
        self.captions = captions;
        self
    }

    /// Glyphs in all panels.
    pub fn glyph_count(&self) -> usize {
        self.panels.iter().map(PreparedScene::glyph_count).sum()
    }

    /// The glyph sets of every panel.
    pub fn sets(&self) -> impl Iterator<Item = &GlyphSetData> {
        self.panels.iter().flat_map(|panel| &panel.sets)
    }

    /// Draws every panel into its cell, with its underlay and caption if any, and the
    /// anatomical directions at each panel's edges if `labels`.
    pub fn render(
        &self,
        renderer: &mut HeadlessRenderer,
        gpu: &Gpu,
        labels: bool,
    ) -> Result<RenderedImage> {
        self.render_with_underlays(renderer, gpu, labels, &[])
    }

    /// [`PreparedMontage::render`] with panel k's underlay `underlays[k]` drawn in its
    /// depth buffer (a panel past the list's end has the one of
    /// [`PreparedMontage::with_underlays`], if any): each panel's planes are its own
    /// slice's (`volume::view_underlay` on the panel's regions).
    pub fn render_with_underlays(
        &self,
        renderer: &mut HeadlessRenderer,
        gpu: &Gpu,
        labels: bool,
        underlays: &[Option<Underlay>],
    ) -> Result<RenderedImage> {
        let (width, height) = self.grid.size()?;
        let mut montage = Montage::new(self.grid, width, height, self.settings.background);
        for (k, panel) in self.panels.iter().enumerate() {
            let (w, h) = (panel.width, panel.height);
            let underlay = underlays
                .get(k)
                .and_then(Option::as_ref)
                .or_else(|| self.underlays.get(k).and_then(Option::as_ref));
            let view = FrameView::new(&panel.camera, w, h)
                .with_underlay(underlay)
                .with_peaks(panel.peaks.as_ref());
            let overlays = Overlays {
                labels,
                caption: self.captions.get(k).and_then(Option::as_deref),
                colorbar: None,
            };
            let image = render_figure(
                renderer,
                gpu,
                (&panel.sets, &view),
                &self.settings,
                &overlays,
            )?;
            montage.place(k, &image);
        }
        Ok(montage.finish())
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
            path: crate::render::RenderPath::Fragment,
            passes: 1,
            culling: crate::render::Culling::Off,
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
        assert!(
            matches!(grid.size(), Err(Error::Limit { value, .. }) if value > u64::from(MAX_SIDE))
        );
    }
}
