// corpus_edit_reference: the comparison files of a surface-editing case, made as
// ../shared/data/edit/README.md says libigl made those of the public cases, by code of its own
// (plain Eigen: nothing of the surface editor it is there to judge).
//
//   corpus_edit_reference REST.obj EDIT.json PREFIX [--most-iterations N] [--last-step S]
//
// writes, with the rest mesh's faces and positions printed with %.17g:
//   PREFIX.harmonic.obj  the baseline: rest + the harmonic (cotangent) interpolation of the
//                        constrained vertices' displacements (a rotated handle's rotation is not
//                        propagated, only its vertices' displacements);
//   PREFIX.arap10.obj    as-rigid-as-possible after 10 iterations (what interactive tools show);
//   PREFIX.arap500.obj   the reference: the same iteration run to convergence (the name is the
//                        public cases' own, kept so every case has the same files).
//
// ARAP is the spokes-and-rims energy (Sorkine and Alexa 2007 with Chao et al.'s rim edges): every
// edge e = (j, k) of every triangle t, with its half-cotangent weight w, pays
// w |(x_j - x_k) - R_i (p_j - p_k)|^2 for each corner i of t, R_i the vertex's rotation. The
// iteration is libigl's arap_solve without dynamics: from the cold start (rest, constrained
// vertices at their targets), fit every R_i to its cell's covariance (polar part by SVD, a
// reflection turned into a rotation), then solve for the free positions with the cotangent
// Laplacian, constrained vertices held at their targets. It stops when an iteration moves no vertex
// farther than --last-step times the rest bounding-box diagonal (default 1e-10) or after
// --most-iterations (default 50000), and prints the iteration count and the last step.

#include <Eigen/Core>
#include <Eigen/SVD>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "harmonia/edit_file.h"
#include "harmonia/io.h"

namespace {

using harmonia::Mesh;

struct Constraints {
  std::vector<int> index_among_free;  // -1 for a constrained vertex
  std::vector<int> free_vertices;
  std::vector<int> constrained_vertices;
  Eigen::MatrixX3d targets;  // #V by 3: the target of every constrained vertex (rest elsewhere)
};

Constraints constraints_of(const Mesh& mesh, const harmonia::EditDescription& edit) {
  const int vertex_count = static_cast<int>(mesh.vertices.rows());
  Constraints constraints;
  constraints.targets = mesh.vertices;
  std::vector<bool> constrained(vertex_count, false);
  for (const int v : edit.regions.fixed) constrained[v] = true;
  for (std::size_t h = 0; h < edit.regions.handles.size(); ++h)
    for (const int v : edit.regions.handles[h]) {
      constrained[v] = true;
      constraints.targets.row(v) = edit.transforms[h].apply(mesh.vertices.row(v).transpose()).transpose();
    }
  constraints.index_among_free.assign(vertex_count, -1);
  for (int v = 0; v < vertex_count; ++v) {
    if (constrained[v]) {
      constraints.constrained_vertices.push_back(v);
    } else {
      constraints.index_among_free[v] = static_cast<int>(constraints.free_vertices.size());
      constraints.free_vertices.push_back(v);
    }
  }
  return constraints;
}

// Half the cotangent of each corner's angle (column f: corners 0, 1, 2 of face f): the weight of
// the edge opposite that corner.
Eigen::Matrix3Xd half_cotangents(const Mesh& mesh) {
  Eigen::Matrix3Xd weights(3, mesh.faces.rows());
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f)
    for (int corner = 0; corner < 3; ++corner) {
      const Eigen::Vector3d p = mesh.vertices.row(mesh.faces(f, corner));
      const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(f, (corner + 1) % 3)).transpose() - p;
      const Eigen::Vector3d b = mesh.vertices.row(mesh.faces(f, (corner + 2) % 3)).transpose() - p;
      weights(corner, f) = 0.5 * a.dot(b) / a.cross(b).norm();
    }
  return weights;
}

