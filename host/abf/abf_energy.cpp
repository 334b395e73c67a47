// The ABF objective (thesis 2.8) and its target angles, shared by ABF and linear ABF so that their
// results compare on the same scale.

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "abf/angle_constraints.h"
#include "harmonia/abf.h"
#include "harmonia/topology.h"
#include "mesh/power_of_two_scale.h"

namespace harmonia {
namespace {

// Vertices on an edge used by exactly one face (the boundary of any surface, disk or not), in
// increasing order.
std::vector<int> boundary_vertices(const Mesh& mesh) {
  std::vector<std::pair<int, int>> edges;
  edges.reserve(3 * static_cast<std::size_t>(mesh.faces.rows()));
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.faces(f, k), b = mesh.faces(f, (k + 1) % 3);
      edges.emplace_back(std::min(a, b), std::max(a, b));
    }
  }
  std::sort(edges.begin(), edges.end());
  std::vector<int> vertices;
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    if (j - i == 1) {
      vertices.push_back(edges[i].first);
      vertices.push_back(edges[i].second);
    }
    i = j;
  }
  std::sort(vertices.begin(), vertices.end());
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  return vertices;
}

void require_valid_arrays(const Mesh& mesh, const char* caller) {
  std::string problem;
  if (check_indices_and_coordinates(mesh, &problem) != Status::ok)
    throw Error(Status::invalid_input, std::string(caller) + ": " + problem);
}

}  // namespace

Eigen::MatrixX3d abf_target_angles(const Mesh& mesh) {
  require_valid_arrays(mesh, "abf_target_angles");
  const detail::AngleTopology topology =
      detail::build_angle_topology(mesh, boundary_vertices(mesh));
  // Angles do not depend on the model's units: measured on the copy of unit size, whose lengths
  // and cross products neither underflow nor overflow (the same bits as the model's own where
  // those do not either).
  const Eigen::VectorXd targets =
      detail::rescaled_angles(topology, detail::corner_angles(detail::unit_scaled(mesh).mesh));
  // Corner 3f + k is row f, column k: the row-major view of the corner vector.
  Eigen::MatrixX3d angles(mesh.faces.rows(), 3);
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f)
    angles.row(f) << targets[3 * f], targets[3 * f + 1], targets[3 * f + 2];
  return angles;
}

double abf_energy(const Mesh& mesh, const Eigen::MatrixX3d& angles) {
  if (angles.rows() != mesh.faces.rows())
    throw Error(Status::invalid_input, "abf_energy: " + std::to_string(angles.rows()) +
                                           " rows of angles for " +
                                           std::to_string(mesh.faces.rows()) + " faces");
  const Eigen::MatrixX3d targets = abf_target_angles(mesh);
  // (2.8): sum (x - a)^2 / a^2. A zero target (a degenerate 3D triangle) carries no weight
  // instead of an infinite one.
  double energy = 0.0;
  for (Eigen::Index f = 0; f < targets.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const double target = targets(f, k);
      if (target > 0.0) {
        const double relative = (angles(f, k) - target) / target;
        energy += relative * relative;
      }
    }
  }
  return energy;
}

}  // namespace harmonia
