//! Mutation fuzzing of every file reader on stable Rust: the scene reader, NIfTI (plain
//! and gzip), bval/bvec, Voigt stiffness and MRtrix `.mif` (plain and gzip). Each
//! reader gets inputs made from its corpus (tests/fuzz/corpus/READER/) by stacked
//! mutations: bit flips, random bytes, inserts, deletions, truncation, splicing with
//! another corpus file, interesting integers and floats over binary fields, and
//! dictionary tokens for the text formats. A gzip file is mutated either as stored or
//! in its decompressed content, recompressed (to reach the header checks behind the
//! gzip layer). Every input must give Ok or Err: a panic fails the test, which saves the
//! input under target/tmp/fuzz-failures/ and prints the seed and iteration that made it.
//!
//! Runs are bounded by time: GLYPHCAST_FUZZ_SECONDS (default 60) in all, shared evenly
//! by the five readers, which run in parallel. GLYPHCAST_FUZZ_SEED (default 1) picks the
//! sequence; input i of a reader depends only on the seed, the reader and i, so a failure
//! reproduces with the same seed. The corpus is rewritten by
//! `cargo test -p glyphcast-cli --test integration -- --ignored fuzz::write_corpus`.
use crate::common;

use glyphcast::glyph::stiffness::VoigtStiffness;
use glyphcast::rng::SplitMix64;
use glyphcast::scene::Scene;
use glyphcast_dmri::fit::gradients::GradientTable;
use glyphcast_dmri::io::mif::{MifWrite, read_mif, write_mif};
use glyphcast_dmri::io::nifti::read_nifti_bytes;
use glyphcast_dmri::io::nifti::write::nifti1_bytes;
use std::io::Read;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

const READERS: u32 = 5;

fn corpus_dir(reader: &str) -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .join("tests/fuzz/corpus")
        .join(reader)
}

/// (file name, bytes) of every corpus file of `reader`, sorted by name.
fn corpus(reader: &str) -> Vec<(String, Vec<u8>)> {
    let dir = corpus_dir(reader);
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|entry| {
            let path = entry.expect("listing the corpus").path();
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            (name, std::fs::read(&path).expect("reading the corpus"))
        })
        .collect();
    files.sort();
    assert!(!files.is_empty(), "empty corpus {}", dir.display());
    files
}

fn env_number(name: &str, default: u64) -> u64 {
    std::env::var(name)
        .ok()
        .map(|v| {
            v.parse()
                .unwrap_or_else(|_| panic!("{name}={v}: not a number"))
        })
        .unwrap_or(default)
}

fn gzip_name(name: &str) -> bool {
    name.ends_with(".gz")
}

fn gunzip(bytes: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    flate2::read::MultiGzDecoder::new(bytes)
        .read_to_end(&mut out)
        .expect("a corpus .gz file decompresses");
    out
}

const INTEGERS: [i64; 16] = [
    0,
    1,
    -1,
    2,
    7,
    8,
    0x7f,
    0x80,
    0xff,
    0x7fff,
    -0x8000,
    0xffff,
    0x7fff_ffff,
    -0x8000_0000,
    i64::MAX,
    i64::MIN,
];
const FLOATS: [f64; 9] = [
    0.0,
    -0.0,
    1.0,
    -1.0,
    f64::NAN,
    f64::INFINITY,
    f64::NEG_INFINITY,
    1e38,
    1e-45,
];

/// A fair coin.
fn coin(rng: &mut SplitMix64) -> bool {
    rng.next_u64() >> 63 == 0
}

/// One mutation step on `bytes`; `others` are the corpus, for splicing, `tokens` the
/// reader's dictionary.
fn mutate(rng: &mut SplitMix64, bytes: &mut Vec<u8>, others: &[Vec<u8>], tokens: &[&str]) {
    let below = |rng: &mut SplitMix64, n: usize| (rng.next_u64() % (n.max(1) as u64)) as usize;
    let at = below(rng, bytes.len() + 1);
    match below(rng, 9) {
        0 if !bytes.is_empty() => {
            let i = below(rng, bytes.len());
            bytes[i] ^= 1 << below(rng, 8);
        }
        1 if !bytes.is_empty() => {
            let i = below(rng, bytes.len());
            bytes[i] = rng.next_u64() as u8;
        }
        2 => {
            let count = 1 + below(rng, 16);
            let fresh: Vec<u8> = (0..count).map(|_| rng.next_u64() as u8).collect();
            bytes.splice(at..at, fresh);
        }
        3 => {
            let end = (at + 1 + below(rng, 32)).min(bytes.len());
            bytes.drain(at.min(end)..end);
        }
        4 => bytes.truncate(at),
        5 => {
            let other = &others[below(rng, others.len())];
            let from = below(rng, other.len() + 1);
            bytes.truncate(at);
            bytes.extend_from_slice(&other[from..]);
        }
        6 => {
            let value = INTEGERS[below(rng, INTEGERS.len())];
            let width = 1 << below(rng, 4);
            overwrite(rng, bytes, &value.to_le_bytes()[..width], width);
        }
        7 => {
            let value = FLOATS[below(rng, FLOATS.len())];
            if coin(rng) {
                overwrite(rng, bytes, &(value as f32).to_le_bytes(), 4);
            } else {
                overwrite(rng, bytes, &value.to_le_bytes(), 8);
            }
        }
        _ if !tokens.is_empty() => {
            let token = tokens[below(rng, tokens.len())];
            bytes.splice(at..at, token.bytes());
        }
        _ => bytes.push(rng.next_u64() as u8),
    }
}

