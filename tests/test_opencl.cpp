#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <fstream>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "compute/cl_program.h"

namespace fc = facesr::compute;

namespace {

// Machines without any OpenCL driver skip rather than fail; CI has PoCL.
#define SKIP_WITHOUT_OPENCL()                                                   \
  do {                                                                          \
    if (fc::list_devices().empty())                                             \
      GTEST_SKIP() << "no OpenCL platform found (install pocl-opencl-icd)";     \
  } while (0)

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const facesr::Error& e) {
    return e.what();
  }
  return "";
}

bool contains(const std::string& haystack, const std::string& needle) {
  return haystack.find(needle) != std::string::npos;
}

// Sets an environment variable for one scope.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    setenv(name, value.c_str(), 1);
  }
  ~ScopedEnv() {
    if (old_) setenv(name_, old_->c_str(), 1);
    else unsetenv(name_);
  }

 private:
  const char* name_;
  std::optional<std::string> old_;
};

}  // namespace

TEST(OpenCL, ListsDevices) {
  SKIP_WITHOUT_OPENCL();
  const auto devices = fc::list_devices();
  for (size_t i = 0; i < devices.size(); ++i) {
    const auto& d = devices[i];
    EXPECT_EQ(d.index, static_cast<int>(i));
    EXPECT_FALSE(d.device_name.empty());
    EXPECT_FALSE(d.platform_name.empty());
    EXPECT_GT(d.compute_units, 0u);
    EXPECT_GT(d.global_mem_bytes, 0u);
    EXPECT_GT(d.max_work_group_size, 0u);
    std::printf("  %s%s\n", fc::describe(d).c_str(), d.double_support ? " fp64" : "");
  }
}

TEST(OpenCL, DefaultSelectsCpu) {
  SKIP_WITHOUT_OPENCL();
  const fc::Context ctx;
  EXPECT_EQ(ctx.device().type, fc::DeviceType::Cpu) << fc::describe(ctx.device());
  // The same device is reachable by index and by name.
  EXPECT_EQ(fc::select_device(fc::DeviceSelector::parse(std::to_string(ctx.device().index))).device_id,
            ctx.device().device_id);
  EXPECT_EQ(fc::select_device(fc::DeviceSelector::parse(ctx.device().device_name)).device_id,
            ctx.device().device_id);
}

TEST(OpenCL, SelectorParsing) {
  EXPECT_EQ(fc::DeviceSelector::parse("GPU").type, fc::DeviceType::Gpu);
  EXPECT_EQ(fc::DeviceSelector::parse("3").index, 3);
  EXPECT_EQ(fc::DeviceSelector::parse("nvidia").name, "nvidia");
  EXPECT_FALSE(fc::DeviceSelector::parse("").index.has_value());
  EXPECT_THROW(fc::parse_device_type("tpu"), facesr::Error);
}

TEST(OpenCL, UnknownDeviceNameThrows) {
  SKIP_WITHOUT_OPENCL();
  fc::DeviceSelector sel;
  sel.name = "no-such-device-xyz";
  const std::string msg = error_of([&] { fc::Context ctx(sel); });
  EXPECT_TRUE(contains(msg, "no-such-device-xyz")) << msg;
  EXPECT_TRUE(contains(msg, "available devices")) << msg;

  sel = {};
  sel.index = 100000;
  EXPECT_THROW(fc::select_device(sel), facesr::Error);
}

TEST(OpenCL, Saxpy) {
  SKIP_WITHOUT_OPENCL();
  fc::Context ctx;
  fc::Program program = ctx.build_program({"smoke.cl"});
  fc::Kernel saxpy = program.kernel("saxpy");

  const cl_uint n = 100003;  // prime: exercises the rounded-up tail
  const float a = 2.5f;
  std::vector<float> x(n), y(n);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> dist(-10.0f, 10.0f);
  for (cl_uint i = 0; i < n; ++i) x[i] = dist(rng), y[i] = dist(rng);

  fc::Buffer<float> dx(ctx, x, CL_MEM_READ_ONLY), dy(ctx, y);
  saxpy.args(n, a, dx, dy).run_1d(n, 64);
  const std::vector<float> got = dy.download();

  ASSERT_EQ(got.size(), n);
  for (cl_uint i = 0; i < n; ++i) {
    // The device may fuse a*x+y into one FMA, so allow a rounding step.
    const float want = a * x[i] + y[i];
    ASSERT_NEAR(got[i], want, 1e-6f * std::max(1.0f, std::fabs(want))) << "i=" << i;
  }
}

