//! The winit event loop: window events become [`Action`]s and camera moves; a redraw
//! uploads changed glyph data, renders through the [`Presenter`] and updates the title
//! with the frame's GPU time. Scripted runs (`--frames`) apply one script event per frame
//! and finish with the screenshot and the window capture.
use super::ViewerOptions;
use super::compose::{PanelDraw, PatchDraw};
use super::content::Content;
use super::controls::{self, Action, HELP, color_name, refinement_name};
use super::figure::Figure;
use super::layout::WindowLayout;
use super::orbit;
use super::panels::Panels;
use super::presenter::{Outcome, Presenter};
use ash::vk;
use glyphcast::render::component::UploadedGlyphs;
use glyphcast::render::compose::labels::{CaptionPatch, caption_patch};
use glyphcast::render::headless::HeadlessRenderer;
use glyphcast::render::peaks::PeaksGpu;
use glyphcast::render::settings::{AmbientOcclusion, RenderSettings, STEP_RANGE, Shadows};
use glyphcast::render::shaders::methods_for;
use glyphcast::render::underlay::Underlay;
use glyphcast::vk::Gpu;
use glyphcast::{Error, Result};
use std::path::{Path, PathBuf};
use std::time::Instant;
use winit::application::ApplicationHandler;
use winit::dpi::{PhysicalPosition, PhysicalSize};
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop, EventLoopProxy};
use winit::raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use winit::window::{Window, WindowId};

/// Frames a scripted run may add, past `--frames`, while waiting for the window to take
/// the size a `resize:` event asked for.
const SETTLE_FRAMES: u32 = 300;

/// How often the title shows the progress of a glyph preparation.
const PROGRESS_INTERVAL: std::time::Duration = std::time::Duration::from_millis(100);

/// The worker's signal that prepared glyphs are ready.
#[derive(Clone, Copy, Debug)]
struct GlyphsReady;

/// Mouse state between events.
#[derive(Default)]
struct Pointer {
    position: Option<PhysicalPosition<f64>>,
    orbiting: bool,
    panning: bool,
    shift: bool,
}

struct App {
    // Declaration order is drop order: the presenter (its surface) before the window it
    // presents to. GPU objects keep the device alive themselves, so the Gpu may go at
    // any point.
    /// Each panel's glyphs on the GPU, shared by every frame in flight, and the version
    /// of its content, the method they were uploaded for and whether they cast shadows.
    scene_gpu: Vec<Option<UploadedGlyphs>>,
    uploaded: Vec<Option<(u64, glyphcast::render::Method, bool, glyphcast::RenderPath)>>,
    /// Per frame slot, each panel's peaks on the GPU (a peak set holds one frame block,
    /// so each slot has its own copy) and the version of its content they hold.
    peaks_gpu: Vec<Vec<Option<PeaksGpu>>>,
    peaks_uploaded: Vec<Vec<Option<u64>>>,
    /// Glyph uploads replaced (slice moves, method switches), and how many of those
    /// replacements happened while another frame was still on the GPU.
    replaced: (u32, u32),
    /// The underlay's volume on the GPU (uploaded once, again when the pass is rebuilt).
    underlay_gpu: Option<glyphcast::render::underlay::UnderlayGpu>,
    headless: Option<HeadlessRenderer>,
    presenter: Option<Presenter>,
    window: Option<Window>,
    panels: Panels,
    options: ViewerOptions,
    figure: Figure,
    pointer: Pointer,
    /// Frames presented, and the script's next event.
    presented: u32,
    script_next: usize,
    /// The size the last `resize:` event asked for, until the window has it.
    pending_size: Option<(u32, u32)>,
    last_extent: Option<vk::Extent2D>,
    gpu_ms: Option<f64>,
    screenshots: u32,
    dirty: bool,
    error: Option<Error>,
    gpu: Gpu,
}

