// Deformation transfer from marker pairs (thesis 8.4, 8.5; harmonia/deformation_transfer.h).
//
// The pieces: the marker fields of each mesh (one Dirichlet system per mesh with the markers
// constrained, all k fields from one factorization), the correspondence (triangle_correspondence.h),
// the source's deformation gradients (deformation_gradients.h), and the target's Poisson
// reconstruction with the fragments' load of the editor (similarity_fragment_load.h) on a system
// with one vertex held, factorized once.

#include "harmonia/deformation_transfer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <utility>

#include <Eigen/Geometry>
#include <Eigen/SVD>

#include "deform/deformation_gradients.h"
#include "deform/edit_roles.h"
#include "deform/similarity_fragment_load.h"
#include "deform/surface_folds.h"
#include "deform/triangle_correspondence.h"
#include "deform/triangle_transforms.h"
#include "planar/map_pipeline.h"

namespace harmonia {
namespace {

// Fold repair: the folded triangles grown by this many rings of neighbours, and the passes of
// averaging over them, per round.
constexpr int kFoldRepairRings = 3;
constexpr int kFoldRepairPasses = 8;

// Area-weighted centroid of a mesh's surface at `positions`.
Eigen::Vector3d surface_centroid(const Eigen::MatrixX3i& faces, const Eigen::MatrixX3d& positions) {
  Eigen::Vector3d weighted = Eigen::Vector3d::Zero();
  double total = 0.0;
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const Eigen::Vector3d a = positions.row(faces(f, 0)), b = positions.row(faces(f, 1)),
                          c = positions.row(faces(f, 2));
    const double area = 0.5 * (b - a).cross(c - a).norm();
    weighted += area * (a + b + c) / 3.0;
    total += area;
  }
  return total > 0.0 ? Eigen::Vector3d(weighted / total) : Eigen::Vector3d(positions.colwise().mean());
}

// The rotation and uniform scale nearest to a linear map: the rotation of its polar decomposition
// (proper: a mirror is not a rotation) and the geometric mean of its singular values.
SimilarityTransform nearest_similarity(const Eigen::Matrix3d& linear) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd;
  svd.compute(linear, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d singular_values = svd.singularValues();
  Eigen::Matrix3d sign = Eigen::Matrix3d::Identity();
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0) sign(2, 2) = -1.0;
  SimilarityTransform similarity;
  similarity.rotation = Eigen::Quaterniond(Eigen::Matrix3d(svd.matrixU() * sign * svd.matrixV().transpose()));
  similarity.scale = std::cbrt(singular_values.prod());
  if (!(similarity.scale > 0.0)) similarity.scale = 1.0;
  return similarity;
}

// One vertex of each connected part (the first of the part in vertex order that a face uses):
// the Poisson equation fixes each part's shape up to a translation.
Eigen::VectorXi one_vertex_per_part(const Mesh& mesh) {
  std::vector<int> parent(static_cast<std::size_t>(mesh.vertex_count()));
  for (std::size_t v = 0; v < parent.size(); ++v) parent[v] = static_cast<int>(v);
  const auto root = [&parent](int v) {
    while (parent[static_cast<std::size_t>(v)] != v)
      v = parent[static_cast<std::size_t>(v)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(v)])];
    return v;
  };
  std::vector<bool> used(parent.size(), false);
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      used[static_cast<std::size_t>(mesh.faces(f, k))] = true;
      const int a = root(mesh.faces(f, k)), b = root(mesh.faces(f, (k + 1) % 3));
      if (a != b) parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
    }
  std::vector<int> held;
  std::vector<bool> seen(parent.size(), false);
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    if (!used[static_cast<std::size_t>(v)]) {
      held.push_back(v);  // a vertex no face uses stays where it is
      continue;
    }
    const int r = root(v);
    if (!seen[static_cast<std::size_t>(r)]) {
      seen[static_cast<std::size_t>(r)] = true;
      held.push_back(v);
    }
  }
  return Eigen::Map<const Eigen::VectorXi>(held.data(), static_cast<Eigen::Index>(held.size()));
}

}  // namespace

// One mesh's marker fields: the Dirichlet system with the markers constrained.
struct MarkerFields {
  Eigen::MatrixXd vertex;  // #V by k
  Eigen::MatrixXd face;    // #F by k, the barycentre values
};

