//! `glyphcast bench`: GPU timings of the glyph pass on a scene, a generated workload, or
//! a sweep, written as a table (stdout) and as CSV and JSON (`--out DIR`). Sweeps that
//! compare methods also measure each frame against the float64 reference (computed once
//! per scene) and print the ratios of `bench::ratios`.
use clap::Args;
use glyphcast::accuracy::suite;
use glyphcast::bench::{self, BenchCase, BenchFrames, BenchResult, Reference, ratios, workload};
use glyphcast::error::Relation;
use glyphcast::render::headless::HeadlessRenderer;
use glyphcast::render::options::{RenderOptions, Value};
use glyphcast::render::peaks::PeakSet;
use glyphcast::render::{
    AmbientOcclusion, MeshKind, Method, Refinement, RenderPath, RenderSettings, Shadows,
};
use glyphcast::scene::Scene;
use glyphcast::vk::{Gpu, GpuOptions};
use glyphcast::{Error, Result, Setting};
use glyphcast_dmri::volume::ImageRequest;
use std::path::{Path, PathBuf};

/// The tables `--out` names, written as one set.
const RESULT_FILES: [&str; 3] = ["results.json", "results.csv", "results.md"];
use std::time::Instant;

#[derive(Args)]
pub struct BenchArgs {
    /// Scene file to measure (default: the --workload).
    #[arg(value_name = "SCENE")]
    scene: Option<PathBuf>,
    /// Generated workload: grid:COUNT:ORDER (fibre tensors), fodf:COUNT:BAND (SH fODFs),
    /// block:NX:NY:NZ:BAND[:front|:corner|:stacked] (a dense 3D block of touching fODFs,
    /// seen head-on through its layers or from a corner, or its first layer copied into
    /// every layer, seen head-on) or tracks:COUNT:POINTS[:slab][:lines] (COUNT synthetic
    /// streamlines of POINTS points 1 mm apart in a brain-sized volume, drawn as tubes of
    /// radius 0.2 mm, or with :lines as lines of that width: whole in 3D, or their parts
    /// in a 5 mm slab over an axial slice).
    #[arg(long, default_value = "grid:100:8")]
    workload: String,
    /// A sweep instead of one measurement: steps (the paper's Table 1), scaling (glyph
    /// count, order, resolution), table2 (ray casting against tessellation levels 1 to 6,
    /// with geometric error), methods (every method on the accuracy suite) or ratios
    /// (the default ray caster against the impostor and against tessellation at equal
    /// error: grids of orders 4, 8 and 12, and band-8 fODFs) or gpu[:COUNTS] (the GPU
    /// report of tools/gpu-report.sh: band-8 fODF fields of 10^3 to 10^6 glyphs at three
    /// sizes, every method and both paths; failures are reported, not fatal) or shadows
    /// (the frame without shadows, with hard and with soft ones, three rounds).
    #[arg(long)]
    sweep: Option<String>,
    /// Method of a single measurement: exact, fixed, interval, affine, impostor,
    /// mesh:LEVEL or latlong:N.
    #[arg(long, default_value = "exact")]
    method: String,
    /// Ray caster of a single measurement: fragment (proxy boxes; the default here, so
    /// that the work counters are measured), compute (a compute shader per pixel over
    /// screen tiles; exact only) or auto (render's default: compute on a GPU, fragment on
    /// a CPU device such as lavapipe and wherever compute cannot draw the glyphs).
    #[arg(long, default_value = "fragment", value_name = "fragment|compute|auto")]
    path: String,
    /// Hidden glyphs in a single measurement: occluded (the device's best of passes and
    /// early-out), passes (drawn in passes front to back, each skipping the pixels an
    /// earlier pass covered nearer), early-out (one pass front to back whose fragments
    /// behind a hit found before skip the root isolation) or off (one pass).
    #[arg(
        long,
        default_value = "occluded",
        value_name = "occluded|passes|early-out|off"
    )]
    cull: String,
    /// What the fragment path draws around each glyph in a single measurement: box (its
    /// oriented box, the paper's proxy), hull (an octagon around the outline of the
    /// glyph's guaranteed 26-sided polytope) or pieces (an octagon around each of its
    /// eight pieces, the ray clipped to its piece).
    #[arg(long, default_value = "box", value_name = "box|hull|pieces")]
    proxy: String,
    /// Also compare a single measurement with the float64 reference.
    #[arg(long)]
    accuracy: bool,
    /// Measured frames (after the warm-up), at least 1 (default 20; 3 with --quick).
    #[arg(long)]
    frames: Option<usize>,
    /// Warm-up frames, not measured (default 3; 1 with --quick).
    #[arg(long)]
    warmup: Option<usize>,
    /// Image width and height (workloads; a scene keeps its own size unless given).
    #[arg(long)]
    width: Option<u32>,
    #[arg(long)]
    height: Option<u32>,
    /// Small sweeps and few frames: a check that finishes in a few minutes on lavapipe.
    #[arg(long)]
    quick: bool,
    /// Folder for results.csv, results.json and results.md (an existing folder, as for
    /// every output).
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Also write the measured scene (a workload, at its size) as a scene file, to render
    /// or inspect it.
    #[arg(long, value_name = "FILE")]
    save_scene: Option<PathBuf>,
    /// With --save-scene: write each glyph set's centers, scales and coefficients as
    /// float64 .npy files beside the scene file (SCENE.0.coeffs.npy, ...), which the
    /// scene file names: a large scene then reads without parsing JSON numbers.
    #[arg(long, requires = "save_scene")]
    scene_arrays: bool,
    /// With a tracks workload: also write its streamlines (the parts it draws) as an
    /// MRtrix .tck, to draw the same set with `render --tracks` or another tool.
    #[arg(long, value_name = "FILE.tck")]
    save_tracks: Option<PathBuf>,
    /// Vulkan device: part of its name or its index.
    #[arg(long)]
    device: Option<String>,
}

