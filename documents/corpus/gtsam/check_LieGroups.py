"""Independent check of every formula of the GTSAM "Lie Groups for
Beginners" excerpt (LieGroups.tex): numpy and scipy only.

    python3 documents/corpus/gtsam/check_LieGroups.py

The document's conventions: an increment moves a group element on the
right (R e^{[ω]}, T e^{ξ̂}) and derivatives are taken at zero; 2D rotations
are R(θ) with [ω]_+ = ω R_{π/2}; SE(2) tangents are ξ = [v; ω], SE(3)
tangents ξ = [ω; v]; Sim(3) is the document's own representation
T = [R t; 0 s⁻¹] with ξ̂ = Σ ξᵢ Gⁱ over its seven generators, e^{ξ̂} scipy's
matrix exponential. Every printed formula is transcribed as printed.
"""

import os
import sys

import numpy as np
from scipy.linalg import expm

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))
from independent import (  # noqa: E402
    add,
    block,
    col,
    hat,
    jacobian,
    judge,
    mul,
    report,
    rotation,
)

rng = np.random.default_rng(13)
I2, I3 = np.eye(2), np.eye(3)
R90 = np.array([[0.0, -1.0], [1.0, 0.0]])


def rot2(theta):
    return np.array([[np.cos(theta), -np.sin(theta)], [np.sin(theta), np.cos(theta)]])


def pose(r, t):
    m = np.eye(4)
    m[:3, :3], m[:3, 3] = r, t
    return m


def twist(xi):
    m = np.zeros((4, 4))
    m[:3, :3], m[:3, 3] = hat(xi[:3]), xi[3:6]
    return m


# The document's Sim(3) generators G¹…G⁷, as printed.
G = np.zeros((7, 4, 4))
G[0][2, 1], G[0][1, 2] = 1, -1
G[1][0, 2], G[1][2, 0] = 1, -1
G[2][1, 0], G[2][0, 1] = 1, -1
G[3][0, 3] = G[4][1, 3] = G[5][2, 3] = 1
G[6][3, 3] = -1


def sim3_hat(xi):
    return np.einsum("i,ijk->jk", xi, G)


def sim3(r, t, s):
    m = np.eye(4)
    m[:3, :3], m[:3, 3], m[3, 3] = r, t, 1 / s
    return m


samples = []
for _ in range(20):
    samples.append(
        {
            "theta": rng.uniform(-3, 3),
            "p2": rng.uniform(-3, 3, 2),
            "w": rng.uniform(-3, 3),
            "v2": rng.uniform(-3, 3, 2),
            "R": rotation(rng),
            "t": rng.uniform(-2, 2, 3),
            "p": rng.uniform(-3, 3, 3),
            "w3": rng.uniform(-3, 3, 3),
            "v3": rng.uniform(-3, 3, 3),
            "s": rng.uniform(0.5, 2.0),
            "m": rng.uniform(0.5, 2.0, 4),
        }
    )
results = {}


def claim(cid, printed, truth):
    results[cid] = judge(printed, truth, samples)


# 2D rotations. q(ω) = R e^{[ω]_+} p; derivatives at ω = 0.
def q2(s, w):
    return rot2(s["theta"]) @ expm(w * R90) @ s["p2"]


def dq2(s):
    return jacobian(lambda w: q2(s, w[0]), np.zeros(1))


def hp(s):
    return R90 @ s["p2"]


claim(
    "SO(2) ∂q(ω)/∂ω = R ∂(e^{[ω]+}p)/∂ω",
    lambda s: rot2(s["theta"]) @ jacobian(lambda w: expm(w[0] * R90) @ s["p2"], np.zeros(1)),
    dq2,
)
claim(
    "SO(2) ∂q(ω)/∂ω = R ∂(ω[1]+p)/∂ω",
    lambda s: rot2(s["theta"]) @ jacobian(lambda w: w[0] * R90 @ s["p2"], np.zeros(1)),
    dq2,
)
claim("SO(2) ∂q(ω)/∂ω = RH_p", lambda s: rot2(s["theta"]) @ hp(s).reshape(2, 1), dq2)
claim(
    "SO(2) e^{[ω]+} ≈ I + [ω]+",
    # To first order at ω = 0: the derivatives of both sides.
    lambda s: jacobian(lambda w: I2 + w[0] * R90, np.zeros(1)),
    lambda s: jacobian(lambda w: expm(w[0] * R90), np.zeros(1)),
)
claim(
    "SO(2) H_p = [−p_y; p_x]",
    lambda s: col(-s["p2"][1], s["p2"][0]),
    lambda s: R90 @ s["p2"],
)
claim(
    "SO(2) I + [ω]+ = I + ω[1]+",
    lambda s: add(I2, s["w"] * R90),
    lambda s: I2 + s["w"] * R90,
)
claim(
    "[1]+ [x; y] = R_{π/2} [x; y]",
    lambda s: R90 @ s["p2"],
    lambda s: R90 @ s["p2"],
)
claim(
    "[1]+ [x; y] = [−y; x]",
    lambda s: col(-s["p2"][1], s["p2"][0]),
    lambda s: R90 @ s["p2"],
)


