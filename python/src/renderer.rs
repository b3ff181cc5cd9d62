//! `Renderer`: one Vulkan device with its pipelines, and the glyphs last loaded, kept on
//! the GPU across frames. Loading prepares and uploads a scene (a scene file or dict, or
//! a slice of a coefficient volume, with its underlay); `render` draws it, from the
//! loaded camera or from a new one, without uploading again. A montage (`views`,
//! `lightbox`) is kept prepared on the CPU and drawn panel by panel, as the CLI draws it.
//! The GIL is released for preparation, upload and drawing, so other Python threads run
//! meanwhile; everything is freed when the object goes (or at `release`).
use std::path::PathBuf;

use glyphcast::Result;
use glyphcast::camera::{Camera, Projection};
use glyphcast::glyph::GlyphShape;
use glyphcast::render::compose::colorbar::{check_colorbar, common_scale};
use glyphcast::render::compose::figure::{
    ColorBarRequest, Overlays, draw_figure, finish_figure, render_figure,
};
use glyphcast::render::compose::montage::{PreparedMontage, prepare_montage};
use glyphcast::render::headless::{FrameView, HeadlessRenderer, PreparedFrame, RenderedImage};
use glyphcast::render::options::{PreparedScene, RenderOptions, prepare_render};
use glyphcast::render::peaks::PeakSet;
use glyphcast::render::underlay::Underlay;
use glyphcast::scene::Scene;
use glyphcast::vk::{Gpu, GpuOptions};
use glyphcast_dmri::volume::{Coefficients, VolumeFigure};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays;
use crate::errors::{spell, to_py};
use crate::kwargs::Kwargs;

/// A headless renderer on one Vulkan device.
#[pyclass(module = "glyphcast._glyphcast")]
pub struct Renderer {
    /// Dropped first: the glyphs on the GPU and the passes go before the device they
    /// were made on (they keep it alive anyway, see `vk::DeviceContext`).
    loaded: Option<Loaded>,
    renderer: HeadlessRenderer,
    gpu: Gpu,
    /// What culling did in the last frame drawn (`RenderedImage::culling_report`).
    culling: Option<String>,
}

/// What is loaded.
enum Loaded {
    /// One scene: prepared on the CPU (its bounds frame a new camera) and uploaded.
    Frame(Box<Frame>),
    /// The panels of a montage, prepared on the CPU.
    Montage {
        montage: Box<PreparedMontage>,
        extras: Extras,
    },
}

/// What is drawn onto the rendered image: the anatomical directions (`labels`) and the
/// colour bar (`colorbar`, with its label, and the scale all glyphs share, if one).
#[derive(Clone, Default)]
struct Extras {
    labels: bool,
    colorbar: Option<Option<String>>,
    common_scale: Option<f64>,
}

impl Extras {
    /// The keywords `labels`, `colorbar` and `colorbar_label`.
    fn from_kwargs(kwargs: &mut Kwargs<'_>) -> PyResult<Extras> {
        let labels = kwargs.flag("labels", false)?;
        let colorbar = kwargs.flag("colorbar", false)?;
        let label = kwargs.text("colorbar_label")?;
        if label.is_some() && !colorbar {
            return Err(PyValueError::new_err(
                "colorbar_label: labels the colour bar: give colorbar=True too",
            ));
        }
        Ok(Extras {
            labels,
            colorbar: colorbar.then_some(label),
            common_scale: None,
        })
    }

    /// The overlays of the figure sequence (`render::compose::figure`) these ask for,
    /// as `glyphcast render --labels --colorbar` draws them.
    fn overlays(&self, labels: bool) -> Overlays<'_> {
        Overlays {
            labels,
            caption: None,
            colorbar: self.colorbar.as_ref().map(|label| ColorBarRequest {
                label: label.as_deref(),
                common_scale: self.common_scale,
            }),
        }
    }
}

/// A scene's glyphs on the GPU, with its underlay.
struct Frame {
    frame: PreparedFrame,
    scene: PreparedScene,
    underlay: Option<Underlay>,
    extras: Extras,
}

#[pymethods]
impl Renderer {
    /// Opens the device (`device`: part of its name or its index; `validation`: the
    /// Vulkan validation layer; both also from GLYPHCAST_DEVICE and
    /// GLYPHCAST_VALIDATION=1) and creates the pipelines' shared state.
    #[new]
    #[pyo3(signature = (device=None, validation=false))]
    fn new(py: Python<'_>, device: Option<String>, validation: bool) -> PyResult<Self> {
        let options = GpuOptions::from_env().with(device, validation);
        py.detach(|| open(&options)).map_err(to_py)
    }

