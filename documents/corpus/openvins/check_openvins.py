"""Independent check of every formula claimed in the OpenVINS excerpt
(openvins.tex): numpy and scipy only.

    python3 documents/corpus/openvins/check_openvins.py            # the excerpt
    python3 documents/corpus/openvins/check_openvins.py --planted  # openvins.planted.tex

Conventions, from their definitions (Trawny & Roumeliotis, the JPL
quaternion report the document cites):
- a JPL quaternion is q̄ = [q_v; q_4] (vector first), its rotation matrix
  C(q̄) = (2q_4² − 1) I − 2 q_4 ⌊q_v×⌋ + 2 q_v q_vᵀ, the product
  q̄ ⊗ p̄ = L(q̄) p̄ with L(q̄) = [q_4 I − ⌊q_v×⌋, q_v; −q_vᵀ, q_4], so that
  C(q̄ ⊗ p̄) = C(q̄) C(p̄) (checked below);
- a rotation state is perturbed by the left multiplicative error the
  document defines, ^I_G q̄ = δq̄ ⊗ ^I_G q̂ with δq̄ = [k̂ sin(θ̃/2); cos(θ̃/2)]
  built from the error angle vector θ̃ = θ̃ k̂; every "derivative by a
  rotation" is the derivative by θ̃ at zero (the document's own note below
  the projection Jacobians);
- positions, velocities, biases and noises are additive;
- J_r is the right Jacobian of SO(3) from its definition (independent.py).

Each printed formula is transcribed as printed, blocks and all; a chain rule
written with partial derivatives uses the partials the document prints
below it. The truth is the derivative, by Richardson-extrapolated central
differences, of the map written from the document's definitions.
"""

import os
import sys

import numpy as np
from scipy.linalg import expm

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))
from independent import (  # noqa: E402
    claimer,
    add,
    block,
    col,
    exp_so3,
    hat,
    jacobian,
    log_so3,
    mul,
    planted_mode,
    report,
    report_planted,
    right_jacobian,
)

HERE = os.path.dirname(__file__)
PLANTED = planted_mode()
rng = np.random.default_rng(26)
I2, I3, I4 = np.eye(2), np.eye(3), np.eye(4)
Z3 = np.zeros((3, 3))
z3 = np.zeros(3)


# ---------------------------------------------------------------------------
# JPL quaternions, from their definitions.
# ---------------------------------------------------------------------------


def jpl_C(q):
    qv, q4 = q[:3], q[3]
    return (2 * q4**2 - 1) * I3 - 2 * q4 * hat(qv) + 2 * np.outer(qv, qv)


def jpl_L(q):
    qv, q4 = q[:3], q[3]
    return block([[q4 * I3 - hat(qv), col(qv)], [-qv.reshape(1, 3), q4]])


def jpl_dq(theta):
    """δq̄ = [k̂ sin(θ̃/2); cos(θ̃/2)] for θ̃ = θ̃ k̂ (sin(x/2)/x by np.sinc
    so that θ̃ = 0 is no special case)."""
    angle = np.linalg.norm(theta)
    return np.concatenate([theta * 0.5 * np.sinc(angle / (2 * np.pi)), [np.cos(angle / 2)]])


def perturbed(q, theta):
    """The rotation matrix of δq̄(θ̃) ⊗ q̂."""
    return jpl_C(jpl_L(jpl_dq(theta)) @ q)


def jpl_error(r, r_hat):
    """θ̃ with C(δq̄(θ̃)) r_hat = r: C(δq̄(θ̃)) = Exp(−θ̃) (checked below)."""
    return -log_so3(r @ r_hat.T)


def unit_quaternion(r):
    q = r.normal(size=4)
    return q / np.linalg.norm(q)


def Omega(w):
    return block([[-hat(w), col(w)], [-w.reshape(1, 3), 0.0]])


# The conventions hold together: C(q⊗p) = C(q)C(p), C(δq̄(θ)) = Exp(−θ), and
# the quaternion kinematics q̇ = ½Ω(ω)q integrate to C = Exp(−ω t) C₀.
for _ in range(5):
    q, p, th, w = unit_quaternion(rng), unit_quaternion(rng), rng.normal(size=3), rng.normal(size=3)
    assert np.allclose(jpl_C(jpl_L(q) @ p), jpl_C(q) @ jpl_C(p))
    assert np.allclose(jpl_C(jpl_dq(th)), exp_so3(-th))
    assert np.allclose(jpl_C(expm(0.5 * Omega(w) * 0.7) @ q), exp_so3(-w * 0.7) @ jpl_C(q))


# ---------------------------------------------------------------------------
# Samples.
# ---------------------------------------------------------------------------

