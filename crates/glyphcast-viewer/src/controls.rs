//! What the user can do, as [`Action`]s: keys map to them, and a test script
//! (`--script`) is a list of them applied one per frame, so scripted runs go through the
//! same code as a person at the keyboard.
use glyphcast::error::quoted;
use glyphcast::glyph::NegativeMode;
use glyphcast::render::{AmbientOcclusion, ColorMode, Method, Refinement, Shadows};
use glyphcast::scene::MAX_IMAGE_SIDE;
use glyphcast::{Error, Result};
use winit::keyboard::{Key, NamedKey};

/// One thing the user can do; a key press or a script event becomes one of these.
#[derive(Clone, Debug, PartialEq)]
pub enum Action {
    /// Ask for a window of this inner size (physical pixels).
    Resize(u32, u32),
    /// Draw with this method (`method:NAME` in a script).
    Method(Method),
    /// Switch to the next method the glyphs allow (`M`).
    NextMethod,
    /// Set the march step, in units of the glyph's bounding radius (`step:X` in a script).
    Step(f32),
    /// Multiply the march step.
    ScaleStep(f32),
    /// Set how a sign change of the march is refined to the surface (`refine:NAME`).
    Refine(Refinement),
    /// Switch to the next of none, bisection, interpolation and secant (`F`).
    NextRefinement,
    /// Colour the glyphs this way (`color:NAME`).
    Color(ColorMode),
    /// Switch to the next colour mode (`C`).
    NextColor,
    /// Draw negative lobes this way in every set (`negative:NAME`).
    Negative(NegativeMode),
    /// Switch every set between hiding negative lobes and drawing their absolute value (`N`).
    ToggleNegative,
    /// Cast shadows this way (`shadows:off|hard|soft:RADIUS` in a script).
    Shadows(Shadows),
    /// Switch shadows on (hard) or off (`L`).
    ToggleShadows,
    /// Ambient occlusion this way (`ambient_occlusion:off|on|REACH` in a script).
    AmbientOcclusion(AmbientOcclusion),
    /// Switch ambient occlusion on (reach 1) or off (`O`).
    ToggleAmbientOcclusion,
    /// Show (true) or hide the streamlines of `--tracks` (`tracks:on|off` in a script).
    Tracks(bool),
    /// Show or hide the streamlines of `--tracks` (`T`).
    ToggleTracks,
    /// Move through the volume by this many slices.
    Slice(i64),
    /// With three slices: the one that slice moves move (0 sagittal, 1 coronal, 2 axial;
    /// the slices across voxel axes i, j, k); with --views the panel (0 the first).
    ActiveSlice(usize),
    /// Turn the camera about its target by a drag of this many pixels (x, y).
    Orbit(f64, f64),
    /// Slide the view by a drag of this many pixels (x, y).
    Pan(f64, f64),
    /// Multiply the distance to the target (perspective) or the view height (orthographic).
    Zoom(f64),
    /// Put the camera back where the scene or the framing put it (`R`, Home).
    ResetCamera,
    /// Write the window's image to a PNG (`S`).
    Screenshot,
    /// Print the key bindings (`H`).
    Help,
    /// Close the window (`Q`, Esc).
    Quit,
    /// Nothing (a script's pause of one frame).
    Wait,
}

/// The key bindings, printed at start and by `H`.
pub const HELP: &str = "\
mouse: left drag orbit, right/middle drag or shift+left drag pan, wheel zoom
keys:  M method   [ ] march step finer/coarser   F refinement   C colour   N negative lobes
       L shadows on/off   O ambient occlusion on/off (exact method; another method turns
       them off)   T streamlines (--tracks) on/off
       Up/PageUp, Down/PageDown slice +1/-1   1/2/3 active slice (of three) or panel (of views)
       R reset camera   S screenshot   H help   Q/Esc quit
montages: the mouse moves every panel's camera alike; lightbox slices move together";

/// Refinements `F` steps through.
const REFINEMENTS: [Refinement; 4] = [
    Refinement::None,
    Refinement::Bisect(3),
    Refinement::Interpolate,
    Refinement::Secant(4),
];

