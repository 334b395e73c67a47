// Surface editing along harmonic fields (thesis 8.3, 8.5): the identity edit returns the rest pose,
// a rigid motion of every handle with nothing fixed moves the mesh rigidly, a pure translation is
// the harmonic interpolation of the displacements, a bent bar's end turns with its handle, the
// corpus edits meet their constraints and come closer to converged ARAP than the translation-only
// baseline, frames reuse the one factorization, and bad regions are refused naming the problem.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>
#include <utility>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <gtest/gtest.h>

#include "harmonia/deformation_metrics.h"
#include "harmonia/edit_file.h"
#include "harmonia/io.h"
#include "harmonia/laplacian.h"
#include "harmonia/procedural.h"
#include "harmonia/surface_editor.h"
#include "support/test_support.h"

namespace harmonia {
namespace {

constexpr double eps = std::numeric_limits<double>::epsilon();

SurfaceEditOptions cpu_options() {
  SurfaceEditOptions options;
  options.solver.backend = BackendChoice::cpu;
  return options;
}

double diagonal(const Mesh& mesh) {
  return (mesh.vertices.colwise().maxCoeff() - mesh.vertices.colwise().minCoeff()).norm();
}

// The vertices of `mesh` whose coordinate `axis` is below `low` / above `high`.
std::vector<int> vertices_where(const Mesh& mesh, int axis, double low, double high) {
  std::vector<int> vertices;
  for (int v = 0; v < mesh.vertex_count(); ++v)
    if (mesh.vertices(v, axis) < low || mesh.vertices(v, axis) > high) vertices.push_back(v);
  return vertices;
}

std::vector<int> below(const Mesh& mesh, int axis, double value) {
  return vertices_where(mesh, axis, value, std::numeric_limits<double>::infinity());
}
std::vector<int> above(const Mesh& mesh, int axis, double value) {
  return vertices_where(mesh, axis, -std::numeric_limits<double>::infinity(), value);
}

Eigen::Vector3d centroid(const Mesh& mesh, const std::vector<int>& vertices) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const int v : vertices) sum += mesh.vertices.row(v).transpose();
  return sum / static_cast<double>(vertices.size());
}

// A closed-around, open-ended tube along x: `rings` rings of `around` vertices from x = 0 to
// x = length, radius `radius`; faces counter-clockwise seen from outside.
Mesh tube(int rings, int around, double length, double radius) {
  Mesh mesh;
  mesh.vertices.resize(static_cast<Eigen::Index>(rings) * around, 3);
  for (int r = 0; r < rings; ++r)
    for (int k = 0; k < around; ++k) {
      const double angle = 2.0 * std::numbers::pi * k / around;
      mesh.vertices.row(r * around + k) << length * r / (rings - 1), radius * std::cos(angle),
          radius * std::sin(angle);
    }
  mesh.faces.resize(2 * static_cast<Eigen::Index>(rings - 1) * around, 3);
  Eigen::Index f = 0;
  for (int r = 0; r + 1 < rings; ++r)
    for (int k = 0; k < around; ++k) {
      const int a = r * around + k, b = r * around + (k + 1) % around;
      const int c = a + around, d = b + around;
      mesh.faces.row(f++) << a, b, d;
      mesh.faces.row(f++) << a, d, c;
    }
  return mesh;
}

// The largest distance between the positions and `expected`, divided by the mesh's diagonal.
double worst_relative_distance(const Eigen::MatrixX3d& positions, const Eigen::MatrixX3d& expected,
                               const Mesh& mesh) {
  return (positions - expected).rowwise().norm().maxCoeff() / diagonal(mesh);
}

Eigen::Vector3d face_normal(const Eigen::MatrixX3d& positions, const Eigen::Vector3i& face) {
  const Eigen::Vector3d a = positions.row(face[0]), b = positions.row(face[1]), c = positions.row(face[2]);
  return (b - a).cross(c - a).normalized();
}

double angle_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

