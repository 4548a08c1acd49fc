//! Document 000 (`000_29653f4af9b68bb8.txt`): the line reprojection factor of
//! §III ((6)–(12)) and the plane factor of §IV ((13) and its links, §IV-B),
//! transcribed as printed.
//!
//! Conventions (the specification's, which are the document's): the pose `T`
//! maps world to camera and is perturbed on the left, `T ← Exp(δξ) T`,
//! `δξ = [δω, δρ]`; the line `(U, W)` on the left, `U ← Exp(δΘ) U`,
//! `W ← R(δρ) W`, tangent `[δΘ, δρ]`; the image line is `l = 𝒦 n_c` and the
//! observed endpoints are `p = [u, v, 1]`; the plane landmark `q_w` is
//! perturbed `q_w ← exp(δω) ⊗ q_w`.

use nalgebra::{DMatrix, Matrix2x3, Matrix3, Matrix4, Matrix6, SMatrix, Vector2, Vector3, Vector4};
use num_dual::DualSVec64;

use crate::derivation::dual_jacobian;
use crate::derivation::{Derivation, Label, Printed};
use crate::doc000_point::DOCUMENT;
use crate::transcription::{Parameters, matrix, stored_names};
use factor_core::geometry::plane::transpose_transform;
use factor_core::geometry::{InfinitePlane, Intrinsics, OrthonormalLine, PluckerLine};
use factor_core::lie::so3::{hat, left_jacobian_inverse, right_jacobian_inverse};
use factor_core::lie::{Quaternion, Se3};
use factor_core::linalg::normalized;
use factor_core::manifold::{Manifold, Perturbation};
use factor_core::scalar::Scalar;
use factor_core::storage::{ScalarReader, Storage};
use factor_testing::samples::Sampler;

fn label(
    equation: &'static str,
    claim: &'static str,
    convention: &'static str,
    erratum: Option<&'static str>,
) -> Label {
    Label::new(DOCUMENT, equation, claim, convention, erratum)
}

// ---------------------------------------------------------------------------
// §III: the line reprojection factor.
// ---------------------------------------------------------------------------

const POSE_TANGENT_NAMES: [&str; 6] = [
    "\\delta\\omega_1",
    "\\delta\\omega_2",
    "\\delta\\omega_3",
    "\\delta\\rho_1",
    "\\delta\\rho_2",
    "\\delta\\rho_3",
];

const LINE_TANGENT_NAMES: [&str; 4] = [
    "\\delta\\Theta_1",
    "\\delta\\Theta_2",
    "\\delta\\Theta_3",
    "\\delta\\rho",
];

/// A camera pose, a world line in view, intrinsics and two observed endpoint
/// pixels: the context of §III.
#[derive(Debug, Clone)]
pub struct LineContext {
    /// `K = [f_u, f_v, c_u, c_v]`.
    pub intrinsics: Intrinsics<f64>,
    /// The world-to-camera pose `T_w^c`.
    pub pose: Se3<f64>,
    /// The world line `(U, W)`.
    pub line: OrthonormalLine<f64>,
    /// The observed start pixel `(p^{1'}, p^{2'})`.
    pub start: Vector2<f64>,
    /// The observed end pixel `(q^{1'}, q^{2'})`.
    pub end: Vector2<f64>,
}

