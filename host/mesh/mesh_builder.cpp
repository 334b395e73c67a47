#include "mesh/mesh_builder.h"

namespace harmonia::detail {

Mesh MeshBuilder::build() const {
  Mesh mesh;
  mesh.vertices = matrix_from_rows<Eigen::MatrixX3d>(coordinates_);
  mesh.faces = matrix_from_rows<Eigen::MatrixX3i>(corners_);
  return mesh;
}

}  // namespace harmonia::detail
