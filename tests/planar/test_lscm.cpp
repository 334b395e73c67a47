// Least-squares conformal maps: exact on planar meshes (up to similarity), nearly conformal and
// valid on curved ones, pins validated, reusable solver.
#include <complex>
#include <iostream>
#include <numbers>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "harmonia/lscm.h"
#include "harmonia/procedural.h"
#include "harmonia/quasi_harmonic_operator.h"
#include "harmonia/topology.h"
#include "planar/lscm_energy.h"
#include "support/topology_meshes.h"

namespace harmonia {
namespace {

int ring_start(int ring) { return ring == 0 ? 0 : 1 + 3 * ring * (ring - 1); }

LscmOptions raw_options() {
  LscmOptions options;
  options.normalization = UvNormalization::none;
  options.solver.backend = BackendChoice::cpu;
  return options;
}

// Largest distance between `target` and the least-squares similarity image of `source`
// (z -> s z + t with complex s: rotation, uniform scale, translation).
double similarity_fit_error(const Eigen::MatrixX2d& source, const Eigen::MatrixX2d& target) {
  using Complex = std::complex<double>;
  const Eigen::RowVector2d source_mean = source.colwise().mean(),
                           target_mean = target.colwise().mean();
  Complex numerator = 0.0;
  double denominator = 0.0;
  for (Eigen::Index v = 0; v < source.rows(); ++v) {
    const Complex z(source(v, 0) - source_mean.x(), source(v, 1) - source_mean.y());
    const Complex w(target(v, 0) - target_mean.x(), target(v, 1) - target_mean.y());
    numerator += std::conj(z) * w;
    denominator += std::norm(z);
  }
  const Complex scale = numerator / denominator;
  double worst = 0.0;
  for (Eigen::Index v = 0; v < source.rows(); ++v) {
    const Complex z(source(v, 0) - source_mean.x(), source(v, 1) - source_mean.y());
    const Complex w(target(v, 0) - target_mean.x(), target(v, 1) - target_mean.y());
    worst = std::max(worst, std::abs(scale * z - w));
  }
  return worst;
}

// Area-weighted mean and the maximum of sigma1/sigma2 of the map (1 = conformal), from the first
// fundamental form of uv -> 3D.
std::pair<double, double> conformal_distortion(const Mesh& mesh, const Eigen::MatrixX2d& uv) {
  const TriangleTensors forms = first_fundamental_forms(mesh, uv);
  double weighted = 0.0, total = 0.0, worst = 0.0;
  for (int f = 0; f < mesh.face_count(); ++f) {
    Eigen::Matrix2d form;
    form << forms(f, 0), forms(f, 1), forms(f, 2), forms(f, 3);
    const Eigen::Vector2d eigenvalues =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(form).eigenvalues();
    const double ratio = std::sqrt(eigenvalues[1] / eigenvalues[0]);
    const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(f, 0)),
                          b = mesh.vertices.row(mesh.faces(f, 1)),
                          c = mesh.vertices.row(mesh.faces(f, 2));
    const double area = 0.5 * (b - a).cross(c - a).norm();
    weighted += area * ratio;
    total += area;
    worst = std::max(worst, ratio);
  }
  return {weighted / total, worst};
}

// The discrete conformal energy sum_T [A_T tr(I_T^-1) - 2 A_uv,T] (= sum_T A_T |grad u + rot90 grad
// v|^2), computed from the first fundamental form I of uv -> 3D, independently of the solver's
// assembly.
double conformal_energy(const Mesh& mesh, const Eigen::MatrixX2d& uv) {
  const TriangleTensors forms = first_fundamental_forms(mesh, uv);
  double energy = 0.0;
  for (int f = 0; f < mesh.face_count(); ++f) {
    Eigen::Matrix2d form;
    form << forms(f, 0), forms(f, 1), forms(f, 2), forms(f, 3);
    const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(f, 0)),
                          b = mesh.vertices.row(mesh.faces(f, 1)),
                          c = mesh.vertices.row(mesh.faces(f, 2));
    const Eigen::Vector2d p = uv.row(mesh.faces(f, 0)), q = uv.row(mesh.faces(f, 1)),
                          r = uv.row(mesh.faces(f, 2));
    const double uv_area = 0.5 * ((q - p).x() * (r - p).y() - (q - p).y() * (r - p).x());
    energy += 0.5 * (b - a).cross(c - a).norm() * form.inverse().trace() - 2.0 * uv_area;
  }
  return energy;
}

