//! Document 000 (`000_29653f4af9b68bb8.txt`): the preliminaries of §I and
//! the point reprojection factor of §II, transcribed as printed.

use nalgebra::{DMatrix, Matrix2x3, Matrix3, Vector3};

use crate::derivation::{Claim, Derivation, Label, Printed};
use crate::transcription::{Parameters, matrix, stored_names};
use factor_core::geometry::Intrinsics;
use factor_core::lie::so3::{
    hat, left_jacobian, left_jacobian_inverse, right_jacobian, right_jacobian_inverse,
};
use factor_core::lie::{Quaternion, Se3, So3};
use factor_core::manifold::{Manifold, Perturbation};
use factor_core::scalar::Scalar;
use factor_core::storage::{ScalarReader, Storage};
use factor_testing::samples::Sampler;

/// The document's file name.
pub const DOCUMENT: &str = "000_29653f4af9b68bb8.txt";

fn label(
    equation: &'static str,
    claim: &'static str,
    convention: &'static str,
    erratum: Option<&'static str>,
) -> Label {
    Label::new(DOCUMENT, equation, claim, convention, erratum)
}

/// A rotation vector of angle in `(0.05, 3.0)`.
fn rotation_vector(s: &mut Sampler) -> Vector3<f64> {
    let axis = s.vector3(1.0).normalize();
    axis * s.uniform(0.05, 3.0)
}

/// §I: `exp(ω) = [½ sinc(θ/2) ω̂, cos(θ/2)]`.
pub struct QuaternionExp(pub Vector3<f64>);

impl Derivation for QuaternionExp {
    fn label(&self) -> Label {
        label(
            "§I exp",
            "quaternion exponential exp(ω) = [½ sinc(θ/2) ω̂, cos(θ/2)]",
            "q = (q_v, q_4); ω̂ = ω/|ω|, θ = |ω|",
            Some(
                "the vector part ½ sinc(θ/2) ω̂ = sin(θ/2)/θ · ω̂ should be sin(θ/2) ω̂ (or ½ sinc(θ/2) ω)",
            ),
        )
    }
    fn point(&self) -> Vec<f64> {
        self.0.to_scalars()
    }
    fn parameters(&self) -> Vec<(String, f64)> {
        Vec::new()
    }
    fn input_names(&self) -> Vec<String> {
        stored_names::<Vector3<f64>>("\\omega")
    }
    fn map<S: Scalar>(&self, x: &[S], _p: &[S]) -> Vec<S> {
        Quaternion::exp(&Vector3::from_scalars(x)).to_scalars()
    }
    fn printed(&self) -> Printed {
        let theta = self.0.norm();
        let sinc = |x: f64| x.sin() / x;
        let v = 0.5 * sinc(theta / 2.0) * self.0 / theta;
        Printed::Evaluated(DMatrix::from_column_slice(
            4,
            1,
            &[v.x, v.y, v.z, (theta / 2.0).cos()],
        ))
    }
    fn claim(&self) -> Claim {
        Claim::Value
    }
}

/// §I: `log(q) = 2 cos⁻¹(q₄) / |q| · q` (vector part).
pub struct QuaternionLog(pub Quaternion<f64>);

impl Derivation for QuaternionLog {
    fn label(&self) -> Label {
        label(
            "§I log",
            "quaternion logarithm log(q) = 2 cos⁻¹(q₄)/|q| · q",
            "q = (q_v, q_4) unit; |q| and q on the right read as the vector part",
            None,
        )
    }
    fn point(&self) -> Vec<f64> {
        self.0.to_scalars()
    }
    fn parameters(&self) -> Vec<(String, f64)> {
        Vec::new()
    }
    fn input_names(&self) -> Vec<String> {
        stored_names::<Quaternion<f64>>("q")
    }
    fn map<S: Scalar>(&self, x: &[S], _p: &[S]) -> Vec<S> {
        Quaternion::from_scalars(x).log().to_scalars()
    }
    fn printed(&self) -> Printed {
        let v = self.0.vector();
        let k = 2.0 * self.0.w.acos() / v.norm();
        Printed::Evaluated(DMatrix::from_column_slice(3, 1, (v * k).as_slice()))
    }
    fn claim(&self) -> Claim {
        Claim::Value
    }
}

