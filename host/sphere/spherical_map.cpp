// Spherical parameterization in curvilinear coordinates (thesis chapter 7; harmonia/spherical_map.h).
//
// The pipeline: poles (spherical_poles.h), the curvilinear domain (curvilinear_domain.h), the first
// harmonic map and the quasi-harmonic rounds on the rectangle (one Dirichlet system, its pattern
// analyzed once), the lift onto the sphere, the relaxation of the band around the date line
// (tangential_relaxation.h), and the untangling of what the lift turned over (local_untangling.h).
//
// The quasi-harmonic rounds (7.2). A triangle whose share of the sphere is larger than its share of
// the surface gets a larger conductance kappa_T, so that the next map's gradient, and with it the
// triangle's area, is smaller there. The thesis computes kappa_T = (sum A / sum A') A'_T / A_T
// from the current map and repeats "until convergence". Computed afresh from a map that is already
// nearly authalic, kappa would be nearly 1 and the next round would fall back to the first map; so
// here each round multiplies the conductances by the current ratios (kappa accumulates), which is
// the thesis' formula in the first round and stops changing where the areas match.
//
// Validity. The maps of the rectangle are embeddings (positive weights, convex boundary), but the
// sphere's triangles are the chord triangles of the lifted corners, and a wide, flat triangle of a
// squashed region can turn over in the lift (local_untangling.h says why). A round that would turn
// more triangles over than the current map, or would not lower the area distortion, is shortened
// (kappa times ratio^s, s halved) and, failing that, not taken: the rounds stop there. The relaxation
// undoes any move that would turn a triangle over, and the untangling moves the corners of the
// triangles the lift did turn over into their kernels. SolveReport::fallbacks lists each of these.

#include "harmonia/spherical_map.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <string>
#include <utility>

#include <Eigen/Geometry>

#include "harmonia/metrics.h"
#include "harmonia/spherical_metrics.h"
#include "harmonia/topology.h"
#include "mesh/power_of_two_scale.h"
#include "planar/map_pipeline.h"
#include "mesh/edge_table.h"
#include "mesh/midpoint_subdivision.h"
#include "mesh/shortest_paths.h"
#include "sphere/central_projection.h"
#include "sphere/curvilinear_domain.h"
#include "sphere/local_untangling.h"
#include "sphere/sphere_orientation.h"
#include "sphere/spherical_poles.h"
#include "sphere/tangential_relaxation.h"

