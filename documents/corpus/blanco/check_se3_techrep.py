"""Independent check of every formula claimed in the excerpt of Blanco's
SE(3) technical report (se3_techrep.tex): numpy and scipy only.

    python3 documents/corpus/blanco/check_se3_techrep.py            # the excerpt
    python3 documents/corpus/blanco/check_se3_techrep.py --planted  # se3_techrep.planted.tex

The report's conventions, from its own definitions:
- a derivative by a pose is by the 12 entries of the top 3 × 4 of its
  matrix, column by column (`vec` without the fixed last row); a derivative
  of a matrix is of its `vec` (column-major), of a pose of its top 3 × 4;
- poses compose as matrices: f_⊕(A, B) = T_A T_B, g_⊕(A, p) = R_A p + t_A,
  p ⊖ A = T_A⁻¹ p with the inverse in its closed form [R_Aᵀ, −R_Aᵀ t_A]
  (a function of the 12 entries);
- ε = (d_x, d_y, d_z, ωᵀ)ᵀ, translation first, e^ε the SE(3) exponential of
  the twist [ω^, d; 0, 0] (scipy's matrix exponential), derivatives at ε = 0;
- e_q^ω = (cos(|ω|/2), sin(|ω|/2)/|ω| ω) the quaternion exponential
  (real part first), log(R)^∨ = θ/(2 sin θ) (R − Rᵀ)^∨ with
  θ = acos((tr R − 1)/2), pseudo-log(T)^∨ = (t, log(R)^∨);
- h(p) = (c_x + f_x p_x/p_z, c_y + f_y p_y/p_z).

Each printed formula is transcribed as printed; a printed derivative on a
right side is evaluated as printed (by finite differences at the point it
names), a Kronecker product is numpy's `kron`. A zero block whose printed
size disagrees with its place takes the size its neighbours force (the
disagreement is reported as an erratum, not as malformed).
"""

import os
import sys

import numpy as np
from scipy.linalg import expm

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))
from independent import (  # noqa: E402
    claimer,
    block,
    col,
    hat,
    jacobian,
    mul,
    planted_mode,
    report,
    report_planted,
    rotation,
    vee,
)

HERE = os.path.dirname(__file__)
PLANTED = planted_mode()
rng = np.random.default_rng(2010)
I3, I4 = np.eye(3), np.eye(4)
Z3 = np.zeros((3, 3))
E = [np.eye(3)[:, i] for i in range(3)]


def vec(m):
    """vec of a matrix, column-major; of a 4 × 4 pose, of its top 3 × 4."""
    m = np.asarray(m)
    return (m[:3, :] if m.shape == (4, 4) else m).ravel(order="F")


def unvec(v):
    """The 4 × 4 pose matrix with the top 3 × 4 vec v (any entries)."""
    m = np.eye(4)
    m[:3, :] = np.asarray(v).reshape(3, 4, order="F")
    return m


def pose_matrix(r, t):
    return unvec(np.concatenate([r.ravel(order="F"), t]))


def twist_dw(eps):
    """The twist of ε = (d, ω): [ω^, d; 0, 0]."""
    m = np.zeros((4, 4))
    m[:3, :3], m[:3, 3] = hat(eps[3:6]), eps[0:3]
    return m


def exp_eps(eps):
    return expm(twist_dw(eps))


def closed_inverse(t):
    r, tr = t[:3, :3], t[:3, 3]
    return pose_matrix(r.T, -r.T @ tr)


def transform(t, p):
    return t[:3, :3] @ p + t[:3, 3]


def log_formula(r):
    """log(R)^∨ by the report's formula, a function of the 9 entries."""
    c = (np.trace(r) - 1) / 2
    th = np.arccos(c)
    return vee(r - r.T) * th / (2 * np.sin(th))


def pseudo_log(t):
    return np.concatenate([t[:3, 3], log_formula(t[:3, :3])])


def quat_exp(w):
    th = np.linalg.norm(w)
    return np.concatenate([[np.cos(th / 2)], np.sin(th / 2) / th * w])


def kron(a, b):
    return np.kron(np.atleast_2d(a), np.atleast_2d(b))


