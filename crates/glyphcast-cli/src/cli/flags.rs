//! The command line's words for the library's settings: each [`Setting`] is spelled as
//! its flag (`--magnitude-range`), with its value after it (`--step 0.0001`), in every
//! message the library's errors carry ([`Error::spelled`]). The library itself names no
//! flag (issue 10: command-line wording stays in `cli/`).
use glyphcast::{Error, Setting};

/// The flag of `setting`.
pub fn flag(setting: Setting) -> &'static str {
    match setting {
        Setting::Width => "--width",
        Setting::Height => "--height",
        Setting::Method => "--method",
        Setting::Path => "--path",
        Setting::Precision => "--precision",
        Setting::Step => "--step",
        Setting::Refine => "--refine",
        Setting::Color => "--color",
        Setting::MagnitudeRange => "--magnitude-range",
        Setting::Colorbar => "--colorbar",
        Setting::Negative => "--negative",
        Setting::Background => "--background",
        Setting::Offset => "--offset",
        Setting::Light => "--light",
        Setting::Ambient => "--ambient",
        Setting::Specular => "--specular",
        Setting::Shininess => "--shininess",
        Setting::Samples => "--samples",
        Setting::Basis => "--basis",
        Setting::Legacy => "--legacy",
        Setting::ForceBasis => "--force-basis",
        Setting::Frame => "--frame",
        Setting::Lmax => "--lmax",
        Setting::Order => "--order",
        Setting::Nonsymmetric => "--nonsymmetric",
        Setting::TensorOrder => "--tensor-order",
        Setting::Slice => "--slice",
        Setting::Slices => "--slices",
        Setting::Voxels => "--voxels",
        Setting::Mask => "--mask",
        Setting::Scale => "--scale",
        Setting::Norm => "--norm",
        Setting::MinAmplitude => "--min-amplitude",
        Setting::Perspective => "--perspective",
        Setting::Orientation => "--orientation",
        Setting::Labels => "--labels",
        Setting::Underlay => "--underlay",
        Setting::UnderlayRange => "--underlay-range",
        Setting::UnderlayPlane => "--underlay-plane",
        Setting::Peaks => "--peaks",
        Setting::PeakValues => "--peak-values",
        Setting::PeaksColor => "--peaks-color",
        Setting::PeaksNorm => "--peaks-norm",
        Setting::PeaksScale => "--peaks-scale",
        Setting::PeaksWidth => "--peaks-width",
        Setting::PeaksFrame => "--peaks-frame",
        Setting::Glyph => "--glyph",
        Setting::Views => "--views",
        Setting::Lightbox => "--lightbox",
        Setting::Bval => "--bval",
        Setting::Bvec => "--bvec",
        Setting::BvecConvention => "--bvec-convention",
        Setting::Odf => "--odf",
        Setting::Lambda => "--lambda",
        Setting::CsdAlgorithm => "--csd-algorithm",
        Setting::Tau => "--tau",
        Setting::Response => "--response",
        Setting::ResponseFa => "--response-fa",
        Setting::Count => "--count",
        Setting::RelativeThreshold => "--relative-threshold",
        Setting::MinSeparation => "--min-separation",
        Setting::PanelSize => "--panel-size",
        Setting::Workload => "--workload",
    }
}

/// `setting` as the command line writes it, with `value` if any.
pub fn spell(setting: Setting, value: Option<&str>) -> String {
    match value {
        Some(value) => format!("{} {value}", flag(setting)),
        None => flag(setting).to_owned(),
    }
}

/// The one-line message of `err` in the command line's words.
pub fn message(err: &Error) -> String {
    err.spelled(&spell)
}

/// The exit code of `err`: 2 for a command line that asks for something impossible (a
/// refused setting, options that clash), 1 for bad data or a failure of the machine.
pub fn exit_code(err: &Error) -> i32 {
    match err {
        err if err.is_usage() => 2,
        _ => 1,
    }
}
