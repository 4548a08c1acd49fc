"""Draws the speed-up of each SIMD candidate over the scalar f64 point kernel
from the criterion output of `cargo bench -p factor-lanes --bench candidates`.

    python3 factor-lanes/benches/plot_candidates.py OUT.png \
        DEFAULT_CRITERION_DIR NATIVE_CRITERION_DIR BASELINE [BASELINE ...]

The criterion directories are the `target/criterion` of a default build and
of a `RUSTFLAGS="-C target-cpu=native"` build (with its own target
directory); each benchmark's figure is its fastest sample over the named
baselines (`--save-baseline NAME`, or `new`). Needs matplotlib.
"""

import glob
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

CONFIGURATIONS = 4096
LANES = ["f64x4", "f32x8", "f64x8"]
CANDIDATES = [("wide", "wide"), ("portable", "portable arrays (chosen)"), ("pulp", "pulp, dispatched")]


def fastest(criterion_dir, baselines):
    """ns per factor of every benchmark: its fastest sample over `baselines`."""
    best = {}
    for baseline in baselines:
        pattern = os.path.join(criterion_dir, "point_reprojection", "*", baseline, "sample.json")
        for path in glob.glob(pattern):
            meta = os.path.join(os.path.dirname(os.path.dirname(path)), baseline, "benchmark.json")
            name = json.load(open(meta))["value_str"]
            sample = json.load(open(path))
            ns = min(t / i for t, i in zip(sample["times"], sample["iters"])) / CONFIGURATIONS
            best[name] = min(ns, best.get(name, float("inf")))
    if "scalar/f64" not in best:
        sys.exit(f"error: no scalar/f64 benchmark under {criterion_dir} for baselines {baselines}")
    return best


def speedup(best, candidate, lanes):
    """Speed-up over scalar f64 of the candidate's loop as the build compiles
    it, or of its runtime-dispatched loop when it has only that (pulp)."""
    name = f"{candidate}/{lanes}"
    times = [best[name]] if name in best else [ns for n, ns in best.items() if n.split("+")[0] == name]
    return best["scalar/f64"] / min(times) if times else 0.0


def main():
    if len(sys.argv) < 5:
        sys.exit(__doc__)
    out, default_dir, native_dir, baselines = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
    builds = [("default x86-64", fastest(default_dir, baselines), "//"), ("target-cpu=native", fastest(native_dir, baselines), "")]
    fig, ax = plt.subplots(figsize=(9, 4.5))
    width = 0.13
    colors = ["tab:blue", "tab:orange", "tab:green"]
    for b, (build, best, hatch) in enumerate(builds):
        for c, (candidate, label) in enumerate(CANDIDATES):
            xs = [i + (b * len(CANDIDATES) + c - 2.5) * width for i in range(len(LANES))]
            ys = [speedup(best, candidate, lanes) for lanes in LANES]
            bars = ax.bar(xs, ys, width, color=colors[c], hatch=hatch, edgecolor="black", label=f"{label}, {build}")
            ax.bar_label(bars, fmt="%.1f", fontsize=7)
    ax.axhline(1.0, color="black", linewidth=0.8)
    ax.set_xticks(range(len(LANES)), [f"{lanes}" for lanes in LANES])
    ax.set_ylabel("speed-up over the scalar f64 kernel")
    ax.set_title("Generated point-reprojection kernel: speed-up per factor over scalar f64")
    ax.set_ylim(0, 9.5)
    ax.legend(fontsize=7, ncol=2, loc="upper left")
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    main()
