//! What the viewer shows: the scene (from a file, or the current slice of a volume), the
//! glyph data prepared from it, the render settings and the camera.
//!
//! Moving the slice or switching the negative-lobe mode rebuilds only the glyph data
//! (coefficients and bounds, on the CPU) and bumps [`Content::version`] so that the
//! window re-uploads it; the tensor layout stays the same, so no pipeline is created.
//! The rebuild runs on a worker thread: the window keeps drawing the glyphs it has, shows
//! the preparation's progress in its title, and takes the new glyphs when
//! [`Content::poll`] finds them ready. A move asked for while one is prepared waits, and
//! only the latest of those is prepared next.
use glyphcast::camera::Camera;
use glyphcast::glyph::NegativeMode;
use glyphcast::parallel::Progress;
use glyphcast::render::RenderSettings;
use glyphcast::render::frame::{FrameParams, SceneExtent};
use glyphcast::render::glyph_data::{
    GlyphSetData, measure_largest_radius, prepare_scene, prepare_set_with_progress,
};
use glyphcast::render::peaks::PeakSet;
use glyphcast::render::underlay::{Underlay, UnderlayPlane, extent_with_planes};
use glyphcast::scene::{GlyphSet, Scene};
use glyphcast::{Error, Result, Setting};
use glyphcast_dmri::volume::{
    SliceRegion, Volume, VolumeOptions, VolumeScene, show_block, slice_framing, slice_plane,
    turned_away, volume_scene_with_progress,
};
use std::ops::Range;
use std::sync::{Arc, mpsc};
use std::time::Instant;

/// Called from the worker thread when a preparation has finished (the window's event
/// loop proxy, so that the window wakes up to take the result).
pub type Waker = Arc<dyn Fn() + Send + Sync>;

/// Where the viewer's glyphs come from.
pub enum ViewSource {
    /// A scene file: its glyphs, camera and image size.
    Scene(Scene),
    /// A volume and the options its first view was built with (`view`, whose report the
    /// caller has shown); the slice can then be moved through the volume.
    Volume {
        /// The volume the slice moves through.
        volume: Box<Volume>,
        /// The options of the first view; slice moves change only their slice.
        options: Box<VolumeOptions>,
        /// The first view, built by the caller with those options.
        view: Box<VolumeScene>,
    },
    /// A montage of slices of one volume (`--views`, `--lightbox`), shown through
    /// [`Panels`](super::Panels).
    Montage(Box<MontageSource>),
}

/// The panels of a montage: each panel's options (its slice) and first view, in reading
/// order, as `render --views/--lightbox` makes them.
pub struct MontageSource {
    /// The volume every panel is a slice of.
    pub volume: Volume,
    /// Each panel's options (its plane and slice) and first view, in reading order.
    pub panels: Vec<(VolumeOptions, VolumeScene)>,
    /// Each panel's underlay on its slice plane (`--underlay`), if any: one volume shared
    /// by all, the planes each panel's own; it moves with the panel's slice.
    pub underlays: Vec<Option<Underlay>>,
    /// Panels to a row.
    pub columns: usize,
    /// `--lightbox`: the panels are slices of one plane that move together; else
    /// (`--views`) each panel is a plane of its own, and slice moves move one of them.
    pub lightbox: bool,
}

/// The volume behind a volume view, and where its slice (or three slices) are.
struct VolumeSlice {
    volume: Arc<Volume>,
    options: VolumeOptions,
    /// The voxel box of a block view (`options.block`), which has no slice to move.
    block: Option<[Range<usize>; 3]>,
    /// Each voxel axis's slice index, and the indices it may take; only the `active`
    /// axis's is shown unless `options.slices` is set.
    index: [usize; 3],
    indices: [Range<usize>; 3],
    active: usize,
    /// The framing camera's target for the current slice: moving the slice moves the
    /// camera by the change of this point, so the view stays on the slice.
    framed_target: glam::DVec3,
    /// The streamlines of `--tracks` while they are hidden (`T`): `options.tracks` is
    /// then `None`.
    hidden_tracks: Option<glyphcast_dmri::volume::ViewTracks>,
}