struct DeformationTransfer::Impl {
  Mesh source;
  Mesh target;
  std::vector<MarkerPair> markers;
  DeformationTransferOptions options;
  SolveReport setup;
  std::unique_ptr<detail::Backend> backend;
  MarkerFields source_fields, target_fields;
  std::unique_ptr<detail::DeformationGradients> gradients;
  std::unique_ptr<detail::SimilarityFragmentLoad> load;
  std::unique_ptr<detail::DirichletSystem> poisson;
  std::vector<int> matches;
  int matched = 0, unmatched = 0;
  Eigen::Vector3d source_rest_centroid, target_rest_centroid;
  Eigen::MatrixXd poisson_load, positions;
  Eigen::VectorXi held;  // one vertex per connected part of the target, kept at rest
  std::vector<std::vector<int>> source_neighbours, target_neighbours;  // across edges
  std::vector<char> at_seam;  // per target triangle: its neighbours' matches jump (find_seams)
  std::vector<char> target_rest_folds;  // target triangles folded at rest

  Impl(const Mesh& source_rest, const Mesh& target_rest, const std::vector<MarkerPair>& pairs,
       const DeformationTransferOptions& transfer_options)
      : source(source_rest), target(target_rest), markers(pairs), options(transfer_options) {
    detail::PhaseClock clock(setup, options.solver.progress);
    if (!clock.start("validation")) return;
    if (!detail::validate_mesh_arrays(source, setup) || !detail::validate_mesh_arrays(target, setup))
      return;
    if (std::string problem = marker_problem(); !problem.empty()) {
      setup.status = Status::invalid_input;
      setup.message = "deformation transfer: " + problem;
      return;
    }
    backend = detail::choose_backend(options.solver, setup);
    if (!backend) return;
    if (!clock.start("fields")) return;
    std::vector<int> source_markers, target_markers;
    for (const MarkerPair& pair : markers) {
      source_markers.push_back(pair.source);
      target_markers.push_back(pair.target);
    }
    if (!solve_marker_fields(source, source_markers, "source", source_fields)) return;
    if (!solve_marker_fields(target, target_markers, "target", target_fields)) return;
    gradients = std::make_unique<detail::DeformationGradients>(source);
    source_neighbours = detail::edge_neighbours(source.faces);
    target_neighbours = detail::edge_neighbours(target.faces);
    target_rest_folds = detail::folded_triangles(target.faces, target_neighbours, target.vertices);
    load = std::make_unique<detail::SimilarityFragmentLoad>(target);
    source_rest_centroid = surface_centroid(source.faces, source.vertices);
    target_rest_centroid = surface_centroid(target.faces, target.vertices);
    if (options.method == TransferMethod::correspondence) {
      if (!clock.start("correspondence")) return;
      const detail::TriangleCorrespondence correspondence = detail::match_triangles(
          source_fields.face, target_fields.face, target.faces, options.components,
          options.max_match_distance);
      matches = correspondence.source_triangle;
      matched = correspondence.matched;
      unmatched = correspondence.unmatched;
      find_seams();
    }
    if (!clock.start("factorization")) return;
    // The Poisson system of the target: one vertex held (the equation fixes the shape up to a
    // translation), its factorization reused for every pose.
    detail::OperatorPattern analyzed = detail::operator_pattern(target);
    const Eigen::SparseMatrix<double> operator_matrix =
        backend->triangle_operators(target.faces, target.vertex_count())->cotangent(target.vertices);
    held = one_vertex_per_part(target);
    poisson = std::make_unique<detail::DirichletSystem>(
        analyzed.pattern, held, *backend,
        detail::MatrixKind::symmetric_positive_definite, options.solver, analyzed.vertex_ordering);
    poisson->prefer_fast_solves();
    if (!poisson->factorize(operator_matrix, setup)) return;
  }