/// (1), first case: `Log(Exp(ω₁) Exp(ω₂)) ≈ Jl(ω₂)⁻¹ ω₁ + ω₂` for small `ω₁`,
/// i.e. `∂/∂ω₁ Log(Exp(ω₁) Exp(ω₂)) = Jl(ω₂)⁻¹` at `ω₁ = 0`.
pub struct BchLeft(pub Vector3<f64>);

/// (1), second case: `∂/∂ω₂ Log(Exp(ω₁) Exp(ω₂)) = Jr(ω₁)⁻¹` at `ω₂ = 0`.
pub struct BchRight(pub Vector3<f64>);

macro_rules! bch {
    ($ty:ident, $equation:literal, $claim:literal, $compose:expr, $printed:expr) => {
        impl Derivation for $ty {
            fn label(&self) -> Label {
                label(
                    $equation,
                    $claim,
                    "Jl(ω) = Exp(ω) Jr(ω); Log, Exp of SO(3)",
                    None,
                )
            }
            fn point(&self) -> Vec<f64> {
                vec![0.0; 3]
            }
            fn parameters(&self) -> Vec<(String, f64)> {
                Parameters::new().with("\\omega", &self.0).into()
            }
            fn input_names(&self) -> Vec<String> {
                DELTA_NAMES.map(String::from).to_vec()
            }
            fn map<S: Scalar>(&self, x: &[S], p: &[S]) -> Vec<S> {
                let compose: fn(So3<S>, So3<S>) -> So3<S> = $compose;
                let (small, fixed) = (Vector3::from_scalars(x), Vector3::from_scalars(p));
                compose(So3::exp(&small), So3::exp(&fixed))
                    .log()
                    .to_scalars()
            }
            fn printed(&self) -> Printed {
                let printed: fn(&Vector3<f64>) -> Matrix3<f64> = $printed;
                Printed::Evaluated(matrix(printed(&self.0)))
            }
        }
    };
}

bch!(
    BchLeft,
    "(1) |ω₁| < ε",
    "∂Log(Exp(ω₁)Exp(ω₂))/∂ω₁ at ω₁ = 0 is Jl(ω₂)⁻¹",
    |small, fixed| small.compose(&fixed),
    left_jacobian_inverse
);
bch!(
    BchRight,
    "(1) |ω₂| < ε",
    "∂Log(Exp(ω₁)Exp(ω₂))/∂ω₂ at ω₂ = 0 is Jr(ω₁)⁻¹",
    |small, fixed| fixed.compose(&small),
    right_jacobian_inverse
);

/// §I: `Jl(ω) = Exp(ω) Jr(ω)` (a matrix identity: a value claim).
pub struct LeftRightJacobians(pub Vector3<f64>);

impl Derivation for LeftRightJacobians {
    fn label(&self) -> Label {
        label(
            "§I Jl = Exp Jr",
            "Jl(ω) = Exp(ω) Jr(ω)",
            "left and right Jacobians of SO(3)",
            None,
        )
    }
    fn point(&self) -> Vec<f64> {
        self.0.to_scalars()
    }
    fn parameters(&self) -> Vec<(String, f64)> {
        Vec::new()
    }
    fn input_names(&self) -> Vec<String> {
        stored_names::<Vector3<f64>>("\\omega")
    }
    fn map<S: Scalar>(&self, x: &[S], _p: &[S]) -> Vec<S> {
        left_jacobian(&Vector3::from_scalars(x)).to_scalars()
    }
    fn printed(&self) -> Printed {
        let m = So3::exp(&self.0).matrix() * right_jacobian(&self.0);
        Printed::Evaluated(DMatrix::from_column_slice(9, 1, m.as_slice()))
    }
    fn claim(&self) -> Claim {
        Claim::Value
    }
}