impl LineContext {
    fn sample(s: &mut Sampler) -> Self {
        let f = s.line_reprojection();
        LineContext {
            intrinsics: f.intrinsics,
            pose: f.pose,
            line: f.line,
            start: f.start,
            end: f.end,
        }
    }
    /// `L_w = [w₁ u₁, w₂ u₂]`.
    fn world_line(&self) -> PluckerLine<f64> {
        self.line.to_plucker()
    }
    /// `L_c = H L_w`.
    fn camera_line(&self) -> PluckerLine<f64> {
        self.world_line().transform(&self.pose)
    }
    /// `𝒦` as printed.
    fn k(&self) -> Matrix3<f64> {
        self.intrinsics.line_projection_matrix()
    }
    /// `l = 𝒦 n_c`.
    fn image_line(&self) -> Vector3<f64> {
        self.k() * self.camera_line().normal
    }
    /// (6) as printed: `1/√(l₁² + l₂²) [[p¹ − l₁ lᵀp/(l₁² + l₂²), p² − l₂ lᵀp/(l₁² + l₂²), 1], [q¹ …, q² …, 1]]`.
    fn dgamma_dl(&self) -> Matrix2x3<f64> {
        let l = self.image_line();
        let (p, q) = (homogeneous(&self.start), homogeneous(&self.end));
        let n2 = l.x * l.x + l.y * l.y;
        let (lp, lq) = (l.dot(&p), l.dot(&q));
        Matrix2x3::new(
            p.x - l.x * lp / n2,
            p.y - l.y * lp / n2,
            1.0,
            q.x - l.x * lq / n2,
            q.y - l.y * lq / n2,
            1.0,
        ) / n2.sqrt()
    }
    /// (7) as printed: `[𝒦 0]` (3 × 6).
    fn dl_dlc(&self) -> SMatrix<f64, 3, 6> {
        let mut m = SMatrix::<f64, 3, 6>::zeros();
        m.fixed_view_mut::<3, 3>(0, 0).copy_from(&self.k());
        m
    }
    /// (8) as printed: `[[R, ⌊t⌋× R], [0, R]]`.
    fn h(&self) -> Matrix6<f64> {
        let r = self.pose.rotation.matrix();
        let mut m = Matrix6::zeros();
        m.fixed_view_mut::<3, 3>(0, 0).copy_from(&r);
        m.fixed_view_mut::<3, 3>(0, 3)
            .copy_from(&(hat(&self.pose.translation) * r));
        m.fixed_view_mut::<3, 3>(3, 3).copy_from(&r);
        m
    }
    /// (9) as printed: `[[−⌊w₁u₁⌋×, −w₂u₁], [−⌊w₂u₂⌋×, w₁u₂]]` (6 × 4).
    fn dlw_dphi(&self) -> SMatrix<f64, 6, 4> {
        let u = self.line.u.matrix();
        let (u1, u2): (Vector3<f64>, Vector3<f64>) = (u.column(0).into(), u.column(1).into());
        let (w1, w2) = (self.line.w.cos, self.line.w.sin);
        let mut m = SMatrix::<f64, 6, 4>::zeros();
        m.fixed_view_mut::<3, 3>(0, 0)
            .copy_from(&(-hat(&(u1 * w1))));
        m.fixed_view_mut::<3, 1>(0, 3).copy_from(&(-u1 * w2));
        m.fixed_view_mut::<3, 3>(3, 0)
            .copy_from(&(-hat(&(u2 * w2))));
        m.fixed_view_mut::<3, 1>(3, 3).copy_from(&(u2 * w1));
        m
    }
    /// The pose block printed in (12): `[[−⌊Rn⌋× − ⌊⌊t⌋×Rv⌋×, −⌊Rv⌋×], [−⌊Rv⌋×, 0]]`.
    fn dlc_dxi_as_in_12(&self) -> Matrix6<f64> {
        let w = self.world_line();
        let r = self.pose.rotation.matrix();
        let (rn, rv) = (r * w.normal, r * w.direction);
        let mut m = Matrix6::zeros();
        m.fixed_view_mut::<3, 3>(0, 0)
            .copy_from(&(-hat(&rn) - hat(&(hat(&self.pose.translation) * rv))));
        m.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-hat(&rv)));
        m.fixed_view_mut::<3, 3>(3, 0).copy_from(&(-hat(&rv)));
        m
    }
    /// `p` followed by the observed endpoints `p'`, `q'` (what [`gamma_at`] reads).
    fn with_endpoints(&self, p: Parameters) -> Vec<(String, f64)> {
        p.with("p'", &self.start).with("q'", &self.end).into()
    }
    /// `p` followed by `K` and the endpoints (what [`gamma_of_camera_line`] reads).
    fn with_projection(&self, p: Parameters) -> Vec<(String, f64)> {
        self.with_endpoints(p.with("K", &self.intrinsics))
    }
}

/// `[u, v, 1]`.
fn homogeneous(p: &Vector2<f64>) -> Vector3<f64> {
    Vector3::new(p.x, p.y, 1.0)
}

/// `γ = [lᵀp', lᵀq'] / √(l₁² + l₂²)` with `p' = [p, 1]`, `q' = [q, 1]`.
fn gamma<S: Scalar>(l: &Vector3<S>, p: &Vector2<S>, q: &Vector2<S>) -> Vec<S> {
    let inv = (l.x * l.x + l.y * l.y).sqrt().recip();
    vec![
        (l.x * p.x + l.y * p.y + l.z) * inv,
        (l.x * q.x + l.y * q.y + l.z) * inv,
    ]
}

/// [`gamma`] of `l` at the endpoints read from `r`.
fn gamma_at<S: Scalar>(l: &Vector3<S>, r: &mut ScalarReader<S>) -> Vec<S> {
    let start: Vector2<S> = r.read();
    gamma(l, &start, &r.read())
}

/// `γ` of the camera line `L_c`, with `K` and the endpoints read from `r`.
fn gamma_of_camera_line<S: Scalar>(camera: &PluckerLine<S>, r: &mut ScalarReader<S>) -> Vec<S> {
    let intrinsics: Intrinsics<S> = r.read();
    gamma_at(&intrinsics.project_line(&camera.normal), r)
}

/// (6): `∂γ/∂l`.
pub struct LineDistanceJacobian(pub LineContext);

