//! What the viewer shows: the scene (from a file, or the current slice of a volume), the
//! glyph data prepared from it, the render settings and the camera.
//!
//! Moving the slice or switching the negative-lobe mode rebuilds only the glyph data
//! (coefficients and bounds, on the CPU) and bumps [`Content::version`] so that the
//! window re-uploads it; the tensor layout stays the same, so no pipeline is created.
use crate::camera::Camera;
use crate::glyph::NegativeMode;
use crate::io::scene::Scene;
use crate::render::RenderSettings;
use crate::render::frame::{FrameParams, SceneExtent};
use crate::render::glyph_data::{GlyphSetData, prepare_scene, prepare_set};
use crate::volume::{SliceRegion, Volume, VolumeOptions, VolumeScene, frame_region, volume_scene};
use crate::{Error, Result};
use std::ops::Range;

/// Where the viewer's glyphs come from.
pub enum ViewSource {
    /// A scene file: its glyphs, camera and image size.
    Scene(Scene),
    /// A volume and the options its first view was built with (`view`, whose report the
    /// caller has shown); the slice can then be moved through the volume.
    Volume {
        volume: Box<Volume>,
        options: Box<VolumeOptions>,
        view: Box<VolumeScene>,
    },
}

/// The volume behind a volume view, and where its slice (or three slices) are.
struct VolumeSlice {
    volume: Box<Volume>,
    options: VolumeOptions,
    /// Each voxel axis's slice index, and the indices it may take; only the `active`
    /// axis's is shown unless `options.slices` is set.
    index: [usize; 3],
    indices: [Range<usize>; 3],
    active: usize,
    /// The framing camera's target for the current slice: moving the slice moves the
    /// camera by the change of this point, so the view stays on the slice.
    framed_target: glam::DVec3,
}

pub struct Content {
    pub scene: Scene,
    pub sets: Vec<GlyphSetData>,
    pub settings: RenderSettings,
    /// The camera on screen, and the one `R` goes back to.
    pub camera: Camera,
    pub home: Camera,
    /// Bumped whenever `sets` change.
    pub version: u64,
    negative: Option<NegativeMode>,
    volume: Option<VolumeSlice>,
}

impl Content {
    pub fn new(source: ViewSource, settings: RenderSettings) -> Result<Content> {
        settings.validate()?;
        let (scene, volume) = match source {
            ViewSource::Scene(scene) => (scene, None),
            ViewSource::Volume {
                volume,
                options,
                view,
            } => {
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
                    framed_target: view.scene.camera.target,
                    index,
                    indices,
                    active: view.region.slice.voxel_axis(),
                    volume,
                    options: *options,
                };
                (view.scene, Some(slice))
            }
        };
        let sets = prepare_scene(&scene, settings.offset as f64)?;
        Ok(Content {
            camera: scene.camera,
            home: scene.camera,
            scene,
            sets,
            settings,
            version: 0,
            negative: None,
            volume,
        })
    }

    /// Frame parameters for an image of `width` x `height` with the current camera, as
    /// the headless renderer computes them.
    pub fn frame_params(&self, width: u32, height: u32) -> FrameParams {
        let extent = SceneExtent::of_glyph_sets(&self.camera, &self.sets);
        FrameParams::new(&self.camera, width, height, &extent, &self.settings)
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

    /// "k=3 of 0..4" for a volume ("i=1 j=2 [k=3]" with three slices, the active one in
    /// brackets), None for a scene file.
    pub fn slice_label(&self) -> Option<String> {
        self.volume.as_ref().map(|v| {
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
                eprintln!("active slice: only a view of three slices (--slices) has one to choose");
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
            let region =
                SliceRegion::new(volume.dims, options.slice, &options.voxels, &volume.file)?;
            let framing = frame_region(
                &region,
                &volume.voxel_to_world,
                options.projection,
                options.image,
            )?;
            let shift = framing.camera.target - v.framed_target;
            self.camera.eye += shift;
            self.camera.target += shift;
            self.home = framing.camera;
            v.framed_target = framing.camera.target;
        }
        v.index[axis] = index;
        let started = std::time::Instant::now();
        let glyph_sets = match volume_scene(volume, &options) {
            Ok(view) => view.scene.glyph_sets,
            Err(Error::Input { message, .. }) => {
                eprintln!("slice {index}: {message}");
                Vec::new()
            }
            Err(e) => return Err(e),
        };
        v.options = options;
        let glyphs: usize = glyph_sets.iter().map(|s| s.len()).sum();
        let moved = self.replace_sets(glyph_sets)?;
        eprintln!(
            "slice {index}: {glyphs} glyphs ready in {:.0} ms",
            started.elapsed().as_secs_f64() * 1e3
        );
        Ok(moved)
    }

    /// Puts `glyph_sets` into the scene, preparing only the sets that changed (with three
    /// slices, moving one leaves the others' glyphs as they were).
    fn replace_sets(&mut self, mut glyph_sets: Vec<crate::io::scene::GlyphSet>) -> Result<bool> {
        if let Some(mode) = self.negative {
            for set in &mut glyph_sets {
                set.negative = mode;
            }
        }
        let mut old: Vec<Option<GlyphSetData>> = std::mem::take(&mut self.sets)
            .into_iter()
            .map(Some)
            .collect();
        let mut sets = Vec::with_capacity(glyph_sets.len());
        for (index, set) in glyph_sets.iter().enumerate() {
            let same = self.scene.glyph_sets.get(index) == Some(set);
            match old.get_mut(index).and_then(Option::take) {
                Some(data) if same => sets.push(data),
                _ => sets.push(prepare_set(set, index, self.settings.offset as f64)?),
            }
        }
        self.scene.glyph_sets = glyph_sets;
        self.sets = sets;
        self.version += 1;
        Ok(true)
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
        self.rebuild()
    }

    pub fn negative_name(&self) -> &'static str {
        let mode = self
            .negative
            .or_else(|| self.scene.glyph_sets.first().map(|s| s.negative));
        match mode {
            Some(NegativeMode::Hide) => "hide",
            _ => "abs",
        }
    }

    /// Applies the negative mode and prepares the glyph data again (bounds depend on it).
    fn rebuild(&mut self) -> Result<()> {
        if let Some(mode) = self.negative {
            for set in &mut self.scene.glyph_sets {
                set.negative = mode;
            }
        }
        self.sets = prepare_scene(&self.scene, self.settings.offset as f64)?;
        self.version += 1;
        Ok(())
    }
}
