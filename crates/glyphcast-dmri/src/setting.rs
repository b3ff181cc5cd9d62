//! The settings of fits, peaks and quality control: named in this crate's errors as the
//! core names its own ([`Setting`]), and spelled by each front end (`--lambda`,
//! `lambda=`). The core knows nothing of b-values or regularisation.
use glyphcast::Setting;

/// Holder of the diffusion settings' constants (`DmriSetting::Bval`).
pub struct DmriSetting;

#[allow(non_upper_case_globals)]
impl DmriSetting {
    /// A DWI's b-values.
    pub const Bval: Setting = glyphcast::setting!(value("bval", "b-values"));
    /// A DWI's gradient directions.
    pub const Bvec: Setting = glyphcast::setting!(value("bvec", "b-vectors"));
    /// The frame of the gradient directions.
    pub const BvecConvention: Setting =
        glyphcast::setting!(value("bvec_convention", "b-vector convention"));
    /// The fibre ODF model of a fit.
    pub const Odf: Setting = glyphcast::setting!(value("odf", "ODF model"));
    /// A fit's regularisation weight.
    pub const Lambda: Setting = glyphcast::setting!(value("lambda", "lambda"));
    /// Which CSD is fitted: MRtrix's or DIPY's.
    pub const CsdAlgorithm: Setting = glyphcast::setting!(value("csd_algorithm", "CSD algorithm"));
    /// CSD's threshold.
    pub const Tau: Setting = glyphcast::setting!(value("tau", "tau"));
    /// CSD's fibre response file.
    pub const Response: Setting = glyphcast::setting!(value("response", "response"));
    /// The FA threshold of the response estimate.
    pub const ResponseFa: Setting = glyphcast::setting!(value("response_fa", "response FA"));
    /// Peaks per voxel.
    pub const Count: Setting = glyphcast::setting!(value("count", "count"));
    /// The relative threshold of peaks.
    pub const RelativeThreshold: Setting =
        glyphcast::setting!(value("relative_threshold", "relative threshold"));
    /// The smallest angle between peaks.
    pub const MinSeparation: Setting =
        glyphcast::setting!(value("min_separation", "minimum separation"));
    /// The side of each panel of a quality-control set, in pixels.
    pub const PanelSize: Setting = glyphcast::setting!(value("panel_size", "panel size"));

    /// A tractogram drawn with the glyphs.
    pub const Tracks: Setting = glyphcast::setting!(value("tracks", "tracks"));
    /// The tubes' colour: direction or one colour.
    pub const TracksColor: Setting = glyphcast::setting!(value("tracks_color", "tracks colour"));
    /// The tubes' radius, millimetres.
    pub const TracksRadius: Setting = glyphcast::setting!(value("tracks_radius", "tracks radius"));
    /// Streamlines drawn as exact tubes or as lines.
    pub const TracksStyle: Setting = glyphcast::setting!(value("tracks_style", "tracks style"));
    /// The most streamlines drawn (a uniform subsample).
    pub const TracksMax: Setting = glyphcast::setting!(value("tracks_max", "tracks max"));
    /// The distance from a slice's plane within which streamlines are drawn.
    pub const Slab: Setting = glyphcast::setting!(value("slab", "slab"));

    /// Every diffusion setting.
    pub const ALL: &'static [Setting] = &[
        DmriSetting::Bval,
        DmriSetting::Bvec,
        DmriSetting::BvecConvention,
        DmriSetting::Odf,
        DmriSetting::Lambda,
        DmriSetting::CsdAlgorithm,
        DmriSetting::Tau,
        DmriSetting::Response,
        DmriSetting::ResponseFa,
        DmriSetting::Count,
        DmriSetting::RelativeThreshold,
        DmriSetting::MinSeparation,
        DmriSetting::PanelSize,
        DmriSetting::Tracks,
        DmriSetting::TracksColor,
        DmriSetting::TracksRadius,
        DmriSetting::TracksStyle,
        DmriSetting::TracksMax,
        DmriSetting::Slab,
    ];
}
