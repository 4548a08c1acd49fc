// A problem file (`ceres-host-export problem FILE.json OUT` turned it into
// text) solved by Ceres with the generated cost functions and manifolds:
//
//   problem FILE [--threads N] [--max-iterations N] [--tolerance T]
//
// - every factor its generated cost function (`FromConstants`), whitened by
//   its noise model's square root information (`SetSqrtInformation`), the
//   cost `½ Σ ‖S r‖²` that `slamjac solve` minimises;
// - every variable one parameter block of its stored scalars, with the
//   manifold in the chart of the first factor that uses it (`NewManifold`);
//   fixed variables held constant;
// - Levenberg–Marquardt, SPARSE_SCHUR (Ceres' own elimination ordering),
//   SuiteSparse, the function, gradient and parameter tolerances `T`
//   (default 1e-12: run to the optimum) and at most N iterations (200).
//
// Prints one JSON line: the costs, iterations, Ceres' termination and times.
#include <ceres/ceres.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "factors.h"

namespace {

[[noreturn]] void Fail(const std::string& what) {
  std::cerr << "error: " << what << "\n";
  std::exit(2);
}

struct Variable {
  std::string name, type;
  bool fixed = false;
  std::vector<double> value;
};

struct FactorEntry {
  std::string factor;
  std::vector<int> variables;
  std::vector<double> constants, sqrt_information;
};

template <typename T>
std::vector<T> ReadN(std::istream& in, int n) {
  std::vector<T> values(n);
  for (T& v : values) in >> v;
  return values;
}

}  // namespace

int main(int argc, char** argv) {
  google::InitGoogleLogging(argv[0]);
  if (argc < 2) Fail("usage: problem FILE [--threads N] [--max-iterations N] [--tolerance T]");
  int threads = 1, max_iterations = 200;
  double tolerance = 1e-12;
  for (int i = 2; i < argc; ++i) {
    const std::string flag = argv[i];
    if (i + 1 >= argc) Fail(flag + " needs a value");
    const std::string value = argv[++i];
    if (flag == "--threads") threads = std::atoi(value.c_str());
    else if (flag == "--max-iterations") max_iterations = std::atoi(value.c_str());
    else if (flag == "--tolerance") tolerance = std::atof(value.c_str());
    else Fail("unknown argument " + flag);
  }
  std::ifstream in(argv[1]);
  std::string word;
  int version = 0, count = 0;
  in >> word >> version;
  if (word != "ceres-host-problem" || version != 1) Fail(std::string(argv[1]) + ": not an export");
  in >> word >> count;
  std::vector<Variable> variables(count);
  for (Variable& v : variables) {
    int n = 0;
    in >> v.name >> v.type >> v.fixed >> n;
    v.value = ReadN<double>(in, n);
  }
  in >> word >> count;
  std::vector<FactorEntry> factors(count);
  for (FactorEntry& f : factors) {
    int k = 0, c = 0, r = 0;
    in >> f.factor >> k;
    f.variables = ReadN<int>(in, k);
    in >> c;
    f.constants = ReadN<double>(in, c);
    in >> r;
    f.sqrt_information = ReadN<double>(in, r * r);
  }
  if (!in) Fail(std::string(argv[1]) + ": truncated");

  ceres::Problem problem;
  for (const FactorEntry& f : factors) {
    const ceres_host::Factor* factor = ceres_host::Find(f.factor);
    if (factor == nullptr) Fail("no generated cost function for " + f.factor);
    ceres::CostFunction* cost = factor->from_constants(f.constants.data());
    factor->whiten(cost, f.sqrt_information.data());
    std::vector<double*> blocks;
    for (int v : f.variables) blocks.push_back(variables[v].value.data());
    problem.AddResidualBlock(cost, nullptr, blocks);
    for (size_t k = 0; k < blocks.size(); ++k) {
      if (problem.GetManifold(blocks[k]) == nullptr) {
        ceres::Manifold* manifold = factor->new_manifold(static_cast<int>(k));
        if (manifold != nullptr) problem.SetManifold(blocks[k], manifold);
      }
    }
  }
  for (Variable& v : variables)
    if (v.fixed && problem.HasParameterBlock(v.value.data()))
      problem.SetParameterBlockConstant(v.value.data());

  ceres::Solver::Options options;
  options.linear_solver_type = ceres::SPARSE_SCHUR;
  options.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
  options.num_threads = threads;
  options.max_num_iterations = max_iterations;
  options.function_tolerance = tolerance;
  options.gradient_tolerance = tolerance;
  options.parameter_tolerance = tolerance;
  ceres::Solver::Summary summary;
  const auto start = std::chrono::steady_clock::now();
  ceres::Solve(options, &problem, &summary);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf(
      "{\"file\": \"%s\", \"variables\": %zu, \"factors\": %zu, \"initial_cost\": %.15e, "
      "\"final_cost\": %.15e, \"iterations\": %d, \"termination\": \"%s\", \"solve_s\": %.6f, "
      "\"jacobian_s\": %.6f}\n",
      argv[1], variables.size(), factors.size(), summary.initial_cost, summary.final_cost,
      summary.num_successful_steps + summary.num_unsuccessful_steps,
      ceres::TerminationTypeToString(summary.termination_type), seconds,
      summary.jacobian_evaluation_time_in_seconds);
  return summary.IsSolutionUsable() ? 0 : 1;
}