# 2D rigid transformations: ξ̂ = [[ω]_+ v; 0 0], ξ = [v; ω].
def xihat2(s):
    return block([[s["w"] * R90, s["v2"].reshape(2, 1)], [np.zeros((1, 2)), 0.0]])


def vel2(s):
    return s["w"] * R90 @ s["p2"] + s["v2"]


claim(
    "SE(2) ξ̂p̂ = [[ω]+ v; 0 0][p; 1]",
    lambda s: mul(
        block([[s["w"] * R90, s["v2"].reshape(2, 1)], [np.zeros((1, 2)), 0.0]]), col(s["p2"], 1)
    ),
    lambda s: xihat2(s) @ col(s["p2"], 1),
)
claim(
    "SE(2) ξ̂p̂ = [[ω]+p + v; 0]",
    lambda s: col(vel2(s), 0),
    lambda s: xihat2(s) @ col(s["p2"], 1),
)
claim(
    "SE(2) [ω]+p + v = v + R_{π/2}pω",
    lambda s: add(s["v2"], R90 @ s["p2"] * s["w"]),
    vel2,
)
claim(
    "SE(2) [ω]+p + v = [I₂ R_{π/2}p][v; ω]",
    lambda s: mul(block([[I2, (R90 @ s["p2"]).reshape(2, 1)]]), col(s["v2"], s["w"])),
    vel2,
)


# 3D rotations: q(ω) = R e^{[ω]×} p at ω = 0.
def dq3(s):
    return jacobian(lambda w: s["R"] @ expm(hat(w)) @ s["p"], np.zeros(3))


claim(
    "SO(3) ∂q(ω)/∂ω = R ∂(e^{[ω]×}p)/∂ω",
    lambda s: s["R"] @ jacobian(lambda w: expm(hat(w)) @ s["p"], np.zeros(3)),
    dq3,
)
claim(
    "SO(3) ∂q(ω)/∂ω = R ∂([ω]×p)/∂ω",
    lambda s: s["R"] @ jacobian(lambda w: hat(w) @ s["p"], np.zeros(3)),
    dq3,
)
claim("SO(3) ∂q(ω)/∂ω = R[−p]×", lambda s: s["R"] @ hat(-s["p"]), dq3)
claim("[ω]×p = ω × p", lambda s: np.cross(s["w3"], s["p"]), lambda s: hat(s["w3"]) @ s["p"])
claim("[ω]×p = −p × ω", lambda s: -np.cross(s["p"], s["w3"]), lambda s: hat(s["w3"]) @ s["p"])
claim("[ω]×p = [−p]×ω", lambda s: hat(-s["p"]) @ s["w3"], lambda s: hat(s["w3"]) @ s["p"])


# 3D rigid transformations: q̂(ξ) = T e^{ξ̂} p̂ at ξ = 0.
def T(s):
    return pose(s["R"], s["t"])


def dq_se3(s):
    return jacobian(lambda x: T(s) @ expm(twist(x)) @ col(s["p"], 1).ravel(), np.zeros(6))


def d_xihat_p(s):
    return jacobian(lambda x: twist(x) @ col(s["p"], 1).ravel(), np.zeros(6))


claim("SE(3) ∂q̂(ξ)/∂ξ = T ∂(ξ̂p̂)/∂ξ", lambda s: T(s) @ d_xihat_p(s), dq_se3)
claim("SE(3) ∂q̂(ξ)/∂ξ = T ∂(ξ̂p̂)/∂ξ (again)", lambda s: T(s) @ d_xihat_p(s), dq_se3)
claim(
    "SE(3) ∂q̂(ξ)/∂ξ = T[−[p]× I₃; 0 0]",
    lambda s: mul(T(s), block([[-hat(s["p"]), I3], [np.zeros((1, 3)), np.zeros((1, 3))]])),
    dq_se3,
)


def xi6(s):
    return np.concatenate([s["w3"], s["v3"]])


def vel3(s):
    return twist(xi6(s)) @ col(s["p"], 1)


claim(
    "SE(3) ξ̂p̂ = [[ω]× v; 0 0][p; 1]",
    lambda s: mul(
        block([[hat(s["w3"]), s["v3"].reshape(3, 1)], [np.zeros((1, 3)), 0.0]]),
        col(s["p"], 1),
    ),
    vel3,
)
claim(
    "SE(3) ξ̂p̂ = [ω × p + v; 0]",
    lambda s: col(np.cross(s["w3"], s["p"]) + s["v3"], 0),
    vel3,
)
claim(
    "SE(3) ω × p + v = −p × ω + v",
    lambda s: add(-np.cross(s["p"], s["w3"]), s["v3"]),
    lambda s: np.cross(s["w3"], s["p"]) + s["v3"],
)
claim(
    "SE(3) ω × p + v = [−[p]× I₃][ω; v]",
    lambda s: mul(block([[-hat(s["p"]), I3]]), col(s["w3"], s["v3"])),
    lambda s: np.cross(s["w3"], s["p"]) + s["v3"],
)