def T33():
    """The transpose permutation matrix: T₃,₃ vec(A) = vec(Aᵀ)."""
    return np.stack([vec(np.reshape(e, (3, 3), order="F").T) for e in np.eye(9)], axis=1)


eps0 = np.zeros(6)


def d_exp_at_zero():
    return jacobian(lambda e: vec(exp_eps(e)), eps0)


def d_vec_by_pose(f, t):
    """∂f(T)/∂T: by the 12 entries of the top of T."""
    return jacobian(lambda v: f(unvec(v)), vec(t))


def random_pose(r):
    return pose_matrix(rotation(r), r.uniform(-2, 2, 3))


samples = []
for _ in range(20):
    s = {
        "A": random_pose(rng),
        "B": random_pose(rng),
        "D": random_pose(rng),
        "P1": random_pose(rng),
        "P2": random_pose(rng),
        "R": rotation(rng),
        "w": rng.normal(size=3) * rng.uniform(0.1, 1.0),
        "f": rng.uniform(300, 600, 2),
        "c": rng.uniform(200, 400, 2),
    }
    # Points in front of the camera: g = A ⊕ p and l = p ⊖ A have z > 1.
    s["p"] = closed_inverse(s["A"])[:3, :] @ np.append(rng.uniform(-1, 1, 2).tolist() + [rng.uniform(2, 4)], 1)
    s["q"] = transform(s["A"], rng.uniform(-1, 1, 2).tolist() + [rng.uniform(2, 4)])
    samples.append(s)

results = {}


claim = claimer(samples, results)


def R_(t):
    return t[:3, :3]


def t_(t):
    return t[:3, 3]


# ---------------------------------------------------------------------------
# Derivatives of pose transformation matrices.
# ---------------------------------------------------------------------------

d_AB_dA = lambda s: d_vec_by_pose(lambda a: vec(a @ s["B"]), s["A"])  # noqa: E731
d_AB_dB = lambda s: d_vec_by_pose(lambda b: vec(s["A"] @ b), s["B"])  # noqa: E731
claim("∂f⊕(A,B)/∂A = ∂T_AT_B/∂T_A", d_AB_dA, d_AB_dA)
claim("∂f⊕(A,B)/∂A = T_Bᵀ ⊗ I₃", lambda s: kron(s["B"].T, I3), d_AB_dA)
claim("∂f⊕(A,B)/∂B = ∂T_AT_B/∂T_B", d_AB_dB, d_AB_dB)
claim("∂f⊕(A,B)/∂B = I₄ ⊗ R_A", lambda s: kron(I4, R_(s["A"])), d_AB_dB)

d_Ap_dp = lambda s: jacobian(lambda p: transform(s["A"], p), s["p"])  # noqa: E731
d_Ap_dA = lambda s: d_vec_by_pose(lambda a: transform(a, s["p"]), s["A"])  # noqa: E731
claim("∂g⊕(A,p)/∂p = ∂T_Ap/∂p", d_Ap_dp, d_Ap_dp)
claim("∂g⊕(A,p)/∂p = ∂(R_Ap + t_A)/∂p",
      lambda s: jacobian(lambda p: R_(s["A"]) @ p + t_(s["A"]), s["p"]), d_Ap_dp)
claim("∂g⊕(A,p)/∂p = R_A", lambda s: R_(s["A"]), d_Ap_dp)
claim("∂g⊕(A,p)/∂A = ∂T_Ap/∂T_A", d_Ap_dA, d_Ap_dA)
claim("∂g⊕(A,p)/∂A = (pᵀ 1) ⊗ I₃", lambda s: kron(np.append(s["p"], 1).reshape(1, 4), I3), d_Ap_dA)

d_inv_dA = lambda s: d_vec_by_pose(lambda a: vec(closed_inverse(a)), s["A"])  # noqa: E731


def dinv_printed(s):
    """[T₃,₃ 0_{9×3}; I₃ ⊗ (−t_Aᵀ) −R_Aᵀ]."""
    return block([[T33(), np.zeros((9, 3))],
                  [kron(I3, -t_(s["A"]).reshape(1, 3)), -R_(s["A"]).T]])


claim("∂T_A⁻¹/∂T_A", dinv_printed, d_inv_dA)

