//! The figure sequence that `glyphcast render`, Python and the viewer share: a view's
//! frame drawn by the headless renderer's passes ([`HeadlessRenderer::render_view`]:
//! the prepared frame, the underlay, the glyphs, their shadows, the peaks), then what is
//! drawn over it (edge labels, a lightbox panel's caption) and beside it (the magnitude
//! colour bar), always in that order. A montage draws each panel by this sequence
//! ([`crate::render::compose::montage`]).
use crate::camera::Camera;
use crate::error::Result;
use crate::render::compose::colorbar::ColorBar;
use crate::render::compose::labels::{draw_caption, draw_edge_labels, edge_labels};
use crate::render::glyph_data::GlyphSetData;
use crate::render::headless::{FrameView, HeadlessRenderer, PreparedFrame, RenderedImage};
use crate::render::settings::RenderSettings;
use crate::vk::Gpu;

/// What a figure draws over and beside its frame.
#[derive(Clone, Copy, Debug, Default)]
pub struct Overlays<'a> {
    /// Edge labels (`--labels`): the anatomical direction each edge of the image faces.
    pub labels: bool,
    /// A caption in the top-left corner (a lightbox panel's slice).
    pub caption: Option<&'a str>,
    /// The magnitude colour bar (`--colorbar`) to the right of the image, where the
    /// colour mode has one.
    pub colorbar: Option<ColorBarRequest<'a>>,
}

/// A colour bar asked for: the range is the drawn glyphs' ([`ColorBar::of_glyphs`]).
#[derive(Clone, Copy, Debug, Default)]
pub struct ColorBarRequest<'a> {
    /// The bar's label; `None`: the colour mode's quantity.
    pub label: Option<&'a str>,
    /// The one scale of every glyph, if they share one: values are divided by it (data
    /// units).
    pub common_scale: Option<f64>,
}

/// The figure of one view: the frame of `sets` seen as `view` with `settings`, then its
/// overlays.
pub fn render_figure(
    renderer: &mut HeadlessRenderer,
    gpu: &Gpu,
    (sets, view): (&[GlyphSetData], &FrameView),
    settings: &RenderSettings,
    overlays: &Overlays,
) -> Result<RenderedImage> {
    let image = renderer.render_view(gpu, sets, view, settings)?;
    finish_figure(image, (sets, view.camera), settings, overlays)
}

/// The figure of a frame prepared before ([`HeadlessRenderer::prepare_view`]), drawn
/// again: `sets` and `camera` are those it was prepared with (or last given).
pub fn draw_figure(
    renderer: &mut HeadlessRenderer,
    gpu: &Gpu,
    frame: &PreparedFrame,
    (sets, camera): (&[GlyphSetData], &Camera),
    settings: &RenderSettings,
    overlays: &Overlays,
) -> Result<RenderedImage> {
    renderer.draw(gpu, frame)?;
    let image = renderer.read(gpu, frame)?;
    finish_figure(image, (sets, camera), settings, overlays)
}

/// A drawn frame of `sets` seen from `camera` with its overlays: edge labels, then the
/// caption, then the colour bar.
pub fn finish_figure(
    mut image: RenderedImage,
    (sets, camera): (&[GlyphSetData], &Camera),
    settings: &RenderSettings,
    overlays: &Overlays,
) -> Result<RenderedImage> {
    let (width, height) = (image.width, image.height);
    if overlays.labels {
        draw_edge_labels(&mut image.rgba, width, height, &edge_labels(camera))?;
    }
    if let Some(caption) = overlays.caption {
        draw_caption(&mut image.rgba, width, height, caption)?;
    }
    if let Some(request) = overlays.colorbar {
        let bar = ColorBar::of_glyphs(
            settings,
            (sets, camera),
            request.common_scale,
            request.label,
        );
        if let Some(bar) = bar {
            bar.append_to(&mut image, settings.background)?;
        }
    }
    Ok(image)
}