using testing::octahedron;  // Closed, outward; vertices 4 and 5 are the poles.

TEST(Lscm, PlanarMeshIsReproducedUpToSimilarity) {
  Mesh mesh = planar_disk(10, 1.0);
  const Eigen::MatrixX2d planar = mesh.vertices.leftCols<2>();
  // Tilt the plane in 3D: LSCM works in each triangle's own frame, so this changes nothing.
  const Eigen::Matrix3d tilt =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1.0, 2.0, 0.5).normalized()).toRotationMatrix();
  mesh.vertices = (mesh.vertices * tilt.transpose()).eval();
  const MapResult result = lscm(mesh, raw_options());
  ASSERT_EQ(result.report.status, Status::ok) << result.report.message;
  EXPECT_LT(similarity_fit_error(result.uv, planar), 1e-8);
  EXPECT_LT(result.report.residual, 1e-10);
}

TEST(Lscm, HemisphereMapIsValidAndNearlyConformal) {
  const Mesh mesh = hemisphere(16);
  const MapResult result = lscm(mesh, raw_options());
  ASSERT_EQ(result.report.status, Status::ok) << result.report.message;
  EXPECT_EQ(result.report.flipped_triangles, 0);
  EXPECT_EQ(result.report.boundary_self_intersections, 0);
  // Compare with the exact conformal map (stereographic projection) sampled at the vertices, moved
  // by the similarity that puts it on LSCM's two pins: LSCM minimizes the discrete conformal energy
  // under the pins, so it must not do worse, and its distortion matches the triangulation's.
  Eigen::MatrixX2d stereographic(mesh.vertex_count(), 2);
  for (int v = 0; v < mesh.vertex_count(); ++v)
    stereographic.row(v) = mesh.vertices.row(v).head<2>() / (1.0 + mesh.vertices(v, 2));
  std::vector<int> pins;
  for (int v = 0; v < mesh.vertex_count(); ++v)
    if (result.uv(v, 1) == 0.0 &&
        (result.uv(v, 0) == 0.0 || std::abs(result.uv(v, 0) - 2.0) < 1e-12))
      pins.push_back(v);
  ASSERT_EQ(pins.size(), 2u);
  using Complex = std::complex<double>;
  const auto complex_at = [](const Eigen::MatrixX2d& uv, int v) {
    return Complex(uv(v, 0), uv(v, 1));
  };
  const Complex scale = (complex_at(result.uv, pins[1]) - complex_at(result.uv, pins[0])) /
                        (complex_at(stereographic, pins[1]) - complex_at(stereographic, pins[0]));
  Eigen::MatrixX2d pinned_stereographic(mesh.vertex_count(), 2);
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    const Complex z = scale * (complex_at(stereographic, v) - complex_at(stereographic, pins[0])) +
                      complex_at(result.uv, pins[0]);
    pinned_stereographic.row(v) << z.real(), z.imag();
  }
  const double lscm_energy = conformal_energy(mesh, result.uv);
  const double exact_energy = conformal_energy(mesh, pinned_stereographic);
  const auto [mean, worst] = conformal_distortion(mesh, result.uv);
  const auto [exact_mean, exact_worst] = conformal_distortion(mesh, pinned_stereographic);
  std::cout << "conformal energy: lscm " << lscm_energy << ", sampled stereographic "
            << exact_energy << "\nsigma1/sigma2 mean/max: lscm " << mean << " / " << worst
            << ", sampled stereographic " << exact_mean << " / " << exact_worst << '\n';
  EXPECT_LE(lscm_energy, exact_energy * (1.0 + 1e-12));
  EXPECT_LT(mean, exact_mean * 1.01);
}