impl BenchArgs {
    /// The frames measured and warmed up: those given, else --quick's or the defaults.
    fn frames(&self) -> BenchFrames {
        let (warmup, measured) = if self.quick { (1, 3) } else { (3, 20) };
        BenchFrames {
            warmup: self.warmup.unwrap_or(warmup),
            measured: self.frames.unwrap_or(measured),
        }
    }

    /// Refuses what no measurement can take: no measured frame, an image side out of
    /// range (as `render` refuses it, before any device is opened).
    fn check(&self) -> Result<()> {
        if self.frames == Some(0) {
            return Err(Error::Flag {
                flag: "--frames",
                message: "must be at least 1 (the frames measured after the warm-up)".into(),
            });
        }
        ImageRequest::checked(self.width, self.height)?;
        Ok(())
    }

    fn size(&self, default: u32) -> (u32, u32) {
        (
            self.width.unwrap_or(default),
            self.height.unwrap_or(default),
        )
    }

    /// `--out`'s tables (its folder must exist) and `--save-scene` (its arrays apart).
    fn output_paths(&self) -> Vec<PathBuf> {
        let mut paths: Vec<PathBuf> = RESULT_FILES
            .iter()
            .filter_map(|name| Some(self.out.as_ref()?.join(name)))
            .collect();
        paths.extend(self.save_scene.clone());
        paths.extend(self.save_tracks.clone());
        paths
    }

    /// The scene file and the arrays it names.
    fn input_paths(&self) -> Vec<PathBuf> {
        let Some(scene) = &self.scene else {
            return Vec::new();
        };
        let mut paths = vec![scene.clone()];
        paths.extend(Scene::array_files(scene));
        paths
    }

    /// Whether the workload (measured without a scene file) is a `tracks:` one.
    fn is_tracks_workload(&self) -> bool {
        self.scene.is_none() && self.workload.starts_with("tracks:")
    }

    /// The scene and tubes of a `tracks:` workload; `None` for any other.
    fn tracks_workload(&self) -> Option<Result<(Scene, PeakSet)>> {
        if !self.is_tracks_workload() {
            return None;
        }
        let (w, h) = self.size(if self.quick { 256 } else { 512 });
        Some(
            workload::parse(&self.workload, w, h).and_then(|(scene, tubes)| {
                tubes.map(|tubes| (scene, tubes)).ok_or(Error::Call {
                    call: "bench::tracks_workload",
                    expected: "the tubes of a tracks workload",
                })
            }),
        )
    }

