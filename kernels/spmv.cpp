#include "kernels/spmv.h"

#include <stdexcept>

namespace harmonia::vulkan::detail {

void record_spmv(CommandRecorder& recorder, const VulkanMatrix& a, const VulkanVectors& x,
                 VulkanVectors& y) {
  if (a.cols() != x.rows() || a.rows() != y.rows() || x.cols() != y.cols())
    throw std::invalid_argument("vulkan backend: spmv: shapes differ");
  if (&x == &y) throw std::invalid_argument("vulkan backend: spmv: y must not be x");
  if (a.precision() != x.precision() || x.precision() != y.precision())
    throw std::logic_error("vulkan backend: spmv: mixed precisions");
  const SpmvPush push{static_cast<std::uint32_t>(a.rows()), static_cast<std::uint32_t>(a.cols())};
  const auto columns = static_cast<std::uint32_t>(x.cols());
  const std::initializer_list<const Buffer*> buffers{&a.row_offsets(), &a.columns(), &a.values(),
                                                     &x.buffer(), &y.buffer()};
  if (a.mean_row_length() >= spmv_lanes_min_mean_row_length) {
    const std::uint64_t lanes = recorder.context().lanes_per_row;
    recorder.dispatch(in_precision(spmv_lanes_program, x.precision()), buffers, push,
                      recorder.groups_for(static_cast<std::uint64_t>(a.rows()) * lanes), columns);
  } else {
    recorder.dispatch(in_precision(spmv_rows_program, x.precision()), buffers, push,
                      recorder.groups_for(static_cast<std::uint64_t>(a.rows())), columns);
  }
  y.written_on_device();
}

}  // namespace harmonia::vulkan::detail
