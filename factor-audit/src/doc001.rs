//! Document 001 (`001_85032ab900231dbd.txt`): the free-line factor's camera
//! position (3.4)–(3.6) and its Jacobians w.r.t. the body pose `T_BW` (§4),
//! transcribed as printed.
//!
//! Notation as the document and the specification use it:
//! - body pose `T_BW`: `X_B = C_BW X_W + _B t_BW`, perturbed on the **right**,
//!   `C_BW ← C_BW Exp(δφ)`, `_B t_BW ← _B t_BW + C_BW δt`, tangent `[δφ, δt]`
//!   (4.1)–(4.2);
//! - extrinsics `T_CB` (constant): `X_C = C_CB X_B + _C t_CB`;
//! - `C_WB = C_BWᵀ`, `C_BC = C_CBᵀ`; a left subscript names the frame a
//!   vector is expressed in, so `_W t_CB = C_WB C_BC _C t_CB` and
//!   `_W t_BW = C_WB _B t_BW`, as (3.5) expands them;
//! - measurement `ñ = f₁ × f₂ / ‖f₁ × f₂‖` (camera frame) and its world
//!   form `_W ñ = C_BWᵀ C_CBᵀ ñ` (so `ñᵀ C_CB C_BW = _W ñᵀ`, (4.30));
//! - line `[q_WL, d_L]`: anchor `p_L = R(q_WL) [0, 0, d_L]`, direction
//!   `x_L = R(q_WL) [1, 0, 0]`; `v = (p_C − p_L)/‖p_C − p_L‖` (4.7).

use nalgebra::{DMatrix, Matrix3, RowVector3, Vector3};

use crate::derivation::{Claim, Derivation, Label, Printed, truth};
use crate::transcription::{Parameters, matrix, stored_names};
use factor_core::geometry::{FreeLine, bearing_plane_normal};
use factor_core::lie::Se3;
use factor_core::lie::so3::hat;
use factor_core::linalg::{norm, scale};
use factor_core::manifold::{Manifold, Perturbation};
use factor_core::scalar::Scalar;
use factor_core::storage::Storage;
use factor_testing::samples::Sampler;
use slam_factors::FreeLineFactor;
use slam_factors::free_line::free_line_residual;

/// The document's file name.
pub const DOCUMENT: &str = "001_85032ab900231dbd.txt";

fn label(
    equation: &'static str,
    claim: &'static str,
    convention: &'static str,
    erratum: Option<&'static str>,
) -> Label {
    Label::new(DOCUMENT, equation, claim, convention, erratum)
}

/// Every quantity of the factor, as it stores them (25 scalars), named by
/// its layout (`body_pose.rotation.qx`).
fn factor_parameters(f: &FreeLineFactor<f64>) -> Vec<(String, f64)> {
    Parameters::new().with("", f).into()
}

/// The body pose `T_BW` and the extrinsics `T_CB`.
const BODY_POSE: &str = "T_{BW}";
const EXTRINSICS: &str = "T_{CB}";

/// The camera centre in the world, `p_C = −C_BWᵀ (C_CBᵀ _C t_CB + _B t_BW)`:
/// the point with `X_C = 0`.
fn camera_centre<S: Scalar>(body_pose: &Se3<S>, extrinsics: &Se3<S>) -> Vector3<S> {
    let in_body =
        extrinsics.rotation.inverse_rotate(&extrinsics.translation) + body_pose.translation;
    -body_pose.rotation.inverse_rotate(&in_body)
}

const ROTATION_TANGENT: [&str; 3] = ["\\delta\\phi_1", "\\delta\\phi_2", "\\delta\\phi_3"];
const TRANSLATION_TANGENT: [&str; 3] = ["\\delta t_1", "\\delta t_2", "\\delta t_3"];

/// Which half of the body-pose tangent `[δφ, δt]` a formula differentiates by.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Half {
    /// `δφ`, with `δt = 0`.
    Rotation,
    /// `δt`, with `δφ = 0`.
    Translation,
}

