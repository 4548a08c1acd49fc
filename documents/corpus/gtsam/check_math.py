"""Independent check of every derivative formula of the GTSAM math.lyx excerpt
(math.tex): numpy and scipy only.

    python3 documents/corpus/gtsam/check_math.py

GTSAM's conventions: R ⊕ ω = R Exp(ω), T ⊕ ξ = T Exp(ξ), ξ = [ω, v]
(rotation first), a group-valued map read in right local coordinates
(log(f₀⁻¹ f)). The adjoint Ad_T is built from its definition
(T ξ̂ T⁻¹ = (Ad_T ξ)^), ad from the Lie bracket, never from a closed form.
"""

import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))
from independent import (  # noqa: E402
    exp_se3,
    exp_so3,
    hat,
    jacobian,
    judge,
    log_se3,
    log_so3,
    pose,
    report,
    rotation,
    twist,
    vee,
)

rng = np.random.default_rng(11)
I3, I6 = np.eye(3), np.eye(6)
z3, z6 = np.zeros(3), np.zeros(6)


def vee6(m):
    return np.concatenate([vee(m[:3, :3]), m[:3, 3]])


def adjoint(t):
    """Ad_T: the matrix with T ξ̂ T⁻¹ = (Ad_T ξ)^, column by column."""
    ti = np.linalg.inv(t)
    return np.stack([vee6(t @ twist(e) @ ti) for e in I6], axis=1)


def small_adjoint(x):
    """ad_x: ad_x y = vee([x̂, ŷ]), column by column."""
    return np.stack([vee6(twist(x) @ twist(e) - twist(e) @ twist(x)) for e in I6], axis=1)


def project(x):
    return np.array([x[0] / x[2], x[1] / x[2]])


def random_pose(r):
    return pose(rotation(r), r.uniform(-2, 2, 3))


samples = [
    {
        "R": rotation(rng),
        "R1": rotation(rng),
        "R2": rotation(rng),
        "p": rng.uniform(-3, 3, 3),
        "T": random_pose(rng),
        "T1": random_pose(rng),
        "T2": random_pose(rng),
        "xb": rng.uniform(-1, 1, 6),
        "xs": rng.uniform(-1, 1, 6),
    }
    for _ in range(20)
]
for s in samples:
    # The point in front of the camera, for π.
    s["p"] = s["T"][:3, :3] @ np.array([0.3, -0.2, 2.0 + s["p"][2] ** 2]) + s["T"][:3, 3]
results = {}


def claim(cid, printed, truth):
    results[cid] = judge(printed, truth, samples)


def right_so3(f):
    f0 = f(z3)
    return lambda d: log_so3(f0.T @ f(d))


def right_se3(f):
    f0 = f(z6)
    return lambda d: log_se3(np.linalg.inv(f0) @ f(d))


def homogeneous(p):
    return np.append(p, 1.0)


def inv(m):
    return np.linalg.inv(m)


# 3D rotations.
claim(
    "∂(Rp)/∂ω",
    lambda s: -s["R"] @ hat(s["p"]),
    lambda s: jacobian(lambda d: s["R"] @ exp_so3(d) @ s["p"], z3),
)
claim(
    "∂(Rᵀp)/∂ω",
    lambda s: hat(s["R"].T @ s["p"]),
    lambda s: jacobian(lambda d: (s["R"] @ exp_so3(d)).T @ s["p"], z3),
)
claim(
    "∂Rᵀ/∂ω",
    lambda s: -s["R"],
    lambda s: jacobian(right_so3(lambda d: (s["R"] @ exp_so3(d)).T), z3),
)
claim(
    "∂(R₁R₂)/∂ω₁",
    lambda s: s["R2"].T,
    lambda s: jacobian(right_so3(lambda d: s["R1"] @ exp_so3(d) @ s["R2"]), z3),
)
claim(
    "∂(R₁R₂)/∂ω₂",
    lambda s: I3,
    lambda s: jacobian(right_so3(lambda d: s["R1"] @ s["R2"] @ exp_so3(d)), z3),
)
claim(
    "∂(R₁ᵀR₂)/∂ω₁",
    lambda s: -(s["R2"].T @ s["R1"]),
    lambda s: jacobian(right_so3(lambda d: (s["R1"] @ exp_so3(d)).T @ s["R2"]), z3),
)
claim(
    "∂(R₁R₂)/∂ω₂ (between)",
    lambda s: I3,
    lambda s: jacobian(right_so3(lambda d: s["R1"] @ s["R2"] @ exp_so3(d)), z3),
)

