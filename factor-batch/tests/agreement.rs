//! How batches are checked against the scalar kernel and dual numbers
//! ([`check`]), for the five document factors (`document_factors.rs`) and a
//! user's factor (`users_factor.rs`) at 10⁴ + 3 configurations each (the
//! plane's straddling both of its branch points,
//! `factor_testing::branch_points`), in every lane type, Jacobians and fused
//! normal equations alike.
//!
//! Tolerances, and why:
//!
//! - **the batch vs the kernel**: bit for bit. The scalar batch (`f64`) is
//!   the derive's `linearize_generated_into` one factor at a time; a lane
//!   batch is the kernel on the same lane type evaluated group by group
//!   here, without the batch's loop, dispatch or unchecked accesses.
//! - **lanes vs the scalar kernel** (`F64x4`, `F64x8` vs `f64`; `F32x8` vs
//!   `f32`): bit for bit for kernels built from `+ − × ÷ √` and `select_lt`
//!   (every lane is correctly rounded as the scalar is; Rust never contracts
//!   to FMA): the point, both line and the free-line kernels. The plane
//!   kernel's one `atan2` is within 2 ulp (`f64`) / 3 ulp (`f32`) of `std`'s,
//!   and the plane in lanes is, bit for bit, the scalar kernel with that
//!   `atan2` (`factor-lanes/tests/kernels.rs`); here the plane and the
//!   relative pose (`sin`, `cos`, `atan2`) in `f64` lanes are held to the
//!   same tolerance against dual numbers as the scalar kernel.
//! - **scalar kernel (and `f64` lanes) vs dual numbers**: both exact, so
//!   rounding only: `GENERATED_TOLERANCE` (1e-12, as [`compare`] measures:
//!   the residual relative to the inputs' scale, blocks relative Frobenius).
//! - **`F32x8` vs dual numbers**: [`F32_VS_DUAL`], the tolerance of the
//!   `f32` kernels in `slam-factors/tests/generated.rs`. The plane comes
//!   closest: just above its small-angle switch (`θ ≈ 2·10⁻³`) its Jacobian
//!   subtracts two nearly equal terms (`atan2(s, w)/s − w/(s² + w²)`, about
//!   5 digits lost), so there the `f32` kernel, scalar or in lanes, keeps
//!   two or three digits of those entries.
//! - **fused normal equations vs the Jacobian kernel's `J` and `r` combined
//!   by `nalgebra`**: the fused kernel computes `J` and `r` with the same
//!   instructions, so only the order of the sums differs: each entry within
//!   `(R + 2) ε` of the sum of the absolute values of its terms (the
//!   standard dot-product bound, `R` the residual length).
//! - **fused normal equations vs dual numbers**: `J` within `1e-12` relative
//!   of the dual `J` makes `Jᵢᵀ w Jⱼ` within `2·1e-12 + rounding` of
//!   `w ‖Jᵢ‖ ‖Jⱼ‖`; likewise the gradient relative to
//!   `w ‖Jᵢ‖ (‖r‖ + scale)` and the cost relative to `w ‖r‖ scale`:
//!   [`NORMAL_VS_DUAL`].
//!
//! The run prints the largest error seen per factor and comparison.

use factor_batch::{Columns, JacobianColumns, NormalColumns, Options, linearize, normal, pairs};
use factor_core::{DynLinearization, Factor, WithKernel};
use factor_lanes::{Array, F32x8, F64x4, F64x8, Kernel, Lanes, NormalKernel};
use factor_testing::GENERATED_TOLERANCE;
use factor_testing::generated::{compare, input_scale};
use factor_testing::samples::Sampler;
use nalgebra::{DMatrix, DVector};

/// Configurations per factor: not a multiple of any lane count, so the
/// scalar tail runs too.
pub(crate) const COUNT: usize = 10_003;

/// `F32x8` vs dual numbers, as [`compare`] measures (the residual relative
/// to the inputs' scale, blocks relative Frobenius): inputs rounded to
/// `f32` move a pixel of 500 by 3·10⁻⁵, and the kernels lose a few digits
/// more to cancellation (the `f32` tolerance of `slam-factors`' tests).
const F32_VS_DUAL: f64 = 1e-3;

/// Fused normal equations vs dual numbers, relative to the scales above.
const NORMAL_VS_DUAL: f64 = 3e-12;