pub fn run(mut panels: Panels, options: ViewerOptions) -> Result<()> {
    let event_loop = EventLoop::<GlyphsReady>::with_user_event()
        .build()
        .map_err(|e| Error::setup("window system (is DISPLAY set?)", e))?;
    let proxy: std::sync::Mutex<EventLoopProxy<GlyphsReady>> =
        std::sync::Mutex::new(event_loop.create_proxy());
    panels.set_waker(std::sync::Arc::new(move || {
        if let Ok(proxy) = proxy.lock() {
            // A closed event loop no longer wants the glyphs.
            let _ = proxy.send_event(GlyphsReady);
        }
    }));
    let display = event_loop
        .display_handle()
        .map_err(|e| Error::setup("display handle", e))?
        .as_raw();
    let gpu = Gpu::for_window(&options.gpu, display)?;
    eprintln!("device: {}", gpu.info);
    if options.frames.is_none() {
        eprintln!("{HELP}");
    }
    let count = panels.panels.len();
    let slots = options.frames_in_flight();
    let mut app = App {
        scene_gpu: (0..count).map(|_| None).collect(),
        uploaded: vec![None; count],
        peaks_gpu: (0..slots)
            .map(|_| (0..count).map(|_| None).collect())
            .collect(),
        peaks_uploaded: vec![vec![None; count]; slots],
        replaced: (0, 0),
        underlay_gpu: None,
        headless: None,
        presenter: None,
        window: None,
        panels,
        options,
        figure: Figure::default(),
        pointer: Pointer::default(),
        presented: 0,
        script_next: 0,
        pending_size: None,
        last_extent: None,
        gpu_ms: None,
        screenshots: 0,
        dirty: true,
        error: None,
        gpu,
    };
    event_loop
        .run_app(&mut app)
        .map_err(|e| Error::setup("running window event loop", e))?;
    if let Some(e) = app.error.take() {
        return Err(e);
    }
    app.gpu.wait_idle()?;
    app.gpu.check_validation()
}

impl ApplicationHandler<GlyphsReady> for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_none()
            && let Err(e) = self.open_window(event_loop)
        {
            self.fail(event_loop, e);
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        if let Err(e) = self.on_event(event_loop, event) {
            self.fail(event_loop, e);
        }
    }

    fn user_event(&mut self, event_loop: &ActiveEventLoop, _: GlyphsReady) {
        if let Err(e) = self.take_glyphs(false) {
            self.fail(event_loop, e);
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        if let Err(e) = self.take_glyphs(false) {
            self.fail(event_loop, e);
            return;
        }
        let scripted = self.options.frames.is_some();
        let busy = self.panels.busy().is_some();
        event_loop.set_control_flow(if scripted {
            ControlFlow::Poll
        } else if busy {
            // Wakes up to show the preparation's progress.
            ControlFlow::WaitUntil(Instant::now() + PROGRESS_INTERVAL)
        } else {
            ControlFlow::Wait
        });
        if busy {
            self.update_title();
        }
        if let Some(window) = &self.window
            && (scripted || std::mem::take(&mut self.dirty))
        {
            window.request_redraw();
        }
    }
}

impl App {
    /// Takes the glyphs of a finished preparation, if any. A preparation that failed on
    /// its input is reported and the glyphs shown stay; other errors end the session.
    fn take_glyphs(&mut self, wait: bool) -> Result<()> {
        match self.panels.poll(wait) {
            Ok(true) => {
                self.dirty = true;
                self.update_title();
                Ok(())
            }
            Ok(false) => Ok(()),
            Err(e @ (Error::Io { .. } | Error::Data { .. } | Error::Input { .. })) => {
                eprintln!("error: {e}");
                self.update_title();
                Ok(())
            }
            Err(e) => Err(e),
        }
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, error: Error) {
        self.error.get_or_insert(error);
        event_loop.exit();
    }

