// Ceres' own checks of the generated cost functions and manifolds, at the
// seeded configurations `ceres-host-export samples DIR` wrote (DIR in the
// environment variable CERES_HOST_SAMPLES):
//
// - every cost function, at every configuration, through Ceres'
//   GradientChecker with its manifolds (`NewManifold`): its Jacobians times
//   the manifolds' PlusJacobian against Ridders' numerical differentiation
//   of the cost function times the same PlusJacobian. The checker's own
//   verdict compares every entry relatively (below kPrecision), with no
//   floor: an entry whose true value is 0 but which is a sum of products
//   that cancel (a residual row that does not depend on a rotation, reached
//   through the PlusJacobian's rotation-translation block) comes out as
//   ±1e-17 from the kernel and ±1e-13 from the differences, a relative
//   error of 1. So the test requires every entry's error relative to the
//   larger of its size and kFloor of its block's largest entry to be below
//   kPrecision, and the printed line also says at how many configurations
//   the checker's verdict alone passed;
// - every manifold satisfies Ceres' own manifold invariants
//   (EXPECT_THAT_MANIFOLD_INVARIANTS_HOLD of ceres/manifold_test_utils.h:
//   Plus(x, 0) = x, Minus(x, x) = 0, Minus(Plus(x, δ), x) = δ,
//   Plus(x, Minus(y, x)) = y, PlusJacobian and MinusJacobian against
//   numerical derivatives, MinusJacobian · PlusJacobian = I) at each
//   configuration's value of its variable, with a seeded step δ and the
//   next configuration's value as y;
// - the pitfall: the point factor's Jacobian in its own tangent padded with
//   a zero column, with a manifold whose PlusJacobian is the identity block
//   (Plus still the factor's own retraction), fails the GradientChecker.
//
// Prints one line per factor: configurations checked and the largest
// relative error the checker found.
#include <ceres/ceres.h>
#include <ceres/gradient_checker.h>
#include <ceres/manifold_test_utils.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "factors.h"

