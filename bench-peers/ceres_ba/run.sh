#!/usr/bin/env bash
# Bundle adjustment against Ceres 2.1: `slamjac solve` (its Schur-complement
# path, and apex-solver's) beside Ceres' SPARSE_SCHUR on synthetic problems,
# whole processes alternated (integrations/schur/benches/versus_ceres.rs).
#
#   bash bench-peers/ceres_ba/run.sh [DRIVER ARGS...]
#   bash bench-peers/ceres_ba/run.sh --sizes 10000,100000 --rounds 5
#
# 1. builds the Ceres peer (build.sh: Debian's libceres-dev, installed with
#    apt-get if missing);
# 2. builds `slamjac` (release, feature `solve`) and copies it beside the
#    peer, so that builds during the run do not change what is measured;
# 3. runs the driver: problems written to bench-peers/out/ba/, the table to
#    bench-peers/out/ba/table.md and the plot to bench-peers/out/ba/plot.svg
#    unless the arguments say otherwise.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
out="$root/bench-peers/out"
ceres="$(bash "$here/build.sh")"
echo "== building slamjac (release, --features solve)" >&2
(cd "$root" && cargo build --release --features solve --quiet)
mkdir -p "$out/ba"
cp "$root/target/release/slamjac" "$out/slamjac"
echo "== running the comparison (load average: $(cut -d' ' -f1-3 /proc/loadavg))" >&2
cd "$root"
CARGO_TARGET_DIR="$root/target" cargo bench --quiet --manifest-path integrations/schur/Cargo.toml \
    --bench versus_ceres -- --slamjac "$out/slamjac" --ceres "$ceres" --out "$out/ba" \
    --markdown "$out/ba/table.md" --svg "$out/ba/plot.svg" "$@"
