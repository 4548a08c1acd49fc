"""The tables of `bench-peers/ceres_host/run.sh`, in Markdown, from its
outputs in OUT (bench-peers/out/ceres_host):

- the gradient check (gradient_check.txt: one line per factor);
- bundle adjustment (ba.jsonl: one JSON line per solve): per file and cost
  function, the median over rounds of Ceres' reported Jacobian evaluation
  time and of the solve's wall time, the final cost and iterations, and
  the ratios of the generated cost function to each AutoDiffCostFunction;
- problem files (problems.txt): the final cost `slamjac solve` /
  `user-cli solve` reached and the one Ceres reached.

    python3 summarize.py OUT
"""

import json
import os
import re
import statistics
import sys


def gradient_check(out):
    lines = ["| factor | configurations | largest relative error (GradientChecker) |",
             "| --- | ---: | ---: |"]
    other = []
    with open(os.path.join(out, "gradient_check.txt")) as f:
        for line in f:
            m = re.match(r"gradient check: (\S+): (\d+) configurations, largest relative error (\S+)", line)
            if m:
                lines.append(f"| `{m.group(1)}` | {m.group(2)} | {m.group(3)} |")
            elif line.startswith("pitfall:") or "PASSED" in line or "FAILED" in line:
                other.append(line.strip())
    return lines + [""] + other


def bundle_adjustment(out):
    runs = {}
    with open(os.path.join(out, "ba.jsonl")) as f:
        for line in f:
            r = json.loads(line)
            runs.setdefault((r["file"], r["observations"]), {}).setdefault(r["cost"], []).append(r)
    lines = ["| problem (observations) | cost function | final cost | iterations | "
             "Jacobian evaluation (s, median) | solve (s, median) | generated / this: Jacobian | "
             "generated / this: solve |",
             "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |"]
    for (file, observations), by_cost in runs.items():
        median = {c: (statistics.median(r["jacobian_s"] for r in rs),
                      statistics.median(r["solve_s"] for r in rs)) for c, rs in by_cost.items()}
        generated = median.get("generated")
        for cost in ("autodiff", "autodiff-quaternion", "generated"):
            if cost not in by_cost:
                continue
            r = by_cost[cost][0]
            jacobian, solve = median[cost]
            ratios = ("—", "—")
            if generated and cost != "generated":
                ratios = (f"{generated[0] / jacobian:.2f}", f"{generated[1] / solve:.2f}")
            lines.append(
                f"| {os.path.basename(file)} ({observations}) | {cost} | {r['final_cost']:.12e} | "
                f"{r['iterations']} | {jacobian:.3f} | {solve:.3f} | {ratios[0]} | {ratios[1]} |")
    return lines


def problems(out):
    lines = ["| problem | final cost, slamjac's solve | final cost, Ceres with the generated "
             "cost functions (iterations) | relative difference |",
             "| --- | ---: | ---: | ---: |"]
    with open(os.path.join(out, "problems.txt")) as f:
        for line in f:
            name = line.split()[0]
            ours = float(re.search(r"final ([0-9.eE+-]+)", line).group(1))
            ceres = json.loads(line[line.index("{"):])
            difference = abs(ceres["final_cost"] - ours) / ours
            lines.append(f"| {name} | {ours:.12e} | {ceres['final_cost']:.12e} "
                         f"({ceres['iterations']}, {ceres['termination']}) | {difference:.1e} |")
    return lines


def main():
    out = sys.argv[1]
    for title, table in (("Ceres' GradientChecker and manifold invariants", gradient_check(out)),
                         ("Bundle adjustment", bundle_adjustment(out)),
                         ("Problem files", problems(out))):
        print(f"### {title}\n")
        print("\n".join(table))
        print()


if __name__ == "__main__":
    main()