/// What one view (or one montage panel) shows: its glyphs, settings, camera and slice,
/// rebuilt on a worker thread when the slice or the negative-lobe mode changes.
pub struct Content {
    /// The scene drawn: its glyph sets, camera and image size.
    pub scene: Scene,
    /// The glyph sets of `scene`, prepared for upload.
    pub sets: Vec<GlyphSetData>,
    /// How the glyphs are drawn; the same copy in every panel.
    pub settings: RenderSettings,
    /// The camera on screen.
    pub camera: Camera,
    /// The camera `R` goes back to (the one the scene or the volume's framing gave).
    pub home: Camera,
    /// Bumped whenever `sets` change.
    pub version: u64,
    /// The underlay, its planes on the current slices.
    pub underlay: Option<Underlay>,
    /// The fibre peaks of the current slices, if any.
    pub peaks: Option<PeakSet>,
    negative: Option<NegativeMode>,
    volume: Option<VolumeSlice>,
    job: Option<Job>,
    queued: Option<Rebuild>,
    waker: Option<Waker>,
}

/// A rebuild of the glyph data. A slice move also applies the current negative mode, so
/// it stands for a negative-mode rebuild queued before it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Rebuild {
    Slice,
    Negative,
}

/// A rebuild running on a worker thread.
struct Job {
    what: String,
    started: Instant,
    progress: Arc<Progress>,
    result: mpsc::Receiver<Result<Prepared>>,
}

/// What a job hands back: the new glyph sets and, for each, its prepared data, or None
/// where the set is unchanged and keeps the data it has.
struct Prepared {
    glyph_sets: Vec<GlyphSet>,
    data: Vec<Option<GlyphSetData>>,
    /// A volume slice's peaks (`None`: kept as they are).
    peaks: Option<Option<PeakSet>>,
}

/// Where a job's glyph sets come from.
enum Source {
    Volume(Arc<Volume>, Box<VolumeOptions>),
    Sets(Vec<GlyphSet>),
}

impl Content {
    /// `negative`, when given, replaces every glyph set's negative-lobe mode, now and
    /// after each slice move (`--negative`).
    pub fn new(
        source: ViewSource,
        settings: RenderSettings,
        negative: Option<NegativeMode>,
    ) -> Result<Content> {
        settings.validate()?;
        match source {
            ViewSource::Scene(scene) => Content::build(scene, None, settings, negative),
            ViewSource::Volume {
                volume,
                options,
                view,
            } => Content::for_slice(Arc::from(volume), *options, *view, settings, negative),
            ViewSource::Montage(_) => Err(Error::Call {
                call: "Content::new",
                expected: "a single view (a montage is shown through viewer::Panels)",
            }),
        }
    }

    /// The content of a view of `volume` made with `options` (one slice, or three).
    pub(crate) fn for_slice(
        volume: Arc<Volume>,
        options: VolumeOptions,
        view: VolumeScene,
        settings: RenderSettings,
        negative: Option<NegativeMode>,
    ) -> Result<Content> {
        let indices = std::array::from_fn(|axis| {
            let (lo, hi) = options.voxels.axes[axis].unwrap_or((None, None));
            let length = volume.dims[axis];
            lo.unwrap_or(0).min(length)..hi.unwrap_or(length).min(length)
        });
        let mut index = [0; 3];
        for region in &view.regions {
            index[region.slice.voxel_axis()] = region.index;
        }
        let slice = VolumeSlice {
            block: view.block.clone(),
            framed_target: view.scene.camera.target,
            index,
            indices,
            active: view.region.slice.voxel_axis(),
            volume,
            options,
            hidden_tracks: None,
        };
        let mut content = Content::build(view.scene, Some(slice), settings, negative)?;
        content.peaks = view.peaks;
        Ok(content)
    }

