// The BAL residual as AutoDiffCostFunction functors, for ba.cc and
// ../ceres_host/cost_speed.cc: predicted minus observed pixel with Snavely's
// model, P = R X + t, p = -P_xy / P_z (the camera looks down -z),
// pixel = f (1 + k1 |p|^2 + k2 |p|^4) p.
#ifndef CERES_BA_SNAVELY_FUNCTORS_H
#define CERES_BA_SNAVELY_FUNCTORS_H

#include <ceres/rotation.h>

// Over the 9-parameter camera [angle-axis, t, f, k1, k2].
struct Reprojection {
  Reprojection(double x, double y) : x(x), y(y) {}

  template <typename T>
  bool operator()(const T* camera, const T* point, T* residual) const {
    T p[3];
    ceres::AngleAxisRotatePoint(camera, point, p);
    for (int k = 0; k < 3; ++k) p[k] += camera[3 + k];
    // The camera looks down -z.
    const T u = -p[0] / p[2], v = -p[1] / p[2];
    const T rho2 = u * u + v * v;
    const T scale = camera[6] * (T(1.0) + rho2 * (camera[7] + camera[8] * rho2));
    residual[0] = scale * u - x;
    residual[1] = scale * v - y;
    return true;
  }

  double x, y;
};

// The same residual with the camera as a pose [qx, qy, qz, qw, tx, ty, tz]
// and intrinsics [f, k1, k2] (the generated cost function's blocks).
struct QuaternionReprojection {
  QuaternionReprojection(double x, double y) : x(x), y(y) {}

  template <typename T>
  bool operator()(const T* pose, const T* intrinsics, const T* point,
                  T* residual) const {
    // Ceres' quaternions are [w, x, y, z].
    const T q[4] = {pose[3], pose[0], pose[1], pose[2]};
    T p[3];
    ceres::UnitQuaternionRotatePoint(q, point, p);
    for (int k = 0; k < 3; ++k) p[k] += pose[4 + k];
    const T u = -p[0] / p[2], v = -p[1] / p[2];
    const T rho2 = u * u + v * v;
    const T scale =
        intrinsics[0] * (T(1.0) + rho2 * (intrinsics[1] + intrinsics[2] * rho2));
    residual[0] = scale * u - x;
    residual[1] = scale * v - y;
    return true;
  }

  double x, y;
};

#endif  // CERES_BA_SNAVELY_FUNCTORS_H
