//! GLSL to SPIR-V: every shader job of the build, compiled on every core, each result
//! kept in a cache keyed by its preprocessed source.
//!
//! The `exact` fragment shaders and the per-layout vertex shaders (`Job::optimize`) are
//! compiled without optimisation, go through one round of the `spirv-opt` program's
//! performance passes, and then have their ids compacted
//! ([`SpirvOpt`]). Without that program, shaderc's own single round of those passes runs.
//!
//! A job is preprocessed first (includes resolved, macros expanded, comments gone; a few
//! milliseconds), and the text, less its line directives and blank lines, is hashed with
//! the job's stage and defines. A job whose hash is in the cache is not compiled again:
//! editing a comment or one shader recompiles only what that edit reaches. The cache lives
//! beside the build profiles (`target/glyphcast-spirv-cache`), so that `cargo build`,
//! `cargo test` and `cargo clippy` share it.
use crate::fail;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// Bumped when anything that shapes the SPIR-V but not the preprocessed text changes
/// (compiler options below).
const CACHE_VERSION: &str = "glyphcast-spirv-cache 2: vulkan1.3 unoptimised";

/// One shader to compile.
pub struct Job {
    /// Unique name; the SPIR-V is written to `<label>.spv`.
    pub label: String,
    /// Source file in glsl/.
    pub file: String,
    pub kind: shaderc::ShaderKind,
    /// Served as "glyph_function.glsl" to the source's includes.
    pub generated: String,
    /// Served as "exact_kernels.glsl": the exact method's arithmetic written out for
    /// this job's degrees (build/exact_kernels.rs); empty for shaders without it.
    pub kernels: String,
    /// Preprocessor names defined (without a value).
    pub defines: Vec<&'static str>,
    /// Relative cost, so that the longest jobs start first.
    pub weight: u32,
    /// Whether spirv-opt's performance passes run on the SPIR-V (see `options`).
    pub optimize: bool,
    /// The label of a variant without the distance output (location 1), for colour-only
    /// targets, derived from this job's SPIR-V ([`without_distance`]) rather than
    /// compiled and optimised again.
    pub without_distance: Option<String>,
}

/// Where the build reads and writes.
pub struct Dirs {
    pub glsl: PathBuf,
    /// The generated glyph functions, for reading compile errors.
    pub generated: PathBuf,
    pub cache: PathBuf,
    /// `<label>.spv` of every job, for the table's include_bytes!.
    pub spirv: PathBuf,
}

/// What a build did, for the build log.
#[derive(Default)]
pub struct Summary {
    pub compiled: usize,
    pub cached: usize,
    /// A hash of every job's cache key: changes whenever any shader's SPIR-V may have.
    pub hash: u64,
}

/// The cache directory: `GLYPHCAST_SPIRV_CACHE` if set, else beside the profile
/// directories when OUT_DIR has cargo's layout (`<target>/<profile>/build/<package>-<hash>/out`),
/// else inside OUT_DIR.
pub fn cache_dir(out_dir: &Path) -> PathBuf {
    println!("cargo:rerun-if-env-changed=GLYPHCAST_SPIRV_CACHE");
    if let Some(dir) = std::env::var_os("GLYPHCAST_SPIRV_CACHE").filter(|d| !d.is_empty()) {
        return PathBuf::from(dir);
    }
    let mut ancestors = out_dir.ancestors();
    let build = ancestors.nth(2);
    let target = ancestors.nth(1);
    match (build, target) {
        (Some(build), Some(target)) if build.file_name().is_some_and(|n| n == "build") => {
            target.join("glyphcast-spirv-cache")
        }
        _ => out_dir.join("spirv-cache"),
    }
}

