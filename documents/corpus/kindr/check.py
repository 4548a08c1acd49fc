"""Independent check of every formula of the kindr cheat sheet excerpt
(cheatsheet_kindr1.tex): numpy and scipy only.

    python3 documents/corpus/kindr/check.py

Conventions as the cheat sheet states them: Φ ⊞ v = exp(v) Φ (a rotation
is perturbed on the left, a rotation-valued map read as log(f f₀ᵀ)),
Φ₁ ⊟ Φ₂ = log(Φ₁ Φ₂ᵀ), C(Φ) the rotation matrix, Γ the Jacobian of the
exponential map (its textbook closed form, checked here against finite
differences by the claim ∂exp(v)/∂v).
"""

import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))
from independent import (  # noqa: E402
    claimer,
    add,
    exp_so3,
    hat,
    jacobian,
    log_so3,
    mul,
    report,
    rotation,
    rotation_vector,
)

rng = np.random.default_rng(7)
I = np.eye(3)


def gamma(v):
    """Γ(v): I + (1 − cos θ)/θ² v̂ + (θ − sin θ)/θ³ v̂²."""
    t = np.linalg.norm(v)
    return I + (1 - np.cos(t)) / t**2 * hat(v) + (t - np.sin(t)) / t**3 * hat(v) @ hat(v)


def left(f):
    """f read in left local coordinates about f at zero: log(f fᵀ(0))."""
    f0 = f(np.zeros(3))
    return lambda d: log_so3(f(d) @ f0.T)


def boxminus(a, b):
    return log_so3(a @ b.T)


samples = [
    {
        "P": rotation(rng),
        "P1": rotation(rng),
        "P2": rotation(rng),
        "r": rng.uniform(-3, 3, 3),
        "v": rotation_vector(rng),
        "v1": rng.uniform(-3, 3, 3),
        "v2": rng.uniform(-3, 3, 3),
        "w": rng.uniform(-3, 3, 3),
        "t": rng.uniform(0.1, 1.0),
    }
    for _ in range(20)
]
zero = np.zeros(3)
results = {}


claim = claimer(samples, results)


# The Derivatives table.
claim(
    "∂(Φ(r))/∂r",
    lambda s: s["P"],
    lambda s: jacobian(lambda r: s["P"] @ r, s["r"]),
)
claim(
    "∂(Φ(r))/∂Φ",
    lambda s: -hat(s["P"] @ s["r"]),
    lambda s: jacobian(lambda d: exp_so3(d) @ s["P"] @ s["r"], zero),
)
claim(
    "∂Φ⁻¹/∂Φ",
    lambda s: -s["P"].T,
    lambda s: jacobian(left(lambda d: (exp_so3(d) @ s["P"]).T), zero),
)
claim(
    "∂(Φ₁⊗Φ₂)/∂Φ₁",
    lambda s: I,
    lambda s: jacobian(left(lambda d: exp_so3(d) @ s["P1"] @ s["P2"]), zero),
)
claim(
    "∂(Φ₁⊗Φ₂)/∂Φ₂",
    lambda s: s["P1"],
    lambda s: jacobian(left(lambda d: s["P1"] @ exp_so3(d) @ s["P2"]), zero),
)
claim(
    "∂exp(v)/∂v",
    lambda s: gamma(s["v"]),
    lambda s: jacobian(lambda d: log_so3(exp_so3(s["v"] + d) @ exp_so3(s["v"]).T), zero),
)
claim(
    "∂log(Φ)/∂Φ",
    lambda s: np.linalg.inv(gamma(log_so3(s["P"]))),
    lambda s: jacobian(lambda d: log_so3(exp_so3(d) @ s["P"]), zero),
)
claim(
    "∂(Φ₁⊟Φ₂)/∂Φ₁",
    lambda s: np.linalg.inv(gamma(boxminus(s["P1"], s["P2"]))),
    lambda s: jacobian(lambda d: boxminus(exp_so3(d) @ s["P1"], s["P2"]), zero),
)
claim(
    "∂(Φ₁⊟Φ₂)/∂Φ₂",
    lambda s: np.linalg.inv(gamma(-boxminus(s["P1"], s["P2"]))),
    lambda s: jacobian(lambda d: boxminus(s["P1"], exp_so3(d) @ s["P2"]), zero),
    # The audit's diagnosis: the whole formula should have the opposite sign.
    correction=lambda s: -np.linalg.inv(gamma(-boxminus(s["P1"], s["P2"]))),
)
claim(
    "d(v̂₁v₂)/dv₁",
    lambda s: -hat(s["v2"]),
    lambda s: jacobian(lambda v1: hat(v1) @ s["v2"], s["v1"]),
)
claim(
    "d(v̂₁v₂)/dv₂",
    lambda s: hat(s["v1"]),
    lambda s: jacobian(lambda v2: hat(s["v1"]) @ v2, s["v2"]),
)

