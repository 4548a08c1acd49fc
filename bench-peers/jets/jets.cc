// Ceres 2.1's automatic differentiation (Jets) on the residuals this
// project's dual numbers are compared with, for bench-peers/jets/run.sh.
//
//   jets SAMPLES check OUT   write every residual and Jacobian block to OUT
//   jets SAMPLES time PASSES time PASSES passes over the samples per factor
//
// SAMPLES is written by the Rust side (`jets write`): the same
// configurations on both sides. Two residuals:
//
// - Snavely's reprojection (BAL), AutoDiffCostFunction<Snavely, 2, 9, 3>,
//   as bench-peers/ceres_ba/ba.cc writes it: camera [angle-axis, t, f, k1,
//   k2], point [X, Y, Z].
// - VINS-Mono's ProjectionFactor residual with an extrinsic and an inverse
//   depth, AutoDiffCostFunction<Projection, 2, 7, 7, 7, 1>: poses [p, q]
//   (q = [x, y, z, w], Eigen's order, as VINS-Mono stores them), body to
//   world; the extrinsic camera to body; the inverse depth.
//
// Timed: CostFunction::Evaluate with every Jacobian block requested, the
// cost functions built once (as a problem holds them). For the projection
// factor also Evaluate followed by what Ceres' evaluator does per residual
// block with a manifold on a parameter block: the ambient block (2 x 7)
// times the manifold's PlusJacobian (7 x 6), computed once per parameter
// block and pass. Prints one JSON line per factor: ns per evaluation, the
// minimum and the median over the passes.
#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace {

[[noreturn]] void Fail(const std::string& what) {
  std::cerr << "error: " << what << "\n";
  std::exit(2);
}

struct Snavely {
  Snavely(double x, double y) : x(x), y(y) {}
  template <typename T>
  bool operator()(const T* camera, const T* point, T* residual) const {
    T p[3];
    ceres::AngleAxisRotatePoint(camera, point, p);
    for (int k = 0; k < 3; ++k) p[k] += camera[3 + k];
    const T u = -p[0] / p[2], v = -p[1] / p[2];
    const T rho2 = u * u + v * v;
    const T scale = camera[6] * (T(1.0) + rho2 * (camera[7] + camera[8] * rho2));
    residual[0] = scale * u - x;
    residual[1] = scale * v - y;
    return true;
  }
  double x, y;
};

// VINS-Mono's ProjectionFactor::Evaluate, written for Jets.
struct Projection {
  Projection(const double* i, const double* j, double weight)
      : xi(i[0]), yi(i[1]), xj(j[0]), yj(j[1]), weight(weight) {}
  template <typename T>
  bool operator()(const T* pose_i, const T* pose_j, const T* extrinsic,
                  const T* inverse_depth, T* residual) const {
    using V = Eigen::Matrix<T, 3, 1>;
    using Q = Eigen::Quaternion<T>;
    const V pi(pose_i[0], pose_i[1], pose_i[2]);
    const Q qi(pose_i[6], pose_i[3], pose_i[4], pose_i[5]);
    const V pj(pose_j[0], pose_j[1], pose_j[2]);
    const Q qj(pose_j[6], pose_j[3], pose_j[4], pose_j[5]);
    const V tic(extrinsic[0], extrinsic[1], extrinsic[2]);
    const Q qic(extrinsic[6], extrinsic[3], extrinsic[4], extrinsic[5]);
    const V pts_camera_i = V(T(xi), T(yi), T(1.0)) / inverse_depth[0];
    const V pts_imu_i = qic * pts_camera_i + tic;
    const V pts_w = qi * pts_imu_i + pi;
    const V pts_imu_j = qj.inverse() * (pts_w - pj);
    const V pts_camera_j = qic.inverse() * (pts_imu_j - tic);
    residual[0] = (pts_camera_j.x() / pts_camera_j.z() - xj) * weight;
    residual[1] = (pts_camera_j.y() / pts_camera_j.z() - yj) * weight;
    return true;
  }
  double xi, yi, xj, yj, weight;
};

struct Samples {
  std::vector<double> cameras, points, observed;  // Snavely: 9, 3, 2 each
  std::vector<double> poses, depths, rays;        // projection: 3 x 7, 1, 5
};

Samples Read(const std::string& path) {
  std::ifstream in(path);
  if (!in) Fail(path + ": cannot open");
  Samples s;
  std::string name;
  size_t n = 0;
  auto read = [&](std::vector<double>& to, size_t count) {
    for (size_t k = 0; k < count; ++k) {
      double v;
      if (!(in >> v)) Fail(path + ": expected a number");
      to.push_back(v);
    }
  };
  if (!(in >> name >> n) || name != "snavely") Fail(path + ": expected `snavely N`");
  for (size_t k = 0; k < n; ++k) {
    read(s.cameras, 9);
    read(s.points, 3);
    read(s.observed, 2);
  }
  if (!(in >> name >> n) || name != "projection")
    Fail(path + ": expected `projection N`");
  for (size_t k = 0; k < n; ++k) {
    read(s.poses, 21);
    read(s.depths, 1);
    read(s.rays, 5);
  }
  return s;
}

using Clock = std::chrono::steady_clock;

// Minimum and median of `passes` timings of `pass` (ns per evaluation).
template <typename F>
void Time(const char* factor, const char* method, size_t n, int passes, F pass) {
  std::vector<double> ns;
  double sink = 0.0;
  for (int p = 0; p < passes; ++p) {
    const auto start = Clock::now();
    sink += pass();
    ns.push_back(std::chrono::duration<double, std::nano>(Clock::now() - start).count() / n);
  }
  std::sort(ns.begin(), ns.end());
  std::printf(
      "{\"factor\": \"%s\", \"method\": \"%s\", \"min_ns\": %.2f, \"median_ns\": %.2f, "
      "\"sink\": %.3e}\n",
      factor, method, ns.front(), ns[ns.size() / 2], sink);
}