namespace harmonia {

Eigen::MatrixX3d sphere_points(const Eigen::MatrixX2d& angles) {
  Eigen::MatrixX3d points(angles.rows(), 3);
  for (Eigen::Index v = 0; v < angles.rows(); ++v) {
    const double theta = angles(v, 0), phi = angles(v, 1);
    points.row(v) << std::cos(theta) * std::sin(phi), std::sin(theta) * std::sin(phi), std::cos(phi);
  }
  return points;
}

namespace {

// Halvings of a quasi-harmonic round's step before the rounds stop.
constexpr int kRoundBisections = 3;
// Passes of the untangling (local_untangling.h); it stops earlier when a pass changes nothing.
constexpr int kUntanglingPasses = 100;
// A mesh too coarse for curvilinear coordinates is subdivided at most this many times (each
// doubles the poles' distance in edges: 1 becomes 4 after two).
constexpr int kMostSubdivisions = 3;

// (theta, phi) of unit-sphere points: theta in [0, 2 pi), phi in [0, pi].
Eigen::MatrixX2d curvilinear_coordinates(const Eigen::MatrixX3d& points) {
  Eigen::MatrixX2d angles(points.rows(), 2);
  for (Eigen::Index v = 0; v < points.rows(); ++v) {
    const double x = points(v, 0), y = points(v, 1), z = points(v, 2);
    double theta = std::atan2(y, x);
    if (theta < 0.0) theta += 2.0 * std::numbers::pi;
    if (theta >= 2.0 * std::numbers::pi) theta = 0.0;
    angles(v, 0) = theta;
    angles(v, 1) = std::atan2(std::hypot(x, y), z);
  }
  return angles;
}

// Per face of `faces`: the unsigned spherical area of its lifted triangle.
Eigen::VectorXd spherical_areas(const Eigen::MatrixX3d& points, const Eigen::MatrixX3i& faces) {
  Eigen::VectorXd areas(faces.rows());
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    areas[f] = std::abs(detail::signed_spherical_area(points.row(faces(f, 0)).transpose(),
                                                      points.row(faces(f, 1)).transpose(),
                                                      points.row(faces(f, 2)).transpose()));
  return areas;
}

Eigen::VectorXd surface_areas(const Mesh& mesh) {
  Eigen::VectorXd areas(mesh.faces.rows());
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    const Eigen::Vector3d p = mesh.vertices.row(mesh.faces(f, 0)), q = mesh.vertices.row(mesh.faces(f, 1)),
                          r = mesh.vertices.row(mesh.faces(f, 2));
    areas[f] = 0.5 * (q - p).cross(r - p).norm();
  }
  return areas;
}

// The 3D-area-weighted mean |log| of (share of the sphere / share of the surface).
double area_distortion(const Eigen::VectorXd& sphere_area, const Eigen::VectorXd& surface_area) {
  const double sphere_total = sphere_area.sum(), surface_total = surface_area.sum();
  double sum = 0.0;
  for (Eigen::Index f = 0; f < sphere_area.size(); ++f) {
    if (!(sphere_area[f] > 0.0) || !(surface_area[f] > 0.0)) continue;
    sum += surface_area[f] *
           std::abs(std::log((sphere_area[f] / sphere_total) / (surface_area[f] / surface_total)));
  }
  return sum / surface_total;
}

// Mean-value weights made symmetric: each edge weighted by the mean of its two directed weights,
// the diagonal again the sum of its row. Both directed weights are positive, so their mean is:
// Tutte's theorem still makes a map of the convex rectangle an embedding. And the operator is
// symmetric, positive definite once the boundary is fixed, so the Cholesky set up for cotangent
// weights (the same pattern, analysis and ordering) factorizes it, where the directed weights need
// an LU of their own: on cow x16 (44K vertices) an LU took about four times a Cholesky's time.
Eigen::SparseMatrix<double> symmetrized(const Eigen::SparseMatrix<double>& laplacian) {
  Eigen::SparseMatrix<double> symmetric = 0.5 * (laplacian + Eigen::SparseMatrix<double>(laplacian.transpose()));
  Eigen::VectorXd diagonal = Eigen::VectorXd::Zero(symmetric.rows());
  for (Eigen::Index column = 0; column < symmetric.outerSize(); ++column)
    for (Eigen::SparseMatrix<double>::InnerIterator entry(symmetric, column); entry; ++entry)
      if (entry.row() != entry.col()) diagonal[entry.col()] -= entry.value();
  for (Eigen::Index column = 0; column < symmetric.outerSize(); ++column)
    for (Eigen::SparseMatrix<double>::InnerIterator entry(symmetric, column); entry; ++entry)
      if (entry.row() == entry.col()) entry.valueRef() = diagonal[column];
  return symmetric;
}

}  // namespace

struct SphericalMapper::Impl {
  Mesh mesh;  // The input scaled to unit size (mesh/power_of_two_scale.h).
  SphericalMapOptions options;
  SolveReport setup;
  std::array<int, 2> poles{-1, -1};
  detail::CurvilinearDomain domain;
  std::unique_ptr<detail::Backend> backend;
  Eigen::SparseMatrix<double> pattern;
  std::vector<int> vertex_ordering;
  // The rectangle's Dirichlet system with the chosen weights. Where cotangent weights fold the
  // first map, mean-value weights made symmetric take their place in the same system.
  std::unique_ptr<detail::DirichletSystem> system;
  bool symmetrized_mean_value = false;
  // Automatic poles fewer than three edges apart (a mesh too coarse for curvilinear coordinates):
  // why, and the map is then a central projection (central_projection.h).
  std::string too_coarse;

