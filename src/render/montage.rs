//! A montage: several scenes (panels) in one image, in a grid of cells of the largest
//! panel's size, in reading order. Each panel is the image its scene renders alone,
//! centred in its cell (cells without a panel, and the margins of smaller panels, are
//! background with NaN depth), except that a magnitude colouring without a range maps
//! one range, 0 to the largest glyph radius of all panels, so that colours compare
//! across panels. What `glyphcast render --views/--lightbox` and the Python module's
//! `views=`/`lightbox=` draw.
use crate::Setting;
use crate::error::{Error, Result};
use crate::glyph::NegativeMode;
use crate::render::antialias::MAX_SUPERSAMPLED_SIDE;
use crate::render::colorbar::srgb_byte;
use crate::render::glyph_data::GlyphSetData;
use crate::render::headless::{HeadlessRenderer, RenderedImage};
use crate::render::labels::{draw_edge_labels, edge_labels};
use crate::render::options::{PreparedScene, prepare_render};
use crate::render::{ColorMode, RenderSettings};
use crate::scene::Scene;
use crate::vk::Gpu;

/// The panels of a montage, prepared for rendering with one set of settings.
pub struct PreparedMontage {
    /// The panels, in reading order.
    pub panels: Vec<PreparedScene>,
    /// Panels to a row.
    pub columns: usize,
    /// The settings every panel is drawn with (one magnitude range for all).
    pub settings: RenderSettings,
    cell: (u32, u32),
    rows: usize,
}

/// Prepares the panels `scenes` (each sized already) for a grid of `columns` to a row,
/// drawn with `settings` and the negative-lobe mode `negative` if given (as
/// [`prepare_render`]); a usage error naming the size when the montage would be wider
/// or higher than an image can be.
pub fn prepare_montage(
    scenes: Vec<Scene>,
    columns: usize,
    mut settings: RenderSettings,
    negative: Option<NegativeMode>,
) -> Result<PreparedMontage> {
    let mut panels = scenes
        .into_iter()
        .map(|scene| prepare_render(scene, settings, negative))
        .collect::<Result<Vec<_>>>()?;
    if settings.needs_largest_radius() {
        let largest = panels
            .iter()
            .flat_map(|panel| &panel.sets)
            .map(|set| set.largest_radius)
            .fold(0.0, f64::max);
        settings.color = ColorMode::Magnitude {
            range: Some((0.0, largest as f32)),
        };
    }
    for panel in &mut panels {
        panel.settings = settings;
    }
    let cell_w = panels.iter().map(|p| p.width).max().unwrap_or(1);
    let cell_h = panels.iter().map(|p| p.height).max().unwrap_or(1);
    let columns = columns.clamp(1, panels.len().max(1));
    let rows = panels.len().div_ceil(columns);
    let (width, height) = (
        u64::from(cell_w) * columns as u64,
        u64::from(cell_h) * rows as u64,
    );
    let largest = u64::from(MAX_SUPERSAMPLED_SIDE);
    if width > largest || height > largest {
        return Err(Error::Usage(format!(
            "the montage would be {width}x{height} pixels; at most {largest} a side: give a \
             smaller {}/{}",
            Setting::Width.mention(),
            Setting::Height.mention()
        )));
    }
    Ok(PreparedMontage {
        panels,
        columns,
        settings,
        cell: (cell_w, cell_h),
        rows,
    })
}

impl PreparedMontage {
    /// The size of each cell: the largest panel's.
    pub fn cell(&self) -> (u32, u32) {
        self.cell
    }

    /// Glyphs in all panels.
    pub fn glyph_count(&self) -> usize {
        self.panels.iter().map(PreparedScene::glyph_count).sum()
    }

    /// The glyph sets of every panel.
    pub fn sets(&self) -> impl Iterator<Item = &GlyphSetData> {
        self.panels.iter().flat_map(|panel| &panel.sets)
    }

    /// Draws every panel into its cell, with the anatomical directions at each panel's
    /// edges if `labels`.
    pub fn render(
        &self,
        renderer: &mut HeadlessRenderer,
        gpu: &Gpu,
        labels: bool,
    ) -> Result<RenderedImage> {
        let (cell_w, cell_h) = self.cell;
        let mut grid = Grid::new(cell_w, cell_h, self.columns, self.rows, &self.settings);
        for (k, panel) in self.panels.iter().enumerate() {
            let (w, h) = (panel.width, panel.height);
            let mut image =
                renderer.render(gpu, &panel.sets, &panel.camera, w, h, &self.settings)?;
            if labels {
                draw_edge_labels(&mut image.rgba, w, h, &edge_labels(&panel.camera))?;
            }
            grid.place(k, &image);
        }
        Ok(RenderedImage {
            width: grid.width,
            height: grid.height,
            rgba: grid.rgba,
            distance: grid.distance,
            draws: 0,
            gpu_ms: None,
            mesh: None,
        })
    }
}

/// The pixels and depth map of a montage being assembled.
struct Grid {
    cell: (u32, u32),
    columns: usize,
    width: u32,
    height: u32,
    rgba: Vec<u8>,
    distance: Vec<f32>,
}

impl Grid {
    /// A grid of `columns` x `rows` cells of `cell_w` x `cell_h`, all background (the
    /// size checked by [`prepare_montage`]).
    fn new(
        cell_w: u32,
        cell_h: u32,
        columns: usize,
        rows: usize,
        settings: &RenderSettings,
    ) -> Grid {
        let width = cell_w * columns as u32;
        let height = cell_h * rows as u32;
        let [r, g, b, a] = settings.background;
        let clear = [
            srgb_byte(r),
            srgb_byte(g),
            srgb_byte(b),
            (a.clamp(0.0, 1.0) * 255.0).round() as u8,
        ];
        let pixels = width as usize * height as usize;
        Grid {
            cell: (cell_w, cell_h),
            columns,
            width,
            height,
            rgba: clear.iter().copied().cycle().take(4 * pixels).collect(),
            distance: vec![f32::NAN; pixels],
        }
    }

    /// Copies panel `k` into its cell, centred.
    fn place(&mut self, k: usize, panel: &RenderedImage) {
        let (cw, ch) = self.cell;
        let x0 = (k % self.columns) as u32 * cw + (cw - panel.width.min(cw)) / 2;
        let y0 = (k / self.columns) as u32 * ch + (ch - panel.height.min(ch)) / 2;
        let w = panel.width as usize;
        for row in 0..panel.height as usize {
            let to = (y0 as usize + row) * self.width as usize + x0 as usize;
            let from = row * w;
            self.rgba[4 * to..4 * (to + w)].copy_from_slice(&panel.rgba[4 * from..4 * (from + w)]);
            self.distance[to..to + w].copy_from_slice(&panel.distance[from..from + w]);
        }
    }
}