    fn base_scene(&self) -> Result<Scene> {
        if self.is_tracks_workload() {
            return Err(Error::conflict(
                "--sweep",
                Relation::Excludes,
                "a tracks workload (it is measured alone)",
            ));
        }
        match &self.scene {
            Some(path) => {
                let mut scene = Scene::load(path)?;
                scene.image.width = self.width.unwrap_or(scene.image.width);
                scene.image.height = self.height.unwrap_or(scene.image.height);
                Ok(scene)
            }
            None => {
                let (w, h) = self.size(if self.quick { 256 } else { 512 });
                workload::parse(&self.workload, w, h).map(|(scene, _)| scene)
            }
        }
    }
}

/// One configuration: a scene of the plan (by index), settings, and whether to hold the
/// frame against the reference.
struct Case {
    label: String,
    scene: usize,
    settings: RenderSettings,
    accuracy: bool,
}

/// What a run measures: named scenes and the configurations drawn on them.
#[derive(Default)]
struct Plan {
    scenes: Vec<(String, Scene)>,
    /// Per scene, the tubes drawn with it (a tracks workload's), if any.
    tubes: Vec<Option<PeakSet>>,
    cases: Vec<Case>,
    /// Configurations left out, with the reason, for the report.
    skipped: Vec<String>,
    /// Whether a configuration that fails is reported and passed over (the GPU report,
    /// which must finish on any device) instead of ending the run.
    tolerate_failures: bool,
    /// The methods of the pivot table, in order, whether measured or not (a
    /// configuration skipped or failed shows "-" in its column).
    columns: Vec<String>,
}

impl Plan {
    fn scene(&mut self, name: impl Into<String>, scene: Scene) -> usize {
        self.scenes.push((name.into(), scene));
        self.tubes.push(None);
        self.scenes.len() - 1
    }

    fn case(&mut self, label: impl Into<String>, scene: usize, settings: RenderSettings) {
        self.cases.push(Case {
            label: label.into(),
            scene,
            settings,
            accuracy: false,
        });
    }

    /// The ray caster, the impostor and the given tessellations on `scene`, each held
    /// against the reference; labels start with `prefix`.
    fn methods(&mut self, prefix: &str, scene: usize, methods: &[Method]) {
        for &method in methods {
            let label = if prefix.is_empty() {
                method.to_string()
            } else {
                format!("{prefix} {method}")
            };
            self.cases.push(Case {
                label,
                scene,
                settings: RenderSettings {
                    method,
                    ..Default::default()
                },
                accuracy: true,
            });
        }
    }
}

/// The ray-casting methods, the impostor, then the icosphere levels and lat-long spheres
/// given.
fn method_list(levels: std::ops::RangeInclusive<u32>, lat_long: &[u32]) -> Vec<Method> {
    let mut methods = Method::RAY_CASTING.to_vec();
    methods.push(Method::Impostor);
    methods.extend(levels.map(|l| Method::Mesh(MeshKind::Icosphere(l))));
    methods.extend(lat_long.iter().map(|&n| Method::Mesh(MeshKind::LatLong(n))));
    methods
}