d_pminA_dp = lambda s: jacobian(lambda p: transform(closed_inverse(s["A"]), p), s["p"])  # noqa: E731
d_pminA_dA = lambda s: d_vec_by_pose(lambda a: transform(closed_inverse(a), s["p"]), s["A"])  # noqa: E731
claim("∂(T_A⁻¹p)/∂p = (R_A)⁻¹", lambda s: np.linalg.inv(R_(s["A"])), d_pminA_dp)
claim("∂(T_A⁻¹p)/∂p = R_Aᵀ", lambda s: R_(s["A"]).T, d_pminA_dp)
claim(
    "∂(T_A⁻¹p)/∂T_A = chain of derivatives",
    lambda s: mul(
        d_vec_by_pose(lambda m: transform(m, s["p"]), closed_inverse(s["A"])),
        d_inv_dA(s),
    ),
    d_pminA_dA,
)
claim(
    "∂(T_A⁻¹p)/∂T_A = [(pᵀ 1) ⊗ I₃][…]",
    # The printed zero block 0_{3×9} sits where only 9 × 3 fits (the same
    # matrix as in ∂T_A⁻¹/∂T_A): taken as its neighbours size it.
    lambda s: mul(kron(np.append(s["p"], 1).reshape(1, 4), I3), dinv_printed(s)),
    d_pminA_dA,
)
claim(
    "∂(T_A⁻¹p)/∂T_A = [I₃ ⊗ (p − t_A)ᵀ | −R_Aᵀ]",
    lambda s: block([[kron(I3, (s["p"] - t_(s["A"])).reshape(1, 3)), -R_(s["A"]).T]]),
    d_pminA_dA,
)

# ---------------------------------------------------------------------------
# Useful manifold derivatives.
# ---------------------------------------------------------------------------

d_expw = lambda s: jacobian(lambda w: vec(expm(hat(w))), np.zeros(3))  # noqa: E731
claim("∂e^ω/∂ω|₀ ≡ ∂vec(e^ω)/∂ω|₀", d_expw, d_expw)
claim("∂vec(e^ω)/∂ω|₀ = (−e₁^; −e₂^; −e₃^)",
      lambda s: block([[-hat(E[0])], [-hat(E[1])], [-hat(E[2])]]), d_expw)


def quat_partials_printed(s):
    w = s["w"]
    n = np.linalg.norm(w)
    sh, ch = np.sin(n / 2), np.cos(n / 2)
    k = ch / (2 * n) - sh / n**2
    first = np.array([
        [0, 0, 0, -sh / 2],
        [sh / n, 0, 0, w[0] * k],
        [0, sh / n, 0, w[1] * k],
        [0, 0, sh / n, w[2] * k],
    ])
    second = block([[I3], [(w / n).reshape(1, 3)]])
    return mul(first, second)


def quat_chain_printed(s):
    # e_q(ω, θ) = (cos(θ/2), sin(θ/2)/θ ω) with θ free, then θ = |ω|.
    w = s["w"]
    n = np.linalg.norm(w)
    eq_wt = lambda x: np.concatenate([[np.cos(x[3] / 2)], np.sin(x[3] / 2) / x[3] * x[0:3]])  # noqa: E731
    return mul(jacobian(eq_wt, np.append(w, n)),
               jacobian(lambda x: np.append(x, np.linalg.norm(x)), w))


d_quat = lambda s: jacobian(quat_exp, s["w"])  # noqa: E731
# The display is evaluated "|_{ω=0}" but its entries divide by |ω|: it is the
# Jacobian at any ω ≠ 0 (checked at sampled ω), undefined at ω = 0 itself.
claim("∂e_q^ω/∂ω (chain)", quat_chain_printed, d_quat)
claim("∂e_q^ω/∂ω (4×4)(4×3)", quat_partials_printed, d_quat)

d_exp_eps = lambda s: d_exp_at_zero()  # noqa: E731
claim("∂e^ε/∂ε|₀ ≡ ∂vec(e^ε)/∂ε|₀", d_exp_eps, d_exp_eps)


def exp_eps_printed(s=None):
    return block([[Z3, -hat(E[0])], [Z3, -hat(E[1])], [Z3, -hat(E[2])], [I3, Z3]])


claim("∂vec(e^ε)/∂ε|₀ = (0 −e₁^; 0 −e₂^; 0 −e₃^; I₃ 0)", exp_eps_printed, d_exp_eps)