// The translation-only baseline, computed independently of the editor: rest + the harmonic
// interpolation (cotangent Laplacian, Eigen's LDLT of the free block) of the displacements that
// take every constrained vertex (targets: vertex -> position) to its target.
Eigen::MatrixX3d harmonic_interpolation(const Mesh& mesh, const std::vector<std::pair<int, Eigen::Vector3d>>& targets) {
  std::vector<int> free_index(static_cast<std::size_t>(mesh.vertex_count()), 0);
  Eigen::MatrixX3d displacement = Eigen::MatrixX3d::Zero(mesh.vertex_count(), 3);
  for (const auto& [v, target] : targets) {
    free_index[static_cast<std::size_t>(v)] = -1;
    displacement.row(v) = target.transpose() - mesh.vertices.row(v);
  }
  int free_count = 0;
  for (int& index : free_index)
    if (index == 0) index = free_count++;
  const Eigen::SparseMatrix<double> operator_matrix = laplacian(mesh, WeightScheme::cotangent);
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::MatrixX3d rhs = Eigen::MatrixX3d::Zero(free_count, 3);
  for (int column = 0; column < operator_matrix.outerSize(); ++column)
    for (Eigen::SparseMatrix<double>::InnerIterator it(operator_matrix, column); it; ++it) {
      const int row = free_index[static_cast<std::size_t>(it.row())];
      if (row < 0) continue;
      if (free_index[static_cast<std::size_t>(column)] >= 0)
        entries.emplace_back(row, free_index[static_cast<std::size_t>(column)], it.value());
      else
        rhs.row(row) -= it.value() * displacement.row(column);
    }
  Eigen::SparseMatrix<double> interior(free_count, free_count);
  interior.setFromTriplets(entries.begin(), entries.end());
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> factor(interior);
  const Eigen::MatrixX3d solved = factor.solve(rhs);
  Eigen::MatrixX3d positions = mesh.vertices + displacement;
  for (int v = 0; v < mesh.vertex_count(); ++v)
    if (free_index[static_cast<std::size_t>(v)] >= 0)
      positions.row(v) += solved.row(free_index[static_cast<std::size_t>(v)]);
  return positions;
}

TEST(SurfaceEditor, IdentityEditReturnsTheRestPose) {
  const Mesh mesh = unit_sphere(3);
  EditRegions regions;
  regions.fixed = below(mesh, 2, -0.5);
  regions.handles = {above(mesh, 2, 0.6)};
  SurfaceEditor editor(mesh, regions, cpu_options());
  ASSERT_TRUE(editor.setup_report().ok()) << editor.setup_report().message;
  SimilarityTransform identity;
  identity.center = centroid(mesh, regions.handles[0]);
  const SurfaceEditResult result = editor.deform({identity});
  ASSERT_TRUE(result.report.ok()) << result.report.message;
  // The load is L x_rest summed triangle by triangle: the solve returns x_rest up to the rounding
  // of a Cholesky solve of a Laplacian of a few hundred vertices (conditioning ~ #V), well below
  // 1e-12 of the diagonal.
  EXPECT_LT(worst_relative_distance(result.positions, mesh.vertices, mesh), 1e-12);
  EXPECT_EQ(result.report.flipped_triangles, 0);
}