  std::string marker_problem() const {
    if (markers.size() < 3)
      return std::to_string(markers.size()) + " marker pairs; at least 3 are needed";
    if (options.components < 3) return "components must be at least 3";
    if (options.smoothing_passes < 0) return "smoothing passes must not be negative";
    if (options.fold_repair_rounds < 0) return "fold repair rounds must not be negative";
    std::set<int> used_source, used_target;
    for (std::size_t i = 0; i < markers.size(); ++i) {
      const MarkerPair& pair = markers[i];
      const std::string name = "marker pair " + std::to_string(i) + ": ";
      if (pair.source < 0 || pair.source >= source.vertex_count())
        return name + "source vertex " + std::to_string(pair.source) + " is outside the source's " +
               std::to_string(source.vertex_count()) + " vertices";
      if (pair.target < 0 || pair.target >= target.vertex_count())
        return name + "target vertex " + std::to_string(pair.target) + " is outside the target's " +
               std::to_string(target.vertex_count()) + " vertices";
      if (!used_source.insert(pair.source).second)
        return name + "source vertex " + std::to_string(pair.source) + " is in an earlier pair";
      if (!used_target.insert(pair.target).second)
        return name + "target vertex " + std::to_string(pair.target) + " is in an earlier pair";
    }
    return {};
  }