impl Derivation for LineDistanceJacobian {
    fn label(&self) -> Label {
        label(
            "(6)",
            "∂γ/∂l of γ = [lᵀp', lᵀq']/√(l₁² + l₂²)",
            "l = 𝒦 n_c additive; p' = [p^{1'}, p^{2'}, 1], q' = [q^{1'}, q^{2'}, 1] (the printed \
             third column 1 is p^{3'} = q^{3'} = 1)",
            None,
        )
    }
    fn point(&self) -> Vec<f64> {
        self.0.image_line().to_scalars()
    }
    fn parameters(&self) -> Vec<(String, f64)> {
        self.0.with_endpoints(Parameters::new())
    }
    fn input_names(&self) -> Vec<String> {
        stored_names::<Vector3<f64>>("l")
    }
    fn map<S: Scalar>(&self, x: &[S], p: &[S]) -> Vec<S> {
        gamma_at(&Vector3::from_scalars(x), &mut ScalarReader::new(p))
    }
    fn printed(&self) -> Printed {
        Printed::Evaluated(matrix(self.0.dgamma_dl()))
    }
}

/// (7): `∂l/∂L_c = [𝒦 0]`.
pub struct ImageLineJacobian(pub LineContext);

impl Derivation for ImageLineJacobian {
    fn label(&self) -> Label {
        label(
            "(7)",
            "∂l/∂L_c of l = 𝒦 n_c",
            "L_c = [n_c, v_c] additive",
            None,
        )
    }
    fn point(&self) -> Vec<f64> {
        self.0.camera_line().to_scalars()
    }
    fn parameters(&self) -> Vec<(String, f64)> {
        Parameters::new().with("K", &self.0.intrinsics).into()
    }
    fn input_names(&self) -> Vec<String> {
        stored_names::<PluckerLine<f64>>("L_c")
    }
    fn map<S: Scalar>(&self, x: &[S], p: &[S]) -> Vec<S> {
        Intrinsics::from_scalars(p)
            .project_line(&PluckerLine::from_scalars(x).normal)
            .to_scalars()
    }
    fn printed(&self) -> Printed {
        Printed::Evaluated(matrix(self.0.dl_dlc()))
    }
}

/// (8): `∂L_c/∂L_w = H = [[R, ⌊t⌋× R], [0, R]]`.
pub struct LineTransformJacobian(pub LineContext);

impl Derivation for LineTransformJacobian {
    fn label(&self) -> Label {
        label(
            "(8)",
            "∂L_c/∂L_w of L_c = H_w^c L_w",
            "L_w = [n_w, v_w] additive; T_w^c = [R t; 0 1] maps world to camera",
            None,
        )
    }
    fn point(&self) -> Vec<f64> {
        self.0.world_line().to_scalars()
    }
    fn parameters(&self) -> Vec<(String, f64)> {
        Parameters::new().with("T", &self.0.pose).into()
    }
    fn input_names(&self) -> Vec<String> {
        stored_names::<PluckerLine<f64>>("L_w")
    }
    fn map<S: Scalar>(&self, x: &[S], p: &[S]) -> Vec<S> {
        PluckerLine::from_scalars(x)
            .transform(&Se3::from_scalars(p))
            .to_scalars()
    }
    fn printed(&self) -> Printed {
        Printed::Evaluated(matrix(self.0.h()))
    }
}

/// (9): `∂L_w/∂φ = [[−⌊w₁u₁⌋×, −w₂u₁], [−⌊w₂u₂⌋×, w₁u₂]]` (6 × 4).
pub struct OrthonormalLineJacobian(pub LineContext);

impl Derivation for OrthonormalLineJacobian {
    fn label(&self) -> Label {
        label(
            "(9)",
            "∂L_w/∂φ of L_w = [w₁u₁, w₂u₂] under U ← Exp(δΘ) U, W ← R(δρ) W",
            "φ = [Θ, ρ], tangent [δΘ, δρ] (4), left perturbation",
            None,
        )
    }
    fn point(&self) -> Vec<f64> {
        vec![0.0; 4]
    }
    fn parameters(&self) -> Vec<(String, f64)> {
        Parameters::new().with("L", &self.0.line).into()
    }
    fn input_names(&self) -> Vec<String> {
        LINE_TANGENT_NAMES.map(String::from).to_vec()
    }
    fn map<S: Scalar>(&self, x: &[S], p: &[S]) -> Vec<S> {
        OrthonormalLine::from_scalars(p)
            .retract(x, Perturbation::Left)
            .to_plucker()
            .to_scalars()
    }
    fn printed(&self) -> Printed {
        Printed::Evaluated(matrix(self.0.dlw_dphi()))
    }
}

/// (10): `∂L_c/∂ξ`, whose final matrix is printed
/// `[[−⌊Rn⌋× − ⌊⌊t⌋×Rv⌋×, −⌊Rv⌋×], [−⌊Rv⌋×]]`: one block short in its second row.
pub struct CameraLinePoseJacobian(pub LineContext);

