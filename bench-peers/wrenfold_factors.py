"""Generate the peer kernels with wrenfold (PyPI) into Rust.

Two functions, written the way a wrenfold user would write them (after the
`gtsam_bal/pose3.py` and `ceres_simple_bundle_adjuster` examples of the
wrenfold repository): the pose is perturbed symbolically on the left with the
exact SE(3) exponential, `T <- Exp([dw, drho]) T`, i.e. `R <- Exp(dw) R`,
`t <- Exp(dw) t + Jl(dw) drho`, built from `Quaternion.from_rotation_vector`,
`to_rotation_matrix` and `left_jacobian_of_so3`; the residual is
differentiated with `sym.jacobian` w.r.t. the symbolic perturbation, which is
then substituted by zero. Additive variables are differentiated directly.

Conventions are this project's (README, "Conventions"): quaternion stored
`[x, y, z, w]`, Hamilton, active rotation; `X_c = R X_w + t`; pose tangent
`[dw, drho]`, rotation first; Jacobians row-major, rows = residual entries.

Only the two `BENCHMARKED` functions are written to Rust. Equivalent
formulations a user might write instead are generated too, for their
operation counts only (`variants` in the JSON): wrenfold's counts depend on how
the expression is written, and the README's quoted figures (150 / 556) are those
of the first-order perturbation with `n_c = R n + [t]x R v`.

Usage: python wrenfold_factors.py OUT_DIR
Writes OUT_DIR/wrenfold_generated.rs and OUT_DIR/wrenfold_counts.json and
prints wrenfold's own operation counts (the `// Operation counts:` block its
code generator writes into every function it emits; its `total` counts
negations as operations).
"""

import json
import re
import sys
import time
from pathlib import Path

import wrenfold as wf
from wrenfold import sym
from wrenfold.geometry import Quaternion, left_jacobian_of_so3

# --- small helpers ----------------------------------------------------------


def cross(a: sym.MatrixExpr, b: sym.MatrixExpr) -> sym.MatrixExpr:
    return sym.vector(
        a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]
    )


def hat(w: sym.MatrixExpr) -> sym.MatrixExpr:
    return sym.matrix([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])


def pose_perturbation() -> sym.MatrixExpr:
    return sym.vector(*sym.make_symbols("dw_x", "dw_y", "dw_z", "drho_x", "drho_y", "drho_z"))


def at_zero(expr: sym.MatrixExpr, delta: sym.MatrixExpr) -> sym.MatrixExpr:
    return expr.subs([(d, 0) for d in delta])


# --- left pose perturbations: (q, t, delta) -> (R', t') ---------------------


def exp_left(q_xyzw: sym.MatrixExpr, t: sym.MatrixExpr, delta: sym.MatrixExpr):
    """`Exp(delta) T` with the exact SE(3) exponential, composed as rotation
    matrices. `epsilon=0` inserts the small-angle branch that `delta = 0`
    selects (as wrenfold's `pose3.py` does)."""
    dw, drho = delta[0:3], delta[3:6]
    d_r = Quaternion.from_rotation_vector(dw, epsilon=0).to_rotation_matrix()
    r = Quaternion.from_xyzw(q_xyzw).to_rotation_matrix()
    return d_r * r, d_r * t + left_jacobian_of_so3(dw, epsilon=0) * drho


def exp_left_quaternion_product(q_xyzw: sym.MatrixExpr, t: sym.MatrixExpr, delta: sym.MatrixExpr):
    """The same, with the rotation composed as the quaternion product
    `exp(dw) * q` before conversion to a matrix (count-only variant)."""
    dw, drho = delta[0:3], delta[3:6]
    dq = Quaternion.from_rotation_vector(dw, epsilon=0)
    r = (dq * Quaternion.from_xyzw(q_xyzw)).to_rotation_matrix()
    return r, dq.to_rotation_matrix() * t + left_jacobian_of_so3(dw, epsilon=0) * drho


def first_order_left(q_xyzw: sym.MatrixExpr, t: sym.MatrixExpr, delta: sym.MatrixExpr):
    """First-order `(I + [dw]x) T + [0, drho]` (count-only variant): the same
    derivative at `delta = 0`."""
    e = sym.eye(3) + hat(delta[0:3])
    return e * Quaternion.from_xyzw(q_xyzw).to_rotation_matrix(), e * t + delta[3:6]


# --- the factors --------------------------------------------------------------


def make_point_reprojection(perturb):
    def point_reprojection(
        rotation: wf.Vector4,
        translation: wf.Vector3,
        point: wf.Vector3,
        intrinsics: wf.Vector4,
        observed: wf.Vector2,
    ):
        """`observed - [fu X/Z + cu, fv Y/Z + cv]`, `[X, Y, Z] = R p + t`.

        Outputs: residual (2), 2x6 block w.r.t. the left pose perturbation
        `[dw, drho]`, 2x3 block w.r.t. the point (additive).
        """
        fu, fv, cu, cv = intrinsics

        def residual(r: sym.MatrixExpr, t: sym.MatrixExpr, p: sym.MatrixExpr):
            x, y, z = r * p + t
            return observed - sym.vector(fu * x / z + cu, fv * y / z + cv)

        delta = pose_perturbation()
        r_delta, t_delta = perturb(rotation, translation, delta)
        r = Quaternion.from_xyzw(rotation).to_rotation_matrix()
        res = residual(r, translation, point)
        d_pose = at_zero(sym.jacobian(residual(r_delta, t_delta, point), delta), delta)
        d_point = sym.jacobian(res, point)
        return (
            wf.OutputArg(res, "residual"),
            wf.OutputArg(d_pose, "d_pose"),
            wf.OutputArg(d_point, "d_point"),
        )

    return point_reprojection


