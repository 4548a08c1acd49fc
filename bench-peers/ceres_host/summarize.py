"""The tables of `bench-peers/ceres_host/run.sh`, in Markdown, from its
outputs in OUT (bench-peers/out/ceres_host):

- the gradient check (gradient_check.txt: one line per factor);
- the cost functions alone (cost_speed.txt, as cost_speed printed it);
- bundle adjustment (ba.jsonl: one JSON line per solve): per file and cost
  function, the medians over rounds of Ceres' reported Jacobian evaluation
  time per evaluation and observation and of the solve's wall and CPU
  times, the final cost and iterations, and the ratios of the generated
  cost function to each AutoDiffCostFunction;
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
    lines = ["| factor | configurations | largest error (relative, floored at 1e-3 of the block) | "
             "the checker's own verdict passed at |",
             "| --- | ---: | ---: | ---: |"]
    other = []
    pattern = (r"gradient check: (\S+): (\d+) configurations, largest error (\S+) .*"
               r"verdict passed at (\d+)")
    with open(os.path.join(out, "gradient_check.txt")) as f:
        for line in f:
            m = re.match(pattern, line)
            if m:
                lines.append(f"| `{m.group(1)}` | {m.group(2)} | {m.group(3)} | {m.group(4)} |")
            elif line.startswith("pitfall:") or "PASSED" in line or "FAILED" in line \
                    or "SKIPPED" in line:
                other.append(line.strip())
    return lines + [""] + other


def bundle_adjustment(out):
    runs = {}
    with open(os.path.join(out, "ba.jsonl")) as f:
        for line in f:
            r = json.loads(line)
            runs.setdefault((r["file"], r["observations"]), {}).setdefault(r["cost"], []).append(r)
    lines = ["| problem (observations) | cost function | final cost | iterations | "
             "Jacobian evaluation, µs per observation (median) | solve, s wall / s CPU (median) | "
             "generated / this: Jacobian evaluation | generated / this: solve (CPU) |",
             "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |"]
    for (file, observations), by_cost in runs.items():
        # Ceres' reported Jacobian evaluation time per evaluation and
        # observation, and the solve's wall and CPU times, medians of rounds.
        median = {c: (statistics.median(r["jacobian_s"] / r["jacobian_evaluations"] /
                                        r["observations"] * 1e6 for r in rs),
                      statistics.median(r["solve_s"] for r in rs),
                      statistics.median(r["solve_cpu_s"] for r in rs))
                  for c, rs in by_cost.items()}
        generated = median.get("generated")
        for cost in ("autodiff", "autodiff-quaternion", "generated", "constant"):
            if cost not in by_cost:
                continue
            r = by_cost[cost][0]
            jacobian, wall, cpu = median[cost]
            ratios = ("—", "—")
            if generated and cost not in ("generated", "constant"):
                ratios = (f"{generated[0] / jacobian:.2f}", f"{generated[2] / cpu:.2f}")
            final = "—" if cost == "constant" else f"{r['final_cost']:.12e}"
            lines.append(
                f"| {os.path.basename(file)} ({observations}) | {cost} | {final} | "
                f"{r['iterations']} | {jacobian:.3f} | {wall:.2f} / {cpu:.2f} | {ratios[0]} | "
                f"{ratios[1]} |")
    return lines


def cost_speed(out):
    with open(os.path.join(out, "cost_speed.txt")) as f:
        return [line.rstrip() for line in f]


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
                         ("The Snavely cost functions alone (ns per call)", cost_speed(out)),
                         ("Bundle adjustment", bundle_adjustment(out)),
                         ("Problem files", problems(out))):
        print(f"### {title}\n")
        print("\n".join(table))
        print()


if __name__ == "__main__":
    main()
