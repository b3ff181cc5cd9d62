//! `glyphcast stiffness --summary`, `--euler`, `--rotation` and `--allow-unstable`, run
//! as a user runs them, held to a float64 reference written here from the definitions
//! alone: the compliance S = C^-1 inverted by nalgebra, the fourth-order compliance
//! s_ijkl from S with the Voigt factors (1, 1/2 or 1/4), Young's modulus 1/E(u) =
//! s_ijkl u_i u_j u_k u_l and linear compressibility beta(u) = s_ijkk u_i u_j, their
//! extremes found by sampling the sphere densely and refining by shrinking steps.
// The loops spell out index notation (s_ijkl u_i u_j u_k u_l), as the definitions do.
#![allow(clippy::needless_range_loop)]
use crate::common;
use common::{glyphcast, text};
use nalgebra::Matrix6;
use serde_json::Value;
use std::path::{Path, PathBuf};

fn fresh_dir(name: &str) -> PathBuf {
    common::fresh_dir(&format!("elastic/{name}"))
}

type Voigt = [[f64; 6]; 6];

/// Sapphire-like trigonal (class -3m) constants in GPa: C11, C33, C44, C12, C13, C14.
fn trigonal() -> Voigt {
    let (c11, c33, c44, c12, c13, c14) = (497.0, 501.0, 147.0, 163.0, 116.0, -22.0);
    let c66 = (c11 - c12) / 2.0;
    [
        [c11, c12, c13, c14, 0.0, 0.0],
        [c12, c11, c13, -c14, 0.0, 0.0],
        [c13, c13, c33, 0.0, 0.0, 0.0],
        [c14, -c14, 0.0, c44, 0.0, 0.0],
        [0.0, 0.0, 0.0, 0.0, c44, c14],
        [0.0, 0.0, 0.0, 0.0, c14, c66],
    ]
}

/// A tetragonal crystal with a negative Poisson's ratio in some directions (alpha
/// cristobalite's constants, GPa).
fn auxetic_tetragonal() -> Voigt {
    let (c11, c33, c44, c66, c12, c13) = (59.4, 42.4, 67.2, 25.7, 3.8, -4.4);
    [
        [c11, c12, c13, 0.0, 0.0, 0.0],
        [c12, c11, c13, 0.0, 0.0, 0.0],
        [c13, c13, c33, 0.0, 0.0, 0.0],
        [0.0, 0.0, 0.0, c44, 0.0, 0.0],
        [0.0, 0.0, 0.0, 0.0, c44, 0.0],
        [0.0, 0.0, 0.0, 0.0, 0.0, c66],
    ]
}

/// Nickel (cubic), GPa.
fn cubic() -> Voigt {
    let (c11, c12, c44) = (246.5, 147.3, 124.7);
    let mut c = [[0.0; 6]; 6];
    for i in 0..3 {
        for j in 0..3 {
            c[i][j] = if i == j { c11 } else { c12 };
        }
        c[3 + i][3 + i] = c44;
    }
    c
}

fn write_matrix(path: &Path, c: &Voigt) {
    let rows: Vec<String> = c
        .iter()
        .map(|row| {
            row.iter()
                .map(|v| format!("{v}"))
                .collect::<Vec<_>>()
                .join(" ")
        })
        .collect();
    std::fs::write(path, rows.join("\n") + "\n").unwrap();
}

/// The fourth-order compliance s_ijkl of a Voigt stiffness matrix.
fn compliance_tensor(c: &Voigt) -> [[[[f64; 3]; 3]; 3]; 3] {
    let s = Matrix6::from_fn(|i, j| c[i][j])
        .try_inverse()
        .expect("an invertible matrix");
    let voigt = |i: usize, j: usize| match (i, j) {
        (0, 0) => 0,
        (1, 1) => 1,
        (2, 2) => 2,
        (1, 2) | (2, 1) => 3,
        (0, 2) | (2, 0) => 4,
        _ => 5,
    };
    let mut t = [[[[0.0; 3]; 3]; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            for k in 0..3 {
                for l in 0..3 {
                    let (m, n) = (voigt(i, j), voigt(k, l));
                    let factor = match (m >= 3, n >= 3) {
                        (false, false) => 1.0,
                        (true, true) => 0.25,
                        _ => 0.5,
                    };
                    t[i][j][k][l] = factor * s[(m, n)];
                }
            }
        }
    }
    t
}

