"""Independent check of every formula claimed in the GTSAM ImuFactor.lyx
excerpt (ImuFactor.tex): numpy and scipy only.

    python3 documents/corpus/gtsam/check_ImuFactor.py            # the excerpt
    python3 documents/corpus/gtsam/check_ImuFactor.py --planted  # ImuFactor.planted.tex

The document's definitions: local coordinates Φ_{R₀}(θ) = R₀ exp([θ]×);
H(θ) the Jacobian of Eq. (push_exp), Φ(θ + δ) ≈ Φ(θ) exp([H(θ)δ]×) (the
right Jacobian of SO(3), here from that definition: independent.py); the
NavState retraction R_{X₀}(ζ) = {Φ_{R₀}(ωt), P₀ + R₀vt, V₀ + R₀at}; the
noise model θ_{k+1} = θ_k + H(θ_k)⁻¹(ω + ε^ω − b^ω − ε_init^ω)Δt,
p_{k+1} = p_k + v_kΔt + R_k(a + ε^a − b^a − ε_init^a)Δt²/2 + ε^int,
v_{k+1} = v_k + R_k(a + …)Δt with R_k = exp([θ_k]×), the state
ζ = [θ, p, v, b^a, b^ω]. A derivative "of a rotation" by θ is read in
right local coordinates, Log(R(θ₀)ᵀ R(θ)), as the document does.
`\\frac{\\Delta_t}{2}^{2}` is read as printed: the square of Δt/2.
"""

import os
import sys

import numpy as np
from scipy.special import factorial

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))
from independent import (  # noqa: E402
    claimer,
    add,
    block,
    exp_so3,
    hat,
    jacobian,
    log_so3,
    mul,
    planted_mode,
    report,
    report_planted,
    right_jacobian,
    rotation,
    vee,
)

HERE = os.path.dirname(__file__)
PLANTED = planted_mode()
rng = np.random.default_rng(15)
I3, Z3 = np.eye(3), np.zeros((3, 3))
z3 = np.zeros(3)

samples = []
for _ in range(20):
    samples.append({
        "R0": rotation(rng),
        "P0": rng.uniform(-2, 2, 3),
        "V0": rng.uniform(-2, 2, 3),
        "w": rng.uniform(-2, 2, 3),
        "v": rng.uniform(-2, 2, 3),
        "a": rng.uniform(-3, 3, 3),
        "theta": rng.normal(size=3) * rng.uniform(0.1, 1.0),
        "thetadot": rng.uniform(-1, 1, 3),
        "delta": rng.uniform(-1, 1, 3),
        "dt": rng.uniform(0.005, 0.2),
        "t": rng.uniform(0.1, 2.0),
    })

results = {}


claim = claimer(samples, results)


def Phi(R0, th):
    return R0 @ exp_so3(th)


def H_series(th, terms=40):
    """H(θ) = Σ_k (−1)^k/(k+1)! [θ]×^k, as printed (summed to convergence)."""
    S, term = np.zeros((3, 3)), np.eye(3)
    for k in range(terms):
        S = S + (-1) ** k / factorial(k + 1) * term
        term = term @ hat(th)
    return S


def d_matrix_dt(f, t0=0.0, h=1e-4):
    """d f(t)/dt of a matrix-valued f at t0 (Richardson-extrapolated)."""
    d = lambda step: (f(t0 + step) - f(t0 - step)) / (2 * step)  # noqa: E731
    return (4 * d(h / 2) - d(h)) / 3


def local(f, th0):
    """f (rotation-valued) in right local coordinates about f(th0)."""
    f0 = f(th0)
    return lambda th: log_so3(f0.T @ f(th))


# ---------------------------------------------------------------------------
# Local coordinates.
# ---------------------------------------------------------------------------

dPhi_dt = lambda s: d_matrix_dt(lambda t: Phi(s["R0"], s["w"] * t))  # noqa: E731
claim("dΦ(ωt)/dt|₀ = dR₀exp([ωt]×)/dt|₀",
      lambda s: d_matrix_dt(lambda t: s["R0"] @ exp_so3(s["w"] * t)), dPhi_dt)
