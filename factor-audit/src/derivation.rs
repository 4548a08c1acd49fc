//! A hand-derived formula as the audit sees it: a labelled claim that some
//! printed matrix is the Jacobian of a map, at any sampled point.
//!
//! The map is written once, generic over the scalar, so the same code gives
//! the truth by dual numbers and the corrected expression by the symbolic
//! engine. The printed formula is transcribed as printed, typos included, and
//! evaluated in `f64` at the same point.

use factor_core::dual::Dual;
use nalgebra::DMatrix;

use factor_core::scalar::Scalar;
use factor_testing::samples::Sampler;

/// Where a formula comes from and what it claims.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Label {
    /// The document's file name.
    pub document: String,
    /// The equation number or section, as printed (`"(4)"`, `"§IV-A ∂u/∂φ"`).
    pub equation: String,
    /// What the formula claims to be, in words.
    pub claim: String,
    /// The variables and convention the document states for it.
    pub convention: String,
    /// A known erratum: the audit still reports it, but it does not fail the
    /// run (`slamjac audit` exits non-zero only for unexpected disagreements).
    pub known_erratum: Option<String>,
}

impl Label {
    /// A label; `known_erratum` is `Some` only once the audit has found it.
    pub fn new(
        document: impl Into<String>,
        equation: impl Into<String>,
        claim: impl Into<String>,
        convention: impl Into<String>,
        known_erratum: Option<&str>,
    ) -> Self {
        Label {
            document: document.into(),
            equation: equation.into(),
            claim: claim.into(),
            convention: convention.into(),
            known_erratum: known_erratum.map(str::to_string),
        }
    }
}

/// What a formula claims about its map.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Claim {
    /// The printed matrix is the Jacobian of the map at the point.
    Jacobian,
    /// The printed vector is the map's value at the point.
    Value,
}

/// A printed formula evaluated at a point.
#[derive(Debug, Clone, PartialEq)]
pub enum Printed {
    /// The matrix the document's formula gives.
    Evaluated(DMatrix<f64>),
    /// The formula is not well formed as printed (dimensions that do not
    /// multiply, a missing block); the reason.
    Malformed(String),
}

/// One audited formula: the claim that [`Derivation::printed`] is the
/// Jacobian of [`Derivation::map`] w.r.t. its input, at
/// [`Derivation::point`]. For a derivative on a manifold the input is the
/// tangent `δ` and the point is zero. The map's other quantities are
/// parameters, so the symbolic engine renders the correction in their names.
pub trait Derivation {
    /// The formula's label.
    fn label(&self) -> Label;
    /// Where the map is differentiated.
    fn point(&self) -> Vec<f64>;
    /// The map's parameters: names (LaTeX) and values at this sample
    /// ([`crate::transcription::Parameters`] writes stored values and names
    /// them from their layouts).
    fn parameters(&self) -> Vec<(String, f64)>;
    /// Names (LaTeX) of the map's inputs.
    fn input_names(&self) -> Vec<String>;
    /// The map, generic over the scalar: `x` the input, `p` the parameters in
    /// the order of [`Derivation::parameters`] (read back value by value with
    /// [`factor_core::storage::ScalarReader`]).
    fn map<S: Scalar>(&self, x: &[S], p: &[S]) -> Vec<S>;
    /// The document's formula, as printed, at this sample.
    fn printed(&self) -> Printed;
    /// Whether the formula claims a Jacobian (the default) or a value.
    fn claim(&self) -> Claim {
        Claim::Jacobian
    }
    /// Truths under other conventions the document might have meant (tangent
    /// ordering, perturbation side, normalisation), with a description each.
    fn conventions(&self) -> Vec<(String, DMatrix<f64>)> {
        Vec::new()
    }
    /// For a claim of agreement to first order (whose Jacobians are
    /// compared): why the printed side is not right even at the point, the
    /// two sides' values differing there; `None` when they agree (or the
    /// claim is no such claim).
    fn gap(&self) -> Option<String> {
        None
    }
}

/// What the printed formula should equal: the Jacobian of the map (one
/// dual-number pass per input) or its value (a column), at the point.
pub fn truth<D: Derivation>(d: &D) -> DMatrix<f64> {
    if d.claim() == Claim::Value {
        let parameters: Vec<f64> = d.parameters().iter().map(|(_, v)| *v).collect();
        let y = d.map(&d.point(), &parameters);
        return DMatrix::from_column_slice(y.len(), 1, &y);
    }
    let parameters: Vec<Dual<1>> = d
        .parameters()
        .iter()
        .map(|(_, v)| Dual::constant(*v))
        .collect();
    dual_jacobian(&d.point(), |x| d.map(x, &parameters))
}

/// The Jacobian at `point` of `f`, written for dual numbers, one pass per
/// input: the truth of a derivation, or of a convention it offers.
pub fn dual_jacobian(point: &[f64], f: impl Fn(&[Dual<1>]) -> Vec<Dual<1>>) -> DMatrix<f64> {
    let columns: Vec<Vec<f64>> = (0..point.len())
        .map(|j| {
            let x: Vec<Dual<1>> = point
                .iter()
                .enumerate()
                .map(|(i, &v)| {
                    if i == j {
                        Dual::variable(v, 0)
                    } else {
                        Dual::constant(v)
                    }
                })
                .collect();
            f(&x).iter().map(|v| v.eps[0]).collect()
        })
        .collect();
    let rows = columns.first().map_or(0, Vec::len);
    DMatrix::from_fn(rows, point.len(), |r, c| columns[c][r])
}

/// How a derivation type is sampled: one well-conditioned instance per call.
pub type SampleFn<D> = fn(&mut Sampler) -> D;
