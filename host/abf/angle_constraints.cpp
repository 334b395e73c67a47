// The angle validity constraints of ABF (thesis section 2.2) and linear ABF (section 3.1): values
// and Jacobian, assembled straight into CSR arrays (the row lengths are known from the topology,
// so no triplets and no sorting pass are needed).

#include "abf/angle_constraints.h"

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

// log |sin x| (the wheel term) from sin x. Outside (0, pi) the constraint has no geometric
// meaning; the absolute value keeps the value finite there (the triangles are then invalid
// anyway, which the callers check separately).
double log_sine(double sine) { return std::log(std::abs(sine)); }

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

namespace {

// h(x), and J(x) when `jacobian` is not null (rows as documented in the header).
Eigen::VectorXd evaluate(const AngleTopology& topology, const Eigen::VectorXd& angles,
                         const std::vector<int>& active_boundary, double boundary_t,
                         RowMajorSparse* jacobian) {
  const int face_count = topology.face_count;
  const int interior_count = topology.interior_count();
  const int row_count = face_count + 2 * interior_count + static_cast<int>(active_boundary.size());
  const auto ring_size = [&topology](int v) {
    return topology.vertex_corner_offsets[static_cast<std::size_t>(v) + 1] -
           topology.vertex_corner_offsets[static_cast<std::size_t>(v)];
  };

  Eigen::VectorXd values(row_count);
  int* columns = nullptr;
  double* slopes = nullptr;
  if (jacobian != nullptr) {
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
    jacobian->resize(row_count, topology.corner_count());
    jacobian->resizeNonZeros(row_starts.back());
    std::copy(row_starts.begin(), row_starts.end(), jacobian->outerIndexPtr());
    columns = jacobian->innerIndexPtr();
    slopes = jacobian->valuePtr();
  }
  int entry = 0;
  const auto put = [&](int column, double slope) {
    if (columns == nullptr) return;
    columns[entry] = column;
    slopes[entry++] = slope;
  };

  // Triangle consistency (2.2): x_a + x_b + x_c = pi.
  for (int f = 0; f < face_count; ++f) {
    for (int k = 0; k < 3; ++k) put(3 * f + k, 1.0);
    values[f] = angles[3 * f] + angles[3 * f + 1] + angles[3 * f + 2] - kPi;
  }
  // Angle sum around a vertex, its ring's corners in increasing order.
  const auto angle_sum_row = [&](int v, double target) {
    double sum = 0.0;
    for (int k = topology.vertex_corner_offsets[v]; k < topology.vertex_corner_offsets[v + 1];
         ++k) {
      const int corner = topology.vertex_corners[static_cast<std::size_t>(k)];
      put(corner, 1.0);
      sum += angles[corner];
    }
    return sum - target;
  };
  // Vertex consistency (2.1): central angles sum to 2 pi.
  for (int i = 0; i < interior_count; ++i)
    values[face_count + i] = angle_sum_row(topology.interior_vertices[i], 2.0 * kPi);
  // Wheel consistency (2.11): sum log sin beta - log sin gamma = 0; its gradient is
  // cot beta / -cot gamma, the linearized wheel condition (3.7). Every corner is the left corner
  // of one wheel and the right corner of another: its log sine and cotangent are computed once.
  const Eigen::Index corner_count = angles.size();
  Eigen::VectorXd log_sines(corner_count), cotangents;
  if (jacobian != nullptr) {
    // The sine serves both (one sincos per corner).
    cotangents.resize(corner_count);
    for (Eigen::Index c = 0; c < corner_count; ++c) {
      const double sine = std::sin(angles[c]);
      log_sines[c] = log_sine(sine);
      cotangents[c] = std::cos(angles[c]) / sine;
    }
  } else {
    for (Eigen::Index c = 0; c < corner_count; ++c) log_sines[c] = log_sine(std::sin(angles[c]));
  }
  // The two corners of one face are adjacent columns; faces come in increasing order, so the row
  // stays sorted.
  for (int i = 0; i < interior_count; ++i) {
    const int v = topology.interior_vertices[i];
    double sum = 0.0;
    for (int k = topology.vertex_corner_offsets[v]; k < topology.vertex_corner_offsets[v + 1]; ++k) {
      const int central = topology.vertex_corners[static_cast<std::size_t>(k)];
      const int left = next_corner(central), right = previous_corner(central);
      sum += log_sines[left] - log_sines[right];
      if (jacobian == nullptr) continue;
      if (left < right) {
        put(left, cotangents[left]);
        put(right, -cotangents[right]);
      } else {
        put(right, -cotangents[right]);
        put(left, cotangents[left]);
      }
    }
    values[face_count + interior_count + i] = sum;
  }
  // Active boundary inequalities (2.6), held with equality: angles at v sum to t pi.
  for (std::size_t b = 0; b < active_boundary.size(); ++b)
    values[face_count + 2 * interior_count + static_cast<int>(b)] =
        angle_sum_row(active_boundary[b], boundary_t * kPi);
  return values;
}

}  // namespace

AngleConstraints evaluate_angle_constraints(const AngleTopology& topology,
                                            const Eigen::VectorXd& angles,
                                            const std::vector<int>& active_boundary,
                                            double boundary_t) {
  AngleConstraints result;
  result.values = evaluate(topology, angles, active_boundary, boundary_t, &result.jacobian);
  return result;
}

Eigen::VectorXd angle_constraint_values(const AngleTopology& topology,
                                        const Eigen::VectorXd& angles,
                                        const std::vector<int>& active_boundary,
                                        double boundary_t) {
  return evaluate(topology, angles, active_boundary, boundary_t, nullptr);
}

double constraint_violation(const AngleConstraints& constraints) {
  return constraints.values.size() == 0 ? 0.0 : constraints.values.lpNorm<Eigen::Infinity>();
}

}  // namespace harmonia::detail