  Impl(const Mesh& input, const SphericalMapOptions& sphere_options)
      : mesh(detail::unit_scaled(input).mesh), options(sphere_options) {
    detail::PhaseClock clock(setup, options.solver.progress);
    if (!clock.start("validation")) return;
    if (!detail::validate_mesh_arrays(mesh, setup)) return;
    std::string message;
    if (const Status status = check_sphere(mesh, &message); status != Status::ok) {
      setup.status = status;
      setup.message = "spherical map: " + message;
      return;
    }
    if (!validate_options()) return;
    if (!clock.start("poles")) return;
    poles = options.poles.value_or(detail::automatic_poles(mesh));
    if (std::string problem = detail::pole_problem(mesh, poles); !problem.empty()) {
      // The automatic poles are the farthest apart there are: the mesh is too coarse for the
      // construction, and is mapped by central projection where it is star-shaped.
      if (!options.poles && options.method == SphericalMethod::curvilinear) {
        too_coarse = std::move(problem);
        return;
      }
      setup.status = Status::invalid_input;
      setup.message = "spherical map: " + problem;
      return;
    }
    if (options.method == SphericalMethod::relaxation) return;
    if (!clock.start("analysis")) return;
    try {
      domain = detail::curvilinear_domain(mesh, poles[0], poles[1], options.pole_margin);
    } catch (const Error& error) {
      setup.status = error.status();
      setup.message = error.what();
      return;
    }
    backend = detail::choose_backend(options.solver, setup);
    if (!backend) return;
    detail::OperatorPattern analyzed = detail::operator_pattern(domain.disk);
    pattern = std::move(analyzed.pattern);
    vertex_ordering = std::move(analyzed.vertex_ordering);
    system = make_system(options.weights);
  }

  std::unique_ptr<detail::DirichletSystem> make_system(WeightScheme weights) const {
    const detail::MatrixKind kind = weights == WeightScheme::cotangent
                                        ? detail::MatrixKind::symmetric_positive_definite
                                        : detail::MatrixKind::general;
    return std::make_unique<detail::DirichletSystem>(pattern, domain.boundary, *backend, kind,
                                                     options.solver, vertex_ordering);
  }

  bool validate_options() {
    const auto fail = [this](const std::string& message) {
      setup.status = Status::invalid_input;
      setup.message = "spherical map: " + message;
      return false;
    };
    if (options.weights != WeightScheme::mean_value && options.weights != WeightScheme::cotangent)
      return fail("weights must be mean-value or cotangent, not " +
                  std::string(to_string(options.weights)));
    if (options.rounds < 0 || options.rounds > 100) return fail("rounds must be in [0, 100]");
    if (!(options.pole_margin > 0.0 && options.pole_margin < 0.5))
      return fail("pole_margin must be in (0, 0.5) radians");
    if (options.relax_rings < 0 || options.relax_rings > 1000)
      return fail("relax_rings must be in [0, 1000]");
    if (options.relax_steps < 0 || options.relax_steps > 10000)
      return fail("relax_steps must be in [0, 10000]");
    if (options.global_relaxation_steps < 0 || options.global_relaxation_steps > 100000)
      return fail("global_relaxation_steps must be in [0, 100000]");
    return true;
  }

  // The sphere points of the domain's vertices for plane coordinates (theta, lambda).
  static Eigen::MatrixX3d lifted(const Eigen::MatrixX2d& plane) {
    return sphere_points(detail::polar_angles(plane));
  }

  // One map of the rectangle with the given face conductances (all 1: the harmonic map).
  bool rectangle_map(WeightScheme weights, const Eigen::VectorXd& conductance, Eigen::MatrixX2d& plane,
                     SolveReport& report) {
    Eigen::SparseMatrix<double> laplacian = face_weighted_laplacian(domain.disk, weights, conductance);
    if (symmetrized_mean_value) laplacian = symmetrized(laplacian);
    return system->factorize(laplacian, report) && system->solve(domain.boundary_plane, plane, report);
  }

  // The first map (7.1). Cotangent weights can fold where mean-value weights cannot: a folded
  // cotangent map is replaced by the map with mean-value weights made symmetric (symmetrized).
  bool harmonic_map(WeightScheme& weights, Eigen::MatrixX2d& plane, SolveReport& report) {
    const Eigen::VectorXd ones = Eigen::VectorXd::Ones(domain.disk.faces.rows());
    symmetrized_mean_value = false;
    if (!rectangle_map(weights, ones, plane, report)) return false;
    if (weights == WeightScheme::mean_value) return true;
    const FlipCount flips = count_flips(plane, domain.disk.faces);
    if (flips.flipped + flips.zero_area == 0) return true;
    report.fallbacks.push_back("first map: symmetrized mean-value weights (the cotangent map has " +
                               std::to_string(flips.flipped + flips.zero_area) +
                               " flipped or zero-area triangles)");
    weights = WeightScheme::mean_value;
    symmetrized_mean_value = true;
    return rectangle_map(weights, ones, plane, report);
  }