/// The kernel over every number type the tests run.
pub(crate) trait AllLanes:
    Kernel<f64>
    + Kernel<f32>
    + Kernel<F64x4>
    + Kernel<F64x8>
    + Kernel<F32x8>
    + NormalKernel<f64>
    + NormalKernel<f32>
    + NormalKernel<F64x4>
    + NormalKernel<F64x8>
    + NormalKernel<F32x8>
{
}

impl<K> AllLanes for K where
    K: Kernel<f64>
        + Kernel<f32>
        + Kernel<F64x4>
        + Kernel<F64x8>
        + Kernel<F32x8>
        + NormalKernel<f64>
        + NormalKernel<f32>
        + NormalKernel<F64x4>
        + NormalKernel<F64x8>
        + NormalKernel<F32x8>
{
}

/// Every output of a batch as one list of columns: the Jacobian outputs,
/// then the normal equations.
struct Outputs<S> {
    jacobian: JacobianColumns<S>,
    normal: NormalColumns<S>,
}

impl<S> Outputs<S> {
    fn columns(&self) -> Vec<&Columns<S>> {
        std::iter::once(&self.jacobian.residual)
            .chain(self.jacobian.blocks.iter().flatten())
            .chain(std::iter::once(&self.normal.cost))
            .chain(self.normal.gradient.iter().flatten())
            .chain(self.normal.hessian.iter().flatten())
            .collect()
    }
}

/// The batch of `inputs` and `weights` with lanes `L`, every block wanted.
fn batch<F, L>(inputs: &Columns<L::Scalar>, weights: &[L::Scalar]) -> Outputs<L::Scalar>
where
    F: WithKernel,
    L: Lanes,
    F::Kernel: NormalKernel<L> + NormalKernel<L::Scalar>,
{
    let n = inputs.len();
    let mut jacobian = JacobianColumns::new::<F>(n, &[]);
    linearize::<F, L>(inputs, &mut jacobian, Options::default()).expect("shapes fit");
    let mut fused = NormalColumns::new::<F>(n, &[]);
    normal::<F, L>(inputs, Some(weights), &mut fused, Options::default()).expect("shapes fit");
    Outputs {
        jacobian,
        normal: fused,
    }
}

/// Rows `at..at + T::LANES` of `columns` as one lane value each.
fn load<T: Lanes>(columns: &Columns<T::Scalar>, at: usize) -> Vec<T> {
    columns.columns().map(|c| T::load(&c[at..])).collect()
}

/// Writes `values` to rows `at..at + T::LANES` of `columns`.
fn store<T: Lanes>(values: &[T], columns: &mut [&mut Columns<T::Scalar>], at: usize) {
    let mut values = values.iter();
    for columns in columns {
        for column in columns.columns_mut() {
            values
                .next()
                .expect("one value per column")
                .store(&mut column[at..]);
        }
    }
}

/// One group of rows through the kernels on `T`, straight from the traits.
fn direct_group<F, T>(
    inputs: &Columns<T::Scalar>,
    weights: &[T::Scalar],
    out: &mut Outputs<T::Scalar>,
    at: usize,
) where
    F: WithKernel,
    T: Lanes,
    F::Kernel: NormalKernel<T>,
{
    let zero = T::splat(T::Scalar::default());
    let mut x = <F::Kernel as Kernel<T>>::Inputs::splat(zero);
    x.as_mut().copy_from_slice(&load::<T>(inputs, at));
    let mut y = <F::Kernel as Kernel<T>>::Outputs::splat(zero);
    <F::Kernel as Kernel<T>>::linearize(&x, &mut y, &[true; 8]);
    let jacobian = &mut out.jacobian;
    let mut columns: Vec<&mut Columns<T::Scalar>> = std::iter::once(&mut jacobian.residual)
        .chain(jacobian.blocks.iter_mut().flatten())
        .collect();
    store(y.as_ref(), &mut columns, at);
    let mut y = <F::Kernel as NormalKernel<T>>::NormalOutputs::splat(zero);
    <F::Kernel as NormalKernel<T>>::normal(&x, T::load(&weights[at..]), &mut y, &[true; 8]);
    let normal = &mut out.normal;
    let mut columns: Vec<&mut Columns<T::Scalar>> = std::iter::once(&mut normal.cost)
        .chain(normal.gradient.iter_mut().flatten())
        .chain(normal.hessian.iter_mut().flatten())
        .collect();
    store(y.as_ref(), &mut columns, at);
}