samples = []
for _ in range(20):
    s = {
        "q_IG": unit_quaternion(rng),
        "q_CI": unit_quaternion(rng),
        "q_a": unit_quaternion(rng),
        "p_I": rng.uniform(-2, 2, 3),
        "p_a": rng.uniform(-2, 2, 3),
        "p_CI": rng.uniform(-0.3, 0.3, 3),
        "lam_xyz": np.array([0.0, 0.0, 0.0]),
        "theta": rng.uniform(-np.pi, np.pi),
        "phi": rng.uniform(0.2, 2.9),
        "rho": rng.uniform(0.2, 2.0),
        "alpha": rng.uniform(-0.5, 0.5),
        "beta": rng.uniform(-0.5, 0.5),
        "zn": rng.uniform(-0.6, 0.6, 2),
        "zeta_rt": np.concatenate([rng.uniform(300, 600, 2), rng.uniform(200, 400, 2),
                                   rng.uniform(-0.3, 0.3, 2), rng.uniform(-0.01, 0.01, 2)]),
        "zeta_eq": np.concatenate([rng.uniform(300, 600, 2), rng.uniform(200, 400, 2),
                                   rng.uniform(-0.05, 0.05, 4)]),
        # IMU propagation: estimates, measurements, gravity, time step.
        "q_k": unit_quaternion(rng),
        "p_k": rng.uniform(-2, 2, 3),
        "v_k": rng.uniform(-2, 2, 3),
        "bg": rng.uniform(-0.1, 0.1, 3),
        "ba": rng.uniform(-0.2, 0.2, 3),
        "wm": rng.uniform(-2, 2, 3),
        "am": rng.uniform(-3, 3, 3) + np.array([0, 0, 9.81]),
        "g": np.array([0.0, 0.0, 9.81]),
        "dt": rng.uniform(0.005, 0.3),
        "w4": rng.uniform(-3, 3, 3),
        "k_theta": rng.normal(size=3),
    }
    s["R_IG"], s["R_CI"], s["R_a"] = jpl_C(s["q_IG"]), jpl_C(s["q_CI"]), jpl_C(s["q_a"])
    s["R_k"] = jpl_C(s["q_k"])
    # A feature in front of the current camera and of the anchor camera.
    s["p_f"] = s["p_I"] + s["R_IG"].T @ (s["R_CI"].T @ (np.array([0.2, -0.1, 3.0]) - s["p_CI"]))
    s["lam_xyz"] = rng.uniform(-0.5, 0.5, 3) + np.array([0, 0, 3.0])
    samples.append(s)

results = {}


claim = claimer(samples, results)


def rotation_jacobian(f, q):
    """∂f/∂(rotation q̂): by the JPL error angle at zero."""
    return jacobian(lambda th: f(perturbed(q, th)), z3)


# ---------------------------------------------------------------------------
# update-feat: the camera measurement chain.
# ---------------------------------------------------------------------------


def h_d_radtan(zn, zeta):
    fx, fy, cx, cy, k1, k2, p1, p2 = zeta
    xn, yn = zn
    r2 = xn**2 + yn**2
    x = xn * (1 + k1 * r2 + k2 * r2**2) + 2 * p1 * xn * yn + p2 * (r2 + 2 * xn**2)
    y = yn * (1 + k1 * r2 + k2 * r2**2) + p1 * (r2 + 2 * yn**2) + 2 * p2 * xn * yn
    return np.array([fx * x + cx, fy * y + cy])


def fisheye_parts(zn, k):
    xn, yn = zn
    r = np.hypot(xn, yn)
    th = np.arctan(r)
    thd = th * (1 + k[0] * th**2 + k[1] * th**4 + k[2] * th**6 + k[3] * th**8)
    return r, th, thd


def h_d_fisheye(zn, zeta):
    fx, fy, cx, cy = zeta[:4]
    r, _, thd = fisheye_parts(zn, zeta[4:])
    return np.array([fx * zn[0] / r * thd + cx, fy * zn[1] / r * thd + cy])


def h_p(p):
    return np.array([p[0] / p[2], p[1] / p[2]])


def cam_point(s, p_f, R_IG=None, p_I=None, R_CI=None, p_CI=None):
    """^{C_k}p_f = ^C_I R ^{I_k}_G R (^G p_f − ^G p_{I_k}) + ^C p_I."""
    R_IG = s["R_IG"] if R_IG is None else R_IG
    p_I = s["p_I"] if p_I is None else p_I
    R_CI = s["R_CI"] if R_CI is None else R_CI
    p_CI = s["p_CI"] if p_CI is None else p_CI
    return R_CI @ R_IG @ (p_f - p_I) + p_CI


def anchored(s, cpf, R_a=None, p_a=None, R_CI=None, p_CI=None):
    """^G p_f = ^{I_a}_G Rᵀ ^C_I Rᵀ (^{C_a}p_f − ^C p_I) + ^G p_{I_a}."""
    R_a = s["R_a"] if R_a is None else R_a
    p_a = s["p_a"] if p_a is None else p_a
    R_CI = s["R_CI"] if R_CI is None else R_CI
    p_CI = s["p_CI"] if p_CI is None else p_CI
    return R_a.T @ R_CI.T @ (cpf - p_CI) + p_a


