#include "kernels/triangle_calculus.h"

#include <stdexcept>
#include <string>

#include "kernels/device_reals.h"
#include "kernels/transfers.h"
#include "mesh/adjacency_pattern.h"

namespace harmonia::vulkan::detail {
namespace {

std::uint64_t word_bytes(std::size_t count) { return static_cast<std::uint64_t>(count) * 4; }

void check_block(const VulkanVectors& block, int rows, const char* what, const char* operation) {
  if (block.rows() != rows)
    throw std::invalid_argument(std::string("vulkan ") + operation + ": " + what + " has " +
                                std::to_string(block.rows()) + " rows, expected " +
                                std::to_string(rows));
}

}  // namespace

TriangleCalculus::TriangleCalculus(CommandRecorder& recorder, const Eigen::MatrixX3i& faces,
                                   const Eigen::MatrixXd& positions, DevicePrecision precision)
    : recorder_(recorder),
      precision_(precision),
      face_count_(static_cast<int>(faces.rows())),
      vertex_count_(static_cast<int>(positions.rows())),
      faces_(recorder.context(), word_bytes(3 * static_cast<std::size_t>(faces.rows())),
             BufferRole::device, "calculus faces"),
      positions_(recorder.context(),
                 real_bytes(precision, 3 * static_cast<std::size_t>(positions.rows())),
                 BufferRole::device, "calculus positions"),
      vertex_offsets_(recorder.context(),
                      word_bytes(static_cast<std::size_t>(positions.rows()) + 1),
                      BufferRole::device, "vertex corner offsets"),
      corner_list_(recorder.context(), word_bytes(3 * static_cast<std::size_t>(faces.rows())),
                   BufferRole::device, "vertex corners") {
  harmonia::detail::check_face_indices(faces, positions.rows(), "triangle calculus");
  // The corners of each vertex in face order (counting sort by vertex).
  offsets_.assign(static_cast<std::size_t>(vertex_count_) + 1, 0);
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) ++offsets_[static_cast<std::size_t>(faces(f, k)) + 1];
  for (std::size_t v = 0; v < static_cast<std::size_t>(vertex_count_); ++v)
    offsets_[v + 1] += offsets_[v];
  corners_.resize(3 * static_cast<std::size_t>(face_count_));
  std::vector<std::uint32_t> next(offsets_.begin(), offsets_.end() - 1);
  std::vector<std::uint32_t> corner_vertices(corners_.size());
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const auto corner = static_cast<std::uint32_t>(3 * f + k);
      corners_[next[static_cast<std::size_t>(faces(f, k))]++] = corner;
      corner_vertices[corner] = static_cast<std::uint32_t>(faces(f, k));
    }
  }
  write_buffer(recorder_, faces_, corner_vertices.data(), word_bytes(corner_vertices.size()));
  write_buffer(recorder_, vertex_offsets_, offsets_.data(), word_bytes(offsets_.size()));
  write_buffer(recorder_, corner_list_, corners_.data(), word_bytes(corners_.size()));
  set_positions(positions);
}

void TriangleCalculus::set_positions(const Eigen::MatrixXd& positions) {
  if (positions.cols() != 2 && positions.cols() != 3)
    throw std::invalid_argument("vulkan triangle calculus: positions must have 2 or 3 columns");
  if (positions.rows() != vertex_count_)
    throw std::invalid_argument("vulkan triangle calculus: " + std::to_string(positions.rows()) +
                                " positions for " + std::to_string(vertex_count_) + " vertices");
  // Planar positions get z = 0: the kernels read 3 coordinates per vertex.
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> padded =
      Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>::Zero(positions.rows(), 3);
  padded.leftCols(positions.cols()) = positions;
  const std::vector<std::byte> coordinates =
      encode_reals(padded.data(), static_cast<std::size_t>(padded.size()), precision_,
                   "calculus position coordinate");
  write_buffer(recorder_, positions_, coordinates.data(), coordinates.size());
}