/// Young's modulus and linear compressibility along unit u, from s_ijkl.
fn young(s: &[[[[f64; 3]; 3]; 3]; 3], u: [f64; 3]) -> f64 {
    let mut q = 0.0;
    for i in 0..3 {
        for j in 0..3 {
            for k in 0..3 {
                for l in 0..3 {
                    q += s[i][j][k][l] * u[i] * u[j] * u[k] * u[l];
                }
            }
        }
    }
    1.0 / q
}

fn compressibility(s: &[[[[f64; 3]; 3]; 3]; 3], u: [f64; 3]) -> f64 {
    let mut b = 0.0;
    for i in 0..3 {
        for j in 0..3 {
            for k in 0..3 {
                b += s[i][j][k][k] * u[i] * u[j];
            }
        }
    }
    b
}

type Compliance = [[[[f64; 3]; 3]; 3]; 3];

/// The extremes over unit v ⊥ u of vᵀ A v for a symmetric 3x3 A: the eigenvalues of
/// its restriction to the plane ⊥ unit u, in closed form (smaller, larger).
fn plane_extremes(a: [[f64; 3]; 3], u: [f64; 3]) -> (f64, f64) {
    let helper = if u[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let along = helper[0] * u[0] + helper[1] * u[1] + helper[2] * u[2];
    let e1: Vec<f64> = (0..3).map(|i| helper[i] - along * u[i]).collect();
    let norm = e1.iter().map(|x| x * x).sum::<f64>().sqrt();
    let e1: [f64; 3] = std::array::from_fn(|i| e1[i] / norm);
    let e2 = [
        u[1] * e1[2] - u[2] * e1[1],
        u[2] * e1[0] - u[0] * e1[2],
        u[0] * e1[1] - u[1] * e1[0],
    ];
    let form = |x: [f64; 3], y: [f64; 3]| {
        let mut sum = 0.0;
        for i in 0..3 {
            for j in 0..3 {
                sum += x[i] * a[i][j] * y[j];
            }
        }
        sum
    };
    let (p, q, r) = (form(e1, e1), form(e1, e2), form(e2, e2));
    let mean = (p + r) / 2.0;
    let radius = (((p - r) / 2.0).powi(2) + q * q).sqrt();
    (mean - radius, mean + radius)
}

/// The smallest and largest shear modulus over the shear directions v ⊥ unit u:
/// 1/G = 4 s_ijkl u_i v_j u_k v_l.
fn shear_range(s: &Compliance, u: [f64; 3]) -> (f64, f64) {
    let mut a = [[0.0; 3]; 3];
    for j in 0..3 {
        for l in 0..3 {
            for i in 0..3 {
                for k in 0..3 {
                    a[j][l] += 4.0 * s[i][j][k][l] * u[i] * u[k];
                }
            }
        }
    }
    let (lo, hi) = plane_extremes(a, u);
    (1.0 / hi, 1.0 / lo)
}

/// The smallest and largest Poisson's ratio over v ⊥ unit u:
/// ν = −s_ijkl u_i u_j v_k v_l / s_ijkl u_i u_j u_k u_l.
fn poisson_range(s: &Compliance, u: [f64; 3]) -> (f64, f64) {
    let mut a = [[0.0; 3]; 3];
    for k in 0..3 {
        for l in 0..3 {
            for i in 0..3 {
                for j in 0..3 {
                    a[k][l] += s[i][j][k][l] * u[i] * u[j];
                }
            }
        }
    }
    let q = 1.0 / young(s, u);
    let (lo, hi) = plane_extremes(a, u);
    (-hi / q, -lo / q)
}

/// s'_ijkl = g_mi g_nj g_ok g_pl s_mnop: the sample-frame tensor of Bunge's g (sample to
/// crystal).
fn rotated(s: &Compliance, g: [[f64; 3]; 3]) -> Compliance {
    let mut t = [[[[0.0; 3]; 3]; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            for k in 0..3 {
                for l in 0..3 {
                    for m in 0..3 {
                        for n in 0..3 {
                            for o in 0..3 {
                                for p in 0..3 {
                                    t[i][j][k][l] +=
                                        g[m][i] * g[n][j] * g[o][k] * g[p][l] * s[m][n][o][p];
                                }
                            }
                        }
                    }
                }
            }
        }
    }
    t
}

fn unit(theta: f64, phi: f64) -> [f64; 3] {
    [
        theta.sin() * phi.cos(),
        theta.sin() * phi.sin(),
        theta.cos(),
    ]
}

/// The largest value of `f` over the sphere: the best of a dense grid, then refined by
/// steps in (theta, phi) that shrink when no neighbour is better.
fn sphere_max(f: impl Fn([f64; 3]) -> f64) -> f64 {
    let n = 200;
    let mut best = (f64::NEG_INFINITY, 0.0, 0.0);
    let mut seeds = Vec::new();
    for a in 0..=n {
        for b in 0..2 * n {
            let (theta, phi) = (
                std::f64::consts::PI * a as f64 / n as f64,
                std::f64::consts::PI * b as f64 / n as f64,
            );
            seeds.push((f(unit(theta, phi)), theta, phi));
        }
    }
    seeds.sort_by(|x, y| y.0.total_cmp(&x.0));
    for &(mut value, mut theta, mut phi) in seeds.iter().take(24) {
        let mut step = std::f64::consts::PI / n as f64;
        while step > 1e-10 {
            let mut moved = false;
            for (dt, dp) in [(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0)] {
                let (t, p) = (theta + dt * step, phi + dp * step);
                let v = f(unit(t, p));
                if v > value {
                    (value, theta, phi, moved) = (v, t, p, true);
                }
            }
            if !moved {
                step /= 2.0;
            }
        }
        if value > best.0 {
            best = (value, theta, phi);
        }
    }
    best.0
}

/// `stiffness --summary` of `c`: its JSON.
fn summary(dir: &Path, name: &str, c: &Voigt, extra: &[&str]) -> Value {
    let input = dir.join(format!("{name}.txt"));
    write_matrix(&input, c);
    let out_path = dir.join(format!("{name}-summary.json"));
    let mut args = vec!["stiffness", text(&input), "--summary", text(&out_path)];
    args.extend(extra);
    let out = glyphcast(&args);
    assert!(
        out.status.success(),
        "{name}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("oung"),
        "{name}: the table is printed: {stdout}"
    );
    serde_json::from_str(&std::fs::read_to_string(&out_path).unwrap()).unwrap()
}

fn number(v: &Value, path: &[&str]) -> f64 {
    let mut v = v;
    for key in path {
        v = &v[key];
    }
    v.as_f64().unwrap_or_else(|| panic!("{path:?} is a number"))
}

fn direction(v: &Value, key: &str) -> [f64; 3] {
    let d: Vec<f64> = v["young"][key]
        .as_array()
        .unwrap_or_else(|| panic!("young.{key}"))
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    let norm = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    assert!((norm - 1.0).abs() < 1e-6, "{key} is a unit vector");
    [d[0], d[1], d[2]]
}

fn close(a: f64, b: f64, tolerance: f64) -> bool {
    (a - b).abs() <= tolerance * b.abs().max(1e-12)
}

/// The extremes of E and beta the command reports are the global ones of the
/// reference, to 1e-6 relative, those of G and ν (over pairs u, v ⊥ u) too, and E's
/// reported directions give those values.
fn holds_to_reference(name: &str, s: &Compliance, reported: &Value) {
    let s = *s;
    let e_max = sphere_max(|u| young(&s, u));
    let e_min = -sphere_max(|u| -young(&s, u));
    let b_max = sphere_max(|u| compressibility(&s, u));
    let b_min = -sphere_max(|u| -compressibility(&s, u));
    for (key, got, want) in [
        ("young.max", number(reported, &["young", "max"]), e_max),
        ("young.min", number(reported, &["young", "min"]), e_min),
        (
            "linear_compressibility.max",
            number(reported, &["linear_compressibility", "max"]),
            b_max,
        ),
        (
            "linear_compressibility.min",
            number(reported, &["linear_compressibility", "min"]),
            b_min,
        ),
    ] {
        assert!(close(got, want, 1e-6), "{name} {key}: {got} against {want}");
    }
    let g_max = sphere_max(|u| shear_range(&s, u).1);
    let g_min = -sphere_max(|u| -shear_range(&s, u).0);
    let nu_max = sphere_max(|u| poisson_range(&s, u).1);
    let nu_min = -sphere_max(|u| -poisson_range(&s, u).0);
    for (key, got, want) in [
        ("shear.max", number(reported, &["shear", "max"]), g_max),
        ("shear.min", number(reported, &["shear", "min"]), g_min),
        ("poisson.max", number(reported, &["poisson", "max"]), nu_max),
        ("poisson.min", number(reported, &["poisson", "min"]), nu_min),
    ] {
        eprintln!("{name} {key}: {got} against {want}");
        assert!(close(got, want, 1e-6), "{name} {key}: {got} against {want}");
    }
    for (key, value) in [("max_direction", e_max), ("min_direction", e_min)] {
        let at = young(&s, direction(reported, key));
        assert!(
            close(at, value, 1e-6),
            "{name} E({key}) = {at}, not {value}"
        );
    }
}

#[test]
fn summary_extremes_are_the_global_ones() {
    let dir = fresh_dir("summary");
    for (name, c) in [("trigonal", trigonal()), ("auxetic", auxetic_tetragonal())] {
        let reported = summary(&dir, name, &c, &[]);
        holds_to_reference(name, &compliance_tensor(&c), &reported);
    }
    // A cubic crystal turned by Bunge angles: the reference turns its compliance tensor.
    let turned = summary(&dir, "cubic-turned", &cubic(), &["--euler", "30,40,50"]);
    let s = rotated(&compliance_tensor(&cubic()), bunge(30.0, 40.0, 50.0));
    holds_to_reference("cubic-turned", &s, &turned);
    // The auxetic crystal's negative Poisson's ratio is reported, and the averages of a
    // cubic crystal are the closed forms.
    let auxetic = summary(&dir, "auxetic-again", &auxetic_tetragonal(), &[]);
    assert!(number(&auxetic, &["poisson", "min"]) < -0.3, "{auxetic}");
    let (c11, c12, c44) = (246.5, 147.3, 124.7);
    let nickel = summary(&dir, "nickel", &cubic(), &[]);
    let bulk = (c11 + 2.0 * c12) / 3.0;
    let shear_voigt = (c11 - c12 + 3.0 * c44) / 5.0;
    let shear_reuss = 5.0 * (c11 - c12) * c44 / (4.0 * c44 + 3.0 * (c11 - c12));
    for (key, want) in [
        (&["bulk", "voigt"], bulk),
        (&["bulk", "reuss"], bulk),
        (&["shear_average", "voigt"], shear_voigt),
        (&["shear_average", "reuss"], shear_reuss),
        (
            &["shear_average", "hill"],
            (shear_voigt + shear_reuss) / 2.0,
        ),
    ] {
        let got = number(&nickel, key);
        assert!(close(got, want, 1e-9), "{key:?}: {got} against {want}");
    }
}

/// Bunge's g = Rz(phi2) Rx(Phi) Rz(phi1) with passive rotations, written out.
fn bunge(phi1: f64, phi: f64, phi2: f64) -> [[f64; 3]; 3] {
    let rz = |a: f64| {
        let (s, c) = a.to_radians().sin_cos();
        [[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]]
    };
    let (s, c) = phi.to_radians().sin_cos();
    let rx = [[1.0, 0.0, 0.0], [0.0, c, s], [0.0, -s, c]];
    let mul = |a: [[f64; 3]; 3], b: [[f64; 3]; 3]| {
        let mut m = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                m[i][j] = (0..3).map(|k| a[i][k] * b[k][j]).sum();
            }
        }
        m
    };
    mul(mul(rz(phi2), rx), rz(phi1))
}

