#include "kernels/triangle_assembly.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "kernels/device_arrays.h"
#include "kernels/device_reals.h"
#include "kernels/transfers.h"
#include "kernels/triangle_tensors.h"
#include "mesh/adjacency_pattern.h"

namespace harmonia::vulkan::detail {
namespace {

std::uint64_t word_bytes(std::size_t count) { return static_cast<std::uint64_t>(count) * 4; }

}  // namespace

double triangle_stiffness_conditioning(const Eigen::MatrixXd& corners, double tensor_norm) {
  double longest = 0.0, shortest = std::numeric_limits<double>::infinity(), farthest = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double length = (corners.row((k + 1) % 3) - corners.row(k)).norm();
    longest = std::max(longest, length);
    shortest = std::min(shortest, length);
    farthest = std::max(farthest, corners.row(k).norm());
  }
  Eigen::Vector3d u = Eigen::Vector3d::Zero(), v = Eigen::Vector3d::Zero();
  u.head(corners.cols()) = (corners.row(1) - corners.row(0)).transpose();
  v.head(corners.cols()) = (corners.row(2) - corners.row(0)).transpose();
  const double twice_area = u.cross(v).norm();
  if (twice_area == 0.0) return std::numeric_limits<double>::infinity();
  const double kappa = longest * longest / twice_area;
  return kappa * kappa * (1.0 + farthest / shortest) * tensor_norm;
}

AssemblySlotMap build_assembly_slot_map(const Eigen::MatrixX3i& faces, int vertex_count) {
  harmonia::detail::check_face_indices(faces, vertex_count, "triangle assembly");
  // Row r of the pattern: r itself and every vertex sharing a face with r, sorted.
  std::vector<std::vector<int>> neighbours(static_cast<std::size_t>(vertex_count));
  for (int v = 0; v < vertex_count; ++v) neighbours[static_cast<std::size_t>(v)].push_back(v);
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        if (a != b) neighbours[static_cast<std::size_t>(faces(f, a))].push_back(faces(f, b));
  AssemblySlotMap map;
  map.face_count = static_cast<int>(faces.rows());
  std::vector<Eigen::Triplet<double>> entries;
  for (int row = 0; row < vertex_count; ++row) {
    auto& list = neighbours[static_cast<std::size_t>(row)];
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    for (const int col : list) entries.emplace_back(row, col, 0.0);
  }
  map.pattern.resize(vertex_count, vertex_count);
  map.pattern.setFromTriplets(entries.begin(), entries.end());
  map.pattern.makeCompressed();

  // Count, then fill, the contributions of each slot in (face, pair) order: the order in which
  // the host assembly adds them.
  const auto slot_of = [&](int row, int col) {
    const int* begin = map.pattern.innerIndexPtr() + map.pattern.outerIndexPtr()[row];
    const int* end = map.pattern.innerIndexPtr() + map.pattern.outerIndexPtr()[row + 1];
    return static_cast<std::size_t>(std::lower_bound(begin, end, col) -
                                    map.pattern.innerIndexPtr());
  };
  const auto nonzeros = static_cast<std::size_t>(map.pattern.nonZeros());
  map.slot_offsets.assign(nonzeros + 1, 0);
  const auto for_each_pair = [&](auto visit) {
    for (Eigen::Index f = 0; f < faces.rows(); ++f) {
      for (int a = 0; a < 3; ++a) {
        const int i = faces(f, a), j = faces(f, (a + 1) % 3);
        if (i == j) continue;  // Lands on the diagonal, which the gather recomputes.
        const auto contribution = static_cast<std::uint32_t>(3 * f + a);
        visit(slot_of(i, j), contribution);
        visit(slot_of(j, i), contribution);
      }
    }
  };
  for_each_pair([&](std::size_t slot, std::uint32_t) { ++map.slot_offsets[slot + 1]; });
  for (std::size_t slot = 0; slot < nonzeros; ++slot)
    map.slot_offsets[slot + 1] += map.slot_offsets[slot];
  map.slot_contributions.resize(map.slot_offsets.back());
  std::vector<std::uint32_t> next(map.slot_offsets.begin(), map.slot_offsets.end() - 1);
  for_each_pair([&](std::size_t slot, std::uint32_t contribution) {
    map.slot_contributions[next[slot]++] = contribution;
  });
  return map;
}

