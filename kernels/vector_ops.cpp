#include "kernels/vector_ops.h"

#include <stdexcept>

namespace harmonia::vulkan::detail {

void record_linear_combination(CommandRecorder& recorder, const Buffer& coefficients,
                               Coefficient alpha, const VulkanVectors& x,
                               std::optional<Coefficient> beta, VulkanVectors& y) {
  if (x.rows() != y.rows() || x.cols() != y.cols())
    throw std::invalid_argument("vulkan backend: vector update: block shapes differ");
  LinearCombinationPush push{};
  push.rows = static_cast<std::uint32_t>(x.rows());
  push.alpha_factor = alpha.factor;
  if (alpha.index) {
    push.flags |= alpha_from_buffer;
    push.alpha_index = *alpha.index;
  }
  if (beta) {
    push.flags |= read_y;
    push.beta_factor = beta->factor;
    if (beta->index) {
      push.flags |= beta_from_buffer;
      push.beta_index = *beta->index;
    }
  }
  recorder.dispatch(in_precision(linear_combination_program, y.precision()),
                    {&coefficients, &x.buffer(), &y.buffer()}, push,
                    recorder.groups_for(static_cast<std::uint64_t>(x.rows())),
                    static_cast<std::uint32_t>(x.cols()));
  y.written_on_device();
}

void record_jacobi(CommandRecorder& recorder, const VulkanMatrix& a, const VulkanVectors& r,
                   VulkanVectors& z) {
  if (r.rows() != z.rows() || r.cols() != z.cols() || a.rows() != r.rows())
    throw std::invalid_argument("vulkan backend: jacobi: shapes differ");
  recorder.dispatch(in_precision(jacobi_program, z.precision()),
                    {&a.inverse_diagonal(), &r.buffer(), &z.buffer()},
                    JacobiPush{static_cast<std::uint32_t>(r.rows())},
                    recorder.groups_for(static_cast<std::uint64_t>(r.rows())),
                    static_cast<std::uint32_t>(r.cols()));
  z.written_on_device();
}

}  // namespace harmonia::vulkan::detail