/// The action of a key press, if any.
pub fn key_action(key: &Key) -> Option<Action> {
    let action = match key {
        Key::Named(NamedKey::ArrowUp | NamedKey::PageUp) => Action::Slice(1),
        Key::Named(NamedKey::ArrowDown | NamedKey::PageDown) => Action::Slice(-1),
        Key::Named(NamedKey::Escape) => Action::Quit,
        Key::Named(NamedKey::Home) => Action::ResetCamera,
        Key::Character(c) => match c.to_lowercase().as_str() {
            "m" => Action::NextMethod,
            "[" => Action::ScaleStep(std::f32::consts::FRAC_1_SQRT_2),
            "]" => Action::ScaleStep(std::f32::consts::SQRT_2),
            "f" => Action::NextRefinement,
            "c" => Action::NextColor,
            "n" => Action::ToggleNegative,
            "l" => Action::ToggleShadows,
            "o" => Action::ToggleAmbientOcclusion,
            "t" => Action::ToggleTracks,
            "r" => Action::ResetCamera,
            "s" => Action::Screenshot,
            "h" => Action::Help,
            "q" => Action::Quit,
            "1" => Action::ActiveSlice(0),
            "2" => Action::ActiveSlice(1),
            "3" => Action::ActiveSlice(2),
            _ => return None,
        },
        _ => return None,
    };
    Some(action)
}

/// The refinement after `current` in the `F` cycle.
pub fn next_refinement(current: Refinement) -> Refinement {
    let at = REFINEMENTS.iter().position(|r| *r == current);
    REFINEMENTS[at.map_or(0, |i| (i + 1) % REFINEMENTS.len())]
}

/// The colour mode after `current` in the `C` cycle.
pub fn next_color(current: ColorMode) -> ColorMode {
    match current {
        ColorMode::Direction => ColorMode::Magnitude { range: None },
        ColorMode::Magnitude { .. } => ColorMode::Uniform([0.8, 0.8, 0.8]),
        // Sign colouring is a start-up choice (--color sign): meshes cannot draw it.
        ColorMode::Uniform(_) | ColorMode::Sign { .. } => ColorMode::Direction,
    }
}

/// Short names for the window title.
pub fn refinement_name(r: Refinement) -> String {
    match r {
        Refinement::None => "none".into(),
        Refinement::Bisect(k) => format!("bisect:{k}"),
        Refinement::Interpolate => "interp".into(),
        Refinement::Secant(k) => format!("secant:{k}"),
    }
}

pub fn color_name(c: ColorMode) -> &'static str {
    match c {
        ColorMode::Direction => "direction",
        ColorMode::Magnitude { .. } => "magnitude",
        ColorMode::Uniform(_) => "uniform",
        ColorMode::Sign { .. } => "sign",
    }
}

/// Parses `--script`: comma-separated events, each applied on its own frame:
/// `resize:WxH`, `method:NAME`, `step:S`, `refine:SPEC`, `color:MODE`,
/// `negative:abs|hide|toggle`, `shadows:off|hard|soft:RADIUS|toggle`,
/// `ambient_occlusion:off|on|REACH|toggle`, `tracks:on|off|toggle`, `slice:+N|-N`,
/// `active:1|2|3` (sagittal, coronal, axial slice of `--slices`; first, second, third panel of `--views`), `orbit:DX:DY`,
/// `pan:DX:DY`, `zoom:F`,
/// `reset`, `screenshot`, `wait`.
pub fn parse_script(text: &str) -> Result<Vec<Action>> {
    text.split(',')
        .map(str::trim)
        .filter(|item| !item.is_empty())
        .map(parse_event)
        .collect()
}

