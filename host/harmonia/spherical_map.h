#pragma once
//! \file spherical_map.h
//! \brief Spherical parameterization of a closed genus-0 mesh in curvilinear coordinates (thesis
//! chapter 7): every vertex gets a point of the unit sphere, with only linear solves and positive
//! weights, so that every intermediate map is valid.
//!
//!   1. Poles and date line: two vertices (given, or the ends of a geodesic diameter) and the
//!      shortest edge path between them.
//!   2. Initial map (7.1): the poles removed and the mesh cut along the date line leave a disk,
//!      mapped harmonically onto a rectangle of longitude theta in [0, 2 pi] and latitude: the pole
//!      rings on its top and bottom, the two sides of the date line on its left and right. The
//!      latitude axis is the Mercator latitude psi = ln cot(phi / 2) of the polar angle phi (the
//!      thesis uses phi itself): theta and psi are harmonic on the sphere, so a sphere maps onto
//!      itself (host/sphere/curvilinear_domain.h).
//!   3. Secondary map (7.2): the scalar quasi-harmonic equation div(kappa grad U) = 0 on the same
//!      rectangle, with kappa per triangle from the area the current map gives it on the sphere
//!      (accumulated over a few rounds); it undoes most of the area distortion of the first map.
//!   4. Lift (x, y, z) = (cos theta sin phi, sin theta sin phi, cos phi), poles restored, and the
//!      local relaxation of 7.3: a few tangential mean-value Laplacian steps, each followed by the
//!      projection back onto the sphere, on the band of rings around the date line (its outer
//!      boundary fixed), where the rectangle's boundary conditions left the most distortion.
//!
//! With mean-value weights (positive) on the rectangle (convex) the planar maps of steps 2 and 3
//! are embeddings by Tutte's theorem; with the default cotangent weights a first map that folds is
//! replaced by the mean-value one. The lift is a diffeomorphism of the open rectangle onto the
//! sphere without the date line, but the sphere's triangles are chord triangles, and a wide, flat
//! triangle of a squashed region can still turn over in it. So every map is checked on the sphere
//! itself (exact orientation of each triangle against the outward normal): a quasi-harmonic round
//! that would turn more triangles over is shortened or not taken, the relaxation undoes a move that
//! would turn one over, and the corners of a triangle the lift did turn over are moved, one vertex
//! at a time, into the region where all their triangles face outward. SolveReport::fallbacks says
//! what was done. Details in host/sphere/ and docs/methods.md ("Spherical maps").

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "harmonia/laplacian.h"
#include "harmonia/mesh.h"
#include "harmonia/solver_options.h"
#include "harmonia/types.h"

