// The host half of the lights: the luminous-power model that weights each light (emissive
// triangles, punctual lights, the environment), the alias table the kernels sample it with,
// and the environment map with its sampling distribution.
#include "render/light_table.h"

#include <algorithm>
#include <cmath>

#include "io/image_io.h"
#include "render/scene_buffers.h"
#include "shared/luminance.h"
#include "util/error.h"
#include "util/log.h"
#include "util/srgb.h"

namespace clpt {
namespace {

double luminance(const glm::dvec3& c) {
  return CLPT_LUMINANCE_R * c.x + CLPT_LUMINANCE_G * c.y + CLPT_LUMINANCE_B * c.z;
}

}  // namespace

void build_alias_table(const std::vector<double>& weight, std::vector<dev::Light>& lights) {
  const size_t n = lights.size();
  double total = 0.0;
  for (double w : weight) total += w;
  if (n == 0 || !(total > 0.0)) return;
  // Vose's alias method: slot i keeps itself with probability threshold[i], else its alias.
  std::vector<double> scaled(n);
  std::vector<size_t> small, large;
  for (size_t i = 0; i < n; ++i) {
    lights[i].pdf_select = static_cast<float>(weight[i] / total);
    scaled[i] = weight[i] / total * static_cast<double>(n);
    (scaled[i] < 1.0 ? small : large).push_back(i);
  }
  while (!small.empty() && !large.empty()) {
    const size_t s = small.back(), l = large.back();
    small.pop_back();
    lights[s].alias_threshold = static_cast<float>(scaled[s]);
    lights[s].alias = static_cast<dev::u32>(l);
    scaled[l] -= 1.0 - scaled[s];
    if (scaled[l] < 1.0) {
      large.pop_back();
      small.push_back(l);
    }
  }
  // Whatever is left has probability 1 up to rounding.
  for (size_t i : small) lights[i].alias_threshold = 1.0f, lights[i].alias = static_cast<dev::u32>(i);
  for (size_t i : large) lights[i].alias_threshold = 1.0f, lights[i].alias = static_cast<dev::u32>(i);
}

double spot_falloff_integral(double cos_outer, double cos_inner) {
  // falloff(c) = t^2, t = clamp((c - cos_outer) / ramp, 0, 1), ramp = max(0.001, inner - outer)
  // (the glTF formula in kernels/light/punctual.cl): a quadratic ramp from cos_outer up to
  // cos_outer + ramp, then 1 up to c = 1.
  const double ramp = std::max(0.001, cos_inner - cos_outer);
  const double top = std::min(1.0, cos_outer + ramp);  // where the ramp ends (or c = 1)
  const double x = (top - cos_outer) / ramp;           // t reached at `top`
  return ramp * x * x * x / 3.0 + std::max(0.0, 1.0 - (cos_outer + ramp));
}

Environment load_environment(const std::string& file, float scale, float rotation_degrees,
                             const ImageLimits& limits) {
  Environment env;
  env.scale = scale;
  env.rotation = rotation_degrees * float(M_PI / 180.0);
  Image img;
  try {
    img = read_image(file, limits);  // Error(BadInput) naming the file
  } catch (const Error& e) {
    throw Error(e.code(), "environment " + std::string(e.what()));
  }
  size_t bad = 0;
  for (float& v : img.rgb)
    if (!(v >= 0.0f) || !std::isfinite(v)) v = 0.0f, ++bad;
  if (bad)
    log::warn("environment " + file + ": " + std::to_string(bad) +
              " negative or non-finite texel values set to 0");
  env.map = std::move(img);
  return env;
}

void build_environment(const Environment& env, FlatScene& flat) {
  flat.info.env_rotation = env.rotation;
  flat.info.env_scale = env.scale;
  flat.env_texels.clear();
  flat.env_cdf.clear();
  flat.env_integral = 0.0;
  if (env.map.width == 0 || env.map.height == 0) {
    flat.info.env_width = flat.info.env_height = 0;
    for (int i = 0; i < 3; ++i) flat.info.background[i] = env.background[i];
    flat.env_integral = 4.0 * M_PI * luminance(glm::dvec3(env.background));
    return;
  }
  const uint32_t w = env.map.width, h = env.map.height;
  flat.info.env_width = w;
  flat.info.env_height = h;
  // f = luminance x sin(theta) at the row's centre: the density in (u, v) that makes the
  // solid-angle density proportional to luminance.
  std::vector<double> f(size_t(w) * h), row_sum(h, 0.0);
  double total = 0.0, integral = 0.0;
  for (uint32_t y = 0; y < h; ++y) {
    const double sin_theta = std::sin(M_PI * (y + 0.5) / h);
    // Exact solid angle of one texel of this row: (cos theta0 - cos theta1) x 2 pi / W.
    const double texel_sr =
        (std::cos(M_PI * y / h) - std::cos(M_PI * (y + 1.0) / h)) * 2.0 * M_PI / w;
    for (uint32_t x = 0; x < w; ++x) {
      const float* p = env.map.pixel(x, y);
      const double lum = luminance(glm::dvec3(p[0], p[1], p[2]));
      f[size_t(y) * w + x] = lum * sin_theta;
      row_sum[y] += lum * sin_theta;
      integral += lum * texel_sr;
    }
    total += row_sum[y];
  }
  flat.env_integral = integral * double(env.scale);
  flat.env_texels.resize(size_t(w) * h * 4);
  const double norm = total > 0.0 ? double(w) * h / total : 0.0;
  for (size_t i = 0; i < size_t(w) * h; ++i) {
    for (int c = 0; c < 3; ++c) flat.env_texels[i * 4 + c] = env.map.rgb[i * 3 + c];
    flat.env_texels[i * 4 + 3] = float(f[i] * norm);  // pdf_uv
  }
  // CDFs: marginal over rows, then one per row; each starts at 0 and ends at exactly 1. A row
  // of zero weight gets a uniform CDF; the marginal never picks it.
  flat.env_cdf.resize(size_t(h) + 1 + size_t(h) * (w + 1));
  float* marginal = flat.env_cdf.data();
  double acc = 0.0;
  marginal[0] = 0.0f;
  for (uint32_t y = 0; y < h; ++y) {
    acc += row_sum[y];
    marginal[y + 1] = total > 0.0 ? float(acc / total) : float(y + 1) / float(h);
  }
  marginal[h] = 1.0f;
  for (uint32_t y = 0; y < h; ++y) {
    float* row = flat.env_cdf.data() + (h + 1) + size_t(y) * (w + 1);
    double racc = 0.0;
    row[0] = 0.0f;
    for (uint32_t x = 0; x < w; ++x) {
      racc += f[size_t(y) * w + x];
      row[x + 1] = row_sum[y] > 0.0 ? float(racc / row_sum[y]) : float(x + 1) / float(w);
    }
    row[w] = 1.0f;
  }
}

namespace {

// Luminance of an emissive texture (sRGB) at uv, nearest texel with repeat wrapping: enough
// for a selection weight.
double texel_luminance(const Texture& tex, glm::vec2 uv) {
  if (tex.width == 0 || tex.height == 0 || tex.texels.empty()) return 0.0;
  auto wrap = [](float x, uint32_t n) {
    const float f = x - std::floor(x);
    return std::min<uint32_t>(uint32_t(f * float(n)), n - 1);
  };
  if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) return 0.0;
  const uint32_t t = tex.rgba8(size_t(wrap(uv.y, tex.height)) * tex.width + wrap(uv.x, tex.width));
  return luminance(glm::dvec3(srgb_to_linear((t & 0xffu) / 255.0),
                              srgb_to_linear(((t >> 8) & 0xffu) / 255.0),
                              srgb_to_linear(((t >> 16) & 0xffu) / 255.0)));
}

// How much of its emission factor an emissive-textured triangle emits, for its selection
// weight: the texture's luminance averaged over the three corners and the centroid, plus a
// small share of the whole texture's mean so that a triangle whose samples all fall on black
// texels but which emits elsewhere keeps some probability (any positive weight is unbiased).
// 1 without a texture; 0 when the whole texture is black (the triangle emits nothing).
double emissive_texture_scale(const Scene& scene, const Material& m, const dev::Triangle& t,
                              std::vector<double>& texture_mean) {
  const TextureRef& ref = m.emissive_texture;
  if (!ref.used() || size_t(ref.texture) >= scene.textures.size()) return 1.0;
  const Texture& tex = scene.textures[size_t(ref.texture)];
  double& mean = texture_mean[size_t(ref.texture)];
  if (mean < 0.0) {
    double sum = 0.0;
    for (uint32_t y = 0; y < tex.height; ++y)
      for (uint32_t x = 0; x < tex.width; ++x)
        sum += texel_luminance(tex, {(x + 0.5f) / float(tex.width), (y + 0.5f) / float(tex.height)});
    mean = tex.width && tex.height ? sum / (double(tex.width) * tex.height) : 0.0;
  }
  if (!(mean > 0.0)) return 0.0;
  const std::vector<glm::vec2>& uvs = ref.texcoord == 1 && !scene.uvs1.empty() ? scene.uvs1 : scene.uvs;
  auto uv_of = [&](uint32_t v) {
    const glm::vec2 uv = v < uvs.size() ? uvs[v] : glm::vec2(0.0f);
    return glm::vec2(ref.transform * glm::vec3(uv, 1.0f));
  };
  const glm::vec2 a = uv_of(t.v[0]), b = uv_of(t.v[1]), c = uv_of(t.v[2]);
  const double local = (texel_luminance(tex, a) + texel_luminance(tex, b) + texel_luminance(tex, c) +
                        texel_luminance(tex, (a + b + c) / 3.0f)) / 4.0;
  return local + 0.05 * mean;
}

}  // namespace

