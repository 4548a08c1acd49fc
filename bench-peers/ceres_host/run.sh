#!/usr/bin/env bash
# The generated C++ in Ceres 2.1 (not part of CI): Ceres' own checks of the
# generated cost functions and manifolds, bundle adjustment with the
# generated Snavely cost function against AutoDiffCostFunction, and problem
# files of the documents' and of the example user crate's factors solved by
# Ceres and by `slamjac solve` / `user-cli solve`.
#
#   bash bench-peers/ceres_host/run.sh                    # everything
#   bash bench-peers/ceres_host/run.sh --sizes 10000,100000 --rounds 3 --threads 1
#
# 1. builds the Ceres peer (../ceres_ba/build.sh: Debian's libceres-dev,
#    installed with apt-get if missing) and, with GoogleTest
#    (libgmock-dev, for Ceres' manifold_test_utils.h), gradient_check.cc,
#    problem.cc and the guide's example.cc, all with -Wall -Wextra -Werror,
#    and runs the example;
# 2. builds the export helper (export/, its own workspace), `slamjac` and
#    `user-cli` (release, feature `solve`);
# 3. gradient check: seeded configurations of every factor
#    (`ceres-host-export samples`) through Ceres' GradientChecker with the
#    generated manifolds, Ceres' manifold invariants, and the pitfall;
# 4. bundle adjustment: synthetic BAL problems (`slamjac synth-bal`, no
#    outliers) of the given sizes (observations; 5 views per point) and
#    data/Balbianello.out, each solved with `--cost autodiff`,
#    `autodiff-quaternion`, `generated` and `constant` (Ceres' own work
#    around a cost function), alternated for `--rounds` rounds; before
#    them, the cost functions alone (cost_speed.cc);
# 5. problem files: a `synth-plp` room solved by `slamjac solve` and by
#    Ceres (problem.cc), and a problem of the user crate's five factors
#    (`ceres-host-export user-problem`) by `user-cli solve` and by Ceres;
# 6. summarize.py prints the tables (and writes out/ceres_host/table.md).
#
# Everything is written under bench-peers/out/ceres_host (git-ignored).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
out="$root/bench-peers/out/ceres_host"
sizes="10000,100000,1000000"
rounds=3
threads=1
while [[ $# -gt 0 ]]; do
    case "$1" in
        --sizes) sizes="$2"; shift 2 ;;
        --rounds) rounds="$2"; shift 2 ;;
        --threads) threads="$2"; shift 2 ;;
        *) echo "error: unknown argument $1 (expected --sizes, --rounds, --threads)" >&2; exit 2 ;;
    esac
done
mkdir -p "$out"

ceres_ba="$(bash "$here/../ceres_ba/build.sh")"
if [[ ! -f /usr/include/gmock/gmock.h ]]; then
    echo "== installing libgmock-dev (apt-get)" >&2
    if [[ "$(id -u)" != 0 ]]; then
        echo "error: GoogleTest is missing; install it: sudo apt-get install libgmock-dev" >&2
        exit 1
    fi
    apt-get install -y libgmock-dev >"$out/apt-gmock.log" 2>&1
fi
flags=(-std=c++17 -Wall -Wextra -Werror -DNDEBUG -I/usr/include/eigen3 -I"$here/../ceres_ba"
       -I"$root/generated/cpp" -I"$root/examples/user-factor/user-kernels/cpp")
# The timing programs as ../ceres_ba/build.sh compiles ba.cc; the others
# without -march=native, whose wider Eigen alignment differs from Debian's
# libceres where Eigen objects cross into it (the checker's results).
for program in gradient_check problem example cost_speed; do
    echo "== compiling $program.cc" >&2
    optimization=(-O2)
    [[ "$program" == cost_speed ]] && optimization=(-O3 -march=native)
    g++ "${optimization[@]}" "${flags[@]}" "$here/$program.cc" -o "$out/$program" \
        -lceres -lglog -lgflags -lgtest -lgmock -lpthread
done

echo "== building the export helper, slamjac and user-cli (release)" >&2
export CARGO_TARGET_DIR="$root/target"
cargo build --release --quiet --manifest-path "$here/export/Cargo.toml"
(cd "$root" && cargo build --release --quiet --features solve -p slamjac -p user-cli)
export_bin="$CARGO_TARGET_DIR/release/ceres-host-export"
slamjac="$CARGO_TARGET_DIR/release/slamjac"
user_cli="$CARGO_TARGET_DIR/release/user-cli"

echo "== the guide's example" >&2
"$out/example" | tee "$out/example.txt"

echo "== gradient check (load average: $(cut -d' ' -f1-3 /proc/loadavg))" >&2
"$export_bin" samples "$out/samples" 100
CERES_HOST_SAMPLES="$out/samples" "$out/gradient_check" --gtest_brief=1 | tee "$out/gradient_check.txt"

echo "== the Snavely cost functions alone (load average: $(cut -d' ' -f1-3 /proc/loadavg))" >&2
"$out/cost_speed" 21 | tee "$out/cost_speed.txt"

echo "== bundle adjustment (load average: $(cut -d' ' -f1-3 /proc/loadavg))" >&2
: >"$out/ba.jsonl"
files=("$root/data/Balbianello.out")
IFS=',' read -r -a observations <<<"$sizes"
for n in "${observations[@]}"; do
    points=$((n / 5))
    cameras=$((n / 1000 > 20 ? n / 1000 : 20))
    file="$out/synthetic-$n.bal"
    [[ -f "$file" ]] || "$slamjac" synth-bal --cameras "$cameras" --points "$points" \
        --outliers 0 --output "$file" >&2
    files+=("$file")
done
for file in "${files[@]}"; do
    for round in $(seq 1 "$rounds"); do
        costs=(autodiff autodiff-quaternion generated constant)
        # Alternate the order from round to round.
        if (( round % 2 == 0 )); then costs=(constant generated autodiff-quaternion autodiff); fi
        for cost in "${costs[@]}"; do
            "$ceres_ba" "$file" --cost "$cost" --threads "$threads" \
                --function-tolerance 1e-8 | tee -a "$out/ba.jsonl"
        done
    done
done

echo "== problem files (load average: $(cut -d' ' -f1-3 /proc/loadavg))" >&2
"$slamjac" synth-plp --output "$out/room.json" >&2
"$export_bin" user-problem "$out/user.json"
: >"$out/problems.txt"
for problem in room user; do
    if [[ "$problem" == room ]]; then cli="$slamjac"; else cli="$user_cli"; fi
    "$cli" solve "$out/$problem.json" >"$out/$problem.solve.txt"
    "$export_bin" problem "$out/$problem.json" "$out/$problem.txt"
    "$out/problem" "$out/$problem.txt" --threads "$threads" >"$out/$problem.ceres.json"
    echo "$problem $(grep -m1 'cost: initial' "$out/$problem.solve.txt") $(cat "$out/$problem.ceres.json")" \
        >>"$out/problems.txt"
done

python3 "$here/summarize.py" "$out" | tee "$out/table.md"