/// Writes `word` at an offset aligned to `width` (often inside a 540-byte header), in
/// either byte order.
fn overwrite(rng: &mut SplitMix64, bytes: &mut [u8], word: &[u8], width: usize) {
    if bytes.len() < width {
        return;
    }
    let span = if coin(rng) {
        bytes.len().min(544)
    } else {
        bytes.len()
    };
    let at = ((rng.next_u64() as usize) % (span - width + 1)) / width * width;
    let mut word = word.to_vec();
    if coin(rng) {
        word.reverse();
    }
    bytes[at..at + width].copy_from_slice(&word);
}

/// Input `iteration` of `reader`: a corpus file with 1 to 4 mutations, and its name.
fn input(
    reader: &str,
    seed: u64,
    iteration: u64,
    files: &[(String, Vec<u8>)],
    tokens: &[&str],
) -> (String, Vec<u8>) {
    let reader_key = reader
        .bytes()
        .fold(0u64, |h, b| h.wrapping_mul(31).wrapping_add(b.into()));
    let mut rng =
        SplitMix64::new(seed ^ reader_key.rotate_left(17) ^ iteration.wrapping_mul(0x9e37_79b9));
    let (name, original) = &files[(rng.next_u64() % files.len() as u64) as usize];
    let others: Vec<Vec<u8>> = files.iter().map(|(_, b)| b.clone()).collect();
    let inside = gzip_name(name) && coin(&mut rng);
    let mut bytes = if inside {
        gunzip(original)
    } else {
        original.clone()
    };
    for _ in 0..1 + rng.next_u64() % 4 {
        mutate(&mut rng, &mut bytes, &others, tokens);
    }
    if inside {
        bytes = common::nifti::gzip(&bytes);
    }
    (name.clone(), bytes)
}

/// Feeds `reader`'s mutated inputs to `read` for its share of the time budget; a panic
/// fails the test naming the seed, the iteration and the saved input.
fn fuzz(reader: &str, tokens: &[&str], read: impl Fn(&str, &[u8])) {
    let seconds = env_number("GLYPHCAST_FUZZ_SECONDS", 60) as f64 / f64::from(READERS);
    let seed = env_number("GLYPHCAST_FUZZ_SEED", 1);
    let files = corpus(reader);
    // The corpus itself first, unmutated.
    for (name, bytes) in &files {
        read(name, bytes);
    }
    let started = Instant::now();
    let budget = Duration::from_secs_f64(seconds);
    let mut iteration = 0u64;
    while started.elapsed() < budget {
        let (name, bytes) = input(reader, seed, iteration, &files, tokens);
        if catch_unwind(AssertUnwindSafe(|| read(&name, &bytes))).is_err() {
            let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("fuzz-failures");
            std::fs::create_dir_all(&dir).expect("failure folder");
            let saved = dir.join(format!("{reader}-{seed}-{iteration}-{name}"));
            std::fs::write(&saved, &bytes).expect("saving the input");
            panic!(
                "{reader}: panic on input {iteration} of GLYPHCAST_FUZZ_SEED={seed} (from \
                 {name}), saved as {}",
                saved.display()
            );
        }
        iteration += 1;
    }
    eprintln!("{reader}: {iteration} inputs in {seconds} s, no panic");
}

/// A scratch folder per reader (the readers run in parallel).
fn scratch(reader: &str) -> PathBuf {
    let dir = common::output_dir().join("fuzz").join(reader);
    std::fs::create_dir_all(&dir).expect("scratch folder");
    dir
}

#[test]
fn fuzz_nifti() {
    fuzz("nifti", &[], |name, bytes| {
        let _ = read_nifti_bytes(bytes, name);
    });
}

#[test]
fn fuzz_mif() {
    let dir = scratch("mif");
    let tokens = [
        "\ndim: ",
        "\nvox: ",
        "\nlayout: ",
        "\ndatatype: ",
        "\nfile: . ",
        "\ntransform: ",
        "\nscaling: ",
        "\ndw_scheme: ",
        "END\n",
        "-0,",
        "+3,",
        "99999999999",
        "nan",
        ",",
        "Bit",
        "CFloat32",
        "Int16BE",
        "1e308",
    ];
    fuzz("mif", &tokens, |name, bytes| {
        let path = dir.join(name);
        std::fs::write(&path, bytes).expect("writing");
        let _ = read_mif(&path);
    });
}