    fn open_window(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        let (width, height) = self.initial_size()?;
        let attributes = Window::default_attributes()
            .with_title("glyphcast")
            .with_inner_size(PhysicalSize::new(width, height));
        let window = event_loop
            .create_window(attributes)
            .map_err(|e| Error::setup("window", e))?;
        let display = window
            .display_handle()
            .map_err(|e| Error::setup("display handle", e))?
            .as_raw();
        let handle = window
            .window_handle()
            .map_err(|e| Error::setup("window handle", e))?
            .as_raw();
        let unthrottled = self.options.frames.is_some();
        let slots = self.options.frames_in_flight();
        let settings = self.panels.frame_settings();
        // SAFETY: the window lives in `self.window`, declared after the presenter, so it
        // outlives the surface; the Gpu was created for this event loop's display.
        let presenter =
            unsafe { Presenter::new(&self.gpu, (display, handle), unthrottled, slots, &settings)? };
        self.presenter = Some(presenter);
        self.window = Some(window);
        Ok(())
    }

    /// The window's first size: a cell of `--width` x `--height` for each panel, and the
    /// colour bar's strip beside them, as `render` lays out its image.
    fn initial_size(&self) -> Result<(u32, u32)> {
        let cell = (self.options.width, self.options.height);
        Figure::window_size(&self.panels, &self.options, cell)
    }

