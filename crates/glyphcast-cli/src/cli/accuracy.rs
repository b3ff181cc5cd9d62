//! `glyphcast accuracy`: the accuracy suite as a table (Markdown on stdout, CSV optional).
use clap::Args;
use glyphcast::Result;
use glyphcast::accuracy::{report, suite};
use glyphcast::render::{Method, Refinement, RenderSettings};
use glyphcast::vk::{Gpu, GpuOptions};
use std::path::PathBuf;

#[derive(Args)]
pub struct AccuracyArgs {
    /// Image side in pixels for every scene, 16 to 4096.
    #[arg(long, default_value_t = 160, value_parser = clap::value_parser!(u32).range(16..=4096))]
    size: u32,
    /// Methods to measure, comma separated: exact, fixed, interval, affine, impostor,
    /// mesh:LEVEL, latlong:N.
    #[arg(
        long,
        default_value = "fixed,interval,affine,exact",
        value_delimiter = ','
    )]
    methods: Vec<String>,
    /// March steps of the fixed-step method, comma separated.
    #[arg(long, default_value = "0.01,0.02,0.05,0.1,0.2", value_delimiter = ',')]
    steps: Vec<f32>,
    /// Refinements of the fixed-step method, comma separated.
    #[arg(
        long,
        default_value = "none,bisect:1,bisect:3,interp,secant:4",
        value_delimiter = ','
    )]
    refine: Vec<String>,
    /// Also write the table as Markdown to this file.
    #[arg(long, value_name = "FILE")]
    markdown: Option<PathBuf>,
    /// Also write the table as CSV to this file.
    #[arg(long, value_name = "FILE")]
    csv: Option<PathBuf>,
    /// Vulkan device: part of its name or its index.
    #[arg(long)]
    device: Option<String>,
}

impl AccuracyArgs {
    fn variants(&self) -> Result<Vec<RenderSettings>> {
        let mut variants = Vec::new();
        for method in &self.methods {
            let method = method.parse::<Method>()?;
            if method == Method::Fixed {
                for &step in &self.steps {
                    for refine in &self.refine {
                        let refinement = refine.parse::<Refinement>()?;
                        variants.push(RenderSettings {
                            method,
                            step,
                            refinement,
                            ..Default::default()
                        });
                    }
                }
            } else {
                // The other methods do not march at a fixed step: their defaults.
                variants.push(RenderSettings {
                    method,
                    ..Default::default()
                });
            }
        }
        for v in &variants {
            v.validate()?;
        }
        Ok(variants)
    }
}

pub fn run(args: &AccuracyArgs) -> Result<()> {
    let variants = args.variants()?;
    // Both tables are checked before the suite runs (existing folders, not the same
    // file twice) and written as one set, both or neither.
    let outputs: Vec<&std::path::Path> = args
        .markdown
        .iter()
        .chain(&args.csv)
        .map(PathBuf::as_path)
        .collect();
    glyphcast::io::atomic::check_outputs(&outputs, &[])?;
    let mut options = GpuOptions::from_env();
    if args.device.is_some() {
        options.device = args.device.clone();
    }
    let gpu = Gpu::headless(&options)?;
    eprintln!("device: {}", gpu.info);
    let scenes = suite::suite(args.size);
    let total = scenes.len() * variants.len();
    let mut done = 0;
    let rows = report::run(&gpu, &scenes, &variants, |row| {
        done += 1;
        eprintln!("[{done}/{total}] {} {}", row.scene, row.method);
    })?;
    let markdown = format!(
        "Device: {}\n\n{}\nSummary over the suite, fastest first:\n\n{}",
        gpu.info,
        report::markdown(&rows),
        report::summary_markdown(&rows)
    );
    let csv = report::csv(&rows);
    let mut tables: Vec<(&std::path::Path, &[u8])> = Vec::new();
    if let Some(path) = &args.markdown {
        tables.push((path, markdown.as_bytes()));
    }
    if let Some(path) = &args.csv {
        tables.push((path, csv.as_bytes()));
    }
    glyphcast::io::atomic::write_all_atomic(&tables)?;
    print!("{markdown}");
    Ok(())
}