impl Half {
    /// The full tangent `[δφ, δt]` with this half `x` and the other zero.
    fn tangent<S: Scalar>(self, x: &[S]) -> [S; 6] {
        let z = S::zero();
        match self {
            Half::Rotation => [x[0], x[1], x[2], z, z, z],
            Half::Translation => [z, z, z, x[0], x[1], x[2]],
        }
    }
    fn names(self) -> Vec<String> {
        match self {
            Half::Rotation => ROTATION_TANGENT,
            Half::Translation => TRANSLATION_TANGENT,
        }
        .map(String::from)
        .to_vec()
    }
}

/// The sampled context of §3–§4: one free-line factor, and the side the
/// body pose is perturbed on (the document's right, or the left for the
/// alternative truth offered by [`Derivation::conventions`]).
#[derive(Debug, Clone)]
pub struct FreeLineContext {
    /// Body pose, extrinsics, line and bearings.
    pub factor: FreeLineFactor<f64>,
    /// The body pose's perturbation side.
    pub side: Perturbation,
}

impl FreeLineContext {
    fn sample(s: &mut Sampler) -> Self {
        FreeLineContext {
            factor: s.free_line(),
            side: Perturbation::Right,
        }
    }
    fn on_the_left(&self) -> Self {
        FreeLineContext {
            factor: self.factor.clone(),
            side: Perturbation::Left,
        }
    }
    /// `C_BW`.
    fn c_bw(&self) -> Matrix3<f64> {
        self.factor.body_pose.rotation.matrix()
    }
    /// `C_CB`.
    fn c_cb(&self) -> Matrix3<f64> {
        self.factor.extrinsics.rotation.matrix()
    }
    /// `C_WB = C_BWᵀ`.
    fn c_wb(&self) -> Matrix3<f64> {
        self.c_bw().transpose()
    }
    /// `C_BC = C_CBᵀ`.
    fn c_bc(&self) -> Matrix3<f64> {
        self.c_cb().transpose()
    }
    /// `_C t_CB`.
    fn t_cb(&self) -> Vector3<f64> {
        self.factor.extrinsics.translation
    }
    /// `_B t_BW`.
    fn t_bw(&self) -> Vector3<f64> {
        self.factor.body_pose.translation
    }
    /// `_W t_CB = C_WB C_BC _C t_CB` (`t_CB` expressed in the world).
    fn w_t_cb(&self) -> Vector3<f64> {
        self.c_wb() * self.c_bc() * self.t_cb()
    }
    /// `_W t_BW = C_WB _B t_BW` (`t_BW` expressed in the world).
    fn w_t_bw(&self) -> Vector3<f64> {
        self.c_wb() * self.t_bw()
    }
    /// `_C ñ`.
    fn n_c(&self) -> Vector3<f64> {
        bearing_plane_normal(&self.factor.bearing_start, &self.factor.bearing_end)
    }
    /// `_W ñ = C_BWᵀ C_CBᵀ _C ñ`.
    fn n_w(&self) -> Vector3<f64> {
        self.c_bw().transpose() * self.c_cb().transpose() * self.n_c()
    }
    /// `_W x_L`.
    fn x_l(&self) -> Vector3<f64> {
        self.factor.line.direction()
    }
    /// `_W p_L`.
    fn p_l(&self) -> Vector3<f64> {
        self.factor.line.anchor()
    }
    /// `_W p_C` by (3.6) (the same as the factor's camera centre).
    fn p_c(&self) -> Vector3<f64> {
        camera_centre(&self.factor.body_pose, &self.factor.extrinsics)
    }
    /// `‖_W p_C − _W p_L‖`.
    fn distance(&self) -> f64 {
        (self.p_c() - self.p_l()).norm()
    }
    /// `v` (4.7).
    fn v(&self) -> Vector3<f64> {
        (self.p_c() - self.p_l()) / self.distance()
    }
    /// `I − v vᵀ`.
    fn projector(&self) -> Matrix3<f64> {
        let v = self.v();
        Matrix3::identity() - v * v.transpose()
    }

    /// The factor with its body pose perturbed by `half` = `x` on
    /// [`FreeLineContext::side`].
    fn perturbed<S: Scalar>(&self, half: Half, x: &[S], p: &[S]) -> FreeLineFactor<S> {
        let mut f = FreeLineFactor::from_scalars(p);
        f.body_pose = f.body_pose.retract(&half.tangent(x), self.side);
        f
    }
}

