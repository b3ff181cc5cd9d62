//! Multi-shell multi-tissue constrained spherical deconvolution (Jeurissen et al. 2014,
//! "Multi-tissue constrained spherical deconvolution for improved analysis of
//! multi-shell diffusion MRI data", NeuroImage 103): `glyphcast fit --odf msmt`.
//!
//! Each volume's signal is the sum over tissues of the tissue's ODF convolved with its
//! response at the volume's shell: S(g, b) = sum_lm c_l(b) f_lm Y_lm(g) for white matter
//! (c_l(b) = sqrt(4 pi/(2l+1)) r_l(b), Funk-Hecke, as in `csd`), plus r_0(b) f for grey
//! matter and for CSF, whose ODFs are band 0 (f is their l = 0 coefficient; sqrt(4 pi) f
//! is the tissue's signal fraction in units of its response). b=0 volumes are a shell of
//! their own, with only band 0 (they have no direction). In every voxel the unknowns
//! (the WM series and the two band-0 coefficients) minimise |X x - S|^2 over all volumes
//! subject to a non-negative WM fODF at [`CONSTRAINT_FREQUENCY`]'s geodesic hemisphere
//! (the fODF is antipodally symmetric) and GM, CSF >= 0: a convex QP, solved by
//! Clarabel's interior-point method (its default tolerances, 1e-8). The hard constraint
//! is what MRtrix's `dwi2fod msmt_csd` and DIPY's `MultiShellDeconvModel` impose (DIPY
//! on its 362-direction `default_sphere`, MRtrix on 300 directions); there is no weight
//! and no threshold as in single-shell CSD.
//!
//! The signal is deconvolved in signal units (the responses' units), scaled by the
//! voxel's mean b=0 signal while solving (the problem is homogeneous, so the scale
//! cancels exactly) to keep the solver's tolerances meaningful for any intensity.
//!
//! Shells ([`Shells`]): volumes with b <= [`B0_THRESHOLD`] are the b=0 shell; the other
//! b-values, sorted, start a new shell wherever one is more than [`SHELL_GAP`] above the
//! previous (MRtrix's default `BValueEpsilon`, 80 s/mm^2, with the same linkage rule);
//! a shell's b-value is the mean of its volumes'.
use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettings, DefaultSolver, IPSolver, NonnegativeConeT, SolverStatus};
use glam::DVec3;
use nalgebra::DMatrix;
use ndarray::{Array4, s};

use super::basis::{WORK_BASIS, basis_change};
use super::gradients::{B0_THRESHOLD, GradientTable};
use super::sphere::GeodesicSphere;
use super::{FitInputs, FitReport};
use glyphcast::error::Problem;
use glyphcast::glyph::sh::{sh_basis_values, sh_count, sh_orders};
use glyphcast::scene::ShBasis;
use glyphcast::{Error, Result};

/// b-values more than this apart (s/mm^2, after sorting) belong to different shells.
pub const SHELL_GAP: f64 = 80.0;

/// Frequency of the constraint sphere: 10 * 8^2 + 2 = 642 directions, whose hemisphere
/// holds 321 (about 8 degrees apart).
pub const CONSTRAINT_FREQUENCY: usize = 8;

/// The QP's duality gap at which a voxel is solved, absolute and relative (see
/// [`MsmtFitter::solver`]).
pub const OBJECTIVE_GAP: f64 = 1e-14;

/// The tissues, in the order of the unknowns after the WM series.
pub const TISSUES: [&str; 3] = ["WM", "GM", "CSF"];

/// The shells of a gradient table.
#[derive(Clone, Debug, PartialEq)]
pub struct Shells {
    /// Each shell's mean b-value, increasing; the b=0 shell first.
    pub bvals: Vec<f64>,
    /// Per volume, its shell's index.
    pub of_volume: Vec<usize>,
    /// Per shell, its volumes.
    pub counts: Vec<usize>,
}