impl Derivation for CameraLinePoseJacobian {
    fn label(&self) -> Label {
        label(
            "(10)",
            "∂L_c/∂ξ_j of L_c = H(T_j) L_w under T_j ← Exp(δξ_j) T_j",
            "ξ = {ω, ρ} (rotation first), left perturbation; n = n_w, v = v_w, R = R_j, t = t_j",
            Some(
                "the final matrix's second block row is printed as the single block −⌊R_j v_w⌋× \
                 (3 × 3) beside a first block row of two blocks (3 × 6): its δρ block 0 is \
                 missing, so it is not a 6 × 6 matrix (the line before it even prints −⌊R_j n_w⌋× \
                 there). The complete matrix [[−⌊Rn⌋× − ⌊⌊t⌋×Rv⌋×, −⌊Rv⌋×], [−⌊Rv⌋×, 0]] is the \
                 one used in (12), and is right",
            ),
        )
    }
    fn point(&self) -> Vec<f64> {
        vec![0.0; 6]
    }
    fn parameters(&self) -> Vec<(String, f64)> {
        Parameters::new()
            .with("T", &self.0.pose)
            .with("L_w", &self.0.world_line())
            .into()
    }
    fn input_names(&self) -> Vec<String> {
        POSE_TANGENT_NAMES.map(String::from).to_vec()
    }
    fn map<S: Scalar>(&self, x: &[S], p: &[S]) -> Vec<S> {
        let mut r = ScalarReader::new(p);
        let pose: Se3<S> = r.read();
        let line: PluckerLine<S> = r.read();
        line.transform(&pose.retract(x, Perturbation::Left))
            .to_scalars()
    }
    fn printed(&self) -> Printed {
        Printed::Malformed(
            "the final matrix has two blocks in its first block row ([−⌊R_j n_w⌋× − \
             ⌊⌊t_j⌋×R_j v_w⌋×, −⌊R_j v_w⌋×], 3 × 6) but only one in its second (−⌊R_j v_w⌋×, \
             3 × 3): the δρ block of the second row is missing, so it is not a 6 × 6 matrix"
                .into(),
        )
    }
}

/// (11): `∂γ/∂φ = (6) (7) (8) (9)` (2 × 4).
pub struct LineResidualLineJacobian(pub LineContext);

impl Derivation for LineResidualLineJacobian {
    fn label(&self) -> Label {
        label(
            "(11)",
            "∂γ/∂φ of γ(l(L_c(L_w(φ)))) under U ← Exp(δΘ) U, W ← R(δρ) W, as (6)(7)(8)(9)",
            "φ = [Θ, ρ], tangent [δΘ, δρ] (4), left perturbation; p', q' = [u, v, 1]",
            None,
        )
    }
    fn point(&self) -> Vec<f64> {
        vec![0.0; 4]
    }
    fn parameters(&self) -> Vec<(String, f64)> {
        let c = &self.0;
        c.with_projection(Parameters::new().with("T", &c.pose).with("L", &c.line))
    }
    fn input_names(&self) -> Vec<String> {
        LINE_TANGENT_NAMES.map(String::from).to_vec()
    }
    fn map<S: Scalar>(&self, x: &[S], p: &[S]) -> Vec<S> {
        let mut r = ScalarReader::new(p);
        let pose: Se3<S> = r.read();
        let line: OrthonormalLine<S> = r.read();
        let camera = line
            .retract(x, Perturbation::Left)
            .to_plucker()
            .transform(&pose);
        gamma_of_camera_line(&camera, &mut r)
    }
    fn printed(&self) -> Printed {
        let c = &self.0;
        Printed::Evaluated(matrix(c.dgamma_dl() * c.dl_dlc() * c.h() * c.dlw_dphi()))
    }
}

/// (12): `∂γ/∂ξ = (6) (7) [[−⌊Rn⌋× − ⌊⌊t⌋×Rv⌋×, −⌊Rv⌋×], [−⌊Rv⌋×, 0]]` (2 × 6).
pub struct LineResidualPoseJacobian(pub LineContext);

impl Derivation for LineResidualPoseJacobian {
    fn label(&self) -> Label {
        label(
            "(12)",
            "∂γ/∂ξ_j of γ(l(L_c(ξ_j))) under T_j ← Exp(δξ_j) T_j, as (6)(7)·∂L_c/∂ξ_j",
            "ξ = {ω, ρ} (rotation first), left perturbation; p', q' = [u, v, 1]",
            None,
        )
    }
    fn point(&self) -> Vec<f64> {
        vec![0.0; 6]
    }
    fn parameters(&self) -> Vec<(String, f64)> {
        let c = &self.0;
        c.with_projection(
            Parameters::new()
                .with("T", &c.pose)
                .with("L_w", &c.world_line()),
        )
    }
    fn input_names(&self) -> Vec<String> {
        POSE_TANGENT_NAMES.map(String::from).to_vec()
    }
    fn map<S: Scalar>(&self, x: &[S], p: &[S]) -> Vec<S> {
        let mut r = ScalarReader::new(p);
        let pose: Se3<S> = r.read();
        let line: PluckerLine<S> = r.read();
        let camera = line.transform(&pose.retract(x, Perturbation::Left));
        gamma_of_camera_line(&camera, &mut r)
    }
    fn printed(&self) -> Printed {
        let c = &self.0;
        Printed::Evaluated(matrix(c.dgamma_dl() * c.dl_dlc() * c.dlc_dxi_as_in_12()))
    }
}