/// The alternative truth of a body-pose Jacobian: the same map with `T_BW`
/// perturbed on the left.
fn left_convention<D: Derivation>(alt: D) -> Vec<(String, DMatrix<f64>)> {
    vec![(
        "left perturbation T_BW ← Exp(δ) T_BW (tangent [δφ, δt])".into(),
        truth(&alt),
    )]
}

/// (3.4), (3.5), (3.6): three printed forms of the camera position, value
/// claims. The map is the camera centre as a function of the body pose
/// `[q_BW, t_BW]`, the extrinsics being parameters.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CameraPositionForm {
    /// (3.4) `−(_W t_CB + _W t_BW)`.
    WorldTranslations,
    /// (3.5) `−(C_WB C_BC _C t_CB + C_WB _B t_BW)`.
    Expanded,
    /// (3.6) `−C_WB (C_BC _C t_CB + _B t_BW)`.
    Factored,
}

/// The camera position `_W p̂_C` in one of its printed forms.
pub struct CameraPosition(pub FreeLineContext, pub CameraPositionForm);

impl Derivation for CameraPosition {
    fn label(&self) -> Label {
        match self.1 {
            CameraPositionForm::WorldTranslations => label(
                "(3.4)",
                "camera position _W p̂_C = −(_W t̂_CB + _W t̂_BW)",
                "X_B = C_BW X_W + _B t_BW, X_C = C_CB X_B + _C t_CB; reading _W t_CB = C_WB C_BC _C t_CB \
                 and _W t_BW = C_WB _B t_BW (t_CB, t_BW re-expressed in W, as (3.5) expands them)",
                None,
            ),
            CameraPositionForm::Expanded => label(
                "(3.5)",
                "camera position _W p̂_C = −(Ĉ_WB C_BC _C t_CB + Ĉ_WB _B t̂_BW)",
                "X_B = C_BW X_W + _B t_BW, X_C = C_CB X_B + _C t_CB; C_WB = C_BWᵀ, C_BC = C_CBᵀ",
                None,
            ),
            CameraPositionForm::Factored => label(
                "(3.6)",
                "camera position _W p̂_C = −Ĉ_WB (C_BC _C t_CB + _B t̂_BW)",
                "X_B = C_BW X_W + _B t_BW, X_C = C_CB X_B + _C t_CB; C_WB = C_BWᵀ, C_BC = C_CBᵀ",
                None,
            ),
        }
    }
    fn point(&self) -> Vec<f64> {
        self.0.factor.body_pose.to_scalars()
    }
    fn parameters(&self) -> Vec<(String, f64)> {
        Parameters::new()
            .with(EXTRINSICS, &self.0.factor.extrinsics)
            .into()
    }
    fn input_names(&self) -> Vec<String> {
        stored_names::<Se3<f64>>(BODY_POSE)
    }
    fn map<S: Scalar>(&self, x: &[S], p: &[S]) -> Vec<S> {
        camera_centre(&Se3::from_scalars(x), &Se3::from_scalars(p)).to_scalars()
    }
    fn printed(&self) -> Printed {
        let c = &self.0;
        let p = match self.1 {
            CameraPositionForm::WorldTranslations => -(c.w_t_cb() + c.w_t_bw()),
            CameraPositionForm::Expanded => -(c.c_wb() * c.c_bc() * c.t_cb() + c.c_wb() * c.t_bw()),
            CameraPositionForm::Factored => -(c.c_wb() * (c.c_bc() * c.t_cb() + c.t_bw())),
        };
        Printed::Evaluated(matrix(p))
    }
    fn claim(&self) -> Claim {
        Claim::Value
    }
}

/// (4.5): `∂ε₁/∂δφ = −_C ñᵀ C_CB C_BW _W x_L^∧` (1 × 3).
pub struct ParallelRotationJacobian(pub FreeLineContext);

