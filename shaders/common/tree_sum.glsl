// Deterministic workgroup sums: a pairwise tree over shared memory in a fixed order, so the same
// input on the same device gives the same bits on every run (no float atomics, and no subgroup
// arithmetic whose order the driver picks). The width is a power of two (kernels/pipelines.h).
shared real partial_sums[gl_WorkGroupSize.x];

// Sums `value` over groups of `span` consecutive invocations (span a power of two dividing the
// width); the first invocation of each group gets the total in partial_sums[its index]. Every
// invocation of the workgroup must call it (it contains barriers).
void tree_sum(real value, uint span) {
  const uint me = gl_LocalInvocationID.x;
  partial_sums[me] = value;
  barrier();
  for (uint half_span = span / 2; half_span > 0; half_span /= 2) {
    if ((me % span) < half_span) partial_sums[me] += partial_sums[me + half_span];
    barrier();
  }
}