fn plan(args: &BenchArgs) -> Result<Plan> {
    let defaults = RenderSettings::default();
    let mut plan = Plan::default();
    let base_name = || match &args.scene {
        Some(path) => path.display().to_string(),
        None => args.workload.clone(),
    };
    if let (Some(_), Some(_)) = (&args.sweep, &args.save_scene) {
        // --save-scene writes the scene of a single measurement; a sweep measures several.
        return Err(Error::conflict(
            "--save-scene",
            Relation::Excludes,
            "--sweep (it writes the scene of a single measurement)",
        ));
    }
    match args.sweep.as_deref() {
        None => {
            // Read and checked as `render` reads them: a `--cull` the method or path
            // cannot take is refused here too.
            let mut options = RenderOptions::default();
            for (setting, text) in [
                (Setting::Method, &args.method),
                (Setting::Path, &args.path),
                (Setting::Cull, &args.cull),
                (Setting::Proxy, &args.proxy),
            ] {
                options.set(setting, Value::Text(text))?;
            }
            let settings = options.settings()?;
            options.check_method_reads(&settings)?;
            if let Some(tracks) = args.tracks_workload() {
                let (scene, tubes) = tracks?;
                if args.accuracy {
                    return Err(Error::conflict(
                        "--accuracy",
                        Relation::Excludes,
                        "a tracks workload (its tubes are no scene's glyphs)",
                    ));
                }
                save_tracks_workload(args, &scene, &tubes)?;
                let scene = plan.scene(base_name(), scene);
                plan.tubes[scene] = Some(tubes);
                plan.cases.push(Case {
                    label: "default".into(),
                    scene,
                    settings,
                    accuracy: false,
                });
                return Ok(plan);
            }
            if args.save_tracks.is_some() {
                return Err(Error::conflict(
                    "--save-tracks",
                    Relation::Requires,
                    "a tracks workload (--workload tracks:COUNT:POINTS[:slab][:lines])",
                ));
            }
            let base = args.base_scene()?;
            if let Some(path) = &args.save_scene {
                let arrays = match args.scene_arrays {
                    true => scene_arrays(&base, path)?,
                    false => Vec::new(),
                };
                let mut outputs = args.output_paths();
                outputs.extend(arrays);
                check_outputs(&outputs, &args.input_paths())?;
                base.save(path, args.scene_arrays)?;
            }
            let scene = plan.scene(base_name(), base);
            plan.cases.push(Case {
                label: "default".into(),
                scene,
                settings,
                accuracy: args.accuracy,
            });
        }
        Some("steps") => {
            let scene = plan.scene(base_name(), args.base_scene()?);
            let steps: &[f32] = if args.quick {
                &[0.02, 0.1]
            } else {
                &[0.01, 0.02, 0.05, 0.1, 0.2]
            };
            let refinements = [
                "none", "bisect:1", "bisect:2", "bisect:3", "interp", "secant:4",
            ];
            for &step in steps {
                for r in refinements {
                    let refinement = r.parse::<Refinement>()?;
                    for (centre, factor) in [("centre", 1.0 / 3.0), ("uniform", 1.0)] {
                        let settings = RenderSettings {
                            step,
                            refinement,
                            centre_step_factor: factor,
                            ..defaults
                        };
                        plan.case(format!("step {step} {r} {centre}"), scene, settings);
                    }
                }
            }
        }
        Some("scaling") => {
            let (counts, orders, sizes): (&[usize], &[u32], &[u32]) = if args.quick {
                (&[16, 100], &[2, 8], &[128, 256])
            } else {
                (
                    &[100, 1000, 10_000, 100_000],
                    &[2, 4, 6, 8, 10, 12],
                    &[512, 1024, 2048],
                )
            };
            let mut add = |label: String, scene: Scene| {
                let index = plan.scene(label.clone(), scene);
                plan.case(label, index, defaults);
            };
            for &n in counts {
                add(
                    format!("glyphs {n} (order 8)"),
                    workload::grid(n, 8, sizes[0], sizes[0])?,
                );
            }
            for &order in orders {
                add(
                    format!("order {order} (100 glyphs)"),
                    workload::grid(100, order, sizes[0], sizes[0])?,
                );
            }
            for &size in sizes {
                add(
                    format!("{size}^2 (100 glyphs, order 8)"),
                    workload::grid(100, 8, size, size)?,
                );
            }
        }
        Some("table2") => {
            // The paper's Table 2: ray casting against tessellation levels 1 to 6.
            let scene = plan.scene(base_name(), args.base_scene()?);
            plan.methods("", scene, &method_list(1..=6, &[]));
        }
        Some("methods") => {
            let (size, lat_long): (u32, &[u32]) = if args.quick {
                (args.width.unwrap_or(64), &[16])
            } else {
                (args.width.unwrap_or(160), &[16, 64])
            };
            for suite_scene in suite::suite(size) {
                let name = suite_scene.name;
                let scene = plan.scene(name, suite_scene.scene);
                plan.methods(name, scene, &method_list(1..=6, lat_long));
            }
        }
        Some("ratios") => {
            let (count, size, levels) = if args.quick {
                (16, args.width.unwrap_or(160), 1..=5)
            } else {
                (100, args.width.unwrap_or(512), 1..=6)
            };
            for order in [4, 8, 12] {
                let name = format!("grid:{count}:{order}");
                let scene = plan.scene(name.clone(), workload::grid(count, order, size, size)?);
                plan.methods(&name, scene, &method_list(levels.clone(), &[]));
            }
            // The common case of real data: one to three fibres per voxel, band 8.
            let (count, width, height) = if args.quick {
                (16, args.width.unwrap_or(160), args.height.unwrap_or(90))
            } else {
                (256, args.width.unwrap_or(1280), args.height.unwrap_or(720))
            };
            let name = format!("fodf:{count}:8");
            let scene = plan.scene(name.clone(), workload::fodf(count, 8, width, height)?);
            plan.methods(&name, scene, &method_list(levels, &[]));
        }
        Some("shadows") => {
            // The cost of shadow and occlusion rays on the scene or workload: the same
            // frame without them, with hard shadows, soft ones and ambient occlusion
            // (reach 1), three rounds interleaved.
            let scene = plan.scene(base_name(), args.base_scene()?);
            for round in 1..=3 {
                for shadows in [
                    Shadows::Off,
                    Shadows::Hard,
                    Shadows::Soft { radius_deg: 5.0 },
                ] {
                    let settings = RenderSettings {
                        shadows,
                        ..defaults
                    };
                    plan.case(format!("shadows {shadows} ({round})"), scene, settings);
                }
                let occlusion = AmbientOcclusion::On {
                    reach: glyphcast::render::settings::AMBIENT_OCCLUSION_REACH,
                };
                let settings = RenderSettings {
                    ambient_occlusion: occlusion,
                    ..defaults
                };
                plan.case(format!("shadows ao:{occlusion} ({round})"), scene, settings);
            }
        }
        Some(sweep) if sweep == "gpu" || sweep.starts_with("gpu:") => {
            gpu_plan(args, &sweep["gpu".len()..], &mut plan)?;
        }
        Some(other) => {
            return Err(bad_sweep(format!(
                "'{}' is not one of steps, scaling, table2, methods, ratios, shadows, \
                 gpu[:COUNTS]",
                glyphcast::error::quoted(other)
            )));
        }
    }
    Ok(plan)
}