void build_lights(const Scene& scene, FlatScene& flat) {
  std::vector<double> texture_mean(scene.textures.size(), -1.0);
  std::vector<double> power;
  flat.lights.clear();
  flat.triangle_light.assign(flat.triangles.size(), -1);
  for (size_t i = 0; i < flat.triangles.size(); ++i) {
    const dev::Triangle& t = flat.triangles[i];
    const Material& m = scene.materials[t.material];
    const double lum =
        luminance(glm::dvec3(m.emission)) * emissive_texture_scale(scene, m, t, texture_mean);
    if (!(lum > 0.0)) continue;
    // In double: a float cross product overflows or underflows for extreme areas.
    const glm::dvec3 p0 = scene.positions[t.v[0]], p1 = scene.positions[t.v[1]],
                     p2 = scene.positions[t.v[2]];
    const double area = 0.5 * glm::length(glm::cross(p1 - p0, p2 - p0));
    if (!(area > 0.0) || !std::isfinite(area)) continue;
    const double p = lum * area * M_PI * (m.double_sided ? 2.0 : 1.0);
    if (!(p > 0.0) || !std::isfinite(p)) continue;
    flat.triangle_light[i] = static_cast<int32_t>(flat.lights.size());
    dev::Light light{};
    light.type = dev::LIGHT_TRIANGLE;
    light.triangle = static_cast<dev::u32>(i);
    light.alias_threshold = 1.0f;
    flat.lights.push_back(light);
    power.push_back(p);
  }
  flat.emissive_triangles = static_cast<uint32_t>(flat.lights.size());

  // Lights outside the geometry are weighted by the power that crosses the disk of the
  // scene's bounding radius (any positive weights are unbiased; this keeps them comparable).
  const double r = flat.info.bounds_radius > 0.0f ? double(flat.info.bounds_radius) : 1.0;
  const double disk = M_PI * r * r;
  flat.punctual_lights = 0;
  flat.info.flags &= ~dev::SCENE_DELTA_LIGHTS;
  for (const PunctualLight& pl : scene.lights) {
    const glm::dvec3 I = glm::dvec3(pl.color) * double(pl.intensity);
    dev::Light light{};
    light.alias_threshold = 1.0f;
    for (int k = 0; k < 3; ++k) {
      light.position[k] = pl.position[k];
      light.direction[k] = pl.direction[k];
      light.intensity[k] = float(I[k]);
    }
    double p = 0.0;
    switch (pl.type) {
      case PunctualLight::Type::Point:
        light.type = dev::LIGHT_POINT;
        p = 4.0 * M_PI * luminance(I);
        break;
      case PunctualLight::Type::Spot:
        light.type = dev::LIGHT_SPOT;
        light.cos_outer = std::cos(pl.outer_cone);
        light.cos_inner = std::cos(pl.inner_cone);
        p = 2.0 * M_PI * luminance(I) * spot_falloff_integral(light.cos_outer, light.cos_inner);
        break;
      case PunctualLight::Type::Directional:
        light.type = dev::LIGHT_DIRECTIONAL;
        p = disk * luminance(I);
        break;
    }
    if (!(p > 0.0) || !std::isfinite(p)) continue;
    flat.lights.push_back(light);
    power.push_back(p);
    ++flat.punctual_lights;
    flat.info.flags |= dev::SCENE_DELTA_LIGHTS;
  }

  flat.info.env_light = ~0u;
  const double env_power = disk * flat.env_integral;
  if (env_power > 0.0 && std::isfinite(env_power)) {
    dev::Light light{};
    light.type = dev::LIGHT_ENVIRONMENT;
    light.alias_threshold = 1.0f;
    flat.info.env_light = static_cast<dev::u32>(flat.lights.size());
    flat.lights.push_back(light);
    power.push_back(env_power);
  }

  double total = 0.0;
  for (double p : power) total += p;
  flat.total_emitted_power = total;
  build_alias_table(power, flat.lights);
  flat.info.num_lights = static_cast<dev::u32>(flat.lights.size());
}

}  // namespace clpt