/// Compiles every job (or takes it from the cache) and writes `<label>.spv` into
/// `dirs.spirv`, in little-endian byte order. Exits the build with the compiler's message,
/// the offending lines shown, on the first error.
pub fn compile_all(jobs: &mut [Job], dirs: &Dirs) -> Summary {
    for dir in [&dirs.generated, &dirs.cache, &dirs.spirv] {
        if let Err(e) = std::fs::create_dir_all(dir) {
            fail(format!("creating {}: {e}", dir.display()));
        }
    }
    let spirv_opt = SpirvOpt::find();
    if spirv_opt.is_none() && jobs.iter().any(|job| job.optimize) {
        println!(
            "cargo:warning=spirv-opt (SPIRV-Tools, Debian package spirv-tools) not found or \
             SPIRV_OPT=none: the exact shaders keep shaderc's single optimisation pass, and \
             creating their pipelines takes lavapipe about three times longer"
        );
    }
    let spirv_opt = spirv_opt.as_ref();
    jobs.sort_by(|a, b| b.weight.cmp(&a.weight).then_with(|| a.label.cmp(&b.label)));
    let next = AtomicUsize::new(0);
    let compiled = AtomicUsize::new(0);
    // The sum of the jobs' keys, which does not depend on the order the workers finish in.
    let hash = std::sync::atomic::AtomicU64::new(0);
    // Seconds each compiled job took, written to `$OUT_DIR/shader-times.txt` (slowest first)
    // for whoever works on the build's time.
    let times = std::sync::Mutex::new(Vec::new());
    // Set by the first failing job, so that the other workers stop instead of compiling
    // the rest of a build that will fail.
    let stop = AtomicBool::new(false);
    let threads = std::thread::available_parallelism().map_or(1, usize::from);
    let jobs = &*jobs;
    let failure: Option<String> = std::thread::scope(|scope| {
        let workers: Vec<_> = (0..threads.min(jobs.len()))
            .map(|_| {
                scope.spawn(|| -> Result<(), String> {
                    let compiler =
                        shaderc::Compiler::new().map_err(|e| format!("shaderc compiler: {e}"))?;
                    loop {
                        let index = next.fetch_add(1, Ordering::Relaxed);
                        let Some(job) = jobs.get(index) else {
                            return Ok(());
                        };
                        if stop.load(Ordering::Relaxed) {
                            return Ok(());
                        }
                        let started = std::time::Instant::now();
                        let result = run(&compiler, job, dirs, spirv_opt).map(|(compiled, key)| {
                            hash.fetch_add(key, Ordering::Relaxed);
                            compiled
                        });
                        match result {
                            Ok(true) => {
                                compiled.fetch_add(1, Ordering::Relaxed);
                                let seconds = started.elapsed().as_secs_f64();
                                if let Ok(mut times) = times.lock() {
                                    times.push((seconds, job.label.clone()));
                                }
                            }
                            Ok(false) => {}
                            Err(message) => {
                                stop.store(true, Ordering::Relaxed);
                                return Err(message);
                            }
                        }
                    }
                })
            })
            .collect();
        workers
            .into_iter()
            .filter_map(|w| match w.join() {
                Ok(Ok(())) => None,
                Ok(Err(message)) => Some(message),
                Err(_) => Some("a shader compiler thread panicked".to_owned()),
            })
            .next()
    });
    if let Some(message) = failure {
        fail(message);
    }
    let mut times = times.into_inner().unwrap_or_default();
    if !times.is_empty() {
        times.sort_by(|a, b| b.0.total_cmp(&a.0));
        let text: String = times
            .iter()
            .map(|(seconds, label)| format!("{seconds:8.3} {label}\n"))
            .collect();
        let _ = std::fs::write(dirs.generated.with_file_name("shader-times.txt"), text);
    }
    let compiled = compiled.into_inner();
    Summary {
        compiled,
        cached: jobs.len() - compiled,
        hash: hash.into_inner(),
    }
}