TEST(OpenCL, ReduceSum) {
  SKIP_WITHOUT_OPENCL();
  fc::Context ctx;
  fc::Kernel reduce = ctx.build_program({"smoke.cl"}).kernel("reduce_sum");

  const cl_uint n = 1u << 20;
  std::vector<float> x(n);
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> dist(0.0f, 1.0f);
  double want = 0.0;
  for (float& v : x) want += (v = dist(rng));

  size_t local = 256;
  while (local > reduce.max_work_group_size()) local /= 2;  // stays a power of two
  const size_t groups = 64;
  fc::Buffer<float> dx(ctx, x, CL_MEM_READ_ONLY), partial(ctx, groups);
  reduce.args(n, dx, partial, fc::LocalMemory{local * sizeof(float)}).run_1d(groups * local, local);

  double got = 0.0;
  for (float p : partial.download()) got += p;
  EXPECT_NEAR(got, want, 1e-5 * want);
}

TEST(OpenCL, BuildErrorContainsLog) {
  SKIP_WITHOUT_OPENCL();
  fc::Context ctx;
  const std::string src = "__kernel void broken(__global float* x) { x[0] = undeclared_thing; }";
  const std::string msg = error_of([&] { ctx.build_program_from_source("broken.cl", src); });
  EXPECT_TRUE(contains(msg, "broken.cl")) << msg;
  EXPECT_TRUE(contains(msg, ctx.device().device_name)) << msg;
  EXPECT_TRUE(contains(msg, "CL_BUILD_PROGRAM_FAILURE")) << msg;
  EXPECT_TRUE(contains(msg, "undeclared_thing")) << msg;  // from the compiler's log
}

TEST(OpenCL, UnknownKernelFileThrows) {
  SKIP_WITHOUT_OPENCL();
  fc::Context ctx;
  const std::string msg = error_of([&] { ctx.build_program({"missing_kernel.cl"}); });
  EXPECT_TRUE(contains(msg, "missing_kernel.cl")) << msg;
  EXPECT_TRUE(contains(msg, "smoke.cl")) << msg;  // lists what is available
}

TEST(OpenCL, UnknownKernelNameThrows) {
  SKIP_WITHOUT_OPENCL();
  fc::Context ctx;
  const fc::Program program = ctx.build_program({"smoke.cl"});
  const std::string msg = error_of([&] { program.kernel("no_such_kernel"); });
  EXPECT_TRUE(contains(msg, "no_such_kernel")) << msg;
  EXPECT_TRUE(contains(msg, "saxpy")) << msg;
}

TEST(OpenCL, ErrorsNameTheCodeAndCall) {
  SKIP_WITHOUT_OPENCL();
  fc::Context ctx;
  fc::Kernel saxpy = ctx.build_program({"smoke.cl"}).kernel("saxpy");
  // size_t where the kernel takes uint.
  std::string msg = error_of([&] { saxpy.arg(0, size_t{1}); });
  EXPECT_TRUE(contains(msg, "CL_INVALID_ARG_SIZE")) << msg;
  EXPECT_TRUE(contains(msg, "clSetKernelArg")) << msg;
  EXPECT_EQ(std::string(fc::cl_error_name(CL_INVALID_KERNEL_ARGS)), "CL_INVALID_KERNEL_ARGS");

  fc::Buffer<float> small(ctx, 4);
  std::vector<float> too_many(5);
  EXPECT_THROW(small.upload(too_many), facesr::Error);
}

