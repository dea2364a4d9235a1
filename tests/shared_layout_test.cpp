// SharedLayout: host and device agree on sizeof/offsetof of every shared struct.
#include <gtest/gtest.h>

#include <cstddef>
#include <string>
#include <vector>

#include "shared/ao_types.h"
#include "shared/bdpt_types.h"
#include "shared/ic_types.h"
#include "shared/indirect_types.h"
#include "shared/mlt_types.h"
#include "shared/photon_types.h"
#include "shared/render_types.h"
#include "shared/scene_types.h"
#include "shared/aov_types.h"
#include "shared/vcm_types.h"
#include "support/device.h"

namespace clpt::shared_layout_test {
namespace {

struct Entry {
  std::string what;
  uint32_t host;
};

std::vector<Entry> host_layout() {
  std::vector<Entry> e;
#define LAYOUT_STRUCT(T) e.push_back({"sizeof(" #T ")", uint32_t(sizeof(dev::T))});
#define LAYOUT_FIELD(T, f) e.push_back({"offsetof(" #T ", " #f ")", uint32_t(offsetof(dev::T, f))});
#include "kernels/layout_fields.h"
#undef LAYOUT_STRUCT
#undef LAYOUT_FIELD
  return e;
}

TEST(SharedLayout, HostMatchesDevice) {
  const std::vector<Entry> host = host_layout();
  ASSERT_GT(host.size(), 30u);
  cl::Context& ctx = test::device_context();
  cl::Program program(ctx, "kernels/layout_test.cl", "", test::test_kernel_sources());
  cl::Kernel kernel(program, "shared_layout");
  std::vector<uint32_t> init(host.size() + 1, 0xffffffffu);
  cl::Buffer out = cl::Buffer::from_vector(ctx, init, CL_MEM_READ_WRITE);
  kernel.args(0, out);
  kernel.launch(ctx, 1);
  const std::vector<uint32_t> device = out.read_vector<uint32_t>(init.size());
  for (size_t i = 0; i < host.size(); ++i)
    EXPECT_EQ(host[i].host, device[i]) << host[i].what << " differs between host and device";
  EXPECT_EQ(device[host.size()], 0xffffffffu) << "the device reported more entries than the host";
}

TEST(SharedLayout, FixedSizes) {
  // Sizes the design depends on (memory per triangle, 32-byte BVH nodes).
  EXPECT_EQ(sizeof(dev::BvhNode4), 128u);
  EXPECT_EQ(sizeof(dev::Triangle), 16u);
  EXPECT_EQ(sizeof(dev::Vertex), 32u);
  EXPECT_EQ(sizeof(dev::VertexExtra), 48u);
  EXPECT_EQ(sizeof(dev::Light), 96u);
  EXPECT_EQ(sizeof(dev::Material), 736u);
}

}  // namespace
}  // namespace clpt::shared_layout_test