/// Meshes of more triangles than this in one frame are left out of the GPU report: a
/// million glyphs at icosphere level 5 would take 2 * 10^10 triangles (hundreds of GB).
const GPU_REPORT_TRIANGLE_BUDGET: usize = 200_000_000;

/// The GPU report's table (`tools/gpu-report.sh`): band-8 fODF fields of 10^3 to 10^6
/// glyphs (or the comma-separated `counts` after `gpu:`) at 1280x720, 1920x1080 and
/// 3840x2160; every method on the fragment path and `exact` on the compute path and on
/// `auto` (the path it takes on the device); meshes
/// where their triangles fit [`GPU_REPORT_TRIANGLE_BUDGET`]; accuracy against the
/// float64 reference on fields of at most 1000 glyphs at the smallest size. `--quick`:
/// 100 and 1000 glyphs at 320x180 and 640x360.
fn gpu_plan(args: &BenchArgs, counts: &str, plan: &mut Plan) -> Result<()> {
    plan.tolerate_failures = true;
    let (default_counts, sizes): (&[usize], &[(u32, u32)]) = if args.quick {
        (&[100, 1000], &[(320, 180), (640, 360)])
    } else {
        (
            &[1_000, 10_000, 100_000, 1_000_000],
            &[(1280, 720), (1920, 1080), (3840, 2160)],
        )
    };
    let counts: Vec<usize> = match counts.strip_prefix(':') {
        None => default_counts.to_vec(),
        Some(list) => list
            .split(',')
            .map(|c| {
                c.trim()
                    .parse::<usize>()
                    .ok()
                    .filter(|&n| n > 0)
                    .ok_or_else(|| {
                        bad_sweep(format!(
                            "gpu:{list}: '{}' is not a glyph count",
                            glyphcast::error::quoted(c)
                        ))
                    })
            })
            .collect::<Result<_>>()?,
    };
    let methods = [
        "exact", "affine", "interval", "fixed", "impostor", "mesh:3", "mesh:5",
    ];
    plan.columns = methods.iter().map(|m| m.to_string()).collect();
    plan.columns.push("exact (compute)".into());
    plan.columns.push("exact (auto)".into());
    for &count in &counts {
        let (w0, h0) = sizes[0];
        let base = workload::fodf(count, 8, w0, h0)?;
        for (size_index, &(width, height)) in sizes.iter().enumerate() {
            let mut scene = base.clone();
            scene.image.width = width;
            scene.image.height = height;
            let name = format!("fodf:{count}:8 {width}x{height}");
            let index = plan.scene(name.clone(), scene);
            let accuracy = count <= 1000 && size_index == 0;
            let mut add = |label: String, settings: RenderSettings| {
                plan.cases.push(Case {
                    label,
                    scene: index,
                    settings,
                    accuracy,
                })
            };
            for spelled in methods {
                let method: Method = spelled.parse()?;
                if let Method::Mesh(kind) = method {
                    let triangles = kind.triangle_count() * count;
                    if triangles > GPU_REPORT_TRIANGLE_BUDGET {
                        plan.skipped.push(format!(
                            "{name} {spelled}: {triangles} triangles, over the report's \
                             budget of {GPU_REPORT_TRIANGLE_BUDGET}"
                        ));
                        continue;
                    }
                }
                add(
                    format!("{name} {spelled}"),
                    RenderSettings {
                        method,
                        path: RenderPath::Fragment,
                        ..Default::default()
                    },
                );
            }
            for path in [RenderPath::Compute, RenderPath::Auto] {
                add(
                    format!("{name} exact ({path})"),
                    RenderSettings {
                        path,
                        ..Default::default()
                    },
                );
            }
        }
    }
    Ok(())
}

