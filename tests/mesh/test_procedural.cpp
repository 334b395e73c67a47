// The procedural meshes the demo and the analytic tests rely on have the claimed shape and topology.
#include <cmath>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "harmonia/procedural.h"

namespace harmonia {
namespace {

TEST(Procedural, HemisphereHasHexagonalRingsOnTheUnitSphere) {
  const Mesh mesh = hemisphere(4);
  EXPECT_EQ(mesh.vertex_count(), 1 + 3 * 4 * 5);  // 1 + 6(1+2+3+4)
  EXPECT_EQ(mesh.face_count(), 6 * 4 * 4);        // 6 r^2
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    EXPECT_NEAR(mesh.vertices.row(v).norm(), 1.0, 1e-12);
    EXPECT_GE(mesh.vertices(v, 2), -1e-12);
  }
}

TEST(Procedural, FacesAreCounterClockwiseSeenFromOutside) {
  const Mesh mesh = hemisphere(3);
  for (int f = 0; f < mesh.face_count(); ++f) {
    const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(f, 0));
    const Eigen::Vector3d b = mesh.vertices.row(mesh.faces(f, 1));
    const Eigen::Vector3d c = mesh.vertices.row(mesh.faces(f, 2));
    const Eigen::Vector3d normal = (b - a).cross(c - a);
    EXPECT_GT(normal.dot((a + b + c) / 3.0), 0.0) << "face " << f;
  }
}

TEST(Procedural, DevelopableStripKeepsEdgeLengthsOfItsFlatRectangle) {
  const int nu = 8, nv = 3;
  const double length = 2.0, width = 0.5;
  const Mesh mesh = developable_strip(nu, nv, length, width, 0.7);
  // Grid edges along u are chords of arcs of length length/nu.
  const double arc = length / nu;
  const double chord = 2.0 * 0.7 * std::sin(arc / (2.0 * 0.7));
  EXPECT_NEAR((mesh.vertices.row(1) - mesh.vertices.row(0)).norm(), chord, 1e-12);
  EXPECT_NEAR((mesh.vertices.row(nu + 1) - mesh.vertices.row(0)).norm(), width / nv, 1e-12);
}

}  // namespace
}  // namespace harmonia
