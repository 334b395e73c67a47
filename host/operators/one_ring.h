#pragma once
//! \file one_ring.h
//! \brief Ordered one-ring fans of every vertex, built once from the face list, and the flattening
//! of one ring into the plane by the exponential map (Floater's construction used by the ring-based
//! weight schemes of thesis chapter 4).

#include <span>
#include <vector>

#include <Eigen/Core>

namespace harmonia::detail {

//! How the faces around a vertex fit together.
enum class FanKind : unsigned char {
  isolated,   //!< No face uses the vertex.
  interior,   //!< The faces form one closed fan (a disk around the vertex).
  boundary,   //!< The faces form one open fan (a half-disk: the vertex is on the boundary).
  irregular,  //!< Non-manifold or inconsistently oriented: several fans, or a fan that branches.
};

//! The neighbours of every vertex in counter-clockwise order (as seen with the faces' orientation),
//! stored as one compressed array. Interior fans list each neighbour once (valence n, n faces);
//! boundary fans run from the first to the last boundary neighbour (n neighbours, n - 1 faces).
//! Irregular vertices have an empty neighbour list.
class VertexFans {
 public:
  //! Builds the fans; faces must index vertices in [0, vertex_count) (checked by the caller).
  VertexFans(const Eigen::MatrixX3i& faces, int vertex_count);

  [[nodiscard]] int vertex_count() const { return static_cast<int>(kinds_.size()); }
  [[nodiscard]] FanKind kind(int vertex) const { return kinds_[static_cast<std::size_t>(vertex)]; }
  [[nodiscard]] std::span<const int> neighbours(int vertex) const {
    const auto begin = static_cast<std::size_t>(offsets_[static_cast<std::size_t>(vertex)]);
    const auto end = static_cast<std::size_t>(offsets_[static_cast<std::size_t>(vertex) + 1]);
    return {neighbours_.data() + begin, end - begin};
  }

 private:
  std::vector<int> offsets_;
  std::vector<int> neighbours_;
  std::vector<FanKind> kinds_;
};

//! Polar flattening of a fan by the exponential map: neighbour k goes to r_k (cos phi_k, sin phi_k)
//! with r_k = |q_k - p| (edge lengths kept) and phi_k the running sum of the 3D angles at the centre
//! p between consecutive neighbours. For a closed fan the angles are scaled so that they sum to
//! 2 pi; an open (boundary) fan keeps its angles. The centre goes to the origin.
[[nodiscard]] std::vector<Eigen::Vector2d> flatten_ring(const Eigen::MatrixX3d& vertices, int centre,
                                                        std::span<const int> neighbours, bool closed);

//! The angle between two 3D vectors, in [0, pi], computed as atan2(|u x v|, u . v) (accurate for
//! small and nearly straight angles alike).
[[nodiscard]] double angle_between(const Eigen::Vector3d& u, const Eigen::Vector3d& v);

}  // namespace harmonia::detail