#[test]
fn fuzz_scene() {
    let dir = scratch("scene");
    let tokens = [
        "{",
        "}",
        "[",
        "]",
        ",",
        ":",
        "\"",
        "null",
        "true",
        "-1",
        "1e400",
        "0.0",
        "65",
        "\"kind\"",
        "\"order\"",
        "\"coeffs\"",
        "\"scale\"",
        "\"camera\"",
        "\"width\"",
        "\"sh\"",
        "\"tensor\"",
        "\"basis\"",
        "\u{feff}",
        "\\u0000",
    ];
    fuzz("scene", &tokens, |name, bytes| {
        let path = dir.join(name);
        std::fs::write(&path, bytes).expect("writing");
        let _ = Scene::load(&path);
    });
}

#[test]
fn fuzz_stiffness() {
    let tokens = [
        "{",
        "}",
        "[",
        "]",
        ",",
        "#",
        "\n",
        " ",
        "nan",
        "inf",
        "-0",
        "1e309",
        "\"voigt\"",
        "\"shear_order\"",
        "\"23,13,12\"",
        "\"12,13,23\"",
    ];
    fuzz("stiffness", &tokens, |name, bytes| {
        let text = String::from_utf8_lossy(bytes);
        let _ = VoigtStiffness::from_text(&text, name, None);
    });
}

#[test]
fn fuzz_gradients() {
    let dir = scratch("gradients");
    let files = corpus("gradients");
    let tokens = [
        "nan", "inf", "-1", "0", "1e309", "\n", "\t", ",", " ", "#", "3000",
    ];
    let partner = |name: &str| -> (PathBuf, PathBuf) {
        let (bval, bvec) = (dir.join("in.bval"), dir.join("in.bvec"));
        let other = if name.ends_with(".bval") {
            ".bvec"
        } else {
            ".bval"
        };
        let (_, original) = files
            .iter()
            .find(|(n, _)| n.ends_with(other))
            .expect("a bval and a bvec in the corpus");
        let other_path = if other == ".bval" { &bval } else { &bvec };
        std::fs::write(other_path, original).expect("writing");
        (bval, bvec)
    };
    fuzz("gradients", &tokens, |name, bytes| {
        let (bval, bvec) = partner(name);
        let mine: &Path = if name.ends_with(".bval") {
            &bval
        } else {
            &bvec
        };
        std::fs::write(mine, bytes).expect("writing");
        let _ = GradientTable::read(&bval, &bvec, 65, "dwi.nii");
    });
}

/// The harness itself: a reader that panics on any input not in its corpus must fail
/// the run with the harness's message.
#[test]
#[should_panic(expected = "stiffness: panic on input")]
fn a_panicking_reader_fails_the_run() {
    let originals: Vec<Vec<u8>> = corpus("stiffness").into_iter().map(|(_, b)| b).collect();
    fuzz("stiffness", &[], |_, bytes| {
        assert!(originals.iter().any(|o| o == bytes), "a mutated input");
    });
}

/// Rewrites the NIfTI and MRtrix corpus with our writers from DIPY's func_coef (SH,
/// 2x3x4x45) and a corner of small_64D (DWI); the scene, stiffness and gradient corpus
/// are copies of tests/scenes, tests/stiffness.rs's copper and DIPY's small_64D tables.
#[test]
#[ignore]
fn write_corpus() {
    let data = |name: &str| {
        PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
            .join("tests/data/dipy")
            .join(name)
    };
    let coef = glyphcast_dmri::io::nifti::read_nifti(&data("func_coef.nii.gz")).unwrap();
    let dwi = glyphcast_dmri::io::nifti::read_nifti(&data("small_64D.nii")).unwrap();
    let corner = dwi
        .data
        .slice(ndarray::s![..2, ..2, ..2, ..])
        .to_owned()
        .into_dyn();
    let nifti = corpus_dir("nifti");
    std::fs::create_dir_all(&nifti).unwrap();
    let write = |name: &str, bytes: Vec<u8>| std::fs::write(nifti.join(name), bytes).unwrap();
    write(
        "func_coef.nii",
        nifti1_bytes(&coef.header, coef.data.view(), false, "").unwrap(),
    );
    write(
        "dwi_corner.nii.gz",
        nifti1_bytes(&dwi.header, corner.view(), true, "").unwrap(),
    );
    write(
        "func_coef_v2be.nii",
        common::nifti::nifti2_bytes(&coef.header, &coef.data, true),
    );
    let mif = corpus_dir("mif");
    std::fs::create_dir_all(&mif).unwrap();
    for (name, image) in [
        ("func_coef.mif", &coef.data),
        ("dwi_corner.mif.gz", &corner),
    ] {
        let keys = [("comments", "fuzz corpus".to_string())];
        let request = MifWrite {
            data: image,
            voxel_to_world: &coef.voxel_to_world,
            keys: &keys,
        };
        write_mif(&mif.join(name), &request).unwrap();
    }
}