fn parse_event(item: &str) -> Result<Action> {
    // The front end names the option the events came in (the command line: --script).
    let bad = |why: &str| Error::input("script", format!("'{}'", quoted(item)), why);
    let (name, value) = item.split_once(':').unwrap_or((item, ""));
    let number = |text: &str| -> Result<f64> {
        text.parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| bad(&format!("'{}' is not a number", quoted(text))))
    };
    let pair = |text: &str| -> Result<(f64, f64)> {
        let (a, b) = text
            .split_once(':')
            .ok_or_else(|| bad("expected two numbers DX:DY"))?;
        Ok((number(a)?, number(b)?))
    };
    let reparse = |e: Error| bad(&e.to_string());
    Ok(match name {
        "resize" => {
            let size = value
                .split_once('x')
                .and_then(|(w, h)| Some((w.parse::<u32>().ok()?, h.parse::<u32>().ok()?)));
            match size {
                Some((w, h))
                    if (1..=MAX_IMAGE_SIDE).contains(&w) && (1..=MAX_IMAGE_SIDE).contains(&h) =>
                {
                    Action::Resize(w, h)
                }
                _ => {
                    return Err(bad(&format!(
                        "expected WIDTHxHEIGHT, each in 1..={MAX_IMAGE_SIDE}"
                    )));
                }
            }
        }
        "method" => Action::Method(value.parse().map_err(reparse)?),
        "step" => Action::Step(number(value)? as f32),
        "refine" => Action::Refine(value.parse().map_err(reparse)?),
        "color" => Action::Color(value.parse().map_err(reparse)?),
        "negative" => match value {
            "abs" => Action::Negative(NegativeMode::Abs),
            "hide" => Action::Negative(NegativeMode::Hide),
            "toggle" => Action::ToggleNegative,
            _ => return Err(bad("expected abs, hide or toggle")),
        },
        "shadows" if value == "toggle" => Action::ToggleShadows,
        "shadows" => Action::Shadows(value.parse().map_err(reparse)?),
        "ambient_occlusion" if value == "toggle" => Action::ToggleAmbientOcclusion,
        "ambient_occlusion" => Action::AmbientOcclusion(value.parse().map_err(reparse)?),
        "tracks" => match value {
            "on" => Action::Tracks(true),
            "off" => Action::Tracks(false),
            "toggle" => Action::ToggleTracks,
            _ => return Err(bad("expected on, off or toggle")),
        },
        "slice" => {
            let delta = (value.starts_with('+') || value.starts_with('-'))
                .then(|| value.parse::<i64>().ok())
                .flatten()
                .ok_or_else(|| bad("expected a signed slice count such as +1 or -2"))?;
            Action::Slice(delta)
        }
        "active" => match value {
            "1" => Action::ActiveSlice(0),
            "2" => Action::ActiveSlice(1),
            "3" => Action::ActiveSlice(2),
            _ => return Err(bad("expected 1, 2 or 3 (sagittal, coronal, axial)")),
        },
        "orbit" => {
            let (dx, dy) = pair(value)?;
            Action::Orbit(dx, dy)
        }
        "pan" => {
            let (dx, dy) = pair(value)?;
            Action::Pan(dx, dy)
        }
        "zoom" => {
            let factor = number(value)?;
            if factor <= 0.0 {
                return Err(bad("the zoom factor must be positive"));
            }
            Action::Zoom(factor)
        }
        "reset" => Action::ResetCamera,
        "screenshot" => Action::Screenshot,
        "wait" => Action::Wait,
        _ => {
            return Err(bad(
                "unknown event; expected resize, method, step, refine, color, negative, \
                 shadows, ambient_occlusion, tracks, slice, active, orbit, pan, zoom, reset, \
                 screenshot or wait",
            ));
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn active_slice_events_and_keys_choose_sagittal_coronal_axial() {
        let script = parse_script("active:1,active:2,active:3").unwrap();
        assert_eq!(
            script,
            [0, 1, 2].map(Action::ActiveSlice).to_vec(),
            "active:N is 1-based"
        );
        assert!(parse_script("active:4").is_err());
        let key = Key::Character("2".into());
        assert_eq!(key_action(&key), Some(Action::ActiveSlice(1)));
    }

    #[test]
    fn parses_the_events_of_a_script() {
        let script = parse_script(
            "resize:300x200, method:fixed,step:0.05,slice:+1,slice:-2,color:magnitude,\
             refine:bisect:2,negative:hide,orbit:30:-10,pan:5:5,zoom:0.8,reset,wait,\
             shadows:toggle,shadows:soft:3,shadows:off,ambient_occlusion:toggle,\
             ambient_occlusion:2,ambient_occlusion:off",
        )
        .unwrap();
        assert_eq!(
            script,
            [
                Action::Resize(300, 200),
                Action::Method(Method::Fixed),
                Action::Step(0.05),
                Action::Slice(1),
                Action::Slice(-2),
                Action::Color(ColorMode::Magnitude { range: None }),
                Action::Refine(Refinement::Bisect(2)),
                Action::Negative(NegativeMode::Hide),
                Action::Orbit(30.0, -10.0),
                Action::Pan(5.0, 5.0),
                Action::Zoom(0.8),
                Action::ResetCamera,
                Action::Wait,
                Action::ToggleShadows,
                Action::Shadows(Shadows::Soft { radius_deg: 3.0 }),
                Action::Shadows(Shadows::Off),
                Action::ToggleAmbientOcclusion,
                Action::AmbientOcclusion(AmbientOcclusion::On { reach: 2.0 }),
                Action::AmbientOcclusion(AmbientOcclusion::Off),
            ]
        );
    }

    #[test]
    fn bad_events_name_themselves() {
        for bad in [
            "resize:300",
            "resize:0x10",
            "method:magic",
            "step:x",
            "shadows:soft:0",
            "shadows:sometimes",
            "slice:1",
            "orbit:3",
            "zoom:-1",
            "explode",
        ] {
            let err = parse_script(bad).unwrap_err().to_string();
            assert!(
                err.starts_with(&format!("script: '{bad}': ")) && !err.contains("--"),
                "{bad}: {err}"
            );
        }
    }

    #[test]
    fn cycles_wrap_around() {
        let mut r = Refinement::Secant(4);
        for _ in 0..REFINEMENTS.len() {
            r = next_refinement(r);
        }
        assert_eq!(r, Refinement::Secant(4));
        let c = next_color(next_color(next_color(ColorMode::Direction)));
        assert_eq!(c, ColorMode::Direction);
    }
}
