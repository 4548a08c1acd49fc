"""Independent checks of the corpus documents' formulas: numpy and scipy only,
nothing of slamjac.

Each formula is checked the same way: its map is written here from its
definition (rotations through scipy's `Rotation`, other groups through
scipy's matrix exponential and logarithm), differentiated by central
differences with Richardson extrapolation, and compared with the printed
formula transcribed in numpy *as printed* (a sum of a scalar and a matrix,
or a product whose sizes do not fit, raises `Malformed` instead of being
broadcast). The verdicts use the audit's vocabulary and tolerance:
`correct` (relative error at most 1e-6 at every sample), `convention`
(right under a stated alternative), `wrong`, `malformed`.

Each document's check script (`check.py`, `check_NAME.py`) lists its claims with the ids of its symbols
file, prints a table, and fails when a verdict differs from the one the
symbols file expects (which `slamjac audit` gates on): so the audit and this
check agree on every formula.
"""

import sys
import tomllib

import numpy as np
from scipy.linalg import expm, logm
from scipy.spatial.transform import Rotation

TOLERANCE = 1e-6


class Malformed(Exception):
    """The printed formula cannot be evaluated as printed."""


def hat(v):
    v = np.asarray(v, dtype=float).reshape(3)
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def vee(m):
    return np.array([m[2, 1], m[0, 2], m[1, 0]])


def exp_so3(v):
    return Rotation.from_rotvec(np.asarray(v, dtype=float).reshape(3)).as_matrix()


def log_so3(r):
    return Rotation.from_matrix(r).as_rotvec()


def twist(xi):
    """The 4 x 4 matrix of a twist [w, v] (rotation first)."""
    m = np.zeros((4, 4))
    m[:3, :3] = hat(xi[:3])
    m[:3, 3] = xi[3:6]
    return m


def exp_se3(xi):
    return expm(twist(np.asarray(xi, dtype=float)))


def log_se3(t):
    m = np.real(logm(t))
    return np.concatenate([vee(m[:3, :3]), m[:3, 3]])


def pose(r, t):
    m = np.eye(4)
    m[:3, :3] = r
    m[:3, 3] = t
    return m


def jacobian(f, x, h=1e-4):
    """d f / d x at x by central differences, Richardson-extrapolated
    (error O(h^4)); f maps a vector to an array (flattened column-major,
    as the audit flattens a matrix)."""
    x = np.asarray(x, dtype=float)

    def d(step):
        cols = []
        for i in range(x.size):
            e = np.zeros_like(x)
            e[i] = step
            cols.append(
                (np.ravel(f(x + e), order="F") - np.ravel(f(x - e), order="F"))
                / (2 * step)
            )
        return np.stack(cols, axis=1)

    return (4 * d(h / 2) - d(h)) / 3


def relative_error(a, b):
    a, b = np.atleast_2d(a), np.atleast_2d(b)
    if a.shape != b.shape:
        return np.inf
    return np.linalg.norm(a - b) / max(np.linalg.norm(b), 1e-9)


def add(*terms):
    """A sum as printed: every term of one shape (a 1 x 1 is a scalar)."""
    shapes = {np.shape(np.atleast_2d(t)) for t in terms}
    if len(shapes) != 1:
        raise Malformed(f"a sum of terms of shapes {sorted(shapes)}")
    return sum(np.atleast_2d(t) for t in terms)


def mul(*factors):
    """A product as printed: scalars scale, matrices must fit."""
    out = np.atleast_2d(1.0)
    for f in factors:
        f = np.atleast_2d(f)
        if out.shape == (1, 1) or f.shape == (1, 1):
            out = out * f
        elif out.shape[1] != f.shape[0]:
            raise Malformed(f"a {out.shape} matrix times a {f.shape} matrix")
        else:
            out = out @ f
    return out


def block(rows):
    """A block matrix as printed: the blocks of a row must have one height."""
    try:
        return np.block([[np.atleast_2d(b) for b in row] for row in rows])
    except ValueError as e:
        raise Malformed(str(e))


def col(*entries):
    """A column vector stacked from scalars and vectors."""
    return np.concatenate([np.atleast_1d(np.asarray(e, dtype=float)) for e in entries]).reshape(
        -1, 1
    )


def right_jacobian(phi):
    """J_r(φ) of SO(3) from its definition, Exp(φ + δ) ≈ Exp(φ) Exp(J_r(φ) δ):
    the derivative of Log(Exp(φ)ᵀ Exp(φ + δ)) at δ = 0 (never a closed form)."""
    phi = np.asarray(phi, dtype=float)
    return jacobian(lambda d: log_so3(exp_so3(phi).T @ exp_so3(phi + d)), np.zeros(3))