namespace harmonia {

//! How the sphere is reached.
enum class SphericalMethod {
  //! The thesis' method (steps 1-4 above). Default.
  curvilinear,
  //! The baseline of the thesis' figure 7.9 (Kobbelt et al. 1999, Alexa 2000): the vertices
  //! projected from their centroid onto the sphere, then tangential mean-value Laplacian steps
  //! with back-projection over the whole mesh. Nothing holds it in place, so it tends to collapse
  //! toward one region of the sphere and to fold; kept to show why the curvilinear method exists.
  relaxation,
};

struct SphericalMapOptions {
  SphericalMethod method = SphericalMethod::curvilinear;
  //! North and south pole (vertex indices, at least three edges apart); automatic when empty: the
  //! two ends of a geodesic diameter (spherical_poles.h), which does not depend on the vertex order.
  //! A mesh with no two vertices three edges apart (a tetrahedron, a 12-triangle cube) is mapped
  //! with automatic poles by central projection from its centroid where it is star-shaped about
  //! it (host/sphere/central_projection.h; report.fallbacks says so): the north pole at +z, the
  //! south pole wherever the projection puts it (at longitude 0 unless that is the antipode). A
  //! coarse mesh star-shaped about none of its centres is subdivided until its poles are three
  //! edges apart and mapped so, its own vertices kept.
  std::optional<std::array<int, 2>> poles;
  //! The Laplacian of steps 2 and 3: cotangent (default: symmetric, one Cholesky factorization
  //! per map, about twice as fast as mean value; a first map that folds in the rectangle is
  //! replaced by the mean-value one, reported in fallbacks) or mean_value (positive, so the maps of
  //! the rectangle cannot fold; an LU factorization per map).
  WeightScheme weights = WeightScheme::cotangent;
  //! Quasi-harmonic rounds of step 3 (0: the first harmonic map only).
  int rounds = 3;
  //! Step 2 puts each pole ring where it would be on a sphere of the same pole-to-pole length (its
  //! mean distance from the pole, the date line scaled to pi), but at least this far from the pole
  //! (polar angle, radians, in (0, 0.5)): the eps of the thesis' [eps, pi - eps].
  double pole_margin = 0.02;
  //! Step 4's band: the vertices within this many rings of the date line (0: no relaxation) ...
  int relax_rings = 5;
  //! ... relaxed this many times.
  int relax_steps = 3;
  //! SphericalMethod::relaxation: the number of global relaxation steps.
  int global_relaxation_steps = 100;
  SolverOptions solver;
};

//! What one quasi-harmonic round (or the first map, round 0) gave.
struct SphericalRound {
  //! Mean over the triangles, weighted by 3D area, of |log| of the ratio of a triangle's share of
  //! the sphere to its share of the surface (spherical areas of the domain's triangles).
  double area_distortion = 0.0;
  double seconds = 0.0;
};

struct SphericalMapResult {
  Eigen::MatrixX3d positions;  //!< #V by 3: points of the unit sphere, in the input's order.
  //! #V by 2: (theta, phi), longitude in [0, 2 pi) and polar angle in [0, pi] (0 at the north
  //! pole), of the same points.
  Eigen::MatrixX2d angles;
  int north_pole = -1;
  int south_pole = -1;
  std::vector<int> date_line;          //!< Vertices from the north pole to the south pole.
  std::vector<SphericalRound> rounds;  //!< The first map, then each quasi-harmonic round.
  int relaxed_vertices = 0;            //!< Vertices moved by step 4 (or by the global relaxation).
  //! report.flipped_triangles / degenerate_triangles count triangles whose orientation against
  //! the sphere's outward normal is negative / zero (exact predicate).
  SolveReport report;
};

//! One-shot: build a SphericalMapper and solve once.
//! \pre mesh is closed, genus 0, manifold and consistently oriented (check_sphere); otherwise
//! report.status says what the mesh is (not_a_sphere, non_manifold, invalid_input).
[[nodiscard]] SphericalMapResult spherical_map(const Mesh& mesh,
                                               const SphericalMapOptions& options = {});

//! Reusable solver: the constructor checks the mesh, chooses the poles and the date line, cuts the
//! curvilinear domain and analyzes its system's pattern; update_geometry takes new positions of
//! the same connectivity (same poles and date line); solve() computes the map.
class SphericalMapper {
 public:
  SphericalMapper(const Mesh& mesh, const SphericalMapOptions& options = {});
  ~SphericalMapper();
  SphericalMapper(SphericalMapper&&) noexcept;
  SphericalMapper& operator=(SphericalMapper&&) noexcept;

  //! Status of the setup and its message.
  [[nodiscard]] const SolveReport& setup_report() const;
  //! New vertex positions (#V by 3, finite) of the same connectivity.
  void update_geometry(const Eigen::MatrixX3d& vertices);
  [[nodiscard]] SphericalMapResult solve();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

//! The unit-sphere points of curvilinear coordinates (theta, phi) (#V by 2):
//! (cos theta sin phi, sin theta sin phi, cos phi).
[[nodiscard]] Eigen::MatrixX3d sphere_points(const Eigen::MatrixX2d& angles);

}  // namespace harmonia
