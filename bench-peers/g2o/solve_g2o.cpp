// Solves a g2o graph with g2o's own Levenberg–Marquardt and prints one JSON
// object: the χ² before and after (total and per edge tag), the iterations
// g2o ran until it stopped by itself, and the time of the optimisation.
//
//   solve_g2o GRAPH [--max-iterations N] [--estimates FILE]
//
// GRAPH is loaded with SparseOptimizer::load, which fixes the vertices of its
// FIX lines; LM with the sparse Cholesky of Eigen (LinearSolverEigen) under a
// variable-size block solver runs until it stops by itself (ten rejected
// steps in a row or no change of χ²), at most N iterations (default 10000).
// --estimates writes the optimised vertices as g2o records with 17
// significant digits (g2o's own save writes 6).
//
// This file is this project's (bench-peers/g2o/run.sh builds it against the
// g2opy wheel's headers and static libraries); it is not g2o code.

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "g2o/core/block_solver.h"
#include "g2o/core/factory.h"
#include "g2o/core/optimization_algorithm_levenberg.h"
#include "g2o/core/sparse_optimizer.h"
#include "g2o/solvers/eigen/linear_solver_eigen.h"

// In a static executable the types' registration objects are dropped unless
// something refers to them: without these, load() reads nothing.
G2O_USE_TYPE_GROUP(slam3d);
G2O_USE_TYPE_GROUP(slam3d_addons);

namespace {

using Clock = std::chrono::steady_clock;

[[noreturn]] void usage(const std::string& what) {
  std::cerr << "error: " << what << "\n"
            << "usage: solve_g2o GRAPH [--max-iterations N] [--estimates FILE]\n";
  std::exit(2);
}

// χ² of the active edges, total and per tag (Σ eᵀ Ω e, no ½).
std::map<std::string, double> chi2_by_tag(const g2o::SparseOptimizer& graph) {
  std::map<std::string, double> sums;
  const g2o::Factory* factory = g2o::Factory::instance();
  for (const auto& e : graph.activeEdges()) {
    sums[factory->tag(e.get())] += e->chi2();
  }
  return sums;
}

std::string json_string(const std::string& s) {
  std::ostringstream out;
  out << '"';
  for (char c : s) {
    if (c == '"' || c == '\\') {
      out << '\\' << c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      out << "\\u" << std::hex << std::setw(4) << std::setfill('0')
          << static_cast<int>(c) << std::dec;
    } else {
      out << c;
    }
  }
  out << '"';
  return out.str();
}

void print_chi2(std::ostream& out, const std::map<std::string, double>& by_tag) {
  out << "{";
  bool first = true;
  for (const auto& [tag, value] : by_tag) {
    out << (first ? "" : ", ") << json_string(tag) << ": " << value;
    first = false;
  }
  out << "}";
}

double total(const std::map<std::string, double>& by_tag) {
  double sum = 0;
  for (const auto& entry : by_tag) sum += entry.second;
  return sum;
}

bool write_estimates(const g2o::SparseOptimizer& graph, const std::string& path) {
  std::ofstream out(path);
  if (!out) return false;
  out << std::setprecision(17);
  const g2o::Factory* factory = g2o::Factory::instance();
  std::map<int, const g2o::OptimizableGraph::Vertex*> by_id;
  for (const auto& [id, v] : graph.vertices()) {
    by_id[id] = static_cast<const g2o::OptimizableGraph::Vertex*>(v.get());
  }
  std::vector<int> fixed;
  for (const auto& [id, v] : by_id) {
    std::vector<double> estimate;
    if (!v->getEstimateData(estimate)) return false;
    out << factory->tag(v) << ' ' << id;
    for (double x : estimate) out << ' ' << x;
    out << '\n';
    if (v->fixed()) fixed.push_back(id);
  }
  if (!fixed.empty()) {
    out << "FIX";
    for (int id : fixed) out << ' ' << id;
    out << '\n';
  }
  return static_cast<bool>(out);
}

}  // namespace

int main(int argc, char** argv) {
  std::string graph_path;
  std::string estimates_path;
  int max_iterations = 10000;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--max-iterations" && i + 1 < argc) {
      max_iterations = std::atoi(argv[++i]);
      if (max_iterations <= 0) usage("--max-iterations takes a positive integer");
    } else if (arg == "--estimates" && i + 1 < argc) {
      estimates_path = argv[++i];
    } else if (!arg.empty() && arg[0] == '-') {
      usage("unknown option " + arg);
    } else if (graph_path.empty()) {
      graph_path = arg;
    } else {
      usage("more than one graph given");
    }
  }
  if (graph_path.empty()) usage("no graph given");

  g2o::SparseOptimizer graph;
  using BlockSolver = g2o::BlockSolverX;
  auto linear = std::make_unique<g2o::LinearSolverEigen<BlockSolver::PoseMatrixType>>();
  graph.setAlgorithm(std::make_shared<g2o::OptimizationAlgorithmLevenberg>(
      std::make_unique<BlockSolver>(std::move(linear))));

  std::ifstream in(graph_path);
  if (!in || !graph.load(in)) {
    std::cerr << "error: " << graph_path << ": cannot load\n";
    return 2;
  }
  if (graph.vertices().empty() || graph.edges().empty()) {
    std::cerr << "error: " << graph_path
              << ": no vertices or edges read (unknown types?)\n";
    return 2;
  }
  int fixed = 0;
  for (const auto& [id, v] : graph.vertices()) {
    fixed += static_cast<const g2o::OptimizableGraph::Vertex*>(v.get())->fixed();
  }

  graph.initializeOptimization();
  graph.computeActiveErrors();
  const auto initial = chi2_by_tag(graph);

  const auto start = Clock::now();
  const int iterations = graph.optimize(max_iterations);
  const double seconds =
      std::chrono::duration<double>(Clock::now() - start).count();

  graph.computeActiveErrors();
  const auto final_chi2 = chi2_by_tag(graph);

  if (!estimates_path.empty() && !write_estimates(graph, estimates_path)) {
    std::cerr << "error: " << estimates_path << ": cannot write\n";
    return 1;
  }

  std::cout << std::setprecision(17) << "{\"graph\": " << json_string(graph_path)
            << ", \"vertices\": " << graph.vertices().size()
            << ", \"fixed\": " << fixed << ", \"edges\": " << graph.edges().size()
            << ", \"active_edges\": " << graph.activeEdges().size()
            << ", \"initial_chi2\": " << total(initial)
            << ", \"final_chi2\": " << total(final_chi2)
            << ", \"iterations\": " << iterations
            << ", \"max_iterations\": " << max_iterations
            << ", \"seconds\": " << seconds << ", \"initial_chi2_by_tag\": ";
  print_chi2(std::cout, initial);
  std::cout << ", \"final_chi2_by_tag\": ";
  print_chi2(std::cout, final_chi2);
  std::cout << "}\n";
  return iterations < 0 ? 1 : 0;
}
