// Surface editing along harmonic fields (thesis 8.3, 8.5; harmonia/surface_editor.h).
//
// The pieces: the roles of the vertices (edit_roles.h), the Dirichlet system of the cotangent
// Laplacian with every constrained vertex on the right (solve/dirichlet_system.h: factorized once),
// the handles' harmonic fields solved with it, the per-triangle blend (triangle_transforms.h) and
// the Poisson load of the transformed fragments (similarity_fragment_load.h).
//
// The editor computes on a copy of the mesh scaled by a power of two to unit size
// (mesh/power_of_two_scale.h), so that it behaves the same at any unit; the handles' centres and
// translations are scaled alike, and the result is scaled back exactly.

#include "harmonia/surface_editor.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <future>
#include <string>
#include <utility>


#include "deform/clustered_rotation_fit.h"
#include "deform/edit_roles.h"
#include "deform/similarity_fragment_load.h"
#include "deform/arap_refinement.h"
#include "deform/triangle_transforms.h"
#include "deform/two_way_split.h"
#include "deform/vertex_clusters.h"
#include "mesh/number_text.h"
#include "mesh/power_of_two_scale.h"
#include "planar/map_pipeline.h"
#include "mesh/helper_tasks.h"

namespace harmonia {
namespace {

using Clock = std::chrono::steady_clock;

// The size from which the editor orders its system by nested dissection rather than AMD.
constexpr int kNestedDissectionVertices = 100000;
// The most refinement steps a frame makes (SurfaceEditOptions::refinement_steps and frame_budget).
constexpr int kMostRefinementSteps = 10000;
// What a further refinement step is expected to cost, in steps: the step, and the orientation
// check that ends the frame (about a tenth of it).
constexpr double kStepAndCheck = 1.1;
// A refinement step before any was timed, in frames without steps: it repeats the frame's
// assembly and solve and adds the rotation fits, which cost about as much again.
constexpr double kFirstStepGuess = 2.0;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace

struct SurfaceEditor::Impl {
  Mesh mesh;           // The input scaled to unit size ...
  double scale = 1.0;  // ... by this power of two.
  SurfaceEditOptions options;
  SolveReport setup;
  detail::EditRoles roles;
  std::unique_ptr<detail::Backend> backend;
  std::unique_ptr<detail::DirichletSystem> system;
  std::unique_ptr<detail::SimilarityFragmentLoad> load;
  std::unique_ptr<detail::ArapRefinement> refinement;
  std::unique_ptr<detail::ClusteredRotationFit> clustered;  // null: the thesis' blend alone
  Eigen::MatrixXd vertex_fields;  // #V by #handles, in [0, 1] up to the solve's rounding
  Eigen::MatrixXd clamped_vertex_fields;
  Eigen::MatrixXd face_fields;    // #F by #handles: barycentre values, clamped to [0, 1]
  Eigen::MatrixX3d rest_normals;  // #F: unnormalized rest normals (for the orientation check)
  int factorizations = 0;
  // A frame's buffers, kept from frame to frame: fresh allocations of this size per frame cost
  // page faults comparable to the back-substitution.
  detail::TriangleSimilarities similarities;
  // A clustered frame's fit: each cluster's rotation, scale and linear part s_c R_c.
  std::vector<Eigen::Quaterniond> cluster_blends;  // the thesis' blend at each cluster
  std::vector<Eigen::Quaterniond> cluster_rotations;
  Eigen::VectorXd cluster_scales;
  std::vector<Eigen::Matrix3d> cluster_linear;
  Eigen::MatrixXd targets;        // the constrained vertices' positions
  Eigen::MatrixXd poisson_load;   // #V by 3
  Eigen::MatrixXd positions;      // #V by 3, in the scaled copy's units
  double first_refinement_step = 0.0;  // seconds, in the last frame that made steps (0: none yet)

