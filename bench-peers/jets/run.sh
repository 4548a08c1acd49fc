#!/usr/bin/env bash
# Dual numbers beside Ceres 2.1's Jets, side by side (not part of CI):
#
#   bash bench-peers/jets/run.sh [ROUNDS] [PASSES]
#
# Builds jets.cc against Debian's libceres-dev (installed with apt-get when
# its headers are missing, as bench-peers/ceres_ba/build.sh does) and this
# crate, both for this machine (-march=native, -C target-cpu=native); writes
# 4 096 configurations of each factor; checks Ceres' residuals and
# Jacobians against ours (1e-9 relative); then alternates ROUNDS (default
# 3) runs of each side, each PASSES (default 200) passes over the
# configurations, and prints every run's JSON lines and, per round, the
# ratio of each of our methods to Ceres' AutoDiffCostFunction (minimum ns
# over the passes). Everything goes under bench-peers/out/.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
out="$here/../out"
mkdir -p "$out"
rounds="${1:-3}"
passes="${2:-200}"
n=4096

if [[ ! -f /usr/include/ceres/ceres.h ]]; then
    echo "== installing libceres-dev (apt-get)" >&2
    apt-get install -y libceres-dev >"$out/apt-ceres.log" 2>&1 || {
        apt-get update >>"$out/apt-ceres.log" 2>&1
        apt-get install -y libceres-dev >>"$out/apt-ceres.log" 2>&1
    }
fi
echo "== compiling jets.cc" >&2
g++ -O3 -march=native -std=c++17 -DNDEBUG -I/usr/include/eigen3 "$here/jets.cc" \
    -o "$out/jets_ceres" -lceres -lglog -lgflags -lpthread
echo "== building the Rust side" >&2
export CARGO_TARGET_DIR="$out/target-jets"
RUSTFLAGS="-C target-cpu=native" cargo build -q --release --manifest-path "$here/Cargo.toml"
ours="$CARGO_TARGET_DIR/release/bench-peers-jets"

"$ours" write "$out/jets_samples.txt" "$n"
"$out/jets_ceres" "$out/jets_samples.txt" check "$out/jets_ceres_outputs.txt"
"$ours" check "$n" "$out/jets_ceres_outputs.txt"

echo "== $rounds alternating rounds, $passes passes each (load: $(cut -d' ' -f1-3 /proc/loadavg))"
for round in $(seq 1 "$rounds"); do
    if (( round % 2 )); then
        ceres="$("$out/jets_ceres" "$out/jets_samples.txt" time "$passes")"
        rust="$("$ours" time "$n" "$passes")"
    else
        rust="$("$ours" time "$n" "$passes")"
        ceres="$("$out/jets_ceres" "$out/jets_samples.txt" time "$passes")"
    fi
    echo "-- round $round"
    echo "$ceres"
    echo "$rust"
    python3 - "$ceres" "$rust" <<'PY'
import json, sys
ceres = [json.loads(l) for l in sys.argv[1].splitlines()]
ours = [json.loads(l) for l in sys.argv[2].splitlines()]
base = {c["factor"]: c["min_ns"] for c in ceres if c["method"] == "ceres_autodiff"}
for o in ours:
    print(f'   {o["factor"]:>10} {o["method"]:>22}: {o["min_ns"]:8.1f} ns, '
          f'{o["min_ns"] / base[o["factor"]]:.2f}x Ceres AutoDiff ({base[o["factor"]]:.1f} ns)')
PY
done
echo "== load after: $(cut -d' ' -f1-3 /proc/loadavg)"