def make_plucker_line_reprojection(perturb, moment_by_hat: bool = False):
    def plucker_line_reprojection(
        rotation: wf.Vector4,
        translation: wf.Vector3,
        line: wf.Vector6,
        intrinsics: wf.Vector4,
        start: wf.Vector2,
        end: wf.Vector2,
    ):
        """`[l.p, l.q] / sqrt(l1^2 + l2^2)`, `l = Kl n_c`, `n_c = R n + t x (R v)`,
        `Kl = [[fv, 0, 0], [0, fu, 0], [-fv cu, -fu cv, fu fv]]`,
        `p = [start, 1]`, `q = [end, 1]`.

        Outputs: residual (2), 2x6 block w.r.t. the left pose perturbation
        `[dw, drho]`, 2x6 block w.r.t. the line `[n, v]` (additive).
        """
        fu, fv, cu, cv = intrinsics
        kl = sym.matrix([[fv, 0, 0], [0, fu, 0], [-fv * cu, -fu * cv, fu * fv]])
        p = sym.vector(start[0], start[1], 1)
        q = sym.vector(end[0], end[1], 1)

        def residual(r: sym.MatrixExpr, t: sym.MatrixExpr, nv: sym.MatrixExpr):
            n, v = nv[0:3], nv[3:6]
            moment = hat(t) * r * v if moment_by_hat else cross(t, r * v)
            l = kl * (r * n + moment)
            inv = 1 / sym.sqrt(l[0] ** 2 + l[1] ** 2)
            return sym.vector((l.T * p)[0] * inv, (l.T * q)[0] * inv)

        delta = pose_perturbation()
        r_delta, t_delta = perturb(rotation, translation, delta)
        r = Quaternion.from_xyzw(rotation).to_rotation_matrix()
        res = residual(r, translation, line)
        d_pose = at_zero(sym.jacobian(residual(r_delta, t_delta, line), delta), delta)
        d_line = sym.jacobian(res, line)
        return (
            wf.OutputArg(res, "residual"),
            wf.OutputArg(d_pose, "d_pose"),
            wf.OutputArg(d_line, "d_line"),
        )

    return plucker_line_reprojection


# Written to Rust and benchmarked.
BENCHMARKED = {
    "point_reprojection": make_point_reprojection(exp_left),
    "plucker_line_reprojection": make_plucker_line_reprojection(exp_left),
}

# Generated for their operation counts only.
VARIANTS = {
    "point_reprojection": {
        "exact_exp_quaternion_product": make_point_reprojection(exp_left_quaternion_product),
        "first_order": make_point_reprojection(first_order_left),
    },
    "plucker_line_reprojection": {
        "exact_exp_quaternion_product": make_plucker_line_reprojection(exp_left_quaternion_product),
        "first_order": make_plucker_line_reprojection(first_order_left),
        "first_order_moment_by_hat_matrix": make_plucker_line_reprojection(
            first_order_left, moment_by_hat=True
        ),
        "exact_exp_moment_by_hat_matrix": make_plucker_line_reprojection(
            exp_left, moment_by_hat=True
        ),
    },
}


def operation_counts(code: str) -> dict[str, int]:
    """wrenfold's own counts, read from the `// Operation counts:` block its
    generators write at the top of every emitted function body."""
    block = re.search(r"// Operation counts:\n((?:\s*// \w+: \d+\n)+)", code)
    if block is None:
        raise RuntimeError("no '// Operation counts:' block in wrenfold's output")
    return {k: int(v) for k, v in re.findall(r"// (\w+): (\d+)", block.group(1))}


def main() -> None:
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).parent / "out"
    out.mkdir(parents=True, exist_ok=True)
    generator = wf.RustGenerator()
    pieces = []
    counts: dict[str, object] = {
        "wrenfold_version": wf.__version__,
        "formulation": "exact SE(3) exponential on the left, rotations composed as matrices "
        "(from_rotation_vector, to_rotation_matrix, left_jacobian_of_so3), "
        "jacobian then substitute delta = 0",
    }
    for name, func in BENCHMARKED.items():
        started = time.perf_counter()
        code = wf.generate_function(func=func, generator=generator, name=name)
        seconds = time.perf_counter() - started
        pieces.append(code)
        entry: dict[str, object] = dict(operation_counts(code))
        entry["generation_seconds"] = round(seconds, 4)
        entry["variants"] = {
            label: operation_counts(wf.generate_function(func=f, generator=generator, name=name))
            for label, f in VARIANTS[name].items()
        }
        counts[name] = entry
        variants = ", ".join(f"{k} {v['total']}" for k, v in entry["variants"].items())
        print(f"wrenfold {name}: total {entry['total']} {operation_counts(code)}")
        print(f"    variants (not benchmarked): {variants}")
    # `generator.apply_preamble` would add an inner doc comment and an inner
    # attribute, which `include!` does not accept; the functions are as emitted.
    header = (
        f"// Generated by bench-peers/wrenfold_factors.py with wrenfold {wf.__version__}\n"
        "// (RustGenerator, default optimization parameters). Peer code for\n"
        "// benchmarking only, `include!`d by bench-peers/harness: never committed.\n\n"
    )
    (out / "wrenfold_generated.rs").write_text(header + "\n\n".join(pieces) + "\n")
    (out / "wrenfold_counts.json").write_text(json.dumps(counts, indent=2) + "\n")
    print(f"wrote {out / 'wrenfold_generated.rs'} and {out / 'wrenfold_counts.json'}")


if __name__ == "__main__":
    main()