def inverse_action(s):
    return np.linalg.inv(T(s)) @ col(s["p"], 1)


claim(
    "SE(3) inverse action q̂ = [Rᵀ(p − t); 1]",
    lambda s: col(s["R"].T @ (s["p"] - s["t"]), 1),
    inverse_action,
)
claim(
    "SE(3) inverse action q̂ = [Rᵀ −Rᵀt; 0 1][p; 1]",
    lambda s: mul(
        block([[s["R"].T, (-s["R"].T @ s["t"]).reshape(3, 1)], [np.zeros((1, 3)), 1.0]]),
        col(s["p"], 1),
    ),
    inverse_action,
)
claim(
    "SE(3) inverse action q̂ = T⁻¹p̂",
    lambda s: np.linalg.inv(T(s)) @ col(s["p"], 1),
    inverse_action,
)


# 3D similarity transformations, in the document's representation.
def S(s):
    return sim3(s["R"], s["t"], s["s"])


def qhat_sim3(s, x):
    return S(s) @ expm(sim3_hat(x)) @ np.append(s["p"], 1.0)


def f_sim3(s, x):
    h = qhat_sim3(s, x)
    return h[:3] / h[3]


def h_of_p(s):
    return jacobian(lambda x: sim3_hat(x) @ np.append(s["p"], 1.0), np.zeros(7))


def dq_sim3(s):
    return jacobian(lambda x: qhat_sim3(s, x), np.zeros(7))


def df_sim3(s):
    return jacobian(lambda x: f_sim3(s, x), np.zeros(7))


def H_printed(s):
    x, y, z = s["p"]
    return np.array(
        [
            [0, z, -y, 1, 0, 0, 0],
            [-z, 0, x, 0, 1, 0, 0],
            [y, -x, 0, 0, 0, 1, 0],
            [0, 0, 0, 0, 0, 0, -1],
        ],
        dtype=float,
    )


def px(s):
    return hat(s["p"])


def lower_right(s):
    return block([[-px(s), I3, np.zeros((3, 1))], [np.zeros((1, 3)), np.zeros((1, 3)), -1.0]])


def homogeneous_d(s):
    return block(
        [
            [-s["R"] @ px(s), s["R"], -s["t"].reshape(3, 1)],
            [np.zeros((1, 3)), np.zeros((1, 3)), -1 / s["s"]],
        ]
    )


def q_sim3(s):
    return s["R"] @ s["p"] + s["t"]


claim("Sim(3) H(p) = [0 z −y 1 0 0 0; …]", H_printed, h_of_p)
claim(
    "Sim(3) D₁f(ξ) = T[−[p]× I₃ 0; 0 0 −1] (homogeneous)",
    lambda s: mul(S(s), lower_right(s)),
    dq_sim3,
)
claim(
    "Sim(3) D₁f(ξ) = [−R[p]× R −t; 0 0 −s⁻¹] (homogeneous)",
    homogeneous_d,
    dq_sim3,
)
claim(
    "Sim(3) D₁f(ξ) = [sI₃ −qs²][…]",
    lambda s: mul(
        block([[s["s"] * I3, -q_sim3(s).reshape(3, 1) * s["s"] ** 2]]), homogeneous_d(s)
    ),
    df_sim3,
)
claim(
    "Sim(3) D₁f(ξ) = [−sR[p]× sR −st+qs]",
    lambda s: block(
        [
            [
                -s["s"] * s["R"] @ px(s),
                s["s"] * s["R"],
                add(-s["s"] * s["t"], q_sim3(s) * s["s"]).reshape(3, 1),
            ]
        ]
    ),
    df_sim3,
)
claim(
    "Sim(3) D₁f(ξ) = [−sR[p]× sR sRp]",
    lambda s: block(
        [[-s["s"] * s["R"] @ px(s), s["s"] * s["R"], (s["s"] * s["R"] @ s["p"]).reshape(3, 1)]]
    ),
    df_sim3,
)
claim(
    "Sim(3) q̂ = [Rp + t; s⁻¹]",
    lambda s: col(q_sim3(s), 1 / s["s"]),
    lambda s: S(s) @ np.append(s["p"], 1.0),
)
claim(
    "Sim(3) q̂ = [R t; 0 s⁻¹][p; 1]",
    lambda s: mul(
        block([[s["R"], s["t"].reshape(3, 1)], [np.zeros((1, 3)), 1 / s["s"]]]),
        col(s["p"], 1),
    ),
    lambda s: S(s) @ np.append(s["p"], 1.0),
)


# Back from homogeneous coordinates: [q; a] ↦ q/a.
claim(
    "∂(q/a)/∂[q; a] = [a⁻¹I₃ −qa⁻²]",
    lambda s: block([[I3 / s["m"][3], (-s["m"][:3] * s["m"][3] ** -2).reshape(3, 1)]]),
    lambda s: jacobian(lambda m: m[:3] / m[3], s["m"]),
)

report(os.path.join(os.path.dirname(__file__), "LieGroups.symbols.toml"), results)