impl Derivation for ParallelRotationJacobian {
    fn label(&self) -> Label {
        label(
            "(4.5)",
            "∂ε₁/∂δφ of ε₁ = _C ñᵀ C_CB C_BW _W x_L under C_BW ← C_BW Exp(δφ)",
            "T_BW right-perturbed (4.1)–(4.2), δt = 0; ^∧ = hat",
            None,
        )
    }
    fn point(&self) -> Vec<f64> {
        vec![0.0; 3]
    }
    fn parameters(&self) -> Vec<(String, f64)> {
        factor_parameters(&self.0.factor)
    }
    fn input_names(&self) -> Vec<String> {
        Half::Rotation.names()
    }
    fn map<S: Scalar>(&self, x: &[S], p: &[S]) -> Vec<S> {
        vec![free_line_residual(&self.0.perturbed(Half::Rotation, x, p))[0]]
    }
    fn printed(&self) -> Printed {
        let c = &self.0;
        let row: RowVector3<f64> = -(c.n_c().transpose() * c.c_cb() * c.c_bw() * hat(&c.x_l()));
        Printed::Evaluated(matrix(row))
    }
    fn conventions(&self) -> Vec<(String, DMatrix<f64>)> {
        left_convention(Self(self.0.on_the_left()))
    }
}

/// (4.6): `∂ε₁/∂δt = [0 0 0]`.
pub struct ParallelTranslationJacobian(pub FreeLineContext);

impl Derivation for ParallelTranslationJacobian {
    fn label(&self) -> Label {
        label(
            "(4.6)",
            "∂ε₁/∂δt of ε₁ = _C ñᵀ C_CB C_BW _W x_L under _B t_BW ← _B t_BW + C_BW δt",
            "T_BW right-perturbed (4.1)–(4.2), δφ = 0",
            None,
        )
    }
    fn point(&self) -> Vec<f64> {
        vec![0.0; 3]
    }
    fn parameters(&self) -> Vec<(String, f64)> {
        factor_parameters(&self.0.factor)
    }
    fn input_names(&self) -> Vec<String> {
        Half::Translation.names()
    }
    fn map<S: Scalar>(&self, x: &[S], p: &[S]) -> Vec<S> {
        vec![free_line_residual(&self.0.perturbed(Half::Translation, x, p))[0]]
    }
    fn printed(&self) -> Printed {
        Printed::Evaluated(DMatrix::zeros(1, 3))
    }
    fn conventions(&self) -> Vec<(String, DMatrix<f64>)> {
        left_convention(Self(self.0.on_the_left()))
    }
}

/// A vector `w` away from zero (norm in `[0.1, 3√3)`).
fn nonzero_vector(s: &mut Sampler) -> Vector3<f64> {
    loop {
        let w = s.vector3(3.0);
        if w.norm() > 0.1 {
            return w;
        }
    }
}

/// (4.14): `d‖w‖/dw = wᵀ/‖w‖`.
pub struct NormJacobian(pub Vector3<f64>);

impl Derivation for NormJacobian {
    fn label(&self) -> Label {
        label("(4.14)", "d‖w‖/dw = wᵀ/‖w‖", "w ∈ ℝ³, w ≠ 0", None)
    }
    fn point(&self) -> Vec<f64> {
        self.0.as_slice().to_vec()
    }
    fn parameters(&self) -> Vec<(String, f64)> {
        Vec::new()
    }
    fn input_names(&self) -> Vec<String> {
        stored_names::<Vector3<f64>>("w")
    }
    fn map<S: Scalar>(&self, x: &[S], _p: &[S]) -> Vec<S> {
        vec![norm(&Vector3::from_scalars(x))]
    }
    fn printed(&self) -> Printed {
        let w = self.0;
        Printed::Evaluated(matrix(w.transpose() / w.norm()))
    }
}

/// (4.15): `d(1/‖w‖)/dw = −wᵀ/‖w‖³`.
pub struct InverseNormJacobian(pub Vector3<f64>);

impl Derivation for InverseNormJacobian {
    fn label(&self) -> Label {
        label("(4.15)", "d(1/‖w‖)/dw = −wᵀ/‖w‖³", "w ∈ ℝ³, w ≠ 0", None)
    }
    fn point(&self) -> Vec<f64> {
        self.0.as_slice().to_vec()
    }
    fn parameters(&self) -> Vec<(String, f64)> {
        Vec::new()
    }
    fn input_names(&self) -> Vec<String> {
        stored_names::<Vector3<f64>>("w")
    }
    fn map<S: Scalar>(&self, x: &[S], _p: &[S]) -> Vec<S> {
        vec![norm(&Vector3::from_scalars(x)).recip()]
    }
    fn printed(&self) -> Printed {
        let w = self.0;
        Printed::Evaluated(matrix(-w.transpose() / w.norm().powi(3)))
    }
}

