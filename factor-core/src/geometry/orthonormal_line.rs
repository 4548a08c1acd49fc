//! The orthonormal representation `(U, W) ∈ SO(3) × SO(2)` of a Plücker line
//! (Bartoli and Sturm; document 000 §III), the line's 4-dof parametrisation:
//!
//! `[n | v] = [n/|n|, v/|v|, n×v/|n×v|] · diag(|n|, |v|)` so
//! `U = [n/|n|, v/|v|, n×v/|n×v|]` and `W = [[w₁, −w₂], [w₂, w₁]]` with
//! `(w₁, w₂) = (|n|, |v|) / |(|n|, |v|)|`. Back: `n = w₁ u₁`, `v = w₂ u₂`
//! (the Plücker line scaled to unit norm).

use nalgebra::{Matrix3, Vector3};

use crate::dual::Dual;
use crate::geometry::PluckerLine;
use crate::lie::{So2, So3};
use crate::linalg::{cross, dot, norm, norm_ratio, scale, unit_of};
use crate::manifold::{Manifold, NoLocal, Perturbation};
use crate::scalar::Scalar;
use crate::storage::{Layout, Storage, StorageError};
use crate::validation::{number_text, within};

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
        Self::from_parts(
            scale(n_norm.recip(), &n),
            scale(v_norm.recip(), &v),
            n_norm,
            v_norm,
        )
    }

    /// From the unit directions `u₁ = n/|n|`, `u₂ = v/|v|` and any positive
    /// multiple of `(|n|, |v|)`.
    fn from_parts(u1: Vector3<S>, u2: Vector3<S>, n_norm: S, v_norm: S) -> Self {
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

    /// The unit direction `d = u₂` (the direction of the Plücker line it
    /// was made from: `v / |v|`).
    pub fn direction(&self) -> Vector3<S> {
        self.u.matrix().column(1).into_owned()
    }

    /// The moment for the unit direction, `m = p × d` for any point `p` of
    /// the line: `(w₁ / w₂) u₁`, of length [`OrthonormalLine::distance`]
    /// (the Plücker normal `n` scaled to `|v| = 1`).
    pub fn moment(&self) -> Vector3<S> {
        scale(self.distance(), &self.u.matrix().column(0).into_owned())
    }

    /// The distance of the line from the origin, `w₁ / w₂ = |n| / |v|`.
    pub fn distance(&self) -> S {
        self.w.cos / self.w.sin
    }

    /// The point of the line closest to the origin, `d × m = −(w₁ / w₂) u₃`.
    pub fn closest_point(&self) -> Vector3<S> {
        scale(-self.distance(), &self.u.matrix().column(2).into_owned())
    }
}

impl OrthonormalLine<f64> {
    /// The line through the points `p` and `q`, directed from `p` to `q`
    /// (`n = p × q`, `v = q − p`, [`PluckerLine::from_points`]), checked by
    /// [`OrthonormalLine::try_from_plucker`]: the points must differ, and
    /// the line may not pass through the origin (`n = 0`), where the
    /// orthonormal representation is undefined.
    pub fn try_from_points(p: &Vector3<f64>, q: &Vector3<f64>) -> Result<Self, StorageError> {
        if p == q {
            return Err(StorageError::new(
                "the two points are the same: they do not define a line",
            ));
        }
        Self::try_from_plucker(&PluckerLine::from_points(p, q))
    }

    /// The line of `line`'s direction nearest it on the Klein quadric: `v`
    /// kept, `n` without its component along `v` (`n − (n · u₂) u₂`, exact
    /// for a Plücker line). A line through the origin (that `n` is zero) gets
    /// `u₁` orthogonal to `v` along the axis `v` leans on least.
    ///
    /// # Panics
    ///
    /// If `v` is zero or not finite (a stored Plücker line's is neither:
    /// its [`Storage::from_input`] refuses it).
    pub fn projected_from_plucker(line: &PluckerLine<f64>) -> Self {
        let v = line.direction;
        let u2 = unit_of(&v).expect("a Plücker line's direction is non-zero and finite");
        let moment = line.normal - scale(dot(&line.normal, &u2), &u2);
        let u1 = unit_of(&moment).unwrap_or_else(|| {
            let axis = Vector3::ith(u2.iamin(), 1.0);
            cross(&u2, &axis).normalize()
        });
        Self::from_parts(u1, u2, norm_ratio(&moment, &v), 1.0)
    }

    /// Checked conversion: `n` and `v` non-zero and orthogonal to `1e-9`
    /// relative (`|n · v| ≤ 1e-9 |n| |v|`); any common scale is accepted,
    /// over the whole `f64` range (each vector is normalised by its largest
    /// magnitude first, and only the distance `|n| / |v|` must be a finite,
    /// non-zero `f64`).
    pub fn try_from_plucker(line: &PluckerLine<f64>) -> Result<Self, StorageError> {
        let (n, v) = (line.normal, line.direction);
        let Some(u2) = unit_of(&v) else {
            return Err(StorageError::new("line direction v has zero norm").within("direction"));
        };
        let Some(u1) = unit_of(&n) else {
            return Err(StorageError::new(
                "line normal n has zero norm (the line passes through the world origin, where \
                 the orthonormal representation is undefined)",
            )
            .within("normal"));
        };
        let cosine = dot(&u1, &u2);
        if !within(cosine, 1e-9) {
            // `n · v` itself overflows or underflows at extreme scales: then
            // only the cosine is shown.
            let product = dot(&n, &v);
            let shown = if product.is_normal() {
                format!(
                    "n · v = {} (cosine {})",
                    number_text(product),
                    number_text(cosine)
                )
            } else {
                format!("n · v ≠ 0 (cosine {})", number_text(cosine))
            };
            return Err(StorageError::new(format!(
                "not a Plücker line: {shown}, must be 0"
            )));
        }
        // The line's distance from the origin, `|n| / |v|`, scales `u₁` and
        // `u₂` into `W`.
        let distance = norm_ratio(&n, &v);
        if !(distance.is_normal() && distance < f64::MAX) {
            return Err(StorageError::new(
                "the line's distance from the origin, |n| / |v|, is beyond the range of f64 \
                 (n and v differ in scale by a factor beyond 1e308)",
            ));
        }
        Ok(Self::from_parts(u1, u2, distance, 1.0))
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
    /// In closed form: `U` as [`So3`]'s, `W` as [`So2`]'s.
    #[inline(always)]
    fn seeded<const D: usize, const N: usize>(
        &self,
        side: Perturbation,
        offset: usize,
    ) -> <Self as Storage<S>>::With<Dual<N>>
    where
        S: Into<f64>,
    {
        OrthonormalLine::new(
            self.u.seeded::<3, N>(side, offset),
            self.w.seeded::<1, N>(side, offset + 3),
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
    fn local(&self, other: &Self, side: Perturbation, delta: &mut [S]) -> Result<(), NoLocal> {
        self.u.local(&other.u, side, &mut delta[..3])?;
        self.w.local(&other.w, side, &mut delta[3..])
    }
}
