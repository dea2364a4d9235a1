#include "support/reference_render.h"

#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "util/hash.h"
#include "cl/program.h"
#include "render/renderer.h"
#include "support/device.h"
#include "support/render.h"
#include "support/scenes.h"

namespace clpt::test {
namespace fs = std::filesystem;

namespace {

constexpr char kMagic[8] = {'C', 'L', 'P', 'T', 'R', 'E', 'F', '1'};

// A digest of this executable's bytes: it changes with any change to the host code, the
// test scenes or the embedded kernels.
const std::string& executable_digest() {
  static const std::string digest = [] {
    std::ifstream f("/proc/self/exe", std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    if (bytes.empty()) return std::string();
    std::ostringstream s;
    s << std::hex << hash64(bytes.data(), bytes.size(), 0);
    return s.str();
  }();
  return digest;
}

const char* scene_name(ReferenceScene scene) {
  return scene == ReferenceScene::CornellBox ? "cornell_box" : "cornell_box_glossy_glass";
}

struct Key {
  std::string text;
  fs::path file;  // empty: no cache
  uint64_t check = 0;
};

// The settings a pt render's image depends on, as text (floats in hex, so exact).
std::string settings_text(const RenderSettings& r) {
  std::ostringstream s;
  s << std::hexfloat << r.integrator << ' ' << r.width << 'x' << r.height << ' ' << r.spp
    << " depth " << r.max_depth << ' ' << r.rr_depth << " sampler " << r.sampler << " direct "
    << r.direct << " mis " << r.mis << ' ' << r.light_samples << " hemisphere " << r.hemisphere
    << " rr " << r.rr << ' ' << r.rr_absorb << " branching " << r.branching << " camera '"
    << r.camera << "' env '" << r.env_file << "' " << r.env_scale << ' ' << r.env_rotation
    << " background " << r.background.x << ' ' << r.background.y << ' ' << r.background.z
    << " lens " << r.aperture << ' ' << r.focus_distance;
  return s.str();
}

// label names the scene; the render's settings enter the key themselves.
Key make_key(const std::string& label, const RenderSettings& settings, uint32_t seed) {
  Key k;
  const std::string exe = executable_digest();
  const fs::path dir = cl::kernel_cache_dir();
  if (exe.empty() || dir.empty()) return k;
  const cl::DeviceInfo& dev = device_context().device();
  std::ostringstream s;
  s << "clpt-test-reference-v1\n"
    << exe << '\n'
    << dev.platform_name << '\n'
    << dev.name << '\n'
    << dev.driver_version << '\n'
    << label << '\n'
    << settings_text(settings) << " seed " << seed << '\n'
    << cl::resolve_kernel_source("integrators/pt.cl", cl::KernelSources::core());
  k.text = s.str();
  const Hash128 h = hash128(k.text.data(), k.text.size());
  std::ostringstream name;
  name << label.substr(0, label.find(' ')) << '-' << std::hex << std::setfill('0') << std::setw(16)
       << h.high << std::setw(16) << h.low
       << ".ref";
  k.file = dir / "test-references" / name.str();
  k.check = hash64(k.text.data(), k.text.size(), 0);
  return k;
}

// The entry's layout: magic, key check, then the header fields and the two images, then an
// XXH64 of everything after the magic.
struct Header {
  uint64_t check, spp, dropped, rays;
  uint32_t width, height, variance_available, pad;
};

bool read_entry(const Key& key, FilmResult* out) {
  std::ifstream f(key.file, std::ios::binary);
  if (!f) return false;
  const std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  Header h;
  if (bytes.size() < 8 + sizeof(Header) + 8 || std::memcmp(bytes.data(), kMagic, 8) != 0) return false;
  std::memcpy(&h, bytes.data() + 8, sizeof(h));
  if (h.check != key.check) return false;
  const size_t floats = size_t(h.width) * h.height * 3;
  if (bytes.size() != 8 + sizeof(Header) + 2 * floats * sizeof(float) + 8) return false;
  uint64_t stored = 0;
  std::memcpy(&stored, bytes.data() + bytes.size() - 8, 8);
  if (hash64(bytes.data() + 8, bytes.size() - 16, 0) != stored) return false;
  FilmResult r;
  r.mean = Image(h.width, h.height);
  r.variance = Image(h.width, h.height);
  const char* p = bytes.data() + 8 + sizeof(Header);
  std::memcpy(r.mean.rgb.data(), p, floats * sizeof(float));
  std::memcpy(r.variance.rgb.data(), p + floats * sizeof(float), floats * sizeof(float));
  r.variance_available = h.variance_available != 0;
  r.samples_per_pixel = h.spp;
  r.dropped_samples = h.dropped;
  r.rays = h.rays;
  *out = std::move(r);
  return true;
}

void write_entry(const Key& key, const FilmResult& r) {
  std::error_code ec;
  fs::create_directories(key.file.parent_path(), ec);
  Header h{key.check, r.samples_per_pixel, r.dropped_samples, r.rays,
           r.mean.width, r.mean.height, r.variance_available ? 1u : 0u, 0u};
  std::string bytes(kMagic, 8);
  bytes.append(reinterpret_cast<const char*>(&h), sizeof(h));
  bytes.append(reinterpret_cast<const char*>(r.mean.rgb.data()), r.mean.rgb.size() * sizeof(float));
  bytes.append(reinterpret_cast<const char*>(r.variance.rgb.data()),
               r.variance.rgb.size() * sizeof(float));
  const uint64_t digest = hash64(bytes.data() + 8, bytes.size() - 8, 0);
  bytes.append(reinterpret_cast<const char*>(&digest), 8);
  const fs::path tmp = key.file.string() + ".tmp" + std::to_string(::getpid());
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    if (!f || !f.write(bytes.data(), std::streamsize(bytes.size())) || !f.flush()) {
      fs::remove(tmp, ec);
      return;  // an unwritable cache only costs the next process a render
    }
  }
  fs::rename(tmp, key.file, ec);
  if (ec) fs::remove(tmp, ec);
}

}  // namespace

fs::path pt_reference_file(ReferenceScene scene, uint32_t size, uint64_t spp, uint32_t seed) {
  return make_key(scene_name(scene), render_settings("pt", spp, size), seed).file;
}

FilmResult pt_reference(ReferenceScene scene, uint32_t size, uint64_t spp, uint32_t seed) {
  return pt_reference(
      scene_name(scene),
      [scene] { return scene == ReferenceScene::CornellBox ? cornell_box() : cornell_box_glossy_glass(); },
      render_settings("pt", spp, size), seed);
}

FilmResult pt_reference(const std::string& label, const std::function<Scene()>& build,
                        const RenderSettings& settings, uint32_t seed) {
  if (settings.integrator != "pt" || settings.width != settings.height)
    throw std::logic_error("pt_reference: square pt renders only");
  const Key key = make_key(label, settings, seed);
  FilmResult result;
  if (!key.file.empty() && read_entry(key, &result)) return result;
  result = render(build(), settings, seed);
  if (!key.file.empty()) write_entry(key, result);
  return result;
}

}  // namespace clpt::test
