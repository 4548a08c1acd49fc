// Bundle adjustment of a BAL or Bundler file with Ceres (SPARSE_SCHUR,
// SuiteSparse/CHOLMOD), set up as `slamjac solve` sets its problem up, for
// the side-by-side comparison of `docs/guide/performance.md`.
//
//   ba FILE [--threads N] [--max-iterations N] [--robust huber:D|cauchy:D]
//           [--gauge fixed|free] [--function-tolerance T] [--report]
//           [--cost autodiff|autodiff-quaternion|generated|constant]
//
// - `--cost autodiff` (the default): one parameter block of 9 per camera,
//   [angle-axis (3), translation (3), f, k1, k2] (world to camera,
//   P = R X + t), one of 3 per point, differentiated by Ceres'
//   AutoDiffCostFunction.
// - `--cost generated`: this project's generated cost function
//   (generated/cpp, `factor_generated::SnavelyReprojectionCost`): per camera
//   a pose block of 7, [qx, qy, qz, qw, tx, ty, tz], with its generated
//   manifold (`Se3RhoThetaRightManifold`: R <- R Exp(dθ), t <- t + R dρ), and
//   an intrinsics block [f, k1, k2]; one block of 3 per point.
// - `--cost autodiff-quaternion`: those blocks and manifold, the residual
//   differentiated by AutoDiffCostFunction: the same problem as `generated`,
//   differentiated otherwise.
// - `--cost constant`: those blocks and manifold with a cost function that
//   only writes the observation and constant Jacobians: what Ceres itself
//   spends on a residual block around its cost function (the solve means
//   nothing).
// - The residual of an observation: predicted minus observed pixel with
//   Snavely's model, p = -P_xy / P_z, pixel = f (1 + k1 |p|^2 + k2 |p|^4) p.
// - The gauge (`--gauge fixed`, the default): camera 0's pose (its first six
//   parameters, or its pose block) held constant, its intrinsics free, as
//   `slamjac solve` holds it. `--gauge free` leaves every camera free.
// - Levenberg-Marquardt, SPARSE_SCHUR with the points eliminated (ordering:
//   points first), SUITE_SPARSE (CHOLMOD), Ceres' default tolerances
//   (function 1e-6, parameter 1e-8, gradient 1e-10; `--function-tolerance`
//   sets the first: `slamjac solve` stops at a relative decrease of 1e-8)
//   and at most 100 iterations (`slamjac solve`'s default limit).
//
// Prints one JSON line: the costs (1/2 sum |r|^2, as `slamjac solve`
// reports them), iterations (steps tried, accepted or rejected), Ceres'
// termination, and the time to read the file and to solve (wall and CPU),
// with Ceres' own split of it (Jacobian evaluation, residual evaluation,
// linear solver: wall times) and the number of Jacobian evaluations.
#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include "factor_generated/ceres/snavely_reprojection.h"
#include "snavely_functors.h"

#include <chrono>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace {

struct Observation {
  int camera;
  int point;
  double x, y;
};

struct Problem {
  std::vector<double> cameras;  // 9 per camera
  std::vector<double> points;   // 3 per point
  std::vector<Observation> observations;
};

[[noreturn]] void Fail(const std::string& what) {
  std::cerr << "error: " << what << "\n";
  std::exit(2);
}

// The whole file, read at once.
std::string Slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) Fail(path + ": cannot open");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Numbers read one after the other from a buffer (whitespace separated).
class Numbers {
 public:
  Numbers(const std::string& path, const std::string& text)
      : path_(path), at_(text.c_str()) {}
  double Next() {
    char* end = nullptr;
    const double value = std::strtod(at_, &end);
    if (end == at_) Fail(path_ + ": expected a number");
    at_ = end;
    return value;
  }
  int NextIndex() { return static_cast<int>(Next()); }
  // Skips the rest of the current line.
  void SkipLine() {
    while (*at_ != '\0' && *at_ != '\n') ++at_;
  }

 private:
  std::string path_;
  const char* at_;
};

// BAL: counts, observations (camera, point, x, y), cameras (9 each), points.
Problem ReadBal(const std::string& path) {
  const std::string text = Slurp(path);
  Numbers in(path, text);
  Problem p;
  const int cameras = in.NextIndex(), points = in.NextIndex(),
            observations = in.NextIndex();
  p.observations.resize(observations);
  for (auto& o : p.observations) {
    o.camera = in.NextIndex();
    o.point = in.NextIndex();
    o.x = in.Next();
    o.y = in.Next();
    if (o.camera < 0 || o.camera >= cameras || o.point < 0 || o.point >= points)
      Fail(path + ": observation index out of range");
  }
  p.cameras.resize(9 * cameras);
  for (auto& v : p.cameras) v = in.Next();
  p.points.resize(3 * points);
  for (auto& v : p.points) v = in.Next();
  return p;
}

