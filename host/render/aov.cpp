#include "render/aov.h"

#include <cmath>
#include <limits>

#include "cl/programs.h"
#include "shared/aov_types.h"

namespace clpt {

static_assert(sizeof(dev::AovSums) == 64, "AovSums should stay 64 bytes");

namespace {

struct AovName {
  const char* option;  // as --aov names it
  uint32_t bit;
  const char* layer;   // as Blender names the pass
};
constexpr AovName kAovNames[] = {{"albedo", AOV_ALBEDO, "Albedo"},
                                 {"normal", AOV_NORMAL, "Normal"},
                                 {"depth", AOV_DEPTH, "Depth"},
                                 {"position", AOV_POSITION, "Position"},
                                 {"material-id", AOV_MATERIAL_ID, "IndexMA"}};

}  // namespace

uint32_t aov_bit(const std::string& name) {
  for (const AovName& a : kAovNames)
    if (name == a.option) return a.bit;
  return 0;
}

const char* aov_layer_name(uint32_t bit) {
  for (const AovName& a : kAovNames)
    if (bit == a.bit) return a.layer;
  return "";
}

AovPass::AovPass(const cl::Context& ctx, const SceneBuffers& scene, uint32_t width, uint32_t height)
    : ctx_(ctx),
      width_(width),
      height_(height),
      program_(ctx, programs::kAov),
      kernel_(program_, "aov_render"),
      params_(ctx, sizeof(dev::RenderParams), CL_MEM_READ_ONLY, nullptr, "render parameters"),
      sums_(ctx, size_t(width) * height * sizeof(dev::AovSums), CL_MEM_READ_WRITE, nullptr, "AOV sums") {
  sums_.fill_zero();
  sums_arg_ = scene.bind(kernel_, 0);
}

void AovPass::add(const dev::RenderParams& p) {
  if (p.sample_offset >= AOV_MAX_SAMPLES || p.samples_per_pass == 0) return;
  params_.write(&p, sizeof(p));
  kernel_.args(sums_arg_, params_, sums_);
  kernel_.launch(ctx_, size_t(width_) * height_);
}

void AovPass::warm_up(const dev::RenderParams& p) {
  dev::RenderParams none = p;
  none.sample_offset = 0;
  none.samples_per_pass = 0;
  params_.write(&none, sizeof(none));
  kernel_.args(sums_arg_, params_, sums_);
  kernel_.launch(ctx_, size_t(width_) * height_);
}

std::vector<dev::AovSums> AovPass::sums() const {
  return sums_.read_vector<dev::AovSums>(size_t(width_) * height_);
}

void AovPass::add(dev::AovSums* to, const dev::AovSums* other, size_t count) {
  for (size_t i = 0; i < count; ++i) {
    dev::AovSums& a = to[i];
    const dev::AovSums& b = other[i];
    for (int c = 0; c < 3; ++c) {
      a.albedo[c] += b.albedo[c];
      a.normal[c] += b.normal[c];
      a.position[c] += b.position[c];
    }
    a.depth += b.depth;
    a.samples += b.samples;
    a.hits += b.hits;
    // The material index is sample 0's, which only the device that took it wrote.
  }
}

std::vector<NamedChannel> AovPass::aov_layers(const std::vector<dev::AovSums>& sums, uint32_t width_,
                                              uint32_t height_, uint32_t bits) {
  const size_t n = size_t(width_) * height_;
  Image albedo(width_, height_), normal(width_, height_), depth(width_, height_), position(width_, height_),
      material(width_, height_);
  for (size_t i = 0; i < n; ++i) {
    const dev::AovSums& s = sums[i];
    const float all = s.samples ? 1.0f / float(s.samples) : 0.0f;
    const float hits = s.hits ? 1.0f / float(s.hits) : 0.0f;
    const float d = s.hits ? s.depth * hits : std::numeric_limits<float>::infinity();
    const float id = s.samples && s.material != AOV_NO_MATERIAL ? float(s.material) : -1.0f;
    for (int c = 0; c < 3; ++c) {
      albedo.rgb[i * 3 + c] = s.albedo[c] * all;
      normal.rgb[i * 3 + c] = s.normal[c] * all;
      position.rgb[i * 3 + c] = s.position[c] * hits;
      depth.rgb[i * 3 + c] = d;
      material.rgb[i * 3 + c] = id;
    }
  }
  std::vector<NamedChannel> out;
  if (bits & AOV_ALBEDO) out.push_back({aov_layer_name(AOV_ALBEDO), std::move(albedo)});
  if (bits & AOV_NORMAL) out.push_back({aov_layer_name(AOV_NORMAL), std::move(normal), {"X", "Y", "Z"}});
  if (bits & AOV_DEPTH) out.push_back({aov_layer_name(AOV_DEPTH), std::move(depth), {"Z"}});
  if (bits & AOV_POSITION) out.push_back({aov_layer_name(AOV_POSITION), std::move(position), {"X", "Y", "Z"}});
  if (bits & AOV_MATERIAL_ID) out.push_back({aov_layer_name(AOV_MATERIAL_ID), std::move(material), {"X"}});
  return out;
}

}  // namespace clpt