TriangleAssembly::TriangleAssembly(CommandRecorder& recorder, const Eigen::MatrixX3i& faces,
                                   int vertex_count, DevicePrecision precision)
    : recorder_(recorder),
      precision_(precision),
      map_(build_assembly_slot_map(faces, vertex_count)),
      vertex_count_(vertex_count),
      faces_(recorder.context(), word_bytes(3 * static_cast<std::size_t>(faces.rows())),
             BufferRole::device, "assembly faces"),
      row_offsets_(recorder.context(), word_bytes(static_cast<std::size_t>(vertex_count) + 1),
                   BufferRole::device, "assembly row offsets"),
      columns_(recorder.context(), word_bytes(map_.slot_offsets.size() - 1), BufferRole::device,
               "assembly column indices"),
      slot_offsets_(recorder.context(), word_bytes(map_.slot_offsets.size()), BufferRole::device,
                    "assembly slot offsets"),
      slot_contributions_(recorder.context(), word_bytes(map_.slot_contributions.size()),
                          BufferRole::device, "assembly slot contributions"),
      contributions_(recorder.context(),
                     real_bytes(precision, 3 * static_cast<std::size_t>(faces.rows())),
                     BufferRole::device, "per-triangle stiffness"),
      values_(recorder.context(), real_bytes(precision, map_.slot_offsets.size() - 1),
              BufferRole::device, "assembled values"),
      tensors_(recorder.context(),
               real_bytes(precision, 4 * static_cast<std::size_t>(faces.rows())),
               BufferRole::device, "triangle tensors"),
      positions_(recorder.context(),
                 real_bytes(precision, 3 * static_cast<std::size_t>(vertex_count)),
                 BufferRole::device, "assembly 3D positions"),
      points_(recorder.context(), real_bytes(precision, 3 * static_cast<std::size_t>(vertex_count)),
              BufferRole::device, "assembly points") {
  std::vector<std::uint32_t> corners(3 * static_cast<std::size_t>(faces.rows()));
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      corners[static_cast<std::size_t>(3 * f + k)] = static_cast<std::uint32_t>(faces(f, k));
  const std::vector<std::uint32_t> offsets(map_.pattern.outerIndexPtr(),
                                           map_.pattern.outerIndexPtr() + vertex_count + 1);
  const std::vector<std::uint32_t> columns(map_.pattern.innerIndexPtr(),
                                           map_.pattern.innerIndexPtr() + map_.pattern.nonZeros());
  write_buffer(recorder_, faces_, corners.data(), word_bytes(corners.size()));
  write_buffer(recorder_, row_offsets_, offsets.data(), word_bytes(offsets.size()));
  write_buffer(recorder_, columns_, columns.data(), word_bytes(columns.size()));
  write_buffer(recorder_, slot_offsets_, map_.slot_offsets.data(),
               word_bytes(map_.slot_offsets.size()));
  write_buffer(recorder_, slot_contributions_, map_.slot_contributions.data(),
               word_bytes(map_.slot_contributions.size()));
}

void TriangleAssembly::upload_points(Buffer& target, const double* data, std::size_t count) {
  const std::vector<std::byte> converted =
      encode_reals(data, count, precision_, "assembly point coordinate");
  write_buffer(recorder_, target, converted.data(), converted.size());
}

