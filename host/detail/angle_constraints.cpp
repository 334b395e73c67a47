// The angle validity constraints of ABF (thesis section 2.2) and linear ABF (section 3.1): values
// and Jacobian, assembled straight into CSR arrays (the row lengths are known from the topology,
// so no triplets and no sorting pass are needed).

#include "detail/angle_constraints.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

namespace harmonia::detail {
namespace {

constexpr double kPi = std::numbers::pi;

// The corners of the face of `corner` that follow it (the wheel's left angle beta) and precede
// it (the right angle gamma), for a face listed counter-clockwise.
int next_corner(int corner) { return 3 * (corner / 3) + (corner % 3 + 1) % 3; }
int previous_corner(int corner) { return 3 * (corner / 3) + (corner % 3 + 2) % 3; }

// log |sin x|: the wheel term. Outside (0, pi) the constraint has no geometric meaning; the
// absolute value keeps the value finite there (the triangles are then invalid anyway, which the
// callers check separately).
double log_sine(double angle) { return std::log(std::abs(std::sin(angle))); }

}  // namespace

AngleTopology build_angle_topology(const Mesh& mesh, const std::vector<int>& boundary_loop) {
  AngleTopology topology;
  topology.face_count = static_cast<int>(mesh.faces.rows());
  topology.vertex_count = static_cast<int>(mesh.vertices.rows());
  const auto vertex_count = static_cast<std::size_t>(topology.vertex_count);

  // Corners per vertex by a counting sort over the corner index: each vertex's corners come out
  // increasing, so every row built from them is sorted.
  topology.vertex_corner_offsets.assign(vertex_count + 1, 0);
  for (int corner = 0; corner < topology.corner_count(); ++corner)
    ++topology.vertex_corner_offsets[static_cast<std::size_t>(mesh.faces(corner / 3, corner % 3)) +
                                     1];
  for (std::size_t v = 0; v < vertex_count; ++v)
    topology.vertex_corner_offsets[v + 1] += topology.vertex_corner_offsets[v];
  topology.vertex_corners.resize(static_cast<std::size_t>(topology.corner_count()));
  std::vector<int> fill(topology.vertex_corner_offsets.begin(),
                        topology.vertex_corner_offsets.end() - 1);
  for (int corner = 0; corner < topology.corner_count(); ++corner) {
    const auto vertex = static_cast<std::size_t>(mesh.faces(corner / 3, corner % 3));
    topology.vertex_corners[static_cast<std::size_t>(fill[vertex]++)] = corner;
  }

  // Interior vertices: every vertex with corners that is not on the boundary loop.
  std::vector<char> on_boundary(vertex_count, 0);
  for (const int v : boundary_loop) on_boundary[static_cast<std::size_t>(v)] = 1;
  topology.boundary_vertices = boundary_loop;
  topology.interior_index.assign(vertex_count, -1);
  for (std::size_t v = 0; v < vertex_count; ++v) {
    const bool has_corners =
        topology.vertex_corner_offsets[v + 1] > topology.vertex_corner_offsets[v];
    if (on_boundary[v] || !has_corners) continue;
    topology.interior_index[v] = static_cast<int>(topology.interior_vertices.size());
    topology.interior_vertices.push_back(static_cast<int>(v));
  }
  return topology;
}

Eigen::VectorXd corner_angles(const Mesh& mesh) {
  const Eigen::Index face_count = mesh.faces.rows();
  Eigen::VectorXd angles(3 * face_count);
  for (Eigen::Index f = 0; f < face_count; ++f) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d at = mesh.vertices.row(mesh.faces(f, k));
      const Eigen::Vector3d to_next =
          Eigen::Vector3d(mesh.vertices.row(mesh.faces(f, (k + 1) % 3))) - at;
      const Eigen::Vector3d to_previous =
          Eigen::Vector3d(mesh.vertices.row(mesh.faces(f, (k + 2) % 3))) - at;
      // atan2 of |cross| and dot: accurate for angles near 0 and pi, unlike acos.
      angles[3 * f + k] = std::atan2(to_next.cross(to_previous).norm(), to_next.dot(to_previous));
    }
  }
  return angles;
}

Eigen::VectorXd rescaled_angles(const AngleTopology& topology, const Eigen::VectorXd& angles) {
  Eigen::VectorXd rescaled = angles;
  for (const int v : topology.interior_vertices) {
    const auto begin = topology.vertex_corners.begin() + topology.vertex_corner_offsets[v];
    const auto end = topology.vertex_corners.begin() + topology.vertex_corner_offsets[v + 1];
    double sum = 0.0;
    for (auto corner = begin; corner != end; ++corner) sum += angles[*corner];
    if (!(sum > 0.0)) continue;  // A ring of zero-area faces: nothing to rescale.
    const double scale = 2.0 * kPi / sum;
    for (auto corner = begin; corner != end; ++corner) rescaled[*corner] = angles[*corner] * scale;
  }
  return rescaled;
}