def dlog_printed(s):
    r = s["R"]
    c = (np.trace(r) - 1) / 2
    sn = np.sqrt(1 - c**2)
    th = np.arccos(c)
    a = vee(r - r.T) * (th * c - sn) / (4 * sn**3)
    b = th / (2 * sn)
    return np.array([
        [a[0], 0, 0, 0, a[0], b, 0, -b, a[0]],
        [a[1], 0, -b, 0, a[1], 0, b, 0, a[1]],
        [a[2], b, 0, -b, a[2], 0, 0, 0, a[2]],
    ])


d_log = lambda s: jacobian(lambda v: log_formula(v.reshape(3, 3, order="F")), vec(s["R"]))  # noqa: E731
claim("∂log(R)^∨/∂R (otherwise)", dlog_printed, d_log)
claim(
    "[a₁ a₂ a₃] = [R − Rᵀ]^∨ … = [R₃₂ − R₂₃ …] …",
    lambda s: (lambda r: np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]]))(s["R"]),
    lambda s: vee(s["R"] - s["R"].T),
)

# e^ε ⊕ D.
d_eD = lambda s: jacobian(lambda e: vec(exp_eps(e) @ s["D"]), eps0)  # noqa: E731


def eD_block(s, left=None):
    left = I3 if left is None else left
    d = s["D"]
    return block([[Z3, -mul(left, hat(d[:3, 0]))], [Z3, -mul(left, hat(d[:3, 1]))],
                  [Z3, -mul(left, hat(d[:3, 2]))], [left, -mul(left, hat(d[:3, 3]))]])


claim("∂(e^εD)/∂ε = ∂(AD)/∂A ∂e^ε/∂ε",
      lambda s: mul(d_vec_by_pose(lambda a: vec(a @ s["D"]), I4), d_exp_at_zero()), d_eD)
claim("∂(e^εD)/∂ε = [T(D)ᵀ ⊗ I₃] ∂e^ε/∂ε",
      lambda s: mul(kron(s["D"].T, I3), d_exp_at_zero()), d_eD)
claim("∂(e^εD)/∂ε = (0 −d_c1^; …; I₃ −d_t^)", eD_block, d_eD)

# D ⊕ e^ε.
d_De = lambda s: jacobian(lambda e: vec(s["D"] @ exp_eps(e)), eps0)  # noqa: E731


def De_printed(s):
    d = s["D"]
    dc1, dc2, dc3 = (col(d[:3, i]) for i in range(3))
    z = np.zeros((3, 1))
    rot = block([[z, -dc3, dc2], [dc3, z, -dc1], [-dc2, dc1, z]])
    return block([[np.zeros((9, 3)), rot], [R_(d), Z3]])


claim("∂(De^ε)/∂ε = ∂(AB)/∂B ∂e^ε/∂ε",
      lambda s: mul(d_vec_by_pose(lambda b: vec(s["D"] @ b), I4), d_exp_at_zero()), d_De)
claim("∂(De^ε)/∂ε = [I₄ ⊗ R(D)](…)", lambda s: mul(kron(I4, R_(s["D"])), exp_eps_printed()), d_De)
claim("∂(De^ε)/∂ε = (0₉ₓ₃ | …; R(D) | 0)", De_printed, d_De)

# e^ε ⊕ D ⊕ p.
d_eDp = lambda s: jacobian(lambda e: transform(exp_eps(e) @ s["D"], s["p"]), eps0)  # noqa: E731
claim("∂((e^εD) ⊕ p)/∂ε = ∂(A ⊕ p)/∂A ∂(e^εD)/∂ε",
      lambda s: mul(d_vec_by_pose(lambda a: transform(a, s["p"]), s["D"]), d_eD(s)), d_eDp)
claim("∂((e^εD) ⊕ p)/∂ε = ((pᵀ 1) ⊗ I₃)(…)",
      lambda s: mul(kron(np.append(s["p"], 1).reshape(1, 4), I3), eD_block(s)), d_eDp)
claim("∂((e^εD) ⊕ p)/∂ε = (I₃ −[D ⊕ p]^)",
      lambda s: block([[I3, -hat(transform(s["D"], s["p"]))]]), d_eDp)