/// A cubic crystal turned by Bunge angles: E's extremes do not change, and the stiffest
/// sample direction is a crystal <111> (nickel is stiffest along the body diagonals),
/// mapped there by g as the definition says; `--rotation` with the same g reports the
/// same numbers.
#[test]
fn bunge_angles_turn_the_crystal_into_the_sample_frame() {
    let dir = fresh_dir("euler");
    let (phi1, phi, phi2) = (30.0, 40.0, 50.0);
    let plain = summary(&dir, "nickel", &cubic(), &[]);
    let turned = summary(&dir, "nickel-turned", &cubic(), &["--euler", "30,40,50"]);
    for key in ["max", "min"] {
        let (a, b) = (
            number(&plain, &["young", key]),
            number(&turned, &["young", key]),
        );
        assert!(close(a, b, 1e-6), "E {key}: {a} and {b}");
    }
    let g = bunge(phi1, phi, phi2);
    let d = direction(&turned, "max_direction");
    let crystal: Vec<f64> = (0..3)
        .map(|i| (0..3).map(|j| g[i][j] * d[j]).sum::<f64>().abs())
        .collect();
    for x in &crystal {
        assert!(
            (x - 1.0 / 3f64.sqrt()).abs() < 1e-4,
            "g d = {crystal:?} is no <111>"
        );
    }
    // The sample-frame direction itself is no <111> (the crystal was turned).
    assert!(
        d.iter().any(|x| (x.abs() - 1.0 / 3f64.sqrt()).abs() > 0.05),
        "{d:?}"
    );
    let matrix = dir.join("g.csv");
    let rows: Vec<String> = g
        .iter()
        .map(|r| format!("{:.17}, {:.17}, {:.17}", r[0], r[1], r[2]))
        .collect();
    std::fs::write(&matrix, rows.join("\n")).unwrap();
    let by_matrix = summary(
        &dir,
        "nickel-matrix",
        &cubic(),
        &["--rotation", text(&matrix)],
    );
    for key in ["max", "min"] {
        let (a, b) = (
            number(&turned, &["young", key]),
            number(&by_matrix, &["young", key]),
        );
        assert!(close(a, b, 1e-9), "E {key}: {a} and {b}");
    }
}