/// shaderc's options for `job`; `optimise`: whether shaderc runs spirv-opt's performance
/// passes itself (only when the `spirv-opt` program is missing, see [`SpirvOpt`]).
fn options<'a>(
    job: &'a Job,
    glsl_dir: &'a Path,
    optimise: bool,
) -> Result<shaderc::CompileOptions<'a>, String> {
    let mut options =
        shaderc::CompileOptions::new().map_err(|e| format!("shaderc options: {e}"))?;
    options.set_target_env(
        shaderc::TargetEnv::Vulkan,
        shaderc::EnvVersion::Vulkan1_3 as u32,
    );
    if job.kind == shaderc::ShaderKind::Compute {
        // SPIR-V 1.6 gives a compute shader's workgroup size as LocalSizeId, which needs
        // the device's maintenance4 feature; 1.5 gives it as LocalSize, which every
        // device takes (a host's device need not enable maintenance4).
        options.set_target_spirv(shaderc::SpirvVersion::V1_5);
    }
    // SPIR-V optimisation only where it pays at run time: the drivers optimise anyway,
    // but creating a pipeline of the default method's shader is several times faster
    // from optimised SPIR-V, and that creation is most of a one-shot render's time, so
    // the `exact` fragment shaders are optimised (`Job::optimize`). Their arithmetic is
    // written out by the generator (build/exact_kernels.rs), so one round of spirv-opt's
    // passes costs about 3 s of CPU at order 12; when it unrolled loops itself, rounds
    // took 100 s there and the build's shaders 435 s.
    options.set_optimization_level(if optimise {
        shaderc::OptimizationLevel::Performance
    } else {
        shaderc::OptimizationLevel::Zero
    });
    for define in &job.defines {
        options.add_macro_definition(define, None);
    }
    options.set_include_callback(move |name, _, _, _| {
        let content = if name == "glyph_function.glsl" {
            job.generated.clone()
        } else if name == "exact_kernels.glsl" {
            job.kernels.clone()
        } else if name == "codes.glsl" {
            crate::catalog::codes_glsl()
        } else {
            std::fs::read_to_string(glsl_dir.join(name)).map_err(|e| format!("{name}: {e}"))?
        };
        Ok(shaderc::ResolvedInclude {
            resolved_name: name.to_owned(),
            content,
        })
    });
    Ok(options)
}

/// SPIRV-Tools' optimiser as a program, run on shaderc's unoptimised output: one round
/// of its performance passes. On the written-out `exact` shaders that is the fixed point
/// (order 12: 617 kB from glslang, 208 kB after it); on loops it had to unroll itself,
/// each round left branches on constants and dead blocks for the next (three rounds,
/// minutes at order 12). The SPIRV-Tools
/// that shaderc links has no C entry point for its optimiser (the C++ one would need a
/// C++ shim), so the program of the same package (`spirv-tools`) runs it.
pub struct SpirvOpt {
    program: std::ffi::OsString,
    /// Its `--version` line, part of the cache key: another version may write other code.
    version: String,
}

impl SpirvOpt {
    /// `$SPIRV_OPT` or `spirv-opt` on the PATH, if it runs; `SPIRV_OPT=none` builds
    /// without it.
    fn find() -> Option<SpirvOpt> {
        println!("cargo:rerun-if-env-changed=SPIRV_OPT");
        let program = std::env::var_os("SPIRV_OPT").unwrap_or_else(|| "spirv-opt".into());
        if program == "none" {
            return None;
        }
        let output = std::process::Command::new(&program)
            .arg("--version")
            .output()
            .ok()
            .filter(|output| output.status.success())?;
        let version = String::from_utf8_lossy(&output.stdout)
            .lines()
            .next()
            .unwrap_or_default()
            .to_owned();
        Some(SpirvOpt { program, version })
    }

    /// One round of `spirv-opt -O` on `spirv` (little-endian, unoptimised). On the
    /// written-out `exact` shaders it reaches the fixed point: a second round left every
    /// variant byte for byte as it was (2026-11-28), and cost another sixth.
    fn optimise(&self, spirv: Vec<u8>, label: &str) -> Result<Vec<u8>, String> {
        self.round(&spirv, label, "-O")
    }

    /// The ids of `spirv` renumbered without gaps. spirv-opt's passes leave the module's
    /// id bound at 50 times its ids (order 8: 248,371 for about 4,800), and Mesa's
    /// SPIR-V reader allocates and clears a table entry for every id up to the bound:
    /// lavapipe's reading of the order-8 shader took 12 ms before, 4.6 ms after.
    fn compact(&self, spirv: &[u8], label: &str) -> Result<Vec<u8>, String> {
        self.round(spirv, label, "--compact-ids")
    }