claim(
    "∂(Rp)/∂ω = RH(p)",
    lambda s: s["R"] @ hat(-s["p"]),
    lambda s: jacobian(lambda d: s["R"] @ exp_so3(d) @ s["p"], z3),
)
claim(
    "∂(Rᵀp)/∂ω = −H(Rᵀp)",
    lambda s: -hat(-(s["R"].T @ s["p"])),
    lambda s: jacobian(lambda d: (s["R"] @ exp_so3(d)).T @ s["p"], z3),
)
claim(
    "∂Rᵀ/∂ω = −Ad_R",
    # Ad_R by its definition: R ω̂ Rᵀ = (Ad_R ω)^, column by column.
    lambda s: -np.stack([vee(s["R"] @ hat(e) @ s["R"].T) for e in I3], axis=1),
    lambda s: jacobian(right_so3(lambda d: (s["R"] @ exp_so3(d)).T), z3),
)
claim(
    "∂(R₁ᵀR₂)/∂ω₁ = −R₂ᵀR₁",
    lambda s: -(s["R2"].T @ s["R1"]),
    lambda s: jacobian(right_so3(lambda d: (s["R1"] @ exp_so3(d)).T @ s["R2"]), z3),
)

# 3D rigid transformations.
claim(
    "∂(Tp̂)/∂ξ",
    lambda s: np.block(
        [[s["T"][:3, :3] @ hat(-s["p"]), s["T"][:3, :3]], [np.zeros((1, 3)), np.zeros((1, 3))]]
    ),
    lambda s: jacobian(lambda d: s["T"] @ exp_se3(d) @ homogeneous(s["p"]), z6),
)
claim(
    "∂(Tp̂)/∂p̂",
    lambda s: s["T"],
    lambda s: jacobian(lambda x: s["T"] @ x, homogeneous(s["p"])),
)
claim(
    "∂(T⁻¹p̂)/∂ξ",
    lambda s: np.hstack([hat((inv(s["T"]) @ homogeneous(s["p"]))[:3]), -I3]),
    lambda s: jacobian(lambda d: (inv(s["T"] @ exp_se3(d)) @ homogeneous(s["p"]))[:3], z6),
)
claim(
    "∂(T⁻¹p̂)/∂p̂",
    lambda s: np.block(
        [
            [s["T"][:3, :3].T, (-s["T"][:3, :3].T @ s["T"][:3, 3]).reshape(3, 1)],
            [np.zeros((1, 3)), np.ones((1, 1))],
        ]
    ),
    lambda s: jacobian(lambda x: inv(s["T"]) @ x, homogeneous(s["p"])),
)


def h_homogeneous(p):
    """H(p) = [[−p]× I₃; 0 0], as the document defines it."""
    return np.block([[hat(-p), I3], [np.zeros((1, 3)), np.zeros((1, 3))]])


claim(
    "∂(Tp̂)/∂ξ = TH(p)",
    lambda s: s["T"] @ h_homogeneous(s["p"]),
    lambda s: jacobian(lambda d: s["T"] @ exp_se3(d) @ homogeneous(s["p"]), z6),
)
claim(
    "∂(Tp̂)/∂ξ = [R t; 0 1][[−p]× I₃; 0 0]",
    lambda s: pose(s["T"][:3, :3], s["T"][:3, 3]) @ h_homogeneous(s["p"]),
    lambda s: jacobian(lambda d: s["T"] @ exp_se3(d) @ homogeneous(s["p"]), z6),
)
claim(
    "∂(T⁻¹p̂)/∂ξ = −H(T⁻¹p̂)",
    # In R³: H(p) = [−[p]× I₃].
    lambda s: -np.hstack([hat(-(inv(s["T"]) @ homogeneous(s["p"]))[:3]), I3]),
    lambda s: jacobian(lambda d: (inv(s["T"] @ exp_se3(d)) @ homogeneous(s["p"]))[:3], z6),
)


def q_of(s):
    return (inv(s["T"]) @ homogeneous(s["p"]))[:3]


def pi_prime(s):
    return jacobian(project, q_of(s))


