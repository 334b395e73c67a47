// The embedded SPIR-V of shaders/normal_product.comp (its only translation unit), its product
// map and its refresh.
#include "kernels/normal_product.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "kernels/device_arrays.h"
#include "kernels/device_reals.h"
#include "kernels/transfers.h"
#include "normal_product.spv.h"
#include "normal_product_fp64.spv.h"

namespace harmonia::vulkan::detail {
namespace {

std::uint64_t word_bytes(std::size_t count) { return static_cast<std::uint64_t>(count) * 4; }

}  // namespace

namespace {
// The same shader compiled with double arithmetic (shaders/common/real.glsl).
const KernelProgram normal_product_fp64_program{
    "normal_product_fp64", normal_product_fp64_spv, sizeof(normal_product_fp64_spv),
    static_cast<std::uint32_t>(NormalProductBinding::count), sizeof(NormalProductPush)};
}  // namespace

const KernelProgram normal_product_program{
    "normal_product",           normal_product_spv,
    sizeof(normal_product_spv), static_cast<std::uint32_t>(NormalProductBinding::count),
    sizeof(NormalProductPush),  &normal_product_fp64_program};

NormalProductMap build_normal_product_map(const harmonia::detail::RowMajorSparse& b) {
  if (!b.isCompressed()) throw std::invalid_argument("vulkan normal product: B must be compressed");
  const auto rows = static_cast<int>(b.rows());
  const auto columns = static_cast<std::size_t>(b.cols());
  // Column k of B: the entry indices of its nonzeros, by increasing row.
  std::vector<std::vector<int>> column_entries(columns);
  for (int row = 0; row < rows; ++row)
    for (int entry = b.outerIndexPtr()[row]; entry < b.outerIndexPtr()[row + 1]; ++entry)
      column_entries[static_cast<std::size_t>(b.innerIndexPtr()[entry])].push_back(entry);
  std::vector<int> entry_rows(static_cast<std::size_t>(b.nonZeros()));
  for (int row = 0; row < rows; ++row)
    for (int entry = b.outerIndexPtr()[row]; entry < b.outerIndexPtr()[row + 1]; ++entry)
      entry_rows[static_cast<std::size_t>(entry)] = row;
  const auto row_of = [&](int entry) { return entry_rows[static_cast<std::size_t>(entry)]; };
  // Pattern: (i, j) for every pair of rows sharing a column.
  std::vector<std::vector<int>> neighbours(static_cast<std::size_t>(rows));
  for (const auto& entries : column_entries)
    for (const int left : entries)
      for (const int right : entries)
        neighbours[static_cast<std::size_t>(row_of(left))].push_back(row_of(right));
  std::vector<Eigen::Triplet<double>> triplets;
  for (int row = 0; row < rows; ++row) {
    auto& list = neighbours[static_cast<std::size_t>(row)];
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    for (const int col : list) triplets.emplace_back(row, col, 0.0);
  }
  NormalProductMap map;
  map.pattern.resize(rows, rows);
  map.pattern.setFromTriplets(triplets.begin(), triplets.end());
  map.pattern.makeCompressed();
  const auto slot_of = [&](int row, int col) {
    const int* begin = map.pattern.innerIndexPtr() + map.pattern.outerIndexPtr()[row];
    const int* end = map.pattern.innerIndexPtr() + map.pattern.outerIndexPtr()[row + 1];
    return static_cast<std::size_t>(std::lower_bound(begin, end, col) -
                                    map.pattern.innerIndexPtr());
  };
  // Products in increasing column k within each entry: count, then fill, walking k upwards.
  const auto for_each_product = [&](auto visit) {
    for (std::size_t k = 0; k < columns; ++k)
      for (const int left : column_entries[k])
        for (const int right : column_entries[k])
          visit(slot_of(row_of(left), row_of(right)), left, right, k);
  };
  const auto entries = static_cast<std::size_t>(map.pattern.nonZeros());
  map.slot_offsets.assign(entries + 1, 0);
  for_each_product([&](std::size_t slot, int, int, std::size_t) { ++map.slot_offsets[slot + 1]; });
  for (std::size_t slot = 0; slot < entries; ++slot)
    map.slot_offsets[slot + 1] += map.slot_offsets[slot];
  map.products.resize(3 * static_cast<std::size_t>(map.slot_offsets.back()));
  std::vector<std::uint32_t> next(map.slot_offsets.begin(), map.slot_offsets.end() - 1);
  for_each_product([&](std::size_t slot, int left, int right, std::size_t k) {
    const std::size_t product = next[slot]++;
    map.products[3 * product] = static_cast<std::uint32_t>(left);
    map.products[3 * product + 1] = static_cast<std::uint32_t>(right);
    map.products[3 * product + 2] = static_cast<std::uint32_t>(k);
  });
  return map;
}

NormalProduct::NormalProduct(CommandRecorder& recorder, const harmonia::detail::RowMajorSparse& b,
                             DevicePrecision precision)
    : recorder_(recorder),
      precision_(precision),
      map_(build_normal_product_map(b)),
      b_entries_(b.nonZeros()),
      b_columns_(b.cols()),
      slot_offsets_(recorder.context(), word_bytes(map_.slot_offsets.size()), BufferRole::device,
                    "normal product slot offsets"),
      products_(recorder.context(), word_bytes(map_.products.size()), BufferRole::device,
                "normal product terms"),
      b_values_(recorder.context(), real_bytes(precision, static_cast<std::size_t>(b.nonZeros())),
                BufferRole::device, "B values"),
      diagonal_(recorder.context(), real_bytes(precision, static_cast<std::size_t>(b.cols())),
                BufferRole::device, "D diagonal"),
      values_(recorder.context(),
              real_bytes(precision, static_cast<std::size_t>(map_.pattern.nonZeros())),
              BufferRole::device, "normal product values") {
  write_buffer(recorder_, slot_offsets_, map_.slot_offsets.data(),
               word_bytes(map_.slot_offsets.size()));
  write_buffer(recorder_, products_, map_.products.data(), word_bytes(map_.products.size()));
}

void NormalProduct::update(const Eigen::Ref<const Eigen::VectorXd>& b_values,
                           const Eigen::Ref<const Eigen::VectorXd>& diagonal) {
  upload(b_values, diagonal);
  recorder_.begin();
  record(recorder_);
  recorder_.end();
  recorder_.submit_and_wait();
}

void NormalProduct::upload(const Eigen::Ref<const Eigen::VectorXd>& b_values,
                           const Eigen::Ref<const Eigen::VectorXd>& diagonal) {
  if (b_values.size() != b_entries_ || diagonal.size() != b_columns_)
    throw std::invalid_argument("vulkan normal product: " + std::to_string(b_values.size()) +
                                " B values and " + std::to_string(diagonal.size()) +
                                " weights for a B with " + std::to_string(b_entries_) +
                                " entries and " + std::to_string(b_columns_) + " columns");
  const Eigen::VectorXd b_copy = b_values, d_copy = diagonal;
  const std::vector<std::byte> b_reals =
      encode_reals(b_copy.data(), static_cast<std::size_t>(b_copy.size()), precision_, "B value");
  const std::vector<std::byte> d_reals =
      encode_reals(d_copy.data(), static_cast<std::size_t>(d_copy.size()), precision_, "D weight");
  write_buffer(recorder_, b_values_, b_reals.data(), b_reals.size());
  write_buffer(recorder_, diagonal_, d_reals.data(), d_reals.size());
}

void NormalProduct::record(CommandRecorder& recorder) { record(recorder, values_); }

void NormalProduct::record(CommandRecorder& recorder, const Buffer& target) {
  const auto entries = static_cast<std::uint32_t>(map_.pattern.nonZeros());
  if (target.bytes() < real_bytes(precision_, entries))
    throw std::logic_error("vulkan normal product: the target buffer is too small");
  recorder.dispatch(in_precision(normal_product_program, precision_),
                    {&slot_offsets_, &products_, &b_values_, &diagonal_, &target},
                    NormalProductPush{entries}, recorder.groups_for(entries));
}

harmonia::detail::RowMajorSparse NormalProduct::download() const {
  return read_pattern_values(recorder_, values_, map_.pattern, precision_);
}

}  // namespace harmonia::vulkan::detail