void TriangleCalculus::record_gradient(CommandRecorder& recorder, const VulkanVectors& values,
                                       VulkanVectors& gradients) {
  check_block(values, vertex_count_, "the function block", "gradient");
  check_block(gradients, 3 * face_count_, "the gradient block", "gradient");
  if (values.cols() != gradients.cols())
    throw std::invalid_argument("vulkan gradient: column counts differ");
  if (values.precision() != precision_ || gradients.precision() != precision_)
    throw std::logic_error("vulkan gradient: blocks of another precision");
  recorder.dispatch(in_precision(triangle_gradient_program, precision_),
                    {&faces_, &positions_, &values.buffer(), &gradients.buffer()},
                    TriangleGradientPush{static_cast<std::uint32_t>(face_count_),
                                         static_cast<std::uint32_t>(vertex_count_)},
                    recorder.groups_for(static_cast<std::uint64_t>(face_count_)),
                    static_cast<std::uint32_t>(values.cols()));
  gradients.written_on_device();
}

void TriangleCalculus::record_corner_sums(CommandRecorder& recorder, CornerTermsMode mode,
                                          const VulkanVectors& inputs, VulkanVectors& result) {
  const char* operation = mode == CornerTermsMode::divergence ? "divergence" : "fragment rhs";
  check_block(inputs, 3 * face_count_, "the per-triangle block", operation);
  check_block(result, vertex_count_, "the vertex block", operation);
  if (inputs.cols() != result.cols())
    throw std::invalid_argument(std::string("vulkan ") + operation + ": column counts differ");
  if (inputs.precision() != precision_ || result.precision() != precision_)
    throw std::logic_error(std::string("vulkan ") + operation + ": blocks of another precision");
  const std::uint64_t term_bytes =
      real_bytes(precision_, 3 * static_cast<std::size_t>(face_count_) *
                                 static_cast<std::size_t>(inputs.cols()));
  if (!terms_ || terms_->bytes() < term_bytes)
    terms_ = std::make_unique<Buffer>(recorder.context(), term_bytes, BufferRole::device,
                                      "per-corner terms");
  const auto columns = static_cast<std::uint32_t>(inputs.cols());
  recorder.dispatch(
      in_precision(corner_terms_program, precision_),
      {&faces_, &positions_, &inputs.buffer(), terms_.get()},
      CornerTermsPush{static_cast<std::uint32_t>(face_count_), static_cast<std::uint32_t>(mode)},
      recorder.groups_for(static_cast<std::uint64_t>(face_count_)), columns);
  recorder.dispatch(in_precision(vertex_gather_program, precision_),
                    {&vertex_offsets_, &corner_list_, terms_.get(), &result.buffer()},
                    VertexGatherPush{static_cast<std::uint32_t>(vertex_count_),
                                     static_cast<std::uint32_t>(3 * face_count_)},
                    recorder.groups_for(static_cast<std::uint64_t>(vertex_count_)), columns);
  result.written_on_device();
}

void TriangleCalculus::gradient(const VulkanVectors& values, VulkanVectors& gradients) {
  recorder_.begin();
  record_gradient(recorder_, values, gradients);
  recorder_.end();
  recorder_.submit_and_wait();
}

void TriangleCalculus::submit_corner_sums(CornerTermsMode mode, const VulkanVectors& inputs,
                                          VulkanVectors& result) {
  recorder_.begin();
  record_corner_sums(recorder_, mode, inputs, result);
  recorder_.end();
  recorder_.submit_and_wait();
}

void TriangleCalculus::divergence(const VulkanVectors& field, VulkanVectors& result) {
  submit_corner_sums(CornerTermsMode::divergence, field, result);
}

void TriangleCalculus::fragment_poisson_rhs(const VulkanVectors& fragments, VulkanVectors& rhs) {
  submit_corner_sums(CornerTermsMode::fragment, fragments, rhs);
}

}  // namespace harmonia::vulkan::detail