    fn build(
        mut scene: Scene,
        volume: Option<VolumeSlice>,
        settings: RenderSettings,
        negative: Option<NegativeMode>,
    ) -> Result<Content> {
        settings.validate()?;
        if let Some(mode) = negative {
            scene
                .glyph_sets
                .iter_mut()
                .for_each(|set| set.negative = mode);
        }
        let mut sets = prepare_scene(&scene, settings.offset as f64)?;
        // Measured once, as after each rebuild (`take_prepared`): the colour bar and a
        // montage's shared magnitude range read it.
        measure_largest_radius(&mut sets);
        Ok(Content {
            camera: scene.camera,
            home: scene.camera,
            scene,
            sets,
            settings,
            version: 0,
            underlay: None,
            peaks: None,
            negative,
            volume,
            job: None,
            queued: None,
            waker: None,
        })
    }

    /// What the worker calls when a rebuild is ready.
    pub fn set_waker(&mut self, waker: Waker) {
        self.waker = Some(waker);
    }

    /// "preparing slice k=7: bounds 40 %" while a rebuild runs.
    pub fn busy(&self) -> Option<String> {
        self.job.as_ref().map(|job| {
            let (phase, done) = job.progress.get();
            format!("preparing {}: {phase} {:.0} %", job.what, 100.0 * done)
        })
    }

    /// Takes the result of the running rebuild if it is ready (and starts the one asked
    /// for meanwhile); true when the glyph data changed. `wait` blocks until it is.
    pub fn poll(&mut self, wait: bool) -> Result<bool> {
        let Some(job) = &self.job else {
            return Ok(false);
        };
        let result = if wait {
            job.result.recv().map_err(|_| ())
        } else {
            match job.result.try_recv() {
                Err(mpsc::TryRecvError::Empty) => return Ok(false),
                received => received.map_err(|_| ()),
            }
        };
        let result = result.unwrap_or(Err(Error::Thread {
            what: "the glyph preparation",
        }));
        let Some(job) = self.job.take() else {
            return Ok(false);
        };
        let applied = result.and_then(|prepared| self.take_prepared(prepared));
        if applied.is_ok() {
            let glyphs: usize = self.scene.glyph_sets.iter().map(|s| s.len()).sum();
            eprintln!(
                "{}: {glyphs} glyphs ready in {:.0} ms",
                job.what,
                job.started.elapsed().as_secs_f64() * 1e3
            );
        }
        if let Some(next) = self.queued.take() {
            self.start(next)?;
        }
        applied.map(|()| true)
    }

    /// Frame parameters for an image of `width` x `height` with the current camera, as
    /// the headless renderer computes them.
    pub fn frame_params(&self, width: u32, height: u32) -> FrameParams {
        self.frame_params_with(width, height, &self.settings)
    }

    /// [`Content::frame_params`] with `settings` in place of the content's own (a
    /// montage's panels share one magnitude range).
    pub fn frame_params_with(
        &self,
        width: u32,
        height: u32,
        settings: &RenderSettings,
    ) -> FrameParams {
        let extent = self.extent(settings);
        FrameParams::new(&self.camera, width, height, &extent, settings)
    }

    /// The depth and magnitude ranges of a frame drawn with `settings`, the underlay's
    /// planes included.
    pub fn extent(&self, settings: &RenderSettings) -> SceneExtent {
        let mut extent = SceneExtent::for_settings(&self.camera, &self.sets, settings);
        if let Some(underlay) = self.underlay_as_seen() {
            extent = extent_with_planes(&self.camera, extent, &underlay.planes);
        }
        if let Some(peaks) = &self.peaks {
            extent = peaks.widen(&self.camera, extent);
        }
        extent
    }

    /// Shows `underlay` on the volume's slices (and moves it with them); an underlay for
    /// a scene file, which has no slices, is a usage error.
    pub fn set_underlay(&mut self, underlay: Option<Underlay>) -> Result<()> {
        if underlay.is_some() && self.volume.is_none() {
            return Err(Error::setting(
                Setting::Underlay,
                "applies to volume input, not to a scene file",
            ));
        }
        self.underlay = underlay;
        self.place_underlay()
    }

    /// The underlay as the current camera sees it: a plane behind the glyphs
    /// (`--underlay-plane back`) on the far side of its slice from the camera, whichever
    /// side the camera has orbited to.
    pub fn underlay_as_seen(&self) -> Option<Underlay> {
        self.underlay.as_ref().map(|underlay| Underlay {
            planes: underlay
                .planes
                .iter()
                .map(|plane| turned_away(plane, &self.camera))
                .collect(),
            ..underlay.clone()
        })
    }

