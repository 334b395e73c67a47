// From corner angles to UVs: both reconstructions reproduce planar meshes and developable
// surfaces exactly (up to similarity), least squares spreads the error of noisy angles better
// than greedy, bad angles are rejected naming the face, and the ABF target angles of every corpus
// disk give finite UVs.
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdint>
#include <numbers>
#include <set>
#include <utility>
#include <string>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "abf/angle_reconstruction_least_squares.h"
#include "harmonia/angles_to_uv.h"
#include "harmonia/io.h"
#include "harmonia/procedural.h"
#include "harmonia/topology.h"
#include "support/test_support.h"
#ifdef HARMONIA_HAVE_VULKAN
#include "support/vulkan_test_support.h"
#endif

namespace harmonia {
namespace {

using Complex = std::complex<double>;

// The corner angles of a 3D mesh (#F x 3), from atan2(|cross|, dot): accurate for every angle.
Eigen::MatrixX3d corner_angles(const Mesh& mesh) {
  Eigen::MatrixX3d angles(mesh.face_count(), 3);
  for (int f = 0; f < mesh.face_count(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d corner = mesh.vertices.row(mesh.faces(f, k));
      const Eigen::Vector3d next = mesh.vertices.row(mesh.faces(f, (k + 1) % 3)).transpose() - corner;
      const Eigen::Vector3d prev = mesh.vertices.row(mesh.faces(f, (k + 2) % 3)).transpose() - corner;
      angles(f, k) = std::atan2(next.cross(prev).norm(), next.dot(prev));
    }
  }
  return angles;
}

// The corner angles of a planar layout, the same way.
Eigen::MatrixX3d uv_corner_angles(const Mesh& mesh, const Eigen::MatrixX2d& uv) {
  Mesh planar = mesh;
  planar.vertices = Eigen::MatrixX3d::Zero(uv.rows(), 3);
  planar.vertices.leftCols<2>() = uv;
  return corner_angles(planar);
}

// Largest distance between `target` and the least-squares similarity image of `source`
// (z -> s z + t with complex s: rotation and uniform scale, no mirror), relative to the extent of
// `target`.
double relative_similarity_error(const Eigen::MatrixX2d& source, const Eigen::MatrixX2d& target) {
  const Eigen::RowVector2d source_mean = source.colwise().mean();
  const Eigen::RowVector2d target_mean = target.colwise().mean();
  const auto centred = [](const Eigen::MatrixX2d& points, const Eigen::RowVector2d& mean,
                          Eigen::Index v) {
    return Complex(points(v, 0) - mean.x(), points(v, 1) - mean.y());
  };
  Complex numerator = 0.0;
  double denominator = 0.0;
  for (Eigen::Index v = 0; v < source.rows(); ++v) {
    numerator += std::conj(centred(source, source_mean, v)) * centred(target, target_mean, v);
    denominator += std::norm(centred(source, source_mean, v));
  }
  const Complex scale = numerator / denominator;
  double worst = 0.0;
  for (Eigen::Index v = 0; v < source.rows(); ++v)
    worst = std::max(worst, std::abs(scale * centred(source, source_mean, v) -
                                     centred(target, target_mean, v)));
  const double extent = (target.colwise().maxCoeff() - target.colwise().minCoeff()).maxCoeff();
  return worst / extent;
}

// A deterministic value in [-1, 1] per index (a hash, the same on every platform).
double signed_noise(std::uint64_t index) {
  std::uint64_t x = index * 0x9E3779B97F4A7C15ull + 0x632BE59BD9B4E019ull;
  x ^= x >> 30;
  x *= 0xBF58476D1CE4E5B9ull;
  x ^= x >> 27;
  x *= 0x94D049BB133111EBull;
  x ^= x >> 31;
  return static_cast<double>(x >> 11) / static_cast<double>(1ull << 52) - 1.0;
}

AnglesToUvOptions options_for(AngleReconstruction method,
                              UvNormalization normalization = UvNormalization::none) {
  AnglesToUvOptions options;
  options.method = method;
  options.normalization = normalization;
  options.solver.backend = BackendChoice::cpu;
  return options;
}

const AngleReconstruction kBothMethods[] = {AngleReconstruction::least_squares,
                                            AngleReconstruction::greedy};

std::string name_of(AngleReconstruction method) {
  return method == AngleReconstruction::least_squares ? "least squares" : "greedy";
}

TEST(AnglesToUv, PlanarMeshIsReproducedUpToSimilarity) {
  const Mesh mesh = planar_disk(12, 0.3);
  const Eigen::MatrixX2d original = mesh.vertices.leftCols<2>();
  for (const AngleReconstruction method : kBothMethods) {
    const MapResult result = angles_to_uv(mesh, corner_angles(mesh), options_for(method));
    ASSERT_TRUE(result.report.ok()) << name_of(method) << ": " << result.report.message;
    EXPECT_LT(relative_similarity_error(result.uv, original), 1e-9) << name_of(method);
    EXPECT_EQ(result.report.flipped_triangles, 0);
    EXPECT_EQ(result.report.boundary_self_intersections, 0);
  }
}

TEST(AnglesToUv, BothMethodsPutThePinsAtTheSamePlaces) {
  // Raw layouts (no normalization) share a frame: pin one at the origin, pin two at (d, 0) with
  // d their 3D distance. For consistent angles both layouts are then the same points.
  const Mesh mesh = planar_disk(8, 0.25);
  AnglesToUvOptions least_squares = options_for(AngleReconstruction::least_squares);
  least_squares.pin_first = 0;
  least_squares.pin_second = 17;
  AnglesToUvOptions greedy = least_squares;
  greedy.method = AngleReconstruction::greedy;
  const MapResult a = angles_to_uv(mesh, corner_angles(mesh), least_squares);
  const MapResult b = angles_to_uv(mesh, corner_angles(mesh), greedy);
  ASSERT_TRUE(a.report.ok()) << a.report.message;
  ASSERT_TRUE(b.report.ok()) << b.report.message;
  const double distance = (mesh.vertices.row(0) - mesh.vertices.row(17)).norm();
  EXPECT_NEAR(a.uv(0, 0), 0.0, 1e-15);
  EXPECT_NEAR(a.uv(0, 1), 0.0, 1e-15);
  EXPECT_NEAR(a.uv(17, 0), distance, 1e-15);
  EXPECT_NEAR(a.uv(17, 1), 0.0, 1e-15);
  // The input is planar and already in the pins' frame up to a rigid motion: compare lengths.
  EXPECT_LT((a.uv - b.uv).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT(relative_similarity_error(a.uv, mesh.vertices.leftCols<2>()), 1e-9);
}

TEST(AnglesToUv, DevelopableStripFlattensIsometrically) {
  // The 3D angles of a rolled-up rectangle are those of the flat one: with the default
  // normalization (UV area = 3D area) every edge keeps its 3D length.
  const Mesh strip = developable_strip(30, 8, 3.0, 0.8, 0.7);
  for (const AngleReconstruction method : kBothMethods) {
    const MapResult result =
        angles_to_uv(strip, corner_angles(strip),
                     options_for(method, UvNormalization::match_surface_area));
    ASSERT_TRUE(result.report.ok()) << name_of(method) << ": " << result.report.message;
    double worst = 0.0;
    for (int f = 0; f < strip.face_count(); ++f) {
      for (int k = 0; k < 3; ++k) {
        const int a = strip.faces(f, k), b = strip.faces(f, (k + 1) % 3);
        const double length_3d = (strip.vertices.row(a) - strip.vertices.row(b)).norm();
        const double length_uv = (result.uv.row(a) - result.uv.row(b)).norm();
        worst = std::max(worst, std::abs(length_uv - length_3d) / length_3d);
      }
    }
    EXPECT_LT(worst, 1e-9) << name_of(method);
    EXPECT_EQ(result.report.flipped_triangles, 0);
  }
}

TEST(AnglesToUv, LeastSquaresSpreadsAngleNoiseBetterThanGreedy) {
  // Angles of a planar mesh with up to 0.02 rad of noise each: no layout has them exactly.
  // Least squares balances the error; greedy piles it into the faces that close the fans.
  const Mesh mesh = planar_disk(16, 0.3);
  const Eigen::MatrixX3d exact = corner_angles(mesh);
  Eigen::MatrixX3d noisy = exact;
  for (int f = 0; f < mesh.face_count(); ++f)
    for (int k = 0; k < 3; ++k) noisy(f, k) += 0.02 * signed_noise(3 * f + k);
  double rms[2] = {0.0, 0.0}, worst[2] = {0.0, 0.0};
  for (int m = 0; m < 2; ++m) {
    const MapResult result = angles_to_uv(mesh, noisy, options_for(kBothMethods[m]));
    ASSERT_TRUE(result.uv.allFinite()) << name_of(kBothMethods[m]) << ": " << result.report.message;
    const Eigen::MatrixX3d error = uv_corner_angles(mesh, result.uv) - exact;
    rms[m] = std::sqrt(error.squaredNorm() / static_cast<double>(error.size()));
    worst[m] = error.cwiseAbs().maxCoeff();
  }
  // Both are near the exact angles, least squares clearly nearer (RMS and worst corner).
  EXPECT_LT(rms[0], 0.02);
  EXPECT_LT(rms[0], 0.5 * rms[1]) << "least squares " << rms[0] << ", greedy " << rms[1];
  EXPECT_LT(worst[0], worst[1]) << "least squares " << worst[0] << ", greedy " << worst[1];
}

// The sine-law normal matrix assembled the direct way: every face's weighted residual written as
// two real rows (real and imaginary part) over the unknowns [u; v], Q = sum_f w_f (row row^T).
Eigen::MatrixXd weighted_residual_normal_matrix(const Mesh& mesh, const Eigen::MatrixX3d& angles) {
  const int vertex_count = mesh.vertex_count();
  Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(2 * vertex_count, 2 * vertex_count);
  for (int f = 0; f < mesh.face_count(); ++f) {
    const Eigen::Vector3d face_angles = angles.row(f).transpose();
    const detail::SineLawRelation relation =
        detail::sine_law_relation(face_angles, detail::largest_sine_corner(face_angles));
    // r_f = p_placed - p_anchor - factor (p_along - p_anchor).
    Complex coefficient[3];
    coefficient[relation.placed] = 1.0;
    coefficient[relation.anchor] = relation.factor - 1.0;
    coefficient[relation.along] = -relation.factor;
    Eigen::VectorXd real_row = Eigen::VectorXd::Zero(2 * vertex_count);
    Eigen::VectorXd imaginary_row = Eigen::VectorXd::Zero(2 * vertex_count);
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.faces(f, k);
      // c (u + i v) = (Re c u - Im c v) + i (Im c u + Re c v).
      real_row[v] += coefficient[k].real();
      real_row[vertex_count + v] -= coefficient[k].imag();
      imaginary_row[v] += coefficient[k].imag();
      imaginary_row[vertex_count + v] += coefficient[k].real();
    }
    const double weight = detail::sine_law_weight(relation);
    normal += weight * real_row * real_row.transpose();
    normal += weight * imaginary_row * imaginary_row.transpose();
  }
  return normal;
}

TEST(AnglesToUv, ConformalFormEqualsTheWeightedSineLawNormalMatrix) {
  // Noisy angles (no face sums to pi, so the reference triangles' angles are not the given ones)
  // and one needle face whose weight is capped: the LSCM-structured matrix is still exactly the
  // weighted normal matrix of the per-face sine-law residuals.
  const Mesh mesh = planar_disk(5, 0.25);
  Eigen::MatrixX3d angles = corner_angles(mesh);
  for (int f = 0; f < mesh.face_count(); ++f)
    for (int k = 0; k < 3; ++k) angles(f, k) += 0.05 * signed_noise(7 * f + k);
  const int needle = 9;
  angles.row(needle) << 1e-8, 1.2, std::numbers::pi - 1.2 - 1e-8;
  const Eigen::MatrixXd expected = weighted_residual_normal_matrix(mesh, angles);
  const Eigen::MatrixXd actual = Eigen::MatrixXd(detail::sine_law_conformal_form(mesh, angles));
  const double scale = expected.cwiseAbs().maxCoeff();
  EXPECT_LT((actual - expected).cwiseAbs().maxCoeff(), 1e-12 * scale);

  // Without capped faces u and v are coupled on the boundary edges only (2 entries per edge in
  // each off-diagonal block), with the LSCM values -1/2 (edge direction) and +1/2.
  const Eigen::MatrixX3d exact = corner_angles(mesh);
  const Eigen::SparseMatrix<double> form = detail::sine_law_conformal_form(mesh, exact);
  const int vertex_count = mesh.vertex_count();
  const std::vector<int> loop = boundary_loops(mesh).front();
  Eigen::MatrixXd boundary_coupling = Eigen::MatrixXd::Zero(vertex_count, vertex_count);
  for (std::size_t k = 0; k < loop.size(); ++k) {
    const int from = loop[k], to = loop[(k + 1) % loop.size()];
    boundary_coupling(from, to) -= 0.5;
    boundary_coupling(to, from) += 0.5;
  }
  const Eigen::MatrixXd dense = Eigen::MatrixXd(form);
  EXPECT_EQ(
      (dense.topRightCorner(vertex_count, vertex_count) - boundary_coupling).cwiseAbs().maxCoeff(),
      0.0);
  EXPECT_EQ((dense.bottomLeftCorner(vertex_count, vertex_count) + boundary_coupling)
                .cwiseAbs()
                .maxCoeff(),
            0.0);
  long coupling_entries = 0;
  for (int column = 0; column < 2 * vertex_count; ++column)
    for (Eigen::SparseMatrix<double>::InnerIterator entry(form, column); entry; ++entry)
      if ((column < vertex_count) != (entry.row() < vertex_count)) ++coupling_entries;
  EXPECT_EQ(coupling_entries, 4 * static_cast<long>(loop.size()));
  // And both diagonal blocks are the same cotangent Laplacian (rows summing to zero).
  const Eigen::MatrixXd laplacian = dense.topLeftCorner(vertex_count, vertex_count);
  EXPECT_EQ((dense.bottomRightCorner(vertex_count, vertex_count) - laplacian).cwiseAbs().maxCoeff(),
            0.0);
  EXPECT_LT(laplacian.rowwise().sum().cwiseAbs().maxCoeff(),
            1e-12 * laplacian.diagonal().maxCoeff());
}

TEST(AnglesToUv, FormPatternComesWithoutItsValues) {
  // The analysis ahead of the final angles reads SineLawFormAssembler::pattern(): the same
  // stored entries as assemble() for the same angles, with a capped needle face (N lives on its
  // edges too), a face with a small angle that is not capped (its share needs a sine), and L's
  // whole vertex adjacency stored.
  const Mesh mesh = planar_disk(5, 0.25);
  Eigen::MatrixX3d angles = corner_angles(mesh);
  for (int f = 0; f < mesh.face_count(); ++f)
    for (int k = 0; k < 3; ++k) angles(f, k) += 0.05 * signed_noise(11 * f + k);
  angles.row(9) << 1e-8, 1.2, std::numbers::pi - 1.2 - 1e-8;   // Capped.
  angles.row(20) << 0.004, 1.4, std::numbers::pi - 1.404;       // Small, not capped.
  const detail::SineLawFormAssembler assembler(mesh);
  const Eigen::SparseMatrix<double> form = assembler.assemble(angles);
  const Eigen::SparseMatrix<double> pattern = assembler.pattern(angles);
  ASSERT_EQ(pattern.rows(), form.rows());
  ASSERT_EQ(pattern.nonZeros(), form.nonZeros());
  EXPECT_TRUE(std::equal(form.outerIndexPtr(), form.outerIndexPtr() + form.outerSize() + 1,
                         pattern.outerIndexPtr()));
  EXPECT_TRUE(std::equal(form.innerIndexPtr(), form.innerIndexPtr() + form.nonZeros(),
                         pattern.innerIndexPtr()));

  const int vertex_count = mesh.vertex_count();
  const auto stored_in_block = [&](const Eigen::SparseMatrix<double>& matrix, bool u_rows,
                                   bool u_columns) {
    long count = 0;
    for (int column = 0; column < 2 * vertex_count; ++column)
      for (Eigen::SparseMatrix<double>::InnerIterator entry(matrix, column); entry; ++entry)
        if ((column < vertex_count) == u_columns && (entry.row() < vertex_count) == u_rows)
          ++count;
    return count;
  };
  // L: every vertex pair that shares a face, and the diagonal.
  std::set<std::pair<int, int>> adjacent;
  for (int f = 0; f < mesh.face_count(); ++f)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) adjacent.emplace(mesh.faces(f, i), mesh.faces(f, j));
  EXPECT_EQ(stored_in_block(form, true, true), static_cast<long>(adjacent.size()));
  EXPECT_EQ(stored_in_block(form, false, false), static_cast<long>(adjacent.size()));
  // N: the boundary edges and the capped face's interior edges, both directions.
  const long boundary_edges = static_cast<long>(boundary_loops(mesh).front().size());
  long interior_needle_edges = 0;
  for (int i = 0; i < 3; ++i) {
    const int a = mesh.faces(9, i), b = mesh.faces(9, (i + 1) % 3);
    int faces_on_edge = 0;
    for (int f = 0; f < mesh.face_count(); ++f)
      for (int k = 0; k < 3; ++k)
        if ((mesh.faces(f, k) == a && mesh.faces(f, (k + 1) % 3) == b) ||
            (mesh.faces(f, k) == b && mesh.faces(f, (k + 1) % 3) == a))
          ++faces_on_edge;
    if (faces_on_edge == 2) ++interior_needle_edges;
  }
  ASSERT_GT(interior_needle_edges, 0);
  EXPECT_EQ(stored_in_block(form, true, false), 2 * (boundary_edges + interior_needle_edges));
  // The pattern's L holds zeros and its N the form's values.
  for (int column = 0; column < 2 * vertex_count; ++column)
    for (Eigen::SparseMatrix<double>::InnerIterator entry(pattern, column); entry; ++entry)
      if ((column < vertex_count) == (entry.row() < vertex_count)) {
        EXPECT_EQ(entry.value(), 0.0);
      } else {
        EXPECT_EQ(entry.value(), form.coeff(entry.row(), column));
      }
}

TEST(AnglesToUv, NeedleReferenceTriangleKeepsTheLayoutFinite) {
  // A valid but extreme angle (1e-10 rad, inconsistent with its neighbours): uncapped, its weight
  // would be 5e9; capped (kSmallestReferenceHeight) the system stays well conditioned and the
  // layout finite, with the normal equations solved accurately.
  const Mesh mesh = planar_disk(10, 0.2);
  Eigen::MatrixX3d angles = corner_angles(mesh);
  const int needle = mesh.face_count() / 2;
  angles.row(needle) << 1e-10, 1.0, std::numbers::pi - 1.0 - 1e-10;
  const MapResult result =
      angles_to_uv(mesh, angles, options_for(AngleReconstruction::least_squares));
  EXPECT_TRUE(result.report.ok() || result.report.status == Status::flipped_triangles)
      << result.report.message;
  ASSERT_EQ(result.uv.rows(), mesh.vertex_count()) << result.report.message;
  EXPECT_TRUE(result.uv.allFinite());
  EXPECT_LT(result.report.residual, 1e-8);
}

TEST(AnglesToUv, InvalidAnglesAreRejectedNamingTheFace) {
  const Mesh mesh = planar_disk(4);
  const Eigen::MatrixX3d good = corner_angles(mesh);
  const auto expect_rejected = [&](const Eigen::MatrixX3d& angles, const std::string& fragment) {
    for (const AngleReconstruction method : kBothMethods) {
      const MapResult result = angles_to_uv(mesh, angles, options_for(method));
      EXPECT_EQ(result.report.status, Status::invalid_input) << name_of(method);
      EXPECT_NE(result.report.message.find(fragment), std::string::npos)
          << name_of(method) << ": " << result.report.message;
      EXPECT_EQ(result.uv.rows(), 0);
    }
  };
  expect_rejected(good.topRows(good.rows() - 1),
                  "expected one row of 3 angles per face (" + std::to_string(mesh.face_count()));
  Eigen::MatrixX3d bad = good;
  bad(7, 1) = std::nan("");
  expect_rejected(bad, "face 7 at corner 1 (vertex " + std::to_string(mesh.faces(7, 1)) +
                           ") is not finite");
  bad = good;
  bad(11, 2) = 0.0;
  expect_rejected(bad, "face 11 at corner 2");
  bad = good;
  bad(3, 0) = std::numbers::pi;
  expect_rejected(bad, "face 3 at corner 0");
  bad = good;
  bad(5, 0) = -0.5;
  expect_rejected(bad, "angles must lie in (0, pi)");
}

TEST(AnglesToUv, NonDisksAndBadPinsAreRejected) {
  const Mesh closed = hemisphere(4);
  Mesh sphere = closed;  // Two hemispheres glued along the equator: a closed surface.
  {
    const int vertex_count = closed.vertex_count();
    const std::vector<int> loop = boundary_loops(closed).front();
    std::vector<int> mirror(static_cast<std::size_t>(vertex_count));
    int next = vertex_count;
    std::vector<Eigen::RowVector3d> extra;
    for (int v = 0; v < vertex_count; ++v) {
      if (std::find(loop.begin(), loop.end(), v) != loop.end()) {
        mirror[v] = v;
      } else {
        mirror[v] = next++;
        Eigen::RowVector3d p = closed.vertices.row(v);
        p.z() = -p.z();
        extra.push_back(p);
      }
    }
    sphere.vertices.conservativeResize(next, 3);
    for (std::size_t k = 0; k < extra.size(); ++k) sphere.vertices.row(vertex_count + k) = extra[k];
    sphere.faces.conservativeResize(2 * closed.face_count(), 3);
    for (int f = 0; f < closed.face_count(); ++f)
      sphere.faces.row(closed.face_count() + f) << mirror[closed.faces(f, 0)],
          mirror[closed.faces(f, 2)], mirror[closed.faces(f, 1)];
  }
  const MapResult not_disk =
      angles_to_uv(sphere, corner_angles(sphere), options_for(AngleReconstruction::least_squares));
  EXPECT_EQ(not_disk.report.status, Status::not_a_disk) << not_disk.report.message;
  EXPECT_NE(not_disk.report.message.find("harmonia cut"), std::string::npos)
      << not_disk.report.message;

  const Mesh mesh = planar_disk(4);
  AnglesToUvOptions options = options_for(AngleReconstruction::least_squares);
  options.pin_first = 3;
  options.pin_second = 3;
  MapResult result = angles_to_uv(mesh, corner_angles(mesh), options);
  EXPECT_EQ(result.report.status, Status::invalid_input);
  EXPECT_NE(result.report.message.find("must differ (both are 3)"), std::string::npos)
      << result.report.message;
  options.pin_second = mesh.vertex_count();
  result = angles_to_uv(mesh, corner_angles(mesh), options);
  EXPECT_EQ(result.report.status, Status::invalid_input);
  EXPECT_NE(result.report.message.find("pinned vertex " + std::to_string(mesh.vertex_count()) +
                                       " is out of range"),
            std::string::npos)
      << result.report.message;
}

TEST(AnglesToUv, ReportsPhasesAndHonoursCancellation) {
  const Mesh mesh = planar_disk(6, 0.2);
  AnglesToUvOptions options = options_for(AngleReconstruction::least_squares);
  const MapResult result = angles_to_uv(mesh, corner_angles(mesh), options);
  ASSERT_TRUE(result.report.ok()) << result.report.message;
  std::vector<std::string> phases;
  for (const PhaseTiming& timing : result.report.timings) phases.push_back(timing.phase);
  const std::vector<std::string> expected{"validation", "assembly", "analysis", "factorization",
                                          "solve",      "normalize", "validity"};
  EXPECT_EQ(phases, expected);
  EXPECT_FALSE(result.report.solver.empty());
  EXPECT_LT(result.report.residual, 1e-10);

  options.solver.progress = [](const Progress& progress) {
    return progress.stage != "factorization";
  };
  const MapResult cancelled = angles_to_uv(mesh, corner_angles(mesh), options);
  EXPECT_EQ(cancelled.report.status, Status::cancelled);
  EXPECT_EQ(cancelled.uv.rows(), 0);
}

// The ABF target angles (abf.h: the 3D angles rescaled to sum 2 pi around interior vertices),
// computed here independently: they are not the angles of any planar layout, yet both
// reconstructions must give finite UVs (flips are allowed: the angles are inconsistent).
Eigen::MatrixX3d rescaled_target_angles(const Mesh& mesh) {
  Eigen::MatrixX3d angles = corner_angles(mesh);
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(mesh.vertex_count());
  for (int f = 0; f < mesh.face_count(); ++f)
    for (int k = 0; k < 3; ++k) sum[mesh.faces(f, k)] += angles(f, k);
  std::vector<char> on_boundary(static_cast<std::size_t>(mesh.vertex_count()), 0);
  for (const auto& loop : boundary_loops(mesh))
    for (const int v : loop) on_boundary[v] = 1;
  for (int f = 0; f < mesh.face_count(); ++f)
    for (int k = 0; k < 3; ++k)
      if (!on_boundary[mesh.faces(f, k)]) angles(f, k) *= 2.0 * std::numbers::pi / sum[mesh.faces(f, k)];
  return angles;
}

TEST(AnglesToUv, CorpusTargetAnglesGiveFiniteUvs) {
  const auto meshes = testing::corpus_meshes("disk");
  if (meshes.empty()) HARMONIA_SKIP_WITHOUT_CORPUS("no corpus at " << testing::shared_data_dir());
  for (const auto& path : meshes) {
    const Mesh mesh = read_mesh(path);
    const Eigen::MatrixX3d targets = rescaled_target_angles(mesh);
    for (const AngleReconstruction method : kBothMethods) {
      const MapResult result =
          angles_to_uv(mesh, targets, options_for(method, UvNormalization::match_surface_area));
      EXPECT_TRUE(result.report.ok() || result.report.status == Status::flipped_triangles)
          << path.filename() << " " << name_of(method) << ": " << result.report.message;
      ASSERT_EQ(result.uv.rows(), mesh.vertex_count()) << path.filename() << " " << name_of(method);
      EXPECT_TRUE(result.uv.allFinite()) << path.filename() << " " << name_of(method);
      // Most faces come out nearly as asked: a sanity bound on the realised angles.
      const Eigen::MatrixX3d error = uv_corner_angles(mesh, result.uv) - targets;
      if (method == AngleReconstruction::least_squares) {
        EXPECT_LT(std::sqrt(error.squaredNorm() / static_cast<double>(error.size())), 0.2)
            << path.filename();
      }
    }
  }
}

#ifdef HARMONIA_HAVE_VULKAN
TEST(AnglesToUv, VulkanLeastSquaresMatchesTheCpu) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  for (const Mesh& mesh : {planar_disk(12, 0.3), developable_strip(24, 6, 3.0, 0.8, 0.7)}) {
    const Eigen::MatrixX3d angles = corner_angles(mesh);
    AnglesToUvOptions options = options_for(AngleReconstruction::least_squares);
    const MapResult cpu = angles_to_uv(mesh, angles, options);
    options.solver.backend = BackendChoice::vulkan;
    options.solver.vulkan_context = testing::vulkan_test_context();
    const MapResult gpu = angles_to_uv(mesh, angles, options);
    ASSERT_TRUE(cpu.report.ok()) << cpu.report.message;
    ASSERT_TRUE(gpu.report.ok()) << gpu.report.message;
    EXPECT_EQ(gpu.report.backend, BackendKind::vulkan);
    EXPECT_EQ(gpu.report.flipped_triangles, cpu.report.flipped_triangles);
    const double extent = (cpu.uv.colwise().maxCoeff() - cpu.uv.colwise().minCoeff()).maxCoeff();
    EXPECT_LT((gpu.uv - cpu.uv).cwiseAbs().maxCoeff() / extent, 1e-4);
  }
}
#endif

}  // namespace
}  // namespace harmonia