// The cotangent Laplacian's blocks: free by free (to factor) and free by constrained (to move the
// constrained vertices' known positions to the right-hand side).
struct LaplacianBlocks {
  Eigen::SparseMatrix<double> free_free;
  Eigen::SparseMatrix<double> free_constrained;
};

LaplacianBlocks laplacian_blocks(const Mesh& mesh, const Eigen::Matrix3Xd& weights, const Constraints& constraints) {
  const int vertex_count = static_cast<int>(mesh.vertices.rows());
  std::vector<int> index_among_constrained(vertex_count, -1);
  for (std::size_t c = 0; c < constraints.constrained_vertices.size(); ++c)
    index_among_constrained[constraints.constrained_vertices[c]] = static_cast<int>(c);
  std::vector<Eigen::Triplet<double>> free_free, free_constrained;
  auto add = [&](int row_vertex, int column_vertex, double value) {
    const int row = constraints.index_among_free[row_vertex];
    if (row < 0) return;
    const int free_column = constraints.index_among_free[column_vertex];
    if (free_column >= 0)
      free_free.emplace_back(row, free_column, value);
    else
      free_constrained.emplace_back(row, index_among_constrained[column_vertex], value);
  };
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f)
    for (int corner = 0; corner < 3; ++corner) {
      const int j = mesh.faces(f, (corner + 1) % 3), k = mesh.faces(f, (corner + 2) % 3);
      const double w = weights(corner, f);
      add(j, j, w);
      add(k, k, w);
      add(j, k, -w);
      add(k, j, -w);
    }
  LaplacianBlocks blocks;
  blocks.free_free.resize(static_cast<Eigen::Index>(constraints.free_vertices.size()),
                          static_cast<Eigen::Index>(constraints.free_vertices.size()));
  blocks.free_free.setFromTriplets(free_free.begin(), free_free.end());
  blocks.free_constrained.resize(static_cast<Eigen::Index>(constraints.free_vertices.size()),
                                 static_cast<Eigen::Index>(constraints.constrained_vertices.size()));
  blocks.free_constrained.setFromTriplets(free_constrained.begin(), free_constrained.end());
  return blocks;
}

Eigen::MatrixX3d rows_of(const Eigen::MatrixX3d& all, const std::vector<int>& vertices) {
  Eigen::MatrixX3d rows(static_cast<Eigen::Index>(vertices.size()), 3);
  for (std::size_t i = 0; i < vertices.size(); ++i) rows.row(static_cast<Eigen::Index>(i)) = all.row(vertices[i]);
  return rows;
}

// The rotation nearest to a cell's covariance S = sum w e' e^T (deformed times rest): R = U V^T of
// the SVD of S, with the last singular direction flipped when that is a reflection.
Eigen::Matrix3d nearest_rotation(const Eigen::Matrix3d& covariance) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d u = svd.matrixU();
  if ((u * svd.matrixV().transpose()).determinant() < 0.0) u.col(2) = -u.col(2);
  return u * svd.matrixV().transpose();
}

class ArapIteration {
 public:
  ArapIteration(const Mesh& mesh, const Constraints& constraints)
      : mesh_(mesh), constraints_(constraints), weights_(half_cotangents(mesh)),
        blocks_(laplacian_blocks(mesh, weights_, constraints)) {
    factor_.compute(blocks_.free_free);
    if (factor_.info() != Eigen::Success) throw std::runtime_error("the Laplacian's free block did not factor");
  }

  // Free positions solving L_ff x_f = right_f - L_fc x_c.
  Eigen::MatrixX3d solve_free(const Eigen::MatrixX3d& right) const {
    const Eigen::MatrixX3d known = rows_of(constraints_.targets, constraints_.constrained_vertices);
    return factor_.solve(right - blocks_.free_constrained * known);
  }

