// Every generated Ceres cost function of this project (generated/cpp) and of
// the example user crate (examples/user-factor/user-kernels/cpp), by the
// factor's name: how a program that reads factors by name (a problem file,
// a sample file) makes their cost functions and manifolds.
#ifndef CERES_HOST_FACTORS_H
#define CERES_HOST_FACTORS_H

#include <ceres/ceres.h>

#include <string>
#include <vector>

#include "factor_generated/ceres.h"
#include "user_kernels/ceres.h"

namespace ceres_host {

// A generated cost function class, type-erased.
struct Factor {
  std::string name;
  // `FromConstants`: the cost function from its constants' stored scalars.
  ceres::CostFunction* (*from_constants)(const double* constants);
  // `NewManifold`: block k's manifold (new), or null when Euclidean.
  ceres::Manifold* (*new_manifold)(int block);
  // `SetSqrtInformation` of a cost function `from_constants` made.
  void (*whiten)(ceres::CostFunction* cost, const double* sqrt_information);
};

template <typename Cost>
ceres::CostFunction* FromConstants(const double* constants) {
  return Cost::FromConstants(constants);
}

template <typename Cost>
void Whiten(ceres::CostFunction* cost, const double* sqrt_information) {
  static_cast<Cost*>(cost)->SetSqrtInformation(sqrt_information);
}

template <typename Cost>
Factor Entry(const std::string& name) {
  return Factor{name, &FromConstants<Cost>, &Cost::NewManifold, &Whiten<Cost>};
}

inline const std::vector<Factor>& Factors() {
  static const std::vector<Factor> factors = {
      Entry<factor_generated::PointReprojectionCost>("point_reprojection"),
      Entry<factor_generated::LineReprojectionCost>("line_reprojection"),
      Entry<factor_generated::PluckerLineReprojectionCost>("plucker_line_reprojection"),
      Entry<factor_generated::PlaneCost>("plane"),
      Entry<factor_generated::LineObservationCost>("line_observation"),
      Entry<factor_generated::FreeLineCost>("free_line"),
      Entry<factor_generated::SnavelyReprojectionCost>("snavely_reprojection"),
      Entry<factor_generated::StereoReprojectionCost>("stereo_reprojection"),
      Entry<factor_generated::BetweenCost>("between"),
      Entry<factor_generated::G2oSe3Cost>("g2o_se3"),
      Entry<user_kernels::RelativePoseCost>("relative_pose"),
      Entry<user_kernels::PointToPlaneCost>("point_to_plane"),
      Entry<user_kernels::ScaledRangeBearingCost>("scaled_range_bearing"),
      Entry<user_kernels::DirectionCost>("direction"),
      Entry<user_kernels::RelativeSim3Cost>("relative_sim3"),
  };
  return factors;
}

// The factor called `name`, or null.
inline const Factor* Find(const std::string& name) {
  for (const Factor& f : Factors())
    if (f.name == name) return &f;
  return nullptr;
}

}  // namespace ceres_host

#endif  // CERES_HOST_FACTORS_H