    /// One `spirv-opt PASS` over stdin and stdout; the module is validated on the way in.
    fn round(&self, spirv: &[u8], label: &str, pass: &str) -> Result<Vec<u8>, String> {
        use std::io::Write as _;
        use std::process::{Command, Stdio};
        let failed = |e: String| {
            format!("spirv-opt {pass} on {label} (SPIRV_OPT=none builds without it): {e}")
        };
        let mut child = Command::new(&self.program)
            .args([pass, "--target-env=vulkan1.3", "-", "-o", "-"])
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|e| failed(e.to_string()))?;
        let mut stdin = child
            .stdin
            .take()
            .ok_or_else(|| failed("no stdin".into()))?;
        // Written from a thread of its own, so that neither side waits on a full pipe.
        let output = std::thread::scope(|scope| {
            let writer = scope.spawn(move || stdin.write_all(spirv));
            let output = child.wait_with_output().map_err(|e| e.to_string())?;
            match writer.join() {
                Ok(Ok(())) => Ok(output),
                Ok(Err(e)) => Err(format!("writing its input: {e}")),
                Err(_) => Err("the thread writing its input panicked".to_owned()),
            }
        })
        .map_err(failed)?;
        if !output.status.success() {
            return Err(failed(String::from_utf8_lossy(&output.stderr).into_owned()));
        }
        let bytes = output.stdout;
        if bytes.len() < 20 || bytes.len() % 4 != 0 || bytes[..4] != 0x0723_0203_u32.to_le_bytes() {
            return Err(failed(format!(
                "{} bytes of output, not a little-endian SPIR-V module",
                bytes.len()
            )));
        }
        Ok(bytes)
    }
}

/// The spirv-opt steps of an optimised job's cache entries: after the round of `-O`,
/// and the final module, its ids compacted.
const OPTIMISED: &str = "one round of spirv-opt -O on unoptimised SPIR-V";
const COMPACTED: &str = "one round of spirv-opt -O on unoptimised SPIR-V, then --compact-ids";

/// One job; true when it was compiled, false when the cache had it; and its cache key.
fn run(
    compiler: &shaderc::Compiler,
    job: &Job,
    dirs: &Dirs,
    spirv_opt: Option<&SpirvOpt>,
) -> Result<(bool, u64), String> {
    let path = dirs.glsl.join(&job.file);
    let source = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let generated_path = dirs
        .generated
        .join(format!("{}.glyph_function.glsl", job.label));
    let _ = std::fs::write(&generated_path, &job.generated);
    let explain = |message: String| explain(&message, job, &dirs.glsl, &generated_path);

    let preprocessed = compiler
        .preprocess(
            &source,
            &job.file,
            "main",
            Some(&options(job, &dirs.glsl, false)?),
        )
        .map_err(|e| explain(e.to_string()))?;
    let text = preprocessed.as_text();
    let spirv_opt = spirv_opt.filter(|_| job.optimize);
    // shaderc optimises only when the spirv-opt program cannot.
    let shaderc_optimises = job.optimize && spirv_opt.is_none();
    let key = cache_key(job, job.optimize, spirv_opt.map(|p| (p, COMPACTED)), &text);
    let target = dirs.spirv.join(format!("{}.spv", job.label));
    let compile = || -> Result<Vec<u8>, String> {
        let artifact = compiler
            .compile_into_spirv(
                &source,
                job.kind,
                &job.file,
                "main",
                Some(&options(job, &dirs.glsl, shaderc_optimises)?),
            )
            .map_err(|e| explain(e.to_string()))?;
        Ok(artifact
            .as_binary()
            .iter()
            .flat_map(|w| w.to_le_bytes())
            .collect())
    };
    let (bytes, compiled) = match (cached(dirs, key), spirv_opt) {
        (Some(bytes), _) => (bytes, false),
        (None, None) => (store(dirs, key, compile()?)?, true),
        // shaderc's output has a cache entry of its own, so that a new spirv-opt (or its
        // arrival) reruns only spirv-opt.
        (None, Some(program)) => {
            // Each step has a cache entry of its own, so that a new step reruns only
            // what follows it.
            // shaderc's unoptimised output: the same entry as an unoptimised job's.
            let shaderc_key = cache_key(job, false, None, &text);
            let shaderc_bytes = match cached(dirs, shaderc_key) {
                Some(bytes) => bytes,
                None => store(dirs, shaderc_key, compile()?)?,
            };
            let optimised_key = cache_key(job, true, Some((program, OPTIMISED)), &text);
            let optimised = match cached(dirs, optimised_key) {
                Some(bytes) => bytes,
                None => store(
                    dirs,
                    optimised_key,
                    program.optimise(shaderc_bytes, &job.label)?,
                )?,
            };
            let bytes = program.compact(&optimised, &job.label)?;
            (store(dirs, key, bytes)?, true)
        }
    };
    // Unchanged outputs keep their times, so cargo sees nothing new in them.
    if std::fs::read(&target).ok().as_deref() != Some(&bytes[..]) {
        write_replacing(&target, &bytes)?;
    }
    let mut key = key;
    if let Some(label) = &job.without_distance {
        let derived_key = derived_key(key, spirv_opt);
        let derived = match cached(dirs, derived_key) {
            Some(bytes) => bytes,
            None => {
                let stripped = without_distance(&bytes).map_err(|e| format!("{label}: {e}"))?;
                // Dead-code elimination drops what only the distance needed, and the
                // validator checks the module on the way in.
                let stripped = match spirv_opt {
                    Some(program) => program.compact(
                        &program.round(&stripped, label, "--eliminate-dead-code-aggressive")?,
                        label,
                    )?,
                    None => stripped,
                };
                store(dirs, derived_key, stripped)?
            }
        };
        let target = dirs.spirv.join(format!("{label}.spv"));
        if std::fs::read(&target).ok().as_deref() != Some(&derived[..]) {
            write_replacing(&target, &derived)?;
        }
        key = key.wrapping_add(derived_key);
    }
    Ok((compiled, key))
}