impl Shells {
    /// Groups `bvals` (one per volume) into shells (see the module notes). The b=0 shell
    /// is always present, possibly empty, so that shell 0 means b = 0.
    pub fn group(bvals: &[f64]) -> Self {
        let mut order: Vec<usize> = (0..bvals.len())
            .filter(|&v| bvals[v] > B0_THRESHOLD)
            .collect();
        order.sort_by(|&a, &b| bvals[a].total_cmp(&bvals[b]));
        let mut of_volume = vec![0; bvals.len()];
        let mut members: Vec<Vec<usize>> = vec![
            (0..bvals.len())
                .filter(|&v| bvals[v] <= B0_THRESHOLD)
                .collect(),
        ];
        let mut previous = f64::NEG_INFINITY;
        for v in order {
            if bvals[v] - previous > SHELL_GAP {
                members.push(Vec::new());
            }
            previous = bvals[v];
            of_volume[v] = members.len() - 1;
            if let Some(last) = members.last_mut() {
                last.push(v);
            }
        }
        let mean =
            |m: &Vec<usize>| m.iter().map(|&v| bvals[v]).sum::<f64>() / m.len().max(1) as f64;
        Self {
            bvals: members
                .iter()
                .map(|m| if m.is_empty() { 0.0 } else { mean(m) })
                .collect(),
            counts: members.iter().map(Vec::len).collect(),
            of_volume,
        }
    }

    /// Number of shells, the b=0 shell included.
    pub fn len(&self) -> usize {
        self.bvals.len()
    }

    /// Whether there are no shells (never: the b=0 shell is always there).
    pub fn is_empty(&self) -> bool {
        self.bvals.is_empty()
    }

    /// The b-values as a list for messages: "0, 1000, 2000, 3000".
    pub fn list(&self) -> String {
        let b: Vec<String> = self.bvals.iter().map(|b| format!("{b:.0}")).collect();
        b.join(", ")
    }
}

/// Per-tissue responses, one row per shell (shell 0 = b=0): WM's zonal coefficients
/// r_0, r_2, ... (signal units, MRtrix's response format), GM's and CSF's r_0.
#[derive(Clone, Debug, PartialEq)]
pub struct TissueResponses {
    /// White matter: per shell, the zonal coefficients r_0, r_2, ... up to its band.
    pub wm: Vec<Vec<f64>>,
    /// Grey matter: per shell, r_0 (the isotropic response).
    pub gm: Vec<f64>,
    /// CSF: per shell, r_0.
    pub csf: Vec<f64>,
}

impl TissueResponses {
    /// The responses as MRtrix's text files would hold them: WM's rows, GM's, CSF's.
    pub fn to_texts(&self) -> [String; 3] {
        let rows = |rows: Vec<Vec<f64>>| {
            rows.iter()
                .map(|r| {
                    let r: Vec<String> = r.iter().map(|v| format!("{v}")).collect();
                    r.join(" ") + "\n"
                })
                .collect::<String>()
        };
        [
            rows(self.wm.clone()),
            rows(self.gm.iter().map(|&v| vec![v]).collect()),
            rows(self.csf.iter().map(|&v| vec![v]).collect()),
        ]
    }
}

/// What a multi-tissue fit is prepared from: the WM fODF's band and basis, the gradient
/// table with its shells, and one response row per shell.
#[derive(Clone, Copy, Debug)]
pub struct MsmtProblem<'a> {
    /// The WM fODF's highest band (even).
    pub band: u32,
    /// The basis the WM series is returned in, and whether it is its legacy variant.
    pub basis: (ShBasis, bool),
    /// Every volume's b-value and direction (`None` for b=0), in the DWI's order.
    pub gradients: &'a GradientTable,
    /// The volumes grouped by b-value ([`Shells::group`] of `gradients.bvals`).
    pub shells: &'a Shells,
    /// The tissues' responses, one row per shell of `shells`.
    pub responses: &'a TissueResponses,
}

/// The QP of one gradient table and set of responses, prepared once.
pub struct MsmtFitter {
    /// X: volumes x (WM coefficients in the work basis, GM, CSF).
    design: DMatrix<f64>,
    /// P = X^T X, upper triangle, for the solver.
    quadratic: CscMatrix<f64>,
    /// -C (C x >= 0 is the constraint), for the solver's A x + s = 0, s >= 0.
    constraint: CscMatrix<f64>,
    /// WM work basis to the requested basis.
    output: DMatrix<f64>,
    /// The volumes fitted (all, b=0 included) and the b=0 ones.
    volumes: Vec<usize>,
    b0: Vec<usize>,
    wm_count: usize,
}

