// Smoke-test kernels: prove that a device compiles and runs our code, and
// exercise local memory and barriers the way the solver kernels will.

// y = a * x + y. The launch may be rounded up past n, hence the guard.
__kernel void saxpy(const uint n, const float a, __global const float* x, __global float* y) {
  const uint i = get_global_id(0);
  if (i < n) y[i] = a * x[i] + y[i];
}

// Writes one partial sum per work-group; the host adds the partials.
// Each work-item first accumulates a grid-strided slice so that any n works
// with any number of groups, then the group reduces in local memory.
// The local size must be a power of two.
__kernel void reduce_sum(const uint n, __global const float* x, __global float* partial,
                         __local float* scratch) {
  const uint lid = get_local_id(0);
  float acc = 0.0f;
  for (uint i = get_global_id(0); i < n; i += get_global_size(0)) acc += x[i];
  scratch[lid] = acc;
  barrier(CLK_LOCAL_MEM_FENCE);

  for (uint stride = get_local_size(0) / 2; stride > 0; stride /= 2) {
    if (lid < stride) scratch[lid] += scratch[lid + stride];
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  if (lid == 0) partial[get_group_id(0)] = scratch[0];
}