    /// Puts the underlay's planes on the current slices.
    fn place_underlay(&mut self) -> Result<()> {
        let (Some(underlay), Some(v)) = (self.underlay.as_mut(), self.volume.as_ref()) else {
            return Ok(());
        };
        let (volume, options) = (&v.volume, &v.options);
        let region = |slice| SliceRegion::new(volume.dims, slice, &options.voxels, &volume.file);
        let regions = match options.slices {
            Some(slices) => (0..3)
                .map(|axis| region(slices.slice(axis)))
                .collect::<Result<Vec<_>>>()?,
            None => vec![region(options.slice)?],
        };
        // Each plane keeps the offset from its slice it was made with (behind the
        // glyphs, `volume::UnderlayPlacement`): the slice moves along the plane's normal
        // and the camera with it, so the glyphs stay in front of it.
        let offsets: Vec<glam::DVec3> = underlay.planes.iter().map(|p| p.sample_offset).collect();
        underlay.planes = regions
            .iter()
            .enumerate()
            .map(|(k, r)| {
                let plane = slice_plane(r, &volume.voxel_to_world);
                let offset = offsets.get(k).copied().unwrap_or_default();
                UnderlayPlane {
                    origin: plane.origin + offset,
                    sample_offset: offset,
                    ..plane
                }
            })
            .collect();
        Ok(())
    }

    /// The scene as shown: the glyphs of the current slice and negative mode, the current
    /// camera and the given image size.
    pub fn shown_scene(&self, width: u32, height: u32) -> Scene {
        let mut scene = self.scene.clone();
        scene.camera = self.camera;
        scene.image.width = width;
        scene.image.height = height;
        scene
    }

