// The example of the guide's chapter "Kernels in C++ solvers"
// (docs/guide/cpp-and-ceres.md quotes it): two small Ceres problems with
// generated cost functions and manifolds.
//
// 1. A camera's pose from six known points (resection): slamjac's
//    `point_reprojection` (generated/cpp), the pose on its own manifold.
// 2. A direction on S² seen from three known orientations: the example
//    user crate's `direction` factor over its own manifold UnitVector3
//    (examples/user-factor/user-kernels/cpp).
//
//   g++ -O2 -std=c++17 -I/usr/include/eigen3 -Igenerated/cpp
//       -Iexamples/user-factor/user-kernels/cpp example.cc -o example
//       -lceres -lglog -lgflags -lpthread
#include <ceres/ceres.h>

#include <cmath>
#include <cstdio>

#include "factor_generated/ceres/point_reprojection.h"
#include "user_kernels/ceres/direction.h"

int main() {
  // 1. A pose is world to camera, stored [qx, qy, qz, qw, tx, ty, tz]; the
  //    truth here is no rotation and t = (-1, 0, 0), so that X_c = X - (1, 0, 0).
  double pose[7] = {0.05, -0.03, 0.02, 1.0, -0.8, 0.1, 0.2};
  // Quaternions must be unit: the retraction keeps their norm, and the
  // residual reads a quaternion of norm λ as λ² times a rotation.
  const double norm = std::sqrt(pose[0] * pose[0] + pose[1] * pose[1] + pose[2] * pose[2] +
                                pose[3] * pose[3]);
  for (int k = 0; k < 4; ++k) pose[k] /= norm;
  double points[6][3] = {{0, 0, 4}, {1, 0, 5}, {0, 1, 6}, {-1, -1, 4}, {2, 1, 7}, {1, -1, 5}};
  const double intrinsics[4] = {500, 500, 320, 240};  // [fu, fv, cu, cv]
  ceres::Problem problem;
  for (auto& p : points) {
    const double observed[2] = {500 * (p[0] - 1) / p[2] + 320, 500 * p[1] / p[2] + 240};
    auto* cost = new factor_generated::PointReprojectionCost(intrinsics, observed);
    const double sqrt_information[4] = {1.0, 0.0, 0.0, 1.0};  // σ = 1 px
    cost->SetSqrtInformation(sqrt_information);
    problem.AddResidualBlock(cost, nullptr, pose, p);
    problem.SetParameterBlockConstant(p);
  }
  // The pose's manifold: the factor's own chart, T <- Exp(δξ) T, [δω, δρ].
  problem.SetManifold(pose, factor_generated::PointReprojectionCost::NewManifold(0));
  ceres::Solver::Options options;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  std::printf("pose: q = (%.6f %.6f %.6f %.6f), t = (%.6f %.6f %.6f) (cost %.1e)\n", pose[0],
              pose[1], pose[2], pose[3], pose[4], pose[5], pose[6], summary.final_cost);

  // 2. Orientations (world to sensor, [qx, qy, qz, qw]) held fixed, the
  //    direction d estimated on S² from the measured directions R_k d.
  const double s = std::sqrt(0.5);
  double orientations[3][4] = {{0, 0, 0, 1}, {s, 0, 0, s}, {0, s, 0, s}};
  const double measured[3][3] = {{0, 0, 1}, {0, -1, 0}, {1, 0, 0}};  // d = (0, 0, 1)
  double direction[3] = {0.6, 0.0, 0.8};
  ceres::Problem sphere;
  for (int k = 0; k < 3; ++k) {
    sphere.AddResidualBlock(new user_kernels::DirectionCost(measured[k]), nullptr,
                            orientations[k], direction);
    sphere.SetParameterBlockConstant(orientations[k]);
  }
  // The user's own manifold, generated from its `Manifold` (retract, local).
  sphere.SetManifold(direction, new user_kernels::UnitVector3LeftManifold());
  ceres::Solve(options, &sphere, &summary);
  std::printf("direction: %.6f %.6f %.6f (cost %.3e)\n", direction[0], direction[1],
              direction[2], summary.final_cost);
  return 0;
}