# p ⊖ (e^ε ⊕ D).
d_pmeD = lambda s: jacobian(lambda e: transform(closed_inverse(exp_eps(e) @ s["D"]), s["p"]), eps0)  # noqa: E731


def pmeD_explicit(s):
    d, (px, py, pz) = s["D"], s["p"]
    rows = [[d[1, i] * pz - d[2, i] * py, -d[0, i] * pz + d[2, i] * px, d[0, i] * py - d[1, i] * px]
            for i in range(3)]
    return block([[-R_(d).T, np.array(rows)]])


claim("∂(p ⊖ (e^εD))/∂ε = ∂(p ⊖ A)/∂A ∂(e^εD)/∂ε",
      lambda s: mul(d_vec_by_pose(lambda a: transform(closed_inverse(a), s["p"]), s["D"]), d_eD(s)),
      d_pmeD)
claim("∂(p ⊖ (e^εD))/∂ε = (I₃ ⊗ (p − d_t)ᵀ | −R_Dᵀ)(…)",
      lambda s: mul(block([[kron(I3, (s["p"] - t_(s["D"])).reshape(1, 3)), -R_(s["D"]).T]]),
                    eD_block(s)),
      d_pmeD)
claim("∂(p ⊖ (e^εD))/∂ε = (−R_Dᵀ | d₂₁p_z − d₃₁p_y …)", pmeD_explicit, d_pmeD)

# A ⊕ e^ε ⊕ D.
d_AeD = lambda s: jacobian(lambda e: vec(s["A"] @ exp_eps(e) @ s["D"]), eps0)  # noqa: E731
claim("∂(Ae^εD)/∂ε = ∂(AB)/∂B ∂(e^εD)/∂ε",
      lambda s: mul(d_vec_by_pose(lambda b: vec(s["A"] @ b), s["D"]), d_eD(s)), d_AeD)
claim("∂(Ae^εD)/∂ε = [I₄ ⊗ R(A)] ∂(e^εD)/∂ε",
      lambda s: mul(kron(I4, R_(s["A"])), d_eD(s)), d_AeD)
claim("∂(Ae^εD)/∂ε = (0 −R(A)d_c1^; …; R(A) −R(A)d_t^)",
      lambda s: eD_block(s, left=R_(s["A"])), d_AeD)

# A ⊕ e^ε ⊕ D ⊕ p.
d_AeDp = lambda s: jacobian(lambda e: transform(s["A"] @ exp_eps(e) @ s["D"], s["p"]), eps0)  # noqa: E731


def AeDp_printed(s):
    d, p = s["D"], s["p"]
    g = [p @ d[i, :3] + d[i, 3] for i in range(3)]  # p · d_ri + d_ti
    m = np.array([[0, g[2], -g[1]], [-g[2], 0, g[0]], [g[1], -g[0], 0]])
    return mul(R_(s["A"]), block([[I3, m]]))


claim("∂(Ae^εDp)/∂ε", AeDp_printed, d_AeDp)


# ≈ for A and D near the identity: at rotations R(A) = R(D) = I the printed
# approximation is the Jacobian itself.
def near_identity(s):
    return dict(s, A=pose_matrix(I3, t_(s["A"])), D=pose_matrix(I3, t_(s["D"])))


claim(
    "∂(Ae^εDp)/∂ε ≈ (I₃ −[p + d_t]^)",
    lambda s: block([[I3, -hat(s["p"] + t_(s["D"]))]]),
    lambda s: d_AeDp(near_identity(s)),
)

# p ⊖ (A ⊕ e^ε ⊕ D).
d_pmAeD = lambda s: jacobian(  # noqa: E731
    lambda e: transform(closed_inverse(s["A"] @ exp_eps(e) @ s["D"]), s["p"]), eps0)
claim(
    "∂((Ae^εD)⁻¹p)/∂ε",
    lambda s: (lambda AD: mul(block([[kron(I3, (s["p"] - t_(AD)).reshape(1, 3)), -R_(AD).T]]),
                              eD_block(s, left=R_(s["A"]))))(s["A"] @ s["D"]),
    d_pmAeD,
)