def sph(lam):
    th, ph, rho = lam
    return np.array([np.cos(th) * np.sin(ph), np.sin(th) * np.sin(ph), np.cos(ph)]) / rho


def msckf(lam):
    a, b, rho = lam
    return np.array([a, b, 1.0]) / rho


def Dhd_radtan_printed(s, zn):
    fx, fy, cx, cy, k1, k2, p1, p2 = s["zeta_rt"]
    xn, yn = zn
    r2 = xn**2 + yn**2
    return np.array([
        [fx * ((1 + k1 * r2 + k2 * r2**2) + (2 * k1 * xn**2 + 4 * k2 * xn**2 * (xn**2 + yn**2))
               + 2 * p1 * yn + (2 * p2 * xn + 4 * p2 * xn)),
         fx * (2 * k1 * xn * yn + 4 * k2 * xn * yn * (xn**2 + yn**2) + 2 * p1 * xn + 2 * p2 * yn)],
        [fy * (2 * k1 * xn * yn + 4 * k2 * xn * yn * (xn**2 + yn**2) + 2 * p1 * xn + 2 * p2 * yn),
         fy * ((1 + k1 * r2 + k2 * r2**2) + (2 * k1 * yn**2 + 4 * k2 * yn**2 * (xn**2 + yn**2))
               + (2 * p1 * yn + 4 * p1 * yn) + 2 * p2 * xn)],
    ])


def Dhp_printed(p):
    x, y, z = p
    return np.array([[1 / z, 0, -x / z**2], [0, 1 / z, -y / z**2]])


# The chain rule ∂z/∂x: the measurement at the current pose of a feature in
# the anchored XYZ representation, anchored at another pose, and x the two
# positions [^G p_{I_k}; ^G p_{I_a}]: h_t depends on the first, h_r on the
# second, so both terms of the sum are non-zero.
def z_of_x(s, x):
    p_f = anchored(s, s["lam_xyz"], p_a=x[3:6])
    return h_d_radtan(h_p(cam_point(s, p_f, p_I=x[0:3])), s["zeta_rt"])


def chain_printed(s):
    x = np.concatenate([s["p_I"], s["p_a"]])
    p_f = anchored(s, s["lam_xyz"])
    cp = cam_point(s, p_f)
    Dhd = Dhd_radtan_printed(s, h_p(cp))
    Dhp = Dhp_printed(cp)
    Dht_x = jacobian(lambda xx: cam_point(s, p_f, p_I=xx[0:3]), x)  # p_f held
    Dht_pf = jacobian(lambda pf: cam_point(s, pf), p_f)
    Dhr_x = jacobian(lambda xx: anchored(s, s["lam_xyz"], p_a=xx[3:6]), x)  # λ held
    return add(mul(Dhd, Dhp, Dht_x), mul(Dhd, Dhp, Dht_pf, Dhr_x))


claim("∂z/∂x (chain rule)", chain_printed,
      lambda s: jacobian(lambda x: z_of_x(s, x), np.concatenate([s["p_I"], s["p_a"]])))

# Radial-tangential distortion.
def radtan_dzeta_printed(s):
    fx, fy = s["zeta_rt"][:2]
    xn, yn = s["zn"]
    r2 = xn**2 + yn**2
    x, y = (h_d_radtan(s["zn"], s["zeta_rt"]) - s["zeta_rt"][2:4]) / s["zeta_rt"][:2]
    return np.array([
        [x, 0, 1, 0, fx * (xn * r2), fx * (xn * r2**2), fx * (2 * xn * yn), fx * (r2 + 2 * xn**2)],
        [0, y, 0, 1, fy * (yn * r2), fy * (yn * r2**2), fy * (r2 + 2 * yn**2), fy * (2 * xn * yn)],
    ])


claim(
    "radtan ∂h_d/∂ζ",
    radtan_dzeta_printed,
    lambda s: jacobian(lambda z: h_d_radtan(s["zn"], z), s["zeta_rt"]),
)
claim(
    "radtan ∂h_d/∂z_n",
    lambda s: Dhd_radtan_printed(s, s["zn"]),
    lambda s: jacobian(lambda z: h_d_radtan(z, s["zeta_rt"]), s["zn"]),
)


# Fisheye distortion. ζ = [f_x f_y c_x c_y k_1 k_2 k_3 k_4].
def fisheye_dzeta(s, first_x, first_y):
    fx, fy = s["zeta_eq"][:2]
    xn, yn = s["zn"]
    r, th, _ = fisheye_parts(s["zn"], s["zeta_eq"][4:])
    return np.array([
        [first_x, 0, 1, 0] + [fx * (xn / r * th**n) for n in (3, 5, 7, 9)],
        [0, first_y, 0, 1] + [fy * (yn / r * th**n) for n in (3, 5, 7, 9)],
    ])


def fisheye_xy(s):
    r, _, thd = fisheye_parts(s["zn"], s["zeta_eq"][4:])
    return s["zn"] / r * thd


