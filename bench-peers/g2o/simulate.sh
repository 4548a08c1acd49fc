#!/usr/bin/env bash
# Regenerates held-out g2o graphs with g2o's own simulators (not part of CI).
#
#   bash bench-peers/g2o/simulate.sh
#
# 1. downloads the g2opy wheel and Eigen 3.3.4's headers as run.sh does
#    (wheel.sh);
# 2. takes g2o's simulator sources at the commit the wheel's headers match
#    (branch pymem, commit G2O_COMMIT below) from $G2O_SRC (a g2o checkout at
#    that commit) or else clones it, and CLI11 v2.5.0's headers from
#    $CLI11_SRC (a CLI11 checkout at v2.5.0) or else clones it;
# 3. builds g2o's simulator_3d_plane (g2o/examples/plane_slam) and this
#    project's simulate3d.cpp (g2o's 3D simulator library) against the wheel,
#    with register_types.cpp;
# 4. writes into bench-peers/out/g2o/sim/:
#    - plane3d_planar.g2o: simulator_3d_plane --planar_motion=true (sensor
#      offset fixed at its truth): poses, planes, EDGE_SE3_PLANE_CALIB and one
#      EDGE_SE3_PRIOR per pose (information diag(0, 0, 1e9, 0, 0, 0): z = 0);
#    - plane3d_planar_calib.g2o: the same with the sensor offset free;
#    - points3d.g2o: g2o's 3D simulator (g2o::Simulator3D, through this
#      project's driver simulate3d.cpp: g2o's own g2o_simulator3d at that
#      commit aborts on start-up, one of its flags lacking its dashes) with
#      odometry and its point sensor (VERTEX_TRACKXYZ, EDGE_SE3_TRACKXYZ
#      through a sensor offset, EDGE_SE3:QUAT), the first pose fixed;
#    - points3d_gps.g2o: the same robot with its "GPS" pose prior too
#      (EDGE_SE3_PRIOR through another sensor offset, full information).
# Then `bash bench-peers/g2o/run.sh bench-peers/out/g2o/sim/*.g2o` solves
# them with g2o. The plane simulator draws from std::rand() without seeding
# it, the 3D simulator from its own default-seeded generators, so a run is
# deterministic for a given C library. Nothing here is committed.
# Environment: PYTHON, CXX, FRESH=1 as run.sh; G2O_SRC, CLI11_SRC.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
out="$root/bench-peers/out/g2o"
python="${PYTHON:-python3}"
cxx="${CXX:-g++}"
G2O_COMMIT=ceaf0de1b89f680493d90f61356f273e46706d1f
CLI11_TAG=v2.5.0
mkdir -p "$out/sim"

source "$here/wheel.sh"

g2o_src="${G2O_SRC:-$out/g2o-src}"
if [[ ! -d "$g2o_src/g2o/examples/plane_slam" ]]; then
    echo "== cloning g2o at $G2O_COMMIT =="
    git clone --quiet https://github.com/RainerKuemmerle/g2o "$g2o_src"
    git -C "$g2o_src" checkout --quiet "$G2O_COMMIT"
fi
cli11_src="${CLI11_SRC:-$out/cli11-src}"
if [[ ! -f "$cli11_src/include/CLI/CLI.hpp" ]]; then
    echo "== cloning CLI11 $CLI11_TAG =="
    git clone --quiet --depth 1 --branch "$CLI11_TAG" https://github.com/CLIUtils/CLI11 "$cli11_src"
fi

flags=(-std=c++17 -O2 -w -I "$out/g2opy/include" -I "$eigen" -I "$cli11_src/include")
libs=(-L "$out/g2opy/lib64" -lg2o_simulator -lg2o_solver_eigen -lg2o_solver_dense
    -lg2o_types_slam3d_addons -lg2o_types_slam3d -lg2o_core -lg2o_stuff -lpthread -lrt)
echo "== building simulator_3d_plane and simulate3d =="
"$cxx" "${flags[@]}" "$g2o_src/g2o/examples/plane_slam/simulator_3d_plane.cpp" \
    "$here/register_types.cpp" -o "$out/simulator_3d_plane" "${libs[@]}"
"$cxx" "${flags[@]}" "$here/simulate3d.cpp" \
    "$here/register_types.cpp" -o "$out/simulate3d" "${libs[@]}"

cd "$out/sim"
echo "== simulating =="
# The plane simulator binds its flags to uninitialised booleans: every flag
# is given. It writes test_preopt.g2o (and test_postOpt.g2o after its own
# solve, not used).
for calib in false true; do
    "$out/simulator_3d_plane" --fix_sensor="$([[ $calib == true ]] && echo false || echo true)" \
        --fix_trajectory=false --fix_first_pose=true --fix_planes=false \
        --planar_motion=true >/dev/null 2>&1
    name=plane3d_planar$([[ $calib == true ]] && echo _calib || true).g2o
    mv test_preopt.g2o "$name"
    rm -f test_postOpt.g2o
done
"$out/simulate3d" points3d.g2o --points
"$out/simulate3d" points3d_gps.g2o --points --gps
rm -f test_gt.g2o
for g in *.g2o; do
    echo "$g: $(awk '{ print $1 }' "$g" | sort | uniq -c | tr -s ' ' | tr '\n' ',')"
done