/// `--save-scene` (the camera and image of the workload; no glyphs) and `--save-tracks`
/// (its streamlines as a `.tck`) of a tracks workload, checked as outputs first.
fn save_tracks_workload(args: &BenchArgs, scene: &Scene, tubes: &PeakSet) -> Result<()> {
    if args.save_scene.is_none() && args.save_tracks.is_none() {
        return Ok(());
    }
    if let Some(path) = &args.save_tracks {
        glyphcast::io::atomic::check_ending(path, "--save-tracks", &["tck"])?;
    }
    check_outputs(&args.output_paths(), &args.input_paths())?;
    if let Some(path) = &args.save_scene {
        scene.save(path, false)?;
    }
    if let Some(path) = &args.save_tracks {
        glyphcast_dmri::io::tracks::tck::write_tck(&polylines(tubes), path)?;
    }
    Ok(())
}

/// The streamlines whose consecutive segments are `tubes`' capsules: a segment that
/// starts where the one before it ended continues its streamline.
fn polylines(tubes: &PeakSet) -> glyphcast_dmri::io::tracks::Tractogram {
    let mut tractogram = glyphcast_dmri::io::tracks::Tractogram::default();
    let mut end = None;
    for segment in tubes.all() {
        let capsule = &segment.capsule;
        if end != Some(capsule.a) {
            tractogram.offsets.push(tractogram.points.len() as u64);
            tractogram.points.push(capsule.a.as_vec3().to_array());
        }
        tractogram.points.push(capsule.b.as_vec3().to_array());
        end = Some(capsule.b);
    }
    tractogram
}