def rotation(rng):
    return Rotation.random(random_state=rng).as_matrix()


def rotation_vector(rng):
    axis = rng.normal(size=3)
    return axis / np.linalg.norm(axis) * rng.uniform(0.05, 3.0)


def judge(printed, truth, samples, alternatives=()):
    """The verdict on a formula: `printed(s)` and `truth(s)` at every sample
    `s`, with `alternatives` (name, truth) tried when it is not right."""
    worst = 0.0
    holding = {name for name, _ in alternatives}
    for s in samples:
        try:
            p = np.atleast_2d(printed(s))
        except Malformed as e:
            return "malformed", str(e)
        t = np.atleast_2d(truth(s))
        if p.shape != t.shape and p.T.shape == t.shape and 1 in t.shape:
            # A vector either way (numpy's 1-D arrays have no orientation).
            p = p.T
        worst = max(worst, relative_error(p, t))
        holding = {
            name
            for name, alt in alternatives
            if name in holding and relative_error(p, np.atleast_2d(alt(s))) <= TOLERANCE
        }
    if worst <= TOLERANCE:
        return "correct", f"{worst:.1e}"
    if holding:
        return "convention", sorted(holding)[0]
    return "wrong", f"{worst:.1e}"


def confirm(corrected, truth, samples):
    """Whether a corrected formula agrees with the truth at every sample."""
    return all(
        relative_error(np.atleast_2d(corrected(s)), np.atleast_2d(truth(s))) <= TOLERANCE
        for s in samples
    )


def claimer(samples, results):
    """The `claim(cid, printed, truth, alternatives=(), correction=None)` of
    a check script: the verdict on a formula at `samples` into `results`,
    with whether a `correction` (the corrected form) agrees with the truth."""

    def claim(cid, printed, truth, alternatives=(), correction=None):
        verdict, detail = judge(printed, truth, samples, alternatives)
        if correction is not None:
            detail += "; corrected form " + (
                "agrees" if confirm(correction, truth, samples) else "DOES NOT agree"
            )
        results[cid] = (verdict, detail)

    return claim


def planted_mode():
    """Whether the check runs on the planted copy (`--planted`)."""
    return "--planted" in sys.argv[1:]


def report_planted(planted_md, results):
    """On the planted copy: every claim listed in `<name>.planted.md` (its
    table's first column, in backquotes) must be found wrong or malformed,
    and it exits non-zero if one is not."""
    with open(planted_md, encoding="utf-8") as f:
        planted = [
            line.split("|")[1].strip().strip("`")
            for line in f
            if line.startswith("| `")
        ]
    failures = 0
    print(f"{'planted claim':<34} {'independent':<12} detail")
    for cid in planted:
        verdict, detail = results.get(cid, ("(no check)", ""))
        caught = verdict in ("wrong", "malformed")
        failures += not caught
        print(f"{cid:<34} {verdict:<12} {detail}{'' if caught else '  <-- NOT CAUGHT'}")
    print(f"{len(planted)} planted errors; {len(planted) - failures} found")
    sys.exit(1 if failures else 0)


def report(symbols_path, results):
    """Prints each claim's verdict beside the symbols file's expectation
    and exits non-zero if one differs (or a claim is missing)."""
    with open(symbols_path, "rb") as f:
        claims = tomllib.load(f)["claim"]
    expected = {c["id"]: c.get("expected", "correct") for c in claims}
    failures = 0
    print(f"{'claim':<34} {'independent':<12} {'audit expects':<14} detail")
    for cid, (verdict, detail) in results.items():
        want = expected.get(cid, "(not in the symbols file)")
        # A correct formula the audit does not read gives no verdict to
        # disagree with; an erratum it does not read is a miss.
        unread = want == "unread" and verdict == "correct"
        agrees = verdict == want or unread
        flag = "  (not read by the audit)" if unread else "" if agrees else "  <-- DISAGREES"
        failures += not agrees
        print(f"{cid:<34} {verdict:<12} {want:<14} {detail}{flag}")
    missing = [cid for cid, want in expected.items() if cid not in results and want != "unread"]
    for cid in missing:
        print(f"{cid:<34} (no independent check)")
    failures += len(missing)
    print(f"{len(results)} formulas checked; {failures} disagreement(s)")
    sys.exit(1 if failures else 0)