  Impl(const Mesh& input, const EditRegions& regions, const SurfaceEditOptions& edit_options)
      : options(edit_options) {
    detail::ScaledMesh unit = detail::unit_scaled(input);
    mesh = std::move(unit.mesh);
    scale = unit.scale;
    detail::PhaseClock clock(setup, options.solver.progress);
    if (!clock.start("validation")) return;
    if (!detail::validate_mesh_arrays(mesh, setup)) return;
    if (options.refinement_steps < 0 || options.refinement_steps > kMostRefinementSteps) {
      setup.status = Status::invalid_input;
      setup.message =
          "surface edit: refinement_steps must be in [0, " + std::to_string(kMostRefinementSteps) + "]";
      return;
    }
    const int clusters =
        options.rotation_clusters.value_or(automatic_rotation_clusters(static_cast<int>(regions.handles.size())));
    if (clusters < 0) {
      setup.status = Status::invalid_input;
      setup.message = "surface edit: rotation_clusters must be at least 0";
      return;
    }
    if (!(options.frame_budget >= 0.0) || !std::isfinite(options.frame_budget)) {
      setup.status = Status::invalid_input;
      setup.message = "surface edit: frame_budget must be a finite number of seconds, at least 0";
      return;
    }
    if (std::string problem = detail::resolve_edit_roles(mesh, regions, roles); !problem.empty()) {
      setup.status = Status::invalid_input;
      setup.message = "surface edit: " + problem;
      return;
    }
    // The fill-reducing ordering depends only on the faces: a second thread computes it (the
    // longest part of the set-up) while this one assembles the operator and the frames' rest data.
    // The tasks are independent, so the result does not depend on their timing.
    std::future<detail::OperatorPattern> ordering = detail::start_beside([this] {
      // From kNestedDissectionVertices vertices on, nested dissection: its factor has about a fifth
      // fewer entries than AMD's on a surface mesh and every frame reads the whole factor twice
      // (a frame's solve at 446K faces: 30 ms against 40 ms), for a second more of set-up. Below,
      // AMD: the solves take the same time and the set-up is shorter.
      return detail::operator_pattern(mesh, mesh.vertex_count() >= kNestedDissectionVertices);
    });
    backend = detail::choose_backend(options.solver, setup);
    if (!backend) return;
    if (!clock.start("analysis")) return;
    const Eigen::SparseMatrix<double> operator_matrix =
        backend->triangle_operators(mesh.faces, mesh.vertex_count())->cotangent(mesh.vertices);
    load = std::make_unique<detail::SimilarityFragmentLoad>(mesh);
    refinement = std::make_unique<detail::ArapRefinement>(mesh);
    rest_normals = face_normals(mesh.vertices);
    detail::OperatorPattern analyzed = ordering.get();
    system = std::make_unique<detail::DirichletSystem>(
        analyzed.pattern, roles.constrained, *backend,
        detail::MatrixKind::symmetric_positive_definite, options.solver,
        analyzed.vertex_ordering);
    system->prefer_fast_solves();
    // The rotation clusters and their covariance map need only the rest mesh: a second thread
    // builds them during the factorization.
    std::future<std::unique_ptr<detail::ClusteredRotationFit>> clusters_beside;
    if (clusters > 0)
      clusters_beside = detail::start_beside([this, clusters] {
        return std::make_unique<detail::ClusteredRotationFit>(mesh, detail::geodesic_clusters(mesh, clusters), *load);
      });
    if (!clock.start("factorization")) return;
    if (!system->factorize(operator_matrix, setup)) return;
    ++factorizations;
    if (!clock.start("fields")) return;
    if (!solve_fields()) return;
    // The fields' solve measured the residual of this factor; a frame's would cost a tenth of it.
    system->skip_residual_checks();
    if (clusters_beside.valid()) {
      clustered = clusters_beside.get();
      if (!clock.start("rotation clusters")) return;
      if (!clustered->couple(mesh, roles, operator_matrix, clamped_vertex_fields, *system, setup)) return;
    }
  }

  // The harmonic field of each handle (8.3): 1 on it, 0 on every other constrained vertex.
  bool solve_fields() {
    Eigen::MatrixXd boundary = Eigen::MatrixXd::Zero(roles.constrained.size(), roles.handle_count);
    for (Eigen::Index k = 0; k < roles.constrained.size(); ++k) {
      const int role = roles.role[static_cast<std::size_t>(roles.constrained[k])];
      if (role >= 0) boundary(k, role) = 1.0;
    }
    if (!system->solve_columns(boundary, Eigen::MatrixXd(), vertex_fields, setup)) return false;
    // The maximum principle keeps a harmonic field in [0, 1]; cotangent weights of obtuse
    // triangles can overshoot it slightly, and a blend weight must not.
    clamped_vertex_fields = vertex_fields.cwiseMax(0.0).cwiseMin(1.0);
    face_fields.resize(mesh.face_count(), roles.handle_count);
    for (Eigen::Index i = 0; i < roles.handle_count; ++i) {
      const auto field = clamped_vertex_fields.col(i);
      for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f)
        face_fields(f, i) =
            (field[mesh.faces(f, 0)] + field[mesh.faces(f, 1)] + field[mesh.faces(f, 2)]) / 3.0;
    }
    return true;
  }

