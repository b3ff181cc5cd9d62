//! What culling of hidden glyphs asked for and what the frame did, in one short phrase for
//! a person: `bench`'s `cull` column and the line `render` prints. The frame reports only
//! what it did (`Passes`, `EarlyOut` or `Off`), and `Off` has several causes: a frame that
//! fits in one pass, a method or path that is never culled, a device or target that
//! cannot take the asked way. The phrase names the cause, so that `off` never stands for
//! "asked for culling and got none" without a reason.
use crate::render::visibility::known_depths_fit;
use crate::render::{Culling, Method, RenderPath, RenderSettings};
use crate::vk::DeviceContext;

/// How a drawn frame was culled: what its renderer reports.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Drawn {
    /// The ray caster that drew it (what `auto` chose).
    pub(crate) path: RenderPath,
    /// How it skipped hidden glyphs.
    pub(crate) culling: Culling,
    /// Passes its glyphs were drawn in.
    pub(crate) passes: usize,
    /// Its target's size in pixels (supersampled where the frame is).
    pub(crate) target: (u32, u32),
}

/// `asked: what was done`, as `occluded: 9 passes`, `occluded: early outs (1 pass)`,
/// `occluded: none needed (1 pass)`, `off (1 pass)`, or `passes: none (...)` with the
/// reason where the asked way could not be taken. `settings` are those the frame was
/// asked to draw with (their `cull`, method and path), on the device of `ctx`.
pub(crate) fn report(ctx: &DeviceContext, settings: &RenderSettings, drawn: Drawn) -> String {
    let asked = settings.cull;
    let passes = match drawn.passes.max(1) {
        1 => "1 pass".to_owned(),
        n => format!("{n} passes"),
    };
    let done = match drawn.culling {
        Culling::Passes => passes,
        Culling::EarlyOut => format!("early outs ({passes})"),
        Culling::Off | Culling::Occluded => match asked {
            Culling::Off => return format!("off ({passes})"),
            _ => format!("none {}", why_none(ctx, settings, drawn, &passes)),
        },
    };
    format!("{asked}: {done}")
}

/// Why a frame asked to cull was drawn without it, in parentheses (or "needed (1 pass)"
/// where nothing stood in the way and one pass held every glyph).
fn why_none(ctx: &DeviceContext, settings: &RenderSettings, drawn: Drawn, passes: &str) -> String {
    let method = settings.method;
    if matches!(method, Method::Impostor | Method::Mesh(_)) {
        return format!("({method} draws every glyph; {passes})");
    }
    if drawn.path == RenderPath::Compute {
        return "(the compute path stops each pixel behind its nearest hit itself)".to_owned();
    }
    if settings.cull == Culling::EarlyOut && method != Method::Exact {
        return format!("(early outs are for the exact method; {passes})");
    }
    if !ctx.fragment_stores() {
        return format!(
            "(the device was created without fragmentStoresAndAtomics, which culling needs; \
             {passes})"
        );
    }
    let (width, height) = drawn.target;
    if !known_depths_fit(ctx.max_storage_buffer_range(), width, height) {
        return format!(
            "(a {width} x {height} target's known depths are over the device's storage \
             buffer range; {passes})"
        );
    }
    // `occluded` takes early outs where they save work (the exact method on a device
    // that skips idle branches), else passes (render::visibility::culling).
    let early_outs = method == Method::Exact && ctx.skips_idle_branches();
    let takes_passes = match settings.cull {
        Culling::Occluded => !early_outs,
        _ => settings.cull == Culling::Passes,
    };
    if takes_passes && !ctx.blends_float32() {
        return format!(
            "(the device does not blend float32 distances, which passes need; {passes})"
        );
    }
    if takes_passes && settings.cull == Culling::Occluded {
        // Passes pay where the glyphs stand in several layers (render::visibility's
        // PASS_COVER); the early outs, which take thinner frames, save no time on a
        // device that runs skipped code masked, and are not taken there.
        return format!(
            "(passes pay from {} layers of glyphs, the frame has fewer; {passes})",
            crate::render::visibility::PASS_COVER
        );
    }
    format!("needed ({passes})")
}