claim(
    "fisheye ∂h_d/∂ζ",
    lambda s: fisheye_dzeta(s, *s["zn"]),
    lambda s: jacobian(lambda z: h_d_fisheye(s["zn"], z), s["zeta_eq"]),
    correction=lambda s: fisheye_dzeta(s, *fisheye_xy(s)),
)


# The fisheye chain: partials as printed, each holding the other arguments
# of x = x_n θ_d / r, y = y_n θ_d / r (r, θ_d, θ as the document names them).
def fisheye_partials(s):
    fx, fy = s["zeta_eq"][:2]
    k1, k2, k3, k4 = s["zeta_eq"][4:]
    xn, yn = s["zn"]
    r, th, thd = fisheye_parts(s["zn"], s["zeta_eq"][4:])
    return {
        "duv_dxy": np.array([[fx, 0], [0, fy]]),
        "dxy_dxnyn": np.array([[thd / r, 0], [0, thd / r]]),
        "dxy_dr": np.array([[-xn / r**2 * thd], [-yn / r**2 * thd]]),
        "dr_dxnyn": np.array([[xn / r, yn / r]]),
        "dxy_dthd": np.array([[xn / r], [yn / r]]),
        "dthd_dth": np.array([[1 + 3 * k1 * th**2 + 5 * k2 * th**4 + 7 * k3 * th**6 + 9 * k4 * th**8]]),
        "dth_dr": np.array([[1 / (r**2 + 1)]]),
    }


def fisheye_chain_printed(s):
    d = fisheye_partials(s)
    return add(
        mul(d["duv_dxy"], d["dxy_dxnyn"]),
        mul(d["duv_dxy"], d["dxy_dr"], d["dr_dxnyn"]),
        mul(d["duv_dxy"], d["dxy_dthd"], d["dthd_dth"], d["dth_dr"], d["dr_dxnyn"]),
    )


claim(
    "fisheye ∂h_d/∂z_n (chain)",
    fisheye_chain_printed,
    lambda s: jacobian(lambda z: h_d_fisheye(z, s["zeta_eq"]), s["zn"]),
)


def xy_of(xn, yn, r, thd):
    return np.array([xn / r * thd, yn / r * thd])


def fisheye_truths(s):
    k = s["zeta_eq"][4:]
    xn, yn = s["zn"]
    r, th, thd = fisheye_parts(s["zn"], k)
    fx, fy = s["zeta_eq"][:2]
    return {
        "duv_dxy": jacobian(lambda xy: np.array([fx * xy[0], fy * xy[1]]), fisheye_xy(s)),
        "dxy_dxnyn": jacobian(lambda z: xy_of(z[0], z[1], r, thd), s["zn"]),
        "dxy_dr": jacobian(lambda rr: xy_of(xn, yn, rr[0], thd), np.array([r])),
        "dr_dxnyn": jacobian(lambda z: np.array([np.hypot(*z)]), s["zn"]),
        "dxy_dthd": jacobian(lambda t: xy_of(xn, yn, r, t[0]), np.array([thd])),
        "dthd_dth": jacobian(
            lambda t: t * (1 + k[0] * t**2 + k[1] * t**4 + k[2] * t**6 + k[3] * t**8), np.array([th])
        ),
        "dth_dr": jacobian(lambda rr: np.arctan(rr), np.array([r])),
    }


for key, cid in [
    ("duv_dxy", "fisheye ∂uv/∂xy"),
    ("dxy_dxnyn", "fisheye ∂xy/∂x_ny_n"),
    ("dxy_dr", "fisheye ∂xy/∂r"),
    ("dr_dxnyn", "fisheye ∂r/∂x_ny_n"),
    ("dxy_dthd", "fisheye ∂xy/∂θ_d"),
    ("dthd_dth", "fisheye ∂θ_d/∂θ"),
    ("dth_dr", "fisheye ∂θ/∂r"),
]:
    claim(cid, lambda s, k=key: fisheye_partials(s)[k], lambda s, k=key: fisheye_truths(s)[k])

claim(
    "∂h_p/∂^{C_k}p_f",
    lambda s: Dhp_printed(cam_point(s, s["p_f"])),
    lambda s: jacobian(h_p, cam_point(s, s["p_f"])),
)

# The Euclidean transformation: camera pose from the IMU pose and extrinsics
# (T_GC = T_GI T_IC), and the substitution.
p_IC = lambda s: -s["R_CI"].T @ s["p_CI"]  # noqa: E731  ^I p_C
def pose_matrix(R, t):
    return block([[R, col(t)], [np.zeros((1, 3)), 1.0]])