  Eigen::MatrixX3d face_normals(const Eigen::MatrixX3d& positions) const {
    Eigen::MatrixX3d normals(mesh.face_count(), 3);
    for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
      const Eigen::Vector3d a = positions.row(mesh.faces(f, 0)), b = positions.row(mesh.faces(f, 1)),
                            c = positions.row(mesh.faces(f, 2));
      normals.row(f) = (b - a).cross(c - a);
    }
    return normals;
  }

  // Transformations in the scaled copy's units (centres and translations times the scale).
  std::vector<SimilarityTransform> scaled(std::vector<SimilarityTransform> transforms) const {
    for (SimilarityTransform& transform : transforms) {
      transform.center *= scale;
      transform.translation *= scale;
    }
    return transforms;
  }

  std::string transform_problem(const std::vector<SimilarityTransform>& transforms) const {
    if (transforms.size() != static_cast<std::size_t>(roles.handle_count))
      return "expected " + std::to_string(roles.handle_count) + " handle transformations, got " +
             std::to_string(transforms.size());
    for (std::size_t i = 0; i < transforms.size(); ++i) {
      const SimilarityTransform& t = transforms[i];
      const std::string name = "handle " + std::to_string(i);
      if (!t.rotation.coeffs().allFinite() || t.rotation.coeffs().norm() == 0.0)
        return name + ": the rotation is not a finite non-zero quaternion";
      if (!t.center.allFinite() || !t.translation.allFinite())
        return name + ": the centre or translation is not finite";
      if (!(t.scale > 0.0) || !std::isfinite(t.scale))
        return name + ": the scale must be positive and finite, not " + detail::number_text(t.scale);
    }
    return {};
  }