claim("dΦ(ωt)/dt|₀ = R₀[ωt]×",
      # The bar sets t = 0: the printed R₀[ωt]× is then the zero matrix.
      lambda s: mul(s["R0"], hat(s["w"] * 0.0)), dPhi_dt,
      correction=lambda s: mul(s["R0"], hat(s["w"])))

# Eq. (push_exp): first order in δ at zero, then an identity.
claim(
    "Φ(θ+δ) ≈ Φ(θ) exp([H(θ)δ]×)",
    lambda s: jacobian(lambda d: Phi(s["R0"], s["theta"]) @ exp_so3(H_series(s["theta"]) @ d), z3),
    lambda s: jacobian(lambda d: Phi(s["R0"], s["theta"] + d), z3),
)
claim(
    "Φ(θ) exp([H(θ)δ]×) = Φ_{Φ(θ)}(H(θ)δ)",
    lambda s: Phi(Phi(s["R0"], s["theta"]), H_series(s["theta"]) @ s["delta"]),
    lambda s: Phi(s["R0"], s["theta"]) @ exp_so3(H_series(s["theta"]) @ s["delta"]),
)
claim("H(θ) = Σ (−1)^k/(k+1)! [θ]×^k", lambda s: H_series(s["theta"]),
      lambda s: right_jacobian(s["theta"]))

# Numerical integration in local coordinates: R(t) = Φ_{R₀}(θ(t)).
claim(
    "γ(δ) ≈ Φ_{R(t)}(H(θ)θ̇δ)",
    lambda s: jacobian(lambda d: Phi(Phi(s["R0"], s["theta"]), H_series(s["theta"]) @ s["thetadot"] * d[0]),
                       np.zeros(1)),
    lambda s: jacobian(lambda d: Phi(s["R0"], s["theta"] + s["thetadot"] * d[0]), np.zeros(1)),
)
Rdot = lambda s: d_matrix_dt(lambda d: Phi(s["R0"], s["theta"] + s["thetadot"] * d))  # noqa: E731
claim("Ṙ(t) = dγ(δ)/dδ|₀", Rdot, Rdot)
claim("Ṙ(t) = dΦ_{R(t)}(H(θ)θ̇δ)/dδ|₀",
      lambda s: d_matrix_dt(lambda d: Phi(Phi(s["R0"], s["theta"]), H_series(s["theta"]) @ s["thetadot"] * d)),
      Rdot)
claim("Ṙ(t) = R(t)[H(θ)θ̇]×",
      lambda s: mul(Phi(s["R0"], s["theta"]), hat(H_series(s["theta"]) @ s["thetadot"])), Rdot)
claim(
    "θ̇ = H(θ)⁻¹{R(t)ᵀF(R,t)}ˇ",
    lambda s: mul(np.linalg.inv(H_series(s["theta"])),
                  vee(Phi(s["R0"], s["theta"]).T @ Rdot(s)).reshape(3, 1)),
    lambda s: s["thetadot"],
)


# Retractions: their tangent vectors at t = 0, as tuples (stacked).
def retraction_T(s, t):
    return np.concatenate([Phi(s["R0"], s["w"] * t).ravel(), s["P0"] + s["R0"] @ s["v"] * t])


def retraction_X(s, t):
    return np.concatenate([retraction_T(s, t), s["V0"] + s["R0"] @ s["a"] * t])


claim("dR_{T₀}(ξ)/dt|₀ = [R₀[ω]×, R₀v]",
      lambda s: np.concatenate([(s["R0"] @ hat(s["w"])).ravel(), s["R0"] @ s["v"]]),
      lambda s: d_matrix_dt(lambda t: retraction_T(s, t)))
claim("dR_{X₀}(ζ)/dt|₀ = [R₀[ω]×, R₀v, R₀a]",
      lambda s: np.concatenate([(s["R0"] @ hat(s["w"])).ravel(), s["R0"] @ s["v"], s["R0"] @ s["a"]]),
      lambda s: d_matrix_dt(lambda t: retraction_X(s, t)))


