//! The accuracy suite: scenes on which fixed-step ray casting is known to struggle.
//! Thin crossing lobes, a slightly tilted copy of a glyph (the paper's Fig. 1), a glyph
//! that touches its centre seen down its pinch, order 12, a non-symmetric stiffness
//! tensor, negative lobes shown and hidden, real SH data, a camera inside a glyph's box, and sizes and distances over 10^6.
use crate::camera::{Camera, Projection};
use crate::demo::{direction, fibre_tensor, glyph_set, symmetric};
use crate::glyph::stiffness::VoigtStiffness;
use crate::glyph::{NegativeMode, Symmetry, TensorLayout};
use crate::scene::{GlyphKind, GlyphSet, ImageSize, Scene, ShBasis};
use glam::{DMat3, DVec3};

/// One named scene of the suite.
pub struct SuiteScene {
    /// Its name in reports.
    pub name: &'static str,
    /// The scene itself.
    pub scene: Scene,
}

/// `sets` seen from `eye` by a 30-degree perspective camera aimed at the origin with z up,
/// in a `size` x `size` image: the framing of the suite's scenes (tests build theirs
/// with it too).
pub fn scene(sets: Vec<GlyphSet>, eye: DVec3, size: u32) -> Scene {
    Scene {
        glyph_sets: sets,
        camera: Camera {
            projection: Projection::Perspective { fov_y_deg: 30.0 },
            eye,
            target: DVec3::ZERO,
            up: DVec3::Z,
        },
        image: ImageSize {
            width: size,
            height: size,
        },
    }
}

/// Two populations at 50 degrees, order 10: lobes a few pixels wide.
pub fn thin_crossing_lobes(size: u32) -> Scene {
    let t = fibre_tensor(
        10,
        &[(direction(0.0, 0.0), 1.0), (direction(50.0, 10.0), 0.9)],
    );
    let set = glyph_set(symmetric(10), vec![DVec3::ZERO], 1.0, vec![t]);
    scene(vec![set], DVec3::new(0.5, -1.0, 4.5), size)
}

/// The same order-8 glyph twice, the second turned by 2 degrees about a skew axis.
pub(crate) fn tilted_copy(size: u32) -> Scene {
    let fibres = [(direction(20.0, 0.0), 1.0), (direction(110.0, 0.0), 1.0)];
    let turn = DMat3::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 2f64.to_radians());
    let turned: Vec<_> = fibres.iter().map(|(d, w)| (turn * *d, *w)).collect();
    let coeffs = vec![fibre_tensor(8, &fibres), fibre_tensor(8, &turned)];
    let centers = vec![DVec3::new(-1.05, 0.0, 0.0), DVec3::new(1.05, 0.0, 0.0)];
    let set = glyph_set(symmetric(8), centers, 1.0, coeffs);
    scene(vec![set], DVec3::new(0.3, -1.0, 7.5), size)
}

/// Order 8, two orthogonal populations: the surface pinches to the centre along z, and
/// the camera looks almost straight down that axis.
pub fn touching_centre(size: u32) -> Scene {
    let t = fibre_tensor(
        8,
        &[(direction(0.0, 0.0), 1.0), (direction(90.0, 0.0), 1.0)],
    );
    let set = glyph_set(symmetric(8), vec![DVec3::ZERO], 1.0, vec![t]);
    scene(vec![set], DVec3::new(0.2, -0.3, 4.0), size)
}

/// Order 12, three populations.
pub(crate) fn order_12(size: u32) -> Scene {
    let fibres = [
        (direction(0.0, 0.0), 1.0),
        (direction(60.0, 20.0), 0.8),
        (direction(130.0, -30.0), 0.7),
    ];
    let set = glyph_set(
        symmetric(12),
        vec![DVec3::ZERO],
        1.0,
        vec![fibre_tensor(12, &fibres)],
    );
    scene(vec![set], DVec3::new(1.0, -3.0, 2.5), size)
}

/// Cubic copper (C11 168.4, C12 121.4, C44 75.4 GPa, divided by C11), all 81 entries.
pub fn stiffness(size: u32) -> Scene {
    let rotation = DMat3::from_euler(glam::EulerRot::ZYX, 0.4, 0.3, 0.2);
    let crystal = VoigtStiffness::cubic(1.0, 121.4 / 168.4, 75.4 / 168.4);
    let coeffs = crystal.rotated(rotation);
    let kind = GlyphKind::Tensor(TensorLayout {
        order: 4,
        symmetry: Symmetry::NonSymmetric,
    });
    let set = glyph_set(kind, vec![DVec3::ZERO], 1.0, vec![coeffs]);
    scene(vec![set], DVec3::new(2.0, -3.0, 2.0), size)
}

/// f = (u.d1)^4 - 0.8 (u.d2)^4: a positive and a negative pair of lobes.
pub(crate) fn negative_lobes(size: u32, negative: NegativeMode) -> Scene {
    let pos = fibre_tensor(4, &[(direction(10.0, 15.0), 1.0)]);
    let neg = fibre_tensor(4, &[(direction(100.0, -10.0), 0.8)]);
    let coeffs: Vec<f64> = pos.iter().zip(&neg).map(|(p, n)| p - n).collect();
    let mut set = glyph_set(symmetric(4), vec![DVec3::ZERO], 1.0, vec![coeffs]);
    set.negative = negative;
    scene(vec![set], DVec3::new(0.4, -0.6, 4.0), size)
}

