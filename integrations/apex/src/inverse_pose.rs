//! A factor written on a world-to-camera pose `T` served on the
//! body-to-world pose `X = T⁻¹` apex holds: where the documents' factors
//! (world-to-camera, [`factor_core::lie::Se3`]) meet factors on the
//! body-to-world pose of the same camera (g2o's edges, GTSAM's between
//! factor), one apex `SE3` variable holds `X` and [`InversePose`] hands the
//! served factor `T`.
//!
//! apex retracts `X ← X Exp(η)`, `η = [ρ, θ]`; then `T ← Exp(−η) T = T
//! Exp(−Ad_X η)` with `Ad_X = [[R, [t]× R], [0, R]]` (`X = (R, t)`), so the
//! Jacobian block of the served factor w.r.t. `T`'s own right chart becomes
//! `J_X = −J_T Ad_X`.

use std::sync::Arc;

use apex_solver::core::variable::ManifoldVariable;
use apex_solver::factors::Factor;
use faer::prelude::ReborrowMut;
use nalgebra::{Matrix3, Matrix6, Quaternion, UnitQuaternion, Vector3};

/// A served factor whose first apex variable is a world-to-camera pose,
/// registered on the body-to-world pose (its inverse).
pub struct InversePose {
    inner: Arc<dyn Factor + Send + Sync>,
}

impl InversePose {
    /// `inner`, its first variable (an `SE3`, columns 0–5) taken as the
    /// inverse of the apex variable it is registered on.
    pub fn new(inner: Arc<dyn Factor + Send + Sync>) -> Self {
        InversePose { inner }
    }
}

/// `(R, t)` of apex's `SE3` parameters `[tx, ty, tz, qw, qx, qy, qz]`.
fn rotation_translation(params: &[f64]) -> (UnitQuaternion<f64>, Vector3<f64>) {
    let q = UnitQuaternion::from_quaternion(Quaternion::new(
        params[3], params[4], params[5], params[6],
    ));
    (q, Vector3::new(params[0], params[1], params[2]))
}

impl Factor for InversePose {
    fn linearize(
        &self,
        params: &[&[f64]],
        residual: &mut [f64],
        jacobian: Option<faer::mat::MatMut<'_, f64>>,
    ) {
        let (q, t) = rotation_translation(params[0]);
        let (q_inv, t_inv) = (q.inverse(), -(q.inverse() * t));
        let inverse = [
            t_inv.x, t_inv.y, t_inv.z, q_inv.w, q_inv.i, q_inv.j, q_inv.k,
        ];
        let mut moved: Vec<&[f64]> = params.to_vec();
        moved[0] = &inverse;
        let Some(mut jacobian) = jacobian else {
            self.inner.linearize(&moved, residual, None);
            return;
        };
        self.inner
            .linearize(&moved, residual, Some(jacobian.rb_mut()));
        let r: Matrix3<f64> = q.to_rotation_matrix().into_inner();
        let mut adjoint = Matrix6::zeros();
        adjoint.fixed_view_mut::<3, 3>(0, 0).copy_from(&r);
        adjoint
            .fixed_view_mut::<3, 3>(0, 3)
            .copy_from(&(t.cross_matrix() * r));
        adjoint.fixed_view_mut::<3, 3>(3, 3).copy_from(&r);
        for row in 0..jacobian.nrows() {
            let j_t: [f64; 6] = std::array::from_fn(|c| jacobian[(row, c)]);
            for c in 0..6 {
                jacobian[(row, c)] = -(0..6).map(|k| j_t[k] * adjoint[(k, c)]).sum::<f64>();
            }
        }
    }

    fn residual_dim(&self) -> usize {
        self.inner.residual_dim()
    }

    fn jacobian_shape(&self) -> (usize, usize) {
        self.inner.jacobian_shape()
    }

    fn whitens_internally(&self) -> bool {
        self.inner.whitens_internally()
    }

    fn validate_variables(&self, variables: &[&dyn ManifoldVariable]) -> Result<(), String> {
        self.inner.validate_variables(variables)
    }
}