# Integration in local coordinates: X(t) = R_{X₀}(ζ(t)), ζ = (θ, p, v) with
# rates (θ̇, ṗ, v̇); its tangent [R(t)[Hθ̇]×, R₀ṗ, R₀v̇].
def X_of(s, d):
    th = s["theta"] + s["thetadot"] * d
    p = s["v"] + s["w"] * d   # p(t) + ṗ δ (p(t) = v, ṗ = w: any values)
    v = s["a"] + s["delta"] * d
    return np.concatenate([Phi(s["R0"], th).ravel(), s["P0"] + s["R0"] @ p, s["V0"] + s["R0"] @ v])


Xdot = lambda s: d_matrix_dt(lambda d: X_of(s, d))  # noqa: E731
claim("Ẋ(t) = dγ(δ)/dδ|₀", Xdot, Xdot)
claim(
    "Ẋ(t) = [R(t)[H(θ)θ̇]×, R₀ṗ, R₀v̇]",
    lambda s: np.concatenate([(Phi(s["R0"], s["theta"]) @ hat(H_series(s["theta"]) @ s["thetadot"])).ravel(),
                              s["R0"] @ s["w"], s["R0"] @ s["delta"]]),
    Xdot,
)


# ---------------------------------------------------------------------------
# Noise propagation: f(ζ_k, a, ω) of the Euler scheme (no noise, no bias).
# ---------------------------------------------------------------------------

def theta_next(s, th, w=None):
    w = s["w"] if w is None else w
    return th + np.linalg.solve(H_series(th), w) * s["dt"]


def Hinv_w(s, th):
    return np.linalg.solve(H_series(th), s["w"])


claim(
    "∂θ_{k+1}/∂θ_k = I + ∂(H⁻¹ω)/∂θ Δt",
    lambda s: add(I3, mul(jacobian(lambda th: Hinv_w(s, th), s["theta"]), s["dt"])),
    lambda s: jacobian(lambda th: theta_next(s, th), s["theta"]),
)
# "For small θ_k": at θ_k = 0.
claim("∂(H(θ)⁻¹ω)/∂θ ≈ −½[ω]× (θ = 0)", lambda s: mul(-0.5, hat(s["w"])),
      lambda s: jacobian(lambda th: Hinv_w(s, th), z3))
claim("∂θ_{k+1}/∂θ_k = I − Δt/2[ω]× (θ = 0)", lambda s: add(I3, -mul(s["dt"] / 2, hat(s["w"]))),
      lambda s: jacobian(lambda th: theta_next(s, th), z3))

dRa = lambda s: jacobian(lambda th: exp_so3(th) @ s["a"], s["theta"])  # noqa: E731
claim(
    "∂(R_k a)/∂θ_k = R_k[−a]× ∂R_k/∂θ_k",
    lambda s: mul(exp_so3(s["theta"]), hat(-s["a"]),
                  jacobian(local(lambda th: exp_so3(th), s["theta"]), s["theta"])),
    dRa,
)
claim("∂(R_k a)/∂θ_k = R_k[−a]× H(θ_k)",
      lambda s: mul(exp_so3(s["theta"]), hat(-s["a"]), H_series(s["theta"])), dRa)
claim("∂(Ra)/∂R ≈ R[−a]×", lambda s: mul(s["R0"], hat(-s["a"])),
      lambda s: jacobian(lambda d: s["R0"] @ exp_so3(d) @ s["a"], z3))


# The Euler step with biases and the measurements as variables:
# x = [θ, p, v, b^a, b^ω], u = [a, ω].
def step(s, x, u):
    th, p, v, ba, bw = (x[i:i + 3] for i in range(0, 15, 3))
    a, w = u[0:3], u[3:6]
    Rk, dt = exp_so3(th), s["dt"]
    return np.concatenate([
        th + np.linalg.solve(H_series(th), w - bw) * dt,
        p + v * dt + Rk @ (a - ba) * dt**2 / 2,
        v + Rk @ (a - ba) * dt,
        ba, bw,
    ])