  SphericalMapResult solve() {
    SphericalMapResult result;
    result.report = setup;
    SolveReport& report = result.report;
    if (!report.ok()) return result;
    result.north_pole = poles[0];
    result.south_pole = poles[1];
    detail::PhaseClock clock(report, options.solver.progress);
    Eigen::MatrixX3d points;
    if (!too_coarse.empty()) {
      if (!coarse_map(points, result, clock)) return result;
    } else if (options.method == SphericalMethod::relaxation) {
      if (!global_relaxation(points, result, clock)) return result;
    } else {
      if (!curvilinear_map(points, result, clock)) return result;
    }
    if (!clock.start("metrics")) return result;
    const SphericalMetrics metrics = spherical_metrics(mesh, points);
    report.flipped_triangles = metrics.flipped_triangles;
    report.degenerate_triangles = metrics.degenerate_triangles;
    if (metrics.flipped_triangles + metrics.degenerate_triangles > 0 && report.ok()) {
      report.status = Status::flipped_triangles;
      report.message = std::to_string(metrics.flipped_triangles) +
                       " triangles turned over and " +
                       std::to_string(metrics.degenerate_triangles) +
                       " degenerate triangles on the sphere";
    }
    clock.stop();
    result.angles = curvilinear_coordinates(points);
    result.positions = std::move(points);
    return result;
  }

  // A mesh too coarse for curvilinear coordinates: its central projection where it is star-shaped
  // about one of the centres tried (central_projection.h: valid by construction); else the map of
  // the mesh subdivided until its poles are three edges apart (the same surface), of which the
  // mesh's own vertices are kept, and the triangles that turned over between them untangled. The
  // date line is the shortest edge path between the poles.
  bool coarse_map(Eigen::MatrixX3d& points, SphericalMapResult& result, detail::PhaseClock& clock) {
    SolveReport& report = result.report;
    const detail::EdgeGraph graph = detail::build_edge_graph(mesh, detail::EdgeTable(mesh));
    result.date_line = detail::path_to(detail::dijkstra(graph, poles[0]), poles[1]);
    if (!clock.start("central projection")) return false;
    if (std::optional<detail::CentralProjection> projection = detail::central_projection(mesh, poles)) {
      points = std::move(projection->points);
      report.fallbacks.push_back("central projection from " + projection->centre_name + " (" + too_coarse +
                                 "): the mesh is too coarse for curvilinear coordinates, and star-shaped about it");
      return true;
    }
    if (!clock.start("refinement")) return false;
    Mesh refined = mesh;
    int subdivisions = 0;
    while (!detail::pole_problem(refined, poles).empty() && subdivisions < kMostSubdivisions) {
      refined = detail::midpoint_subdivision(refined);
      ++subdivisions;
    }
    SphericalMapOptions refined_options = options;
    refined_options.poles = poles;  // the subdivision keeps every vertex's index
    refined_options.solver.progress = nullptr;
    const SphericalMapResult fine = spherical_map(refined, refined_options);
    if (fine.positions.rows() != refined.vertex_count()) {
      report.status = fine.report.status;
      report.message = "spherical map: " + too_coarse + "; the mesh, star-shaped about none of its centres, was "
                       "subdivided " + std::to_string(subdivisions) + " times and then failed: " + fine.report.message;
      return false;
    }
    points = fine.positions.topRows(mesh.vertex_count());
    const detail::UntanglingOutcome untangled = detail::untangle_on_sphere(mesh, kUntanglingPasses, points);
    const std::string times = subdivisions == 1 ? "once" : subdivisions == 2 ? "twice" : std::to_string(subdivisions) + " times";
    std::string note = "subdivided " + times + " (" + too_coarse +
                       ") and mapped by curvilinear coordinates, the mesh's own vertices kept";
    if (untangled.turned_before > 0)
      note += "; of " + std::to_string(untangled.turned_before) + " triangles turned over between them, " +
              std::to_string(untangled.turned_after) + " left after untangling";
    report.fallbacks.push_back(note);
    return true;
  }