// With nothing fixed, every field is 1 everywhere (the only constraint value is 1), so every
// triangle gets the handle's rotation and the Poisson solve reproduces the rigid motion.
TEST(SurfaceEditor, RigidMotionOfEveryHandleWithNothingFixedMovesTheMeshRigidly) {
  const Mesh mesh = unit_sphere(3);
  SimilarityTransform motion;
  motion.rotation = Eigen::AngleAxisd(1.2, Eigen::Vector3d(1.0, 2.0, -0.5).normalized());
  motion.center = Eigen::Vector3d(0.3, -0.2, 0.1);
  motion.translation = Eigen::Vector3d(2.0, -1.0, 0.5);
  Eigen::MatrixX3d expected(mesh.vertex_count(), 3);
  for (int v = 0; v < mesh.vertex_count(); ++v)
    expected.row(v) = motion.apply(mesh.vertices.row(v).transpose()).transpose();
  for (const int handle_count : {1, 2}) {
    EditRegions regions;
    regions.handles = {above(mesh, 2, 0.6)};
    if (handle_count == 2) regions.handles.push_back(below(mesh, 2, -0.6));
    SurfaceEditor editor(mesh, regions, cpu_options());
    ASSERT_TRUE(editor.setup_report().ok()) << editor.setup_report().message;
    const SurfaceEditResult result =
        editor.deform(std::vector<SimilarityTransform>(static_cast<std::size_t>(handle_count), motion));
    ASSERT_TRUE(result.report.ok()) << result.report.message;
    EXPECT_LT(worst_relative_distance(result.positions, expected, mesh), 1e-11)
        << handle_count << " handles";
  }
}

// The thesis' method alone (no rotation clusters): a translation has no rotation to propagate, so
// the result is rest + the harmonic interpolation of the constraint displacements, computed here
// independently (Eigen's LDLT of the cotangent Laplacian's free block).
TEST(SurfaceEditor, PureTranslationIsTheHarmonicInterpolationOfTheDisplacements) {
  const Mesh mesh = unit_sphere(3);
  EditRegions regions;
  regions.fixed = below(mesh, 2, -0.8);
  regions.handles = {above(mesh, 1, 0.7)};  // y > 0.7 and z < -0.8 cannot meet on the sphere
  const Eigen::Vector3d translation(0.1, 0.4, -0.2);
  SurfaceEditOptions thesis_blend = cpu_options();
  thesis_blend.rotation_clusters = 0;
  SurfaceEditor editor(mesh, regions, thesis_blend);
  const SurfaceEditResult dragged = editor.drag({translation});
  ASSERT_TRUE(dragged.report.ok()) << dragged.report.message;

  std::vector<std::pair<int, Eigen::Vector3d>> targets;
  for (const int v : regions.fixed) targets.emplace_back(v, mesh.vertices.row(v).transpose());
  for (const int v : regions.handles[0])
    targets.emplace_back(v, mesh.vertices.row(v).transpose() + translation);
  const Eigen::MatrixX3d expected = harmonic_interpolation(mesh, targets);
  // Two direct solves of the same well-conditioned system (#V ~ 600): rounding-level agreement.
  EXPECT_LT(worst_relative_distance(dragged.positions, expected, mesh), 1e-11);

  SimilarityTransform translated;
  translated.translation = translation;
  translated.center = Eigen::Vector3d(5.0, 5.0, 5.0);  // irrelevant without rotation or scale
  const SurfaceEditResult deformed = editor.deform({translated});
  EXPECT_LT(worst_relative_distance(deformed.positions, dragged.positions, mesh), 1e-14);
}

// A bar of length 10 along x, fixed below x = 1, its end above x = 9 a handle turned by
// `degrees` about the y axis through (6, 0, 0).
struct BentBar {
  Mesh mesh;
  EditRegions regions;
  SimilarityTransform bend;
};
BentBar bent_bar(int rings, int around, double degrees) {
  BentBar bar{tube(rings, around, 10.0, 0.5), {}, {}};
  bar.regions.fixed = below(bar.mesh, 0, 1.0);
  bar.regions.handles = {above(bar.mesh, 0, 9.0)};
  bar.bend.rotation = Eigen::AngleAxisd(degrees * std::numbers::pi / 180.0, Eigen::Vector3d::UnitY());
  bar.bend.center = Eigen::Vector3d(6.0, 0.0, 0.0);
  return bar;
}

