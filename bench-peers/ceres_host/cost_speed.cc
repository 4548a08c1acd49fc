// The cost functions alone, outside a solve: CostFunction::Evaluate with
// every Jacobian, per call, for the generated Snavely cost function and the
// two AutoDiffCostFunctions of ../ceres_ba/ba.cc (snavely_functors.h: the
// same residual over the same blocks, and over the 9-parameter angle-axis
// camera), on 1000
// seeded BAL-like configurations, in rounds that alternate the order (the
// machine is shared: the per-round ratios are what to read).
//
//   cost_speed [ROUNDS]
//
// Prints one line per cost function (the minimum ns per call over the
// rounds) and the median and quartiles of the per-round ratios of the
// generated cost function to each AutoDiffCostFunction.
#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "factor_generated/ceres/snavely_reprojection.h"
#include "snavely_functors.h"

namespace {

struct Configuration {
  double camera[9], pose[7], intrinsics[3], point[3], observed[2];
};

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

// Nanoseconds per call of `cost` over every configuration, `passes` times.
template <typename Blocks>
double Time(const ceres::CostFunction& cost, const std::vector<Configuration>& all, int passes,
            Blocks blocks, double* sink) {
  double residuals[2] = {0.0, 0.0}, j0[18] = {}, j1[6] = {}, j2[6] = {};
  double* jacobians[3] = {j0, j1, j2};
  const auto start = std::chrono::steady_clock::now();
  for (int pass = 0; pass < passes; ++pass) {
    for (const Configuration& c : all) {
      const std::array<const double*, 3> parameters = blocks(c);
      cost.Evaluate(parameters.data(), residuals, jacobians);
      *sink += residuals[0] + j0[3];
    }
  }
  return Seconds(start) * 1e9 / (static_cast<double>(passes) * all.size());
}

double Quartile(std::vector<double> values, double q) {
  std::sort(values.begin(), values.end());
  return values[static_cast<size_t>(q * (values.size() - 1) + 0.5)];
}

}  // namespace

int main(int argc, char** argv) {
  const int rounds = argc > 1 ? std::atoi(argv[1]) : 21;
  const int passes = 200;
  std::mt19937 random(29);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<Configuration> all(1000);
  for (Configuration& c : all) {
    for (int k = 0; k < 3; ++k) c.camera[k] = 0.3 * unit(random);
    for (int k = 3; k < 6; ++k) c.camera[k] = unit(random);
    c.camera[5] -= 10.0;  // the points in front: the camera looks down -z
    c.camera[6] = 500.0 + 50.0 * unit(random);
    c.camera[7] = 1e-2 * unit(random);
    c.camera[8] = 1e-4 * unit(random);
    double q[4];
    ceres::AngleAxisToQuaternion(c.camera, q);
    const double pose[7] = {q[1], q[2], q[3], q[0], c.camera[3], c.camera[4], c.camera[5]};
    std::copy(pose, pose + 7, c.pose);
    std::copy(c.camera + 6, c.camera + 9, c.intrinsics);
    for (double& v : c.point) v = unit(random);
    c.observed[0] = 10.0 * unit(random);
    c.observed[1] = 10.0 * unit(random);
  }
  // One cost function per kind, its constant the first configuration's
  // observation: the work per call does not depend on it.
  const double* observed = all[0].observed;
  factor_generated::SnavelyReprojectionCost generated(observed);
  ceres::AutoDiffCostFunction<QuaternionReprojection, 2, 7, 3, 3> quaternion(
      new QuaternionReprojection(observed[0], observed[1]));
  ceres::AutoDiffCostFunction<Reprojection, 2, 9, 3> angle_axis(
      new Reprojection(observed[0], observed[1]));
  auto split = [](const Configuration& c) {
    return std::array<const double*, 3>{c.pose, c.intrinsics, c.point};
  };
  auto whole = [](const Configuration& c) {
    return std::array<const double*, 3>{c.camera, c.point, nullptr};
  };
  double sink = 0.0;
  std::vector<double> g, q, a, to_q, to_a;
  for (int round = 0; round < rounds; ++round) {
    double tg, tq, ta;
    if (round % 2 == 0) {
      tg = Time(generated, all, passes, split, &sink);
      tq = Time(quaternion, all, passes, split, &sink);
      ta = Time(angle_axis, all, passes, whole, &sink);
    } else {
      ta = Time(angle_axis, all, passes, whole, &sink);
      tq = Time(quaternion, all, passes, split, &sink);
      tg = Time(generated, all, passes, split, &sink);
    }
    g.push_back(tg);
    q.push_back(tq);
    a.push_back(ta);
    to_q.push_back(tg / tq);
    to_a.push_back(tg / ta);
  }
  std::printf("generated: %.1f ns per call (minimum of %d rounds)\n",
              *std::min_element(g.begin(), g.end()), rounds);
  std::printf("autodiff-quaternion: %.1f ns per call\n", *std::min_element(q.begin(), q.end()));
  std::printf("autodiff (angle-axis): %.1f ns per call\n", *std::min_element(a.begin(), a.end()));
  std::printf("generated / autodiff-quaternion: median %.3f (quartiles %.3f, %.3f)\n",
              Quartile(to_q, 0.5), Quartile(to_q, 0.25), Quartile(to_q, 0.75));
  std::printf("generated / autodiff (angle-axis): median %.3f (quartiles %.3f, %.3f)\n",
              Quartile(to_a, 0.5), Quartile(to_a, 0.25), Quartile(to_a, 0.75));
  return sink == 0.0 ? 1 : 0;  // keeps the calls
}
