"""Operation counts of SymForce (PyPI) generating the document factors into C++.

Four functions, each returning the residual and its Jacobian blocks in this
project's conventions (README, "Conventions"):

- `point_reprojection`: pose (left, `[dw, drho]`), point (additive);
- `line_reprojection`: pose (left), orthonormal line `(U, W)` with
  `U <- Exp(dT) U`, `W <- R(drho) W`, tangent `[dT, drho]` (4); `U` is a
  `Rot3` (quaternion storage), `W` a `Rot2` (storage `(cos, sin)`);
- `plucker_line_reprojection`: pose (left), line `[n, v]` (additive);
- `plane`: `log(q(T^T q(pi_c)) * q_w^-1)` (full-sphere quaternion log,
  `2 atan2(|v|, w) v / |v|`), pose (left), plane `q_w <- exp(dw) * q_w` (3),
  `q_w` a `Rot3` (its quaternion storage `[a, b, c, d]`).

Left perturbations are written the way SymForce's own
`jacobian_helpers.tangent_jacobians_first_order` perturbs a variable: the
first-order retraction `identity.storage + storage_D_tangent(identity) xi`
(for `Pose3`: rotation `[xi_w / 2, 1]`, translation `xi_rho`), composed on the
left, then `jacobian(xi)` at `xi = 0`. At `xi = 0` this is the derivative of
the exact `Exp(xi) T`. Additive variables are differentiated directly.

Each function goes through `Codegen.function(..., config=CppConfig())` and
`generate_function`; the op count is SymForce's own (`Codegen.total_ops()`,
the `// Total ops: N` line of the generated header), and is checked against
that line. For reference, the count SymForce gives the same residuals by
default, `Codegen.with_jacobians` on its own tangent spaces (Pose3: rotation
perturbed on the right, translation additively; not this project's
conventions), is recorded too as `native_with_jacobians_total_ops`.

If OUT_DIR/samples.json exists (written by the harness's `dump_samples`
binary from this project's `linearize_dual()`), each SymForce expression is
also evaluated at those configurations and compared with it, so the counts are
known to be of the same functions.

Usage: python symforce_counts.py OUT_DIR
Writes OUT_DIR/symforce_counts.json and the C++ under OUT_DIR/symforce_cpp/.
"""

import json
import re
import sys
import time
from pathlib import Path

_started = time.perf_counter()
import symforce  # noqa: E402

symforce.set_log_level("warning")
# No epsilon terms: the kernels are evaluated on validated, non-degenerate
# configurations (as this project's and wrenfold's are), so none is added
# (the C++ config below allows epsilon = 0 without SymForce's warning).
symforce.set_epsilon_to_zero()
import symforce.symbolic as sf  # noqa: E402
from symforce import codegen  # noqa: E402
from symforce.codegen.codegen_config import ZeroEpsilonBehavior  # noqa: E402
from symforce.ops import LieGroupOps, StorageOps  # noqa: E402
from symforce.type_helpers import symbolic_inputs  # noqa: E402

IMPORT_SECONDS = time.perf_counter() - _started
TOLERANCE = 1e-9
CPP = codegen.CppConfig(zero_epsilon_behavior=ZeroEpsilonBehavior.ALLOW)


def left_perturbation(cls, name: str):
    """`(D, xi)`: SymForce's first-order retraction of the identity of `cls`
    by a symbolic tangent `xi`, to be composed on the left of a variable."""
    identity = cls.identity()
    xi = sf.M(LieGroupOps.tangent_dim(identity), 1).symbolic(name)
    storage = sf.M(StorageOps.to_storage(identity)) + LieGroupOps.storage_D_tangent(identity) * xi
    return StorageOps.from_storage(identity, storage.to_storage()), xi


def jacobian_at_zero(expr: sf.Matrix, xi: sf.Matrix) -> sf.Matrix:
    return expr.jacobian(xi).subs(xi, xi.zero())


def project(k: sf.V4, p: sf.V3) -> sf.V2:
    fu, fv, cu, cv = k
    return sf.V2(fu * p[0] / p[2] + cu, fv * p[1] / p[2] + cv)


def endpoint_distances(k: sf.V4, n_c: sf.V3, start: sf.V2, end: sf.V2) -> sf.V2:
    """`[l.p, l.q] / sqrt(l1^2 + l2^2)`, `l = Kl n_c`."""
    fu, fv, cu, cv = k
    kl = sf.M33([[fv, 0, 0], [0, fu, 0], [-fv * cu, -fu * cv, fu * fv]])
    l = kl * n_c
    inv = 1 / sf.sqrt(l[0] ** 2 + l[1] ** 2)
    p = sf.V3(start[0], start[1], 1)
    q = sf.V3(end[0], end[1], 1)
    return sf.V2(l.dot(p) * inv, l.dot(q) * inv)