/// The outputs of the kernels on lanes `L` called group by group (the rows
/// left over with `L::Scalar`), with none of the batch's machinery.
fn direct<F, L>(inputs: &Columns<L::Scalar>, weights: &[L::Scalar]) -> Outputs<L::Scalar>
where
    F: WithKernel,
    L: Lanes,
    F::Kernel: NormalKernel<L> + NormalKernel<L::Scalar>,
{
    let n = inputs.len();
    let mut out = Outputs {
        jacobian: JacobianColumns::new::<F>(n, &[]),
        normal: NormalColumns::new::<F>(n, &[]),
    };
    let whole = n / L::LANES * L::LANES;
    for at in (0..whole).step_by(L::LANES) {
        direct_group::<F, L>(inputs, weights, &mut out, at);
    }
    for at in whole..n {
        direct_group::<F, L::Scalar>(inputs, weights, &mut out, at);
    }
    out
}

/// Whether two sets of columns are identical, bit for bit; else the first
/// difference.
fn first_difference<S: Copy + Into<f64>>(a: &[&Columns<S>], b: &[&Columns<S>]) -> Option<String> {
    for (k, (a, b)) in a.iter().zip(b).enumerate() {
        for (j, (ca, cb)) in a.columns().zip(b.columns()).enumerate() {
            for (i, (x, y)) in ca.iter().zip(cb).enumerate() {
                let (x, y): (f64, f64) = ((*x).into(), (*y).into());
                if x.to_bits() != y.to_bits() {
                    return Some(format!("output {k}, column {j}, row {i}: {x:e} vs {y:e}"));
                }
            }
        }
    }
    None
}

/// The largest difference of `a` from `b`, relative to each column's
/// largest magnitude (or 1).
fn column_difference<S: Copy + Into<f64>>(a: &[&Columns<S>], b: &[&Columns<S>]) -> f64 {
    let mut worst = 0.0_f64;
    for (a, b) in a.iter().zip(b) {
        for (ca, cb) in a.columns().zip(b.columns()) {
            let scale = cb.iter().fold(1.0_f64, |m, x| m.max((*x).into().abs()));
            for (x, y) in ca.iter().zip(cb) {
                let (x, y): (f64, f64) = ((*x).into(), (*y).into());
                worst = worst.max((x - y).abs() / scale);
            }
        }
    }
    worst
}

/// Row `i` of a batch's Jacobian outputs as a linearization.
fn row<F: Factor, S: Copy + Into<f64>>(outputs: &JacobianColumns<S>, i: usize) -> DynLinearization {
    let r = F::RESIDUAL_DIM;
    let at = |c: &Columns<S>| -> Vec<f64> { c.row(i).into_iter().map(Into::into).collect() };
    DynLinearization {
        residual: DVector::from_vec(at(&outputs.residual)),
        jacobians: outputs
            .blocks
            .iter()
            .zip(F::variables())
            .map(|(b, v)| {
                DMatrix::from_row_slice(r, v.tangent_dim, &at(b.as_ref().expect("all free")))
            })
            .collect(),
    }
}

/// The largest error of a linearization against another, as [`compare`]
/// measures.
fn worst_error<F: Factor>(factor: &F, a: &DynLinearization, b: &DynLinearization) -> f64 {
    let check = compare(factor, a, b);
    check
        .block_errors
        .iter()
        .fold(check.residual_error, |m, (_, e)| m.max(*e))
}

/// `Jᵢᵀ w Jⱼ` as the batch lays it out (a diagonal block as its upper
/// triangle row by row), with `f` applied to every entry of both blocks
/// first (`f64::abs` gives the scale of each sum's rounding).
fn hessian_block(
    lin: &DynLinearization,
    w: f64,
    i: usize,
    j: usize,
    f: fn(f64) -> f64,
) -> Vec<f64> {
    let h = lin.jacobians[i].map(f).transpose() * lin.jacobians[j].map(f) * w;
    let mut out = Vec::new();
    for a in 0..h.nrows() {
        for b in (if i == j { a } else { 0 })..h.ncols() {
            out.push(h[(a, b)]);
        }
    }
    out
}

/// Where an entry of the normal equations is: the cost, entry `a` of the
/// gradient block of variable `k`, or entry `e` of Hessian block `p` (of
/// variables `a` and `b`).
#[derive(Clone, Copy)]
enum Slot {
    Cost,
    Gradient {
        k: usize,
        a: usize,
    },
    Hessian {
        p: usize,
        a: usize,
        b: usize,
        e: usize,
    },
}