claim(
    "∂h/∂ξ",
    lambda s: np.hstack([pi_prime(s) @ hat(q_of(s)), -pi_prime(s)]),
    lambda s: jacobian(
        lambda d: project((inv(s["T"] @ exp_se3(d)) @ homogeneous(s["p"]))[:3]), z6
    ),
)
claim(
    "∂h/∂ξ = ∂π(q)/∂q ∂(T⁻¹p)/∂ξ",
    lambda s: pi_prime(s)
    @ jacobian(lambda d: (inv(s["T"] @ exp_se3(d)) @ homogeneous(s["p"]))[:3], z6),
    lambda s: jacobian(
        lambda d: project((inv(s["T"] @ exp_se3(d)) @ homogeneous(s["p"]))[:3]), z6
    ),
)


def printed_projection_jacobian(s):
    x, y, z = q_of(s)
    return np.array([[1, 0, -x / z], [0, 1, -y / z]]) / z


claim(
    "∂h/∂ξ = (1/z')[1 0 −x'/z'; 0 1 −y'/z'][[q]× −I₃]",
    lambda s: printed_projection_jacobian(s) @ np.hstack([hat(q_of(s)), -I3]),
    lambda s: jacobian(
        lambda d: project((inv(s["T"] @ exp_se3(d)) @ homogeneous(s["p"]))[:3]), z6
    ),
)
claim(
    "∂h/∂p",
    lambda s: pi_prime(s) @ s["T"][:3, :3].T,
    lambda s: jacobian(lambda p: project((inv(s["T"]) @ homogeneous(p))[:3]), s["p"]),
)


def ad_block(t):
    r, tt = t[:3, :3], t[:3, 3]
    return np.block([[r, np.zeros((3, 3))], [hat(tt) @ r, r]])


claim(
    "∂T⁻¹/∂ξ",
    lambda s: -ad_block(s["T"]),
    lambda s: jacobian(right_se3(lambda d: inv(s["T"] @ exp_se3(d))), z6),
)
claim(
    "∂T⁻¹/∂ξ = −Ad_T",
    lambda s: -adjoint(s["T"]),
    lambda s: jacobian(right_se3(lambda d: inv(s["T"] @ exp_se3(d))), z6),
)
claim(
    "∂(T₁T₂)/∂ξ₁",
    lambda s: adjoint(inv(s["T2"])),
    lambda s: jacobian(right_se3(lambda d: s["T1"] @ exp_se3(d) @ s["T2"]), z6),
)
claim(
    "∂(T₁T₂)/∂ξ₂",
    lambda s: I6,
    lambda s: jacobian(right_se3(lambda d: s["T1"] @ s["T2"] @ exp_se3(d)), z6),
)


def between_block(s):
    r1, t1, r2, t2 = s["T1"][:3, :3], s["T1"][:3, 3], s["T2"][:3, :3], s["T2"][:3, 3]
    return np.block(
        [[-r2.T @ r1, np.zeros((3, 3))], [r2.T @ hat(t2 - t1) @ r1, -r2.T @ r1]]
    )


claim(
    "∂(T₁⁻¹T₂)/∂ξ₁",
    between_block,
    lambda s: jacobian(right_se3(lambda d: inv(s["T1"] @ exp_se3(d)) @ s["T2"]), z6),
)
claim(
    "∂(T₁⁻¹T₂)/∂ξ₁ = −Ad(T₂⁻¹T₁)",
    lambda s: -adjoint(inv(s["T2"]) @ s["T1"]),
    lambda s: jacobian(right_se3(lambda d: inv(s["T1"] @ exp_se3(d)) @ s["T2"]), z6),
)
claim(
    "∂(T₁⁻¹T₂)/∂ξ₂",
    lambda s: I6,
    lambda s: jacobian(right_se3(lambda d: inv(s["T1"]) @ s["T2"] @ exp_se3(d)), z6),
)

# The derivative of the adjoint: f(T, ξ_b) = Ad_T ξ_b, by its definition.
def f_adjoint(t, xb):
    return vee6(t @ twist(xb) @ inv(t))


claim(
    "D₂f = Ad_T",
    lambda s: adjoint(s["T"]),
    lambda s: jacobian(lambda xb: f_adjoint(s["T"], xb), s["xb"]),
)
claim(
    "D₁F = −Ad_T ad_ξb",
    lambda s: -adjoint(s["T"]) @ small_adjoint(s["xb"]),
    lambda s: jacobian(lambda d: f_adjoint(s["T"] @ exp_se3(d), s["xb"]), z6),
)