// ---------------------------------------------------------------------------
// §IV: the plane factor.
// ---------------------------------------------------------------------------

/// A camera pose, a measured camera-frame plane and a world plane landmark:
/// the context of §IV.
#[derive(Debug, Clone)]
pub struct PlaneContext {
    /// The world-to-camera pose `T_w^c`.
    pub pose: Se3<f64>,
    /// `q(π_c) = q(ω̂)`, the measured plane normalised.
    pub measured: Quaternion<f64>,
    /// `q(π_w) = q(ω)`, the landmark.
    pub landmark: Quaternion<f64>,
}

impl PlaneContext {
    fn sample(s: &mut Sampler) -> Self {
        let f = s.plane();
        PlaneContext {
            pose: f.pose,
            measured: Quaternion::from_coords(f.measured.normalize()),
            landmark: f.plane.quaternion,
        }
    }
    /// `y = Tᵀ q(ω̂)`.
    fn y(&self) -> Vector4<f64> {
        transpose_transform(&self.pose, &self.measured.coords())
    }
    /// `φ = y / |y|`.
    fn phi(&self) -> Quaternion<f64> {
        Quaternion::from_coords(self.y().normalize())
    }
    /// `u = log φ`.
    fn u(&self) -> Vector3<f64> {
        self.phi().log()
    }
    /// `β = log(exp(u) ⊕ exp(ω)⁻¹)`, the error `E` itself.
    fn beta(&self) -> Vector3<f64> {
        self.phi().mul(&self.landmark.conjugate()).log()
    }
    /// `∂E/∂u = Jl(β)⁻¹` as printed.
    fn de_du(&self) -> Matrix3<f64> {
        left_jacobian_inverse(&self.beta())
    }
    /// `∂u/∂φ` as printed: `( 2cos⁻¹(φ₄)/|φ_v| I − 2cos⁻¹(φ₄)/|q|^{3/2} φ_v φ_vᵀ |
    /// 2cos⁻¹(φ₄)/√(1−φ₄²) φ_v )`, with `|q|` read as `|φ_v|`.
    fn du_dphi(&self) -> SMatrix<f64, 3, 4> {
        let phi = self.phi();
        let v = phi.vector();
        let s = v.norm();
        let theta = 2.0 * phi.w.acos();
        let mut m = SMatrix::<f64, 3, 4>::zeros();
        m.fixed_view_mut::<3, 3>(0, 0).copy_from(
            &(Matrix3::identity() * (theta / s) - v * v.transpose() * (theta / s.powf(1.5))),
        );
        m.fixed_view_mut::<3, 1>(0, 3)
            .copy_from(&(v * (theta / (1.0 - phi.w * phi.w).sqrt())));
        m
    }
    /// `∂φ/∂y = I/|y| − y yᵀ/|y|^{3/2}` as printed.
    fn dphi_dy(&self) -> Matrix4<f64> {
        let y = self.y();
        let n = y.norm();
        Matrix4::identity() / n - y * y.transpose() / n.powf(1.5)
    }
    /// `∂y/∂ξ` as printed on the last line: `[Rᵀ ⌊q_v⌋× δφ; tᵀ ⌊q_v⌋× δφ] / δξ`
    /// with `δξ = (δφ, δρ)`, i.e. `[[Rᵀ⌊q_v⌋×, 0], [tᵀ⌊q_v⌋×, 0]]` (4 × 6).
    fn dy_dxi(&self) -> SMatrix<f64, 4, 6> {
        let qv = self.measured.vector();
        let r = self.pose.rotation.matrix();
        let mut m = SMatrix::<f64, 4, 6>::zeros();
        m.fixed_view_mut::<3, 3>(0, 0)
            .copy_from(&(r.transpose() * hat(&qv)));
        m.fixed_view_mut::<1, 3>(3, 0)
            .copy_from(&(self.pose.translation.transpose() * hat(&qv)));
        m
    }
    /// The pose and `q(ω̂)`, the parameters [`perturbed_y`] reads.
    fn pose_and_measured(&self) -> Parameters {
        Parameters::new()
            .with("T", &self.pose)
            .with("\\hat{q}", &self.measured)
    }
}

/// `log(exp(u) ⊕ q_w⁻¹)`.
fn error_of_u<S: Scalar>(u: &Vector3<S>, landmark: &Quaternion<S>) -> Vec<S> {
    Quaternion::exp(u)
        .mul(&landmark.conjugate())
        .log()
        .as_slice()
        .to_vec()
}

/// §IV-A: `∂E/∂u = Jl(β)⁻¹`.
pub struct PlaneErrorLogJacobian(pub PlaneContext);