/// Two voxels of DIPY's `func_coef.nii.gz` (BSD-3-Clause, see tests/data/dipy/): band-8
/// SH series in the legacy tournier07 basis, as MRtrix `dwi2SH` wrote them.
pub(crate) const FUNC_COEF_VOXELS: [[f64; 45]; 2] = [
    [
        8.7864, 0.342276, 0.442553, 0.270174, 0.928213, 0.139285, 0.592551, 0.199409, 0.897911,
        0.96843, 0.288806, 0.598305, 0.481065, 0.10044, 0.253468, 0.00571739, 0.750511, 0.0663764,
        0.306417, 0.731513, 0.905236, 0.04207, 0.492066, 0.570545, 0.41929, 0.972574, 0.534756,
        0.569755, 0.320661, 0.945923, 0.403049, 0.581058, 0.478956, 0.0366745, 0.755427, 0.889492,
        0.822498, 0.368287, 0.984448, 0.674553, 0.0348767, 0.950024, 0.502195, 0.48926, 0.762025,
    ],
    [
        8.13892, 0.0686394, 0.363406, 0.879801, 0.0185506, 0.87856, 0.802459, 0.365453, 0.745288,
        0.250596, 0.642608, 0.865265, 0.931002, 0.796405, 0.741693, 0.794433, 0.657056, 0.0228288,
        0.786322, 0.552605, 0.898643, 0.179245, 0.306459, 0.57976, 0.822872, 0.8825, 0.391304,
        0.89064, 0.936283, 0.831922, 0.650757, 0.72865, 0.260964, 0.672358, 0.183581, 0.753542,
        0.753822, 0.509775, 0.267283, 0.0639749, 0.452839, 0.830839, 0.544745, 0.69062, 0.362052,
    ],
];

/// Real SH data: the two `func_coef` voxels as SH glyphs side by side.
pub fn sh_func_coef(size: u32) -> Scene {
    let kind = GlyphKind::Sh {
        band: 8,
        basis: ShBasis::Tournier07,
        legacy: true,
    };
    let centers = vec![DVec3::new(-0.55, 0.0, 0.0), DVec3::new(0.55, 0.0, 0.0)];
    let coeffs = FUNC_COEF_VOXELS.iter().map(|c| c.to_vec()).collect();
    // Radii reach about 3.4 in these units; scale them to half a unit.
    let set = glyph_set(kind, centers, 0.15, coeffs);
    scene(vec![set], DVec3::new(0.5, -2.5, 2.0), size)
}

/// The camera inside a glyph's bounding box (zooming into a glyph with the viewer): an
/// order-8 crossing of two orthogonal fibres, the eye between its lobes, where the glyph
/// is thin, looking past its centre at a second glyph behind it. The near plane cuts the
/// first glyph's box, which is drawn inside out (raycast.vert).
pub fn camera_inside_box(size: u32) -> Scene {
    let crossing = fibre_tensor(
        8,
        &[(direction(90.0, 0.0), 1.0), (direction(90.0, 90.0), 1.0)],
    );
    let single = fibre_tensor(8, &[(direction(60.0, 30.0), 1.0)]);
    let centers = vec![DVec3::ZERO, DVec3::new(-0.3, -1.8, -1.8)];
    let set = glyph_set(symmetric(8), centers, 1.0, vec![crossing, single]);
    let mut scene = scene(vec![set], DVec3::new(0.02, 0.3, 0.3), size);
    scene.camera.projection = Projection::Perspective { fov_y_deg: 75.0 };
    scene
}

/// Sizes and distances spanning a factor of 10^6 in one view: a crossing of scale 1e-3 at
/// distance 0.01, a glyph of scale 1 at distance 10 and one of scale 1e3 at distance 1e4.
/// Depth must hold all three (the near plane at the smallest distance, no far plane to
/// lose precision to).
pub fn scale_range(size: u32) -> Scene {
    let tiny = fibre_tensor(
        8,
        &[(direction(0.0, 20.0), 1.0), (direction(70.0, -10.0), 0.8)],
    );
    let middle = fibre_tensor(8, &[(direction(30.0, 40.0), 1.0)]);
    let huge = fibre_tensor(
        8,
        &[(direction(100.0, 0.0), 1.0), (direction(10.0, 60.0), 0.7)],
    );
    let centers = vec![
        DVec3::new(-1.2e-3, 0.01, 0.0),
        DVec3::new(0.0, 10.0, 1.4),
        DVec3::new(1.3e3, 1.0e4, -0.2e3),
    ];
    let mut set = glyph_set(symmetric(8), centers, 1.0, vec![tiny, middle, huge]);
    set.scales = vec![1e-3, 1.0, 1e3];
    let mut scene = scene(vec![set], DVec3::ZERO, size);
    scene.camera.target = DVec3::Y;
    scene
}

/// Every scene of the suite at `size` x `size` pixels.
pub fn suite(size: u32) -> Vec<SuiteScene> {
    vec![
        SuiteScene {
            name: "thin-lobes",
            scene: thin_crossing_lobes(size),
        },
        SuiteScene {
            name: "tilted-copy",
            scene: tilted_copy(size),
        },
        SuiteScene {
            name: "centre-order8",
            scene: touching_centre(size),
        },
        SuiteScene {
            name: "order12",
            scene: order_12(size),
        },
        SuiteScene {
            name: "stiffness",
            scene: stiffness(size),
        },
        SuiteScene {
            name: "negative-abs",
            scene: negative_lobes(size, NegativeMode::Abs),
        },
        SuiteScene {
            name: "negative-hide",
            scene: negative_lobes(size, NegativeMode::Hide),
        },
        SuiteScene {
            name: "sh-func-coef",
            scene: sh_func_coef(size),
        },
        SuiteScene {
            name: "camera-inside-box",
            scene: camera_inside_box(size),
        },
        SuiteScene {
            name: "scale-range-1e6",
            scene: scale_range(size),
        },
    ]
}
