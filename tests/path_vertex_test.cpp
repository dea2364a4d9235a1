// PathVertex (kernels/shared/bdpt_types.h): what bdpt, vcm and mlt keep of a light vertex
// between kernels reads back as the SurfaceHit it was stored from (tests/kernels/
// path_vertex_test.cl), the film, diffuse transmission, sheen and the coat's normal
// included. The clearcoat pair shares one word as unorm16 and the sheen's colour and
// roughness one as unorm8, which is exact because material_resolve rounds to the same
// steps; the front flag shares the material's word.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "cl/buffer.h"
#include "shared/bdpt_types.h"
#include "support/device.h"

namespace clpt::path_vertex_test {
namespace {

TEST(PathVertex, StoresTheBsdfAndTheSideExactly) {
  constexpr uint32_t n = 256;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> U(0.0f, 1.0f);
  std::vector<float> in(36 * n);
  for (uint32_t i = 0; i < n; ++i) {
    float* c = &in[36 * i];
    for (int k = 0; k < 13; ++k) c[k] = U(rng);
    c[10] = 1.0f + 2.0f * U(rng);  // ior
    if (i % 4 == 0) c[11] = 0.0f;  // no coat
    if (i % 7 == 0) c[12] = 1.0f;
    c[13] = float(i % 2 ? i * 1000 : i);  // material indices, up to 255000
    c[14] = float(i % 3 == 0);
    c[16] = i % 5 == 0 ? 0.0f : U(rng);  // iridescence
    c[17] = 1.0f + U(rng);
    c[18] = 1000.0f * U(rng);              // nm
    c[19] = i % 3 == 1 ? 0.0f : U(rng);    // diffuse transmission and its colour
    for (int k = 20; k < 23; ++k) c[k] = U(rng);
    for (int k = 23; k < 27; ++k) c[k] = i % 4 == 2 ? 0.0f : U(rng);  // sheen colour, roughness
    for (int k = 27; k < 30; ++k) c[k] = 2.0f * U(rng) - 1.0f;           // anisotropy direction
    c[30] = i % 3 == 2 ? 0.0f : U(rng);                                  // and strength
    for (int k = 32; k < 35; ++k) c[k] = 2.0f * U(rng) - 1.0f;           // the coat's normal
  }
  cl::Context& ctx = test::device_context();
  cl::Buffer input = cl::Buffer::from_vector(ctx, in);
  cl::Buffer vertices(ctx, n * sizeof(dev::PathVertex), CL_MEM_READ_WRITE, nullptr, "vertices");
  cl::Buffer output(ctx, in.size() * sizeof(float), CL_MEM_WRITE_ONLY, nullptr, "output");
  cl::Kernel k(test::test_program("kernels/path_vertex_test.cl"), "path_vertex_round_trip");
  k.args(0, input, vertices, output, n);
  k.launch(ctx, n);
  const std::vector<float> out = output.read_vector<float>(in.size());
  for (uint32_t i = 0; i < n; ++i) {
    const float* c = &in[36 * i];
    const float* o = &out[36 * i];
    for (int f = 0; f <= 10; ++f) EXPECT_EQ(o[f], c[f]) << "item " << i << " field " << f;
    EXPECT_EQ(o[11], 0.0f) << "item " << i << ": clearcoat " << c[11];
    EXPECT_EQ(o[12], 0.0f) << "item " << i << ": clearcoat roughness " << c[12];
    EXPECT_EQ(o[13], c[13]) << "item " << i << ": material";
    EXPECT_EQ(o[14], c[14]) << "item " << i << ": front";
    EXPECT_EQ(o[15], c[14] != 0.0f ? 0.0f : 1.0f) << "item " << i << ": flipped";
    for (int f = 16; f <= 22; ++f) EXPECT_EQ(o[f], c[f]) << "item " << i << " iridescence / transmission field " << f;
    for (int f = 23; f <= 26; ++f) EXPECT_EQ(o[f], 0.0f) << "item " << i << " sheen field " << f << ": " << c[f];
    for (int f = 27; f <= 30; ++f) EXPECT_EQ(o[f], c[f]) << "item " << i << " anisotropy field " << f;
    for (int f = 32; f <= 34; ++f) EXPECT_EQ(o[f], c[f]) << "item " << i << " clearcoat normal field " << f;
  }
}

}  // namespace
}  // namespace clpt::path_vertex_test