AngleConstraints evaluate_angle_constraints(const AngleTopology& topology,
                                            const Eigen::VectorXd& angles,
                                            const std::vector<int>& active_boundary,
                                            double boundary_t) {
  const int face_count = topology.face_count;
  const int interior_count = topology.interior_count();
  const int row_count = face_count + 2 * interior_count + static_cast<int>(active_boundary.size());
  const auto ring_size = [&topology](int v) {
    return topology.vertex_corner_offsets[static_cast<std::size_t>(v) + 1] -
           topology.vertex_corner_offsets[static_cast<std::size_t>(v)];
  };

  // Row lengths: 3 per triangle row, the ring size per vertex row, twice it per wheel row.
  std::vector<int> row_starts(static_cast<std::size_t>(row_count) + 1, 0);
  int row = 0;
  for (int f = 0; f < face_count; ++f, ++row) row_starts[row + 1] = row_starts[row] + 3;
  for (const int v : topology.interior_vertices) {
    row_starts[row + 1] = row_starts[row] + ring_size(v);
    ++row;
  }
  for (const int v : topology.interior_vertices) {
    row_starts[row + 1] = row_starts[row] + 2 * ring_size(v);
    ++row;
  }
  for (const int v : active_boundary) {
    row_starts[row + 1] = row_starts[row] + ring_size(v);
    ++row;
  }

  AngleConstraints result;
  result.values.resize(row_count);
  RowMajorSparse& jacobian = result.jacobian;
  jacobian.resize(row_count, topology.corner_count());
  jacobian.resizeNonZeros(row_starts.back());
  std::copy(row_starts.begin(), row_starts.end(), jacobian.outerIndexPtr());
  int* columns = jacobian.innerIndexPtr();
  double* values = jacobian.valuePtr();
  int entry = 0;

  // Triangle consistency (2.2): x_a + x_b + x_c = pi.
  for (int f = 0; f < face_count; ++f) {
    for (int k = 0; k < 3; ++k, ++entry) {
      columns[entry] = 3 * f + k;
      values[entry] = 1.0;
    }
    result.values[f] = angles[3 * f] + angles[3 * f + 1] + angles[3 * f + 2] - kPi;
  }
  // Angle sum around a vertex, its ring's corners in increasing order.
  const auto angle_sum_row = [&](int v, double target) {
    double sum = 0.0;
    for (int k = topology.vertex_corner_offsets[v]; k < topology.vertex_corner_offsets[v + 1];
         ++k, ++entry) {
      const int corner = topology.vertex_corners[static_cast<std::size_t>(k)];
      columns[entry] = corner;
      values[entry] = 1.0;
      sum += angles[corner];
    }
    return sum - target;
  };
  // Vertex consistency (2.1): central angles sum to 2 pi.
  for (int i = 0; i < interior_count; ++i)
    result.values[face_count + i] = angle_sum_row(topology.interior_vertices[i], 2.0 * kPi);
  // Wheel consistency (2.11): sum log sin beta - log sin gamma = 0; its gradient is
  // cot beta / -cot gamma, the linearized wheel condition (3.7). The two corners of one face are
  // adjacent columns; faces come in increasing order, so the row stays sorted.
  for (int i = 0; i < interior_count; ++i) {
    const int v = topology.interior_vertices[i];
    double sum = 0.0;
    for (int k = topology.vertex_corner_offsets[v]; k < topology.vertex_corner_offsets[v + 1]; ++k) {
      const int central = topology.vertex_corners[static_cast<std::size_t>(k)];
      const int left = next_corner(central), right = previous_corner(central);
      sum += log_sine(angles[left]) - log_sine(angles[right]);
      const double left_slope = 1.0 / std::tan(angles[left]);
      const double right_slope = -1.0 / std::tan(angles[right]);
      if (left < right) {
        columns[entry] = left, values[entry++] = left_slope;
        columns[entry] = right, values[entry++] = right_slope;
      } else {
        columns[entry] = right, values[entry++] = right_slope;
        columns[entry] = left, values[entry++] = left_slope;
      }
    }
    result.values[face_count + interior_count + i] = sum;
  }
  // Active boundary inequalities (2.6), held with equality: angles at v sum to t pi.
  for (std::size_t b = 0; b < active_boundary.size(); ++b)
    result.values[face_count + 2 * interior_count + static_cast<int>(b)] =
        angle_sum_row(active_boundary[b], boundary_t * kPi);
  return result;
}

double constraint_violation(const AngleConstraints& constraints) {
  return constraints.values.size() == 0 ? 0.0 : constraints.values.lpNorm<Eigen::Infinity>();
}

}  // namespace harmonia::detail