# The identities beside them (values: the left side is the truth).
claim(
    "Φ₁⊟Φ₂ = −(Φ₂⊟Φ₁)",
    lambda s: -boxminus(s["P2"], s["P1"]),
    lambda s: boxminus(s["P1"], s["P2"]),
)
claim(
    "C(Φ₁Φ₂) = C(Φ₁)C(Φ₂)",
    lambda s: s["P1"] @ s["P2"],
    lambda s: s["P1"] @ s["P2"],
)
claim("C(Φ)⁻¹ = C(Φ⁻¹)", lambda s: s["P"].T, lambda s: np.linalg.inv(s["P"]))
claim("Γ(v)v = v", lambda s: s["v"], lambda s: gamma(s["v"]) @ s["v"])
claim(
    "Γ⁻¹(v)v = v",
    lambda s: s["v"],
    lambda s: np.linalg.inv(gamma(s["v"])) @ s["v"],
)
claim("Γ(−v) = Γ(v)ᵀ", lambda s: gamma(s["v"]).T, lambda s: gamma(-s["v"]))
claim(
    "Γ⁻¹(−v) = Γ(v) + v̂",
    lambda s: add(gamma(s["v"]), hat(s["v"])),
    lambda s: np.linalg.inv(gamma(-s["v"])),
    # The audit's diagnosis: Γ(v) should be inverted.
    correction=lambda s: np.linalg.inv(gamma(s["v"])) + hat(s["v"]),
)
claim(
    "Γ⁻¹(v)C(v) = Γ⁻¹(v) + v̂",
    lambda s: add(np.linalg.inv(gamma(s["v"])), hat(s["v"])),
    lambda s: np.linalg.inv(gamma(s["v"])) @ exp_so3(s["v"]),
)


def near_zero(f):
    """f and its Jacobian at v = 0 (what agrees to first order)."""
    return lambda s: np.concatenate([np.ravel(f(zero), order="F"), np.ravel(jacobian(f, zero))])


def gamma_series_inverse(v):
    """Γ⁻¹(v) by its series I − v̂/2 + v̂²/12 − …, valid at 0."""
    h = hat(v)
    return I - h / 2 + h @ h / 12 - h @ h @ h @ h / 720


claim(
    "Γ⁻¹(v) ≈ I − v̂/2",
    near_zero(lambda v: I - hat(v) / 2),
    near_zero(gamma_series_inverse),
)
claim(
    "Γ(v), ‖v‖ ≠ 0",
    lambda s: add(
        I,
        mul(
            add(1.0, -mul(np.cos(np.linalg.norm(s["v"])), hat(s["v"]))),
            1 / np.linalg.norm(s["v"]) ** 2,
        ),
        mul(
            np.linalg.norm(s["v"]) - np.sin(np.linalg.norm(s["v"])),
            hat(s["v"]) @ hat(s["v"]),
            1 / np.linalg.norm(s["v"]) ** 3,
        ),
    ),
    lambda s: jacobian(lambda d: log_so3(exp_so3(s["v"] + d) @ exp_so3(s["v"]).T), zero),
    # The audit's diagnosis: (1 − cos(‖v‖)) v̂, a parenthesis misplaced.
    correction=lambda s: gamma(s["v"]),
)
claim(
    "Γ(v), otherwise",
    near_zero(lambda v: I + hat(v) / 2),
    near_zero(
        lambda v: jacobian(lambda d: log_so3(exp_so3(v + d) @ exp_so3(v).T), zero)
    ),
)

# The time derivative of Φ_BI(t) = (C_IB Exp(t ω))⁻¹.
claim(
    "∂Φ_BI(t)/∂t",
    lambda s: -s["w"],
    lambda s: jacobian(
        lambda dt: log_so3(
            (s["P"] @ exp_so3((s["t"] + dt[0]) * s["w"])).T
            @ (s["P"] @ exp_so3(s["t"] * s["w"]))
        ),
        np.zeros(1),
    ),
)


# Time derivatives of the rotation vector.
def rates(sign):
    def printed(s):
        p = s["v"]
        t = np.linalg.norm(p)
        return (
            I
            + sign * hat(p) * ((1 - np.cos(t)) / t**2)
            + hat(p) @ hat(p) * ((t - np.sin(t)) / t**3)
        )

    return printed


def rates_inverse(sign):
    def printed(s):
        p = log_so3(s["P"])
        t = np.linalg.norm(p)
        return (
            I
            + sign * 0.5 * hat(p)
            + hat(p) @ hat(p) * (1 / t**2) * (1 - t / 2 * np.sin(t) / (1 - np.cos(t)))
        )

    return printed


claim(
    "_I ω_IB = (…) φ̇",
    rates(+1),
    lambda s: jacobian(lambda d: log_so3(exp_so3(s["v"] + d) @ exp_so3(s["v"]).T), zero),
)
claim(
    "_B ω_IB = (…) φ̇",
    rates(-1),
    lambda s: jacobian(lambda d: log_so3(exp_so3(s["v"]).T @ exp_so3(s["v"] + d)), zero),
)
claim(
    "φ̇ = (…) _I ω_IB",
    rates_inverse(-1),
    lambda s: jacobian(lambda d: log_so3(exp_so3(d) @ s["P"]), zero),
)
claim(
    "φ̇ = (…) _B ω_IB",
    rates_inverse(+1),
    lambda s: jacobian(lambda d: log_so3(s["P"] @ exp_so3(d)), zero),
)

report(os.path.join(os.path.dirname(__file__), "cheatsheet_kindr1.symbols.toml"), results)