  Eigen::MatrixX3d harmonic_baseline() const {
    // The displacements interpolated with zero right-hand side; constrained displacements known.
    const Eigen::MatrixX3d known = rows_of(constraints_.targets - mesh_.vertices, constraints_.constrained_vertices);
    const Eigen::MatrixX3d free = factor_.solve(-(blocks_.free_constrained * known));
    Eigen::MatrixX3d result = constraints_.targets;
    for (std::size_t i = 0; i < constraints_.free_vertices.size(); ++i) {
      const int v = constraints_.free_vertices[i];
      result.row(v) = mesh_.vertices.row(v) + free.row(static_cast<Eigen::Index>(i));
    }
    return result;
  }

  // The local step: every vertex's rotation fitted to its cell in `positions`.
  std::vector<Eigen::Matrix3d> fitted_rotations(const Eigen::MatrixX3d& positions) const {
    const Eigen::Index vertex_count = mesh_.vertices.rows();
    std::vector<Eigen::Matrix3d> covariances(static_cast<std::size_t>(vertex_count), Eigen::Matrix3d::Zero());
    for (Eigen::Index f = 0; f < mesh_.faces.rows(); ++f) {
      Eigen::Matrix3d cell = Eigen::Matrix3d::Zero();
      for (int corner = 0; corner < 3; ++corner) {
        const int j = mesh_.faces(f, (corner + 1) % 3), k = mesh_.faces(f, (corner + 2) % 3);
        const Eigen::Vector3d rest = (mesh_.vertices.row(j) - mesh_.vertices.row(k)).transpose();
        const Eigen::Vector3d deformed = (positions.row(j) - positions.row(k)).transpose();
        cell += weights_(corner, f) * deformed * rest.transpose();
      }
      for (int corner = 0; corner < 3; ++corner) covariances[mesh_.faces(f, corner)] += cell;
    }
    std::vector<Eigen::Matrix3d> rotations(covariances.size());
    for (std::size_t v = 0; v < covariances.size(); ++v) rotations[v] = nearest_rotation(covariances[v]);
    return rotations;
  }

  // The spokes-and-rims energy of `positions` with its best vertex rotations.
  double energy(const Eigen::MatrixX3d& positions) const {
    const std::vector<Eigen::Matrix3d> rotations = fitted_rotations(positions);
    double sum = 0.0;
    for (Eigen::Index f = 0; f < mesh_.faces.rows(); ++f)
      for (int corner = 0; corner < 3; ++corner) {
        const int j = mesh_.faces(f, (corner + 1) % 3), k = mesh_.faces(f, (corner + 2) % 3);
        const Eigen::Vector3d rest = (mesh_.vertices.row(j) - mesh_.vertices.row(k)).transpose();
        const Eigen::Vector3d deformed = (positions.row(j) - positions.row(k)).transpose();
        for (int i = 0; i < 3; ++i)
          sum += weights_(corner, f) * (deformed - rotations[mesh_.faces(f, i)] * rest).squaredNorm();
      }
    return sum;
  }

  // One local-global iteration from `positions`.
  Eigen::MatrixX3d step(const Eigen::MatrixX3d& positions) const {
    const std::vector<Eigen::Matrix3d> rotations = fitted_rotations(positions);
    // Right-hand side of L x = b / 3: every edge pulls its ends apart by the corners' rotated edge.
    Eigen::MatrixX3d right = Eigen::MatrixX3d::Zero(static_cast<Eigen::Index>(constraints_.free_vertices.size()), 3);
    for (Eigen::Index f = 0; f < mesh_.faces.rows(); ++f) {
      const Eigen::Matrix3d corner_mean =
          (rotations[mesh_.faces(f, 0)] + rotations[mesh_.faces(f, 1)] + rotations[mesh_.faces(f, 2)]) / 3.0;
      for (int corner = 0; corner < 3; ++corner) {
        const int j = mesh_.faces(f, (corner + 1) % 3), k = mesh_.faces(f, (corner + 2) % 3);
        const Eigen::Vector3d pull =
            weights_(corner, f) * corner_mean * (mesh_.vertices.row(j) - mesh_.vertices.row(k)).transpose();
        if (constraints_.index_among_free[j] >= 0) right.row(constraints_.index_among_free[j]) += pull.transpose();
        if (constraints_.index_among_free[k] >= 0) right.row(constraints_.index_among_free[k]) -= pull.transpose();
      }
    }
    const Eigen::MatrixX3d free = solve_free(right);
    Eigen::MatrixX3d result = constraints_.targets;
    for (std::size_t i = 0; i < constraints_.free_vertices.size(); ++i)
      result.row(constraints_.free_vertices[i]) = free.row(static_cast<Eigen::Index>(i));
    return result;
  }

