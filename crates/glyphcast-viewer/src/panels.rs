//! What the window shows, as panels: one [`Content`] for a scene file or a volume view,
//! or one per panel of a montage (`--views`, `--lightbox`), each with its own slice,
//! glyphs and camera, laid out in `render`'s grid.
//!
//! Settings are one for all panels (each content holds the same copy). Camera moves
//! (orbit, pan, zoom, reset) act on every panel alike, so the panels of a lightbox stay
//! the same view of different slices. Slice moves move every lightbox panel by the same
//! count, shortened so that none leaves the volume (the spacing is kept); with `--views`
//! they move the active panel's slice: the first panel's until `1`/`2`/`3` (`active:N`)
//! choose the first, second or third panel. As in `render`, `--color magnitude` without a range
//! maps one range over all panels ([`shared_magnitude_range`]).
use super::content::{Content, ViewSource, Waker};
use glyphcast::camera::Camera;
use glyphcast::glyph::NegativeMode;
use glyphcast::render::compose::colorbar::{ColorBar, common_scale};
use glyphcast::render::compose::montage::shared_magnitude_range;
use glyphcast::render::frame::FrameParams;
use glyphcast::render::settings::RenderSettings;
use glyphcast::render::underlay::Underlay;
use glyphcast::{Error, Result};
use std::sync::Arc;

/// How slice moves act on the panels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Arrangement {
    /// One view.
    Single,
    /// `--views`: the panel at `active` moves.
    Views { active: usize },
    /// `--lightbox`: all panels move together.
    Lightbox,
}

/// Every view the window shows, with one settings copy for all and the rule by which slice
/// moves move them (see the module notes).
pub struct Panels {
    /// In reading order.
    pub panels: Vec<Content>,
    /// Panels to a row.
    pub columns: usize,
    arrangement: Arrangement,
}

