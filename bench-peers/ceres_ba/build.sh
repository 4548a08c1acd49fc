#!/usr/bin/env bash
# Builds the Ceres bundle-adjustment peer (ba.cc, with this project's generated
# Ceres cost function from generated/cpp) into bench-peers/out/ceres_ba,
# installing Debian's libceres-dev (Ceres 2.1, SuiteSparse/CHOLMOD) first if
# its headers are missing. Prints the binary's path.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
out="$here/../out"
mkdir -p "$out"
if [[ ! -f /usr/include/ceres/ceres.h ]]; then
    echo "== installing libceres-dev (apt-get)" >&2
    if [[ "$(id -u)" != 0 ]]; then
        echo "error: libceres-dev is missing; install it: sudo apt-get install libceres-dev" >&2
        exit 1
    fi
    apt-get install -y libceres-dev >"$out/apt-ceres.log" 2>&1 || {
        apt-get update >>"$out/apt-ceres.log" 2>&1
        apt-get install -y libceres-dev >>"$out/apt-ceres.log" 2>&1
    }
fi
generated="$here/../../generated/cpp/factor_generated"
if [[ ! -x "$out/ceres_ba" || "$here/ba.cc" -nt "$out/ceres_ba" \
      || "$here/snavely_functors.h" -nt "$out/ceres_ba" \
      || -n "$(find "$generated" -newer "$out/ceres_ba" -name '*.h' -print -quit)" ]]; then
    echo "== compiling ba.cc" >&2
    g++ -O3 -march=native -DNDEBUG -std=c++17 -Wall -Wextra -Werror -I/usr/include/eigen3 \
        -I"$here/../../generated/cpp" "$here/ba.cc" \
        -o "$out/ceres_ba" -lceres -lglog -lgflags -lpthread
fi
echo "$out/ceres_ba"