/// A camera pose, a world point in view and intrinsics: the context of §II.
#[derive(Debug, Clone)]
pub struct PointContext {
    /// `K = [f_u, f_v, c_u, c_v]`.
    pub k: [f64; 4],
    /// The world-to-camera pose `T_j`.
    pub pose: Se3<f64>,
    /// The world point `^wP_i`.
    pub point: Vector3<f64>,
}

impl PointContext {
    fn sample(s: &mut Sampler) -> Self {
        let f = s.point_reprojection();
        let k = f.intrinsics;
        PointContext {
            k: [k.fu, k.fv, k.cu, k.cv],
            pose: f.pose,
            point: f.point,
        }
    }
    /// `P = R X + t`.
    fn camera_point(&self) -> Vector3<f64> {
        self.pose.transform_point(&self.point)
    }
    /// `K` as intrinsics.
    fn intrinsics(&self) -> Intrinsics<f64> {
        Intrinsics::from_scalars(&self.k)
    }
    /// `[f_u 0 c_u; 0 f_v c_v]`.
    fn k23(&self) -> Matrix2x3<f64> {
        Matrix2x3::new(self.k[0], 0.0, self.k[2], 0.0, self.k[1], self.k[3])
    }
    /// `[[1/P_z, 0, −P_x/P_z²], [0, 1/P_z, −P_y/P_z²], [0, 0, 0]]` as printed in (2).
    fn projection_derivative(&self) -> Matrix3<f64> {
        let p = self.camera_point();
        Matrix3::new(
            1.0 / p.z,
            0.0,
            -p.x / (p.z * p.z),
            0.0,
            1.0 / p.z,
            -p.y / (p.z * p.z),
            0.0,
            0.0,
            0.0,
        )
    }
}

/// The pinhole projection `[f_u X/Z + c_u, f_v Y/Z + c_v]`.
fn project<S: Scalar>(k: &Intrinsics<S>, p: &Vector3<S>) -> Vec<S> {
    k.project(p).to_scalars()
}

/// `−v`, element-wise.
fn negated<S: Scalar>(v: Vec<S>) -> Vec<S> {
    v.into_iter().map(|x| -x).collect()
}

/// (2): `∂p'/∂(P_x, P_y, P_z) = [f_u 0 c_u; 0 f_v c_v] · [[1/P_z, 0, −P_x/P_z²], …, [0, 0, 0]]`.
pub struct ProjectionJacobian(pub PointContext);

impl Derivation for ProjectionJacobian {
    fn label(&self) -> Label {
        label(
            "(2)",
            "∂p'/∂(P_x, P_y, P_z) of the pinhole projection",
            "p' = K [P_x/P_z, P_y/P_z, 1]",
            None,
        )
    }
    fn point(&self) -> Vec<f64> {
        self.0.camera_point().to_scalars()
    }
    fn parameters(&self) -> Vec<(String, f64)> {
        Parameters::new().with("K", &self.0.intrinsics()).into()
    }
    fn input_names(&self) -> Vec<String> {
        stored_names::<Vector3<f64>>("P")
    }
    fn map<S: Scalar>(&self, x: &[S], p: &[S]) -> Vec<S> {
        project(&Intrinsics::from_scalars(p), &Vector3::from_scalars(x))
    }
    fn printed(&self) -> Printed {
        Printed::Evaluated(matrix(self.0.k23() * self.0.projection_derivative()))
    }
}

/// (3): `∂(P_x, P_y, P_z)/∂(x, y, z) = R_j`.
pub struct PointTransformJacobian(pub PointContext);

impl Derivation for PointTransformJacobian {
    fn label(&self) -> Label {
        label(
            "(3)",
            "∂P/∂^wP of P = R_j ^wP + t_j",
            "world point additive",
            None,
        )
    }
    fn point(&self) -> Vec<f64> {
        self.0.point.to_scalars()
    }
    fn parameters(&self) -> Vec<(String, f64)> {
        Parameters::new().with("T", &self.0.pose).into()
    }
    fn input_names(&self) -> Vec<String> {
        stored_names::<Vector3<f64>>("X")
    }
    fn map<S: Scalar>(&self, x: &[S], p: &[S]) -> Vec<S> {
        Se3::from_scalars(p)
            .transform_point(&Vector3::from_scalars(x))
            .to_scalars()
    }
    fn printed(&self) -> Printed {
        Printed::Evaluated(matrix(self.0.pose.rotation.matrix()))
    }
}