// A bar fixed at one end whose other end turns by 90 degrees: the handle's faces turn with it,
// and so do the free faces next to the handle (their field is nearly 1), where the translation-only
// interpolation of the same targets shears them instead.
TEST(SurfaceEditor, BarBentBy90DegreesTurnsItsFarEnd) {
  const auto [bar, regions, bend] = bent_bar(81, 16, 90.0);
  SurfaceEditor editor(bar, regions, cpu_options());
  ASSERT_TRUE(editor.setup_report().ok()) << editor.setup_report().message;
  const SurfaceEditResult result = editor.deform({bend});
  ASSERT_TRUE(result.report.ok()) << result.report.message;
  EXPECT_EQ(result.report.flipped_triangles, 0);
  EXPECT_EQ(result.report.degenerate_triangles, 0);

  // The translation-only interpolation of the same targets, for comparison.
  std::vector<std::pair<int, Eigen::Vector3d>> targets;
  for (const int v : regions.fixed) targets.emplace_back(v, bar.vertices.row(v).transpose());
  for (const int v : regions.handles[0])
    targets.emplace_back(v, bend.apply(bar.vertices.row(v).transpose()));
  const Eigen::MatrixX3d translation_only = harmonic_interpolation(bar, targets);

  // The handle's faces turn by 90 degrees with their constrained corners. The free faces of the
  // ring next to the handle (field about 0.98) turn nearly as much; the translation-only
  // interpolation shears them instead, leaving their normals far from the turned ones.
  double worst_handle_error = 0.0, ring_error = 0.0, ring_error_translation_only = 0.0;
  int handle_faces = 0, ring_faces = 0;
  for (Eigen::Index f = 0; f < bar.faces.rows(); ++f) {
    const Eigen::Vector3i face = bar.faces.row(f);
    double lowest_x = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) lowest_x = std::min(lowest_x, bar.vertices(face[k], 0));
    const Eigen::Vector3d turned = bend.rotation * face_normal(bar.vertices, face);
    const double error = angle_between(face_normal(result.positions, face), turned);
    if (lowest_x > 9.0) {
      worst_handle_error = std::max(worst_handle_error, error);
      ++handle_faces;
    } else if (lowest_x > 8.8) {
      ring_error += error;
      ring_error_translation_only += angle_between(face_normal(translation_only, face), turned);
      ++ring_faces;
    }
  }
  ASSERT_GT(handle_faces, 0);
  ASSERT_GT(ring_faces, 0);
  const double degree = std::numbers::pi / 180.0;
  EXPECT_LT(worst_handle_error, degree);
  EXPECT_LT(ring_error, 0.25 * ring_error_translation_only)
      << "mean degrees: " << ring_error / ring_faces / degree << " against "
      << ring_error_translation_only / ring_faces / degree;
}