TEST(Lscm, DefaultPinsAreTheFarthestBoundaryPair) {
  const int rings = 6;
  const Mesh mesh = hemisphere(rings);
  const MapResult result = lscm(mesh, raw_options());
  ASSERT_EQ(result.report.status, Status::ok);
  // Pins sit at (0,0) and (d,0) with d their 3D distance: the diameter of the equator, 2.
  int at_origin = -1, at_distance = -1;
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    if (result.uv.row(v) == Eigen::RowVector2d(0.0, 0.0)) at_origin = v;
    if (result.uv(v, 1) == 0.0 && std::abs(result.uv(v, 0) - 2.0) < 1e-12) at_distance = v;
  }
  ASSERT_GE(at_origin, ring_start(rings));
  ASSERT_GE(at_distance, ring_start(rings));
  EXPECT_NEAR((mesh.vertices.row(at_origin) - mesh.vertices.row(at_distance)).norm(), 2.0, 1e-12);
}

TEST(Lscm, ChosenPinsAreValidated) {
  const Mesh mesh = hemisphere(4);
  LscmOptions options = raw_options();
  options.pin_first = 40;
  options.pin_second = 50;
  const MapResult pinned = lscm(mesh, options);
  ASSERT_EQ(pinned.report.status, Status::ok);
  EXPECT_EQ(pinned.uv.row(40), Eigen::RowVector2d(0.0, 0.0));
  EXPECT_NEAR(pinned.uv(50, 0), (mesh.vertices.row(40) - mesh.vertices.row(50)).norm(), 1e-15);

  options.pin_second = 40;
  MapResult result = lscm(mesh, options);
  EXPECT_EQ(result.report.status, Status::invalid_input);
  EXPECT_NE(result.report.message.find("must differ"), std::string::npos) << result.report.message;
  options.pin_second = mesh.vertex_count();
  result = lscm(mesh, options);
  EXPECT_EQ(result.report.status, Status::invalid_input);
  EXPECT_NE(result.report.message.find(std::to_string(mesh.vertex_count())), std::string::npos);
  EXPECT_EQ(result.uv.rows(), 0);
}

