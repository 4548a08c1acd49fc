# Sourced by run.sh and simulate.sh with $out, $python set: downloads the
# PyPI wheel g2opy==2.3.0 (g2o's headers and static libraries) and the source
# package peigen==0.0.9 (Eigen 3.3.4's headers, which the wheel was built
# against) into $out once (again with FRESH=1), and sets $eigen.
if [[ "${FRESH:-0}" == 1 ]]; then rm -rf "$out/wheels" "$out/g2opy" "$out/peigen"; fi

if [[ ! -d "$out/g2opy/include/g2o" ]]; then
    echo "== downloading g2opy 2.3.0 and peigen 0.0.9 (Eigen 3.3.4) from PyPI =="
    "$python" -m pip download --disable-pip-version-check --no-deps \
        --only-binary :all: --platform manylinux_2_28_x86_64 --python-version 3.11 \
        g2opy==2.3.0 -d "$out/wheels" >"$out/pip.log" 2>&1
    "$python" -m pip download --disable-pip-version-check --no-deps --no-binary :all: \
        peigen==0.0.9 -d "$out/wheels" >>"$out/pip.log" 2>&1
    mkdir -p "$out/g2opy" "$out/peigen"
    "$python" -m zipfile -e "$out"/wheels/g2opy-2.3.0-*.whl "$out/g2opy"
    tar xzf "$out/wheels/peigen-0.0.9.tar.gz" -C "$out/peigen" --strip-components=1
fi
eigen="$out/peigen/peigen/include"
grep -q "define EIGEN_MINOR_VERSION 4" "$eigen/Eigen/src/Core/util/Macros.h" || {
    echo "error: $eigen is not Eigen 3.3.4" >&2
    exit 1
}

