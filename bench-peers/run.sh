#!/usr/bin/env bash
# Side-by-side benchmark against peer code generators (not part of CI).
#
#   bash bench-peers/run.sh [CRITERION ARGS...]
#
# 1. a virtualenv out/venv with wrenfold (PyPI); wrenfold_factors.py generates
#    the point and Plücker-line kernels into out/wrenfold_generated.rs and its
#    op counts into out/wrenfold_counts.json;
# 2. the harness crate (its own workspace) checks wrenfold's outputs against
#    this project's linearize_dual() at 64 configurations per factor, and this
#    project's generated kernels (generated/, feature `generated`) against
#    wrenfold's, then benchmarks all three in one criterion run;
# 3. a virtualenv out/venv-symforce with SymForce; symforce_counts.py records
#    SymForce's op counts for the four document factors (skipped, with pip's
#    error, if SymForce does not install);
# 4. summarize.py prints the table (times, ratios, each generator's op counts,
#    ours read from the headers of generated/src/*.rs) and writes
#    out/summary.json.
#
# Everything is written under bench-peers/out/, which is git-ignored: nothing
# a peer generates is committed. Environment: PYTHON (default python3.11),
# WRENFOLD_VERSION (0.5.3), SYMFORCE_VERSION (0.12.0), SKIP_SYMFORCE=1,
# FRESH=1 (recreate the virtualenvs), GENERATED=0 (leave this project's
# generated kernels out of the criterion run and skip the A/B run), AB_ROUNDS
# (rounds of the A/B run, default 61).
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
out="$here/out"
python="${PYTHON:-python3.11}"
wrenfold_version="${WRENFOLD_VERSION:-0.5.3}"
symforce_version="${SYMFORCE_VERSION:-0.12.0}"
mkdir -p "$out"

if ! command -v "$python" >/dev/null; then
    echo "error: $python not found (set PYTHON to a CPython 3.11 interpreter)" >&2
    exit 1
fi

# A virtualenv at $1 with the pip requirement $2; returns pip's status, its
# log in $1.pip.log.
make_venv() {
    local venv="$1" requirement="$2"
    if [[ "${FRESH:-0}" == 1 ]]; then rm -rf "$venv"; fi
    if [[ ! -x "$venv/bin/python" ]]; then
        "$python" -m venv "$venv"
    fi
    "$venv/bin/python" -m pip install --disable-pip-version-check "$requirement" \
        >"$venv.pip.log" 2>&1
}

echo "== wrenfold $wrenfold_version: generating Rust =="
if ! make_venv "$out/venv" "wrenfold==$wrenfold_version"; then
    echo "error: pip install wrenfold==$wrenfold_version failed:" >&2
    tail -n 20 "$out/venv.pip.log" >&2
    exit 1
fi
"$out/venv/bin/python" "$here/wrenfold_factors.py" "$out"

echo "== harness: conventions check and criterion run =="
# Builds and criterion's reports (which follow CARGO_TARGET_DIR) go under out/.
export CARGO_TARGET_DIR="$out/target"
manifest="$here/harness/Cargo.toml"
cargo run -q --release --manifest-path "$manifest" --bin dump_samples -- "$out/samples.json" 8
features=(--features generated)
if [[ "${GENERATED:-1}" == 0 ]]; then features=(); fi
cargo bench --manifest-path "$manifest" "${features[@]}" --bench peers -- "$@"
if [[ "${GENERATED:-1}" != 0 ]]; then
    echo "== A/B-alternated ratios (harness/src/bin/ab.rs) =="
    cargo run -q --release --manifest-path "$manifest" --features generated --bin ab -- "${AB_ROUNDS:-61}"
fi

if [[ "${SKIP_SYMFORCE:-0}" == 1 ]]; then
    echo '{"skipped": "SKIP_SYMFORCE=1"}' >"$out/symforce_counts.json"
else
    echo "== SymForce $symforce_version: op counts =="
    if make_venv "$out/venv-symforce" "symforce==$symforce_version"; then
        "$out/venv-symforce/bin/python" "$here/symforce_counts.py" "$out"
    else
        reason="$(grep -E '^ERROR' "$out/venv-symforce.pip.log" | head -n 3 | tr '\n' ' ')"
        echo "SymForce did not install; skipped. pip said: $reason" >&2
        "$python" -c 'import json, sys; print(json.dumps({"skipped": "pip install failed: " + sys.argv[1]}))' \
            "$reason" >"$out/symforce_counts.json"
    fi
fi

"$python" "$here/summarize.py" "$out"