def plucker_normal(pose: sf.Pose3, n: sf.V3, v: sf.V3) -> sf.V3:
    """`n_c = R n + t x (R v)`."""
    return pose.R * n + pose.t.cross(pose.R * v)


def quaternion_log(q: sf.Quaternion) -> sf.V3:
    """`2 atan2(|v|, w) v / |v|` on the whole sphere (no folding to `w >= 0`)."""
    s = q.xyz.norm()
    return (2 * sf.atan2(s, q.w) / s) * q.xyz


def point_reprojection_residual(
    pose: sf.Pose3, point: sf.V3, intrinsics: sf.V4, observed: sf.V2
) -> sf.V2:
    return observed - project(intrinsics, pose * point)


def line_reprojection_residual(
    pose: sf.Pose3, u: sf.Rot3, w: sf.Rot2, intrinsics: sf.V4, start: sf.V2, end: sf.V2
) -> sf.V2:
    cos, sin = StorageOps.to_storage(w)
    m = u.to_rotation_matrix()
    n_c = plucker_normal(pose, cos * m[:, 0], sin * m[:, 1])
    return endpoint_distances(intrinsics, n_c, start, end)


def plucker_line_reprojection_residual(
    pose: sf.Pose3, line: sf.V6, intrinsics: sf.V4, start: sf.V2, end: sf.V2
) -> sf.V2:
    n_c = plucker_normal(pose, sf.V3(line[0:3]), sf.V3(line[3:6]))
    return endpoint_distances(intrinsics, n_c, start, end)


def plane_residual(pose: sf.Pose3, plane: sf.Rot3, measured: sf.V4) -> sf.V3:
    pi_c = measured / measured.norm()
    n = sf.V3(pi_c[0:3])
    y = sf.V4(*(pose.R.inverse() * n), pose.t.dot(n) + pi_c[3])
    phi = sf.Quaternion.from_storage((y / y.norm()).to_storage())
    return quaternion_log(phi * plane.q.conj())


def point_reprojection(pose: sf.Pose3, point: sf.V3, intrinsics: sf.V4, observed: sf.V2):
    d_pose, xi = left_perturbation(sf.Pose3, "xi")
    res = point_reprojection_residual(pose, point, intrinsics, observed)
    perturbed = point_reprojection_residual(d_pose * pose, point, intrinsics, observed)
    return res, jacobian_at_zero(perturbed, xi), res.jacobian(point)


def line_reprojection(
    pose: sf.Pose3, u: sf.Rot3, w: sf.Rot2, intrinsics: sf.V4, start: sf.V2, end: sf.V2
):
    d_pose, xi = left_perturbation(sf.Pose3, "xi")
    d_u, theta = left_perturbation(sf.Rot3, "theta")
    d_w, rho = left_perturbation(sf.Rot2, "rho")
    res = line_reprojection_residual(pose, u, w, intrinsics, start, end)
    by_pose = line_reprojection_residual(d_pose * pose, u, w, intrinsics, start, end)
    by_line = line_reprojection_residual(pose, d_u * u, d_w * w, intrinsics, start, end)
    return (
        res,
        jacobian_at_zero(by_pose, xi),
        jacobian_at_zero(by_line, sf.V4(*theta, *rho)),
    )


def plucker_line_reprojection(
    pose: sf.Pose3, line: sf.V6, intrinsics: sf.V4, start: sf.V2, end: sf.V2
):
    d_pose, xi = left_perturbation(sf.Pose3, "xi")
    res = plucker_line_reprojection_residual(pose, line, intrinsics, start, end)
    perturbed = plucker_line_reprojection_residual(d_pose * pose, line, intrinsics, start, end)
    return res, jacobian_at_zero(perturbed, xi), res.jacobian(line)


def plane(pose: sf.Pose3, plane: sf.Rot3, measured: sf.V4):
    d_pose, xi = left_perturbation(sf.Pose3, "xi")
    d_plane, omega = left_perturbation(sf.Rot3, "omega")
    return (
        plane_residual(pose, plane, measured),
        jacobian_at_zero(plane_residual(d_pose * pose, plane, measured), xi),
        jacobian_at_zero(plane_residual(pose, d_plane * plane, measured), omega),
    )