// A frame budget (SurfaceEditOptions::frame_budget) decides only how many refinement steps are
// made: whatever it allows, the positions are those of a fixed count of that many steps.
TEST(SurfaceEditor, AFrameBudgetMakesAsManyRefinementStepsAsFit) {
  const BentBar bar = bent_bar(41, 12, 60.0);  // named, not bound: the lambda below captures it
  const auto frame = [&](int steps, double budget) {
    SurfaceEditOptions options = cpu_options();
    options.refinement_steps = steps;
    options.frame_budget = budget;
    SurfaceEditor editor(bar.mesh, bar.regions, options);
    EXPECT_TRUE(editor.setup_report().ok()) << editor.setup_report().message;
    SurfaceEditResult result = editor.deform({bar.bend});
    EXPECT_TRUE(result.report.ok()) << result.report.message;
    return result;
  };
  const SurfaceEditResult harmonic = frame(0, 0.0);
  EXPECT_EQ(harmonic.refinement_steps, 0);

  // Shorter than the frame itself: the harmonic-field frame, no step.
  const SurfaceEditResult too_short = frame(0, 1e-9);
  EXPECT_EQ(too_short.refinement_steps, 0);
  EXPECT_EQ(too_short.positions, harmonic.positions);

  // An hour: the steps refinement_steps asks for, as without a budget.
  const SurfaceEditResult capped = frame(4, 3600.0);
  EXPECT_EQ(capped.refinement_steps, 4);
  EXPECT_EQ(capped.positions, frame(4, 0.0).positions);
  EXPECT_NE(capped.positions, harmonic.positions);

  // A fifth of a second, uncapped: a step on this bar takes well under a millisecond, so some
  // fit (but not the 10000 of the cap); the result is that of as many fixed steps.
  const SurfaceEditResult budgeted = frame(0, 0.2);
  EXPECT_GE(budgeted.refinement_steps, 1);
  EXPECT_LT(budgeted.refinement_steps, 10000);
  EXPECT_EQ(budgeted.positions, frame(budgeted.refinement_steps, 0.0).positions);

  for (const double wrong : {-1.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    SurfaceEditOptions options = cpu_options();
    options.frame_budget = wrong;
    const SurfaceEditor editor(bar.mesh, bar.regions, options);
    EXPECT_EQ(editor.setup_report().status, Status::invalid_input);
    EXPECT_NE(editor.setup_report().message.find("frame_budget"), std::string::npos) << editor.setup_report().message;
  }
}

// RMS vertex distance divided by the reference's bounding-box diagonal (../shared/data/edit).
double rms_relative(const Eigen::MatrixX3d& positions, const Eigen::MatrixX3d& reference) {
  const double diagonal = (reference.colwise().maxCoeff() - reference.colwise().minCoeff()).norm();
  return std::sqrt((positions - reference).rowwise().squaredNorm().mean()) / diagonal;
}

// The edit cases: every constraint met to the last bit's rounding, no triangle turned over, and
// the quality classes against the translation-only harmonic baseline shipped with each
// case: where every handle rotates, at least 2x closer to converged ARAP; where the handles only
// translate, no farther; a limb rotated about its joint with a translation, 1.33x closer. The
// public cases (../shared/data/edit, libigl's references) and this project's own
// (tests/assets/edit: limbs turned about their joints on every closed corpus mesh with legs or arms,
// references by bench/corpus_edit_reference, which reproduces libigl's). The thesis' blend alone
// missed elephant-c (0.92x: the body between the limb and the fixed feet turned by a fraction of
// the limb's angle); the rotation clusters (the default) meet it, and with 8 of them per handle and
// 8 more, the two-handle cases too (cheburashka-b: 1.29x of 1.33 at 16 clusters, 1.41x at 24). One
// of the project's cases is still missed (issue 33: elephant-d 1.46x of 2): a known miss, asserted
// below its target so that it turns red when it starts passing.
TEST(SurfaceEditor, EditCasesMeetTheirConstraintsAndComeCloserToArap) {
  const std::filesystem::path public_folder = testing::shared_data_dir() / "edit";
  if (!std::filesystem::exists(public_folder)) HARMONIA_SKIP_WITHOUT_CORPUS("no " << public_folder);
  const std::filesystem::path own_folder = testing::assets_dir() / "edit";
  struct Case {
    const char* name;
    const std::filesystem::path& folder;
    double required_ratio;
    bool known_miss = false;
  };
  for (const Case& edit_case :
       {Case{"homer-a", public_folder, 1.0}, Case{"homer-b", public_folder, 2.0},
        Case{"homer-c", public_folder, 1.33}, Case{"elephant-a", public_folder, 1.0},
        Case{"elephant-b", public_folder, 2.0}, Case{"elephant-c", public_folder, 1.33},
        Case{"cheburashka-a", own_folder, 2.0}, Case{"cheburashka-b", own_folder, 1.33},
        Case{"cow-a", own_folder, 2.0}, Case{"cow-b", own_folder, 2.0},
        Case{"spot-a", own_folder, 2.0}, Case{"spot-b", own_folder, 2.0},
        Case{"homer-d", own_folder, 2.0}, Case{"elephant-d", own_folder, 2.0, true},
        Case{"elephant-e", own_folder, 2.0}}) {
    SCOPED_TRACE(edit_case.name);
    const std::string name = edit_case.name;
    const std::string mesh_name = name.substr(0, name.find('-'));
    const Mesh mesh = read_mesh(testing::shared_data_dir() / "closed" / (mesh_name + ".obj"));
    const EditDescription edit = read_edit_file(edit_case.folder / (name + ".json"), mesh);
    const SurfaceEditResult result = edit_surface(mesh, edit.regions, edit.transforms, cpu_options());
    ASSERT_TRUE(result.report.ok()) << result.report.message;
    EXPECT_EQ(result.report.flipped_triangles, 0);
    EXPECT_EQ(deformation_metrics(mesh, result.positions).turned_faces, 0);
    // Constrained vertices are placed, not solved for: their targets computed alike.
    double worst_constraint = 0.0;
    for (const int v : edit.regions.fixed)
      worst_constraint = std::max(worst_constraint, (result.positions.row(v) - mesh.vertices.row(v)).norm());
    for (std::size_t i = 0; i < edit.regions.handles.size(); ++i)
      for (const int v : edit.regions.handles[i])
        worst_constraint = std::max(
            worst_constraint, (result.positions.row(v).transpose() -
                               edit.transforms[i].apply(mesh.vertices.row(v).transpose())).norm());
    EXPECT_LE(worst_constraint, 1e-9 * diagonal(mesh));
    const Mesh reference = read_mesh(edit_case.folder / (name + ".arap500.obj"));
    const Mesh baseline = read_mesh(edit_case.folder / (name + ".harmonic.obj"));
    const double ours = rms_relative(result.positions, reference.vertices);
    const double theirs = rms_relative(baseline.vertices, reference.vertices);
    // The baseline file is another program's solve of the same equations: "no farther" within the
    // rounding of two solvers (1e-9 of the diagonal is far above it and far below any real
    // difference).
    if (edit_case.known_miss)
      EXPECT_GT(ours * edit_case.required_ratio, theirs + 1e-9)
          << "a known miss now meets its target: " << theirs / ours << "x; make it a required case";
    else
      EXPECT_LE(ours * edit_case.required_ratio, theirs + 1e-9) << ours << " against " << theirs;
  }
}

// Rotation clusters: a negative count is refused by name; with them (16) and without (0), a rigid
// motion of every constrained vertex moves the whole mesh rigidly.
TEST(SurfaceEditor, RotationClustersCanBeTurnedOffAndAreChecked) {
  const Mesh mesh = unit_sphere(3);
  EditRegions regions;
  regions.fixed = below(mesh, 2, -0.5);
  regions.handles = {above(mesh, 2, 0.6)};
  SurfaceEditOptions options = cpu_options();
  options.rotation_clusters = -1;
  const SurfaceEditor refused(mesh, regions, options);
  EXPECT_EQ(refused.setup_report().status, Status::invalid_input);
  EXPECT_NE(refused.setup_report().message.find("rotation_clusters"), std::string::npos);
  // A rigid motion of every constrained vertex alike: both ways give that motion of the whole mesh
  // (zero energy, an exact optimum), to the solves' rounding.
  SimilarityTransform rigid;
  rigid.rotation = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized());
  rigid.center = Eigen::Vector3d(0.2, -0.1, 0.3);
  rigid.translation = Eigen::Vector3d(0.3, 0.1, -0.2);
  EditRegions all_handles;
  all_handles.handles = {below(mesh, 2, -0.5), above(mesh, 2, 0.6)};
  for (const int clusters : {0, 16}) {
    options.rotation_clusters = clusters;
    const SurfaceEditResult result = edit_surface(mesh, all_handles, {rigid, rigid}, options);
    ASSERT_TRUE(result.report.ok()) << result.report.message;
    Eigen::MatrixX3d expected(mesh.vertex_count(), 3);
    for (int v = 0; v < mesh.vertex_count(); ++v) expected.row(v) = rigid.apply(mesh.vertices.row(v).transpose());
    EXPECT_LT(worst_relative_distance(result.positions, expected, mesh), 1e-10) << clusters << " clusters";
  }
}

