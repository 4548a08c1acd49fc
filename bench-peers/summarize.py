"""Summarise a `run.sh` run: criterion times, ratios and peers' op counts.

Reads OUT_DIR/target/criterion/<factor>/<method>/new/estimates.json (the
slope estimate, or the mean when criterion took no slope),
OUT_DIR/wrenfold_counts.json and OUT_DIR/symforce_counts.json; prints a table
and writes OUT_DIR/summary.json. Standard library only.

Usage: python3 summarize.py OUT_DIR
"""

import json
import sys
from pathlib import Path


def load(path: Path) -> dict:
    return json.loads(path.read_text()) if path.exists() else {}


def nanoseconds(estimates: dict) -> float:
    key = "slope" if estimates.get("slope") else "mean"
    return estimates[key]["point_estimate"]


def main() -> None:
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).parent / "out"
    criterion = out / "target" / "criterion"
    wrenfold = load(out / "wrenfold_counts.json")
    symforce = load(out / "symforce_counts.json")
    summary: dict[str, object] = {
        "wrenfold_version": wrenfold.get("wrenfold_version"),
        "symforce_version": symforce.get("symforce_version"),
        "symforce_skipped": symforce.get("skipped"),
        "factors": {},
    }
    print("\n== time per call (criterion, 64 configurations in turn) ==")
    for factor in ("point_reprojection", "plucker_line_reprojection"):
        times = {}
        for method_dir in sorted((criterion / factor).glob("*/new/estimates.json")):
            method = method_dir.parent.parent.name
            times[method] = nanoseconds(load(method_dir))
        entry: dict[str, object] = {"ns_per_call": times}
        if "dual" in times:
            entry["time_vs_dual"] = {m: t / times["dual"] for m, t in times.items()}
        if factor in wrenfold:
            entry["wrenfold_ops"] = wrenfold[factor]["total"]
        summary["factors"][factor] = entry
        for method, t in times.items():
            ratio = f"  ({t / times['dual']:.3f}x dual)" if "dual" in times else ""
            print(f"  {factor:28} {method:10} {t:10.1f} ns{ratio}")
    print("\n== operation counts (each peer's own) ==")
    for factor in ("point_reprojection", "plucker_line_reprojection"):
        if factor in wrenfold:
            print(
                f"  wrenfold {wrenfold['wrenfold_version']:7} {factor:28} {wrenfold[factor]['total']}"
            )
    if symforce.get("skipped"):
        print(f"  symforce: skipped ({symforce['skipped']})")
    for factor, entry in symforce.items():
        if isinstance(entry, dict) and "total_ops" in entry:
            print(
                f"  symforce {symforce['symforce_version']:7} {factor:28} {entry['total_ops']}"
                f"  (with_jacobians on SymForce's own tangents: "
                f"{entry['native_with_jacobians_total_ops']})"
            )
            summary["factors"].setdefault(factor, {})["symforce_ops"] = entry["total_ops"]
    (out / "summary.json").write_text(json.dumps(summary, indent=2) + "\n")
    print(f"\nwrote {out / 'summary.json'}")


if __name__ == "__main__":
    main()