// The PlusJacobian (7 x 6, row-major) of Ceres' product manifold
// EuclideanManifold<3> x EigenQuaternionManifold at a pose [p, q].
void PlusJacobian(const double* pose, double* out) {
  std::fill(out, out + 42, 0.0);
  for (int k = 0; k < 3; ++k) out[6 * k + k] = 1.0;
  ceres::EigenQuaternionManifold q;
  double jq[12];
  q.PlusJacobian(pose + 3, jq);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 3; ++c) out[6 * (3 + r) + 3 + c] = jq[3 * r + c];
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) Fail("usage: jets SAMPLES check OUT | jets SAMPLES time PASSES");
  const Samples s = Read(argv[1]);
  const std::string mode = argv[2];
  const size_t ns = s.observed.size() / 2, np = s.depths.size();

  std::vector<std::unique_ptr<ceres::CostFunction>> snavely, projection;
  for (size_t k = 0; k < ns; ++k)
    snavely.emplace_back(new ceres::AutoDiffCostFunction<Snavely, 2, 9, 3>(
        new Snavely(s.observed[2 * k], s.observed[2 * k + 1])));
  for (size_t k = 0; k < np; ++k)
    projection.emplace_back(new ceres::AutoDiffCostFunction<Projection, 2, 7, 7, 7, 1>(
        new Projection(&s.rays[5 * k], &s.rays[5 * k + 2], s.rays[5 * k + 4])));

  double r[2], jc[18], jp[6], ji[14], jj[14], je[14], jd[2];
  double* snavely_jacobians[] = {jc, jp};
  double* projection_jacobians[] = {ji, jj, je, jd};
  auto snavely_pass = [&] {
    double sum = 0.0;
    for (size_t k = 0; k < ns; ++k) {
      const double* parameters[] = {&s.cameras[9 * k], &s.points[3 * k]};
      snavely[k]->Evaluate(parameters, r, snavely_jacobians);
      sum += r[0] + jc[0] + jp[0];
    }
    return sum;
  };
  auto projection_parameters = [&](size_t k, const double** parameters) {
    for (int v = 0; v < 3; ++v) parameters[v] = &s.poses[21 * k + 7 * v];
    parameters[3] = &s.depths[k];
  };
  auto projection_pass = [&] {
    double sum = 0.0;
    for (size_t k = 0; k < np; ++k) {
      const double* parameters[4];
      projection_parameters(k, parameters);
      projection[k]->Evaluate(parameters, r, projection_jacobians);
      sum += r[0] + ji[0] + jj[0] + je[0] + jd[0];
    }
    return sum;
  };

  if (mode == "check") {
    std::ofstream out(argv[3]);
    out.precision(17);
    for (size_t k = 0; k < ns; ++k) {
      const double* parameters[] = {&s.cameras[9 * k], &s.points[3 * k]};
      snavely[k]->Evaluate(parameters, r, snavely_jacobians);
      out << "snavely";
      for (double v : r) out << ' ' << v;
      for (double v : jc) out << ' ' << v;
      for (double v : jp) out << ' ' << v;
      out << '\n';
    }
    for (size_t k = 0; k < np; ++k) {
      const double* parameters[4];
      projection_parameters(k, parameters);
      projection[k]->Evaluate(parameters, r, projection_jacobians);
      out << "projection";
      for (double v : r) out << ' ' << v;
      for (double* block : {ji, jj, je})
        for (int i = 0; i < 14; ++i) out << ' ' << block[i];
      for (double v : jd) out << ' ' << v;
      out << '\n';
    }
    return 0;
  }
  if (mode != "time") Fail("mode: check or time");
  const int passes = std::atoi(argv[3]);
  if (passes < 1) Fail("PASSES: a positive number");

  // Ceres' evaluator with a manifold on each pose: the PlusJacobians once
  // per parameter block and pass (3 per residual block here, each block
  // its own), then one 2x7 times 7x6 product per pose block.
  std::vector<double> plus(np * 3 * 42);
  double tangent[3][12];
  auto projection_manifold_pass = [&] {
    double sum = 0.0;
    for (size_t k = 0; k < np; ++k)
      for (int v = 0; v < 3; ++v) PlusJacobian(&s.poses[21 * k + 7 * v], &plus[42 * (3 * k + v)]);
    for (size_t k = 0; k < np; ++k) {
      const double* parameters[4];
      projection_parameters(k, parameters);
      projection[k]->Evaluate(parameters, r, projection_jacobians);
      const double* ambient[] = {ji, jj, je};
      for (int v = 0; v < 3; ++v) {
        const double* p = &plus[42 * (3 * k + v)];
        for (int row = 0; row < 2; ++row)
          for (int c = 0; c < 6; ++c) {
            double acc = 0.0;
            for (int i = 0; i < 7; ++i) acc += ambient[v][7 * row + i] * p[6 * i + c];
            tangent[v][6 * row + c] = acc;
          }
      }
      sum += r[0] + tangent[0][0] + tangent[1][0] + tangent[2][0] + jd[0];
    }
    return sum;
  };
  Time("snavely", "ceres_autodiff", ns, passes, snavely_pass);
  Time("projection", "ceres_autodiff", np, passes, projection_pass);
  Time("projection", "ceres_autodiff_with_manifolds", np, passes, projection_manifold_pass);
  return 0;
}
