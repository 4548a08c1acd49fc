//! A factor's noise model, in its residual space: the residual `r` is
//! whitened to `S r`, so the cost is `½ ‖S r‖²` (or `½ ρ(‖S r‖²)` with a
//! robust loss). The one model every solver path takes: apex-solver's
//! adapter (`factor_apex::builder`), the Schur-complement solver
//! (`factor_schur::Problem::add_weighted`), pose-only tracking
//! (`factor_tracking::PoseProblem::add`) and problem files (`"noise"`).

use nalgebra::{DMatrix, DVector};

/// How a residual is whitened (`S`, with `Sᵀ S` the information).
///
/// ```
/// use factor_core::noise::Noise;
///
/// let noise = Noise::Sigmas(vec![0.5, 2.0]);
/// noise.check(2).unwrap();
/// assert_eq!(noise.sqrt_information(2)[(0, 0)], 2.0);
/// assert!(Noise::Sigma(0.0).check(2).is_err());
/// ```
#[derive(Debug, Clone, PartialEq)]
pub enum Noise {
    /// No whitening (`S = I`).
    Unit,
    /// One standard deviation for every component (`S = I / σ`).
    Sigma(f64),
    /// A standard deviation per component (`S = diag(1 / σᵢ)`).
    Sigmas(Vec<f64>),
    /// A square-root information matrix `S` (`Sᵀ S` is the information),
    /// residual-dimension square.
    SqrtInformation(DMatrix<f64>),
}

impl Noise {
    /// Checks that the model fits a residual of `dim` components: as many
    /// standard deviations as components, each finite and above 0; a
    /// `dim × dim` square-root information with finite entries.
    ///
    /// # Errors
    ///
    /// What does not fit, in words.
    pub fn check(&self, dim: usize) -> Result<(), String> {
        let deviations =
            |sigmas: &[f64]| match sigmas.iter().find(|s| !(s.is_finite() && **s > 0.0)) {
                Some(bad) => Err(format!(
                    "standard deviation {bad} is not a finite number above 0"
                )),
                None => Ok(()),
            };
        match self {
            Noise::Unit => Ok(()),
            Noise::Sigma(sigma) => deviations(&[*sigma]),
            Noise::Sigmas(sigmas) if sigmas.len() != dim => Err(format!(
                "{} standard deviations for a residual of {dim}",
                sigmas.len()
            )),
            Noise::Sigmas(sigmas) => deviations(sigmas),
            Noise::SqrtInformation(s) if s.shape() != (dim, dim) => Err(format!(
                "square-root information is {}×{}, the residual has {dim} components",
                s.nrows(),
                s.ncols()
            )),
            Noise::SqrtInformation(s) if s.iter().any(|x| !x.is_finite()) => {
                Err("a square-root information entry is not finite".into())
            }
            Noise::SqrtInformation(_) => Ok(()),
        }
    }

    /// `S` for a residual of `dim` components, of a model that passed
    /// [`Noise::check`].
    pub fn sqrt_information(&self, dim: usize) -> DMatrix<f64> {
        match self {
            Noise::Unit => DMatrix::identity(dim, dim),
            Noise::Sigma(sigma) => DMatrix::identity(dim, dim) / *sigma,
            Noise::Sigmas(sigmas) => {
                DMatrix::from_diagonal(&DVector::from_iterator(dim, sigmas.iter().map(|s| 1.0 / s)))
            }
            Noise::SqrtInformation(s) => s.clone(),
        }
    }
}