void TriangleAssembly::assemble_cotangent(const Eigen::MatrixX3d& positions) {
  if (positions.rows() != vertex_count_)
    throw std::invalid_argument("vulkan triangle assembly: " + std::to_string(positions.rows()) +
                                " positions for " + std::to_string(vertex_count_) + " vertices");
  const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> interleaved = positions;
  upload_points(points_, interleaved.data(), static_cast<std::size_t>(interleaved.size()));
  submit(StiffnessKind::cotangent);
}

void TriangleAssembly::assemble_tensor(const Eigen::MatrixX2d& uv, const TriangleTensors& tensors) {
  if (uv.rows() != vertex_count_ || tensors.rows() != map_.face_count)
    throw std::invalid_argument("vulkan triangle assembly: " + std::to_string(uv.rows()) +
                                " uv rows and " + std::to_string(tensors.rows()) + " tensors for " +
                                std::to_string(vertex_count_) + " vertices and " +
                                std::to_string(map_.face_count) + " faces");
  const Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor> interleaved = uv;
  upload_points(points_, interleaved.data(), static_cast<std::size_t>(interleaved.size()));
  const std::vector<std::byte> converted =
      encode_reals(tensors.data(), static_cast<std::size_t>(tensors.size()), precision_,
                   "triangle tensor entry");
  write_buffer(recorder_, tensors_, converted.data(), converted.size());
  submit(StiffnessKind::tensor);
}

void TriangleAssembly::assemble_quasi_harmonic(const Eigen::MatrixX3d& positions,
                                               const Eigen::MatrixX2d& uv) {
  if (positions.rows() != vertex_count_ || uv.rows() != vertex_count_)
    throw std::invalid_argument("vulkan triangle assembly: " + std::to_string(positions.rows()) +
                                " positions and " + std::to_string(uv.rows()) + " uv rows for " +
                                std::to_string(vertex_count_) + " vertices");
  const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> positions_interleaved = positions;
  upload_points(positions_, positions_interleaved.data(),
                static_cast<std::size_t>(positions_interleaved.size()));
  const Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor> uv_interleaved = uv;
  upload_points(points_, uv_interleaved.data(), static_cast<std::size_t>(uv_interleaved.size()));
  recorder_.begin();
  record_triangle_tensors(recorder_, faces_, positions_, points_, tensors_,
                          static_cast<std::uint32_t>(map_.face_count), precision_);
  record(recorder_, StiffnessKind::tensor);
  recorder_.end();
  recorder_.submit_and_wait();
}

TriangleTensors TriangleAssembly::download_tensors() const {
  const std::size_t count = 4 * static_cast<std::size_t>(map_.face_count);
  std::vector<std::byte> bytes(real_bytes(precision_, count));
  read_buffer(recorder_, tensors_, bytes.data(), bytes.size());
  TriangleTensors tensors(map_.face_count, 4);
  decode_reals(bytes.data(), count, precision_, tensors.data());
  return tensors;
}

void TriangleAssembly::submit(StiffnessKind kind) {
  recorder_.begin();
  record(recorder_, kind);
  recorder_.end();
  recorder_.submit_and_wait();
}

void TriangleAssembly::record(CommandRecorder& recorder, StiffnessKind kind) {
  const auto face_count = static_cast<std::uint32_t>(map_.face_count);
  recorder.dispatch(in_precision(triangle_stiffness_program, precision_),
                    {&faces_, &points_, &tensors_, &contributions_},
                    TriangleStiffnessPush{face_count, static_cast<std::uint32_t>(kind)},
                    recorder.groups_for(face_count));
  const auto rows = static_cast<std::uint32_t>(vertex_count_);
  recorder.dispatch(
      in_precision(slot_gather_program, precision_),
      {&row_offsets_, &columns_, &slot_offsets_, &slot_contributions_, &contributions_, &values_},
      SlotGatherPush{rows}, recorder.groups_for(rows));
}

harmonia::detail::RowMajorSparse TriangleAssembly::download() const {
  return read_pattern_values(recorder_, values_, map_.pattern, precision_);
}

}  // namespace harmonia::vulkan::detail