# ^I p_{C_k} = ^I p_C and ^{C_k}_I R = ^C_I R (time-invariant extrinsics): the
# two sides of each chain print the same numbers.
for cid in ["^G p_{C_k} = ^G p_{I_k} + ^G_I R ^I p_{C_k}", "^G p_{C_k} = ^G p_{I_k} + ^G_I R ^I p_C"]:
    claim(
        cid,
        lambda s: s["p_I"] + s["R_IG"].T @ p_IC(s),
        lambda s: (pose_matrix(s["R_IG"].T, s["p_I"]) @ pose_matrix(s["R_CI"].T, p_IC(s)))[:3, 3],
    )
for cid in ["^{C_k}_G R = ^{C_k}_I R ^{I_k}_G R", "^{C_k}_G R = ^C_I R ^{I_k}_G R"]:
    claim(
        cid,
        lambda s: s["R_CI"] @ s["R_IG"],
        lambda s: np.linalg.inv(s["R_IG"].T @ s["R_CI"].T),
    )
claim(
    "^{C_k}p_f substituted",
    lambda s: cam_point(s, s["p_f"]),
    lambda s: (s["R_CI"] @ s["R_IG"]) @ (s["p_f"] - (s["p_I"] + s["R_IG"].T @ p_IC(s))),
)

# h_t Jacobians.
claim("∂h_t/∂^G p_f", lambda s: s["R_CI"] @ s["R_IG"],
      lambda s: jacobian(lambda pf: cam_point(s, pf), s["p_f"]))
claim(
    "∂h_t/∂^{I_k}_G R",
    lambda s: mul(s["R_CI"], hat(s["R_IG"] @ (s["p_f"] - s["p_I"]))),
    lambda s: rotation_jacobian(lambda R: cam_point(s, s["p_f"], R_IG=R), s["q_IG"]),
)
claim("∂h_t/∂^G p_{I_k}", lambda s: -s["R_CI"] @ s["R_IG"],
      lambda s: jacobian(lambda p: cam_point(s, s["p_f"], p_I=p), s["p_I"]))
claim(
    "∂h_t/∂^C_I R",
    lambda s: hat(s["R_CI"] @ s["R_IG"] @ (s["p_f"] - s["p_I"])),
    lambda s: rotation_jacobian(lambda R: cam_point(s, s["p_f"], R_CI=R), s["q_CI"]),
)
claim("∂h_t/∂^C p_I", lambda s: I3,
      lambda s: jacobian(lambda p: cam_point(s, s["p_f"], p_CI=p), s["p_CI"]))

# Feature representations.
claim("global xyz ∂f/∂λ", lambda s: I3, lambda s: jacobian(lambda lam: lam, s["lam_xyz"]))


def lam_sph(s):
    return np.array([s["theta"], s["phi"], s["rho"]])


def dsph_printed(s):
    th, ph, rho = lam_sph(s)
    c, sn = np.cos, np.sin
    return np.array([
        [-1 / rho * sn(th) * sn(ph), 1 / rho * c(th) * c(ph), -1 / rho**2 * c(th) * sn(ph)],
        [1 / rho * c(th) * sn(ph), 1 / rho * sn(th) * c(ph), -1 / rho**2 * sn(th) * sn(ph)],
        [0, -1 / rho * sn(ph), -1 / rho**2 * c(ph)],
    ])


claim("global inverse depth ∂f/∂λ", dsph_printed, lambda s: jacobian(sph, lam_sph(s)))


def lam_msckf(s):
    return np.array([s["alpha"], s["beta"], s["rho"]])


def dmsckf_printed(s):
    a, b, rho = lam_msckf(s)
    return np.array([[1 / rho, 0, -1 / rho**2 * a], [0, 1 / rho, -1 / rho**2 * b], [0, 0, -1 / rho**2]])


# The three anchored representations: λ ↦ ^{C_a}p_f, and ∂(^{C_a}p_f)/∂λ as printed.
REPRESENTATIONS = {
    "anchored xyz": (lambda s: s["lam_xyz"], lambda lam: lam, lambda s: I3),
    "anchored inverse depth": (lam_sph, sph, dsph_printed),
    "anchored msckf": (lam_msckf, msckf, dmsckf_printed),
}
for name, (lam, cpf_of, dcpf) in REPRESENTATIONS.items():
    def cpf(s, lam=lam, cpf_of=cpf_of):
        return cpf_of(lam(s))

    claim(
        f"{name} ∂f/∂λ",
        lambda s, dcpf=dcpf: mul(s["R_a"].T, s["R_CI"].T, dcpf(s)),
        lambda s, lam=lam, cpf_of=cpf_of: jacobian(lambda x: anchored(s, cpf_of(x)), lam(s)),
    )
    claim(
        f"{name} ∂f/∂^{{I_a}}_G R",
        lambda s, cpf=cpf: mul(-s["R_a"].T, hat(s["R_CI"].T @ (cpf(s) - s["p_CI"]))),
        lambda s, cpf=cpf: rotation_jacobian(lambda R: anchored(s, cpf(s), R_a=R), s["q_a"]),
    )
    claim(
        f"{name} ∂f/∂^G p_{{I_a}}",
        lambda s: I3,
        lambda s, cpf=cpf: jacobian(lambda p: anchored(s, cpf(s), p_a=p), s["p_a"]),
    )
    claim(
        f"{name} ∂f/∂^C_I R",
        lambda s, cpf=cpf: mul(-s["R_a"].T, s["R_CI"].T, hat(cpf(s) - s["p_CI"])),
        lambda s, cpf=cpf: rotation_jacobian(lambda R: anchored(s, cpf(s), R_CI=R), s["q_CI"]),
    )
    claim(
        f"{name} ∂f/∂^C p_I",
        lambda s: mul(-s["R_a"].T, s["R_CI"].T),
        lambda s, cpf=cpf: jacobian(lambda p: anchored(s, cpf(s), p_CI=p), s["p_CI"]),
    )