# The same residuals with `Codegen.with_jacobians`, i.e. w.r.t. SymForce's own
# tangent spaces (Pose3: product manifold SO(3) x R3 with the rotation
# perturbed on the RIGHT and the translation additively; Rot3, Rot2: right).
# Not this project's conventions: recorded because they are what a SymForce
# user gets by default, and to compare with the figures quoted in the README.
NATIVE = {
    "point_reprojection": (point_reprojection_residual, ["pose", "point"]),
    "line_reprojection": (line_reprojection_residual, ["pose", "u", "w"]),
    "plucker_line_reprojection": (plucker_line_reprojection_residual, ["pose", "line"]),
    "plane": (plane_residual, ["pose", "plane"]),
}

FUNCTIONS = {
    "point_reprojection": (point_reprojection, ["residual", "d_pose", "d_point"]),
    "line_reprojection": (line_reprojection, ["residual", "d_pose", "d_line"]),
    "plucker_line_reprojection": (plucker_line_reprojection, ["residual", "d_pose", "d_line"]),
    "plane": (plane, ["residual", "d_pose", "d_plane"]),
}


def numeric_storage(arg: str, inputs: dict) -> list[float]:
    """The storage of argument `arg` from a dumped configuration."""
    if arg == "pose":
        return inputs["rotation"] + inputs["translation"]  # Pose3: [qx, qy, qz, qw, t]
    return inputs[arg]  # Rot3 [x, y, z, w], Rot2 [cos, sin], vectors as they are


def check_against_samples(configs: list, func, output_names: list[str]) -> float:
    """Worst relative error of SymForce's outputs vs `linearize_dual()` over the
    dumped configurations (each block: max |a - b| / max |b|)."""
    inputs = symbolic_inputs(func)
    outputs = func(*inputs.values())
    worst = 0.0
    for config in configs:
        subs = {}
        for arg, value in inputs.items():
            storage = StorageOps.to_storage(value)
            subs.update(zip(storage, numeric_storage(arg, config["inputs"]), strict=True))
        for out_name, value in zip(output_names, outputs, strict=True):
            want = config["outputs"][out_name]
            m = sf.M(value)
            got = [
                [float(m[i, j].subs(subs)) for j in range(m.shape[1])] for i in range(m.shape[0])
            ]
            scale = max(abs(x) for row in want for x in row) or 1.0
            diff = max(abs(a - b) for ra, rb in zip(got, want) for a, b in zip(ra, rb))
            worst = max(worst, diff / scale)
    return worst


def main() -> None:
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).parent / "out"
    cpp_dir = out / "symforce_cpp"
    samples_path = out / "samples.json"
    samples = json.loads(samples_path.read_text()) if samples_path.exists() else {}
    counts: dict[str, object] = {
        "symforce_version": symforce.__version__,
        "import_seconds": round(IMPORT_SECONDS, 3),
        "perturbation": "first-order left retraction of the identity (SymForce's "
        "storage_D_tangent), composed on the left, jacobian at xi = 0",
    }
    for name, (func, output_names) in FUNCTIONS.items():
        started = time.perf_counter()
        cg = codegen.Codegen.function(func=func, config=CPP, name=name, output_names=output_names)
        paths = cg.generate_function(output_dir=cpp_dir, skip_directory_nesting=True)
        seconds = time.perf_counter() - started
        header = Path(paths.generated_files[0]).read_text()
        line = re.search(r"// Total ops: (\d+)", header)
        if line is None or int(line.group(1)) != cg.total_ops():
            raise RuntimeError(f"{name}: '// Total ops' line missing or not {cg.total_ops()}")
        entry: dict[str, object] = {
            "total_ops": cg.total_ops(),
            "generation_seconds": round(seconds, 3),
        }
        if name in samples:
            entry["configurations_checked"] = len(samples[name])
            worst = check_against_samples(samples[name], func, output_names)
            entry["worst_relative_error_vs_linearize_dual"] = worst
            if not worst <= TOLERANCE:
                raise RuntimeError(
                    f"{name}: SymForce's outputs differ from linearize_dual() by {worst:e} "
                    f"relative (tolerance {TOLERANCE:e}): not the same function"
                )
        native, which_args = NATIVE[name]
        native_cg = codegen.Codegen.function(
            func=native, config=CPP, name=f"{name}_native"
        ).with_jacobians(which_args=which_args, include_results=True)
        entry["native_with_jacobians_total_ops"] = native_cg.total_ops()
        counts[name] = entry
        print(f"symforce {name}: {entry}")
    (out / "symforce_counts.json").write_text(json.dumps(counts, indent=2) + "\n")
    print(f"wrote {out / 'symforce_counts.json'} (C++ in {cpp_dir})")


if __name__ == "__main__":
    main()
