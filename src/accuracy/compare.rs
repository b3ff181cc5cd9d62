//! Comparing a rendered depth map with the float64 reference: holes (reference hits, the
//! render misses), false hits (the reverse), and depth errors, all counted away from a
//! one-pixel band around the reference's silhouettes, where a pixel-centre ray grazes the
//! surface and either answer is defensible.

/// The outcome of one comparison. Errors are in units of `scale` (the glyph scale).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DepthComparison {
    /// Pixels in the image.
    pub pixels: usize,
    /// Pixels the reference covers, outside the silhouette band.
    pub covered: usize,
    /// Pixels the reference hits and the render misses, outside the band.
    pub holes: usize,
    /// Pixels the render hits and the reference misses, outside the band.
    pub false_hits: usize,
    /// Pixels in the silhouette band (not judged).
    pub band: usize,
    /// Median |rendered - reference| ray distance over pixels both hit.
    pub median_error: f64,
    /// 99th percentile of the same errors.
    pub p99_error: f64,
    /// Largest of the same errors (0 when no pixel is hit by both).
    pub max_error: f64,
}

/// Pixels whose reference hit status differs from one of their 8 neighbours.
pub fn silhouette_band(reference: &[f64], width: usize, height: usize) -> Vec<bool> {
    let hit = |x: usize, y: usize| !reference[y * width + x].is_nan();
    let mut band = vec![false; reference.len()];
    for y in 0..height {
        for x in 0..width {
            let h = hit(x, y);
            let neighbours = (y.saturating_sub(1)..=(y + 1).min(height - 1)).flat_map(|ny| {
                (x.saturating_sub(1)..=(x + 1).min(width - 1)).map(move |nx| (nx, ny))
            });
            band[y * width + x] = neighbours.into_iter().any(|(nx, ny)| hit(nx, ny) != h);
        }
    }
    band
}

fn percentile(sorted: &[f64], p: f64) -> f64 {
    if sorted.is_empty() {
        return 0.0;
    }
    let i = ((sorted.len() - 1) as f64 * p).round() as usize;
    sorted[i.min(sorted.len() - 1)]
}

/// Compares `rendered` (NaN = miss) with `reference` (NaN = miss), both row-major.
pub fn compare_depth(
    rendered: &[f32],
    reference: &[f64],
    width: usize,
    height: usize,
    scale: f64,
) -> DepthComparison {
    let band = silhouette_band(reference, width, height);
    let mut c = DepthComparison {
        pixels: width * height,
        ..Default::default()
    };
    let mut errors = Vec::new();
    for (i, (&r, &e)) in rendered.iter().zip(reference).enumerate() {
        if band[i] {
            c.band += 1;
            continue;
        }
        match (r.is_nan(), e.is_nan()) {
            (true, false) => c.holes += 1,
            (false, true) => c.false_hits += 1,
            (false, false) => errors.push((r as f64 - e).abs() / scale),
            (true, true) => {}
        }
        if !e.is_nan() {
            c.covered += 1;
        }
    }
    errors.sort_by(f64::total_cmp);
    c.median_error = percentile(&errors, 0.5);
    c.p99_error = percentile(&errors, 0.99);
    c.max_error = errors.last().copied().unwrap_or(0.0);
    c
}

impl std::fmt::Display for DepthComparison {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "covered {} px, holes {}, false hits {}, band {} px, depth error median {:.2e}, p99 {:.2e}, max {:.2e}",
            self.covered,
            self.holes,
            self.false_hits,
            self.band,
            self.median_error,
            self.p99_error,
            self.max_error
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn band_surrounds_the_silhouette_and_counts_are_exact() {
        // A 6x6 reference with a 2x2 covered square; the render misses one covered pixel
        // inside and adds one hit far away.
        let (w, h) = (6, 6);
        let mut reference = vec![f64::NAN; w * h];
        for y in 2..4 {
            for x in 2..4 {
                reference[y * w + x] = 1.0;
            }
        }
        let band = silhouette_band(&reference, w, h);
        // Every covered pixel of a 2x2 square touches a miss, and so does the ring around it.
        assert_eq!(band.iter().filter(|b| **b).count(), 16);
        assert!(!band[0]);
        let mut rendered: Vec<f32> = reference.iter().map(|&d| d as f32).collect();
        rendered[0] = 2.0; // a false hit outside the band
        let c = compare_depth(&rendered, &reference, w, h, 1.0);
        assert_eq!((c.holes, c.false_hits, c.band), (0, 1, 16));
    }

    #[test]
    fn holes_and_errors_inside_a_large_region() {
        let (w, h) = (10, 10);
        let reference = vec![5.0f64; w * h];
        let mut rendered = vec![5.001f32; w * h];
        rendered[55] = f32::NAN;
        let c = compare_depth(&rendered, &reference, w, h, 0.5);
        assert_eq!(c.holes, 1);
        assert_eq!(c.false_hits, 0);
        assert!((c.median_error - 0.002).abs() < 1e-5, "{c}");
    }
}