/// One voxel's result: the WM series in the requested basis, GM's and CSF's band 0.
#[derive(Clone, Debug, PartialEq)]
pub struct TissueOdfs {
    /// The WM fODF's SH coefficients in the requested basis.
    pub wm: Vec<f64>,
    /// GM's band-0 coefficient (sqrt(4 pi) times it is GM's signal fraction in units of
    /// its response).
    pub gm: f64,
    /// CSF's band-0 coefficient, likewise.
    pub csf: f64,
}

impl MsmtFitter {
    /// The fit of `problem`, with the WM fODF constrained on the geodesic hemisphere of
    /// [`CONSTRAINT_FREQUENCY`].
    pub fn new(problem: &MsmtProblem) -> Result<Self> {
        Self::with_constraint(problem, &GeodesicSphere::hemisphere(CONSTRAINT_FREQUENCY))
    }

    /// [`MsmtFitter::new`] with the WM fODF constrained at `constraint` (unit vectors).
    pub fn with_constraint(problem: &MsmtProblem, constraint: &[DVec3]) -> Result<Self> {
        let MsmtProblem {
            band,
            basis,
            gradients,
            shells,
            responses,
        } = *problem;
        let (bvals, directions) = (&gradients.bvals, &gradients.directions);
        let k = sh_count(band);
        let n = k + 2;
        let volumes: Vec<usize> = (0..bvals.len()).collect();
        let b0: Vec<usize> = volumes
            .iter()
            .copied()
            .filter(|&v| directions[v].is_none())
            .collect();
        for (what, rows) in [
            (
                "white-matter response rows (one per shell)",
                responses.wm.len(),
            ),
            (
                "grey-matter response rows (one per shell)",
                responses.gm.len(),
            ),
            ("CSF response rows (one per shell)", responses.csf.len()),
        ] {
            if rows != shells.len() {
                return Err(Error::data(
                    what,
                    Problem::Count {
                        expected: shells.len(),
                        found: rows,
                    },
                ));
            }
        }
        let mut design = DMatrix::zeros(volumes.len(), n);
        for &v in &volumes {
            let shell = shells.of_volume[v];
            let wm = &responses.wm[shell];
            match directions[v] {
                // b=0 (or a shell without direction): band 0 only, Y_00 sqrt(4 pi) = 1.
                None => design[(v, 0)] = wm.first().copied().unwrap_or(0.0),
                Some(g) => {
                    let values = sh_basis_values(band, WORK_BASIS.0, WORK_BASIS.1, g);
                    for (j, ((l, _), y)) in sh_orders(band).zip(values).enumerate() {
                        let r = wm.get(l as usize / 2).copied().unwrap_or(0.0);
                        let factor =
                            (4.0 * std::f64::consts::PI / (2.0 * f64::from(l) + 1.0)).sqrt();
                        design[(v, j)] = factor * r * y;
                    }
                }
            }
            design[(v, k)] = responses.gm[shell];
            design[(v, k + 1)] = responses.csf[shell];
        }
        let normal = design.transpose() * &design;
        let mut upper = normal.clone();
        for j in 0..n {
            for i in j + 1..n {
                upper[(i, j)] = 0.0;
            }
        }
        let m = constraint.len() + 2;
        let mut negated = DMatrix::zeros(m, n);
        for (i, u) in constraint.iter().enumerate() {
            for (j, y) in sh_basis_values(band, WORK_BASIS.0, WORK_BASIS.1, *u)
                .into_iter()
                .enumerate()
            {
                negated[(i, j)] = -y;
            }
        }
        negated[(constraint.len(), k)] = -1.0;
        negated[(constraint.len() + 1, k + 1)] = -1.0;
        Ok(Self {
            design,
            quadratic: dense_csc(&upper),
            constraint: dense_csc(&negated),
            output: basis_change(band, basis)?,
            volumes,
            b0,
            wm_count: k,
        })
    }