// Bundler v0.3: per camera f k1 k2, R (row-major, world to camera), t; per
// point its position, colour and views (camera, key, x, y).
Problem ReadBundler(const std::string& path) {
  const std::string text = Slurp(path);
  Numbers in(path, text);
  in.SkipLine();  // "# Bundle file v0.3"
  Problem p;
  const int cameras = in.NextIndex(), points = in.NextIndex();
  p.cameras.resize(9 * cameras);
  for (int c = 0; c < cameras; ++c) {
    double* camera = &p.cameras[9 * c];
    double intrinsics[3], rotation[9];
    for (double& v : intrinsics) v = in.Next();
    for (double& v : rotation) v = in.Next();
    // Ceres' matrices here are column-major; the file's rows are R's rows.
    double column_major[9];
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) column_major[3 * k + r] = rotation[3 * r + k];
    ceres::RotationMatrixToAngleAxis(column_major, camera);
    for (int k = 0; k < 3; ++k) camera[3 + k] = in.Next();
    for (int k = 0; k < 3; ++k) camera[6 + k] = intrinsics[k];
  }
  p.points.resize(3 * points);
  for (int j = 0; j < points; ++j) {
    for (int k = 0; k < 3; ++k) p.points[3 * j + k] = in.Next();
    for (int k = 0; k < 3; ++k) in.Next();  // colour
    const int views = in.NextIndex();
    for (int v = 0; v < views; ++v) {
      Observation o;
      o.camera = in.NextIndex();
      in.Next();  // feature key
      o.x = in.Next();
      o.y = in.Next();
      o.point = j;
      if (o.camera < 0 || o.camera >= cameras)
        Fail(path + ": view camera out of range");
      p.observations.push_back(o);
    }
  }
  return p;
}

// No arithmetic: the observation as the residual, constant Jacobians.
class ConstantCost final : public ceres::SizedCostFunction<2, 7, 3, 3> {
 public:
  ConstantCost(double x, double y) : x_(x), y_(y) {}
  bool Evaluate(double const* const*, double* residuals, double** jacobians) const override {
    residuals[0] = x_;
    residuals[1] = y_;
    const int sizes[3] = {14, 6, 6};
    for (int b = 0; jacobians != nullptr && b < 3; ++b)
      if (jacobians[b] != nullptr)
        for (int k = 0; k < sizes[b]; ++k) jacobians[b][k] = 1.0;
    return true;
  }

 private:
  double x_, y_;
};

// A camera's 9 BAL parameters as a pose [qx, qy, qz, qw, t] and intrinsics.
void SplitCamera(const double* camera, double* pose, double* intrinsics) {
  double q[4];  // [w, x, y, z]
  ceres::AngleAxisToQuaternion(camera, q);
  pose[0] = q[1];
  pose[1] = q[2];
  pose[2] = q[3];
  pose[3] = q[0];
  for (int k = 0; k < 3; ++k) pose[4 + k] = camera[3 + k];
  for (int k = 0; k < 3; ++k) intrinsics[k] = camera[6 + k];
}

bool EndsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() &&
         s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

// The process's CPU time (every thread's), in seconds: on a shared machine
// steadier than the wall time of a single-threaded solve.
double CpuSeconds() {
  timespec now;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since)
      .count();
}

}  // namespace