# ---------------------------------------------------------------------------
# update-zerovelocity: the printed residual z̃ = [−(a_m − b_a − R g − n_a);
# −(ω_m − b_g − n_g)] (the synthetic measurement a = ω = 0). The printed
# Jacobians are 3 × 3 blocks: the accelerometer rows for R and b_a, the
# gyroscope rows for b_g. Their signs are those of the EKF's H = ∂h/∂x of
# the measurement function h = a_m − b_a − R g (= −z̃): an alternative.
# ---------------------------------------------------------------------------


def ztilde(s, R=None, ba=None, bg=None):
    R = s["R_IG"] if R is None else R
    ba = s["ba"] if ba is None else ba
    bg = s["bg"] if bg is None else bg
    return np.concatenate([-(s["am"] - ba - R @ s["g"]), -(s["wm"] - bg)])


def zv_claim(cid, printed, d, rows):
    claim(cid, printed, lambda s: d(s)[rows], alternatives=[
        ("the Jacobian of h = −z̃ (the EKF's H)", lambda s: -d(s)[rows]),
    ])


zv_claim(
    "zero velocity ∂z̃/∂^{I_k}_G R",
    lambda s: -hat(s["R_IG"] @ s["g"]),
    lambda s: rotation_jacobian(lambda R: ztilde(s, R=R), s["q_IG"]),
    slice(0, 3),
)
zv_claim("zero velocity ∂z̃/∂b_a", lambda s: -I3,
         lambda s: jacobian(lambda b: ztilde(s, ba=b), s["ba"]), slice(0, 3))
zv_claim("zero velocity ∂z̃/∂b_g", lambda s: -I3,
         lambda s: jacobian(lambda b: ztilde(s, bg=b), s["bg"]), slice(3, 6))


# ---------------------------------------------------------------------------
# propagation and propagation-discrete.
# ---------------------------------------------------------------------------

# δq̄ = [k̂ sin(θ̃/2); cos(θ̃/2)] ≃ [θ̃/2; 1]: first order in θ̃ at zero.
claim(
    "δq̄ ≃ [½θ̃; 1]",
    lambda s: jacobian(lambda th: np.concatenate([0.5 * th, [1.0]]), z3),
    lambda s: jacobian(jpl_dq, z3),
)

# Θ(t_{k+1}, t_k) = exp(½Ω(ω)Δt): `exp` is the general matrix exponential.
claim(
    "Θ = cos(|ω|Δt/2) I₄ + sin(|ω|Δt/2)/|ω| Ω",
    lambda s: (lambda w, dt: add(
        mul(np.cos(np.linalg.norm(w) / 2 * dt), I4),
        mul(1 / np.linalg.norm(w), np.sin(np.linalg.norm(w) / 2 * dt), Omega(w)),
    ))(s["w4"], s["dt"]),
    lambda s: expm(0.5 * Omega(s["w4"]) * s["dt"]),
)
claim(
    "Θ ≃ I₄ + Δt/2 Ω (small |ω|)",
    lambda s: jacobian(lambda w: add(I4, mul(s["dt"] / 2, Omega(w))), z3),
    lambda s: jacobian(lambda w: expm(0.5 * Omega(w) * s["dt"]), z3),
)
claim(
    "^I_G R ≈ (I₃ − ⌊θ̃×⌋) ^I_G R̂",
    lambda s: jacobian(lambda th: mul(add(I3, -hat(th)), s["R_k"]), z3),
    lambda s: jacobian(lambda th: perturbed(s["q_k"], th), z3),
)


# The discrete IMU model (the document's): ω = ω_m − b_g − n_g,
# a = a_m − b_a − n_a, R_{k+1} = Exp(−ωΔt) R_k,
# p_{k+1} = p + vΔt − ½gΔt² + ½R_kᵀ a Δt², v_{k+1} = v − gΔt + R_kᵀ a Δt.
# The error state x̃ = [θ̃ p̃ ṽ b̃_g b̃_a], the noise n = [n_g n_a n_wg n_wa].
def truth_state(s, xt, n):
    R = perturbed(s["q_k"], xt[0:3])
    p, v = s["p_k"] + xt[3:6], s["v_k"] + xt[6:9]
    bg, ba = s["bg"] + xt[9:12], s["ba"] + xt[12:15]
    w, a, dt, g = s["wm"] - bg - n[0:3], s["am"] - ba - n[3:6], s["dt"], s["g"]
    return (exp_so3(-w * dt) @ R, p + v * dt - 0.5 * g * dt**2 + 0.5 * R.T @ a * dt**2,
            v - g * dt + R.T @ a * dt, bg + n[6:9], ba + n[9:12])


