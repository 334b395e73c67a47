// Iterations and time per solve of the conjugate gradients, preconditioned by the diagonal
// (Jacobi) and by the smoothed-aggregation V-cycle (backend/aggregation_hierarchy.h), on the
// Dirichlet system of the fixed-boundary cotangent map (thesis eq. 6.1, boundary on a circle) of
// corpus disks and their subdivisions, beside one CHOLMOD factorization of the same matrix.
//
//   corpus_multilevel_benchmark [--backend cpu|vulkan|both] [--tolerance 1e-8]
//                               [--jacobi-cap N] [--out-md FILE] [--out-json FILE] [mesh[:factor]...]
//
// Default meshes: camel_b, face, face x4, face x16. On the Vulkan backend (lavapipe here) every
// solve is fp32 on the device refined in double, so its iterations add up the refinement rounds.
// The hierarchy's set-up (aggregation and Galerkin products on the host) is timed against the
// CHOLMOD analysis and factorization; the solution is compared with the direct one.

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "backend/aggregation_hierarchy.h"
#include "backend/backend.h"
#include "bench/bench_support.h"
#include "fallback/cpu_backend.h"
#include "fallback/direct_solvers.h"
#include "harmonia/boundary.h"
#include "harmonia/io.h"
#include "harmonia/laplacian.h"
#include "harmonia/topology.h"
#include "solve/backend_selection.h"

namespace {

using harmonia::detail::Backend;
using Clock = std::chrono::steady_clock;
using Sparse = Eigen::SparseMatrix<double>;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

struct DirichletProblem {
  Sparse matrix;       // L_II.
  Eigen::MatrixXd rhs;  // -L_IB X_B, two columns.
};

DirichletProblem circle_dirichlet_problem(const harmonia::Mesh& mesh) {
  const auto loops = harmonia::boundary_loops(mesh);
  std::size_t longest = 0;
  for (std::size_t k = 1; k < loops.size(); ++k)
    if (loops[k].size() > loops[longest].size()) longest = k;
  const harmonia::BoundaryPlacement boundary =
      harmonia::place_boundary(mesh, loops.at(longest), harmonia::BoundaryOptions{});
  const Sparse laplacian = harmonia::laplacian(mesh, harmonia::WeightScheme::cotangent);
  const Eigen::Index n = laplacian.rows();
  std::vector<int> free_index(static_cast<std::size_t>(n), 0);
  for (Eigen::Index k = 0; k < boundary.vertices.size(); ++k) free_index[boundary.vertices[k]] = -1;
  int free_count = 0;
  for (auto& index : free_index)
    if (index == 0) index = free_count++;
  Eigen::MatrixXd fixed = Eigen::MatrixXd::Zero(n, 2);
  for (Eigen::Index k = 0; k < boundary.vertices.size(); ++k)
    fixed.row(boundary.vertices[k]) = boundary.uv.row(k);
  std::vector<Eigen::Triplet<double>> entries;
  DirichletProblem problem;
  problem.rhs = Eigen::MatrixXd::Zero(free_count, 2);
  for (Eigen::Index column = 0; column < laplacian.outerSize(); ++column)
    for (Sparse::InnerIterator it(laplacian, column); it; ++it) {
      const int row = free_index[it.row()];
      if (row < 0) continue;
      const int col = free_index[it.col()];
      if (col >= 0)
        entries.emplace_back(row, col, it.value());
      else
        problem.rhs.row(row) -= it.value() * fixed.row(it.col());
    }
  problem.matrix.resize(free_count, free_count);
  problem.matrix.setFromTriplets(entries.begin(), entries.end());
  problem.matrix.makeCompressed();
  return problem;
}

struct SolveFigures {
  int iterations = 0;
  double seconds = 0.0;
  double relative_residual = 0.0;
  double error = 0.0;  // max |x - x_direct| / max |x_direct|.
  std::string status;
};

SolveFigures run_pcg(Backend& backend, const DirichletProblem& problem,
                     harmonia::detail::Preconditioner* preconditioner,
                     const harmonia::detail::IterativeSettings& settings,
                     const Eigen::MatrixXd& direct) {
  harmonia::detail::RowMajorSparse row_major(problem.matrix);
  row_major.makeCompressed();
  const auto a = backend.upload(row_major);
  const auto b = backend.upload(problem.rhs);
  const auto x = backend.allocate(static_cast<int>(problem.rhs.rows()), 2);
  const auto start = Clock::now();
  const harmonia::detail::SolveStats stats =
      preconditioner != nullptr
          ? backend.preconditioned_pcg(*a, *preconditioner, *b, *x, settings, {})
          : backend.pcg(*a, *b, *x, settings, {});
  SolveFigures figures;
  figures.seconds = seconds_since(start);
  figures.iterations = stats.iterations;
  figures.relative_residual = stats.relative_residual;
  figures.status = stats.status == harmonia::Status::ok ? "ok" : stats.message;
  figures.error = (x->download() - direct).cwiseAbs().maxCoeff() / direct.cwiseAbs().maxCoeff();
  return figures;
}

nlohmann::json to_json(const SolveFigures& f) {
  return {{"iterations", f.iterations},
          {"seconds", f.seconds},
          {"relative_residual", f.relative_residual},
          {"error", f.error},
          {"status", f.status}};
}

}  // namespace