int main(int argc, char** argv) {
  google::InitGoogleLogging(argv[0]);
  if (argc < 2) {
    std::cerr << "usage: ba FILE [--threads N] [--max-iterations N] "
                 "[--robust huber:D|cauchy:D] [--gauge fixed|free] "
                 "[--function-tolerance T] [--report] "
                 "[--cost autodiff|autodiff-quaternion|generated|constant]\n";
    return 2;
  }
  const std::string path = argv[1];
  int threads = 1, max_iterations = 100;
  double function_tolerance = ceres::Solver::Options().function_tolerance;
  bool report = false, fixed_gauge = true;
  std::string robust, cost = "autodiff";
  for (int i = 2; i < argc; ++i) {
    const std::string flag = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) Fail(flag + " needs a value");
      return argv[++i];
    };
    if (flag == "--threads") threads = std::atoi(value().c_str());
    else if (flag == "--max-iterations") max_iterations = std::atoi(value().c_str());
    else if (flag == "--robust") robust = value();
    else if (flag == "--gauge") fixed_gauge = value() != "free";
    else if (flag == "--function-tolerance")
      function_tolerance = std::atof(value().c_str());
    else if (flag == "--report") report = true;
    else if (flag == "--cost") cost = value();
    else Fail("unknown argument " + flag);
  }

  const auto start = std::chrono::steady_clock::now();
  Problem data = EndsWith(path, ".out") ? ReadBundler(path) : ReadBal(path);
  const double read_seconds = Seconds(start);

  // One loss for every block, owned here.
  std::unique_ptr<ceres::LossFunction> loss;
  if (!robust.empty()) {
    const double delta = std::atof(robust.substr(robust.find(':') + 1).c_str());
    if (robust.rfind("huber:", 0) == 0) loss.reset(new ceres::HuberLoss(delta));
    else if (robust.rfind("cauchy:", 0) == 0) loss.reset(new ceres::CauchyLoss(delta));
    else Fail("--robust: huber:D or cauchy:D");
  }
  if (cost != "autodiff" && cost != "autodiff-quaternion" && cost != "generated" &&
      cost != "constant")
    Fail("--cost: autodiff, autodiff-quaternion, generated or constant");
  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  const int cameras = static_cast<int>(data.cameras.size() / 9);
  // The quaternion parametrization: per camera a pose and intrinsics block.
  std::vector<double> poses(7 * cameras), intrinsics(3 * cameras);
  factor_generated::Se3RhoThetaRightManifold pose_manifold;
  // The blocks each camera's parameters are in (one, or pose and intrinsics).
  std::vector<double*> camera_blocks;
  if (cost == "autodiff") {
    for (const Observation& o : data.observations) {
      problem.AddResidualBlock(
          new ceres::AutoDiffCostFunction<Reprojection, 2, 9, 3>(
              new Reprojection(o.x, o.y)),
          loss.get(), &data.cameras[9 * o.camera], &data.points[3 * o.point]);
    }
    if (fixed_gauge && cameras > 0 &&
        problem.HasParameterBlock(&data.cameras[0])) {
      problem.SetManifold(&data.cameras[0],
                          new ceres::SubsetManifold(9, {0, 1, 2, 3, 4, 5}));
    }
    for (int c = 0; c < cameras; ++c) camera_blocks.push_back(&data.cameras[9 * c]);
  } else {
    for (int c = 0; c < cameras; ++c) {
      SplitCamera(&data.cameras[9 * c], &poses[7 * c], &intrinsics[3 * c]);
      camera_blocks.push_back(&poses[7 * c]);
      camera_blocks.push_back(&intrinsics[3 * c]);
    }
    for (const Observation& o : data.observations) {
      const double observed[2] = {o.x, o.y};
      ceres::CostFunction* function;
      if (cost == "generated")
        function = new factor_generated::SnavelyReprojectionCost(observed);
      else if (cost == "constant")
        function = new ConstantCost(o.x, o.y);
      else
        function = new ceres::AutoDiffCostFunction<QuaternionReprojection, 2, 7, 3, 3>(
            new QuaternionReprojection(o.x, o.y));
      problem.AddResidualBlock(function, loss.get(), &poses[7 * o.camera],
                               &intrinsics[3 * o.camera], &data.points[3 * o.point]);
    }
    for (int c = 0; c < cameras; ++c)
      if (problem.HasParameterBlock(&poses[7 * c]))
        problem.SetManifold(&poses[7 * c], &pose_manifold);
    if (fixed_gauge && cameras > 0 && problem.HasParameterBlock(&poses[0]))
      problem.SetParameterBlockConstant(&poses[0]);
  }

  ceres::Solver::Options options;
  options.linear_solver_type = ceres::SPARSE_SCHUR;
  options.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
  options.num_threads = threads;
  options.max_num_iterations = max_iterations;
  options.function_tolerance = function_tolerance;
  options.minimizer_progress_to_stdout = report;
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  for (size_t j = 0; j < data.points.size() / 3; ++j)
    if (problem.HasParameterBlock(&data.points[3 * j]))
      ordering->AddElementToGroup(&data.points[3 * j], 0);
  for (double* block : camera_blocks)
    if (problem.HasParameterBlock(block)) ordering->AddElementToGroup(block, 1);
  options.linear_solver_ordering = ordering;

  ceres::Solver::Summary summary;
  const auto solve_start = std::chrono::steady_clock::now();
  const double cpu_start = CpuSeconds();
  ceres::Solve(options, &problem, &summary);
  const double solve_seconds = Seconds(solve_start);
  const double cpu_seconds = CpuSeconds() - cpu_start;
  if (report) std::cerr << summary.FullReport() << "\n";

  std::printf(
      "{\"file\": \"%s\", \"cost\": \"%s\", \"threads\": %d, \"cameras\": %d, \"points\": %zu, "
      "\"observations\": %zu, \"initial_cost\": %.15e, \"final_cost\": %.15e, "
      "\"iterations\": %d, \"termination\": \"%s\", \"read_s\": %.6f, "
      "\"solve_s\": %.6f, \"solve_cpu_s\": %.6f, \"linear_solver_s\": %.6f, \"jacobian_s\": %.6f, "
      "\"jacobian_evaluations\": %d, \"residual_s\": %.6f}\n",
      path.c_str(), cost.c_str(), threads, cameras, data.points.size() / 3,
      data.observations.size(), summary.initial_cost, summary.final_cost,
      summary.num_successful_steps + summary.num_unsuccessful_steps,
      ceres::TerminationTypeToString(summary.termination_type), read_seconds,
      solve_seconds, cpu_seconds, summary.linear_solver_time_in_seconds,
      summary.jacobian_evaluation_time_in_seconds, summary.num_jacobian_evaluations,
      summary.residual_evaluation_time_in_seconds);
  return summary.IsSolutionUsable() ? 0 : 1;
}
