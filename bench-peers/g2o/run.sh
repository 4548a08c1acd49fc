#!/usr/bin/env bash
# g2o as the peer on its own line and plane graphs (not part of CI).
#
#   bash bench-peers/g2o/run.sh [GRAPH...]
#
# 1. downloads the PyPI wheel g2opy==2.3.0 (g2o's headers and static
#    libraries) and the source package peigen==0.0.9 (Eigen 3.3.4's headers:
#    the wheel was built against Eigen 3.3, and the plane edge's inline code
#    differs under Eigen 3.4) into bench-peers/out/g2o;
# 2. builds this project's driver solve_g2o.cpp against them;
# 3. solves each GRAPH (default: the three graphs of data/g2o-addons/) with
#    g2o's Levenberg–Marquardt until it stops by itself, printing one JSON
#    line per graph (initial and final χ², iterations, seconds) into
#    bench-peers/out/g2o/results.jsonl, and the optimised vertices into
#    bench-peers/out/g2o/NAME.estimates.g2o;
# 4. with the ground truth beside a graph (NAME_truth.g2o; the calibration
#    graph's is the plane graph's), errors.py prints the pose, landmark and
#    sensor-offset errors of g2o's solution into errors.jsonl.
#
# Everything is written under bench-peers/out/ (git-ignored). Environment:
# PYTHON (default python3), CXX (default g++), FRESH=1 (download again).
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
out="$root/bench-peers/out/g2o"
python="${PYTHON:-python3}"
cxx="${CXX:-g++}"
mkdir -p "$out"

source "$here/wheel.sh"

echo "== building solve_g2o =="
"$cxx" -std=c++17 -O2 -w -I "$out/g2opy/include" -I "$eigen" \
    "$here/solve_g2o.cpp" -o "$out/solve_g2o" \
    -L "$out/g2opy/lib64" -lg2o_solver_eigen -lg2o_solver_dense \
    -lg2o_types_slam3d_addons -lg2o_types_slam3d -lg2o_core -lg2o_stuff -lpthread -lrt

if [[ $# -eq 0 ]]; then
    set -- "$root"/data/g2o-addons/{line3d,plane3d,plane3d_calib}.g2o
fi
: >"$out/results.jsonl"
: >"$out/errors.jsonl"
for graph in "$@"; do
    name="$(basename "$graph" .g2o)"
    echo "== g2o LM on $name =="
    "$out/solve_g2o" "$graph" --estimates "$out/$name.estimates.g2o" | tee -a "$out/results.jsonl"
    # The ground truth beside the graph (the calibration graph shares the plane graph's).
    truth="$(dirname "$graph")/${name%_calib}_truth.g2o"
    if [[ -f "$truth" ]]; then
        "$python" "$here/errors.py" "$out/$name.estimates.g2o" "$truth" | tee -a "$out/errors.jsonl"
    fi
done
echo "results: $out/results.jsonl, errors against the ground truth: $out/errors.jsonl"
