#include "kernels/spmv.h"

#include <stdexcept>

namespace harmonia::vulkan::detail {

void record_spmv(CommandRecorder& recorder, const VulkanMatrix& a, const VulkanVectors& x,
                 VulkanVectors& y) {
  if (a.cols() != x.rows() || a.rows() != y.rows() || x.cols() != y.cols())
    throw std::invalid_argument("vulkan backend: spmv: shapes differ");
  if (&x == &y) throw std::invalid_argument("vulkan backend: spmv: y must not be x");
  const SpmvPush push{static_cast<std::uint32_t>(a.rows()), static_cast<std::uint32_t>(a.cols())};
  const auto columns = static_cast<std::uint32_t>(x.cols());
  const std::initializer_list<const Buffer*> buffers{&a.row_offsets(), &a.columns(), &a.values(),
                                                     &x.buffer(), &y.buffer()};
  if (a.mean_row_length() >= spmv_lanes_min_mean_row_length) {
    const std::uint64_t lanes = recorder.context().lanes_per_row;
    recorder.dispatch(spmv_lanes_program, buffers, push,
                      recorder.groups_for(static_cast<std::uint64_t>(a.rows()) * lanes), columns);
  } else {
    recorder.dispatch(spmv_rows_program, buffers, push,
                      recorder.groups_for(static_cast<std::uint64_t>(a.rows())), columns);
  }
  y.written_on_device();
}

}  // namespace harmonia::vulkan::detail