impl Slot {
    /// Its name, for messages.
    fn name<F: Factor>(self) -> String {
        let variables = F::variables();
        match self {
            Slot::Cost => "cost".into(),
            Slot::Gradient { k, a } => format!("g_{}[{a}]", variables[k].name),
            Slot::Hessian { a, b, e, .. } => {
                format!("h_{}_{}[{e}]", variables[a].name, variables[b].name)
            }
        }
    }

    /// Its value in row `i` of the fused normal equations `out`.
    fn fused(self, out: &NormalColumns<f64>, i: usize) -> f64 {
        match self {
            Slot::Cost => out.cost.column(0)[i],
            Slot::Gradient { k, a } => out.gradient[k].as_ref().expect("free").column(a)[i],
            Slot::Hessian { p, e, .. } => out.hessian[p].as_ref().expect("free").column(e)[i],
        }
    }
}

/// One entry of the normal equations of a row from a linearization: where
/// it is, its value, the sum of the absolute values of its terms, and the
/// natural scale of its error given `J` within a relative `δ` and `r`
/// within `δ · scale`.
struct Entry {
    slot: Slot,
    reference: f64,
    magnitude: f64,
    natural: f64,
}

/// Every entry of the normal equations (cost, gradient blocks, Hessian
/// blocks) of the linearization `lin` of `factor` with weight `w`, computed
/// once for every fused output it is compared with.
fn normal_entries<F: Factor>(factor: &F, lin: &DynLinearization, w: f64) -> Vec<Entry> {
    let r = &lin.residual;
    let scale = input_scale(factor);
    let norms: Vec<f64> = lin.jacobians.iter().map(|j| j.norm()).collect();
    let rn = r.norm();
    let mut entries = vec![Entry {
        slot: Slot::Cost,
        reference: 0.5 * w * r.norm_squared(),
        magnitude: 0.5 * w * r.norm_squared(),
        natural: w * rn.max(1e-9) * scale,
    }];
    let variables = F::variables();
    for (k, v) in variables.iter().enumerate() {
        let g = lin.jacobians[k].transpose() * r * w;
        let m = lin.jacobians[k].map(f64::abs).transpose() * r.map(f64::abs) * w;
        for a in 0..v.tangent_dim {
            entries.push(Entry {
                slot: Slot::Gradient { k, a },
                reference: g[a],
                magnitude: m[a],
                natural: w * norms[k] * (rn + scale),
            });
        }
    }
    for (p, (a, b)) in pairs(variables.len()).into_iter().enumerate() {
        let reference = hessian_block(lin, w, a, b, |x| x);
        let magnitude = hessian_block(lin, w, a, b, f64::abs);
        for (e, (h, m)) in reference.iter().zip(&magnitude).enumerate() {
            entries.push(Entry {
                slot: Slot::Hessian { p, a, b, e },
                reference: *h,
                magnitude: *m,
                natural: w * norms[a] * norms[b],
            });
        }
    }
    entries
}

/// Weights in `[0.1, 10)`, log-uniform.
fn weights(sampler: &mut Sampler, count: usize) -> Vec<f64> {
    (0..count)
        .map(|_| sampler.uniform(0.1f64.ln(), 10f64.ln()).exp())
        .collect()
}

/// Lanes `L` against their direct evaluation (bit for bit) and against the
/// scalar batch `scalar` (bit for bit unless `transcendental`); returns the
/// largest difference from the scalar batch, relative to the column scale.
fn lanes<F, L>(
    inputs: &Columns<L::Scalar>,
    w: &[L::Scalar],
    scalar: &Outputs<L::Scalar>,
    transcendental: bool,
) -> (Outputs<L::Scalar>, f64)
where
    F: WithKernel,
    L: Lanes,
    L::Scalar: Into<f64>,
    F::Kernel: NormalKernel<L> + NormalKernel<L::Scalar>,
{
    let name = F::NAME;
    let lanes = batch::<F, L>(inputs, w);
    let reference = direct::<F, L>(inputs, w);
    if let Some(d) = first_difference(&lanes.columns(), &reference.columns()) {
        panic!("{name}: the batch in lanes differs from its kernel in lanes: {d}");
    }
    let difference = column_difference(&lanes.columns(), &scalar.columns());
    if !transcendental && let Some(d) = first_difference(&lanes.columns(), &scalar.columns()) {
        panic!("{name}: lanes differ from the scalar kernel: {d}");
    }
    (lanes, difference)
}