def differential(printed_of_direction):
    """A printed differential (linear in the direction ξ) as its matrix."""
    return lambda s: np.stack(
        [np.ravel(printed_of_direction(s, e), order="F") for e in I6], axis=1
    )


claim(
    "D₁Ad_T ξ̂_b(ξ)",
    differential(
        lambda s, x: -(
            s["T"] @ (twist(s["xb"]) @ twist(x) - twist(x) @ twist(s["xb"])) @ inv(s["T"])
        )
    ),
    lambda s: jacobian(
        lambda d: (s["T"] @ exp_se3(d)) @ twist(s["xb"]) @ inv(s["T"] @ exp_se3(d)), z6
    ),
)


# The first derivation of D₁f(ξ), line by line: differentials (linear in
# the direction x) of f = (T e^{x̂}) ξ̂_b (T e^{x̂})⁻¹ as 4 × 4 matrices.
def conjugated_truth(s):
    return jacobian(
        lambda d: (s["T"] @ exp_se3(d)) @ twist(s["xb"]) @ inv(s["T"] @ exp_se3(d)), z6
    )


def bracket(a, b):
    return a @ b - b @ a


for cid, printed in [
    (
        "D₁f(ξ) = D₂g(ξ) ξ̂_b g⁻¹(T,0) + g(T,0) ξ̂_b D₂g⁻¹(ξ)",
        lambda s, x: (s["T"] @ twist(x)) @ twist(s["xb"]) @ inv(s["T"])
        + s["T"] @ twist(s["xb"]) @ (-twist(x) @ inv(s["T"])),
    ),
    (
        "D₁f(ξ) = T ξ̂ ξ̂_b T⁻¹ − T ξ̂_b ξ̂ T⁻¹",
        lambda s, x: s["T"] @ twist(x) @ twist(s["xb"]) @ inv(s["T"])
        - s["T"] @ twist(s["xb"]) @ twist(x) @ inv(s["T"]),
    ),
    (
        "D₁f(ξ) = T(ξ̂ ξ̂_b − ξ̂_b ξ̂)T⁻¹",
        lambda s, x: s["T"] @ (twist(x) @ twist(s["xb"]) - twist(s["xb"]) @ twist(x)) @ inv(s["T"]),
    ),
    (
        "D₁f(ξ) = Ad_T(ad_ξ̂ ξ̂_b)",
        lambda s, x: s["T"] @ bracket(twist(x), twist(s["xb"])) @ inv(s["T"]),
    ),
    (
        "D₁f(ξ) = −Ad_T(ad_ξ̂b ξ̂)",
        lambda s, x: -(s["T"] @ bracket(twist(s["xb"]), twist(x)) @ inv(s["T"])),
    ),
    (
        "D₁Ad_T ξ̂_b(ξ) = Ad_T(ad_ξ̂(ξ̂_b))",
        lambda s, x: s["T"] @ bracket(twist(x), twist(s["xb"])) @ inv(s["T"]),
    ),
]:
    claim(cid, differential(printed), conjugated_truth)


def w_of(t, xs):
    return adjoint(t).T @ xs


claim(
    "D₁Ad_Tᵀ ξ̂_b*(ξ)",
    lambda s: np.block(
        [
            [hat(w_of(s["T"], s["xs"])[:3]), hat(w_of(s["T"], s["xs"])[3:])],
            [hat(w_of(s["T"], s["xs"])[3:]), np.zeros((3, 3))],
        ]
    ),
    lambda s: jacobian(lambda d: w_of(s["T"] @ exp_se3(d), s["xs"]), z6),
)
claim(
    "D₂g(ξ) = T ξ̂",
    differential(lambda s, x: s["T"] @ twist(x)),
    lambda s: jacobian(lambda u: s["T"] @ exp_se3(u), z6),
)
claim(
    "D₂g⁻¹(ξ) = −ξ̂ T⁻¹",
    differential(lambda s, x: -twist(x) @ inv(s["T"])),
    lambda s: jacobian(lambda u: inv(s["T"] @ exp_se3(u)), z6),
)

assert exp_so3 and log_so3  # rotations through scipy's Rotation
report(os.path.join(os.path.dirname(__file__), "math.symbols.toml"), results)