int main(int argc, char** argv) {
  std::string backend_choice = "both", out_md, out_json;
  double tolerance = 1e-8;
  int jacobi_cap = 20000;
  std::vector<std::string> requested;
  for (int k = 1; k < argc; ++k) {
    const std::string argument = argv[k];
    const auto value = [&]() -> std::string {
      if (k + 1 >= argc) {
        std::cerr << argument << " needs a value\n";
        std::exit(2);
      }
      return argv[++k];
    };
    if (argument == "--backend") backend_choice = value();
    else if (argument == "--tolerance") tolerance = std::stod(value());
    else if (argument == "--jacobi-cap") jacobi_cap = std::stoi(value());
    else if (argument == "--out-md") out_md = value();
    else if (argument == "--out-json") out_json = value();
    else requested.push_back(argument);
  }
  if (requested.empty()) requested = {"camel_b", "face", "face:4", "face:16"};

  std::vector<std::pair<std::string, std::unique_ptr<Backend>>> backends;
  if (backend_choice == "cpu" || backend_choice == "both")
    backends.emplace_back("cpu", std::make_unique<harmonia::detail::CpuBackend>());
  if (backend_choice == "vulkan" || backend_choice == "both") {
    std::string message;
    auto vulkan = harmonia::detail::make_backend(harmonia::BackendChoice::vulkan, &message);
    if (vulkan)
      backends.emplace_back("vulkan", std::move(vulkan));
    else
      std::cerr << "no Vulkan backend: " << message << "\n";
  }

  nlohmann::json report = nlohmann::json::array();
  std::string table =
      "| mesh | rows | backend | levels (rows) | set-up s | CHOLMOD s | Jacobi it. | Jacobi s | "
      "multilevel it. | multilevel s | error |\n|---|---:|---|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const std::string& name : requested) {
    const auto colon = name.find(':');
    const std::string stem = name.substr(0, colon);
    const int factor = colon == std::string::npos ? 1 : std::stoi(name.substr(colon + 1));
    std::string message;
    const auto path =
        harmonia::bench::scaled_mesh(harmonia::bench::shared_data_dir() / "disk" / (stem + ".obj"),
                                     factor, &message);
    if (!path) {
      std::cerr << message << "\n";
      return 1;
    }
    const harmonia::Mesh mesh = harmonia::read_mesh(*path);
    const DirichletProblem problem = circle_dirichlet_problem(mesh);

    auto start = Clock::now();
    const auto cholesky = harmonia::detail::make_cholesky_solver();
    cholesky->analyze(problem.matrix);
    (void)cholesky->factorize(problem.matrix);
    const double cholmod_seconds = seconds_since(start);
    Eigen::MatrixXd direct;
    (void)cholesky->solve(problem.rhs, direct);

    start = Clock::now();
    const harmonia::detail::AggregationHierarchy hierarchy(problem.matrix);
    const double setup_seconds = seconds_since(start);
    std::string levels;
    for (const int rows : hierarchy.level_rows())
      levels += (levels.empty() ? "" : ", ") + std::to_string(rows);

    for (auto& [backend_name, backend] : backends) {
      harmonia::detail::IterativeSettings settings;
      settings.relative_tolerance = tolerance;
      settings.max_iterations = jacobi_cap;
      const SolveFigures jacobi = run_pcg(*backend, problem, nullptr, settings, direct);
      const auto preconditioner = backend->multilevel_preconditioner(hierarchy);
      settings.max_iterations = 20000;
      const SolveFigures multilevel =
          run_pcg(*backend, problem, preconditioner.get(), settings, direct);
      char line[512];
      std::snprintf(line, sizeof line,
                    "| %s | %ld | %s | %zu (%s) | %.3f | %.3f | %d%s | %.3f | %d%s | %.3f | %.1e |\n",
                    name.c_str(), static_cast<long>(problem.matrix.rows()), backend_name.c_str(),
                    hierarchy.level_rows().size(), levels.c_str(), setup_seconds,
                    cholmod_seconds, jacobi.iterations, jacobi.status == "ok" ? "" : " (stopped)",
                    jacobi.seconds, multilevel.iterations,
                    multilevel.status == "ok" ? "" : " (stopped)", multilevel.seconds,
                    multilevel.error);
      table += line;
      std::cout << line << std::flush;
      report.push_back({{"mesh", name},
                        {"rows", problem.matrix.rows()},
                        {"backend", backend->description()},
                        {"levels", hierarchy.level_rows()},
                        {"operator_complexity", hierarchy.operator_complexity()},
                        {"setup_seconds", setup_seconds},
                        {"cholmod_seconds", cholmod_seconds},
                        {"tolerance", tolerance},
                        {"jacobi", to_json(jacobi)},
                        {"multilevel", to_json(multilevel)}});
    }
  }
  if (!out_md.empty()) std::ofstream(out_md) << table;
  if (!out_json.empty()) std::ofstream(out_json) << report.dump(2) << "\n";
  return 0;
}