TEST(Lscm, ReusableSolverFollowsNewGeometry) {
  const Mesh mesh = demo_surface(8);
  LscmSolver solver(mesh, raw_options());
  ASSERT_TRUE(solver.setup_report().ok()) << solver.setup_report().message;
  const MapResult first = solver.solve();
  ASSERT_EQ(first.report.status, Status::ok);
  // Conformal maps commute with scaling; the pins move apart with the surface.
  solver.update_geometry(2.5 * mesh.vertices);
  const MapResult scaled = solver.solve();
  ASSERT_EQ(scaled.report.status, Status::ok);
  EXPECT_LT((scaled.uv - 2.5 * first.uv).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(Lscm, TwoRunsGiveIdenticalBitsAndNormalizationIsCounterClockwise) {
  const Mesh mesh = demo_surface(10);
  const MapResult first = lscm(mesh), second = lscm(mesh);
  ASSERT_EQ(first.report.status, Status::ok) << first.report.message;
  EXPECT_EQ(first.uv, second.uv);
  EXPECT_EQ(first.report.flipped_triangles, 0);
}

TEST(Lscm, ClosedMeshIsNotADiskAndCancellationWorks) {
  const MapResult closed = lscm(octahedron());
  EXPECT_EQ(closed.report.status, Status::not_a_disk);
  EXPECT_NE(closed.report.message.find("harmonia cut"), std::string::npos);
  LscmOptions options;
  options.solver.progress = [](const Progress& progress) { return progress.stage != "solve"; };
  const MapResult cancelled = lscm(hemisphere(4), options);
  EXPECT_EQ(cancelled.report.status, Status::cancelled);
  EXPECT_EQ(cancelled.uv.rows(), 0);
}

// The conformal energy assembled the textbook way (Levy et al. 2002): per triangle, in its own
// orthonormal frame, two residual rows sqrt(area) (grad u + rot90(grad v)) over the unknowns
// u_0..u_{V-1}, v_0..v_{V-1}; the quadratic form is M^T M. Zero-area triangles carry no rows.
Eigen::SparseMatrix<double> residual_rows_normal_matrix(const Mesh& mesh) {
  const int vertex_count = mesh.vertex_count();
  std::vector<Eigen::Triplet<double>> entries;
  for (int f = 0; f < mesh.face_count(); ++f) {
    const Eigen::Vector3d p0 = mesh.vertices.row(mesh.faces(f, 0));
    const Eigen::Vector3d p1 = mesh.vertices.row(mesh.faces(f, 1));
    const Eigen::Vector3d p2 = mesh.vertices.row(mesh.faces(f, 2));
    const Eigen::Vector3d normal = (p1 - p0).cross(p2 - p0);
    const double area = 0.5 * normal.norm();
    if (!(area > 0.0)) continue;
    const Eigen::Vector3d x_axis = (p1 - p0).normalized();
    const Eigen::Vector3d y_axis = normal.normalized().cross(x_axis);
    const Eigen::Vector2d corner[3] = {
        Eigen::Vector2d::Zero(), Eigen::Vector2d((p1 - p0).dot(x_axis), 0.0),
        Eigen::Vector2d((p2 - p0).dot(x_axis), (p2 - p0).dot(y_axis))};
    for (int k = 0; k < 3; ++k) {
      // grad phi_k = rot90(e_k) / (2 area), e_k the edge opposite corner k.
      const Eigen::Vector2d edge = corner[(k + 2) % 3] - corner[(k + 1) % 3];
      const Eigen::Vector2d gradient = Eigen::Vector2d(-edge.y(), edge.x()) / (2.0 * area);
      const Eigen::Vector2d rotated = Eigen::Vector2d(-gradient.y(), gradient.x());
      const double weight = std::sqrt(area);
      const int vertex = mesh.faces(f, k);
      entries.emplace_back(2 * f, vertex, weight * gradient.x());
      entries.emplace_back(2 * f + 1, vertex, weight * gradient.y());
      entries.emplace_back(2 * f, vertex_count + vertex, weight * rotated.x());
      entries.emplace_back(2 * f + 1, vertex_count + vertex, weight * rotated.y());
    }
  }
  Eigen::SparseMatrix<double> rows(2 * mesh.face_count(), 2 * vertex_count);
  rows.setFromTriplets(entries.begin(), entries.end());
  return Eigen::SparseMatrix<double>(rows.transpose() * rows);
}

TEST(Lscm, QuadraticFormEqualsResidualRowsNormalMatrix) {
  // The assembled form [L N; N^T L] (two cotangent Laplacians and the boundary area coupling)
  // must be the very quadratic form of the residual rows, up to rounding.
  Mesh collapsed = planar_disk(6, 0.2);
  // Vertex 8 moved onto its neighbour 1 (exactly): the two triangles on edge 1-8 get zero area,
  // so interior edges beside them carry area coupling too.
  collapsed.vertices.row(8) = collapsed.vertices.row(1);
  int zero_area_faces = 0;
  for (int f = 0; f < collapsed.face_count(); ++f) {
    const Eigen::Vector3d a = collapsed.vertices.row(collapsed.faces(f, 0));
    const Eigen::Vector3d b = collapsed.vertices.row(collapsed.faces(f, 1));
    const Eigen::Vector3d c = collapsed.vertices.row(collapsed.faces(f, 2));
    if ((b - a).cross(c - a).norm() == 0.0) ++zero_area_faces;
  }
  ASSERT_EQ(zero_area_faces, 2);
  const std::pair<const char*, Mesh> meshes[] = {{"hemisphere", hemisphere(6)},
                                                 {"demo surface", demo_surface(12)},
                                                 {"jittered disk", planar_disk(7, 0.3)},
                                                 {"disk with zero-area triangles", collapsed}};
  for (const auto& [name, mesh] : meshes) {
    const Eigen::SparseMatrix<double> expected = residual_rows_normal_matrix(mesh);
    const Eigen::SparseMatrix<double> assembled =
        detail::lscm_quadratic_form(mesh, boundary_loops(mesh).front());
    ASSERT_EQ(assembled.rows(), expected.rows()) << name;
    const double scale = Eigen::MatrixXd(expected).cwiseAbs().maxCoeff();
    const double difference = Eigen::MatrixXd(assembled - expected).cwiseAbs().maxCoeff();
    EXPECT_LT(difference, 1e-12 * scale) << name << ": largest entry difference " << difference;
    // Symmetric, and the coupling block only where the energy needs it (not on every edge).
    EXPECT_EQ(Eigen::MatrixXd(assembled - Eigen::SparseMatrix<double>(assembled.transpose()))
                  .cwiseAbs()
                  .maxCoeff(),
              0.0)
        << name;
    EXPECT_LT(assembled.nonZeros(), expected.nonZeros()) << name;
  }
}

}  // namespace
}  // namespace harmonia
