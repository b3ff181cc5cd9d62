//! The window's figure as `render` makes it: the layout of a window size (panels and the
//! colour bar's strip, [`WindowLayout`]), the strip's pixels (drawn again only when the
//! bar or the height changes), and the same figure through the headless renderer for
//! screenshots: each panel at its cell's size, composed as `render` composes a montage,
//! with the strip appended as `render --colorbar` appends it.
use super::ViewerOptions;
use super::layout::WindowLayout;
use super::panels::Panels;
use ash::vk;
use glyphcast::Result;
use glyphcast::render::compose::colorbar::ColorBar;
use glyphcast::render::compose::figure::{Overlays, render_figure};
use glyphcast::render::compose::montage::Montage;
use glyphcast::render::headless::{FrameView, HeadlessRenderer, RenderedImage};
use glyphcast::vk::Gpu;

/// The colour bar's strip as last drawn.
struct Strip {
    bar: ColorBar,
    height: u32,
    width: u32,
    rgba: Vec<u8>,
}

#[derive(Default)]
pub struct Figure {
    strip: Option<Strip>,
}

impl Figure {
    /// The colour bar shown now: `--colorbar` with `--color magnitude`.
    fn colorbar(panels: &Panels, options: &ViewerOptions) -> Option<ColorBar> {
        let label = options.colorbar_label.as_deref();
        options.colorbar.then(|| panels.colorbar(label)).flatten()
    }

    /// The window size that gives each panel a cell of `cell` and the colour bar its
    /// strip beside them.
    pub fn window_size(
        panels: &Panels,
        options: &ViewerOptions,
        cell: (u32, u32),
    ) -> Result<(u32, u32)> {
        let (width, height) = WindowLayout::grid_size(cell, panels.panels.len(), panels.columns);
        let strip = Figure::colorbar(panels, options)
            .map(|bar| bar.strip_width(height))
            .transpose()?;
        Ok((width.saturating_add(strip.unwrap_or(0)), height))
    }

    /// The layout of a window of `size`, with the strip's pixels made for it.
    pub fn layout(
        &mut self,
        panels: &Panels,
        options: &ViewerOptions,
        size: vk::Extent2D,
    ) -> Result<WindowLayout> {
        let height = size.height;
        match Figure::colorbar(panels, options) {
            Some(bar) => {
                let kept = self
                    .strip
                    .as_ref()
                    .is_some_and(|s| s.bar == bar && s.height == height);
                if !kept {
                    let [r, g, b, _] = panels.settings().background;
                    // The window is opaque: its background, and so its strip, has alpha 1.
                    let (width, rgba) = bar.strip(height, [r, g, b, 1.0])?;
                    self.strip = Some(Strip {
                        bar,
                        height,
                        width,
                        rgba,
                    });
                }
            }
            None => self.strip = None,
        }
        Ok(WindowLayout::new(
            size.width,
            height,
            panels.panels.len(),
            panels.columns,
            self.strip.as_ref().map(|s| s.width),
        ))
    }

    /// The strip's pixels for the last layout, if it has a colour bar.
    pub fn strip_pixels(&self) -> Option<&[u8]> {
        self.strip.as_ref().map(|s| s.rgba.as_slice())
    }

    /// The figure of `layout` (from [`Figure::layout`]) through the headless renderer.
    pub fn render_headless(
        &self,
        renderer: &mut HeadlessRenderer,
        gpu: &Gpu,
        panels: &Panels,
        layout: &WindowLayout,
    ) -> Result<RenderedImage> {
        let settings = panels.frame_settings();
        let (width, height) = (layout.panel_area_width(), layout.height);
        let mut image = if panels.is_montage() {
            let mut montage = Montage::new(layout.grid, width, height, settings.background);
            let captions = panels.captions();
            for (k, panel) in panels.panels.iter().enumerate() {
                let Some(cell) = layout.cell(k) else { continue };
                let (w, h) = (cell.extent.width, cell.extent.height);
                let underlay = panel.underlay_as_seen();
                let view = FrameView::new(&panel.camera, w, h)
                    .with_underlay(underlay.as_ref())
                    .with_peaks(panel.peaks.as_ref());
                let overlays = Overlays {
                    caption: captions.get(k).and_then(Option::as_deref),
                    ..Overlays::default()
                };
                let shot =
                    render_figure(renderer, gpu, (&panel.sets, &view), &settings, &overlays)?;
                montage.place(k, &shot);
            }
            montage.finish()
        } else {
            let c = panels.first();
            let underlay = c.underlay_as_seen();
            let view = FrameView::new(&c.camera, width, height)
                .with_underlay(underlay.as_ref())
                .with_peaks(c.peaks.as_ref());
            render_figure(
                renderer,
                gpu,
                (&c.sets, &view),
                &settings,
                &Overlays::default(),
            )?
        };
        if let Some(strip) = self.strip.as_ref().filter(|_| layout.strip.is_some()) {
            let (total, rgba, distance) = strip.bar.append(
                &image.rgba,
                &image.distance,
                image.width,
                image.height,
                settings.background,
            )?;
            (image.width, image.rgba, image.distance) = (total, rgba, distance);
        }
        Ok(image)
    }
}
