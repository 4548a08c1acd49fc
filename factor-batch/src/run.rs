//! The loop over one range of factors: groups of `L::LANES` factors loaded
//! from the input columns into lanes, evaluated, and stored into the
//! wanted output columns; the factors left over one at a time with the lane
//! scalar.

use factor_lanes::{Array, Kernel, Lanes, NormalKernel};

/// One evaluation of a kernel over the number type `T`: its inputs, the
/// factor's weight (used by the normal equations only) and its outputs, each
/// in one array.
pub(crate) trait Eval<T: Copy>: Sync {
    /// Every stored scalar of the factor.
    type In: Array<T>;
    /// Every output the kernel writes.
    type Out: Array<T>;
    /// Evaluates; writes the outputs it was asked for.
    fn eval(&self, inputs: &Self::In, weight: T, outputs: &mut Self::Out);
}

/// The residual-and-Jacobian kernel `K`, with the blocks of the variables
/// flagged in `blocks`.
pub(crate) struct Jacobian<'a, K> {
    pub(crate) blocks: &'a [bool],
    pub(crate) kernel: core::marker::PhantomData<fn() -> K>,
}

impl<T: Copy, K: Kernel<T>> Eval<T> for Jacobian<'_, K> {
    type In = K::Inputs;
    type Out = K::Outputs;

    #[inline(always)]
    fn eval(&self, inputs: &Self::In, _weight: T, outputs: &mut Self::Out) {
        K::linearize(inputs, outputs, self.blocks);
    }
}

/// The normal-equation kernel `K`, with the blocks of the variables flagged
/// in `free`.
pub(crate) struct Normal<'a, K> {
    pub(crate) free: &'a [bool],
    pub(crate) kernel: core::marker::PhantomData<fn() -> K>,
}

impl<T: Copy, K: NormalKernel<T>> Eval<T> for Normal<'_, K> {
    type In = K::Inputs;
    type Out = K::NormalOutputs;

    #[inline(always)]
    fn eval(&self, inputs: &Self::In, weight: T, outputs: &mut Self::Out) {
        K::normal(inputs, weight, outputs, self.free);
    }
}

/// One range of factors: the input columns, the weights (`None`: 1), and
/// one entry per kernel output, the column to store it in or `None` for an
/// output not wanted. Every column has `len` rows.
pub(crate) struct Range<'a, S> {
    pub(crate) len: usize,
    pub(crate) inputs: Vec<&'a [S]>,
    pub(crate) weights: Option<&'a [S]>,
    pub(crate) outputs: Vec<Option<&'a mut [S]>>,
}

/// Evaluates rows `at..at + T::LANES` with the number type `T`: loads the
/// inputs, evaluates and stores the wanted outputs. The buffers are local
/// and their indices constant once the loops are unrolled, so they live in
/// registers.
///
/// # Safety
///
/// Every column of `range` (inputs, weights, outputs) has at least
/// `at + T::LANES` rows: the accesses are unchecked (bounds checks on each of
/// the dozens of columns cost 10–15% of a lane group's time).
#[inline(always)]
unsafe fn group<T: Lanes, E: Eval<T>>(eval: &E, range: &mut Range<T::Scalar>, at: usize) {
    let zero = T::splat(T::Scalar::default());
    let mut x = E::In::splat(zero);
    for (input, column) in x.as_mut().iter_mut().zip(&range.inputs) {
        // SAFETY: the column has `at + T::LANES` rows (the caller's promise).
        *input = T::load(unsafe { column.get_unchecked(at..at + T::LANES) });
    }
    let weight = match range.weights {
        // SAFETY: as above.
        Some(w) => T::load(unsafe { w.get_unchecked(at..at + T::LANES) }),
        None => T::splat(T::Scalar::from(1.0)),
    };
    let mut y = E::Out::splat(zero);
    eval.eval(&x, weight, &mut y);
    for (output, column) in y.as_ref().iter().zip(range.outputs.iter_mut()) {
        if let Some(column) = column {
            // SAFETY: as above.
            output.store(unsafe { column.get_unchecked_mut(at..at + T::LANES) });
        }
    }
}

/// Evaluates every row of `range`: groups of `L::LANES` in lanes, the rest
/// with the scalar.
///
/// # Panics
///
/// If the columns do not fit the kernel or `range.len` (checked before).
#[inline(always)]
pub(crate) fn run<L, E>(eval: &E, range: &mut Range<L::Scalar>)
where
    L: Lanes,
    E: Eval<L> + Eval<L::Scalar>,
{
    assert_eq!(range.inputs.len(), <E as Eval<L>>::In::LEN);
    assert_eq!(range.outputs.len(), <E as Eval<L>>::Out::LEN);
    // What `group` needs: every column has `len` rows.
    let len = range.len;
    assert!(range.inputs.iter().all(|c| c.len() == len));
    assert!(range.weights.is_none_or(|w| w.len() == len));
    assert!(range.outputs.iter().flatten().all(|c| c.len() == len));
    let groups = len / L::LANES;
    for g in 0..groups {
        // SAFETY: `g · LANES + LANES ≤ len`, the rows of every column.
        unsafe { group::<L, E>(eval, range, g * L::LANES) };
    }
    // SAFETY: every column has `len` rows (asserted above).
    unsafe { tail::<L::Scalar, E>(eval, range, groups * L::LANES) };
}

/// Evaluates rows `from..range.len` one at a time with the scalar `S`: the
/// rows fewer than a lane group that [`run`] leaves over. Not inlined, so
/// each kernel's scalar tail is compiled once per scalar type rather than
/// copied into every lane type's and instruction set's instance of [`run`]
/// (which would add a kernel's code to each, for at most `LANES − 1` rows
/// of a range). Results are the same in either: Rust never contracts to
/// FMA, so the instruction set changes no rounding.
///
/// # Safety
///
/// Every column of `range` (inputs, weights, outputs) has `range.len` rows.
#[inline(never)]
unsafe fn tail<S: Lanes, E: Eval<S>>(eval: &E, range: &mut Range<S::Scalar>, from: usize) {
    for at in from..range.len {
        // SAFETY: `at + 1 ≤ len`, the rows of every column (the caller's promise).
        unsafe { group::<S, E>(eval, range, at) };
    }
}
