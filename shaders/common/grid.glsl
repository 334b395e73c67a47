// Shared by every kernel: the workgroup width is specialization constant 0, chosen on the host
// from the device limits and subgroup size (kernels/pipelines.h); nothing assumes a width.
layout(local_size_x_id = 0) in;

// A dispatch may be capped at maxComputeWorkGroupCount, so kernels walk their items with a stride
// of the whole grid: item = first_item(); item < count; item += grid_stride().
uint first_item() { return gl_GlobalInvocationID.x; }
uint grid_stride() { return gl_NumWorkGroups.x * gl_WorkGroupSize.x; }

// The column of a block of vectors this invocation works on (blocks are column-major, n x k;
// the dispatch has one row of workgroups per column).
uint block_column() { return gl_WorkGroupID.y; }