  SurfaceEditResult deform(const std::vector<SimilarityTransform>& model_transforms) {
    SurfaceEditResult result;
    result.report = setup;
    result.report.timings.clear();
    SolveReport& report = result.report;
    if (!report.ok()) return result;
    report.iterations = 0;  // report.residual stays the set-up's (see SurfaceEditResult)
    if (std::string problem = transform_problem(model_transforms); !problem.empty()) {
      report.status = Status::invalid_input;
      report.message = "surface edit: " + problem;
      return result;
    }
    const std::vector<SimilarityTransform> transforms = scaled(model_transforms);
    targets.resize(roles.constrained.size(), 3);
    for (Eigen::Index k = 0; k < roles.constrained.size(); ++k) {
      const int v = roles.constrained[k];
      const int role = roles.role[static_cast<std::size_t>(v)];
      const Eigen::Vector3d rest = mesh.vertices.row(v);
      targets.row(k) = role >= 0 ? transforms[static_cast<std::size_t>(role)].apply(rest) : rest;
    }
    const Clock::time_point frame_start = Clock::now();
    Clock::time_point start = frame_start;
    bool solved = false;
    if (clustered) {
      clustered->fit(transforms, cluster_blends, cluster_rotations, cluster_scales);
      cluster_linear.resize(cluster_rotations.size());
      for (std::size_t c = 0; c < cluster_rotations.size(); ++c)
        cluster_linear[c] = cluster_scales[static_cast<Eigen::Index>(c)] * cluster_rotations[c].toRotationMatrix();
      result.timing.blending += seconds_since(start);
      solved = solve_frame([&] { load->assemble(clustered->triangle_mix(), cluster_linear, poisson_load); },
                           result);
    } else {
      detail::blend_triangle_transforms(face_fields, transforms, similarities);
      result.timing.blending += seconds_since(start);
      solved = solve_frame([&] { load->assemble(similarities, poisson_load); }, result);
    }
    const bool budgeted = options.frame_budget > 0.0;
    const int most_steps =
        budgeted && options.refinement_steps == 0 ? kMostRefinementSteps : options.refinement_steps;
    // With a budget, a step is begun only if it and the check after it are expected to end within
    // it: the first step of a frame (which also blends the vertex rotations) as long as the last
    // frame's first, a later one as long as the step before it. Before any step was timed, a step
    // is guessed at kFirstStepGuess times the frame so far, which it repeats with the rotation
    // fits added.
    double expected_step = first_refinement_step > 0.0 ? first_refinement_step
                                                       : kFirstStepGuess * seconds_since(frame_start);
    const auto another_step_fits = [&] {
      return !budgeted || seconds_since(frame_start) + expected_step * kStepAndCheck <= options.frame_budget;
    };
    if (most_steps > 0 && solved && another_step_fits()) {
      Clock::time_point step_start = Clock::now();
      // Warm start of the vertex rotations: the same blend at the vertices (timed with the first
      // step).
      std::vector<Eigen::Quaterniond> vertex_rotations;
      if (clustered) {
        // The clusters' rotations blended at their vertices by the soft membership (quaternions
        // on the own cluster's side, normalized: the refinement's warm start), and the scales
        // at the triangles by the triangles' shares.
        const detail::VertexClusters& soft = clustered->clusters();
        vertex_rotations.resize(soft.cluster_of.size());
        for (std::size_t v = 0; v < soft.cluster_of.size(); ++v) {
          const Eigen::Quaterniond& own = cluster_rotations[static_cast<std::size_t>(soft.cluster_of[v])];
          Eigen::Vector4d sum = Eigen::Vector4d::Zero();
          for (int i = soft.weight_start[v]; i < soft.weight_start[v + 1]; ++i) {
            const Eigen::Quaterniond& q =
                cluster_rotations[static_cast<std::size_t>(soft.weight_cluster[static_cast<std::size_t>(i)])];
            const double side = q.coeffs().dot(own.coeffs()) < 0.0 ? -1.0 : 1.0;
            sum += side * soft.weight_value[static_cast<std::size_t>(i)] * q.coeffs();
          }
          vertex_rotations[v] = sum.norm() > 0.0 ? Eigen::Quaterniond(sum / sum.norm()) : own;
        }
        const detail::GroupMix& mix = clustered->triangle_mix();
        similarities.scale.resize(mesh.faces.rows());
        for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
          double scale = 0.0;
          for (int i = mix.start[static_cast<std::size_t>(f)]; i < mix.start[static_cast<std::size_t>(f) + 1]; ++i)
            scale += mix.weight[static_cast<std::size_t>(i)] *
                     cluster_scales[mix.group[static_cast<std::size_t>(i)]];
          similarities.scale[f] = scale;
        }
      } else {
        detail::TriangleSimilarities at_vertices;
        detail::blend_triangle_transforms(clamped_vertex_fields, transforms, at_vertices);
        vertex_rotations = std::move(at_vertices.rotation);
      }
      do {
        start = Clock::now();
        refinement->fit_vertex_rotations(positions, vertex_rotations);
        const std::vector<Eigen::Matrix3d> linear =
            refinement->triangle_linear_parts(vertex_rotations, similarities.scale);
        result.timing.refinement += seconds_since(start);
        solved = solve_frame([&] { load->assemble(linear, poisson_load); }, result);
        expected_step = seconds_since(step_start);
        if (result.refinement_steps++ == 0) first_refinement_step = expected_step;
        step_start = Clock::now();
      } while (solved && result.refinement_steps < most_steps && another_step_fits());
    }
    const int refinement_steps = result.refinement_steps;
    report.timings.push_back({"blending", result.timing.blending});
    report.timings.push_back({"assembly", result.timing.assembly});
    report.timings.push_back({"solve", result.timing.solve});
    if (refinement_steps > 0) report.timings.push_back({"refinement", result.timing.refinement});
    if (!solved) return result;
    if (!positions.allFinite()) {
      report.status = Status::numerical_failure;
      report.message = "surface edit: the solve gave non-finite positions";
      return result;
    }
    if (options.check_orientation) {
      start = Clock::now();
      if (clustered) {
        // What the handles ask of a triangle: the mean of its corners' clusters' blends (the
        // fit's own rotations would follow a fold they should reveal).
        const std::vector<int>& cluster_of = clustered->cluster_of();
        std::vector<Eigen::Matrix3d> asked(cluster_blends.size());
        for (std::size_t c = 0; c < asked.size(); ++c) asked[c] = cluster_blends[c].toRotationMatrix();
        count_turned_triangles(positions, [&](Eigen::Index f, const Eigen::Vector3d& rest) {
          Eigen::Vector3d target = Eigen::Vector3d::Zero();
          for (int k = 0; k < 3; ++k)
            target += asked[static_cast<std::size_t>(cluster_of[static_cast<std::size_t>(mesh.faces(f, k))])] * rest;
          return target;
        }, report);
      } else {
        count_turned_triangles(positions, [&](Eigen::Index f, const Eigen::Vector3d& rest) {
          return Eigen::Vector3d(similarities.rotation[static_cast<std::size_t>(f)] * rest);
        }, report);
      }
      result.timing.check = seconds_since(start);
      report.timings.push_back({"check", result.timing.check});
    }
    result.positions = positions / scale;
    return result;
  }

  // The Poisson solve (8.3) for the triangles' similarities.
  // `assemble_load` fills poisson_load with the fragments' load (timed as assembly); the solve
  // puts the constrained vertices at `targets` and writes `positions`.
  template <typename AssembleLoad>
  bool solve_frame(const AssembleLoad& assemble_load, SurfaceEditResult& result) {
    Clock::time_point start = Clock::now();
    assemble_load();
    result.timing.assembly += seconds_since(start);
    start = Clock::now();
    const bool solved = system->solve_columns(targets, poisson_load, positions, result.report);
    result.timing.solve += seconds_since(start);
    return solved;
  }

  // Triangles whose normal makes 90 degrees or more with the rest normal carried by their own
  // transformation (`target_normal`(f, rest normal)), and triangles of zero area.
  template <typename TargetNormal>
  void count_turned_triangles(const Eigen::MatrixXd& positions, const TargetNormal& target_normal,
                              SolveReport& report) const {
    int counts[2][2] = {{0, 0}, {0, 0}};  // per part: flipped, degenerate
    detail::split_two_ways(mesh.faces.rows(), [&](int part, Eigen::Index begin, Eigen::Index end) {
      for (Eigen::Index f = begin; f < end; ++f) {
        const Eigen::Vector3d a = positions.row(mesh.faces(f, 0));
        const Eigen::Vector3d b = positions.row(mesh.faces(f, 1));
        const Eigen::Vector3d c = positions.row(mesh.faces(f, 2));
        const Eigen::Vector3d normal = (b - a).cross(c - a);
        if (normal.squaredNorm() == 0.0) {
          ++counts[part][1];
          continue;
        }
        if (normal.dot(target_normal(f, Eigen::Vector3d(rest_normals.row(f)))) <= 0.0) ++counts[part][0];
      }
    });
    report.flipped_triangles = counts[0][0] + counts[1][0];
    report.degenerate_triangles = counts[0][1] + counts[1][1];
  }
};