impl Panels {
    /// The panels of `source`; `negative`, when given, replaces every glyph set's
    /// negative-lobe mode (`--negative`).
    pub fn new(
        source: ViewSource,
        settings: RenderSettings,
        negative: Option<NegativeMode>,
    ) -> Result<Panels> {
        let ViewSource::Montage(montage) = source else {
            return Ok(Panels {
                panels: vec![Content::new(source, settings, negative)?],
                columns: 1,
                arrangement: Arrangement::Single,
            });
        };
        if montage.panels.is_empty() {
            return Err(Error::data(
                "montage panels",
                glyphcast::error::Problem::Empty,
            ));
        }
        let volume = Arc::new(montage.volume);
        let mut underlays = montage.underlays.into_iter();
        let panels = montage
            .panels
            .into_iter()
            .map(|(options, view)| {
                let mut panel =
                    Content::for_slice(volume.clone(), options, view, settings, negative)?;
                panel.set_underlay(underlays.next().flatten())?;
                Ok(panel)
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(Panels {
            panels,
            columns: montage.columns.max(1),
            arrangement: if montage.lightbox {
                Arrangement::Lightbox
            } else {
                Arrangement::Views { active: 0 }
            },
        })
    }

    /// Whether this is a montage (several views of a volume in a grid).
    pub fn is_montage(&self) -> bool {
        self.arrangement != Arrangement::Single
    }

    /// The first panel (the only one of a single view).
    pub fn first(&self) -> &Content {
        &self.panels[0]
    }

    /// The settings every panel is drawn with.
    pub fn settings(&self) -> RenderSettings {
        self.first().settings
    }

    /// Sets every panel's settings.
    pub fn set_settings(&mut self, settings: RenderSettings) {
        for panel in &mut self.panels {
            panel.settings = settings;
        }
    }

    /// The settings the frames are drawn with: a montage's panels share one magnitude
    /// range, 0 to the largest glyph radius of all of them, as `render` maps it.
    pub fn frame_settings(&self) -> RenderSettings {
        let settings = self.settings();
        match self.arrangement {
            Arrangement::Single => settings,
            _ => shared_magnitude_range(&settings, self.panels.iter().flat_map(|p| &p.sets)),
        }
    }

    /// Panel k's frame block for a cell of `width` x `height`, drawn with `settings`
    /// ([`Panels::frame_settings`]).
    pub fn frame_params(
        &self,
        k: usize,
        width: u32,
        height: u32,
        settings: &RenderSettings,
    ) -> FrameParams {
        self.panels[k].frame_params_with(width, height, settings)
    }

    /// The colour bar of the frames (`--colorbar`, labelled `label` if given), as
    /// `render --colorbar` makes it for the same glyphs; None unless the colour is
    /// magnitude.
    pub fn colorbar(&self, label: Option<&str>) -> Option<ColorBar> {
        let settings = self.frame_settings();
        let extent = self.first().extent(&settings);
        let scale = common_scale(self.panels.iter().map(|p| &p.scene));
        ColorBar::of_magnitude(&settings, &extent, scale, label)
    }

    /// Shows `underlay` on the slices of a single view. A montage's panels have each
    /// their own, on their own slices (`MontageSource::underlays`).
    pub fn set_underlay(&mut self, underlay: Option<Underlay>) -> Result<()> {
        if underlay.is_some() && self.is_montage() {
            return Err(Error::Call {
                call: "Panels::set_underlay",
                expected: "a single view (a montage's underlays come with its panels)",
            });
        }
        self.panels[0].set_underlay(underlay)
    }

    /// Each panel's caption: its slice ("k=3") in a lightbox, as `render --lightbox`
    /// captions its panels; none in other arrangements.
    pub fn captions(&self) -> Vec<Option<String>> {
        let lightbox = self.arrangement == Arrangement::Lightbox;
        self.panels
            .iter()
            .map(|panel| panel.slice_name().filter(|_| lightbox))
            .collect()
    }

    /// What every panel's worker calls when a rebuild is ready.
    pub fn set_waker(&mut self, waker: Waker) {
        for panel in &mut self.panels {
            panel.set_waker(waker.clone());
        }
    }

    /// The first running rebuild's progress, if any.
    pub fn busy(&self) -> Option<String> {
        self.panels.iter().find_map(Content::busy)
    }

    /// Takes every finished rebuild ([`Content::poll`]); true when glyph data changed.
    /// All panels are polled before the first error is returned.
    pub fn poll(&mut self, wait: bool) -> Result<bool> {
        let mut changed = false;
        let mut first_error = None;
        for panel in &mut self.panels {
            match panel.poll(wait) {
                Ok(c) => changed |= c,
                Err(e) => {
                    first_error.get_or_insert(e);
                }
            }
        }
        match first_error {
            Some(e) => Err(e),
            None => Ok(changed),
        }
    }

    /// Applies `change` to every panel's camera.
    pub fn move_cameras(&mut self, mut change: impl FnMut(&mut Camera)) {
        for panel in &mut self.panels {
            change(&mut panel.camera);
        }
    }

    /// Every panel's camera back to its home.
    pub fn reset_cameras(&mut self) {
        for panel in &mut self.panels {
            panel.camera = panel.home;
        }
    }

    /// Moves the slice(s) by `delta` (see the module's note); returns whether any moved.
    pub fn move_slice(&mut self, delta: i64) -> Result<bool> {
        match self.arrangement {
            Arrangement::Single => self.panels[0].move_slice(delta),
            Arrangement::Views { active } => self.panels[active].move_slice(delta),
            Arrangement::Lightbox => {
                let (down, up) = self
                    .panels
                    .iter()
                    .filter_map(Content::slice_room)
                    .fold((usize::MAX, usize::MAX), |(d, u), (pd, pu)| {
                        (d.min(pd), u.min(pu))
                    });
                let limit = |room: usize| i64::try_from(room).unwrap_or(i64::MAX);
                let delta = delta.clamp(-limit(down), limit(up));
                if delta == 0 {
                    eprintln!("slice: the lightbox's first or last slice is at the volume's end");
                    return Ok(false);
                }
                let mut moved = false;
                for panel in &mut self.panels {
                    moved |= panel.move_slice(delta)?;
                }
                Ok(moved)
            }
        }
    }

    /// Chooses the slice that moves: with three slices (--slices) the one across voxel
    /// axis `choice` (0 = i, 1 = j, 2 = k), with --views the panel at `choice` (0 the
    /// first). Returns whether it changed.
    pub fn set_active_slice(&mut self, choice: usize) -> bool {
        match self.arrangement {
            Arrangement::Single => self.panels[0].set_active_slice(choice),
            Arrangement::Views { active } if choice < self.panels.len() => {
                self.arrangement = Arrangement::Views { active: choice };
                choice != active
            }
            Arrangement::Views { .. } => {
                eprintln!(
                    "active slice: the montage has {} panel(s), not {}",
                    self.panels.len(),
                    choice + 1
                );
                false
            }
            Arrangement::Lightbox => {
                eprintln!("active slice: the lightbox's slices move together");
                false
            }
        }
    }

    /// The title's slice label: the single view's ([`Content::slice_label`]), or each
    /// panel's slice ("k=1 k=3 k=5 k=7", the active --views panel in brackets).
    pub fn slice_label(&self) -> Option<String> {
        if self.arrangement == Arrangement::Single {
            return self.first().slice_label();
        }
        let names: Vec<String> = self
            .panels
            .iter()
            .enumerate()
            .filter_map(|(k, panel)| {
                let name = panel.slice_name()?;
                let active = self.arrangement == Arrangement::Views { active: k };
                Some(if active { format!("[{name}]") } else { name })
            })
            .collect();
        let kind = match self.arrangement {
            Arrangement::Lightbox => "lightbox",
            _ => "views",
        };
        Some(format!("{} ({kind})", names.join(" ")))
    }

    /// Shows (`Some(true)`), hides or toggles (`None`, from the first panel's state)
    /// every panel's streamlines; whether any panel changed.
    pub fn set_tracks(&mut self, shown: Option<bool>) -> Result<bool> {
        let mut changed = false;
        let mut shown = shown;
        for panel in &mut self.panels {
            let now = panel.set_tracks(shown)?;
            if now && shown.is_none() {
                // The first panel's toggle decides for the others.
                shown = Some(panel.tracks_shown());
            }
            changed |= now;
        }
        Ok(changed)
    }

    /// Sets every panel's negative-lobe mode (`None`: toggle between abs and hide, from
    /// the first panel's).
    pub fn set_negative(&mut self, mode: Option<NegativeMode>) -> Result<()> {
        let mode = mode.unwrap_or(match self.first().negative_name() {
            "hide" => NegativeMode::Abs,
            _ => NegativeMode::Hide,
        });
        for panel in &mut self.panels {
            panel.set_negative(Some(mode))?;
        }
        Ok(())
    }
}