  // The points of the closed mesh for a map of the rectangle: the lift, with the poles restored.
  Eigen::MatrixX3d closed_points(const Eigen::MatrixX3d& lifted_points) const {
    Eigen::MatrixX3d points = Eigen::MatrixX3d::Zero(mesh.vertex_count(), 3);
    for (std::size_t v = 0; v < domain.original_vertex.size(); ++v)
      points.row(domain.original_vertex[v]) = lifted_points.row(static_cast<Eigen::Index>(v));
    points.row(poles[0]) << 0.0, 0.0, 1.0;
    points.row(poles[1]) << 0.0, 0.0, -1.0;
    return points;
  }

  bool curvilinear_map(Eigen::MatrixX3d& points, SphericalMapResult& result,
                       detail::PhaseClock& clock) {
    SolveReport& report = result.report;
    result.date_line = domain.date_line;
    const Eigen::MatrixX3i& faces = domain.disk.faces;
    const Eigen::VectorXd surface_area = surface_areas(domain.disk);

    // A map of the rectangle as a candidate: its sphere (lifted and untangled), how many triangles
    // stay turned over, and its area distortion.
    struct Candidate {
      Eigen::MatrixX2d plane;
      Eigen::VectorXd sphere_area;
      double distortion = 0.0;
      Eigen::MatrixX3d points;
      detail::UntanglingOutcome untangling;
    };
    const auto evaluate = [&](Eigen::MatrixX2d plane) {
      Candidate candidate;
      const Eigen::MatrixX3d lifted_points = lifted(plane);
      candidate.sphere_area = spherical_areas(lifted_points, faces);
      candidate.distortion = area_distortion(candidate.sphere_area, surface_area);
      candidate.points = closed_points(lifted_points);
      candidate.untangling =
          detail::untangle_on_sphere(mesh, kUntanglingPasses, candidate.points);
      candidate.plane = std::move(plane);
      return candidate;
    };

    // The first map (7.1).
    auto begin = std::chrono::steady_clock::now();
    if (!clock.start("harmonic map")) return false;
    WeightScheme weights = options.weights;
    Eigen::MatrixX2d first_plane;
    if (!harmonic_map(weights, first_plane, report)) return false;
    Candidate current = evaluate(std::move(first_plane));
    const auto record_round = [&] {
      SphericalRound round;
      round.area_distortion = current.distortion;
      round.seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
      result.rounds.push_back(round);
    };
    record_round();

    // The quasi-harmonic rounds (7.2), see the file comment.
    Eigen::VectorXd conductance = Eigen::VectorXd::Ones(faces.rows());
    const double surface_total = surface_area.sum();
    for (int round = 1; round <= options.rounds; ++round) {
      begin = std::chrono::steady_clock::now();
      if (!clock.start("quasi-harmonic round", round, options.rounds)) return false;
      const double sphere_total = current.sphere_area.sum();
      Eigen::VectorXd ratio(faces.rows());
      for (Eigen::Index f = 0; f < faces.rows(); ++f) {
        const double value =
            (surface_total / sphere_total) * current.sphere_area[f] / surface_area[f];
        ratio[f] = std::isfinite(value) && value > 0.0 ? value : 1.0;
      }
      // The round in full (kappa times the ratio), or shortened (times ratio^s, s halved) where
      // the full one leaves more triangles turned over after untangling than the current map.
      bool taken = false;
      double step = 1.0;
      for (int attempt = 0; attempt <= kRoundBisections && !taken; ++attempt, step /= 2.0) {
        const Eigen::VectorXd next_conductance =
            conductance.cwiseProduct(ratio.array().pow(step).matrix());
        Eigen::MatrixX2d next_plane;
        if (!rectangle_map(weights, next_conductance, next_plane, report)) return false;
        Candidate next = evaluate(std::move(next_plane));
        if (next.untangling.turned_after > current.untangling.turned_after ||
            !(next.distortion < current.distortion))
          continue;
        if (step < 1.0)
          report.fallbacks.push_back("quasi-harmonic round " + std::to_string(round) +
                                     ": shortened to ratio^" + std::to_string(step) +
                                     " (the full round leaves triangles turned over on the sphere)");
        conductance = next_conductance;
        current = std::move(next);
        taken = true;
      }
      if (!taken) {
        report.fallbacks.push_back("quasi-harmonic round " + std::to_string(round) +
                                   ": not taken, rounds stopped (every shortened round leaves "
                                   "triangles turned over on the sphere or adds area distortion)");
        break;
      }
      ++report.rounds;
      record_round();
    }
    if (current.untangling.turned_before > 0)
      report.fallbacks.push_back(
          "untangling: " + std::to_string(current.untangling.turned_before) +
          " triangles turned over by the lift, " + std::to_string(current.untangling.turned_after) +
          " left after moving " + std::to_string(current.untangling.moved_vertices) + " vertices");
    points = std::move(current.points);

    // The band around the date line (7.3); no move may turn a triangle over.
    if (options.relax_rings > 0 && options.relax_steps > 0) {
      if (!clock.start("relaxation")) return false;
      const std::vector<char> band = detail::vertices_within_rings(
          mesh.faces, mesh.vertex_count(), domain.date_line, options.relax_rings - 1);
      const detail::RelaxationOutcome outcome =
          detail::relax_on_sphere(laplacian(mesh, WeightScheme::mean_value), mesh.faces, band,
                                  options.relax_steps, true, points);
      result.relaxed_vertices = outcome.moved_vertices;
      if (outcome.held_back > 0)
        report.fallbacks.push_back("relaxation: " + std::to_string(outcome.held_back) +
                                   " vertex moves undone (they would have turned a triangle over)");
    }
    report.cross_check_error = backend->cross_check_error();
    return true;
  }