def error_next(s, xt, n):
    R1, p1, v1, bg1, ba1 = truth_state(s, xt, n)
    Rh, ph, vh, bgh, bah = truth_state(s, np.zeros(15), np.zeros(12))
    return np.concatenate([jpl_error(R1, Rh), p1 - ph, v1 - vh, bg1 - bgh, ba1 - bah])


def hats(s):
    dt = s["dt"]
    w_hat, a_hat = s["wm"] - s["bg"], s["am"] - s["ba"]
    th_hat = -w_hat * dt
    return dt, exp_so3(th_hat), th_hat, a_hat, s["R_k"]


# Orientation: the true R_{k+1} as a function of e = [θ̃_k; ω̃]
# (ω̃ = ω − ω̂), and the three printed right sides, first order in e.
def R_next_of(s, e):
    dt, _, th_hat, _, _ = hats(s)
    return exp_so3(th_hat - e[3:6] * dt) @ perturbed(s["q_k"], e[0:3])


def orientation_sides(s, e):
    dt, R_hat_kk, th_hat, _, R_k = hats(s)
    Jr = right_jacobian(th_hat)
    th, wt = e[0:3], e[3:6]
    return [
        mul(exp_so3(th_hat - wt * dt), add(I3, -hat(th)), R_k),
        mul(exp_so3(th_hat), exp_so3(-mul(Jr, col(wt)).ravel() * dt), add(I3, -hat(th)), R_k),
        mul(R_hat_kk, add(I3, -hat(mul(Jr, col(wt)).ravel() * dt)), add(I3, -hat(th)), R_k),
    ]


e0 = np.zeros(6)
for i, cid in enumerate(["orientation ≈ (line 2)", "orientation = (line 3)", "orientation = (line 4)"]):
    claim(
        cid,
        lambda s, i=i: jacobian(lambda e: orientation_sides(s, e)[i], e0),
        lambda s: jacobian(lambda e: R_next_of(s, e), e0),
    )


# θ̃_{k+1} ≈ R̂ θ̃_k − R̂ J_r(θ̂) Δt (b̃_g + n_g): first order in [θ̃_k; b̃_g; n_g].
def theta_next_truth(s, u):
    xt, n = np.zeros(15), np.zeros(12)
    xt[0:3], xt[9:12], n[0:3] = u[0:3], u[3:6], u[6:9]
    return error_next(s, xt, n)[0:3]


def theta_next_printed(s, u):
    dt, R_hat_kk, th_hat, _, _ = hats(s)
    return add(mul(R_hat_kk, col(u[0:3])),
               -mul(R_hat_kk, right_jacobian(th_hat), dt, col(u[3:6] + u[6:9])))


claim(
    "θ̃_{k+1} ≈ …",
    lambda s: jacobian(lambda u: theta_next_printed(s, u), np.zeros(9)),
    lambda s: jacobian(lambda u: theta_next_truth(s, u), np.zeros(9)),
)


# Position and velocity: first order in u = [θ̃_k; p̃_k; ṽ_k; ã] with
# ã = a − â, i.e. the true acceleration â + ã.
def pv_truth(s, u):
    dt, _, _, a_hat, _ = hats(s)
    R = perturbed(s["q_k"], u[0:3])
    p, v, a, g = s["p_k"] + u[3:6], s["v_k"] + u[6:9], a_hat + u[9:12], s["g"]
    return p + v * dt - 0.5 * g * dt**2 + 0.5 * R.T @ a * dt**2, v - g * dt + R.T @ a * dt


def pv_printed(s, u):
    dt, _, _, a_hat, R_k = hats(s)
    g = s["g"]
    th, pt, vt, at = (col(u[i:i + 3]) for i in (0, 3, 6, 9))
    ph, vh = col(s["p_k"]), col(s["v_k"])
    p1 = add(ph, pt, mul(vh, dt), mul(vt, dt), -mul(0.5, col(g), dt**2),
             mul(0.5, R_k.T, add(I3, hat(th)), add(col(a_hat), at), dt**2))
    v1 = add(vh, vt, -mul(col(g), dt), mul(R_k.T, add(I3, hat(th)), add(col(a_hat), at), dt))
    return p1, v1


u0 = np.zeros(12)
claim("position ≈ (two lines)", lambda s: jacobian(lambda u: pv_printed(s, u)[0], u0),
      lambda s: jacobian(lambda u: pv_truth(s, u)[0], u0))