    /// The device, as the CLI prints it.
    #[getter]
    fn device(&self) -> String {
        self.gpu.info.to_string()
    }

    /// Glyphs loaded (0 before the first load).
    #[getter]
    fn glyph_count(&self) -> usize {
        match &self.loaded {
            None => 0,
            Some(Loaded::Frame(frame)) => frame.scene.glyph_count(),
            Some(Loaded::Montage { montage, .. }) => montage.glyph_count(),
        }
    }

    /// The loaded view: the camera the glyphs are drawn with (the one the load framed,
    /// or the last one given to `render`) as a scene's `camera` object in JSON text, and
    /// the image's width and height. None before a load and for a montage, whose panels
    /// have a camera each.
    #[getter]
    fn view(&self) -> Option<(String, u32, u32)> {
        let Some(Loaded::Frame(frame)) = &self.loaded else {
            return None;
        };
        let scene = &frame.scene;
        Some((camera_json(&scene.camera), scene.width, scene.height))
    }

    /// Loads a scene in the scene format, given as JSON text, or as a file when
    /// `is_path`; `options` are the image size (`width`, `height`), `glyph` (every set's
    /// shape) and the render options. Returns the notes the CLI prints (shadows asked for
    /// glyphs whose shape takes no rays).
    #[pyo3(signature = (scene, is_path, options=None))]
    fn load_scene(
        &mut self,
        py: Python<'_>,
        scene: String,
        is_path: bool,
        options: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Vec<String>> {
        let mut kwargs = Kwargs::new(options)?;
        let image = kwargs.image_request()?;
        let shape = kwargs
            .text("glyph")?
            .map(|text| text.parse::<GlyphShape>())
            .transpose()
            .map_err(to_py)?;
        let render = kwargs.render_options()?;
        let mut extras = Extras::from_kwargs(&mut kwargs)?;
        kwargs.finish()?;
        let settings = render.settings().map_err(to_py)?;
        render.check_method_reads(&settings).map_err(to_py)?;
        if extras.colorbar.is_some() {
            check_colorbar(&settings).map_err(to_py)?;
        }
        self.loaded = None;
        let loaded = py.detach(|| {
            let scene_text = scene;
            let mut scene = if is_path {
                Scene::load(&PathBuf::from(&scene_text))?
            } else {
                Scene::from_json_str(&scene_text, "scene")?
            };
            if let Some(shape) = shape {
                scene.set_shape(shape)?;
            }
            scene.image.width = image.width.unwrap_or(scene.image.width);
            scene.image.height = image.height.unwrap_or(scene.image.height);
            extras.common_scale = common_scale([&scene]);
            let shapes = scene.glyph_sets.iter().map(|set| set.shape);
            let notes: Vec<String> = settings
                .shapes_without_rays_note(shapes)
                .into_iter()
                .collect();
            // A scene given as text is named as its parse errors name it.
            let source = if is_path {
                scene_text.as_str()
            } else {
                "scene"
            };
            self.upload(scene, (None, None), &render, extras)
                .map_err(|e| e.in_scene_file(source))
                .map(|loaded| (loaded, notes))
        });
        let (loaded, notes) = loaded.map_err(to_py)?;
        self.loaded = Some(loaded);
        Ok(notes)
    }

    /// Loads a slice (or a montage of slices) of a coefficient volume: `kind` is "sh"
    /// or "tensor", `coeffs` an (X, Y, Z, K) array, `affine` its voxel-to-world matrix;
    /// `options` hold the image size, the volume options (`mask`, `underlay`, `views`,
    /// `lightbox` and the rest), `labels`, `colorbar`, `colorbar_label` and the render
    /// options. Returns the notes and the warnings the CLI prints (the plane asked for is
    /// another voxel axis; voxels left out for NaN coefficients), in this module's words.
    #[pyo3(signature = (kind, coeffs, affine=None, options=None))]
    fn load_volume(
        &mut self,
        py: Python<'_>,
        kind: &str,
        coeffs: &Bound<'_, PyAny>,
        affine: Option<&Bound<'_, PyAny>>,
        options: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<(Vec<String>, Vec<String>)> {
        let input = match kind {
            "sh" => Coefficients::Sh,
            "tensor" => Coefficients::Tensor,
            other => {
                return Err(PyValueError::new_err(format!(
                    "kind '{other}': expected sh or tensor"
                )));
            }
        };
        let voxel_to_world = arrays::affine(affine)?;
        let mut kwargs = Kwargs::new(options)?;
        let mut image = kwargs.image_request()?;
        let request = kwargs.volume_request(voxel_to_world.affine)?;
        let render = kwargs.render_options()?;
        let mut extras = Extras::from_kwargs(&mut kwargs)?;
        kwargs.finish()?;
        // Edge labels get a band free of glyphs, as on the command line (a lightbox's
        // captions always do).
        image.keep_edges = extras.labels;
        // The options on their own first: refused before the array is converted.
        request.check(input).map_err(to_py)?;
        request.options(image).map_err(to_py)?;
        let settings = render.settings().map_err(to_py)?;
        render.check_method_reads(&settings).map_err(to_py)?;
        if extras.colorbar.is_some() {
            check_colorbar(&settings).map_err(to_py)?;
        }
        let data = arrays::coefficients(coeffs)?;
        self.loaded = None;
        let loaded = py.detach(|| {
            let volume = request.memory_volume(input, "coeffs", data, voxel_to_world)?;
            let figure = request.figure(volume, image)?;
            let (notes, warnings) = figure.messages();
            let spelled = |lines: &[glyphcast::error::Message]| -> Vec<String> {
                lines.iter().map(|line| line.spelled(&spell)).collect()
            };
            let messages = (spelled(notes), spelled(warnings));
            match figure {
                VolumeFigure::View(view) => {
                    let view = *view;
                    let shapes = view.scene.scene.glyph_sets.iter().map(|set| set.shape);
                    let mut messages = messages;
                    messages.0.extend(settings.shapes_without_rays_note(shapes));
                    extras.common_scale = common_scale([&view.scene.scene]);
                    let overlays = (view.underlay, view.scene.peaks);
                    let loaded = self.upload(view.scene.scene, overlays, &render, extras)?;
                    Ok((loaded, messages))
                }
                VolumeFigure::Montage(montage) => {
                    let (scenes, peaks): (Vec<Scene>, Vec<_>) = montage
                        .panels
                        .into_iter()
                        .map(|p| (p.scene, p.peaks))
                        .unzip();
                    extras.common_scale = common_scale(&scenes);
                    let settings = render.settings()?;
                    let mut prepared =
                        prepare_montage(scenes, montage.columns, settings, render.negative)?
                            .with_underlays(montage.underlays)
                            .with_captions(montage.captions);
                    for (panel, peaks) in prepared.panels.iter_mut().zip(peaks) {
                        panel.peaks = peaks;
                    }
                    let loaded = Loaded::Montage {
                        montage: Box::new(prepared),
                        extras,
                    };
                    Ok((loaded, messages))
                }
            }
        });
        let (loaded, messages) = loaded.map_err(to_py)?;
        self.loaded = Some(loaded);
        Ok(messages)
    }

    /// Draws the loaded glyphs, seen by the loaded camera or by `camera` (a scene's
    /// `camera` object as JSON text), and returns (rgba, depth).
    #[pyo3(signature = (camera=None))]
    fn render<'py>(
        &mut self,
        py: Python<'py>,
        camera: Option<String>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let camera = camera
            .map(|text| Scene::camera_from_json_str(&text, "camera"))
            .transpose()
            .map_err(to_py)?;
        let (renderer, gpu) = (&mut self.renderer, &self.gpu);
        let image = match self.loaded.as_mut() {
            None => {
                return Err(PyRuntimeError::new_err(
                    "nothing loaded: load a scene or a volume first",
                ));
            }
            Some(Loaded::Montage { .. }) if camera.is_some() => {
                return Err(PyValueError::new_err(
                    "camera: a montage (views, lightbox) has a camera per panel; draw it \
                     again without one",
                ));
            }
            Some(Loaded::Montage { montage, extras }) => py
                .detach(|| {
                    let image = montage.render(renderer, gpu, extras.labels)?;
                    // One range for all panels (prepare_montage): the first panel's
                    // extent stands in for them, as in `glyphcast render`.
                    match montage.panels.first() {
                        Some(first) => finish_figure(
                            image,
                            (&first.sets, &first.camera),
                            &montage.settings,
                            &extras.overlays(false),
                        ),
                        None => Ok(image),
                    }
                })
                .map_err(to_py)?,
            Some(Loaded::Frame(frame)) => py
                .detach(|| draw(renderer, gpu, frame, camera))
                .map_err(to_py)?,
        };
        self.culling = match &self.loaded {
            Some(Loaded::Frame(frame)) => Some(
                image
                    .culling_report(&self.gpu, &frame.scene.settings)
                    .map_err(to_py)?,
            ),
            _ => None,
        };
        arrays::image_arrays(py, image)
    }

    /// Frees the loaded glyphs on the GPU and the CPU (the device stays open).
    fn release(&mut self) {
        self.loaded = None;
        self.culling = None;
    }

    /// What culling of hidden glyphs the last frame drawn was asked for and what it did,
    /// as `glyphcast render` prints it (`occluded: early outs (1 pass)`, `off (1 pass)`,
    /// `occluded: none (...)` with the reason); `None` before the first frame and for a
    /// montage.
    #[getter]
    fn culling(&self) -> Option<String> {
        self.culling.clone()
    }
}

impl Renderer {
    /// Prepares and uploads `scene`, with `underlay` on its planes and its `peaks`.
    fn upload(
        &mut self,
        scene: Scene,
        (underlay, peaks): (Option<Underlay>, Option<PeakSet>),
        options: &RenderOptions,
        extras: Extras,
    ) -> Result<Loaded> {
        let settings = options.settings()?;
        let mut scene = prepare_render(scene, settings, options.negative)?;
        scene.peaks = peaks;
        let view = FrameView::new(&scene.camera, scene.width, scene.height)
            .with_underlay(underlay.as_ref())
            .with_peaks(scene.peaks.as_ref());
        let frame = self
            .renderer
            .prepare_view(&self.gpu, &scene.sets, &view, &scene.settings)?;
        Ok(Loaded::Frame(Box::new(Frame {
            frame,
            scene,
            underlay,
            extras,
        })))
    }
}

/// A camera as the scene format writes it (`docs/scene-format.md`): what
/// `Scene::camera_from_json_str` reads back to the same camera.
fn camera_json(camera: &Camera) -> String {
    let mut object = serde_json::json!({
        "eye": camera.eye.to_array(),
        "target": camera.target.to_array(),
        "up": camera.up.to_array(),
    });
    match camera.projection {
        Projection::Perspective { fov_y_deg } => {
            object["projection"] = "perspective".into();
            object["fov_y_deg"] = fov_y_deg.into();
        }
        Projection::Orthographic { height } => {
            object["projection"] = "orthographic".into();
            object["height"] = height.into();
        }
    }
    object.to_string()
}

/// The device and the renderer's passes.
fn open(options: &GpuOptions) -> Result<Renderer> {
    let gpu = Gpu::headless(options)?;
    let renderer = HeadlessRenderer::new(&gpu)?;
    Ok(Renderer {
        loaded: None,
        renderer,
        gpu,
        culling: None,
    })
}

/// One frame of the loaded glyphs; a new camera is written into the uploaded frame
/// (prepared again on the compute path, whose tiles follow the camera, and with an
/// underlay, whose planes the depth range covers). With more than one sample per pixel
/// the frame is drawn as the CLI draws it (`HeadlessRenderer::render_view`: at
/// s times the size, averaged down, and once more at 1x for the depth map), not from the
/// uploaded one-sample frame.
fn draw(
    renderer: &mut HeadlessRenderer,
    gpu: &Gpu,
    loaded: &mut Frame,
    camera: Option<glyphcast::camera::Camera>,
) -> Result<RenderedImage> {
    let supersampled = loaded.scene.settings.samples > 1;
    if let Some(camera) = camera {
        loaded.scene.camera = camera;
        if !supersampled
            && (loaded.underlay.is_some()
                || !loaded.frame.set_camera(&loaded.scene.sets, &camera)?)
        {
            let s = &loaded.scene;
            let view = FrameView::new(&s.camera, s.width, s.height)
                .with_underlay(loaded.underlay.as_ref())
                .with_peaks(s.peaks.as_ref());
            loaded.frame = renderer.prepare_view(gpu, &s.sets, &view, &s.settings)?;
        }
    }
    let s = &loaded.scene;
    let overlays = loaded.extras.overlays(loaded.extras.labels);
    if supersampled {
        let view = FrameView::new(&s.camera, s.width, s.height)
            .with_underlay(loaded.underlay.as_ref())
            .with_peaks(s.peaks.as_ref());
        render_figure(renderer, gpu, (&s.sets, &view), &s.settings, &overlays)
    } else {
        let seen = (s.sets.as_slice(), &s.camera);
        draw_figure(renderer, gpu, &loaded.frame, seen, &s.settings, &overlays)
    }
}
