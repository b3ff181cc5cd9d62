//! The set's page (`index.html`: the figures with their captions, the inputs, the
//! orientation convention) and its sidecar (`qc.json`). Both are written from the same
//! [`Summary`]. Neither holds a time; the sidecar keeps the device and the timings apart
//! in its `run` field, so two runs on the same inputs and device give the same page and
//! sidecars that differ there only.
use std::io::Read;
use std::path::PathBuf;

use serde_json::{Value, json};
use sha2::{Digest, Sha256};

use super::figures::Figure;
use super::survey::{PlaneCuts, Region, Survey, voxel_world};
use super::{InputFile, QcRequest};
use crate::volume::{Orientation, Volume};
use glyphcast::scene::GlyphKind;
use glyphcast::{Error, Result};

/// Everything the page and the sidecar report.
pub struct Summary<'a> {
    /// What was asked: inputs, options and the output folder.
    pub request: &'a QcRequest,
    /// Each panel's side in pixels.
    pub panel_size: u32,
    /// The files read, with sizes and checksums.
    pub inputs: &'a [InputFile],
    /// The volume the figures show.
    pub volume: &'a Volume,
    /// The per-voxel maps and counts of the set.
    pub survey: &'a Survey,
    /// The slices of the mosaic, per plane.
    pub cuts: &'a [PlaneCuts],
    /// The zoomed regions, in figure order.
    pub regions: &'a [Region],
    /// The rendered figures, in page order.
    pub figures: &'a [Figure],
    /// The figures' files (name, PNG bytes).
    pub files: &'a [(String, Vec<u8>)],
    /// Notes shown on the page and kept in the sidecar, one per entry.
    pub notes: &'a [String],
    /// The device the figures were drawn on, as `gpu.info` prints it (sidecar only).
    pub device: &'a str,
    /// Milliseconds per step (read, survey, build, device, render, encode, total),
    /// for the sidecar's `run`.
    pub timings: &'a [(&'static str, f64)],
}

/// The size and SHA-256 of each input, read in blocks.
pub fn checksums(inputs: Vec<(&'static str, PathBuf)>) -> Result<Vec<InputFile>> {
    inputs
        .into_iter()
        .map(|(role, path)| {
            let (bytes, sha256) = file_sha256(&path)?;
            Ok(InputFile {
                role,
                path,
                bytes,
                sha256,
            })
        })
        .collect()
}

fn file_sha256(path: &std::path::Path) -> Result<(u64, String)> {
    let mut file = std::fs::File::open(path).map_err(|err| Error::io(path, err))?;
    let mut hasher = Sha256::new();
    let mut block = vec![0u8; 1 << 20];
    let mut total = 0u64;
    loop {
        let n = file.read(&mut block).map_err(|err| Error::io(path, err))?;
        if n == 0 {
            break;
        }
        hasher.update(&block[..n]);
        total += n as u64;
    }
    Ok((total, hex(&hasher.finalize())))
}

/// The SHA-256 of `bytes`, in hexadecimal.
pub fn sha256_hex(bytes: &[u8]) -> String {
    hex(&Sha256::digest(bytes))
}

fn hex(digest: &[u8]) -> String {
    digest.iter().map(|b| format!("{b:02x}")).collect()
}

fn file_name(path: &std::path::Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}

/// The orientation the panels are drawn in.
fn orientation(request: &QcRequest) -> Orientation {
    request
        .volume
        .orientation
        .as_deref()
        .and_then(|o| o.parse().ok())
        .unwrap_or_default()
}

/// How the panels are oriented, in words.
fn orientation_text(request: &QcRequest) -> &'static str {
    match orientation(request) {
        Orientation::Radiological => {
            "Radiological convention (as mrview): in axial and coronal panels the subject's \
             right is on the image's left. Axial panels are seen from below with anterior up, \
             coronal panels from the front with superior up, sagittal panels from the \
             subject's left with anterior on the left and superior up."
        }
        Orientation::Neurological => {
            "Neurological convention: in axial and coronal panels the subject's right is on \
             the image's right. Axial panels are seen from above with anterior up, coronal \
             panels from behind with superior up, sagittal panels from the subject's left \
             with anterior on the left and superior up."
        }
    }
}

