//! `Renderer`: one Vulkan device with its pipelines, and the glyphs last loaded, kept on
//! the GPU across frames. Loading prepares and uploads a scene (a scene file or dict, or
//! a slice of a coefficient volume); `render` draws it, from the loaded camera or from a
//! new one, without uploading again. The GIL is released for preparation, upload and
//! drawing, so other Python threads run meanwhile; everything is freed when the object
//! goes (or at `release`).
use std::path::PathBuf;

use glyphcast::Result;
use glyphcast::render::headless::{HeadlessRenderer, PreparedFrame, RenderedImage};
use glyphcast::render::labels::{draw_edge_labels, edge_labels};
use glyphcast::render::options::{PreparedScene, RenderOptions, prepare_render};
use glyphcast::scene::Scene;
use glyphcast::vk::{Gpu, GpuOptions};
use glyphcast::volume::{Volume, VolumeKind, VolumeRequest};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays;
use crate::errors::to_py;
use crate::kwargs::Kwargs;

/// A headless renderer on one Vulkan device.
#[pyclass(module = "glyphcast._glyphcast")]
pub struct Renderer {
    /// Dropped first: the glyphs on the GPU and the passes go before the device they
    /// were made on (they keep it alive anyway, see `vk::DeviceContext`).
    loaded: Option<Loaded>,
    renderer: HeadlessRenderer,
    gpu: Gpu,
}

/// The glyphs loaded: prepared on the CPU (their bounds frame a new camera) and uploaded.
struct Loaded {
    frame: PreparedFrame,
    scene: PreparedScene,
    labels: bool,
}

#[pymethods]
impl Renderer {
    /// Opens the device (`device`: part of its name or its index; `validation`: the
    /// Vulkan validation layer; both also from GLYPHCAST_DEVICE and
    /// GLYPHCAST_VALIDATION=1) and creates the pipelines' shared state.
    #[new]
    #[pyo3(signature = (device=None, validation=false))]
    fn new(py: Python<'_>, device: Option<String>, validation: bool) -> PyResult<Self> {
        let options = RenderOptions {
            device,
            validation,
            ..Default::default()
        }
        .gpu_options();
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
        self.loaded.as_ref().map_or(0, |l| l.scene.glyph_count())
    }