    fn on_event(&mut self, event_loop: &ActiveEventLoop, event: WindowEvent) -> Result<()> {
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(_) | WindowEvent::ScaleFactorChanged { .. } => {
                if let Some(p) = self.presenter.as_mut() {
                    p.mark_stale();
                }
                self.dirty = true;
            }
            WindowEvent::RedrawRequested => self.redraw(event_loop)?,
            WindowEvent::KeyboardInput { event, .. } if event.state == ElementState::Pressed => {
                // Scripted runs ignore the keyboard: their sequence is the script.
                if self.options.frames.is_none()
                    && let Some(action) = controls::key_action(&event.logical_key)
                {
                    // A key that cannot be carried out (a screenshot path that cannot
                    // be written, ...) is reported; the session goes on.
                    match self.apply(event_loop, action) {
                        Err(e @ (Error::Io { .. } | Error::Data { .. } | Error::Input { .. })) => {
                            eprintln!("error: {e}")
                        }
                        result => result?,
                    }
                }
            }
            WindowEvent::ModifiersChanged(modifiers) => {
                self.pointer.shift = modifiers.state().shift_key();
            }
            WindowEvent::MouseInput { state, button, .. } => {
                let pressed = state == ElementState::Pressed;
                match button {
                    MouseButton::Left => self.pointer.orbiting = pressed,
                    MouseButton::Right | MouseButton::Middle => self.pointer.panning = pressed,
                    _ => {}
                }
            }
            WindowEvent::CursorMoved { position, .. } => {
                let previous = self.pointer.position.replace(position);
                if let Some(previous) = previous {
                    let (dx, dy) = (position.x - previous.x, position.y - previous.y);
                    let p = &self.pointer;
                    if p.panning || (p.orbiting && p.shift) {
                        self.apply(event_loop, Action::Pan(dx, dy))?;
                    } else if p.orbiting {
                        self.apply(event_loop, Action::Orbit(dx, dy))?;
                    }
                }
            }
            WindowEvent::MouseWheel { delta, .. } => {
                let lines = match delta {
                    MouseScrollDelta::LineDelta(_, y) => f64::from(y),
                    MouseScrollDelta::PixelDelta(p) => p.y / 40.0,
                };
                self.apply(event_loop, Action::Zoom(0.9f64.powf(lines)))?;
            }
            WindowEvent::Occluded(false) => self.dirty = true,
            _ => {}
        }
        Ok(())
    }

    fn window_size(&self) -> vk::Extent2D {
        let size = self
            .window
            .as_ref()
            .map_or(PhysicalSize::new(0, 0), Window::inner_size);
        vk::Extent2D {
            width: size.width,
            height: size.height,
        }
    }

    /// The layout of a window of `size`.
    fn layout(&mut self, size: vk::Extent2D) -> Result<WindowLayout> {
        self.figure.layout(&self.panels, &self.options, size)
    }

    /// The height of one panel's cell: camera drags are measured in it.
    fn cell_height(&self) -> u32 {
        let size = self.window_size();
        let (panels, columns) = (self.panels.panels.len(), self.panels.columns);
        // The strip takes width only, so the cells' height does not depend on it.
        let layout = WindowLayout::new(size.width, size.height, panels, columns, None);
        layout.grid.cell.1.max(1)
    }

    fn apply(&mut self, event_loop: &ActiveEventLoop, action: Action) -> Result<()> {
        let height = self.cell_height();
        let mut settings = self.panels.settings();
        match action {
            Action::Resize(width, height) => {
                if let Some(window) = &self.window {
                    let _ = window.request_inner_size(PhysicalSize::new(width, height));
                }
                self.pending_size = Some((width, height));
            }
            Action::Method(method) => self.check_method(&mut settings, method)?,
            Action::NextMethod => {
                let methods = self.methods();
                let at = methods
                    .iter()
                    .position(|m| *m == settings.method)
                    .unwrap_or(0);
                if let Some(next) = methods.get((at + 1) % methods.len().max(1)) {
                    self.check_method(&mut settings, *next)?;
                }
            }
            Action::Step(step) => change_checked(&mut settings, |s| s.step = step)?,
            Action::ScaleStep(factor) => {
                settings.step = (settings.step * factor).clamp(STEP_RANGE.0, STEP_RANGE.1)
            }
            Action::Refine(refinement) => settings.refinement = refinement,
            Action::NextRefinement => {
                settings.refinement = controls::next_refinement(settings.refinement)
            }
            Action::Color(color) => change_checked(&mut settings, |s| s.color = color)?,
            Action::NextColor => settings.color = controls::next_color(settings.color),
            Action::Negative(mode) => self.panels.set_negative(Some(mode))?,
            Action::ToggleNegative => self.panels.set_negative(None)?,
            Action::Shadows(shadows) => change_checked(&mut settings, |s| s.shadows = shadows)?,
            Action::ToggleShadows => {
                let shadows = match settings.shadows {
                    Shadows::Off => Shadows::Hard,
                    _ => Shadows::Off,
                };
                change_checked(&mut settings, |s| s.shadows = shadows)?
            }
            Action::AmbientOcclusion(occlusion) => {
                change_checked(&mut settings, |s| s.ambient_occlusion = occlusion)?
            }
            Action::ToggleAmbientOcclusion => {
                let occlusion = match settings.ambient_occlusion {
                    AmbientOcclusion::Off => "on".parse()?,
                    AmbientOcclusion::On { .. } => AmbientOcclusion::Off,
                };
                change_checked(&mut settings, |s| s.ambient_occlusion = occlusion)?
            }
            Action::Tracks(shown) => {
                if self.panels.set_tracks(Some(shown))? {
                    return Ok(());
                }
            }
            Action::ToggleTracks => {
                if self.panels.set_tracks(None)? {
                    return Ok(());
                }
            }
            Action::Slice(delta) => {
                if self.panels.move_slice(delta)? {
                    // Nothing new to show until the slice's glyphs are ready, and on a
                    // CPU renderer (lavapipe) drawing the old ones would take the cores
                    // the preparation needs.
                    return Ok(());
                }
            }
            Action::ActiveSlice(axis) => {
                self.panels.set_active_slice(axis);
            }
            Action::Orbit(dx, dy) => self
                .panels
                .move_cameras(|camera| orbit::orbit(camera, dx, dy, height)),
            Action::Pan(dx, dy) => self
                .panels
                .move_cameras(|camera| orbit::pan(camera, dx, dy, height)),
            Action::Zoom(factor) => self
                .panels
                .move_cameras(|camera| orbit::zoom(camera, factor)),
            Action::ResetCamera => self.panels.reset_cameras(),
            Action::Screenshot => {
                let path = self.options.screenshot.clone().unwrap_or_else(|| {
                    self.screenshots += 1;
                    PathBuf::from(format!("glyphcast-view-{}.png", self.screenshots))
                });
                self.screenshot(&path)?;
            }
            Action::Help => eprintln!("{HELP}"),
            Action::Quit => event_loop.exit(),
            Action::Wait => {}
        }
        // Shadows or occlusion just switched on: glyphs whose shape takes no rays are
        // drawn without them, as `render` and Python say.
        if !self.panels.settings().casts_rays() {
            let shapes = self.panels.panels.iter().flat_map(|p| p.sets.iter());
            if let Some(note) = settings.shapes_without_rays_note(shapes.map(|s| s.shape)) {
                eprintln!("note: {note}");
            }
        }
        self.panels.set_settings(settings);
        self.dirty = true;
        Ok(())
    }

    /// Methods that have shaders for every glyph set on screen.
    fn methods(&self) -> Vec<glyphcast::render::Method> {
        let layouts: Vec<_> = self
            .panels
            .panels
            .iter()
            .flat_map(|p| p.sets.iter().map(|s| s.layout))
            .collect();
        methods_for(&layouts)
    }

    /// Sets `settings.method` to `method` where every glyph set has its shader and the
    /// other settings allow it.
    fn check_method(
        &self,
        settings: &mut RenderSettings,
        method: glyphcast::render::Method,
    ) -> Result<()> {
        if !self.methods().contains(&method) {
            return Err(Error::Unsupported {
                what: glyphcast::error::Asked::Method(glyphcast::Setting::Method.with(method)),
                by: "the shaders of these glyphs".into(),
            });
        }
        // The other settings may refuse the method (--color sign and meshes); only the
        // exact method casts shadow and occlusion rays, so another one turns them off.
        change_checked(settings, |s| {
            s.method = method;
            if method != glyphcast::render::Method::Exact {
                s.shadows = Shadows::Off;
                s.ambient_occlusion = AmbientOcclusion::Off;
            }
        })
    }

    fn redraw(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        let scripted = self.options.frames.is_some();
        if scripted && self.script_next == self.presented as usize {
            if let Some(action) = self.options.script.get(self.script_next).cloned() {
                self.apply(event_loop, action)?;
            }
            self.script_next += 1;
        }
        // A script waits for each preparation, so that its frame shows the glyphs the
        // event made (and is not drawn while they are prepared).
        if scripted && self.panels.busy().is_some() {
            self.take_glyphs(true)?;
        }
        let size = self.window_size();
        let minimised = self.window.as_ref().and_then(Window::is_minimized) == Some(true);
        let Some(presenter) = self.presenter.as_mut() else {
            return Ok(());
        };
        if minimised {
            return Ok(());
        }
        let Some(rebuilt) = presenter.prepare(&self.gpu, size)? else {
            return Ok(()); // no area: nothing to render into
        };
        let Some(extent) = presenter.extent() else {
            return Ok(());
        };
        // Only this slot's previous frame is waited for; the other slots' frames may
        // still be on the GPU while this one is uploaded and recorded.
        let (slot, gpu_ms) = presenter.begin_frame()?;
        self.upload(rebuilt, extent, slot)?;
        let layout = self.layout(extent)?;
        let Some(presenter) = self.presenter.as_mut() else {
            return Ok(());
        };
        let settings = self.panels.frame_settings();
        // Each panel's underlay (a montage's share one volume), turned away from its camera.
        let seen: Vec<Option<Underlay>> = self
            .panels
            .panels
            .iter()
            .map(Content::underlay_as_seen)
            .collect();
        let mut draws = Vec::with_capacity(self.scene_gpu.len());
        let slot_peaks = self.peaks_gpu.get_mut(slot).map(Vec::as_mut_slice);
        let on_gpu = self
            .scene_gpu
            .iter_mut()
            .zip(slot_peaks.unwrap_or_default().iter_mut());
        for (k, (glyphs, peaks)) in on_gpu.enumerate() {
            let (Some(glyphs), Some(cell)) = (glyphs.as_mut(), layout.cell(k)) else {
                continue;
            };
            let (w, h) = (cell.extent.width, cell.extent.height);
            let underlay = self.underlay_gpu.as_ref().zip(seen[k].as_ref());
            draws.push(PanelDraw {
                glyphs,
                underlay: underlay.map(|(volume, u)| (volume, u.planes.as_slice())),
                peaks: peaks.as_mut(),
                frame: self.panels.frame_params(k, w, h, &settings),
                cell,
            });
        }
        let captions = caption_patches(&self.panels.captions(), &layout)?;
        let strip = self
            .figure
            .strip_pixels()
            .zip(layout.strip_rect())
            .map(|(rgba, rect)| PatchDraw { rgba, rect });
        let patches: Vec<PatchDraw> = strip
            .into_iter()
            .chain(captions.iter().map(|(rect, patch)| PatchDraw {
                rgba: &patch.rgba,
                rect: *rect,
            }))
            .collect();
        let capture = self.options.capture_window.is_some();
        // Not waited for: the next frame in this slot waits (begin_frame), and the GPU
        // time shown is that of the slot's previous frame.
        let outcome = presenter.render(slot, &mut draws, &patches, &settings, capture)?;
        match outcome {
            Outcome::Presented { extent } => {
                self.presented += 1;
                self.last_extent = Some(extent);
                self.gpu_ms = gpu_ms.or(self.gpu_ms);
                self.update_title();
            }
            Outcome::Skipped => self.dirty = true,
        }
        if scripted {
            self.finish_if_done(event_loop)?;
        }
        Ok(())
    }

    /// Uploads the underlay and each panel's glyphs where they changed (content or
    /// method), or all of them when the passes were `rebuilt` for a new colour format,
    /// and `slot`'s copy of each panel's peaks. Replaced glyphs are retired through the
    /// glyph renderer, never waited for: they are dropped once every slot has begun a
    /// frame since.
    fn upload(&mut self, rebuilt: bool, extent: vk::Extent2D, slot: usize) -> Result<()> {
        let Some(presenter) = self.presenter.as_mut() else {
            return Ok(());
        };
        if rebuilt {
            self.underlay_gpu = None;
            for versions in &mut self.peaks_uploaded {
                versions.fill(None);
            }
        }
        if let (Some(underlay), None) = (&self.panels.first().underlay, &self.underlay_gpu) {
            let pass = presenter.underlay_pass();
            self.underlay_gpu = Some(pass.upload(self.gpu.context(), &underlay.volume)?);
        }
        let settings = self.panels.frame_settings();
        for (k, panel) in self.panels.panels.iter().enumerate() {
            let settings = RenderSettings {
                path: crate::panel_path(&settings, self.gpu.context(), &panel.sets),
                ..settings
            };
            // Shadows or ambient occlusion on or off take a pipeline of their own, as a
            // method does; the ray caster its glyphs of their own.
            let wanted = Some((
                panel.version,
                settings.method,
                settings.casts_rays(),
                settings.path,
            ));
            if rebuilt || self.uploaded[k] != wanted {
                // Glyphs keep the method (and shadows) they were uploaded for: a switch
                // uploads again.
                let glyphs = presenter.glyphs_mut().upload(&panel.sets, &settings)?;
                if let Some(old) = self.scene_gpu[k].replace(glyphs) {
                    self.replaced.0 += 1;
                    if presenter.others_in_flight(slot)? {
                        self.replaced.1 += 1;
                    }
                    presenter.glyphs_mut().retire(old);
                }
                self.uploaded[k] = wanted;
            }
            let peaks_version = &mut self.peaks_uploaded[slot][k];
            if *peaks_version != Some(panel.version) {
                // The frame block is written again before each frame, for the cell.
                let frame = panel.frame_params_with(extent.width, extent.height, &settings);
                // This slot's previous frame completed: its old copy is free.
                self.peaks_gpu[slot][k] = match &panel.peaks {
                    Some(peaks) => {
                        presenter
                            .peaks_pass()
                            .upload(self.gpu.context(), peaks, &frame)?
                    }
                    None => None,
                };
                *peaks_version = Some(panel.version);
            }
        }
        Ok(())
    }

    fn update_title(&self) {
        let Some(window) = &self.window else { return };
        let s = self.panels.settings();
        let first = self.panels.first();
        // A block's label names the block; a slice's is its index.
        let slice = self.panels.slice_label().map_or_else(String::new, |l| {
            if l.starts_with("block ") {
                format!(" | {l}")
            } else {
                format!(" | slice {l}")
            }
        });
        let orientation = first
            .orientation_name()
            .map_or_else(String::new, |name| format!(" | {name}"));
        let time = self
            .gpu_ms
            .map_or_else(|| "n/a".to_owned(), |ms| format!("{ms:.2} ms"));
        let busy = self
            .panels
            .busy()
            .map_or_else(String::new, |b| format!(" | {b}"));
        window.set_title(&format!(
            "glyphcast | {} step {:.4} {} | {} | negative {}{slice}{orientation} | GPU {time}{busy}",
            format!("{:?}", s.method).to_lowercase(),
            s.step,
            refinement_name(s.refinement),
            color_name(s.color),
            first.negative_name(),
        ));
    }

    /// A scripted run ends after its frames and script, once the window has the size
    /// the last `resize:` asked for: then the capture and the screenshot are written.
    fn finish_if_done(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        let Some(frames) = self.options.frames else {
            return Ok(());
        };
        let script_done = self.script_next >= self.options.script.len();
        let settled = self.pending_size.is_none_or(|(w, h)| {
            self.last_extent
                == Some(vk::Extent2D {
                    width: w,
                    height: h,
                })
        });
        if self.presented < frames || !script_done || self.panels.busy().is_some() {
            return Ok(());
        }
        if !settled {
            if self.presented >= frames + SETTLE_FRAMES {
                let (w, h) = self.pending_size.unwrap_or_default();
                return Err(Error::setup(
                    "window of the size asked for",
                    format_args!("{w}x{h} was not taken"),
                ));
            }
            return Ok(());
        }
        if let Some(presenter) = self.presenter.as_mut() {
            presenter.wait_all()?;
            let replaced = self.replaced;
            eprintln!(
                "frames in flight: {}; glyph uploads replaced: {} ({} while another frame was \
                 on the GPU), retired ones still held: {}",
                presenter.frames_in_flight(),
                replaced.0,
                replaced.1,
                presenter.glyphs().retired_count()
            );
            let mut paths: Vec<String> = self
                .scene_gpu
                .iter()
                .flatten()
                .map(|glyphs| glyphs.path().to_string())
                .collect();
            paths.dedup();
            eprintln!("ray caster: {}", paths.join(", "));
            // How the last frame's hidden glyphs were culled (early outs, or off).
            let mut culling: Vec<String> = self
                .scene_gpu
                .iter()
                .flatten()
                .map(|glyphs| {
                    let slots = 0..presenter.frames_in_flight();
                    let early = slots
                        .into_iter()
                        .any(|k| glyphs.culling(k) == glyphcast::render::Culling::EarlyOut);
                    if early { "early-out" } else { "off" }.to_owned()
                })
                .collect();
            culling.dedup();
            eprintln!("hidden glyphs culled: {}", culling.join(", "));
        }
        if let Some(path) = self.options.capture_window.clone() {
            let capture = self
                .presenter
                .as_ref()
                .map(Presenter::capture)
                .transpose()?
                .flatten()
                .ok_or(Error::Call {
                    call: "capture",
                    expected: "a captured frame",
                })?;
            glyphcast::io::png::write_png_rgba8(
                &path,
                capture.width,
                capture.height,
                &capture.rgba,
            )?;
            eprintln!("wrote {}", path.display());
        }
        if let Some(path) = self.options.screenshot.clone() {
            self.screenshot(&path)?;
        }
        event_loop.exit();
        Ok(())
    }

    /// Renders the current view through the headless renderer at the window's size and
    /// writes it as a PNG (and the scene as shown, with --save-scene): each panel at its
    /// cell's size, composed as `render` composes a montage, with the colour bar's strip
    /// appended as `render --colorbar` appends it, in the window's layout.
    fn screenshot(&mut self, path: &Path) -> Result<()> {
        let size = self.last_extent.unwrap_or_else(|| self.window_size());
        if size.width == 0 || size.height == 0 {
            eprintln!("screenshot: the window has no area");
            return Ok(());
        }
        let layout = self.layout(size)?;
        if self.headless.is_none() {
            self.headless = Some(HeadlessRenderer::new(&self.gpu)?);
        }
        let Some(renderer) = self.headless.as_mut() else {
            return Ok(());
        };
        let started = Instant::now();
        let image = self
            .figure
            .render_headless(renderer, &self.gpu, &self.panels, &layout)?;
        // The screenshot and the scene as shown: both new, or both as they were.
        let png =
            glyphcast::io::png::encode_png_rgba8(path, image.width, image.height, &image.rgba)?;
        // The scene's image is the glyphs' area: without the colour bar's strip.
        let (width, height) = (layout.grid.cell.0, layout.grid.cell.1);
        let scene = self.options.save_scene.as_ref().map(|scene_path| {
            let shown = self.panels.first().shown_scene(width, height);
            (scene_path, shown.to_json())
        });
        let mut files: Vec<(&Path, &[u8])> = vec![(path, &png)];
        if let Some((scene_path, json)) = &scene {
            files.push((scene_path.as_path(), json.as_bytes()));
        }
        glyphcast::io::atomic::write_all_atomic(&files)?;
        eprintln!(
            "wrote {} ({}x{}, {:.0} ms)",
            path.display(),
            image.width,
            image.height,
            started.elapsed().as_secs_f64() * 1e3
        );
        Ok(())
    }
}