/// The two printed lines of (4.16).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NormalisationForm {
    /// `I/‖w‖ − w wᵀ/‖w‖³`.
    First,
    /// `(I − (w/‖w‖)(w/‖w‖)ᵀ)/‖w‖`.
    Second,
}

/// (4.16): `d(w/‖w‖)/dw`, in one of its two printed forms.
pub struct NormalisationJacobian(pub Vector3<f64>, pub NormalisationForm);

impl Derivation for NormalisationJacobian {
    fn label(&self) -> Label {
        match self.1 {
            NormalisationForm::First => label(
                "(4.16) first form",
                "d(w/‖w‖)/dw = I/‖w‖ − w wᵀ/‖w‖³",
                "w ∈ ℝ³, w ≠ 0",
                None,
            ),
            NormalisationForm::Second => label(
                "(4.16) second form",
                "d(w/‖w‖)/dw = (I − (w/‖w‖)(w/‖w‖)ᵀ)/‖w‖",
                "w ∈ ℝ³, w ≠ 0",
                None,
            ),
        }
    }
    fn point(&self) -> Vec<f64> {
        self.0.as_slice().to_vec()
    }
    fn parameters(&self) -> Vec<(String, f64)> {
        Vec::new()
    }
    fn input_names(&self) -> Vec<String> {
        stored_names::<Vector3<f64>>("w")
    }
    fn map<S: Scalar>(&self, x: &[S], _p: &[S]) -> Vec<S> {
        let w = Vector3::from_scalars(x);
        scale(norm(&w).recip(), &w).to_scalars()
    }
    fn printed(&self) -> Printed {
        let w = self.0;
        let n = w.norm();
        let m = match self.1 {
            NormalisationForm::First => Matrix3::identity() / n - w * w.transpose() / n.powi(3),
            NormalisationForm::Second => {
                let u = w / n;
                (Matrix3::identity() - u * u.transpose()) / n
            }
        };
        Printed::Evaluated(matrix(m))
    }
}

/// (4.17): `∂v/∂_W p_C = (I − v vᵀ)/‖_W p_C − _W p_L‖`, at the sampled camera
/// centre and line anchor.
pub struct BearingToAnchorJacobian(pub FreeLineContext);

impl Derivation for BearingToAnchorJacobian {
    fn label(&self) -> Label {
        label(
            "(4.17)",
            "∂v/∂_W p_C of v = (_W p_C − _W p_L)/‖_W p_C − _W p_L‖",
            "_W p_C ∈ ℝ³ additive; _W p_L = R(q_WL) [0, 0, d_L]",
            None,
        )
    }
    fn point(&self) -> Vec<f64> {
        self.0.p_c().to_scalars()
    }
    fn parameters(&self) -> Vec<(String, f64)> {
        Parameters::new().with("l", &self.0.factor.line).into()
    }
    fn input_names(&self) -> Vec<String> {
        stored_names::<Vector3<f64>>("p_C")
    }
    fn map<S: Scalar>(&self, x: &[S], p: &[S]) -> Vec<S> {
        let ray = Vector3::from_scalars(x) - FreeLine::from_scalars(p).anchor();
        scale(norm(&ray).recip(), &ray).to_scalars()
    }
    fn printed(&self) -> Printed {
        let c = &self.0;
        Printed::Evaluated(matrix(c.projector() / c.distance()))
    }
}

/// (4.26): `∂_W p_C/∂δφ = −(_W t_CB + _W t_BW)^∧`.
pub struct CameraPositionRotationJacobian(pub FreeLineContext);