namespace {

// The checker's bound on the relative error of each Jacobian entry.
constexpr double kPrecision = 1e-7;
// The floor of an entry's size, as a fraction of its block's largest
// entry: below it, differences are rounding (the numerical differences'
// own is about 1e-13 of the block).
constexpr double kFloor = 1e-3;

// The largest error of the checker's results: each entry's difference
// relative to the larger of its size and kFloor of its block's largest.
double LargestError(const ceres::GradientChecker::ProbeResults& results) {
  double largest = 0.0;
  for (size_t k = 0; k < results.local_jacobians.size(); ++k) {
    const ceres::Matrix& user = results.local_jacobians[k];
    const ceres::Matrix& numeric = results.local_numeric_jacobians[k];
    const double floor = kFloor * numeric.cwiseAbs().maxCoeff();
    for (int i = 0; i < user.rows(); ++i) {
      for (int j = 0; j < user.cols(); ++j) {
        const double size =
            std::max({std::abs(user(i, j)), std::abs(numeric(i, j)), floor});
        if (size > 0) largest = std::max(largest, std::abs(user(i, j) - numeric(i, j)) / size);
      }
    }
  }
  return largest;
}

// The checker's numerical differentiation: Ridders' method from a step of
// 1e-4 of each parameter, as Ceres' manifold_test_utils.h sets it. From
// Ceres' default first step, 1e-2 of the parameter, the extrapolation
// settles on a wrong value at a few configurations (the point factor's
// ∂r/∂q_x 7% off at 6 of 100, where central differences with h = 1e-6 and
// dual numbers agree with the kernel to 1e-10).
ceres::NumericDiffOptions Ridders() {
  ceres::NumericDiffOptions options;
  options.ridders_relative_initial_step_size = 1e-4;
  return options;
}
// The invariants' tolerance (Ceres' tests of its own manifolds use 1e-9
// with exact inputs; the numerical derivatives dominate here).
constexpr double kInvariantTolerance = 1e-8;

// One field of a factor: its stored scalars, variable or constant.
struct Field {
  bool variable;
  int scalars;
};

// A sample file: the fields and the configurations.
struct Samples {
  std::vector<Field> fields;
  std::vector<std::vector<double>> configurations;
};

Samples Read(const std::string& name) {
  const char* dir = std::getenv("CERES_HOST_SAMPLES");
  if (dir == nullptr) ADD_FAILURE() << "CERES_HOST_SAMPLES is not set";
  std::ifstream in(std::string(dir == nullptr ? "." : dir) + "/" + name + ".txt");
  Samples samples;
  int count = 0, scalars = 0, total = 0;
  in >> count >> scalars;
  while (total < scalars) {
    std::string kind;
    int n = 0;
    in >> kind >> n;
    samples.fields.push_back({kind == "variable", n});
    total += n;
  }
  for (int c = 0; c < count; ++c) {
    std::vector<double> configuration(scalars);
    for (double& v : configuration) in >> v;
    samples.configurations.push_back(configuration);
  }
  EXPECT_TRUE(in.good() && count > 0) << name << ": no samples";
  return samples;
}

// The constants' stored scalars concatenated, and each variable's start.
void Split(const Samples& samples, const std::vector<double>& stored,
           std::vector<double>* constants, std::vector<int>* variables) {
  int at = 0;
  for (const Field& f : samples.fields) {
    if (f.variable) {
      variables->push_back(at);
    } else {
      constants->insert(constants->end(), stored.begin() + at,
                        stored.begin() + at + f.scalars);
    }
    at += f.scalars;
  }
}

class Factors : public testing::TestWithParam<std::string> {};

TEST_P(Factors, GradientCheckerPassesWithTheGeneratedManifolds) {
  const ceres_host::Factor* factor = ceres_host::Find(GetParam());
  ASSERT_NE(factor, nullptr);
  Samples samples = Read(GetParam());
  double worst = 0.0;
  int passed = 0;
  for (std::vector<double>& stored : samples.configurations) {
    std::vector<double> constants;
    std::vector<int> variables;
    Split(samples, stored, &constants, &variables);
    std::unique_ptr<ceres::CostFunction> cost(factor->from_constants(constants.data()));
    std::vector<std::unique_ptr<ceres::Manifold>> owned;
    std::vector<const ceres::Manifold*> manifolds;
    std::vector<double*> parameters;
    for (size_t k = 0; k < variables.size(); ++k) {
      owned.emplace_back(factor->new_manifold(static_cast<int>(k)));
      manifolds.push_back(owned.back().get());
      parameters.push_back(stored.data() + variables[k]);
    }
    ceres::GradientChecker checker(cost.get(), &manifolds, Ridders());
    ceres::GradientChecker::ProbeResults results;
    if (checker.Probe(parameters.data(), kPrecision, &results)) ++passed;
    const double error = LargestError(results);
    EXPECT_LT(error, kPrecision) << GetParam() << ":\n" << results.error_log;
    worst = std::max(worst, error);
  }
  std::printf(
      "gradient check: %s: %zu configurations, largest error %.2e (relative, floored at %.0e "
      "of the block); the checker's own verdict passed at %d\n",
      GetParam().c_str(), samples.configurations.size(), worst, kFloor, passed);
}

TEST_P(Factors, ManifoldInvariantsHold) {
  const ceres_host::Factor* factor = ceres_host::Find(GetParam());
  ASSERT_NE(factor, nullptr);
  if (GetParam() == "g2o_se3") {
    // Its poses are sampled as g2o's six-digit files hold them, quaternions
    // of norm 1 ± 1e-6, off the manifold, where the invariants hold to that
    // order only; `between` checks the same manifold at unit quaternions.
    GTEST_SKIP() << "quaternions off the unit sphere by 1e-6 (between checks this manifold)";
  }
  Samples samples = Read(GetParam());
  std::mt19937 random(29);
  std::uniform_real_distribution<double> step(-0.3, 0.3);
  const size_t count = samples.configurations.size();
  for (size_t c = 0; c < count; ++c) {
    std::vector<double> constants;
    std::vector<int> variables;
    Split(samples, samples.configurations[c], &constants, &variables);
    std::vector<int> next_variables;
    std::vector<double> unused;
    Split(samples, samples.configurations[(c + 1) % count], &unused, &next_variables);
    for (size_t k = 0; k < variables.size(); ++k) {
      std::unique_ptr<ceres::Manifold> manifold(factor->new_manifold(static_cast<int>(k)));
      if (manifold == nullptr) continue;  // Euclidean
      const int n = manifold->AmbientSize();
      const ceres::Manifold& m = *manifold;
      ceres::Vector x(n), y(n), delta(m.TangentSize());
      for (int i = 0; i < n; ++i) {
        x[i] = samples.configurations[c][variables[k] + i];
        y[i] = samples.configurations[(c + 1) % count][next_variables[k] + i];
      }
      for (int i = 0; i < m.TangentSize(); ++i) delta[i] = step(random);
      // The macro names Ceres' matchers and `Vector` unqualified.
      using namespace ceres;  // NOLINT
      EXPECT_THAT_MANIFOLD_INVARIANTS_HOLD(m, x, delta, y, kInvariantTolerance);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    Generated, Factors,
    testing::Values("point_reprojection", "line_reprojection", "plucker_line_reprojection",
                    "plane", "line_observation", "free_line", "snavely_reprojection",
                    "stereo_reprojection", "between", "g2o_se3", "relative_pose",
                    "point_to_plane", "scaled_range_bearing", "direction", "relative_sim3"));

// The point factor's Jacobian in its own tangent (left, [δω, δρ]) padded
// with a zero column to the pose's 7 stored scalars.
class Padded final : public ceres::SizedCostFunction<2, 7, 3> {
 public:
  explicit Padded(const double* constants) : constants_(constants, constants + 6) {}
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    double d_pose[12], d_point[6];
    factor_generated::point_reprojection<double>(
        constants_.data(), constants_.data() + 4, parameters[0], parameters[1], residuals,
        d_pose, d_point);
    if (jacobians != nullptr && jacobians[0] != nullptr)
      for (int r = 0; r < 2; ++r)
        for (int c = 0; c < 7; ++c) jacobians[0][7 * r + c] = c < 6 ? d_pose[6 * r + c] : 0.0;
    if (jacobians != nullptr && jacobians[1] != nullptr)
      for (int k = 0; k < 6; ++k) jacobians[1][k] = d_point[k];
    return true;
  }

 private:
  std::vector<double> constants_;
};

// The factor's own retraction with an identity-block PlusJacobian.
class IdentityBlock final : public ceres::Manifold {
 public:
  int AmbientSize() const override { return 7; }
  int TangentSize() const override { return 6; }
  bool Plus(const double* x, const double* delta, double* out) const override {
    factor_generated::se3_left_retract<double>(x, delta, out);
    return true;
  }
  bool PlusJacobian(const double*, double* jacobian) const override {
    for (int r = 0; r < 7; ++r)
      for (int c = 0; c < 6; ++c) jacobian[6 * r + c] = r == c ? 1.0 : 0.0;
    return true;
  }
  bool Minus(const double* y, const double* x, double* delta) const override {
    factor_generated::se3_left_local<double>(x, y, delta);
    return true;
  }
  bool MinusJacobian(const double*, double* jacobian) const override {
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < 7; ++c) jacobian[7 * r + c] = r == c ? 1.0 : 0.0;
    return true;
  }
};

TEST(Pitfall, AnIdentityBlockPlusJacobianFailsTheChecker) {
  Samples samples = Read("point_reprojection");
  int failed = 0;
  double smallest = 1e300;
  for (std::vector<double>& stored : samples.configurations) {
    Padded cost(stored.data());
    IdentityBlock manifold;
    std::vector<const ceres::Manifold*> manifolds = {&manifold, nullptr};
    double* parameters[2] = {stored.data() + 6, stored.data() + 13};
    ceres::GradientChecker checker(&cost, &manifolds, Ridders());
    ceres::GradientChecker::ProbeResults results;
    if (!checker.Probe(parameters, kPrecision, &results)) ++failed;
    smallest = std::min(smallest, results.maximum_relative_error);
  }
  std::printf("pitfall: identity-block PlusJacobian fails the checker at %d of %zu "
              "configurations (smallest of the largest relative errors %.2e)\n",
              failed, samples.configurations.size(), smallest);
  EXPECT_EQ(failed, static_cast<int>(samples.configurations.size()));
}

}  // namespace

int main(int argc, char** argv) {
  google::InitGoogleLogging(argv[0]);
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