TEST(SurfaceEditor, FramesReuseTheOneFactorization) {
  const Mesh mesh = unit_sphere(3);
  EditRegions regions;
  // Disjoint on the unit sphere: no point has two of z < -0.7, z > 0.6, y > 0.8.
  regions.fixed = below(mesh, 2, -0.7);
  regions.handles = {above(mesh, 2, 0.6), above(mesh, 1, 0.8)};
  SimilarityTransform first, second;
  first.rotation = Eigen::AngleAxisd(0.8, Eigen::Vector3d::UnitX());
  first.center = centroid(mesh, regions.handles[0]);
  second.translation = Eigen::Vector3d(0.2, 0.0, 0.1);
  second.scale = 1.3;
  second.center = centroid(mesh, regions.handles[1]);
  SurfaceEditor editor(mesh, regions, cpu_options());
  ASSERT_TRUE(editor.setup_report().ok()) << editor.setup_report().message;
  EXPECT_EQ(editor.factorization_count(), 1);
  SurfaceEditResult last;
  for (int k = 1; k <= 5; ++k) {
    last = editor.deform({first.partial(k / 5.0), second.partial(k / 5.0)});
    ASSERT_TRUE(last.report.ok()) << last.report.message;
    EXPECT_GT(last.timing.solve, 0.0);
  }
  EXPECT_EQ(editor.factorization_count(), 1);
  // The last frame equals a fresh editor's single frame of the full edit.
  const SurfaceEditResult fresh = edit_surface(mesh, regions, {first, second}, cpu_options());
  EXPECT_LT(worst_relative_distance(last.positions, fresh.positions, mesh), 1e-13);
  EXPECT_EQ(last.report.flipped_triangles, 0);
}

