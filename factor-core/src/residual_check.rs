//! The derive's check of the residual function's signature: generic over
//! the factor's scalar, `fn<S: Scalar>(&Factor<S>) -> SVector<S, DIM>`.
//!
//! `#[derive(Factor)]` sees the residual only by its path. Calling it
//! through a `fn(&Self) -> _` pointer reported a non-generic residual as
//! "expected fn pointer, found fn item" with no hint. Instead the residual is
//! called with an argument of a type left to inference, and one bound,
//! [`ResidualOf`], then relates its argument and value types to the
//! factor's: a residual written over `f64` fails it, once, with the
//! diagnostic below.

use nalgebra::SVector;

use crate::Scalar;

/// Implemented by `T` when `fn(&T) -> Out` is a residual of the factor `F`
/// over its scalar `S`: `T` is `F` and `Out` is `SVector<S, D>`.
#[diagnostic::on_unimplemented(
    message = "the residual function of `{F}` is not generic over its scalar `{S}`",
    label = "must take `&{F}` and return `SVector<{S}, DIM>`, for every `{S}: Scalar`",
    note = "the factor is evaluated at `f64`, on dual numbers and over a symbolic scalar, all \
            through this one function: write it `fn my_residual<{S}: Scalar>(f: &{F}) -> \
            SVector<{S}, DIM>` (`Vector2<{S}>` for `dim = 2`), with `{S}` wherever it has \
            `f64` (a literal is `{S}::from_f64(0.5)`)"
)]
pub trait ResidualOf<F, S, Out, const D: usize> {
    /// The factor as the residual's argument.
    fn arg(factor: &F) -> &Self;
    /// The residual's value as the factor's residual vector.
    fn value(value: Out) -> SVector<S, D>;
}

#[diagnostic::do_not_recommend]
impl<F, S: Scalar, const D: usize> ResidualOf<F, S, SVector<S, D>, D> for F {
    #[inline(always)]
    fn arg(factor: &F) -> &F {
        factor
    }
    #[inline(always)]
    fn value(value: SVector<S, D>) -> SVector<S, D> {
        value
    }
}

/// Never a residual's value. Its impl makes [`ResidualOf`] have two, so that
/// the bound infers nothing before the residual's own types are known (with
/// one impl, rustc would take the argument to be `F` and report a
/// non-generic residual as mismatched types again).
pub enum NotAResidual {}

#[diagnostic::do_not_recommend]
impl<F, S, const D: usize> ResidualOf<F, S, NotAResidual, D> for F {
    fn arg(factor: &F) -> &F {
        factor
    }
    fn value(value: NotAResidual) -> SVector<S, D> {
        match value {}
    }
}

/// `factor` as the argument of the residual `fn(&T) -> Out` (the marker
/// carries `T` and `Out` from the call to [`residual_value`]).
#[inline(always)]
pub fn residual_arg<F, S, T, Out, const D: usize>(
    factor: &F,
    _signature: core::marker::PhantomData<fn(&T) -> Out>,
) -> &T
where
    T: ResidualOf<F, S, Out, D>,
{
    T::arg(factor)
}

/// The residual's value as the factor's residual vector.
#[inline(always)]
pub fn residual_value<F, S, T, Out, const D: usize>(
    value: Out,
    _signature: core::marker::PhantomData<fn(&T) -> Out>,
) -> SVector<S, D>
where
    T: ResidualOf<F, S, Out, D>,
{
    T::value(value)
}
