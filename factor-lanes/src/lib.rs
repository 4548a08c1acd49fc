//! SIMD lane types for the generated kernels: one value holds several
//! configurations of a factor, one per lane, so a kernel generic over its
//! `Real` trait linearizes that many factors per call.
//!
//! # Types
//!
//! | type | lanes | code compiled for AVX-512 | for AVX2 + FMA | default `x86-64` (SSE2) |
//! | --- | --- | --- | --- | --- |
//! | [`F64x4`] | 4 × `f64` | one 256-bit register | one 256-bit register | two 128-bit halves |
//! | [`F32x8`] | 8 × `f32` | one 256-bit register | one 256-bit register | two 128-bit halves |
//! | [`F64x8`] | 8 × `f64` | one 512-bit register | two 256-bit halves | four 128-bit quarters |
//!
//! A lane type is an aligned array whose arithmetic, square root and select
//! are loops over the lanes, which LLVM vectorises for the instruction set
//! of the function they are inlined into: the build's target, or a
//! `#[target_feature]` function chosen at run time, which is how the batch
//! evaluators of `factor-batch` reach AVX2 and AVX-512 without
//! `-C target-cpu` (see "Choice of SIMD library" below). Every build is
//! correct on any target. The elementary functions are `wide`'s
//! (vectorised, compiled for the build's target).
//!
//! # Operations
//!
//! - `+ − × ÷`, unary `−`, [`sqrt`](F64x4::sqrt): IEEE 754, correctly rounded
//!   in each lane, so each lane is **bit for bit** the scalar result (Rust
//!   never fuses a multiply and an add behind your back; `tests/kernels.rs`
//!   checks whole kernels this way).
//! - [`constant`](F64x4::constant) (`c as` the scalar, in every lane),
//!   [`splat`](F64x4::splat), [`from_array`](F64x4::from_array) /
//!   [`to_array`](F64x4::to_array) and `From` both ways.
//! - [`select_lt`](F64x4::select_lt): the lane-wise blend
//!   `if lhs < rhs { if_less } else { otherwise }` (NaN selects `otherwise`,
//!   as the scalar `<`).
//! - Memory: [`load`](F64x4::load) / [`store`](F64x4::store) of `N`
//!   consecutive scalars of a structure-of-arrays column (take the chunks
//!   from `column.as_chunks::<N>()`, the tail with the scalar kernel),
//!   [`gather_strided`](F64x4::gather_strided) (one field of `N` consecutive
//!   records: array-of-structs data) and [`gather`](F64x4::gather) (by
//!   index); the gathers return `None`, never panic, when a lane falls outside
//!   the data.
//! - [`sin`](F64x4::sin), [`cos`](F64x4::cos), [`sin_cos`](F64x4::sin_cos),
//!   [`atan2`](F64x4::atan2), [`atan`](F64x4::atan), [`asin`](F64x4::asin),
//!   [`acos`](F64x4::acos), [`exp`](F64x4::exp), [`ln`](F64x4::ln):
//!   vectorised, with the accuracy below.
//! - [`impl_real!`]: implements a generated crate's own `Real` trait for all
//!   three types.
//! - [`Lanes`]: the lane types and `f64`, `f32` (one lane) behind one trait,
//!   with loads and stores of structure-of-arrays columns, for batch code
//!   generic over the lane type.
//! - [`Kernel`], [`NormalKernel`] (with [`Array`]): a generated kernel over
//!   any number type of its crate's `Real`, inputs and outputs each in one
//!   fixed-size array, which a generated crate's `lanes` feature implements
//!   for each kernel module's marker type `Kernel`.
//!
//! # Accuracy of the elementary functions
//!
//! Largest distance from the scalar `std` function of the lane scalar, in
//! ulp, measured by `tests/math_accuracy.rs` over 2¹⁸ random inputs per range
//! and 4–7 ranges per function (≥ 10⁶ inputs per function and type), the same
//! with and without `-C target-cpu=native` (FMA, AVX-512):
//!
//! | function | `F64x4`, `F64x8` | `F32x8` | ranges measured |
//! | --- | --- | --- | --- |
//! | `sin`, `cos` | 2 | 1 | `[−π, π]`; `[−1000, 1000]`; `\|x\|` log-uniform in `[1, 2²⁸]`, in `[2²⁸, MAX]` and down to the smallest subnormal; doubles within 4 ulp of `k·π/2` (`k < 2²⁷`) and just outside the band sent to `std` |
//! | `atan2` | 2 | 3 | the four quadrants; magnitudes log-uniform over all normals; both subnormal; near the axes; on the axes (`x = ±0` or `y = ±0`) |
//! | `atan` | 1 | 3 | `[−10, 10]`; all normals; subnormals; `[0.4, 2.5]` |
//! | `asin` | 2 | 2 | `[−1, 1]`; tiny; `±(1 − d)`, `d` down to 10⁻¹⁷; `[0.4, 0.7]`; outside `[−1, 1]` (NaN) |
//! | `acos` | 2 | 1 | as `asin` |
//! | `exp` | 1 | 1 | `[−10, 10]`; the whole range, from subnormal results to overflow; tiny |
//! | `ln` | 1 | 1 | all normals; subnormals; `1 ± d`; `[0.5, 2]`; negative (NaN) |
//!
//! `sin` and `cos` are accurate for **every finite argument**: lanes with
//! `|x| ≤ 2²⁸` are reduced and evaluated in vector registers, except the rare
//! ones within `k·2⁻⁴⁶` of a multiple `k·π/2` (where the three-part reduction
//! would lose digits to cancellation); those and larger arguments are computed
//! lane by lane by `std` (a cold path, taken by a fraction ≈ `1.3·k·2⁻⁴⁶`
//! of uniformly random arguments: below 10⁻¹⁰ for `|x| ≤ 1000`). `F32x8` evaluates `sin`/`cos` in `f64` lanes.
//! Special values match `std`: ±0 keep their sign, ±∞ and NaN give what
//! `std` gives (NaN for `sin(∞)`, `±π/2` for `atan(±∞)`, `atan2`'s signed
//! zeros and `±π`, `±3π/4` on the axes and at infinities, `−∞` for `ln(0)`, NaN
//! for `ln` of a negative and `asin`/`acos` outside `[−1, 1]`).
//!
//! # Choice of SIMD library
//!
//! Measured by `benches/candidates.rs`: the generated point-reprojection
//! kernel itself (`generated/src/point_reprojection.rs`, residual and both
//! Jacobian blocks) over 4096 sampled configurations held as
//! structure-of-arrays columns, per lane type and library, in one run per
//! build; ns of thread CPU time per factor (the machine is shared: wall time
//! was too noisy), the best of three runs, and the ratio to the scalar `f64`
//! kernel of the same run. AMD EPYC with AVX2, FMA and AVX-512; Rust 1.95.
//!
//! | candidate | lanes | default `x86-64` build | `-C target-cpu=native` |
//! | --- | --- | --- | --- |
//! | scalar | `f64` | 25.6 ns (1.0×) | 25.6 ns (1.0×) |
//! | scalar | `f32` | 25.2 ns (1.0×) | 21.8 ns (1.2×) |
//! | **`wide`** (these types) | `F64x4` | 10.6 ns (2.4×) | **7.2 ns (3.6×)** |
//! | **`wide`** (these types) | `F32x8` | 5.2 ns (5.0×) | **4.0 ns (6.5×)** |
//! | **`wide`** (these types) | `F64x8` | 10.9 ns (2.4×) | **5.0 ns (5.1×)** |
//! | portable arrays (lane loops left to LLVM) | 4 × `f64` | 10.0 ns (2.6×) | 9.4 ns (2.7×) |
//! | portable arrays | 8 × `f32` | 4.5 ns (5.6×) | 4.3 ns (6.0×) |
//! | portable arrays | 8 × `f64` | 8.3 ns (3.1×) | 5.3 ns (4.9×) |
//! | `pulp` `V3`/`V4`, loop chosen at run time | 4 × `f64` | 148 ns (0.17×) | 7.2 ns (3.6×) |
//! | `pulp` `V3`/`V4`, loop chosen at run time | 8 × `f32` | 77 ns (0.33×) | 3.3 ns (7.7×) |
//! | `pulp` `V4`, loop chosen at run time | 8 × `f64` | 88 ns (0.29×) | 5.2 ns (4.9×) |
//!
//! The same figures as a chart: `factor-lanes/doc/candidates.png`, drawn from
//! the benchmark's output by `benches/plot_candidates.py`.
//!
//! Runtime dispatch (a batch loop compiled with `#[target_feature(enable =
//! "avx2,fma")]` or AVX-512 and chosen by `is_x86_feature_detected!`, the
//! `+avx2`/`+avx512` rows of the benchmark) gains nothing in the default build
//! with the kernels as generated: LLVM does not inline the `#[inline]` point
//! kernel into the feature-enabled loop, so the kernel keeps the baseline
//! instructions (portable arrays, `wide`: 2.5–3.1×), and `pulp`, whose every
//! operation is a `#[target_feature]` function, becomes a call per operation
//! (0.17–0.33×). With the kernel marked `#[inline(always)]` (an experiment on
//! a local copy, default build, same benchmark) the dispatched loops reach
//! native speed without `target-cpu`: portable arrays 3.5× (`f64x4`, AVX2),
//! 7.0× (`f32x8`, AVX2), 4.7× (`f64x8`, AVX2); `pulp` 2.8×, 6.9×, 4.0×;
//! while `wide`, whose instruction set is fixed when it is compiled, stays at
//! 2.9–3.1×.
//!
//! Chosen at first: **`wide`** (1.7). Compiled for the machine it is the fastest or
//! level with the fastest for `f64` (4 lanes 3.6×, 8 lanes 5.1×) and within
//! 20% of `pulp` for `f32` (6.5× against 7.7×); it is correct on every target
//! with no `unsafe` here, and it is the only candidate that brings the
//! vectorised `sin`, `cos`, `atan2`, `exp`, `ln`, `acos`, `asin`, `atan`
//! (`pulp`, `fearless_simd` and `macerator` have none; `simba`'s SIMD types
//! wrap `wide`; `std::simd` and the `sleef` crate need nightly). `pulp` and
//! hand-written `core::arch` need a CPU-feature token that the generated
//! `Real` has no place for (the benchmark conjures one unsafely) and are only
//! fast inside a dispatched loop the kernel is inlined into. The types are
//! newtypes, so a later batch API that wants runtime dispatch without
//! `target-cpu` can move their arithmetic to portable arrays (and have the
//! generator emit `#[inline(always)]`) without changing this interface.
//!
//! **Revisited with the batch API: portable arrays, `wide` for the
//! elementary functions.** The batch evaluators of `factor-batch` must be
//! fast on a machine of unknown features without `RUSTFLAGS`, so they
//! compile their loop for the build's target, AVX2 + FMA and AVX-512 and
//! pick one at run time; the generator now emits the kernels
//! `#[inline(always)]` (the scalar path through the derive measured the same
//! either way, 28.0 vs 28.1 ns for the point factor and 75.0 vs 75.5 ns for
//! the Plücker factor, A/B-alternated), so they are inlined into those
//! loops. Measured in the batch loop, `wide`'s build-time instruction set
//! left the AVX2 and AVX-512 instances no faster than the baseline, as the
//! table above found, while portable arrays took the instruction set of the
//! instance (`benches/candidates.rs`, `portable` rows; the batch figures
//! are in `factor-batch`'s documentation). So the lane types' arithmetic,
//! `sqrt` and `select_lt` are now loops over aligned arrays, bit for bit as
//! before (IEEE 754 per lane), and their `sin`, `cos`, `atan2`, `exp`, `ln`,
//! `acos`, `asin`, `atan` are still `wide`'s, with the accuracy above.

#![forbid(unsafe_code)]
#![deny(missing_docs)]

mod generic;
mod kernel;
mod lanes;
mod math;
mod memory;
mod real;

pub use generic::Lanes;
pub use kernel::{Array, Kernel, NormalKernel};
pub use lanes::{F32x8, F64x4, F64x8};