claim("velocity ≈", lambda s: jacobian(lambda u: pv_printed(s, u)[1], u0),
      lambda s: jacobian(lambda u: pv_truth(s, u)[1], u0))


# p̃_{k+1}, ṽ_{k+1}: first order in w = [θ̃_k; p̃_k; ṽ_k; b̃_a; n_a].
def pv_error_truth(s, w):
    xt, n = np.zeros(15), np.zeros(12)
    xt[0:9], xt[12:15], n[3:6] = w[0:9], w[9:12], w[12:15]
    return error_next(s, xt, n)[3:9]


def pv_error_printed(s, w):
    dt, _, _, a_hat, R_k = hats(s)
    th, pt, vt, ba, na = (col(w[i:i + 3]) for i in (0, 3, 6, 9, 12))
    p1 = add(pt, mul(vt, dt), -mul(0.5, R_k.T, hat(a_hat * dt**2), th),
             -mul(0.5, R_k.T, dt**2, add(ba, na)))
    v1 = add(vt, -mul(R_k.T, hat(a_hat * dt), th), -mul(R_k.T, dt, add(ba, na)))
    return np.concatenate([p1.ravel(), v1.ravel()])


w0 = np.zeros(15)
claim("p̃_{k+1} = …", lambda s: jacobian(lambda w: pv_error_printed(s, w)[0:3], w0),
      lambda s: jacobian(lambda w: pv_error_truth(s, w)[0:3], w0))
claim("ṽ_{k+1} = …", lambda s: jacobian(lambda w: pv_error_printed(s, w)[3:6], w0),
      lambda s: jacobian(lambda w: pv_error_truth(s, w)[3:6], w0))


def Phi_printed(s):
    dt, R_hat_kk, th_hat, a_hat, R_k = hats(s)
    Jr = right_jacobian(th_hat)
    return block([
        [R_hat_kk, Z3, Z3, -mul(R_hat_kk, Jr, dt), Z3],
        [-mul(0.5, R_k.T, hat(a_hat * dt**2)), I3, dt * I3, Z3, -mul(0.5, R_k.T, dt**2)],
        [-mul(R_k.T, hat(a_hat * dt)), Z3, I3, Z3, -mul(R_k.T, dt)],
        [Z3, Z3, Z3, I3, Z3],
        [Z3, Z3, Z3, Z3, I3],
    ])


def G_printed(s):
    dt, R_hat_kk, th_hat, _, R_k = hats(s)
    return block([
        [-mul(R_hat_kk, right_jacobian(th_hat), dt), Z3, Z3, Z3],
        [Z3, -mul(0.5, R_k.T, dt**2), Z3, Z3],
        [Z3, -mul(R_k.T, dt), Z3, Z3],
        [Z3, Z3, I3, Z3],
        [Z3, Z3, Z3, I3],
    ])


claim("Φ(t_{k+1}, t_k)", Phi_printed,
      lambda s: jacobian(lambda xt: error_next(s, xt, np.zeros(12)), np.zeros(15)))
claim("G_k", G_printed,
      lambda s: jacobian(lambda n: error_next(s, np.zeros(15), n), np.zeros(12)))


if PLANTED:
    # The planted copy's printed formulas (openvins.planted.md says where).
    claim(
        "∂h_t/∂^{I_k}_G R",
        lambda s: mul(-s["R_CI"], hat(s["R_IG"] @ (s["p_f"] - s["p_I"]))),
        lambda s: rotation_jacobian(lambda R: cam_point(s, s["p_f"], R_IG=R), s["q_IG"]),
    )
    claim(
        "anchored msckf ∂f/∂λ",
        lambda s: mul(s["R_a"], s["R_CI"].T, dmsckf_printed(s)),
        lambda s: jacobian(lambda x: anchored(s, msckf(x)), lam_msckf(s)),
    )

    def radtan_planted(s):
        J = radtan_dzeta_printed(s)
        J[0, 6] /= 2  # f_x*(x_ny_n): the factor 2 lost
        return J

    def Phi_planted(s):
        P = Phi_printed(s)
        P[0:3, 9:15] = P[0:3, [12, 13, 14, 9, 10, 11]]  # blocks (1,4) and (1,5) swapped
        return P

    claim("radtan ∂h_d/∂ζ", radtan_planted,
          lambda s: jacobian(lambda z: h_d_radtan(s["zn"], z), s["zeta_rt"]))
    claim("Φ(t_{k+1}, t_k)", Phi_planted,
          lambda s: jacobian(lambda xt: error_next(s, xt, np.zeros(12)), np.zeros(15)))
    claim(
        "∂h_p/∂^{C_k}p_f",
        lambda s: Dhp_printed(cam_point(s, s["p_f"]))[::-1],  # the two rows swapped
        lambda s: jacobian(h_p, cam_point(s, s["p_f"])),
    )
    report_planted(os.path.join(HERE, "openvins.planted.md"), results)
else:
    report(os.path.join(HERE, "openvins.symbols.toml"), results)