impl Derivation for PlaneErrorLogJacobian {
    fn label(&self) -> Label {
        label(
            "§IV-A ∂E/∂u",
            "∂E/∂u of E = log(exp(u) ⊕ exp(ω)⁻¹), the first link of (13), is Jl(β)⁻¹",
            "u = log φ additive (as the chain rule (13) needs it); the document's difference \
             quotient perturbs exp(u) on the left, exp(δu) ⊕ exp(u); β = E",
            Some(
                "Jl(β)⁻¹ is the derivative w.r.t. a left perturbation exp(u) ← exp(δu) ⊗ exp(u), \
                 which the document's difference quotient takes; the chain rule (13) multiplies \
                 it by ∂u/∂φ of u itself, which needs the derivative w.r.t. an additive u, \
                 Jl(β)⁻¹ Jl(u)",
            ),
        )
    }
    fn point(&self) -> Vec<f64> {
        self.0.u().to_scalars()
    }
    fn parameters(&self) -> Vec<(String, f64)> {
        Parameters::new().with("q_w", &self.0.landmark).into()
    }
    fn input_names(&self) -> Vec<String> {
        stored_names::<Vector3<f64>>("u")
    }
    fn map<S: Scalar>(&self, x: &[S], p: &[S]) -> Vec<S> {
        error_of_u(&Vector3::from_scalars(x), &Quaternion::from_scalars(p))
    }
    fn printed(&self) -> Printed {
        Printed::Evaluated(matrix(self.0.de_du()))
    }
    fn conventions(&self) -> Vec<(String, DMatrix<f64>)> {
        let u = self.0.u();
        let landmark = self.0.landmark;
        let left = dual_jacobian(&[0.0; 3], |d| {
            let exp_u = Quaternion::exp(&u.map(DualSVec64::from_re));
            let landmark = Quaternion::from_coords(landmark.coords().map(DualSVec64::from_re));
            Quaternion::exp(&Vector3::from_scalars(d))
                .mul(&exp_u)
                .mul(&landmark.conjugate())
                .log()
                .as_slice()
                .to_vec()
        });
        vec![(
            "right for a left perturbation of exp(u), exp(u) ← exp(δu) ⊗ exp(u) (the document's \
             difference quotient), not for the additive u the chain rule (13) needs"
                .into(),
            left,
        )]
    }
}

/// `2 cos⁻¹(φ₄)/|φ_v| φ_v`, with `cos⁻¹ x = atan2(√(1 − x²), x)`.
fn document_log<S: Scalar>(phi: &Quaternion<S>) -> Vec<S> {
    let v = phi.vector();
    let w = phi.w;
    let acos = (S::one() - w * w).sqrt().atan2(w);
    let k = S::from_f64(2.0) * acos * (v.x * v.x + v.y * v.y + v.z * v.z).sqrt().recip();
    vec![k * v.x, k * v.y, k * v.z]
}

/// §IV-A: `∂u/∂φ` (3 × 4).
pub struct QuaternionLogJacobian(pub PlaneContext);

impl Derivation for QuaternionLogJacobian {
    fn label(&self) -> Label {
        label(
            "§IV-A ∂u/∂φ",
            "∂u/∂φ of u = 2cos⁻¹(φ₄)/|φ_v| · φ_v",
            "φ = (φ_v, φ₄) ∈ R⁴ additive, at a unit φ; the |q|^{3/2} of the printed formula read \
             as |φ_v|^{3/2} (φ has no other q)",
            Some(
                "both blocks are wrong: the φ_v φ_vᵀ term should be divided by |φ_v|³ (not \
                 |q|^{3/2}), and the φ₄ column should be −2/(|φ_v| √(1−φ₄²)) φ_v (= −2φ_v/(1−φ₄²) \
                 at a unit φ; the derivative of cos⁻¹ was replaced by cos⁻¹ itself and its sign \
                 and the 1/|φ_v| dropped), not 2cos⁻¹(φ₄)/√(1−φ₄²) φ_v",
            ),
        )
    }
    fn point(&self) -> Vec<f64> {
        self.0.phi().to_scalars()
    }
    fn parameters(&self) -> Vec<(String, f64)> {
        Vec::new()
    }
    fn input_names(&self) -> Vec<String> {
        stored_names::<Quaternion<f64>>("\\phi")
    }
    fn map<S: Scalar>(&self, x: &[S], _p: &[S]) -> Vec<S> {
        document_log(&Quaternion::from_scalars(x))
    }
    fn printed(&self) -> Printed {
        Printed::Evaluated(matrix(self.0.du_dphi()))
    }
}

/// §IV-A: `∂φ/∂y = I/|y| − y yᵀ/|y|^{3/2}` (4 × 4).
pub struct NormalisationJacobian(pub PlaneContext);