impl Drop for App {
    /// Frames may still be in flight when the event loop ends (a closed window, an
    /// error): they are waited for before the glyphs, peaks and underlay they read go.
    fn drop(&mut self) {
        let _ = self.gpu.wait_idle();
    }
}

/// Applies `change` to `settings` if the result passes validation; otherwise leaves them
/// as they were and returns the validation's error.
fn change_checked(
    settings: &mut RenderSettings,
    change: impl FnOnce(&mut RenderSettings),
) -> Result<()> {
    let mut changed = *settings;
    change(&mut changed);
    changed.validate()?;
    *settings = changed;
    Ok(())
}

/// The captions of the panels (`Panels::captions`) as `render --lightbox` draws them, and
/// where each goes in the window.
fn caption_patches(
    captions: &[Option<String>],
    layout: &WindowLayout,
) -> Result<Vec<(vk::Rect2D, CaptionPatch)>> {
    let mut patches = Vec::new();
    for (k, caption) in captions.iter().enumerate() {
        let (Some(text), Some(cell)) = (caption, layout.cell(k)) else {
            continue;
        };
        let patch = caption_patch(cell.extent.width, cell.extent.height, text)?;
        let rect = vk::Rect2D {
            offset: vk::Offset2D {
                x: cell.offset.x + patch.x as i32,
                y: cell.offset.y + patch.y as i32,
            },
            extent: vk::Extent2D {
                width: patch.w,
                height: patch.h,
            },
        };
        if patch.w > 0 && patch.h > 0 {
            patches.push((rect, patch));
        }
    }
    Ok(patches)
}