/// `X ↦ R X + t` for a pose perturbed on the left by the tangent `x`, the
/// pose and the point read from `r`.
fn perturbed_point<S: Scalar>(x: &[S], r: &mut ScalarReader<S>) -> Vector3<S> {
    let pose: Se3<S> = r.read();
    let point: Vector3<S> = r.read();
    pose.retract(x, Perturbation::Left).transform_point(&point)
}

/// The pose `T` and the world point `X`, the parameters [`perturbed_point`] reads.
fn pose_and_point(c: &PointContext) -> Parameters {
    Parameters::new().with("T", &c.pose).with("X", &c.point)
}

const DELTA_NAMES: [&str; 3] = ["\\delta_1", "\\delta_2", "\\delta_3"];

const TANGENT_NAMES: [&str; 6] = [
    "\\delta\\omega_1",
    "\\delta\\omega_2",
    "\\delta\\omega_3",
    "\\delta\\rho_1",
    "\\delta\\rho_2",
    "\\delta\\rho_3",
];

/// (4): `∂(P_x, P_y, P_z)/∂ξ_j = [I  −⌊R_j ^wP_i + t_j⌋×]` (3 × 6).
pub struct PoseTransformJacobian(pub PointContext);

impl Derivation for PoseTransformJacobian {
    fn label(&self) -> Label {
        label(
            "(4)",
            "∂P/∂ξ_j of P = T_j ^wP_i under T ← Exp(δξ) T",
            "ξ = {ω, ρ} (rotation first), left perturbation",
            Some("the columns are in the order [δρ, δω], not the document's own ξ = {ω, ρ}"),
        )
    }
    fn point(&self) -> Vec<f64> {
        vec![0.0; 6]
    }
    fn parameters(&self) -> Vec<(String, f64)> {
        pose_and_point(&self.0).into()
    }
    fn input_names(&self) -> Vec<String> {
        TANGENT_NAMES.map(String::from).to_vec()
    }
    fn map<S: Scalar>(&self, x: &[S], p: &[S]) -> Vec<S> {
        perturbed_point(x, &mut ScalarReader::new(p)).to_scalars()
    }
    fn printed(&self) -> Printed {
        let mut m = DMatrix::zeros(3, 6);
        m.view_mut((0, 0), (3, 3)).copy_from(&Matrix3::identity());
        m.view_mut((0, 3), (3, 3))
            .copy_from(&(-hat(&self.0.camera_point())));
        Printed::Evaluated(m)
    }
}

/// (5), first line: `∂ρ/∂^wP_i = −[f_u 0 c_u; 0 f_v c_v] [[1/P_z, …]] R_j`.
pub struct PointResidualJacobian(pub PointContext);

impl Derivation for PointResidualJacobian {
    fn label(&self) -> Label {
        label(
            "(5) ∂ρ/∂^wP",
            "∂ρ_ij/∂^wP_i of ρ = p − p'",
            "world point additive",
            None,
        )
    }
    fn point(&self) -> Vec<f64> {
        self.0.point.to_scalars()
    }
    fn parameters(&self) -> Vec<(String, f64)> {
        Parameters::new()
            .with("T", &self.0.pose)
            .with("K", &self.0.intrinsics())
            .into()
    }
    fn input_names(&self) -> Vec<String> {
        stored_names::<Vector3<f64>>("X")
    }
    fn map<S: Scalar>(&self, x: &[S], p: &[S]) -> Vec<S> {
        // ρ = p_obs − p': the observation is a constant, so ∂ρ = −∂p'.
        let mut r = ScalarReader::new(p);
        let pose: Se3<S> = r.read();
        let camera_point = pose.transform_point(&Vector3::from_scalars(x));
        negated(project(&r.read(), &camera_point))
    }
    fn printed(&self) -> Printed {
        let c = &self.0;
        Printed::Evaluated(matrix(
            -(c.k23() * c.projection_derivative() * c.pose.rotation.matrix()),
        ))
    }
}