impl Derivation for NormalisationJacobian {
    fn label(&self) -> Label {
        label(
            "§IV-A ∂φ/∂y",
            "∂φ/∂y of φ = y/|y|",
            "y ∈ R⁴ additive, y = T_w^cᵀ q(ω̂)",
            Some("the exponent 3/2 of |y| in the y yᵀ term should be 3: I/|y| − y yᵀ/|y|³"),
        )
    }
    fn point(&self) -> Vec<f64> {
        self.0.y().to_scalars()
    }
    fn parameters(&self) -> Vec<(String, f64)> {
        Vec::new()
    }
    fn input_names(&self) -> Vec<String> {
        stored_names::<Vector4<f64>>("y")
    }
    fn map<S: Scalar>(&self, x: &[S], _p: &[S]) -> Vec<S> {
        normalized(&Vector4::from_scalars(x)).to_scalars()
    }
    fn printed(&self) -> Printed {
        Printed::Evaluated(matrix(self.0.dphi_dy()))
    }
}

/// `y = (Exp(δξ) T)ᵀ q(ω̂)`, the pose and `q(ω̂)` read from `r`.
fn perturbed_y<S: Scalar>(x: &[S], r: &mut ScalarReader<S>) -> Vector4<S> {
    let pose: Se3<S> = r.read();
    let measured: Quaternion<S> = r.read();
    transpose_transform(&pose.retract(x, Perturbation::Left), &measured.coords())
}

/// `2 atan2(|e_v|, e₄)/|e_v| · e_v`: the quaternion logarithm of §I on unit
/// quaternions (`atan2(|e_v|, e₄) = cos⁻¹ e₄` there), homogeneous of degree 0,
/// without the small-angle branch of [`Quaternion::log`] (`e_v ≠ 0` at every
/// sample).
fn branch_free_log<S: Scalar>(e: &Quaternion<S>) -> Vec<S> {
    let v = e.vector();
    let s = (v.x * v.x + v.y * v.y + v.z * v.z).sqrt();
    let k = S::from_f64(2.0) * s.atan2(e.w) / s;
    vec![k * v.x, k * v.y, k * v.z]
}

/// §IV-A: `∂y/∂ξ`, the last line of its derivation.
pub struct PlaneTransformJacobian(pub PlaneContext);

impl Derivation for PlaneTransformJacobian {
    fn label(&self) -> Label {
        label(
            "§IV-A ∂y/∂ξ",
            "∂y/∂ξ of y = T_w^c(ξ)ᵀ q(ω̂) under T ← Exp(δξ) T, as the last line of the \
             derivation prints it",
            "ξ = (δφ, δρ) (rotation first), left perturbation; the last line is \
             [Rᵀ⌊q_v⌋× δφ; tᵀ⌊q_v⌋× δφ] / δξ with no δρ term, read as the 4 × 6 \
             [[Rᵀ⌊q_v⌋×, 0], [tᵀ⌊q_v⌋×, 0]] (its δρ columns zero): well formed, and claiming \
             to be the whole Jacobian",
            Some(
                "the last line drops the + q_vᵀ δρ term of the line before it (which is right): \
                 the δρ block of the fourth row should be q_vᵀ, not 0 — \
                 [[Rᵀ⌊q_v⌋×, 0], [tᵀ⌊q_v⌋×, q_vᵀ]]",
            ),
        )
    }
    fn point(&self) -> Vec<f64> {
        vec![0.0; 6]
    }
    fn parameters(&self) -> Vec<(String, f64)> {
        self.0.pose_and_measured().into()
    }
    fn input_names(&self) -> Vec<String> {
        POSE_TANGENT_NAMES.map(String::from).to_vec()
    }
    fn map<S: Scalar>(&self, x: &[S], p: &[S]) -> Vec<S> {
        perturbed_y(x, &mut ScalarReader::new(p)).to_scalars()
    }
    fn printed(&self) -> Printed {
        Printed::Evaluated(matrix(self.0.dy_dxi()))
    }
}

/// (13): `∂E/∂ξ = ∂E/∂u ∂u/∂φ ∂φ/∂y ∂y/∂ξ` (3 × 6).
pub struct PlanePoseJacobian(pub PlaneContext);

