// The least-squares angle -> UV reconstruction against the floor, on one corpus mesh at a chosen
// size: prints the floor (one CHOLMOD factorization of the cotangent Dirichlet system), LSCM and
// the reconstruction from the ABF target angles (abf_target_angles: the matrix has the same
// pattern and cost as for linear ABF's angles), each phase in seconds.
//
//   corpus_angle_reconstruction [MESH.obj|corpus name] [FACTOR]   (default: face 16)
#include <cstdio>
#include <cstdlib>
#include <string>

#include "abf/angle_reconstruction_least_squares.h"
#include "bench/bench_support.h"
#include "harmonia/abf.h"
#include "harmonia/angles_to_uv.h"
#include "harmonia/blas_threads.h"
#include "harmonia/io.h"
#include "harmonia/laplacian.h"
#include "harmonia/lscm.h"
#include "planar/map_pipeline.h"
#include "solve/uv_block_ordering.h"

namespace {

#ifdef HARMONIA_HAVE_CHOLMOD
// CHOLMOD's symbolic analysis of the symmetric `matrix` (lower triangle read) in `ordering`
// (empty: CHOLMOD's own): entries of the factor and flops of the factorization. Independent of
// the machine's load, unlike the timings.
void print_symbolic(const char* what, Eigen::SparseMatrix<double> matrix,
                    std::vector<int> ordering) {
  cholmod_common common;
  cholmod_start(&common);
  common.supernodal = CHOLMOD_SUPERNODAL;
  cholmod_sparse view{};
  view.nrow = view.ncol = static_cast<std::size_t>(matrix.rows());
  view.nzmax = static_cast<std::size_t>(matrix.nonZeros());
  view.p = matrix.outerIndexPtr();
  view.i = matrix.innerIndexPtr();
  view.x = matrix.valuePtr();
  view.stype = -1;
  view.itype = CHOLMOD_INT;
  view.xtype = CHOLMOD_REAL;
  view.dtype = CHOLMOD_DOUBLE;
  view.sorted = view.packed = 1;
  if (!ordering.empty()) {
    common.nmethods = 1;
    common.method[0].ordering = CHOLMOD_GIVEN;
  }
  cholmod_factor* factor = cholmod_analyze_p(&view, ordering.empty() ? nullptr : ordering.data(),
                                             nullptr, 0, &common);
  std::printf("%-34s factor entries %.3e, flops %.3e\n", what, common.lnz, common.fl);
  cholmod_free_factor(&factor, &common);
  cholmod_finish(&common);
}
#endif

void print_report(const char* what, const harmonia::SolveReport& report) {
  std::printf("%-16s %-8s total %7.3f s |", what, report.ok() ? "ok" : "FAILED",
              report.total_seconds());
  for (const harmonia::PhaseTiming& timing : report.timings)
    std::printf(" %s %.3f", timing.phase.c_str(), timing.seconds);
  std::printf("\n");
  std::printf("  solver: %s\n", report.solver.c_str());
  if (!report.ok()) std::printf("  %s\n", report.message.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  // As the harmonia program: two halves of a large system may be factorized side by side, with
  // OpenBLAS held to one thread per call (harmonia/blas_threads.h).
  harmonia::set_blas_thread_policy(harmonia::BlasThreadPolicy::hold_during_split_factorizations);
  namespace fs = std::filesystem;
  const std::string name = argc > 1 ? argv[1] : "face";
  const int factor = argc > 2 ? std::atoi(argv[2]) : 16;
  const fs::path base = fs::exists(name) ? fs::path(name)
                                         : harmonia::bench::shared_data_dir() / "disk" /
                                               (name + ".obj");
  std::string message;
  const auto path = harmonia::bench::scaled_mesh(base, factor, &message);
  if (!path) {
    std::printf("%s\n", message.c_str());
    return 1;
  }
  const harmonia::Mesh mesh = harmonia::read_mesh(*path);
  std::printf("%s: %d vertices, %d faces\n", path->filename().c_str(), mesh.vertex_count(),
              mesh.face_count());

  const harmonia::bench::FloorMeasurement floor = harmonia::bench::measure_floor(
      harmonia::bench::dirichlet_system(mesh, harmonia::laplacian(
                                                  mesh, harmonia::WeightScheme::cotangent)));
  std::printf("%-16s %-8s total %7.3f s | analysis %.3f factorization %.3f solve %.3f\n", "floor",
              floor.available ? "ok" : "FAILED", floor.total_seconds(), floor.analyze_seconds,
              floor.factorize_seconds, floor.solve_seconds);

  harmonia::LscmOptions lscm_options;
  lscm_options.solver.backend = harmonia::BackendChoice::cpu;
  print_report("lscm", harmonia::lscm(mesh, lscm_options).report);

  const Eigen::MatrixX3d angles = harmonia::abf_target_angles(mesh);
#ifdef HARMONIA_HAVE_CHOLMOD
  {  // Symbolic cost of the reconstruction's system in three orderings, and of the floor's.
    const int vertex_count = mesh.vertex_count();
    const Eigen::SparseMatrix<double> form =
        harmonia::detail::sine_law_conformal_form(mesh, angles);
    const std::vector<int> vertex_ordering =
        harmonia::detail::operator_pattern(mesh).vertex_ordering;
    std::vector<int> interleaved, blocks;
    for (const int v : vertex_ordering) {
      interleaved.push_back(v);
      interleaved.push_back(vertex_count + v);
      blocks.push_back(v);
    }
    for (const int v : vertex_ordering) blocks.push_back(vertex_count + v);
    // Pins left in (one similarity's worth of singularity does not change the pattern's cost).
    print_symbolic("reconstruction, interleaved", form, interleaved);
    print_symbolic("reconstruction, [u; v] vertex order", form, blocks);
    print_symbolic("reconstruction, CHOLMOD's ordering", form, {});
    {
      const std::vector<int> nested =
          harmonia::detail::operator_pattern(mesh, true).vertex_ordering;
      std::vector<int> nested_blocks(nested);
      for (const int v : nested) nested_blocks.push_back(vertex_count + v);
      print_symbolic("reconstruction, [u; v] nested dissection", form, nested_blocks);
      std::vector<int> free_index(2 * vertex_count);
      for (int i = 0; i < 2 * vertex_count; ++i) free_index[i] = i;
      print_symbolic("reconstruction, [u; v; boundary v] nested dissection", form,
                     harmonia::detail::uv_block_ordering(nested, free_index, form));
    }
    // The unweighted equations' pattern: a full 2 x 2 block on every mesh edge, interleaved.
    const Eigen::SparseMatrix<double> adjacency = harmonia::detail::operator_pattern(mesh).pattern;
    std::vector<Eigen::Triplet<double>> entries;
    for (int column = 0; column < adjacency.outerSize(); ++column)
      for (Eigen::SparseMatrix<double>::InnerIterator entry(adjacency, column); entry; ++entry)
        for (int a = 0; a < 2; ++a)
          for (int b = 0; b < 2; ++b)
            entries.emplace_back(2 * static_cast<int>(entry.row()) + a, 2 * column + b, 1.0);
    Eigen::SparseMatrix<double> blocked(2 * vertex_count, 2 * vertex_count);
    blocked.setFromTriplets(entries.begin(), entries.end());
    std::vector<int> pairs;
    for (const int v : vertex_ordering) {
      pairs.push_back(2 * v);
      pairs.push_back(2 * v + 1);
    }
    print_symbolic("unweighted 2x2-block pattern", blocked, pairs);
    print_symbolic("floor (Dirichlet, CHOLMOD's ordering)",
                   harmonia::bench::dirichlet_system(
                       mesh, harmonia::laplacian(mesh, harmonia::WeightScheme::cotangent))
                       .interior_matrix,
                   {});
  }
#endif
  harmonia::AnglesToUvOptions options;
  options.solver.backend = harmonia::BackendChoice::cpu;
  const harmonia::MapResult reconstruction = harmonia::angles_to_uv(mesh, angles, options);
  print_report("angles_to_uv", reconstruction.report);
  std::printf("flips %d, boundary self-intersections %d, residual %.2e\n",
              reconstruction.report.flipped_triangles,
              reconstruction.report.boundary_self_intersections, reconstruction.report.residual);
  if (floor.available)
    std::printf("angles_to_uv: %.2f x the floor\n",
                reconstruction.report.total_seconds() / floor.total_seconds());
  return 0;
}