/// The volume as the sidecar describes it.
fn volume_json(volume: &Volume) -> Value {
    let sizes = volume.voxel_to_world.voxel_sizes().to_array();
    let (band, basis, legacy) = match volume.kind {
        GlyphKind::Sh {
            band,
            basis,
            legacy,
        } => (band, basis.name().to_owned(), legacy),
        GlyphKind::Tensor(_) => (0, String::new(), false),
    };
    json!({
        "dims": volume.dims,
        "voxel_size_mm": sizes,
        "sh_band": band,
        "basis": basis,
        "legacy": legacy,
        "frame": volume.frame.name(),
    })
}

fn region_json(volume: &Volume, rank: usize, region: &Region) -> Value {
    json!({
        "rank": rank + 1,
        "voxels": region.ranges_text(),
        "centre_voxel": region.centre(),
        "slices_shown": region.slices,
        "centre_world_mm": voxel_world(volume, region.centre()).to_array(),
        "mean_gfa": region.mean_gfa,
        "mean_amplitude": region.mean_amplitude,
        "figure": format!("zoom-{}.png", rank + 1),
    })
}

/// The sidecar, `qc.json` (see the module notes).
pub fn sidecar(summary: &Summary) -> Result<String> {
    let request = summary.request;
    let options = &request.render;
    let inputs: Vec<Value> = summary
        .inputs
        .iter()
        .map(|input| {
            json!({
                "role": input.role,
                "name": file_name(&input.path),
                "path": input.path.display().to_string(),
                "bytes": input.bytes,
                "sha256": input.sha256,
            })
        })
        .collect();
    let figures: Vec<Value> = summary
        .figures
        .iter()
        .zip(summary.files)
        .map(|(figure, (name, png))| {
            json!({
                "file": name,
                "title": figure.title,
                "caption": figure.caption,
                "panels": figure.panel_captions,
                "columns": figure.columns,
                "width": figure.image.width,
                "height": figure.image.height,
                "glyphs": figure.glyphs,
                "bytes": png.len(),
                "sha256": sha256_hex(png),
            })
        })
        .collect();
    let cuts: Vec<Value> = summary
        .cuts
        .iter()
        .map(|c| {
            let letter = ["i", "j", "k"][c.voxel_plane.voxel_axis()];
            json!({
                "plane": c.plane.name(),
                "voxel_axis": letter,
                "indices": c.indices,
            })
        })
        .collect();
    let regions: Vec<Value> = summary
        .regions
        .iter()
        .enumerate()
        .map(|(rank, region)| region_json(summary.volume, rank, region))
        .collect();
    let timings: serde_json::Map<String, Value> = summary
        .timings
        .iter()
        .map(|(name, ms)| ((*name).to_owned(), json!(ms)))
        .collect();
    let document = json!({
        "format": "glyphcast qc 1",
        "glyphcast_version": env!("CARGO_PKG_VERSION"),
        "inputs": inputs,
        "volume": volume_json(summary.volume),
        "settings": {
            "panel_size": summary.panel_size,
            "method": options.method.map_or_else(|| "exact".to_owned(), |m| m.to_string()),
            "negative": options.negative.unwrap_or_default().to_string(),
            "samples": options.samples.unwrap_or(1),
            "orientation": orientation(request).name(),
            "labels": true,
            "sizing": "one scale for every panel: glyph radius proportional to the ODF's \
                       largest radius, up to 0.45 of the smallest voxel size, which the \
                       larger half of the set's glyphs share (radius at or above the median)",
            "color": "direction",
        },
        "selection": {
            "looked_at": match &request.mask {
                Some(mask) => format!("voxels of the mask {} with a positive mean amplitude", file_name(mask)),
                None => "voxels with finite coefficients and a positive mean amplitude".to_owned(),
            },
            "voxels": summary.survey.count,
            "cuts": cuts,
            "cut_rule": "slices at the quartiles of the ODF amplitude summed over each slice",
            "regions": regions,
            "region_rule": "non-overlapping cubes of highest mean GFA, at least half inside",
        },
        "figures": figures,
        "notes": summary.notes,
        "run": {
            "device": summary.device,
            "timings_ms": timings,
        },
    });
    serde_json::to_string_pretty(&document)
        .map(|text| text + "\n")
        .map_err(|err| Error::io("qc.json", err))
}

