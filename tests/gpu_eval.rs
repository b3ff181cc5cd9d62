//! The generated GLSL glyph functions (every variant build.rs compiles from src/catalog.rs) against the
//! float64 reference at thousands of random points.
use crate::common;
use glam::DVec3;
use glyphcast::glyph::monomials::monomials;
use glyphcast::glyph::polynomial::GlyphPolynomial;
use glyphcast::render::harness::eval::evaluate_on_gpu;
use glyphcast::render::shaders::layouts;

/// |grad| of sum_k |c_k| |x^a y^b z^c|: the scale of float32 rounding in the gradient.
fn abs_gradient_scale(poly: &GlyphPolynomial, q: DVec3) -> f64 {
    let q = q.abs();
    let pw = |v: f64, k: u32| if k == 0 { 1.0 } else { v.powi(k as i32) };
    let mut g = DVec3::ZERO;
    for (c, m) in poly.coeffs.iter().zip(monomials(poly.order)) {
        let c = c.abs();
        if m.a > 0 {
            g.x += c * m.a as f64 * pw(q.x, m.a - 1) * pw(q.y, m.b) * pw(q.z, m.c);
        }
        if m.b > 0 {
            g.y += c * m.b as f64 * pw(q.x, m.a) * pw(q.y, m.b - 1) * pw(q.z, m.c);
        }
        if m.c > 0 {
            g.z += c * m.c as f64 * pw(q.x, m.a) * pw(q.y, m.b) * pw(q.z, m.c - 1);
        }
    }
    g.length()
}

/// A small deterministic generator, so failures reproduce.
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

#[test]
fn generated_functions_match_float64_reference() {
    let gpu = common::gpu();
    let mut rng = Lcg(7);
    let mut checked = 0;
    for layout in layouts() {
        let n = layout.coefficient_count();
        let glyphs = 4;
        let tensors: Vec<Vec<f64>> = (0..glyphs)
            .map(|_| (0..n).map(|_| rng.next()).collect())
            .collect();
        let coeffs32: Vec<f32> = tensors.iter().flatten().map(|&c| c as f32).collect();
        let points: Vec<[f32; 4]> = (0..1024)
            .map(|i| {
                [
                    rng.next() as f32,
                    rng.next() as f32,
                    rng.next() as f32,
                    (i % glyphs) as f32,
                ]
            })
            .collect();
        let results = evaluate_on_gpu(&gpu, layout, &coeffs32, &points).expect("GPU evaluation");
        assert_eq!(results.len(), points.len());
        let polys: Vec<GlyphPolynomial> = tensors
            .iter()
            .map(|t| {
                // The GPU sees the float32-rounded coefficients; so does the reference.
                let rounded: Vec<f64> = t.iter().map(|&c| c as f32 as f64).collect();
                GlyphPolynomial::from_tensor(layout, &rounded).expect("tensor")
            })
            .collect();
        for (p, r) in points.iter().zip(&results) {
            let q = DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64);
            let poly = &polys[p[3] as usize];
            let (f, grad) = poly.eval_with_gradient(q);
            // Relative to the sum of |terms| at q: the scale float32 rounding works on.
            let scale = poly.abs_eval(q).max(1e-30);
            let err_f = (r[0] as f64 - f).abs() / scale;
            assert!(
                err_f < 1e-5,
                "{layout:?} at {q}: f gpu {} ref {f} (rel {err_f:.2e})",
                r[0]
            );
            let gscale = abs_gradient_scale(poly, q).max(1e-30);
            let err_g =
                (DVec3::new(r[1] as f64, r[2] as f64, r[3] as f64) - grad).length() / gscale;
            assert!(
                err_g < 1e-5,
                "{layout:?} at {q}: gradient gpu {:?} ref {grad} (rel {err_g:.2e})",
                &r[1..]
            );
            checked += 1;
        }
    }
    assert!(
        checked >= 16 * 1024,
        "every variant was checked ({checked} points)"
    );
}