# ((P₂ ⊕ e^ε²) ⊖ (P₁ ⊕ e^ε¹)) ⊖ D: "log" is the pseudo-log of the report's
# Eq. (dLnSE3_wrt_SE3), to which the printed chain refers.
def dpseudo_log_printed(t):
    return block([[np.zeros((3, 9)), I3], [dlog_printed({"R": R_(t)}), Z3]])


def graph_T(s):
    return closed_inverse(s["D"]) @ closed_inverse(s["P1"]) @ s["P2"]


d_graph1 = lambda s: jacobian(  # noqa: E731
    lambda e: pseudo_log(closed_inverse(s["D"]) @ closed_inverse(s["P1"] @ exp_eps(e)) @ s["P2"]), eps0)
d_graph2 = lambda s: jacobian(  # noqa: E731
    lambda e: pseudo_log(closed_inverse(s["D"]) @ closed_inverse(s["P1"]) @ s["P2"] @ exp_eps(e)), eps0)
claim(
    "∂log(D⁻¹(P₁e^ε¹)⁻¹P₂)^∨/∂ε₁ (chain)",
    lambda s: mul(
        dpseudo_log_printed(graph_T(s)),
        d_vec_by_pose(lambda a: vec(a @ closed_inverse(s["P1"]) @ s["P2"]), closed_inverse(s["D"])),
        -jacobian(lambda e: vec(closed_inverse(s["D"]) @ exp_eps(e)), eps0),
    ),
    d_graph1,
)
claim(
    "∂log(D⁻¹P₁⁻¹P₂e^ε²)^∨/∂ε₂ (chain)",
    lambda s: mul(dpseudo_log_printed(graph_T(s)),
                  jacobian(lambda e: vec(graph_T(s) @ exp_eps(e)), eps0)),
    d_graph2,
)
claim(
    "∂pseudo-log(T)^∨/∂T",
    lambda s: dpseudo_log_printed(pose_matrix(s["R"], t_(s["A"]))),
    lambda s: d_vec_by_pose(pseudo_log, pose_matrix(s["R"], t_(s["A"]))),
)

# ---------------------------------------------------------------------------
# Applications to computer vision.
# ---------------------------------------------------------------------------


def h(s, p):
    return np.array([s["c"][0] + s["f"][0] * p[0] / p[2], s["c"][1] + s["f"][1] * p[1] / p[2]])


def dh_printed(s, g):
    (fx, fy), (gx, gy, gz) = s["f"], g
    return np.array([[fx / gz, 0, -fx * gx / gz**2], [0, fy / gz, -fy * gy / gz**2]])


claim("∂h(p)/∂p", lambda s: dh_printed(s, s["q"]), lambda s: jacobian(lambda p: h(s, p), s["q"]))


def g_of(s):
    return transform(s["A"], s["p"])


def l_of(s):
    return transform(closed_inverse(s["A"]), s["q"])


d_hAp_dp = lambda s: jacobian(lambda p: h(s, transform(s["A"], p)), s["p"])  # noqa: E731
d_hAp_de = lambda s: jacobian(lambda e: h(s, transform(exp_eps(e) @ s["A"], s["p"])), eps0)  # noqa: E731
dh_at = lambda s, g: jacobian(lambda p: h(s, p), g)  # noqa: E731  the printed ∂h(p')/∂p'|_{p'=g}
claim("∂h(e^ε⊕A⊕p)/∂p = ∂h/∂p'|_g ∂(e^ε⊕A⊕p)/∂p",
      lambda s: mul(dh_at(s, g_of(s)), jacobian(lambda p: transform(s["A"], p), s["p"])), d_hAp_dp)
claim("∂h(e^ε⊕A⊕p)/∂p = ∂h/∂p'|_g ∂(A⊕p)/∂p",
      lambda s: mul(dh_at(s, g_of(s)), jacobian(lambda p: transform(s["A"], p), s["p"])), d_hAp_dp)
claim("∂h(e^ε⊕A⊕p)/∂p = (…) R_A", lambda s: mul(dh_printed(s, g_of(s)), R_(s["A"])), d_hAp_dp)