  // The baseline of figure 7.9: central projection, then global tangential relaxation.
  bool global_relaxation(Eigen::MatrixX3d& points, SphericalMapResult& result,
                         detail::PhaseClock& clock) {
    if (!clock.start("relaxation")) return false;
    const Eigen::RowVector3d centroid = mesh.vertices.colwise().mean();
    points = mesh.vertices.rowwise() - centroid;
    for (Eigen::Index v = 0; v < points.rows(); ++v) {
      const double radius = points.row(v).norm();
      if (radius > 0.0) points.row(v) /= radius; else points.row(v) << 0.0, 0.0, 1.0;
    }
    const std::vector<char> everything(static_cast<std::size_t>(mesh.vertex_count()), 1);
    const detail::RelaxationOutcome outcome =
        detail::relax_on_sphere(laplacian(mesh, WeightScheme::mean_value), mesh.faces, everything,
                                options.global_relaxation_steps, false, points);
    result.relaxed_vertices = outcome.moved_vertices;
    result.report.rounds = options.global_relaxation_steps;
    return true;
  }
};

SphericalMapper::SphericalMapper(const Mesh& mesh, const SphericalMapOptions& options)
    : impl_(std::make_unique<Impl>(mesh, options)) {}
SphericalMapper::~SphericalMapper() = default;
SphericalMapper::SphericalMapper(SphericalMapper&&) noexcept = default;
SphericalMapper& SphericalMapper::operator=(SphericalMapper&&) noexcept = default;

const SolveReport& SphericalMapper::setup_report() const { return impl_->setup; }

void SphericalMapper::update_geometry(const Eigen::MatrixX3d& vertices) {
  Impl& impl = *impl_;
  if (!detail::accept_new_geometry(impl.mesh, vertices, impl.setup)) return;
  impl.mesh.vertices = detail::unit_scaled(Mesh{vertices, impl.mesh.faces}).mesh.vertices;
  if (impl.options.method == SphericalMethod::relaxation || !impl.system) return;
  // Same connectivity and poles. The date line is the shortest path for the new geometry; where it
  // moved, the domain's connectivity changed and its pattern is analyzed again.
  try {
    detail::CurvilinearDomain domain = detail::curvilinear_domain(
        impl.mesh, impl.poles[0], impl.poles[1], impl.options.pole_margin);
    const bool same_cut = domain.date_line == impl.domain.date_line;
    impl.domain = std::move(domain);
    if (same_cut) return;
    detail::OperatorPattern analyzed = detail::operator_pattern(impl.domain.disk);
    impl.pattern = std::move(analyzed.pattern);
    impl.vertex_ordering = std::move(analyzed.vertex_ordering);
    impl.system = impl.make_system(impl.options.weights);
  } catch (const Error& error) {
    impl.setup.status = error.status();
    impl.setup.message = error.what();
  }
}

SphericalMapResult SphericalMapper::solve() { return impl_->solve(); }

SphericalMapResult spherical_map(const Mesh& mesh, const SphericalMapOptions& options) {
  SphericalMapper mapper(mesh, options);
  return mapper.solve();
}

}  // namespace harmonia