  // The k marker fields of one mesh (8.4): h_i = 1 at marker i, 0 at the others, harmonic
  // elsewhere; one factorization, k right-hand sides.
  bool solve_marker_fields(const Mesh& mesh, const std::vector<int>& mesh_markers,
                           const std::string& which, MarkerFields& fields) {
    EditRegions regions;  // every marker a constrained set of its own
    for (const int v : mesh_markers) regions.handles.push_back({v});
    detail::EditRoles roles;
    if (std::string problem = detail::resolve_edit_roles(mesh, regions, roles); !problem.empty()) {
      setup.status = Status::invalid_input;
      setup.message = "deformation transfer: " + which + " mesh: " + problem;
      return false;
    }
    detail::OperatorPattern analyzed = detail::operator_pattern(mesh);
    const Eigen::SparseMatrix<double> operator_matrix =
        backend->triangle_operators(mesh.faces, mesh.vertex_count())->cotangent(mesh.vertices);
    detail::DirichletSystem system(analyzed.pattern, roles.constrained, *backend,
                                   detail::MatrixKind::symmetric_positive_definite, options.solver,
                                   analyzed.vertex_ordering);
    if (!system.factorize(operator_matrix, setup)) return false;
    const auto k = static_cast<Eigen::Index>(mesh_markers.size());
    Eigen::MatrixXd boundary = Eigen::MatrixXd::Zero(roles.constrained.size(), k);
    for (Eigen::Index row = 0; row < roles.constrained.size(); ++row) {
      const int role = roles.role[static_cast<std::size_t>(roles.constrained[row])];
      if (role >= 0) boundary(row, role) = 1.0;
    }
    if (!system.solve_columns(boundary, Eigen::MatrixXd(), fields.vertex, setup)) return false;
    const Eigen::MatrixXd clamped = fields.vertex.cwiseMax(0.0).cwiseMin(1.0);
    fields.face.resize(mesh.face_count(), k);
    for (Eigen::Index i = 0; i < k; ++i)
      for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f)
        fields.face(f, i) = (clamped(mesh.faces(f, 0), i) + clamped(mesh.faces(f, 1), i) +
                             clamped(mesh.faces(f, 2), i)) / 3.0;
    return true;
  }

  // Where the matches of neighbouring target triangles jump between parts of the source (across a
  // joint, at the edge of a marker's region), their deformations disagree and the Poisson solve
  // folds the seam. The target triangles at such a jump: a neighbour's match is neither the
  // triangle's own match nor one of its match's neighbours.
  void find_seams() {
    at_seam.assign(matches.size(), 0);
    const auto adjacent_in_source = [&](int a, int b) {
      if (a == b) return true;
      const std::vector<int>& around = source_neighbours[static_cast<std::size_t>(a)];
      return std::binary_search(around.begin(), around.end(), b);
    };
    for (std::size_t t = 0; t < matches.size(); ++t)
      for (const int g : target_neighbours[t])
        if (matches[t] < 0 || matches[static_cast<std::size_t>(g)] < 0 ||
            !adjacent_in_source(matches[t], matches[static_cast<std::size_t>(g)])) {
          at_seam[t] = 1;
          break;
        }
  }

  // Each pass replaces the deformation of every triangle of `region` by the mean over it and its
  // edge neighbours; elsewhere the deformations are kept as they are.
  void average_within(const std::vector<char>& region, int passes, std::vector<Eigen::Matrix3d>& linear) const {
    std::vector<Eigen::Matrix3d> averaged;
    for (int pass = 0; pass < passes; ++pass) {
      averaged = linear;
      for (std::size_t t = 0; t < linear.size(); ++t) {
        if (!region[t]) continue;
        Eigen::Matrix3d sum = linear[t];
        for (const int g : target_neighbours[t]) sum += linear[static_cast<std::size_t>(g)];
        averaged[t] = sum / static_cast<double>(target_neighbours[t].size() + 1);
      }
      linear.swap(averaged);
    }
  }

  // `region` grown by `rings` rings of edge neighbours.
  void dilate(std::vector<char>& region, int rings) const {
    for (int ring = 0; ring < rings; ++ring) {
      std::vector<char> grown = region;
      for (std::size_t t = 0; t < region.size(); ++t)
        if (region[t])
          for (const int g : target_neighbours[t]) grown[static_cast<std::size_t>(g)] = 1;
      region.swap(grown);
    }
  }

  // The linear part of every target triangle's deformation for a pose.
  std::vector<Eigen::Matrix3d> target_deformations(const std::vector<Eigen::Matrix3d>& source_gradients) const {
    std::vector<Eigen::Matrix3d> linear(static_cast<std::size_t>(target.face_count()),
                                        Eigen::Matrix3d::Identity());
    if (options.method == TransferMethod::correspondence) {
      for (std::size_t t = 0; t < linear.size(); ++t)
        if (matches[t] >= 0) linear[t] = source_gradients[static_cast<std::size_t>(matches[t])];
      average_within(at_seam, options.smoothing_passes, linear);
      return linear;
    }
    // 8.5: the deformation at each source marker, as a rotation and a scale, interpolated over the
    // target by its marker fields.
    std::vector<SimilarityTransform> at_markers;
    for (const MarkerPair& pair : markers)
      at_markers.push_back(nearest_similarity(gradients->mean_around(pair.source, source_gradients)));
    detail::TriangleSimilarities similarities;
    detail::blend_triangle_transforms(target_fields.face, at_markers, similarities);
    for (std::size_t t = 0; t < linear.size(); ++t)
      linear[t] = similarities.scale[static_cast<Eigen::Index>(t)] *
                  similarities.rotation[t].toRotationMatrix();
    return linear;
  }

  TransferResult transfer(const Eigen::MatrixX3d& source_pose) {
    TransferResult result;
    result.report = setup;
    result.report.timings.clear();
    SolveReport& report = result.report;
    if (!report.ok()) return result;
    if (source_pose.rows() != source.vertices.rows() || !source_pose.allFinite()) {
      report.status = Status::invalid_input;
      report.message = "deformation transfer: the pose has " + std::to_string(source_pose.rows()) +
                       " rows (finite positions of the source's " +
                       std::to_string(source.vertex_count()) + " vertices expected)";
      return result;
    }
    detail::PhaseClock clock(report, options.solver.progress);
    if (!clock.start("deformations")) return result;
    std::vector<Eigen::Matrix3d> linear = target_deformations(gradients->of(source_pose));
    Eigen::MatrixXd held_positions(held.size(), 3);
    for (Eigen::Index k = 0; k < held.size(); ++k) held_positions.row(k) = target.vertices.row(held[k]);
    // The solve, then fold repair: where the result folds triangles that are not folded at rest,
    // the deformations around them are evened out and the target solved again (each round one
    // more back-substitution), as long as the folds become fewer.
    Eigen::MatrixXd best_positions;
    std::vector<Eigen::Matrix3d> best_deformations;
    int best_folds = std::numeric_limits<int>::max();
    for (int round = 0; round <= options.fold_repair_rounds; ++round) {
      if (!clock.start("assembly")) return result;
      load->assemble(linear, poisson_load);
      if (!clock.start("solve")) return result;
      if (!poisson->solve_columns(held_positions, poisson_load, positions, report)) return result;
      if (!positions.allFinite()) {
        report.status = Status::numerical_failure;
        report.message = "deformation transfer: the solve gave non-finite positions";
        return result;
      }
      if (!clock.start("fold repair")) return result;
      std::vector<char> new_folds = detail::folded_triangles(target.faces, target_neighbours, positions);
      int count = 0;
      for (std::size_t t = 0; t < new_folds.size(); ++t) {
        new_folds[t] = new_folds[t] && !target_rest_folds[t];
        count += new_folds[t];
      }
      if (count >= best_folds) break;
      best_folds = count;
      best_positions = positions;
      best_deformations = linear;
      if (count == 0) break;
      dilate(new_folds, kFoldRepairRings);
      average_within(new_folds, kFoldRepairPasses, linear);
    }
    positions = std::move(best_positions);
    // Placement: the target's centroid moves as the source's did.
    const Eigen::Vector3d shift = target_rest_centroid +
                                  (surface_centroid(source.faces, source_pose) - source_rest_centroid) -
                                  surface_centroid(target.faces, positions);
    result.positions = positions.rowwise() + shift.transpose();
    result.folded_triangles =
        detail::triangles_folded_by_pose(target.faces, target_neighbours, target.vertices, result.positions);
    report.flipped_triangles = result.folded_triangles;
    report.degenerate_triangles = degenerate_triangles(result.positions);
    result.turned_over_triangles = turned_over_triangles(result.positions, best_deformations);
    result.source_folded_triangles =
        detail::triangles_folded_by_pose(source.faces, source_neighbours, source.vertices, source_pose);
    clock.stop();
    return result;
  }

  // Target triangles of non-zero area whose normal in `result` makes 90 degrees or more with
  // their rest normal carried by their deformation: the normal of the deformed rest edges,
  // (L e1) x (L e2) = cof(L) (e1 x e2).
  int turned_over_triangles(const Eigen::MatrixX3d& result, const std::vector<Eigen::Matrix3d>& deformations) const {
    int count = 0;
    for (Eigen::Index f = 0; f < target.faces.rows(); ++f) {
      const Eigen::Vector3i face = target.faces.row(f);
      const Eigen::Matrix3d& deformation = deformations[static_cast<std::size_t>(f)];
      const Eigen::Vector3d expected =
          (deformation * (target.vertices.row(face[1]) - target.vertices.row(face[0])).transpose())
              .cross(deformation * (target.vertices.row(face[2]) - target.vertices.row(face[0])).transpose());
      const Eigen::Vector3d normal = (result.row(face[1]) - result.row(face[0]))
                                         .cross(result.row(face[2]) - result.row(face[0]));
      if (normal.squaredNorm() > 0.0 && normal.dot(expected) <= 0.0) ++count;
    }
    return count;
  }

  // Zero-area target triangles; a degenerate triangle also counts as folded.
  int degenerate_triangles(const Eigen::MatrixX3d& result) const {
    int count = 0;
    for (Eigen::Index f = 0; f < target.faces.rows(); ++f) {
      const Eigen::Vector3i face = target.faces.row(f);
      const Eigen::Vector3d normal = (result.row(face[1]) - result.row(face[0]))
                                         .cross(result.row(face[2]) - result.row(face[0]));
      if (normal.squaredNorm() == 0.0) ++count;
    }
    return count;
  }
};

DeformationTransfer::DeformationTransfer(const Mesh& source_rest, const Mesh& target_rest,
                                         const std::vector<MarkerPair>& markers,
                                         const DeformationTransferOptions& options)
    : impl_(std::make_unique<Impl>(source_rest, target_rest, markers, options)) {}
DeformationTransfer::~DeformationTransfer() = default;
DeformationTransfer::DeformationTransfer(DeformationTransfer&&) noexcept = default;
DeformationTransfer& DeformationTransfer::operator=(DeformationTransfer&&) noexcept = default;

const SolveReport& DeformationTransfer::setup_report() const { return impl_->setup; }
const Eigen::MatrixXd& DeformationTransfer::source_fields() const { return impl_->source_fields.vertex; }
const Eigen::MatrixXd& DeformationTransfer::target_fields() const { return impl_->target_fields.vertex; }
const std::vector<int>& DeformationTransfer::matches() const { return impl_->matches; }
int DeformationTransfer::matched_triangles() const { return impl_->matched; }
int DeformationTransfer::unmatched_triangles() const { return impl_->unmatched; }

TransferResult DeformationTransfer::transfer(const Eigen::MatrixX3d& source_pose) {
  return impl_->transfer(source_pose);
}

}  // namespace harmonia