    /// The orientation convention of a volume's views ("radiological"), None for a scene
    /// file.
    pub fn orientation_name(&self) -> Option<&'static str> {
        self.volume.as_ref().map(|v| v.options.orientation.name())
    }

    /// "k=3 of 0..4" for a volume ("i=1 j=2 [k=3]" with three slices, the active one in
    /// brackets; "block 0:10,0:10,2:8" for a block, which has no slice), None for a scene
    /// file.
    pub fn slice_label(&self) -> Option<String> {
        self.volume.as_ref().map(|v| {
            if let Some(block) = &v.block {
                return format!("block {}", show_block(block));
            }
            let empty = if self.sets.iter().all(|s| s.is_empty()) {
                " (empty)"
            } else {
                ""
            };
            let name = |axis: usize| format!("{}={}", ["i", "j", "k"][axis], v.index[axis]);
            if v.options.slices.is_some() {
                let names: Vec<String> = (0..3)
                    .map(|axis| {
                        if axis == v.active {
                            format!("[{}]", name(axis))
                        } else {
                            name(axis)
                        }
                    })
                    .collect();
                format!("{}{empty}", names.join(" "))
            } else {
                let range = &v.indices[v.active];
                format!(
                    "{} of {}..{}{empty}",
                    name(v.active),
                    range.start,
                    range.end
                )
            }
        })
    }

    /// "k=3": the voxel axis and index of the (active) slice; None for a scene file.
    pub fn slice_name(&self) -> Option<String> {
        self.volume
            .as_ref()
            .map(|v| format!("{}={}", ["i", "j", "k"][v.active], v.index[v.active]))
    }

    /// How many slices the (active) slice can move down and up within the volume and
    /// --voxels; None for a scene file.
    pub fn slice_room(&self) -> Option<(usize, usize)> {
        self.volume.as_ref().map(|v| {
            let (range, index) = (&v.indices[v.active], v.index[v.active]);
            (
                index.saturating_sub(range.start),
                range.end.saturating_sub(1).saturating_sub(index),
            )
        })
    }

    /// With three slices, makes the slice perpendicular to voxel axis `axis` (0 = i,
    /// sagittal; 1 = j, coronal; 2 = k, axial) the one that moves; returns whether it
    /// changed.
    pub fn set_active_slice(&mut self, axis: usize) -> bool {
        match self.volume.as_mut() {
            Some(v) if v.options.slices.is_some() && axis < 3 => {
                let changed = v.active != axis;
                v.active = axis;
                changed
            }
            _ => {
                eprintln!("active slice: only a view of three slices has one to choose");
                false
            }
        }
    }

    /// Moves the (active) slice by `delta` (clamped to the volume and --voxels); returns
    /// whether it moved. A slice with nothing to draw is shown empty, with the reason on
    /// stderr.
    pub fn move_slice(&mut self, delta: i64) -> Result<bool> {
        let Some(v) = self.volume.as_mut() else {
            eprintln!("slice: a scene file has no slices to move through");
            return Ok(false);
        };
        if v.block.is_some() {
            eprintln!("slice: a block has no slice to move; orbit, pan and zoom move the camera");
            return Ok(false);
        }
        let axis = v.active;
        let range = &v.indices[axis];
        let last = range.end.saturating_sub(1) as i64;
        let index = (v.index[axis] as i64 + delta).clamp(range.start as i64, last) as usize;
        if index == v.index[axis] {
            return Ok(false);
        }
        let mut options = v.options.clone();
        let volume = &v.volume;
        if let Some(slices) = options.slices.as_mut() {
            // The three-slice camera frames the whole volume: it stays where it is.
            slices.indices[axis] = Some(index);
        } else {
            options.slice.index = Some(index);
            let framing = slice_framing(volume, &options)?;
            let shift = framing.camera.target - v.framed_target;
            self.camera.eye += shift;
            self.camera.target += shift;
            self.home = framing.camera;
            v.framed_target = framing.camera.target;
        }
        v.index[axis] = index;
        v.options = options;
        self.place_underlay()?;
        self.request(Rebuild::Slice)?;
        Ok(true)
    }

    /// Shows (`Some(true)`), hides or toggles (`None`) the streamlines of `--tracks`;
    /// returns whether that changes the view (rebuilt as after a slice move). A view
    /// without streamlines says so on stderr.
    pub fn set_tracks(&mut self, shown: Option<bool>) -> Result<bool> {
        let Some(v) = self.volume.as_mut() else {
            eprintln!(
                "tracks: a scene file has no streamlines (render or view a volume with --tracks)"
            );
            return Ok(false);
        };
        let now = v.options.tracks.is_some();
        if !now && v.hidden_tracks.is_none() {
            eprintln!("tracks: no streamlines to show (--tracks FILE)");
            return Ok(false);
        }
        if shown.unwrap_or(!now) == now {
            return Ok(false);
        }
        std::mem::swap(&mut v.options.tracks, &mut v.hidden_tracks);
        eprintln!("tracks: {}", if now { "hidden" } else { "shown" });
        self.request(Rebuild::Slice)?;
        Ok(true)
    }

    /// Whether the view draws the streamlines of `--tracks` now.
    pub fn tracks_shown(&self) -> bool {
        self.volume
            .as_ref()
            .is_some_and(|v| v.options.tracks.is_some())
    }

    /// Starts a rebuild, or queues it behind the running one.
    fn request(&mut self, rebuild: Rebuild) -> Result<()> {
        if self.job.is_some() {
            if self.queued != Some(Rebuild::Slice) {
                self.queued = Some(rebuild);
            }
            return Ok(());
        }
        self.start(rebuild)
    }

    fn start(&mut self, rebuild: Rebuild) -> Result<()> {
        let (what, source) = match (rebuild, &self.volume) {
            (Rebuild::Slice, Some(v)) => {
                let axis = v.active;
                let name = ["i", "j", "k"][axis];
                (
                    format!("slice {name}={}", v.index[axis]),
                    Source::Volume(v.volume.clone(), Box::new(v.options.clone())),
                )
            }
            _ => (
                "negative lobes".to_owned(),
                Source::Sets(self.scene.glyph_sets.clone()),
            ),
        };
        let old = self.scene.glyph_sets.clone();
        let negative = self.negative;
        let offset = self.settings.offset as f64;
        let progress = Arc::new(Progress::default());
        let (sender, result) = mpsc::channel();
        let waker = self.waker.clone();
        let worker_progress = progress.clone();
        let worker_what = what.clone();
        std::thread::Builder::new()
            .name("glyphcast-prepare".into())
            .spawn(move || {
                let prepared = prepare(
                    &worker_what,
                    source,
                    &old,
                    negative,
                    offset,
                    &worker_progress,
                );
                // The window may have closed meanwhile; then nobody wants the result.
                let _ = sender.send(prepared);
                if let Some(wake) = waker {
                    wake();
                }
            })
            .map_err(|e| Error::setup("thread for the glyph preparation", e))?;
        self.job = Some(Job {
            what,
            started: Instant::now(),
            progress,
            result,
        });
        Ok(())
    }

    /// Puts a job's glyph sets into the scene, keeping the data of the unchanged ones.
    fn take_prepared(&mut self, prepared: Prepared) -> Result<()> {
        let mut old: Vec<Option<GlyphSetData>> = std::mem::take(&mut self.sets)
            .into_iter()
            .map(Some)
            .collect();
        let mut sets = Vec::with_capacity(prepared.data.len());
        for (index, mut data) in prepared.data.into_iter().enumerate() {
            // New sets are measured once here (about 2 us a glyph), not in every frame.
            if let Some(fresh) = data.as_mut() {
                measure_largest_radius(std::slice::from_mut(fresh));
            }
            match data.or_else(|| old.get_mut(index).and_then(Option::take)) {
                Some(data) => sets.push(data),
                None => {
                    return Err(Error::Call {
                        call: "take_prepared",
                        expected: "prepared data for every glyph set kept",
                    });
                }
            }
        }
        self.scene.glyph_sets = prepared.glyph_sets;
        self.sets = sets;
        if let Some(peaks) = prepared.peaks {
            self.peaks = peaks;
        }
        self.version += 1;
        Ok(())
    }

    /// Sets every glyph set's negative-lobe mode (`None`: toggle between abs and hide).
    pub fn set_negative(&mut self, mode: Option<NegativeMode>) -> Result<()> {
        let current = self
            .negative
            .or_else(|| self.scene.glyph_sets.first().map(|s| s.negative));
        let mode = mode.unwrap_or(match current {
            Some(NegativeMode::Hide) => NegativeMode::Abs,
            _ => NegativeMode::Hide,
        });
        self.negative = Some(mode);
        self.request(Rebuild::Negative)
    }

    /// The negative-lobe mode shown in the title: the one set by `N` or `--negative`,
    /// else the first glyph set's own.
    pub fn negative_name(&self) -> &'static str {
        let mode = self
            .negative
            .or_else(|| self.scene.glyph_sets.first().map(|s| s.negative));
        match mode {
            Some(NegativeMode::Hide) => "hide",
            _ => "abs",
        }
    }
}