 private:
  const Mesh& mesh_;
  const Constraints& constraints_;
  Eigen::Matrix3Xd weights_;
  LaplacianBlocks blocks_;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> factor_;
};

void write_positions(const std::filesystem::path& path, const Mesh& mesh, const Eigen::MatrixX3d& positions) {
  const std::filesystem::path temporary = path.string() + ".partial";
  std::FILE* file = std::fopen(temporary.c_str(), "w");
  if (!file) throw std::runtime_error("cannot write " + temporary.string());
  for (Eigen::Index v = 0; v < positions.rows(); ++v)
    std::fprintf(file, "v %.17g %.17g %.17g\n", positions(v, 0), positions(v, 1), positions(v, 2));
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f)
    std::fprintf(file, "f %d %d %d\n", mesh.faces(f, 0) + 1, mesh.faces(f, 1) + 1, mesh.faces(f, 2) + 1);
  if (std::fclose(file) != 0) throw std::runtime_error("cannot write " + temporary.string());
  std::filesystem::rename(temporary, path);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) {
    std::cerr << "usage: corpus_edit_reference REST.obj EDIT.json PREFIX [--most-iterations N] "
                 "[--last-step S]\n";
    return 2;
  }
  long most_iterations = 50000;
  std::vector<std::string> measured;
  double last_step = 1e-10;
  for (int i = 4; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--most-iterations") {
      most_iterations = std::stol(argv[i + 1]);
    } else if (flag == "--energy-of") {
      measured.push_back(argv[i + 1]);
    } else if (flag == "--last-step") {
      last_step = std::stod(argv[i + 1]);
    } else {
      std::cerr << "unknown option " << flag << "\n";
      return 2;
    }
  }
  try {
    const Mesh mesh = harmonia::read_mesh(argv[1]);
    const harmonia::EditDescription edit = harmonia::read_edit_file(argv[2], mesh);
    const std::string prefix = argv[3];
    const Constraints constraints = constraints_of(mesh, edit);
    const ArapIteration arap(mesh, constraints);
    if (!measured.empty()) {
      for (const std::string& file : measured)
        std::printf("%s: ARAP energy %.9g\n", file.c_str(), arap.energy(harmonia::read_mesh(file).vertices));
      return 0;
    }
    const double diagonal = (mesh.vertices.colwise().maxCoeff() - mesh.vertices.colwise().minCoeff()).norm();
    write_positions(prefix + ".harmonic.obj", mesh, arap.harmonic_baseline());
    Eigen::MatrixX3d positions = constraints.targets;  // the cold start
    double step = 0.0;
    long iteration = 0;
    while (iteration < most_iterations) {
      Eigen::MatrixX3d next = arap.step(positions);
      step = (next - positions).rowwise().norm().maxCoeff() / diagonal;
      positions = std::move(next);
      ++iteration;
      if (iteration == 10) write_positions(prefix + ".arap10.obj", mesh, positions);
      if (iteration >= 10 && step <= last_step) break;
    }
    write_positions(prefix + ".arap500.obj", mesh, positions);
    std::printf("%s: %ld iterations, last step %.3g of the diagonal\n", prefix.c_str(), iteration, step);
  } catch (const std::exception& error) {
    std::cerr << "corpus_edit_reference: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
