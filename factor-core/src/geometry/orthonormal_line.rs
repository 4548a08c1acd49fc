//! The orthonormal representation `(U, W) ∈ SO(3) × SO(2)` of a Plücker line
//! (Bartoli and Sturm; document 000 §III), the line's 4-dof parametrisation:
//!
//! `[n | v] = [n/|n|, v/|v|, n×v/|n×v|] · diag(|n|, |v|)` so
//! `U = [n/|n|, v/|v|, n×v/|n×v|]` and `W = [[w₁, −w₂], [w₂, w₁]]` with
//! `(w₁, w₂) = (|n|, |v|) / |(|n|, |v|)|`. Back: `n = w₁ u₁`, `v = w₂ u₂`
//! (the Plücker line scaled to unit norm).

use nalgebra::{Matrix3, Vector3};

use crate::geometry::PluckerLine;
use crate::lie::{So2, So3};
use crate::linalg::{cross, dot, norm, scale};
use crate::manifold::{Manifold, Perturbation};
use crate::scalar::Scalar;
use crate::storage::{Layout, Storage, StorageError};
use crate::validation::{exceeds, number_text, within};

/// A line as `(U, W)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrthonormalLine<S> {
    /// `U`, stored as a unit quaternion.
    pub u: So3<S>,
    /// `W`, stored as `(w₁, w₂)`.
    pub w: So2<S>,
}

impl<S: Scalar> OrthonormalLine<S> {
    /// From `U` and `W`.
    pub fn new(u: So3<S>, w: So2<S>) -> Self {
        OrthonormalLine { u, w }
    }

    /// From a Plücker line with `|n| > 0`, `|v| > 0`, `n · v = 0` (not checked;
    /// see [`OrthonormalLine::try_from_plucker`]).
    pub fn from_plucker(line: &PluckerLine<S>) -> Self {
        let (n, v) = (line.normal, line.direction);
        let (n_norm, v_norm) = (norm(&n), norm(&v));
        let u1 = scale(n_norm.recip(), &n);
        let u2 = scale(v_norm.recip(), &v);
        let u3 = cross(&u1, &u2);
        let u = Matrix3::from_columns(&[u1, u2, u3]);
        let sigma = (n_norm * n_norm + v_norm * v_norm).sqrt().recip();
        Self::new(
            So3::from_matrix(&u),
            So2::new(n_norm * sigma, v_norm * sigma),
        )
    }

    /// The Plücker line `[w₁ u₁, w₂ u₂]` (unit norm), document 000 (9).
    pub fn to_plucker(&self) -> PluckerLine<S> {
        let u = self.u.matrix();
        let u1: Vector3<S> = u.column(0).into_owned();
        let u2: Vector3<S> = u.column(1).into_owned();
        PluckerLine::new(scale(self.w.cos, &u1), scale(self.w.sin, &u2))
    }
}

impl OrthonormalLine<f64> {
    /// Checked conversion: `n` and `v` non-zero and orthogonal to `1e-9`
    /// relative (`|n · v| ≤ 1e-9 |n| |v|`); any common scale is accepted.
    pub fn try_from_plucker(line: &PluckerLine<f64>) -> Result<Self, StorageError> {
        let (n, v) = (line.normal, line.direction);
        let (n_norm, v_norm) = (n.norm(), v.norm());
        if !exceeds(v_norm, 0.0) {
            return Err(StorageError::new("line direction v has zero norm").within("direction"));
        }
        if !exceeds(n_norm, 0.0) {
            return Err(StorageError::new(
                "line normal n has zero norm (the line passes through the world origin, where \
                 the orthonormal representation is undefined)",
            )
            .within("normal"));
        }
        let cosine = dot(&n, &v) / (n_norm * v_norm);
        if !within(cosine, 1e-9) {
            return Err(StorageError::new(format!(
                "not a Plücker line: n · v = {} (cosine {}), must be 0",
                number_text(dot(&n, &v)),
                number_text(cosine)
            )));
        }
        Ok(Self::from_plucker(line))
    }
}

/// Stored `{u: [qx, qy, qz, qw], w: [cos, sin]}`; users write the Plücker
/// coordinates `{normal, direction}` at any scale, converted by
/// [`OrthonormalLine::try_from_plucker`].
impl<S: Scalar> Storage<S> for OrthonormalLine<S> {
    type With<T: Scalar> = OrthonormalLine<T>;
    const SCALARS: usize = 6;
    fn layout() -> Layout {
        Layout::Record(vec![
            ("u", <So3<S> as Storage<S>>::layout()),
            ("w", <So2<S> as Storage<S>>::layout()),
        ])
    }
    fn map_scalars<T: Scalar>(&self, f: &mut impl FnMut(S) -> T) -> OrthonormalLine<T> {
        OrthonormalLine::new(self.u.map_scalars(f), self.w.map_scalars(f))
    }
    fn read_scalars(next: &mut impl FnMut() -> S) -> Self {
        let u = So3::read_scalars(next);
        OrthonormalLine::new(u, So2::read_scalars(next))
    }
    fn input_layout() -> Layout {
        <PluckerLine<S> as Storage<S>>::layout()
    }
    fn from_input(input: &[f64]) -> Result<Vec<f64>, StorageError> {
        let plucker = <PluckerLine<f64> as Storage<f64>>::from_scalars(input);
        let line = OrthonormalLine::<f64>::try_from_plucker(&plucker)?;
        Ok(<OrthonormalLine<f64> as Storage<f64>>::to_scalars(&line))
    }
}

/// Tangent `[δΘ, δρ]` (4). Left (document 000): `U ← Exp(δΘ) U`,
/// `W ← R(δρ) W`; right: `U ← U Exp(δΘ)`, `W ← W R(δρ)`.
impl<S: Scalar> Manifold<S> for OrthonormalLine<S> {
    const DIM: usize = 4;
    fn retract(&self, delta: &[S], side: Perturbation) -> Self {
        Self::new(
            self.u.retract(&delta[..3], side),
            self.w.retract(&delta[3..], side),
        )
    }
    fn retract_first_order(&self, delta: &[S], side: Perturbation) -> Self {
        Self::new(
            self.u.retract_first_order(&delta[..3], side),
            self.w.retract_first_order(&delta[3..], side),
        )
    }
    fn tangent_description(side: Perturbation) -> &'static str {
        match side {
            Perturbation::Left => {
                "left: U ← Exp(δΘ) U, W ← R(δρ) W, columns [δΘ_x, δΘ_y, δΘ_z, δρ]"
            }
            Perturbation::Right => {
                "right: U ← U Exp(δΘ), W ← W R(δρ), columns [δΘ_x, δΘ_y, δΘ_z, δρ]"
            }
        }
    }
}