/// The worker's part of a rebuild: the glyph sets (a volume slice, sized and normalised,
/// or the sets as they are), the negative mode, and the bounds of every set that changed.
fn prepare(
    what: &str,
    source: Source,
    old: &[GlyphSet],
    negative: Option<NegativeMode>,
    offset: f64,
    progress: &Progress,
) -> Result<Prepared> {
    let (mut glyph_sets, peaks) = match source {
        Source::Volume(volume, options) => {
            match volume_scene_with_progress(&volume, &options, Some(progress)) {
                Ok(view) => (view.scene.glyph_sets, Some(view.peaks)),
                // A slice with nothing to draw is shown empty, with the reason.
                Err(Error::Input { message, .. }) => {
                    eprintln!("{what}: {message}");
                    (Vec::new(), Some(None))
                }
                Err(e) => return Err(e),
            }
        }
        Source::Sets(sets) => (sets, None),
    };
    if let Some(mode) = negative {
        for set in &mut glyph_sets {
            set.negative = mode;
        }
    }
    let data = glyph_sets
        .iter()
        .enumerate()
        .map(|(index, set)| {
            if old.get(index) == Some(set) {
                Ok(None)
            } else {
                prepare_set_with_progress(set, index, offset, Some(progress)).map(Some)
            }
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(Prepared {
        glyph_sets,
        data,
        peaks,
    })
}