/// Every check of this file for one factor type, whose kernel calls `sin`,
/// `cos`, `atan2`, … when `transcendental` (then lanes are not bit for bit
/// the scalar kernel).
pub(crate) fn check<F>(factors: &[F], seed: u64, transcendental: bool)
where
    F: WithKernel,
    F::Kernel: AllLanes,
{
    let name = F::NAME;
    let inputs = Columns::from_factors(factors);
    let inputs32 = inputs.map(|x| *x as f32);
    let w = weights(&mut Sampler::new(seed), factors.len());
    let w32: Vec<f32> = w.iter().map(|x| *x as f32).collect();

    let scalar = batch::<F, f64>(&inputs, &w);
    let scalar32 = batch::<F, f32>(&inputs32, &w32);
    let (x4, d4) = lanes::<F, F64x4>(&inputs, &w, &scalar, transcendental);
    let (x8, d8) = lanes::<F, F64x8>(&inputs, &w, &scalar, transcendental);
    let (s8, d32) = lanes::<F, F32x8>(&inputs32, &w32, &scalar32, transcendental);
    println!(
        "{name}: lanes vs the scalar kernel, largest difference of the column scale: \
         F64x4 {d4:e}, F64x8 {d8:e}, F32x8 {d32:e}"
    );

    let mut worst = [0.0_f64; 5];
    for (i, factor) in factors.iter().enumerate() {
        // The scalar batch is the derive's kernel path, one factor at a time.
        let one = factor
            .linearize_generated_dyn()
            .expect("a kernel")
            .expect("valid");
        let kernel = row::<F, f64>(&scalar.jacobian, i);
        assert_eq!(kernel, one, "{name} configuration {i}");

        // Scalar and `f64` lanes vs dual numbers.
        let dual = factor.linearize_dual_dyn().expect("valid");
        for (what, outputs) in [("f64", &scalar), ("F64x4", &x4), ("F64x8", &x8)] {
            let e = worst_error(factor, &row::<F, f64>(&outputs.jacobian, i), &dual);
            assert!(
                e <= GENERATED_TOLERANCE,
                "{name} configuration {i}: {what} vs dual {e:e}"
            );
            worst[0] = worst[0].max(e);
        }
        let e = worst_error(factor, &row::<F, f32>(&s8.jacobian, i), &dual);
        assert!(
            e <= F32_VS_DUAL,
            "{name} configuration {i}: F32x8 vs dual {e:e}"
        );
        worst[1] = worst[1].max(e);

        // Fused vs the Jacobian kernel's J and r: only the order of the sums.
        let r = F::RESIDUAL_DIM as f64;
        for e in normal_entries(factor, &kernel, w[i]) {
            let fused = e.slot.fused(&scalar.normal, i);
            let bound = (r + 2.0) * f64::EPSILON * e.magnitude;
            let error = (fused - e.reference).abs();
            assert!(
                error <= bound,
                "{name} configuration {i}: {}: fused {fused:e} vs {:e} (bound {bound:e})",
                e.slot.name::<F>(),
                e.reference
            );
            worst[2] = worst[2].max(error / e.magnitude.max(f64::MIN_POSITIVE));
        }
        // Fused vs dual numbers, relative to the natural scales; in `f64`
        // lanes too.
        let entries = normal_entries(factor, &dual, w[i]);
        for outputs in [&scalar, &x4, &x8] {
            for e in &entries {
                let fused = e.slot.fused(&outputs.normal, i);
                let error = (fused - e.reference).abs() / e.natural.max(f64::MIN_POSITIVE);
                assert!(
                    error <= NORMAL_VS_DUAL,
                    "{name} configuration {i}: {}: fused {fused:e} vs dual {:e} ({error:e})",
                    e.slot.name::<F>(),
                    e.reference
                );
                worst[3] = worst[3].max(error);
            }
        }
    }
    println!(
        "{name}: {} configurations; kernel (f64, F64x4, F64x8) vs dual {:e}; F32x8 vs dual {:e}; \
         fused vs the kernel's J and r {:e} of the terms' magnitude; fused vs dual {:e}",
        factors.len(),
        worst[0],
        worst[1],
        worst[2],
        worst[3]
    );
}

/// `COUNT` factors drawn by `sample` from a sampler seeded with `seed`.
pub(crate) fn sampled<F>(seed: u64, mut sample: impl FnMut(&mut Sampler) -> F) -> Vec<F> {
    let mut sampler = Sampler::new(seed);
    (0..COUNT).map(|_| sample(&mut sampler)).collect()
}