/// The array files `scene` saved as `path` with --scene-arrays writes. Each is an output:
/// one that exists is replaced only where the scene file already at `path` names it (an
/// earlier save of the same scene); any other file of that name is refused (a usage
/// error naming it), never overwritten.
fn scene_arrays(scene: &Scene, path: &Path) -> Result<Vec<PathBuf>> {
    let arrays = scene.array_paths(path)?;
    let earlier = Scene::array_files(path);
    for array in &arrays {
        let exists = std::fs::symlink_metadata(array).is_ok();
        if exists && !earlier.contains(array) {
            let folder = array.parent().filter(|p| !p.as_os_str().is_empty());
            return Err(Error::ForeignEntry {
                folder: folder.unwrap_or(Path::new(".")).display().to_string(),
                entry: array
                    .file_name()
                    .map(|name| name.to_string_lossy().into_owned())
                    .unwrap_or_default(),
                remedy: "--scene-arrays replaces only the arrays of an earlier scene saved \
                         to the same --save-scene path: remove the file or give another name",
            });
        }
    }
    Ok(arrays)
}

/// Checks the outputs of `args` before any work: `--out`'s files and `--save-scene`
/// (`io::atomic::check_outputs`: existing folders, no file twice, none an input).
fn check_outputs(outputs: &[PathBuf], inputs: &[PathBuf]) -> Result<()> {
    let outputs: Vec<&Path> = outputs.iter().map(PathBuf::as_path).collect();
    let inputs: Vec<&Path> = inputs.iter().map(PathBuf::as_path).collect();
    glyphcast::io::atomic::check_outputs(&outputs, &inputs)
}

pub fn run(args: &BenchArgs) -> Result<()> {
    // What the scene file's glyphs cannot be drawn as names the file.
    run_plan(args).map_err(|e| match &args.scene {
        Some(path) => e.in_scene_file(path),
        None => e,
    })
}

fn run_plan(args: &BenchArgs) -> Result<()> {
    args.check()?;
    check_outputs(&args.output_paths(), &args.input_paths())?;
    let plan = plan(args)?;
    let mut options = GpuOptions::from_env();
    if args.device.is_some() {
        options.device = args.device.clone();
    }
    let gpu = Gpu::headless(&options)?;
    // The device is named once, at the head of the table (stdout and results.md).
    let mut renderer = HeadlessRenderer::new(&gpu)?;
    let mut references: Vec<Option<Reference>> = plan.scenes.iter().map(|_| None).collect();
    let progress = super::progress::bar(plan.cases.len() as u64, "bench");
    let mut results: Vec<BenchResult> = Vec::new();
    let mut failed: Vec<String> = Vec::new();
    for case in &plan.cases {
        let (scene_name, scene) = &plan.scenes[case.scene];
        progress.set_message(case.label.clone());
        let reference = match (&mut references[case.scene], case.accuracy) {
            (slot @ None, true) => {
                let started = Instant::now();
                let reference = slot.insert(Reference::of(scene)?);
                progress.suspend(|| {
                    eprintln!(
                        "float64 reference of {scene_name}: {:.1} s",
                        started.elapsed().as_secs_f64()
                    )
                });
                Some(&*reference)
            }
            (slot, true) => slot.as_ref(),
            (_, false) => None,
        };
        let bench_case = BenchCase {
            label: &case.label,
            scene_name,
            scene,
            settings: &case.settings,
            reference,
            tubes: plan.tubes[case.scene].as_ref(),
        };
        match bench::run(&gpu, &mut renderer, &bench_case, args.frames()) {
            Ok(result) => results.push(result),
            Err(e) if plan.tolerate_failures => {
                progress.suspend(|| eprintln!("{}: failed: {e}", case.label));
                failed.push(format!("{}: failed: {e}", case.label));
            }
            Err(e) => return Err(e),
        }
        progress.inc(1);
    }
    progress.finish_and_clear();
    let ratios = ratios::ratios(&results);
    let mut table = format!(
        "Device: {}\n\n{}\n{}",
        gpu.info,
        legend(args.frames()),
        bench::markdown(&results)
    );
    if plan.tolerate_failures {
        table.push_str(&format!(
            "\nGPU milliseconds per frame (median), glyphs by size and method:\n\n{}",
            bench::tables::pivot(&results, &plan.columns)
        ));
    }
    for r in results.iter().filter(|r| r.tube_segments > 0) {
        let mb = r.tube_bytes as f64 / 1e6;
        table.push_str(&format!(
            "\nTubes ({}): {} segments, {mb:.1} MB on the GPU ({:.1} MB per million \
             segments), {:.1} million segments per second\n",
            r.label,
            r.tube_segments,
            mb / (r.tube_segments as f64 / 1e6),
            r.tube_segments as f64 / (r.gpu_ms_median * 1e-3) / 1e6,
        ));
    }
    for line in plan.skipped.iter().chain(&failed) {
        table.push_str(&format!("\n- {line}"));
    }
    if !plan.skipped.is_empty() || !failed.is_empty() {
        table.push('\n');
    }
    if !ratios.is_empty() {
        table.push_str(&format!(
            "\nRatios (tessellation at equal error: the coarsest mesh below {} px):\n\n{}",
            ratios::EQUAL_ERROR_PX,
            ratios::markdown(&ratios)
        ));
    }
    if args.sweep.as_deref() == Some("shadows") {
        table.push_str(&shadow_ratios(&results));
    }
    if let Some(dir) = &args.out {
        let json = serde_json::json!({
            "device": gpu.info.to_string(),
            "sweep": args.sweep,
            "results": results,
            "ratios": ratios,
            "skipped": plan.skipped,
            "failed": failed,
        });
        let json = serde_json::to_string_pretty(&json)
            .map_err(|e| Error::io(dir.join("results.json"), e))?;
        let csv = bench::csv(&results);
        let [json_path, csv_path, md_path] = RESULT_FILES.map(|name| dir.join(name));
        glyphcast::io::atomic::write_all_atomic(&[
            (&json_path, json.as_bytes()),
            (&csv_path, csv.as_bytes()),
            (&md_path, table.as_bytes()),
        ])?;
        let title = args.sweep.as_deref().unwrap_or("bench");
        match super::plot::write_plots(dir, title, &results) {
            Ok(files) => eprintln!("plots: {}", files.join(", ")),
            // Plots are a view of the tables just written: without a font they are
            // left out with a warning rather than failing the measurements.
            Err(e) => eprintln!("warning: no plots: {e}"),
        }
    }
    print!("{table}");
    Ok(())
}