TEST(OpenCL, KernelDirOverride) {
  SKIP_WITHOUT_OPENCL();
  const auto dir = std::filesystem::temp_directory_path() / "facesr_cl_dir_test";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "smoke.cl") << "__kernel void from_override(__global float* x) { x[0] = 1.0f; }\n";

  fc::Context ctx;
  {
    ScopedEnv env("FACESR_CL_DIR", dir.string());
    const fc::Program program = ctx.build_program({"smoke.cl"});
    EXPECT_EQ(program.kernel_names(), std::vector<std::string>{"from_override"});
    EXPECT_THROW(ctx.build_program({"absent.cl"}), facesr::Error);
  }
  std::filesystem::remove_all(dir);
}

// #include "name" lines are replaced by that kernel file (recursively), the
// same file as often as it is included; a missing one names itself.
TEST(OpenCL, KernelIncludesAreExpanded) {
  const auto dir = std::filesystem::temp_directory_path() / "facesr_cl_include_test";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "twice.h") << "#include \"leaf.h\"\n";
  std::ofstream(dir / "leaf.h") << "KERNEL_LINE(N)\n";
  std::ofstream(dir / "top.cl") << "first\n  #include \"twice.h\"\nmiddle\n#include \"leaf.h\"\nlast\n";
  std::ofstream(dir / "bad.cl") << "#include \"nowhere.h\"\n";
  {
    ScopedEnv env("FACESR_CL_DIR", dir.string());
    EXPECT_EQ(fc::load_kernel_source("top.cl"), "first\nKERNEL_LINE(N)\nmiddle\nKERNEL_LINE(N)\nlast\n");
    try {
      fc::load_kernel_source("bad.cl");
      ADD_FAILURE() << "missing include accepted";
    } catch (const facesr::Error& e) {
      EXPECT_NE(std::string(e.what()).find("nowhere.h"), std::string::npos) << e.what();
    }
  }
  std::filesystem::remove_all(dir);
  // The embedded material header brings its body with it.
  const std::string material = fc::load_kernel_source("fsr_material.h");
  EXPECT_EQ(material.find("#include"), std::string::npos);
  EXPECT_NE(material.find("FSR(svd3)"), std::string::npos);
}

// Sub-devices: half the compute units each and usable; a device that cannot
// be split comes back whole; a part out of range is refused.
TEST(OpenCL, SplitDeviceHalvesComputeUnits) {
  SKIP_WITHOUT_OPENCL();
  const fc::DeviceInfo whole = fc::select_device();
  fc::DeviceSelector sel;
  sel.parts = 2;
  sel.part = 1;
  const fc::DeviceInfo half = fc::select_device(sel);
  if (whole.compute_units >= 2) {
    EXPECT_EQ(half.compute_units, whole.compute_units / 2);
    EXPECT_NE(half.device_name.find("part 2 of 2"), std::string::npos) << half.device_name;
    EXPECT_TRUE(bool(half.sub_device));
  } else {
    EXPECT_EQ(half.device_id, whole.device_id);
  }
  fc::Context ctx(half);
  fc::Kernel saxpy = ctx.build_program({"smoke.cl"}).kernel("saxpy");
  const cl_uint n = 1000;
  std::vector<float> x(n, 1.5f), y(n, -2.0f);
  fc::Buffer<float> dx(ctx, x, CL_MEM_READ_ONLY), dy(ctx, y);
  saxpy.args(n, 2.0f, dx, dy).run_1d(n, 64);
  for (float v : dy.download()) ASSERT_EQ(v, 1.0f);
  sel.part = 2;
  EXPECT_THROW(fc::select_device(sel), facesr::Error);
}

TEST(OpenCL, EmptyBufferIsUsable) {
  SKIP_WITHOUT_OPENCL();
  fc::Context ctx;
  fc::Buffer<float> empty(ctx, std::vector<float>{});
  EXPECT_EQ(empty.size(), 0u);
  EXPECT_TRUE(empty.download().empty());
}