impl Derivation for CameraPositionRotationJacobian {
    fn label(&self) -> Label {
        label(
            "(4.26)",
            "∂_W p_C/∂δφ of _W p_C = −C_WB (C_BC _C t_CB + _B t_BW) under C_BW ← C_BW Exp(δφ)",
            "T_BW right-perturbed (4.1)–(4.2), δt = 0; _W t_CB = C_WB C_BC _C t_CB, _W t_BW = C_WB _B t_BW",
            None,
        )
    }
    fn point(&self) -> Vec<f64> {
        vec![0.0; 3]
    }
    fn parameters(&self) -> Vec<(String, f64)> {
        factor_parameters(&self.0.factor)
    }
    fn input_names(&self) -> Vec<String> {
        Half::Rotation.names()
    }
    fn map<S: Scalar>(&self, x: &[S], p: &[S]) -> Vec<S> {
        let f = self.0.perturbed(Half::Rotation, x, p);
        camera_centre(&f.body_pose, &f.extrinsics).to_scalars()
    }
    fn printed(&self) -> Printed {
        let c = &self.0;
        Printed::Evaluated(matrix(-hat(&(c.w_t_cb() + c.w_t_bw()))))
    }
    fn conventions(&self) -> Vec<(String, DMatrix<f64>)> {
        left_convention(Self(self.0.on_the_left()))
    }
}

/// (4.27): `∂_W p_C/∂δt = −I`.
pub struct CameraPositionTranslationJacobian(pub FreeLineContext);

impl Derivation for CameraPositionTranslationJacobian {
    fn label(&self) -> Label {
        label(
            "(4.27)",
            "∂_W p_C/∂δt of _W p_C = −C_WB (C_BC _C t_CB + _B t_BW) under _B t_BW ← _B t_BW + C_BW δt",
            "T_BW right-perturbed (4.1)–(4.2), δφ = 0",
            None,
        )
    }
    fn point(&self) -> Vec<f64> {
        vec![0.0; 3]
    }
    fn parameters(&self) -> Vec<(String, f64)> {
        factor_parameters(&self.0.factor)
    }
    fn input_names(&self) -> Vec<String> {
        Half::Translation.names()
    }
    fn map<S: Scalar>(&self, x: &[S], p: &[S]) -> Vec<S> {
        let f = self.0.perturbed(Half::Translation, x, p);
        camera_centre(&f.body_pose, &f.extrinsics).to_scalars()
    }
    fn printed(&self) -> Printed {
        Printed::Evaluated(matrix(-Matrix3::<f64>::identity()))
    }
    fn conventions(&self) -> Vec<(String, DMatrix<f64>)> {
        left_convention(Self(self.0.on_the_left()))
    }
}

/// (4.33): `∂ε₂/∂δφ = −_W ñᵀ ((I − v vᵀ)(_W t_CB + _W t_BW)^∧/‖_W p_C − _W p_L‖ + v^∧)`,
/// the chain (4.12) of (4.17) and (4.26) plus the rotation term `−_W ñᵀ v^∧`
/// of (4.9).
pub struct DistanceRotationJacobian(pub FreeLineContext);

impl Derivation for DistanceRotationJacobian {
    fn label(&self) -> Label {
        label(
            "(4.33)",
            "∂ε₂/∂δφ of ε₂ = _C ñᵀ C_CB C_BW v under C_BW ← C_BW Exp(δφ)",
            "T_BW right-perturbed (4.1)–(4.2), δt = 0; _W ñ = C_BWᵀ C_CBᵀ _C ñ (so _C ñᵀ C_CB C_BW = _W ñᵀ, (4.30)); \
             _W t_CB = C_WB C_BC _C t_CB, _W t_BW = C_WB _B t_BW",
            None,
        )
    }
    fn point(&self) -> Vec<f64> {
        vec![0.0; 3]
    }
    fn parameters(&self) -> Vec<(String, f64)> {
        factor_parameters(&self.0.factor)
    }
    fn input_names(&self) -> Vec<String> {
        Half::Rotation.names()
    }
    fn map<S: Scalar>(&self, x: &[S], p: &[S]) -> Vec<S> {
        vec![free_line_residual(&self.0.perturbed(Half::Rotation, x, p))[1]]
    }
    fn printed(&self) -> Printed {
        let c = &self.0;
        let inner = c.projector() * hat(&(c.w_t_cb() + c.w_t_bw())) / c.distance() + hat(&c.v());
        let row: RowVector3<f64> = -(c.n_w().transpose() * inner);
        Printed::Evaluated(matrix(row))
    }
    fn conventions(&self) -> Vec<(String, DMatrix<f64>)> {
        left_convention(Self(self.0.on_the_left()))
    }
}