impl Derivation for PlanePoseJacobian {
    fn label(&self) -> Label {
        label(
            "(13)",
            "∂E/∂ξ of E = log(q(T_w^c(ξ)ᵀ q(ω̂)) ⊕ q(ω)⁻¹) under T ← Exp(δξ) T, as the product of \
             the printed ∂E/∂u, ∂u/∂φ, ∂φ/∂y and ∂y/∂ξ",
            "ξ = (δφ, δρ) (rotation first), left perturbation; q(·) = ·/|·|",
            Some(
                "every link is off: ∂E/∂u is the derivative for a left-perturbed exp(u) where the \
                 chain needs the additive u, ∂u/∂φ and ∂φ/∂y have wrong powers of the norm (and a \
                 wrong φ₄ column), and ∂y/∂ξ drops its q_vᵀ δρ block",
            ),
        )
    }
    fn point(&self) -> Vec<f64> {
        vec![0.0; 6]
    }
    fn parameters(&self) -> Vec<(String, f64)> {
        self.0
            .pose_and_measured()
            .with("q_w", &self.0.landmark)
            .into()
    }
    fn input_names(&self) -> Vec<String> {
        POSE_TANGENT_NAMES.map(String::from).to_vec()
    }
    fn map<S: Scalar>(&self, x: &[S], p: &[S]) -> Vec<S> {
        // q(y) = y/|y| is a positive scaling and the logarithm is homogeneous
        // of degree 0, so E = log(y ⊕ q(ω)⁻¹) without it; that, and the
        // branch-free logarithm, keep the corrected LaTeX some 20× shorter
        // (it is still large: E expanded in the pose, q(ω̂) and q(ω)).
        let mut r = ScalarReader::new(p);
        let y = Quaternion::from_coords(perturbed_y(x, &mut r));
        let landmark: Quaternion<S> = r.read();
        branch_free_log(&y.mul(&landmark.conjugate()))
    }
    fn printed(&self) -> Printed {
        let c = &self.0;
        Printed::Evaluated(matrix(c.de_du() * c.du_dphi() * c.dphi_dy() * c.dy_dxi()))
    }
}

/// §IV-B: `∂E/∂ω = −Jr(u)⁻¹`, `u` the error `E`.
pub struct PlaneLandmarkJacobian(pub PlaneContext);

impl Derivation for PlaneLandmarkJacobian {
    fn label(&self) -> Label {
        label(
            "§IV-B ∂E/∂ω",
            "∂E/∂ω of E = log(φ ⊕ q(ω)⁻¹) under q(ω) ← q(δω) ⊕ q(ω), is −Jr(E)⁻¹",
            "left perturbation of the landmark, tangent δω (3); φ = q(T_w^cᵀ q(ω̂)); the u of \
             §IV-B is the error E",
            None,
        )
    }
    fn point(&self) -> Vec<f64> {
        vec![0.0; 3]
    }
    fn parameters(&self) -> Vec<(String, f64)> {
        Parameters::new()
            .with("\\phi", &self.0.phi())
            .with("q_w", &self.0.landmark)
            .into()
    }
    fn input_names(&self) -> Vec<String> {
        POSE_TANGENT_NAMES[..3]
            .iter()
            .map(|n| n.to_string())
            .collect()
    }
    fn map<S: Scalar>(&self, x: &[S], p: &[S]) -> Vec<S> {
        let mut r = ScalarReader::new(p);
        let phi: Quaternion<S> = r.read();
        let landmark = InfinitePlane {
            quaternion: r.read(),
        }
        .retract(x, Perturbation::Left)
        .quaternion;
        phi.mul(&landmark.conjugate()).log().to_scalars()
    }
    fn printed(&self) -> Printed {
        Printed::Evaluated(matrix(-right_jacobian_inverse(&self.0.beta())))
    }
}

/// Every formula of this module, with its sampler.
pub fn audits() -> Vec<crate::Audit> {
    use crate::Audit;
    vec![
        Audit::of(|s| LineDistanceJacobian(LineContext::sample(s))),
        Audit::of(|s| ImageLineJacobian(LineContext::sample(s))),
        Audit::of(|s| LineTransformJacobian(LineContext::sample(s))),
        Audit::of(|s| OrthonormalLineJacobian(LineContext::sample(s))),
        Audit::of(|s| CameraLinePoseJacobian(LineContext::sample(s))),
        Audit::of(|s| LineResidualLineJacobian(LineContext::sample(s))),
        Audit::of(|s| LineResidualPoseJacobian(LineContext::sample(s))),
        Audit::of(|s| PlaneErrorLogJacobian(PlaneContext::sample(s))),
        Audit::of(|s| QuaternionLogJacobian(PlaneContext::sample(s))),
        Audit::of(|s| NormalisationJacobian(PlaneContext::sample(s))),
        Audit::of(|s| PlaneTransformJacobian(PlaneContext::sample(s))),
        Audit::of(|s| PlanePoseJacobian(PlaneContext::sample(s))),
        Audit::of(|s| PlaneLandmarkJacobian(PlaneContext::sample(s))),
    ]
}

/// The chain rules of §III and §IV: (11), (12) and (13).
pub fn chains() -> Vec<crate::chain::Chain> {
    use crate::chain::Chain;
    vec![
        Chain {
            document: DOCUMENT.into(),
            composed: "(11)".into(),
            links: ["(6)", "(7)", "(8)", "(9)"].map(String::from).to_vec(),
        },
        Chain {
            document: DOCUMENT.into(),
            composed: "(12)".into(),
            links: ["(6)", "(7)", "(10)"].map(String::from).to_vec(),
        },
        Chain {
            document: DOCUMENT.into(),
            composed: "(13)".into(),
            links: ["§IV-A ∂E/∂u", "§IV-A ∂u/∂φ", "§IV-A ∂φ/∂y", "§IV-A ∂y/∂ξ"]
                .map(String::from)
                .to_vec(),
        },
    ]
}
