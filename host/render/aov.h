// First-hit AOVs (--aov; issue 24): albedo, normal, depth, position and material index of each
// pixel's first samples, from kernels/integrators/aov.cl, beside any integrator. Each pass of
// the render hands its sample range to add(); the kernel takes the samples below
// AOV_MAX_SAMPLES and skips the rest, so the AOVs cost one camera ray per sample for their
// first 64 samples and nothing after.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "cl/buffer.h"
#include "cl/context.h"
#include "cl/program.h"
#include "io/image_io.h"
#include "render/scene_buffers.h"
#include "shared/aov_types.h"
#include "shared/render_types.h"

namespace clpt {

// The AOVs --aov names, as bits.
enum AovBits : uint32_t {
  AOV_ALBEDO = 1u << 0,
  AOV_NORMAL = 1u << 1,
  AOV_DEPTH = 1u << 2,
  AOV_POSITION = 1u << 3,
  AOV_MATERIAL_ID = 1u << 4,
};

// --aov's name of each AOV ("albedo", ..., "material-id") to its bit; 0 for any other name
// (variance is the film's, not an AovPass layer).
uint32_t aov_bit(const std::string& name);
// The EXR layer of one bit (layers() names them so): "Albedo", "Normal", "Depth", "Position",
// "IndexMA".
const char* aov_layer_name(uint32_t bit);

class AovPass {
 public:
  AovPass(const cl::Context& ctx, const SceneBuffers& scene, uint32_t width, uint32_t height);

  // The samples [p.sample_offset, p.sample_offset + p.samples_per_pass) of every pixel.
  void add(const dev::RenderParams& p);
  // A launch of no samples: drivers such as PoCL compile a kernel at its first launch, which
  // belongs to start-up, not to the first pass.
  void warm_up(const dev::RenderParams& p);

  // The AOVs in `bits`, as EXR layers named as Blender names its passes: "Albedo" (R, G, B),
  // "Normal" (X, Y, Z), "Depth" (Z), "Position" (X, Y, Z), "IndexMA" (X; -1 where the first
  // sample hit nothing). Depth and position average over the samples that hit (+inf and 0
  // where none did), albedo and normal over all.
  std::vector<NamedChannel> layers(uint32_t bits) const { return aov_layers(sums(), width_, height_, bits); }

  // The per-pixel sums read back, and another device's added to them; the material index stays
  // `to`'s: the sums of the device that took the render's sample 0 must come first.
  std::vector<dev::AovSums> sums() const;
  static void add(dev::AovSums* to, const dev::AovSums* other, size_t count);
  static std::vector<NamedChannel> aov_layers(const std::vector<dev::AovSums>& sums, uint32_t width,
                                              uint32_t height, uint32_t bits);

  size_t device_bytes() const { return sums_.size(); }

 private:
  const cl::Context& ctx_;
  uint32_t width_, height_;
  cl::Program program_;
  cl::Kernel kernel_;
  cl::Buffer params_, sums_;
  cl_uint sums_arg_;
};

}  // namespace clpt