SurfaceEditor::SurfaceEditor(const Mesh& mesh, const EditRegions& regions,
                             const SurfaceEditOptions& options)
    : impl_(std::make_unique<Impl>(mesh, regions, options)) {}
SurfaceEditor::~SurfaceEditor() = default;
SurfaceEditor::SurfaceEditor(SurfaceEditor&&) noexcept = default;
SurfaceEditor& SurfaceEditor::operator=(SurfaceEditor&&) noexcept = default;

const SolveReport& SurfaceEditor::setup_report() const { return impl_->setup; }
const Eigen::MatrixXd& SurfaceEditor::handle_fields() const { return impl_->vertex_fields; }
int SurfaceEditor::factorization_count() const { return impl_->factorizations; }

SurfaceEditResult SurfaceEditor::deform(const std::vector<SimilarityTransform>& handle_transforms) {
  return impl_->deform(handle_transforms);
}

SurfaceEditResult SurfaceEditor::drag(const std::vector<Eigen::Vector3d>& handle_translations) {
  std::vector<SimilarityTransform> transforms(handle_translations.size());
  for (std::size_t i = 0; i < transforms.size(); ++i) transforms[i].translation = handle_translations[i];
  return impl_->deform(transforms);
}

SurfaceEditResult edit_surface(const Mesh& mesh, const EditRegions& regions,
                               const std::vector<SimilarityTransform>& handle_transforms,
                               const SurfaceEditOptions& options) {
  SurfaceEditor editor(mesh, regions, options);
  return editor.deform(handle_transforms);
}

}  // namespace harmonia
