//! The settings of fits, peaks and quality control: named in this crate's errors as the
//! core names its own ([`Setting`]), and spelled by each front end (`--lambda`,
//! `lambda=`). The core knows nothing of b-values or regularisation.
use glyphcast::Setting;

/// Holder of the diffusion settings' constants (`DmriSetting::Bval`).
pub struct DmriSetting;

#[allow(non_upper_case_globals)]
impl DmriSetting {
    /// A DWI's b-values.
    pub const Bval: Setting = Setting::value("bval", "b-values");
    /// A DWI's gradient directions.
    pub const Bvec: Setting = Setting::value("bvec", "b-vectors");
    /// The frame of the gradient directions.
    pub const BvecConvention: Setting = Setting::value("bvec_convention", "b-vector convention");
    /// The fibre ODF model of a fit.
    pub const Odf: Setting = Setting::value("odf", "ODF model");
    /// A fit's regularisation weight.
    pub const Lambda: Setting = Setting::value("lambda", "lambda");
    /// Which CSD is fitted: MRtrix's or DIPY's.
    pub const CsdAlgorithm: Setting = Setting::value("csd_algorithm", "CSD algorithm");
    /// CSD's threshold.
    pub const Tau: Setting = Setting::value("tau", "tau");
    /// CSD's fibre response file.
    pub const Response: Setting = Setting::value("response", "response");
    /// The FA threshold of the response estimate.
    pub const ResponseFa: Setting = Setting::value("response_fa", "response FA");
    /// Peaks per voxel.
    pub const Count: Setting = Setting::value("count", "count");
    /// The relative threshold of peaks.
    pub const RelativeThreshold: Setting =
        Setting::value("relative_threshold", "relative threshold");
    /// The smallest angle between peaks.
    pub const MinSeparation: Setting = Setting::value("min_separation", "minimum separation");
    /// The side of each panel of a quality-control set, in pixels.
    pub const PanelSize: Setting = Setting::value("panel_size", "panel size");

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
    ];
}