/// The cache key of a job's variant without the distance output.
fn derived_key(key: u64, spirv_opt: Option<&SpirvOpt>) -> u64 {
    let mut hash = key ^ 0x9e37_79b9_7f4a_7c15;
    let step = format!(
        "without the output at location 1, then spirv-opt --eliminate-dead-code-aggressive \
         and --compact-ids ({})",
        spirv_opt.map_or("none", |p| p.version.as_str())
    );
    for b in step.bytes() {
        hash ^= u64::from(b);
        hash = hash.wrapping_mul(0x0000_0100_0000_01b3);
    }
    hash
}

/// A fragment shader's SPIR-V (little-endian) without its output variable at location 1
/// (the ray distance): the variable, its names and decorations, its entry in the entry
/// point's interface and the stores to it are taken out, which is what compiling the
/// GLSL without that output (`GLYPHCAST_NO_DISTANCE`) gives, less the optimisation's
/// second run. A module that used the variable otherwise would be left with a dangling
/// id, which spirv-opt's validation of the next step's input refuses.
fn without_distance(spirv: &[u8]) -> Result<Vec<u8>, String> {
    const OP_NAME: u32 = 5;
    const OP_ENTRY_POINT: u32 = 15;
    const OP_VARIABLE: u32 = 59;
    const OP_STORE: u32 = 62;
    const OP_DECORATE: u32 = 71;
    const OP_MEMBER_DECORATE: u32 = 72;
    const DECORATION_LOCATION: u32 = 30;
    const STORAGE_OUTPUT: u32 = 3;
    if spirv.len() < 20 || !spirv.len().is_multiple_of(4) {
        return Err("not a SPIR-V module".into());
    }
    let words: Vec<u32> = spirv
        .chunks_exact(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    // The instructions after the header, as (start, word count).
    let mut instructions = Vec::new();
    let mut at = 5;
    while at < words.len() {
        let count = (words[at] >> 16) as usize;
        if count == 0 || at + count > words.len() {
            return Err(format!("a malformed instruction at word {at}"));
        }
        instructions.push((at, count));
        at += count;
    }
    let op = |(start, _): (usize, usize)| words[start] & 0xffff;
    let outputs: Vec<u32> = instructions
        .iter()
        .filter(|&&(s, c)| op((s, c)) == OP_VARIABLE && c >= 4 && words[s + 3] == STORAGE_OUTPUT)
        .map(|&(s, _)| words[s + 2])
        .collect();
    let located: Vec<u32> = instructions
        .iter()
        .filter(|&&(s, c)| {
            op((s, c)) == OP_DECORATE
                && c == 4
                && words[s + 2] == DECORATION_LOCATION
                && words[s + 3] == 1
                && outputs.contains(&words[s + 1])
        })
        .map(|&(s, _)| words[s + 1])
        .collect();
    let [target] = located[..] else {
        return Err(format!("{} outputs at location 1, not one", located.len()));
    };
    let mut out: Vec<u32> = words[..5].to_vec();
    for &(start, count) in &instructions {
        let body = &words[start..start + count];
        match op((start, count)) {
            OP_NAME | OP_DECORATE | OP_MEMBER_DECORATE if body[1] == target => continue,
            OP_VARIABLE if body[2] == target => continue,
            OP_STORE if body[1] == target => continue,
            OP_ENTRY_POINT => {
                // Execution model, function id, the name (a NUL-terminated string padded
                // to whole words), then the interface's ids.
                let name_words = body[3..]
                    .iter()
                    .position(|w| w.to_le_bytes().contains(&0))
                    .ok_or("an entry point name without its end")?
                    + 1;
                let head = 3 + name_words;
                let mut kept: Vec<u32> = body[..head.min(body.len())].to_vec();
                kept.extend(
                    body[head.min(body.len())..]
                        .iter()
                        .filter(|&&id| id != target),
                );
                kept[0] = ((kept.len() as u32) << 16) | OP_ENTRY_POINT;
                out.extend(kept);
                continue;
            }
            _ => {}
        }
        out.extend_from_slice(body);
    }
    Ok(out.iter().flat_map(|w| w.to_le_bytes()).collect())
}

/// The cache's SPIR-V under `key`, if it holds a plausible module.
fn cached(dirs: &Dirs, key: u64) -> Option<Vec<u8>> {
    std::fs::read(dirs.cache.join(format!("{key:016x}.spv")))
        .ok()
        .filter(|bytes| !bytes.is_empty() && bytes.len() % 4 == 0)
}

/// Puts `bytes` into the cache under `key` and gives them back.
fn store(dirs: &Dirs, key: u64, bytes: Vec<u8>) -> Result<Vec<u8>, String> {
    write_replacing(&dirs.cache.join(format!("{key:016x}.spv")), &bytes)?;
    Ok(bytes)
}

/// FNV-1a (64 bit) of the cache version, the stage, the optimisation (with spirv-opt's
/// version where it runs), the defines and the preprocessed text without line directives,
/// blank lines or indentation.
fn cache_key(
    job: &Job,
    optimised: bool,
    spirv_opt: Option<(&SpirvOpt, &str)>,
    preprocessed: &str,
) -> u64 {
    let mut hash = 0xcbf2_9ce4_8422_2325_u64;
    let mut feed = |bytes: &[u8]| {
        for b in bytes {
            hash ^= u64::from(*b);
            hash = hash.wrapping_mul(0x0000_0100_0000_01b3);
        }
        hash ^= 0xff;
        hash = hash.wrapping_mul(0x0000_0100_0000_01b3);
    };
    feed(CACHE_VERSION.as_bytes());
    feed(format!("{:?}", job.kind).as_bytes());
    if job.kind == shaderc::ShaderKind::Compute {
        feed(b"spirv 1.5");
    }
    feed(if optimised {
        b"optimised"
    } else {
        b"unoptimised"
    });
    if let Some((program, steps)) = spirv_opt {
        feed(steps.as_bytes());
        feed(program.version.as_bytes());
    }
    for define in &job.defines {
        feed(define.as_bytes());
    }
    for line in preprocessed.lines() {
        let line = line.trim();
        if !line.is_empty() && !line.starts_with("#line") {
            feed(line.as_bytes());
        }
    }
    hash
}

/// Writes through a temporary file and a rename, so that a build killed half way never
/// leaves a truncated SPIR-V file behind.
fn write_replacing(path: &Path, bytes: &[u8]) -> Result<(), String> {
    let temporary = path.with_extension(format!("tmp{}", std::process::id()));
    std::fs::write(&temporary, bytes)
        .and_then(|()| std::fs::rename(&temporary, path))
        .map_err(|e| format!("writing {}: {e}", path.display()))
}

/// glslang's messages read `name:line: ...`; shows the offending source lines.
fn explain(message: &str, job: &Job, glsl_dir: &Path, generated_path: &Path) -> String {
    let mut out = format!("GLSL compile error in variant {}:\n{message}\n", job.label);
    for line in message.lines() {
        let mut parts = line.splitn(3, ':');
        let (Some(name), Some(number)) = (parts.next(), parts.next()) else {
            continue;
        };
        let name = name.trim().trim_start_matches("ERROR").trim();
        let Ok(number) = number.trim().parse::<usize>() else {
            continue;
        };
        let text = if name == "glyph_function.glsl" {
            Some(job.generated.clone())
        } else {
            std::fs::read_to_string(glsl_dir.join(name)).ok()
        };
        if let Some(line_text) = text
            .as_deref()
            .and_then(|t| t.lines().nth(number.saturating_sub(1)))
        {
            let _ = writeln!(out, "  {name}:{number}: {}", line_text.trim());
        }
    }
    let _ = writeln!(out, "generated source: {}", generated_path.display());
    out
}