TEST(SurfaceEditor, FieldsArePartitionsOfUnityWithTheFixedSet) {
  const Mesh mesh = unit_sphere(3);
  EditRegions regions;
  regions.handles = {above(mesh, 2, 0.6), below(mesh, 2, -0.6)};
  SurfaceEditor editor(mesh, regions, cpu_options());
  ASSERT_TRUE(editor.setup_report().ok());
  // Without fixed vertices the handle fields sum to the harmonic function equal to 1 on every
  // constraint: 1 everywhere, up to the solve's rounding.
  const Eigen::VectorXd sum = editor.handle_fields().rowwise().sum();
  EXPECT_LT((sum.array() - 1.0).abs().maxCoeff(), 1e3 * eps);
  for (const int v : regions.handles[0]) EXPECT_EQ(editor.handle_fields()(v, 0), 1.0);
  for (const int v : regions.handles[0]) EXPECT_EQ(editor.handle_fields()(v, 1), 0.0);
}

TEST(SurfaceEditor, BadRegionsAreRefusedNamingTheProblem) {
  const Mesh mesh = unit_sphere(2);
  const auto setup_message = [&mesh](const EditRegions& regions) {
    SurfaceEditor editor(mesh, regions, cpu_options());
    EXPECT_EQ(editor.setup_report().status, Status::invalid_input);
    const SurfaceEditResult result = editor.deform(std::vector<SimilarityTransform>(regions.handles.size()));
    EXPECT_EQ(result.report.status, Status::invalid_input);
    EXPECT_EQ(result.positions.rows(), 0);
    return editor.setup_report().message;
  };
  EditRegions no_handle;
  no_handle.fixed = {0, 1};
  EXPECT_NE(setup_message(no_handle).find("no handle"), std::string::npos);
  EditRegions out_of_range;
  out_of_range.handles = {{3, mesh.vertex_count() + 4}};
  EXPECT_NE(setup_message(out_of_range).find("handle 0: vertex index " + std::to_string(mesh.vertex_count() + 4)),
            std::string::npos);
  EditRegions overlapping;
  overlapping.fixed = {5, 6};
  overlapping.handles = {{7, 6}};
  EXPECT_NE(setup_message(overlapping).find("vertex 6 is in both fixed and handle 0"), std::string::npos);
  EditRegions empty_handle;
  empty_handle.handles = {{1}, {}};
  EXPECT_NE(setup_message(empty_handle).find("handle 1 has no vertex"), std::string::npos);

  // Two separate spheres, constraints on one only: the other's vertices would be undetermined.
  Mesh two = mesh;
  two.vertices.conservativeResize(2 * mesh.vertex_count(), 3);
  two.vertices.bottomRows(mesh.vertex_count()) = mesh.vertices.rowwise() + Eigen::RowVector3d(3.0, 0.0, 0.0);
  two.faces.conservativeResize(2 * mesh.face_count(), 3);
  two.faces.bottomRows(mesh.face_count()) = mesh.faces.array() + mesh.vertex_count();
  EditRegions one_part;
  one_part.handles = {{0}};
  SurfaceEditor editor(two, one_part, cpu_options());
  EXPECT_EQ(editor.setup_report().status, Status::invalid_input);
  EXPECT_NE(editor.setup_report().message.find("no fixed or handle vertex"), std::string::npos);
  // Leaving the second sphere out of the region of interest makes it stay where it is.
  one_part.region_of_interest.resize(static_cast<std::size_t>(mesh.vertex_count()));
  for (int v = 0; v < mesh.vertex_count(); ++v) one_part.region_of_interest[static_cast<std::size_t>(v)] = v;
  SurfaceEditor restricted(two, one_part, cpu_options());
  ASSERT_TRUE(restricted.setup_report().ok()) << restricted.setup_report().message;
  const SurfaceEditResult moved = restricted.drag({Eigen::Vector3d(1.0, 0.0, 0.0)});
  ASSERT_TRUE(moved.report.ok());
  EXPECT_TRUE(moved.positions.bottomRows(mesh.vertex_count()) == two.vertices.bottomRows(mesh.vertex_count()));
  EXPECT_GT((moved.positions.topRows(mesh.vertex_count()) - mesh.vertices).norm(), 1.0);
}