    /// Loads a scene in the scene format, given as JSON text, or as a file when
    /// `is_path`; `options` are the image size (`width`, `height`) and the render options.
    #[pyo3(signature = (scene, is_path, options=None))]
    fn load_scene(
        &mut self,
        py: Python<'_>,
        scene: String,
        is_path: bool,
        options: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<()> {
        let mut kwargs = Kwargs::new(options)?;
        let image = kwargs.image_request()?;
        let render = kwargs.render_options()?;
        kwargs.finish()?;
        self.loaded = None;
        let loaded = py.detach(|| {
            let mut scene = if is_path {
                Scene::load(&PathBuf::from(&scene))?
            } else {
                Scene::from_json_str(&scene, "scene")?
            };
            scene.image.width = image.width.unwrap_or(scene.image.width);
            scene.image.height = image.height.unwrap_or(scene.image.height);
            self.upload(scene, &render, false)
        });
        self.loaded = Some(loaded.map_err(to_py)?);
        Ok(())
    }

    /// Loads a slice of a coefficient volume: `kind` is "sh" or "tensor", `coeffs` an
    /// (X, Y, Z, K) array, `affine` its voxel-to-world matrix; `options` hold the image
    /// size, the volume options, `mask`, `labels` and the render options. Returns the
    /// note the CLI prints, if any (the plane asked for is another voxel axis).
    #[pyo3(signature = (kind, coeffs, affine=None, options=None))]
    fn load_volume(
        &mut self,
        py: Python<'_>,
        kind: &str,
        coeffs: &Bound<'_, PyAny>,
        affine: Option<&Bound<'_, PyAny>>,
        options: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Option<String>> {
        let mut kwargs = Kwargs::new(options)?;
        let image = kwargs.image_request()?;
        let request = kwargs.volume_request()?;
        let render = kwargs.render_options()?;
        let labels = kwargs.flag("labels", false)?;
        let mask = kwargs.object("mask");
        kwargs.finish()?;
        let kind = volume_kind(kind, &request).map_err(to_py)?;
        let mut volume_options = request.options(image).map_err(to_py)?;
        volume_options.mask = mask.as_ref().map(arrays::mask).transpose()?;
        let voxel_to_world = arrays::affine(affine)?;
        let data = arrays::coefficients(coeffs)?;
        self.loaded = None;
        let loaded = py.detach(|| {
            let volume = Volume::new("coeffs", data, kind, voxel_to_world)?;
            let view = request.view(volume, volume_options)?;
            let note = view.note;
            Ok((self.upload(view.scene.scene, &render, labels)?, note))
        });
        let (loaded, note) = loaded.map_err(to_py)?;
        self.loaded = Some(loaded);
        Ok(note)
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
        let Some(loaded) = self.loaded.as_mut() else {
            return Err(PyRuntimeError::new_err(
                "nothing loaded: load a scene or a volume first",
            ));
        };
        let (renderer, gpu) = (&mut self.renderer, &self.gpu);
        let image = py
            .detach(|| draw(renderer, gpu, loaded, camera))
            .map_err(to_py)?;
        arrays::image_arrays(py, image)
    }

    /// Frees the loaded glyphs on the GPU and the CPU (the device stays open).
    fn release(&mut self) {
        self.loaded = None;
    }
}

impl Renderer {
    /// Prepares and uploads `scene`.
    fn upload(&mut self, scene: Scene, options: &RenderOptions, labels: bool) -> Result<Loaded> {
        let settings = options.settings()?;
        let scene = prepare_render(scene, settings, options.negative()?)?;
        let frame = self.renderer.prepare(
            &self.gpu,
            &scene.sets,
            &scene.camera,
            scene.width,
            scene.height,
            &scene.settings,
        )?;
        Ok(Loaded {
            frame,
            scene,
            labels,
        })
    }
}

/// The device and the renderer's passes.
fn open(options: &GpuOptions) -> Result<Renderer> {
    let gpu = Gpu::headless(options)?;
    let renderer = HeadlessRenderer::new(&gpu)?;
    Ok(Renderer {
        loaded: None,
        renderer,
        gpu,
    })
}

/// One frame of the loaded glyphs; a new camera is written into the uploaded frame
/// (prepared again only on the compute path, whose tiles follow the camera).
fn draw(
    renderer: &mut HeadlessRenderer,
    gpu: &Gpu,
    loaded: &mut Loaded,
    camera: Option<glyphcast::camera::Camera>,
) -> Result<RenderedImage> {
    if let Some(camera) = camera {
        loaded.scene.camera = camera;
        if !loaded.frame.set_camera(&loaded.scene.sets, &camera)? {
            let s = &loaded.scene;
            loaded.frame =
                renderer.prepare(gpu, &s.sets, &s.camera, s.width, s.height, &s.settings)?;
        }
    }
    renderer.draw(gpu, &loaded.frame)?;
    let mut image = renderer.read(gpu, &loaded.frame)?;
    if loaded.labels {
        let edges = edge_labels(&loaded.scene.camera);
        draw_edge_labels(&mut image.rgba, image.width, image.height, &edges)?;
    }
    Ok(image)
}

/// "sh" or "tensor", with the basis or the layout the request gives.
fn volume_kind(kind: &str, request: &VolumeRequest) -> Result<VolumeKind> {
    match kind {
        "sh" => request.sh_kind(None),
        "tensor" => request.tensor_kind(),
        other => Err(glyphcast::Error::Invalid(format!(
            "kind '{other}': expected sh or tensor"
        ))),
    }
}