/// (5), second line: `∂ρ/∂ξ_j = −[f_u 0 c_u; 0 f_v c_v] M [I −⌊…⌋×]` with the
/// middle factor `M` printed 4 × 3 (its second row repeated).
pub struct PointPoseResidualJacobian(pub PointContext);

impl Derivation for PointPoseResidualJacobian {
    fn label(&self) -> Label {
        label(
            "(5) ∂ρ/∂ξ",
            "∂ρ_ij/∂ξ_j of ρ = p − p' under T ← Exp(δξ) T",
            "ξ = {ω, ρ}, left perturbation",
            Some(
                "the middle factor is printed 4 × 3 (its second row repeated), so the product does not multiply",
            ),
        )
    }
    fn point(&self) -> Vec<f64> {
        vec![0.0; 6]
    }
    fn parameters(&self) -> Vec<(String, f64)> {
        pose_and_point(&self.0)
            .with("K", &self.0.intrinsics())
            .into()
    }
    fn input_names(&self) -> Vec<String> {
        TANGENT_NAMES.map(String::from).to_vec()
    }
    fn map<S: Scalar>(&self, x: &[S], p: &[S]) -> Vec<S> {
        let mut r = ScalarReader::new(p);
        let camera_point = perturbed_point(x, &mut r);
        negated(project(&r.read(), &camera_point))
    }
    fn printed(&self) -> Printed {
        // [f_u 0 c_u; 0 f_v c_v] (2 × 3) · M (4 × 3, as printed) does not multiply.
        Printed::Malformed(
            "the middle factor is printed with 4 rows ([1/P_z, 0, −P_x/P_z²], [0, 1/P_z, −P_y/P_z²] twice, \
             [0, 0, 0]): a 2 × 3 matrix times a 4 × 3 matrix is undefined"
                .into(),
        )
    }
}

/// A context sampler for §II.
pub fn sample_point_context(s: &mut Sampler) -> PointContext {
    PointContext::sample(s)
}

/// A unit quaternion away from the identity (angle in `(0.05, 3.0)`).
fn unit_quaternion(s: &mut Sampler) -> Quaternion<f64> {
    Quaternion::exp(&rotation_vector(s))
}

/// Every formula of this module, with its sampler.
pub fn audits() -> Vec<crate::Audit> {
    use crate::Audit;
    vec![
        Audit::of(|s| QuaternionExp(rotation_vector(s))),
        Audit::of(|s| QuaternionLog(unit_quaternion(s))),
        Audit::of(|s| BchLeft(rotation_vector(s))),
        Audit::of(|s| BchRight(rotation_vector(s))),
        Audit::of(|s| LeftRightJacobians(rotation_vector(s))),
        Audit::of(|s| ProjectionJacobian(PointContext::sample(s))),
        Audit::of(|s| PointTransformJacobian(PointContext::sample(s))),
        Audit::of(|s| PoseTransformJacobian(PointContext::sample(s))),
        Audit::of(|s| PointResidualJacobian(PointContext::sample(s))),
        Audit::of(|s| PointPoseResidualJacobian(PointContext::sample(s))),
    ]
}

/// The chain rules of §II: (5) combines (2), (3) and (4).
pub fn chains() -> Vec<crate::chain::Chain> {
    use crate::chain::Chain;
    vec![
        Chain {
            document: DOCUMENT.into(),
            composed: "(5) ∂ρ/∂^wP".into(),
            links: ["(2)", "(3)"].map(String::from).to_vec(),
        },
        Chain {
            document: DOCUMENT.into(),
            composed: "(5) ∂ρ/∂ξ".into(),
            links: ["(2)", "(4)"].map(String::from).to_vec(),
        },
    ]
}