/// What the timing table's columns measure, and in which units, for `frames`.
fn legend(frames: BenchFrames) -> String {
    let BenchFrames { warmup, measured } = frames;
    format!(
        "GPU ms: the glyph pass's GPU time (timestamp queries) over {measured} timed \
         frame(s) after {warmup} warm-up frame(s): median, min and max. prepare ms: CPU time \
         to turn the scene into GPU data; upload ms: CPU time to upload it and make the \
         frame's targets (mesh generation apart). Mrays/s: covered pixels (pixels with a \
         glyph hit) per second of median GPU time; glyphs/s alike. coeff and instance \
         bytes: GPU memory of the glyph data. fragments/px and evaluations/px: fragment \
         shader runs and glyph evaluations of one more frame drawn with counters, per \
         covered pixel; \"-\" where nothing is counted (the impostor, meshes, the compute \
         path). cull: the --cull asked for, then what the frame did.\n"
    )
}

/// `--sweep shadows`: each round's frame with shadows over the same round's frame
/// without them (GPU medians), as Markdown lines.
fn shadow_ratios(results: &[BenchResult]) -> String {
    let mut text =
        String::from("\nShadows: GPU median over the same round's frame without them\n\n");
    for result in results {
        let Some((kind, round)) = result
            .label
            .strip_prefix("shadows ")
            .and_then(|l| l.split_once(' '))
        else {
            continue;
        };
        let off = results
            .iter()
            .find(|r| r.label == format!("shadows off {round}"));
        if let (Some(off), true) = (off, kind != "off") {
            let ratio = result.gpu_ms_median / off.gpu_ms_median.max(1e-9);
            text.push_str(&format!("- {kind} {round}: {ratio:.2}\n"));
        }
    }
    text
}

/// A `--sweep` value refused: what is wrong and what is accepted.
fn bad_sweep(message: String) -> Error {
    Error::Flag {
        flag: "--sweep",
        message: message.into(),
    }
}