TEST(SurfaceEditor, BadTransformationsAreRefused) {
  const Mesh mesh = unit_sphere(2);
  EditRegions regions;
  regions.handles = {{0, 1}};
  SurfaceEditor editor(mesh, regions, cpu_options());
  ASSERT_TRUE(editor.setup_report().ok());
  EXPECT_EQ(editor.deform({}).report.status, Status::invalid_input);
  SimilarityTransform bad;
  bad.scale = -1.0;
  const SurfaceEditResult negative = editor.deform({bad});
  EXPECT_EQ(negative.report.status, Status::invalid_input);
  EXPECT_NE(negative.report.message.find("scale"), std::string::npos);
  bad.scale = 1.0;
  bad.translation.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(editor.deform({bad}).report.status, Status::invalid_input);
  // The editor is still usable afterwards.
  EXPECT_TRUE(editor.deform({SimilarityTransform{}}).report.ok());
}

// A model in tiny units edits exactly like the same model at unit size, scaled.
TEST(SurfaceEditor, ResultDoesNotDependOnTheUnitOfTheModel) {
  const Mesh mesh = unit_sphere(3);
  EditRegions regions;
  regions.fixed = below(mesh, 2, -0.5);
  regions.handles = {above(mesh, 2, 0.6)};
  SimilarityTransform edit;
  edit.rotation = Eigen::AngleAxisd(0.9, Eigen::Vector3d::UnitY());
  edit.center = centroid(mesh, regions.handles[0]);
  edit.translation = Eigen::Vector3d(0.1, 0.2, 0.3);
  const SurfaceEditResult unit = edit_surface(mesh, regions, {edit}, cpu_options());
  const double tiny = 1e-120;  // not a power of two: the inputs round differently
  Mesh small = mesh;
  small.vertices *= tiny;
  SimilarityTransform small_edit = edit;
  small_edit.center *= tiny;
  small_edit.translation *= tiny;
  const SurfaceEditResult scaled = edit_surface(small, regions, {small_edit}, cpu_options());
  ASSERT_TRUE(scaled.report.ok()) << scaled.report.message;
  EXPECT_LT(worst_relative_distance(scaled.positions / tiny, unit.positions, mesh), 1e-12);
}

}  // namespace
}  // namespace harmonia