def hAp_de_explicit(s):
    (fx, fy), (gx, gy, gz) = s["f"], g_of(s)
    return np.array([
        [fx / gz, 0, -fx * gx / gz**2, -fx * gx * gy / gz**2, fx * (1 + gx**2 / gz**2), -fx * gy / gz],
        [0, fy / gz, -fy * gy / gz**2, -fy * (1 + gy**2 / gz**2), fy * gx * gy / gz**2, fy * gx / gz],
    ])


claim("∂h(e^ε⊕A⊕p)/∂ε = ∂h/∂p'|_g ∂(e^ε⊕A⊕p)/∂ε",
      lambda s: mul(dh_at(s, g_of(s)),
                    jacobian(lambda e: transform(exp_eps(e) @ s["A"], s["p"]), eps0)), d_hAp_de)
claim("∂h(e^ε⊕A⊕p)/∂ε = (…)(I₃ −g^)",
      lambda s: mul(dh_printed(s, g_of(s)), block([[I3, -hat(g_of(s))]])), d_hAp_de)
claim("∂h(e^ε⊕A⊕p)/∂ε = (2 × 6 explicit)", hAp_de_explicit, d_hAp_de)

d_hpmA_dp = lambda s: jacobian(lambda p: h(s, transform(closed_inverse(s["A"]), p)), s["q"])  # noqa: E731
d_hpmA_de = lambda s: jacobian(  # noqa: E731
    lambda e: h(s, transform(closed_inverse(exp_eps(e) @ s["A"]), s["q"])), eps0)
d_pmA = lambda s: jacobian(lambda p: transform(closed_inverse(s["A"]), p), s["q"])  # noqa: E731
claim("∂h(p⊖(e^ε⊕A))/∂p = ∂h/∂p'|_l ∂(p⊖(e^ε⊕A))/∂p",
      lambda s: mul(dh_at(s, l_of(s)), d_pmA(s)), d_hpmA_dp)
claim("∂h(p⊖(e^ε⊕A))/∂p = ∂h/∂p'|_l ∂(p⊖A)/∂p",
      lambda s: mul(dh_at(s, l_of(s)), d_pmA(s)), d_hpmA_dp)
claim("∂h(p⊖(e^ε⊕A))/∂p = (…) R_Aᵀ", lambda s: mul(dh_printed(s, l_of(s)), R_(s["A"]).T), d_hpmA_dp)
d_pmeA = lambda s: jacobian(lambda e: transform(closed_inverse(exp_eps(e) @ s["A"]), s["q"]), eps0)  # noqa: E731
claim("∂h(p⊖(e^ε⊕A))/∂ε = ∂h/∂p'|_{p⊖A} ∂(p⊖(e^ε⊕A))/∂ε",
      lambda s: mul(dh_at(s, l_of(s)), d_pmeA(s)), d_hpmA_de)
claim("∂h(p⊖(e^ε⊕A))/∂ε = (…) ∂(p⊖(e^ε⊕A))/∂ε",
      lambda s: mul(dh_printed(s, l_of(s)), d_pmeA(s)), d_hpmA_de)


if PLANTED:
    # The planted copy's printed formulas (se3_techrep.planted.md says where).
    claim("∂(e^εD)/∂ε = [T(D)ᵀ ⊗ I₃] ∂e^ε/∂ε",
          lambda s: mul(kron(s["D"], I3), d_exp_at_zero()), d_eD)
    claim("∂(Ae^εD)/∂ε = (0 −R(A)d_c1^; …; R(A) −R(A)d_t^)",
          lambda s: (lambda m: block([[m[0:3]], [m[6:9]], [m[3:6]], [m[9:12]]]))(
              eD_block(s, left=R_(s["A"]))),
          d_AeD)
    claim("∂h(p⊖(e^ε⊕A))/∂p = (…) R_Aᵀ",
          lambda s: mul(-dh_printed(s, l_of(s)), R_(s["A"]).T), d_hpmA_dp)

    def dh_planted(s, g):
        m = dh_printed(s, g)
        m[0, 2] /= s["f"][0]  # −p_x/p_z²: the factor f_x lost
        return m

    claim("∂h(p)/∂p", lambda s: dh_planted(s, s["q"]), lambda s: jacobian(lambda p: h(s, p), s["q"]))
    report_planted(os.path.join(HERE, "se3_techrep.planted.md"), results)
else:
    report(os.path.join(HERE, "se3_techrep.symbols.toml"), results)