/// (4.38): `∂ε₂/∂δt = −_W ñᵀ (I − v vᵀ)/‖_W p_C − _W p_L‖`, the chain (4.13)
/// of (4.17) and (4.27).
pub struct DistanceTranslationJacobian(pub FreeLineContext);

impl Derivation for DistanceTranslationJacobian {
    fn label(&self) -> Label {
        label(
            "(4.38)",
            "∂ε₂/∂δt of ε₂ = _C ñᵀ C_CB C_BW v under _B t_BW ← _B t_BW + C_BW δt",
            "T_BW right-perturbed (4.1)–(4.2), δφ = 0; _W ñ = C_BWᵀ C_CBᵀ _C ñ (so _C ñᵀ C_CB C_BW = _W ñᵀ, (4.30))",
            None,
        )
    }
    fn point(&self) -> Vec<f64> {
        vec![0.0; 3]
    }
    fn parameters(&self) -> Vec<(String, f64)> {
        factor_parameters(&self.0.factor)
    }
    fn input_names(&self) -> Vec<String> {
        Half::Translation.names()
    }
    fn map<S: Scalar>(&self, x: &[S], p: &[S]) -> Vec<S> {
        vec![free_line_residual(&self.0.perturbed(Half::Translation, x, p))[1]]
    }
    fn printed(&self) -> Printed {
        let c = &self.0;
        let row: RowVector3<f64> = -(c.n_w().transpose() * c.projector()) / c.distance();
        Printed::Evaluated(matrix(row))
    }
    fn conventions(&self) -> Vec<(String, DMatrix<f64>)> {
        left_convention(Self(self.0.on_the_left()))
    }
}

/// A context sampler for §3–§4.
pub fn sample_free_line_context(s: &mut Sampler) -> FreeLineContext {
    FreeLineContext::sample(s)
}

/// Every formula of this module, with its sampler.
pub fn audits() -> Vec<crate::Audit> {
    use crate::Audit;
    use CameraPositionForm::{Expanded, Factored, WorldTranslations};
    vec![
        Audit::of(|s| CameraPosition(FreeLineContext::sample(s), WorldTranslations)),
        Audit::of(|s| CameraPosition(FreeLineContext::sample(s), Expanded)),
        Audit::of(|s| CameraPosition(FreeLineContext::sample(s), Factored)),
        Audit::of(|s| ParallelRotationJacobian(FreeLineContext::sample(s))),
        Audit::of(|s| ParallelTranslationJacobian(FreeLineContext::sample(s))),
        Audit::of(|s| NormJacobian(nonzero_vector(s))),
        Audit::of(|s| InverseNormJacobian(nonzero_vector(s))),
        Audit::of(|s| NormalisationJacobian(nonzero_vector(s), NormalisationForm::First)),
        Audit::of(|s| NormalisationJacobian(nonzero_vector(s), NormalisationForm::Second)),
        Audit::of(|s| BearingToAnchorJacobian(FreeLineContext::sample(s))),
        Audit::of(|s| CameraPositionRotationJacobian(FreeLineContext::sample(s))),
        Audit::of(|s| CameraPositionTranslationJacobian(FreeLineContext::sample(s))),
        Audit::of(|s| DistanceRotationJacobian(FreeLineContext::sample(s))),
        Audit::of(|s| DistanceTranslationJacobian(FreeLineContext::sample(s))),
    ]
}

/// The chain rules of §4.2: (4.33) combines (4.17) and (4.26) (with the
/// rotation term `−_W ñᵀ v^∧` of (4.9), not a numbered link), (4.38)
/// combines (4.17) and (4.27).
pub fn chains() -> Vec<crate::chain::Chain> {
    use crate::chain::Chain;
    vec![
        Chain {
            document: DOCUMENT.into(),
            composed: "(4.33)".into(),
            links: ["(4.17)", "(4.26)"].map(String::from).to_vec(),
        },
        Chain {
            document: DOCUMENT.into(),
            composed: "(4.38)".into(),
            links: ["(4.17)", "(4.27)"].map(String::from).to_vec(),
        },
    ]
}