/// A matrix that is not positive definite is refused with exit 1, naming the file and
/// its smallest eigenvalue, and nothing is written; `--allow-unstable` draws it.
#[test]
fn an_unstable_matrix_is_refused_unless_allowed() {
    let dir = fresh_dir("unstable");
    let mut c = cubic();
    // C12 above C11: the shear C11 - C12 is negative, a mechanically unstable cubic.
    for i in 0..3 {
        for j in 0..3 {
            if i != j {
                c[i][j] = 260.0;
            }
        }
    }
    let input = dir.join("unstable.txt");
    write_matrix(&input, &c);
    let (scene, numbers) = (dir.join("scene.json"), dir.join("summary.json"));
    let args = [
        "stiffness",
        text(&input),
        "-o",
        text(&scene),
        "--summary",
        text(&numbers),
    ];
    let out = glyphcast(&args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("unstable.txt")
            && stderr.contains("not positive definite")
            && stderr.contains("smallest eigenvalue -1.35"),
        "{stderr}"
    );
    assert!(!scene.exists() && !numbers.exists(), "no partial output");
    let mut allowed = args.to_vec();
    allowed.push("--allow-unstable");
    let out = glyphcast(&allowed);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(scene.exists() && numbers.exists());
}

/// Files as materials scientists keep them: ELATE's whitespace text, CSV and JSON with
/// its units (the summary keeps them); several files draw a row of glyphs on one scale.
#[test]
fn example_materials_make_one_scene_on_one_scale() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let examples = root.join("examples/stiffness");
    let dir = fresh_dir("row");
    let (scene_path, numbers) = (dir.join("row.json"), dir.join("summary.json"));
    let files = ["copper.txt", "quartz.csv", "cristobalite.json"].map(|f| examples.join(f));
    let mut args = vec!["stiffness"];
    args.extend(files.iter().map(|f| text(f)));
    args.extend(["-o", text(&scene_path), "--summary", text(&numbers)]);
    let out = glyphcast(&args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let scene = glyphcast::scene::Scene::load(&scene_path).expect("the scene loads");
    let set = &scene.glyph_sets[0];
    assert_eq!(set.centers.len(), 3);
    assert!(set.scales.iter().all(|&s| s == set.scales[0]), "one scale");
    assert!(set.centers[0].x < set.centers[1].x && set.centers[1].x < set.centers[2].x);
    let all: Value = serde_json::from_str(&std::fs::read_to_string(&numbers).unwrap()).unwrap();
    let all = all.as_array().expect("one summary a material");
    assert_eq!(all.len(), 3);
    assert_eq!(all[2]["units"], "GPa", "cristobalite.json states its units");
    // Copper's Young's modulus along <100> is 1/S11 (the closed form of a cubic).
    let (c11, c12) = (168.4, 121.4);
    let s11 = (c11 + c12) / ((c11 - c12) * (c11 + 2.0 * c12));
    let got = number(&all[0], &["young", "min"]);
    assert!(close(got, 1.0 / s11, 1e-9), "copper E min {got}");
}
