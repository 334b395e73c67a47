#pragma once
// Internal: element-wise kernels on blocks of vectors (column by column).
//   shaders/linear_combination.comp: y = a x + b y with per-column a, b -> axpy, xpay, copy, scale.
//   shaders/jacobi.comp: z = r ./ diag(A).
// Eigen twins: CpuBackend::axpy, xpay, copy, jacobi.

#include <cstddef>
#include <cstdint>
#include <optional>

#include "kernels/device_arrays.h"
#include "kernels/pipelines.h"
#include "kernels/recorder.h"

namespace harmonia::vulkan::detail {

// Mirrors `Push` in shaders/linear_combination.comp.
struct LinearCombinationPush {
  std::uint32_t rows;
  std::uint32_t alpha_index;
  std::uint32_t beta_index;
  std::uint32_t flags;  // LinearCombinationFlag bits.
  float alpha_factor;
  float beta_factor;
};
static_assert(sizeof(LinearCombinationPush) == 24);
static_assert(offsetof(LinearCombinationPush, flags) == 12);
static_assert(offsetof(LinearCombinationPush, alpha_factor) == 16);
static_assert(offsetof(LinearCombinationPush, beta_factor) == 20);

enum LinearCombinationFlag : std::uint32_t {
  alpha_from_buffer = 1u,
  beta_from_buffer = 2u,
  read_y = 4u,
};

// Mirrors `Push` in shaders/jacobi.comp.
struct JacobiPush {
  std::uint32_t rows;
};
static_assert(sizeof(JacobiPush) == 4);

enum class LinearCombinationBinding : std::uint32_t { coefficients, x, y, count };
enum class JacobiBinding : std::uint32_t { inverse_diagonal, r, z, count };

extern const KernelProgram linear_combination_program;
extern const KernelProgram jacobi_program;

// A coefficient of the combination: factor, times coefficients[index + column] when index is set.
struct Coefficient {
  float factor = 1.0f;
  std::optional<std::uint32_t> index;
};

// Error of y = a x + b y relative to |a x| + |b y|: a, b, x, y rounded to float (u each; a, b
// given in double), two products and one sum rounded, u = 2^-24, plus one u of slack.
constexpr double linear_combination_error_bound = 6.0 * 0x1p-24;
// Error of z = r ./ d relative to |z|: 1/d formed in double and rounded (u), r rounded (u), the
// product rounded (u), plus one u of slack.
constexpr double jacobi_error_bound = 4.0 * 0x1p-24;

// Records y = alpha x + beta y (beta unset: y = alpha x, y not read). x may be y (scale).
void record_linear_combination(CommandRecorder& recorder, const Buffer& coefficients,
                               Coefficient alpha, const VulkanVectors& x,
                               std::optional<Coefficient> beta, VulkanVectors& y);

// Records z = r ./ diag(A).
void record_jacobi(CommandRecorder& recorder, const VulkanMatrix& a, const VulkanVectors& r,
                   VulkanVectors& z);

}  // namespace harmonia::vulkan::detail
