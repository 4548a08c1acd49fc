"""Summarise a `run.sh` run: criterion times, ratios and operation counts.

Reads OUT_DIR/target/criterion/<factor>/<method>/new/estimates.json (the
slope estimate, or the mean when criterion took no slope),
OUT_DIR/wrenfold_counts.json, OUT_DIR/symforce_counts.json and the operation
counts this project's generator writes into the header of each
generated/src/<factor>.rs (the "| all | ... | total |" row of its
"Operation counts" table: every block requested); prints a table and writes
OUT_DIR/summary.json. Standard library only.

Each generator's count is its own: wrenfold's `// Operation counts:` block
(add, multiply, divide, negate, call; negations count), SymForce's
`// Total ops:` line, and ours (add, mul, div, neg, sqrt, func, branch;
negations count, loading inputs and literals does not).

Usage: python3 summarize.py OUT_DIR
"""

import json
import re
import sys
from pathlib import Path

GENERATED_SRC = Path(__file__).resolve().parent.parent / "generated" / "src"
BENCHMARKED = ("point_reprojection", "plucker_line_reprojection")
# Every factor with a count from at least one generator, in the table's order.
COUNTED = (
    "point_reprojection",
    "plucker_line_reprojection",
    "line_reprojection",
    "plane",
    "free_line",
)


def load(path: Path) -> dict:
    return json.loads(path.read_text()) if path.exists() else {}


def nanoseconds(estimates: dict) -> float:
    key = "slope" if estimates.get("slope") else "mean"
    return estimates[key]["point_estimate"]


def generated_counts(source: Path) -> dict[str, int] | None:
    """The "all" row of the module header's operation-count table, by kind
    (the header row names the columns), or None without one."""
    if not source.exists():
        return None
    columns = None
    for line in source.read_text().splitlines():
        if not line.startswith("//! |"):
            continue
        cells = [c.strip() for c in line.removeprefix("//!").strip().strip("|").split("|")]
        if cells[0] == "outputs" and "total" in cells:
            columns = cells[1:]
        elif columns is not None and cells[0] == "all":
            return {kind: int(n) for kind, n in zip(columns, cells[1:], strict=True)}
    return None


def ratio(a: float | None, b: float | None) -> float | None:
    return a / b if a is not None and b else None


def fmt(x: float | int | None, width: int, spec: str = "d") -> str:
    return f"{'-':>{width}}" if x is None else format(x, f"{width}{spec}")


def main() -> None:
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).parent / "out"
    criterion = out / "target" / "criterion"
    wrenfold = load(out / "wrenfold_counts.json")
    symforce = load(out / "symforce_counts.json")
    summary: dict[str, object] = {
        "wrenfold_version": wrenfold.get("wrenfold_version"),
        "symforce_version": symforce.get("symforce_version"),
        "symforce_skipped": symforce.get("skipped"),
        "generated_sources": str(GENERATED_SRC),
        "factors": {},
    }
    factors: dict[str, dict] = summary["factors"]  # type: ignore[assignment]

    print("\n== time per call (criterion, 64 configurations in turn) ==")
    for factor in BENCHMARKED:
        times = {}
        for method_dir in sorted((criterion / factor).glob("*/new/estimates.json")):
            method = method_dir.parent.parent.name
            times[method] = nanoseconds(load(method_dir))
        entry: dict[str, object] = {"ns_per_call": times}
        if "dual" in times:
            entry["time_vs_dual"] = {m: t / times["dual"] for m, t in times.items()}
        if "wrenfold" in times:
            entry["time_vs_wrenfold"] = {m: t / times["wrenfold"] for m, t in times.items()}
        factors[factor] = entry
        for method, t in times.items():
            vs_dual = f"  {t / times['dual']:6.3f}x dual" if "dual" in times else ""
            vs_wrenfold = f"  {t / times['wrenfold']:6.3f}x wrenfold" if "wrenfold" in times else ""
            print(f"  {factor:28} {method:10} {t:10.1f} ns{vs_dual}{vs_wrenfold}")

    print("\n== batch API, ns per factor (criterion, the configurations repeated; 1 thread) ==")
    for factor in BENCHMARKED:
        batch = {}
        for method_dir in sorted((criterion / f"{factor}_batch").glob("*/new/estimates.json")):
            method = method_dir.parent.parent.name
            elements = load(method_dir.parent / "benchmark.json")["throughput"]["Elements"]
            batch[method] = nanoseconds(load(method_dir)) / elements
        if not batch:
            continue
        calls = factors[factor]["ns_per_call"]
        factors[factor]["batch_ns_per_factor"] = batch
        for method, t in batch.items():
            speedups = "".join(
                f"  {calls[m] / t:6.2f}x {m} throughput" for m in ("generated", "wrenfold") if m in calls
            )
            print(f"  {factor:28} {'batch ' + method:12} {t:8.2f} ns{speedups}")

    for factor in COUNTED:
        entry = factors.setdefault(factor, {})
        ours = generated_counts(GENERATED_SRC / f"{factor}.rs")
        if ours is not None:
            entry["generated_ops"] = ours["total"]
            entry["generated_ops_by_kind"] = ours
        if isinstance(wrenfold.get(factor), dict):
            entry["wrenfold_ops"] = wrenfold[factor]["total"]
            entry["wrenfold_ops_by_kind"] = {
                k: v for k, v in wrenfold[factor].items() if isinstance(v, int)
            }
        if isinstance(symforce.get(factor), dict) and "total_ops" in symforce[factor]:
            entry["symforce_ops"] = symforce[factor]["total_ops"]
        if "generated_ops" in entry and "wrenfold_ops" in entry:
            entry["ops_generated_vs_wrenfold"] = entry["generated_ops"] / entry["wrenfold_ops"]
        if not entry:
            del factors[factor]

    print("\n== operation counts (each generator's own; all blocks) ==")
    wv = wrenfold.get("wrenfold_version") or "-"
    sv = symforce.get("symforce_version") or "-"
    print(f"  {'factor':28} {'ours':>6} {'wrenfold ' + wv:>15} {'symforce ' + sv:>16}  ours/wrenfold")
    for factor, entry in factors.items():
        if not any(k.endswith("_ops") for k in entry):
            continue
        print(
            f"  {factor:28} {fmt(entry.get('generated_ops'), 6)} "
            f"{fmt(entry.get('wrenfold_ops'), 15)} {fmt(entry.get('symforce_ops'), 16)}"
            f"  {fmt(entry.get('ops_generated_vs_wrenfold'), 13, '.3f')}"
        )
    if symforce.get("skipped"):
        print(f"  symforce: skipped ({symforce['skipped']})")
    for factor, entry in symforce.items():
        if isinstance(entry, dict) and "native_with_jacobians_total_ops" in entry:
            print(
                f"  (symforce {factor}: with_jacobians on SymForce's own tangents: "
                f"{entry['native_with_jacobians_total_ops']})"
            )
    by_kind = [
        f"  ours {factor}: "
        + ", ".join(f"{k} {n}" for k, n in entry["generated_ops_by_kind"].items() if n)
        for factor, entry in factors.items()
        if "generated_ops_by_kind" in entry
    ]
    print("\n".join(by_kind))

    (out / "summary.json").write_text(json.dumps(summary, indent=2) + "\n")
    print(f"\nwrote {out / 'summary.json'}")


if __name__ == "__main__":
    main()