    /// A solver for this QP, to be reused across voxels ([`MsmtFitter::fit`]).
    pub fn solver(&self) -> Result<DefaultSolver<f64>> {
        // The objective is half the squared residual of a signal scaled to S0 = 1: near 0
        // where the model fits, so Clarabel's default absolute gap (1e-8) would leave the
        // coefficients at about its square root; the gap is asked of the solver at
        // 1e-8 of that default instead.
        let settings = DefaultSettings {
            verbose: false,
            presolve_enable: false,
            tol_gap_abs: OBJECTIVE_GAP,
            tol_gap_rel: OBJECTIVE_GAP,
            ..DefaultSettings::default()
        };
        let zeros = vec![0.0; self.constraint.m];
        let q = vec![0.0; self.constraint.n];
        DefaultSolver::new(
            &self.quadratic,
            &q,
            &self.constraint,
            &zeros,
            &[NonnegativeConeT(self.constraint.m)],
            settings,
        )
        .map_err(|e| Error::Numerical {
            step: "multi-tissue CSD's QP",
            detail: e.to_string(),
        })
    }

    /// The tissue ODFs of one voxel's `series` (every volume, signal units) with
    /// `solver` (from [`MsmtFitter::solver`]); `None` when the solver does not converge.
    pub fn fit(&self, solver: &mut DefaultSolver<f64>, series: &[f64]) -> Option<TissueOdfs> {
        let s0 = self.b0.iter().map(|&v| series[v]).sum::<f64>() / self.b0.len().max(1) as f64;
        let scale = if s0 > 0.0 { s0 } else { 1.0 };
        let signal: Vec<f64> = self.volumes.iter().map(|&v| series[v] / scale).collect();
        let q: Vec<f64> = (self.design.tr_mul(&nalgebra::DVector::from_vec(signal)) * -1.0)
            .iter()
            .copied()
            .collect();
        if solver.update_q(&q).is_err() {
            *solver = self.solver().ok()?;
            solver.update_q(&q).ok()?;
        }
        solver.solve();
        if !matches!(
            solver.solution.status,
            SolverStatus::Solved | SolverStatus::AlmostSolved
        ) {
            return None;
        }
        let x = &solver.solution.x;
        let k = self.wm_count;
        let wm = &self.output * nalgebra::DVector::from_column_slice(&x[..k]);
        Some(TissueOdfs {
            wm: wm.iter().map(|v| v * scale).collect(),
            gm: x[k].max(0.0) * scale,
            csf: x[k + 1].max(0.0) * scale,
        })
    }
}

/// A dense matrix in the solver's compressed-column form, zeros kept, so that the
/// structure never changes between voxels.
fn dense_csc(matrix: &DMatrix<f64>) -> CscMatrix<f64> {
    let (m, n) = matrix.shape();
    let mut colptr = Vec::with_capacity(n + 1);
    let (mut rowval, mut nzval) = (Vec::new(), Vec::new());
    colptr.push(0);
    for j in 0..n {
        for i in 0..m {
            rowval.push(i);
            nzval.push(matrix[(i, j)]);
        }
        colptr.push(rowval.len());
    }
    CscMatrix::new(m, n, colptr, rowval, nzval)
}

/// The outputs of a multi-tissue fit: [x, y, z, coefficient] per tissue (WM: the series
/// in the requested basis; GM and CSF: one band-0 coefficient), and what became of the
/// voxels.
pub struct MsmtVolumes {
    /// The WM fODF, one SH series per voxel.
    pub wm: Array4<f64>,
    /// GM's band-0 coefficient, one per voxel.
    pub gm: Array4<f64>,
    /// CSF's band-0 coefficient, one per voxel.
    pub csf: Array4<f64>,
    /// Voxels fitted, floored and left out, by reason.
    pub report: FitReport,
    /// Voxels where the solver did not converge (left at 0).
    pub unsolved: usize,
}