def u0(s):
    return np.concatenate([s["a"], s["w"]])


# A_k and F_k are "≈": their first block is the small-θ one, so they are
# claimed at θ_k = 0 (R_k = H = I); B_k, C_k hold at any θ_k.
def A_printed(s, sq):
    dt, w, a = s["dt"], s["w"], s["a"]
    Rk, H = I3, I3
    return block([
        [add(I3, -mul(dt / 2, hat(w))), Z3, Z3],
        [mul(Rk, hat(-a), H, sq(dt)), I3, I3 * dt],
        [mul(Rk, hat(-a), H, dt), Z3, I3],
    ])


def half_sq(dt):
    """\\frac{\\Delta_t}{2}^{2} as printed."""
    return (dt / 2) ** 2


def half_dt2(dt):
    return dt**2 / 2


def truth_A_at_zero(s):
    z = np.concatenate([z3, s["P0"], s["V0"]])
    return jacobian(lambda zz: step(s, np.concatenate([zz, z3, z3]), u0(s))[0:9], z)


claim("A_k ≈ […]", lambda s: A_printed(s, half_sq), truth_A_at_zero,
      correction=lambda s: A_printed(s, half_dt2))


def B_printed(s, sq):
    Rk = exp_so3(s["theta"])
    return block([[Z3], [mul(Rk, sq(s["dt"]))], [mul(Rk, s["dt"])]])


def C_printed(s):
    return block([[mul(np.linalg.inv(H_series(s["theta"])), s["dt"])], [Z3], [Z3]])


def truth_BC(s):
    x = np.concatenate([s["theta"], s["P0"], s["V0"], z3, z3])
    return jacobian(lambda u: step(s, x, u)[0:9], u0(s))


claim("B_k", lambda s: B_printed(s, half_sq), lambda s: truth_BC(s)[:, 0:3],
      correction=lambda s: B_printed(s, half_dt2))
claim("C_k", C_printed, lambda s: truth_BC(s)[:, 3:6])


def F_printed(s, sq, sign=1.0):
    dt = s["dt"]
    A = A_printed(s, sq)
    return block([
        [A[0:3, 0:3], Z3, Z3, Z3, mul(sign, I3, dt)],
        [A[3:6, 0:3], I3, I3 * dt, mul(sign, I3, sq(dt)), Z3],
        [A[6:9, 0:3], Z3, I3, mul(sign, I3, dt), Z3],
        [Z3, Z3, Z3, I3, Z3],
        [Z3, Z3, Z3, Z3, I3],
    ])


def truth_F_at_zero(s):
    return jacobian(lambda x: step(s, x, u0(s)), np.concatenate([z3, s["P0"], s["V0"], z3, z3]))


claim("F_k ≈ […]", lambda s: F_printed(s, half_sq), truth_F_at_zero,
      correction=lambda s: F_printed(s, half_dt2, sign=-1.0))


if PLANTED:
    # The planted copy's printed formulas (ImuFactor.planted.md says where).
    claim("∂θ_{k+1}/∂θ_k = I − Δt/2[ω]× (θ = 0)", lambda s: add(I3, -mul(s["dt"], hat(s["w"]))),
          lambda s: jacobian(lambda th: theta_next(s, th), z3))
    claim("∂(R_k a)/∂θ_k = R_k[−a]× H(θ_k)",
          lambda s: mul(exp_so3(s["theta"]), hat(-s["a"]), H_series(s["theta"]).T), dRa)
    claim("∂(Ra)/∂R ≈ R[−a]×", lambda s: mul(s["R0"], hat(s["a"])),
          lambda s: jacobian(lambda d: s["R0"] @ exp_so3(d) @ s["a"], z3))
    claim("C_k", lambda s: block([[Z3], [mul(np.linalg.inv(H_series(s["theta"])), s["dt"])], [Z3]]),
          lambda s: truth_BC(s)[:, 3:6])
    report_planted(os.path.join(HERE, "ImuFactor.planted.md"), results)
else:
    report(os.path.join(HERE, "ImuFactor.symbols.toml"), results)