/// `text` with HTML's special characters escaped.
fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

const STYLE: &str = "body{font-family:DejaVu Sans,Helvetica,Arial,sans-serif;margin:1.5em;\
background:#fafafa;color:#222;max-width:1300px}h1{font-size:1.4em}h2{font-size:1.15em;\
margin-top:1.6em}figure{margin:0.5em 0}img{max-width:100%;height:auto;border:1px solid #999;\
background:#222}figcaption{font-size:0.9em;margin-top:0.3em}table{border-collapse:collapse;\
font-size:0.85em}td,th{border:1px solid #ccc;padding:2px 8px;text-align:left}\
code{font-size:0.95em}.note{background:#fff3cd;padding:0.4em 0.8em;border:1px solid #e0c060}";

/// The page, `index.html`.
pub fn index_html(summary: &Summary) -> String {
    let request = summary.request;
    let fod = file_name(&request.fod);
    let mut html = String::new();
    html.push_str("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n");
    html.push_str(&format!(
        "<title>glyphcast qc: {}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n",
        escape(&fod)
    ));
    html.push_str(&format!("<h1>Fibre ODFs: {}</h1>\n", escape(&fod)));
    html.push_str("<table>\n<tr><th>input</th><th>file</th><th>bytes</th><th>SHA-256</th></tr>\n");
    for input in summary.inputs {
        html.push_str(&format!(
            "<tr><td>{}</td><td>{}</td><td>{}</td><td><code>{}</code></td></tr>\n",
            input.role,
            escape(&file_name(&input.path)),
            input.bytes,
            input.sha256
        ));
    }
    html.push_str("</table>\n");
    let v = summary.volume;
    let sizes = v.voxel_to_world.voxel_sizes();
    html.push_str(&format!(
        "<p>{} x {} x {} voxels of {:.2} x {:.2} x {:.2} mm, {}; {} voxels looked at ({}). \
         Glyphs coloured by direction (red left-right, green anterior-posterior, blue \
         superior-inferior); one size scale for every panel: proportional to the ODF's \
         amplitude below the set's median, full size at or above it.</p>\n",
        v.dims[0],
        v.dims[1],
        v.dims[2],
        sizes.x,
        sizes.y,
        sizes.z,
        escape(&v.kind.to_string()),
        summary.survey.count,
        match &request.mask {
            Some(mask) => format!("inside the mask {}", escape(&file_name(mask))),
            None => "no mask: voxels with a positive mean amplitude".into(),
        }
    ));
    html.push_str(&format!(
        "<p><b>Orientation.</b> {} The letters at each panel's edges name the direction \
         towards that edge (R/L right/left, A/P anterior/posterior, S/I superior/inferior).</p>\n",
        orientation_text(request)
    ));
    for note in summary.notes {
        html.push_str(&format!("<p class=\"note\">{}</p>\n", escape(note)));
    }
    for figure in summary.figures {
        html.push_str(&format!(
            "<h2>{}</h2>\n<figure>\n<img src=\"{}\" width=\"{}\" height=\"{}\" alt=\"{}\">\n\
             <figcaption>{} Panels, left to right{}: {}.</figcaption>\n</figure>\n",
            escape(&figure.title),
            escape(&figure.file),
            figure.image.width,
            figure.image.height,
            escape(&figure.title),
            escape(&figure.caption),
            if figure.panel_captions.len() > figure.columns {
                ", then down"
            } else {
                ""
            },
            escape(&figure.panel_captions.join(", "))
        ));
    }
    html.push_str(&format!(
        "<p>Made by glyphcast {} on {}; the settings, choices and checksums are in \
         <a href=\"qc.json\">qc.json</a>.</p>\n</body>\n</html>\n",
        env!("CARGO_PKG_VERSION"),
        escape(summary.device)
    ));
    html
}