/// Fits every voxel of `inputs` in the mask; `progress` hears of voxels done. Voxels
/// with a non-finite sample or S0 <= 0 are left at 0 and counted. Err when no voxel can be
/// fitted.
pub fn fit_msmt(
    inputs: &FitInputs,
    fitter: &MsmtFitter,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<MsmtVolumes> {
    let [nx, ny, nz] = inputs.dwi.spatial_shape();
    let k = fitter.wm_count;
    let voxels: Vec<[usize; 3]> = (0..nz)
        .flat_map(|z| (0..ny).flat_map(move |y| (0..nx).map(move |x| [x, y, z])))
        .filter(|&[x, y, z]| inputs.in_mask(x, y, z))
        .collect();
    let chunks: Vec<&[[usize; 3]]> = voxels.chunks(256).collect();
    let results = glyphcast::parallel::map_chunks(&chunks, "multi-tissue CSD", |chunk| {
        let mut solver = fitter.solver()?;
        let out: Vec<Outcome> = chunk
            .iter()
            .map(|&[x, y, z]| {
                let series: Vec<f64> = inputs.dwi.signal.slice(s![x, y, z, ..]).to_vec();
                fit_one(fitter, &mut solver, &series)
            })
            .collect();
        progress(chunk.len() as u64);
        Ok(out)
    })?;
    let mut wm = Array4::zeros((nx, ny, nz, k));
    let mut gm = Array4::zeros((nx, ny, nz, 1));
    let mut csf = Array4::zeros((nx, ny, nz, 1));
    let mut report = FitReport::default();
    let mut unsolved = 0;
    for (&[x, y, z], outcome) in voxels.iter().zip(results.into_iter().flatten()) {
        report.visited += 1;
        match outcome {
            Outcome::Fitted(odfs) => {
                for (o, v) in wm.slice_mut(s![x, y, z, ..]).iter_mut().zip(&odfs.wm) {
                    *o = *v;
                }
                gm[[x, y, z, 0]] = odfs.gm;
                csf[[x, y, z, 0]] = odfs.csf;
            }
            Outcome::NonFinite => report.non_finite += 1,
            Outcome::NegativeS0 => report.negative_s0 += 1,
            Outcome::ZeroS0 => report.zero_s0 += 1,
            Outcome::Unsolved => unsolved += 1,
        }
    }
    let culprit = match (&inputs.files.mask, report.visited) {
        (Some(mask), 0) => mask.display().to_string(),
        _ => inputs.files.dwi.display().to_string(),
    };
    report.check_any_fitted(&culprit)?;
    Ok(MsmtVolumes {
        wm,
        gm,
        csf,
        report,
        unsolved,
    })
}

enum Outcome {
    Fitted(TissueOdfs),
    NonFinite,
    NegativeS0,
    ZeroS0,
    Unsolved,
}

fn fit_one(fitter: &MsmtFitter, solver: &mut DefaultSolver<f64>, series: &[f64]) -> Outcome {
    if series.iter().any(|v| !v.is_finite()) {
        return Outcome::NonFinite;
    }
    let s0 = fitter.b0.iter().map(|&v| series[v]).sum::<f64>() / fitter.b0.len().max(1) as f64;
    if s0 < 0.0 {
        return Outcome::NegativeS0;
    }
    if s0 <= 0.0 {
        return Outcome::ZeroS0;
    }
    match fitter.fit(solver, series) {
        Some(odfs) => Outcome::Fitted(odfs),
        None => Outcome::Unsolved,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::response::Response;
    use glyphcast::glyph::sh::sh_eval;

    #[test]
    fn shells_are_grouped_by_gaps() {
        let shells = Shells::group(&[0.0, 0.0, 995.0, 1005.0, 2990.0, 1990.0, 2010.0, 3000.0]);
        assert_eq!(shells.counts, vec![2, 2, 2, 2]);
        assert_eq!(shells.of_volume, vec![0, 0, 1, 1, 3, 2, 2, 3]);
        assert!((shells.bvals[1] - 1000.0).abs() < 1e-9);
        assert_eq!(shells.list(), "0, 1000, 2000, 2995");
        // A gap above 80 s/mm^2 splits; a chain of small steps does not.
        assert_eq!(Shells::group(&[0.0, 700.0, 790.0]).len(), 3);
        assert_eq!(Shells::group(&[0.0, 700.0, 760.0, 820.0]).len(), 2);
    }

    /// A band-limited, non-negative WM fODF plus GM and CSF, made with the model itself:
    /// the QP must give it back (to the solver's tolerance).
    #[test]
    fn recovers_a_mixture_the_model_can_represent() {
        let sphere = GeodesicSphere::new(3);
        let hemi: Vec<DVec3> = sphere
            .vertices
            .iter()
            .copied()
            .filter(|v| v.z > 0.05)
            .collect();
        let mut bvals = vec![0.0, 0.0];
        let mut directions = vec![None, None];
        for b in [1000.0, 2000.0, 3000.0] {
            for d in &hemi {
                bvals.push(b);
                directions.push(Some(*d));
            }
        }
        let shells = Shells::group(&bvals);
        let wm: Vec<Vec<f64>> = shells
            .bvals
            .iter()
            .map(|&b| Response::from_tensor(1.7e-3, 0.3e-3, 1000.0, b, 8).zonal)
            .collect();
        let iso = |s0: f64, d: f64| -> Vec<f64> {
            shells
                .bvals
                .iter()
                .map(|&b| (4.0 * std::f64::consts::PI).sqrt() * s0 * (-b * d).exp())
                .collect()
        };
        let responses = TissueResponses {
            wm,
            gm: iso(1300.0, 0.8e-3),
            csf: iso(3000.0, 3e-3),
        };
        let basis = (ShBasis::Tournier07, false);
        let gradients = GradientTable { bvals, directions };
        let problem = MsmtProblem {
            band: 8,
            basis,
            gradients: &gradients,
            shells: &shells,
            responses: &responses,
        };
        let fitter = MsmtFitter::new(&problem).unwrap();
        // WM fODF: 0.6 (9/(4 pi)) (u.a)^8 + ..., as SH by a least-squares fit on a dense
        // sphere (exact: a degree-8 polynomial is of band 8).
        let (a, c) = (DVec3::new(1.0, 0.2, 0.1).normalize(), DVec3::Z);
        let dense = GeodesicSphere::new(10).vertices;
        let fodf = |u: DVec3| {
            9.0 / (4.0 * std::f64::consts::PI) * (0.4 * u.dot(a).powi(8) + 0.2 * u.dot(c).powi(8))
        };
        let rows: Vec<f64> = dense
            .iter()
            .flat_map(|u| sh_basis_values(8, WORK_BASIS.0, WORK_BASIS.1, *u))
            .collect();
        let b = DMatrix::from_row_slice(dense.len(), sh_count(8), &rows);
        let values = nalgebra::DVector::from_iterator(dense.len(), dense.iter().map(|u| fodf(*u)));
        let truth = b.clone().svd(true, true).solve(&values, 1e-12).unwrap();
        let mut x = truth.as_slice().to_vec();
        let (gm, csf) = (
            0.25 / (4.0 * std::f64::consts::PI).sqrt(),
            0.15 / (4.0 * std::f64::consts::PI).sqrt(),
        );
        x.extend([gm, csf]);
        let signal = &fitter.design * nalgebra::DVector::from_vec(x);
        let mut solver = fitter.solver().unwrap();
        let odfs = fitter.fit(&mut solver, signal.as_slice()).unwrap();
        assert!((odfs.gm - gm).abs() < 1e-6 * gm, "{} vs {gm}", odfs.gm);
        assert!((odfs.csf - csf).abs() < 1e-6 * gm, "{} vs {csf}", odfs.csf);
        // The amplitudes to 1e-4 of the peak: where the fODF nearly touches zero (broad
        // flanks of (u.a)^8) the interior point stops a little inside the constraints.
        for u in [a, c, DVec3::X, DVec3::new(0.3, -0.5, 0.8).normalize()] {
            let got = sh_eval(8, basis.0, basis.1, &odfs.wm, u);
            assert!(
                (got - fodf(u)).abs() < 1e-4 * fodf(a),
                "{u}: {got} vs {}",
                fodf(u)
            );
        }
        // The fit is homogeneous: twice the signal, twice every coefficient.
        let doubled: Vec<f64> = signal.iter().map(|v| 2.0 * v).collect();
        let twice = fitter.fit(&mut solver, &doubled).unwrap();
        assert!((twice.gm - 2.0 * odfs.gm).abs() < 1e-6 * gm);
    }
}
