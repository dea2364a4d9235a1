// glTF 2.0 loader: .gltf / .glb -> clpt::Scene (world-space triangles, materials, cameras).
//
// Parsing is done by tinygltf (Debian's shared build, 2.7, stb_image compiled in through
// libstb). No TINYGLTF_* macro is defined here: the class layout in tiny_gltf.h does not
// depend on them, and the implementation lives in the shared library.
//
// Everything tinygltf hands back is treated as untrusted: every index, count, offset and
// length is checked here before it is used, in 64/128-bit arithmetic, so a hostile file gives
// a clpt::Error(BadInput) that names the file and the problem, never a crash, a hang or an
// out-of-bounds read.
//
// Before tinygltf sees the file, this loader
//   * reads it itself (size-capped), picks GLB or JSON by the first 4 bytes (not the
//     extension), and checks the GLB header and chunk table;
//   * scans the JSON text for its nesting depth (tinygltf and nlohmann recurse on nesting);
//   * parses the JSON with nlohmann to give a clear message for invalid JSON, to refuse
//     required extensions clpt does not support (before tinygltf trips over, e.g., Draco
//     accessors that have no bufferView) and to check every buffer/image URI.
// tinygltf then parses the same bytes (LoadBinaryFromMemory / LoadASCIIFromString, so that the
// file is read once, size-capped, and the base folder is ours rather than tinygltf's guess) with
// file-system callbacks that only open files inside the scene's folder (defence in depth: its
// own fallback of looking in the current directory is refused too) and an image loader that
// decodes nothing: it only keeps a copy of the encoded bytes of external and data: URI images.
// Images are decoded by scene/image_decode (OpenImageIO), from those bytes or from a
// range-checked GLB bufferView, never by tinygltf's stb_image. A missing or undecodable image
// is an error, or with --lenient a warning and a magenta texture.
//
// URI policy: `data:` URIs (base64, the media types tinygltf knows) and relative paths that
// stay inside the folder of the scene file (percent-encoding decoded, `..` allowed only while
// it stays inside). Absolute paths, `..` escaping the folder and any other scheme (http:,
// file:, C:, ...) are refused. The check is on the URI text: a symlink inside the folder that
// points elsewhere is followed.
//
// Limits against hostile files (each one gives a BadInput error, not an attempt) are in
// scene/load_limits.h, with their defaults; --limit NAME=VALUE changes one. They cap single
// and total file sizes, JSON nesting, accessor element counts (with a much lower cap for
// accessors without a bufferView: zeros cost memory without costing file size), vertices and
// triangles after instancing, node hierarchy depth and node visits (a graph that reuses
// children could otherwise explode), image width/height and pixels (checked from the header
// before decoding), all textures' texels, and the host memory the geometry will need
// (estimated per vertex and triangle, against 80 % of physical memory by default).
// Cycles in the node graph are errors.
#include "scene/gltf_loader.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <glm/gtc/matrix_inverse.hpp>
#include <nlohmann/json.hpp>

#include "scene/gltf_lights.h"
#include "scene/image_decode.h"
#include "scene/tangents.h"
#include "util/error.h"
#include "util/log.h"

namespace clpt {
namespace {

namespace fs = std::filesystem;

constexpr double kPi = 3.14159265358979323846;

// Extensions clpt implements. Anything else in extensionsRequired is refused; anything else in
// extensionsUsed is ignored with one warning.
const char* const kSupportedExtensions[] = {
    "KHR_materials_emissive_strength",
    "KHR_materials_transmission",
    "KHR_materials_ior",
    "KHR_materials_specular",
    "KHR_materials_volume",
    "KHR_texture_transform",
    "EXT_mesh_gpu_instancing",
    "KHR_lights_punctual",
};

bool is_supported_extension(const std::string& name) {
  for (const char* s : kSupportedExtensions)
    if (name == s) return true;
  return false;
}

using u128 = unsigned __int128;

std::string to_string_u128(u128 v) {
  if (v == 0) return "0";
  std::string s;
  while (v != 0) {
    s.push_back(char('0' + int(v % 10)));
    v /= 10;
  }
  std::reverse(s.begin(), s.end());
  return s;
}

std::string number(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

// 1536 -> "1.5 KiB": sizes in messages.
std::string bytes_text(uint64_t b) {
  const char* units[] = {"bytes", "KiB", "MiB", "GiB", "TiB"};
  double v = double(b);
  int u = 0;
  while (v >= 1024.0 && u < 4) v /= 1024.0, ++u;
  char buf[48];
  std::snprintf(buf, sizeof buf, u == 0 ? "%.0f %s" : "%.1f %s", v, units[u]);
  return buf;
}

std::string join(const std::vector<std::string>& items, const char* sep) {
  std::string out;
  for (size_t i = 0; i < items.size(); ++i) {
    if (i) out += sep;
    out += items[i];
  }
  return out;
}

// tinygltf's messages are several "\n"-terminated lines; clpt's errors are one line.
std::string one_line(const std::string& text) {
  std::vector<std::string> lines;
  std::string line;
  std::istringstream in(text);
  while (std::getline(in, line)) {
    while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) line.pop_back();
    size_t start = 0;
    while (start < line.size() && std::isspace(static_cast<unsigned char>(line[start]))) ++start;
    if (start >= line.size()) continue;
    line = line.substr(start);
    if (line.size() > 300) line = line.substr(0, 300) + "...";  // e.g. a whole data: URI
    lines.push_back(line);
  }
  return join(lines, "; ");
}

std::string printable(const std::string& s) {
  // Keep messages on one line and printable whatever the file contains.
  std::string out = "'";
  for (unsigned char c : s.substr(0, 200)) {
    if (c < 0x20 || c == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", c);
      out += buf;
    } else {
      out += char(c);
    }
  }
  if (s.size() > 200) out += "...";
  return out + "'";
}

// ------------------------------------------------------------------------------------------
// Files and URIs

// Reads a whole regular file of at most `cap` bytes. On failure returns false and a reason.
bool read_whole_file(const fs::path& path, uint64_t cap, std::vector<unsigned char>* out,
                     std::string* why) {
  std::error_code ec;
  fs::file_status st = fs::status(path, ec);
  if (ec || !fs::exists(st)) {
    *why = ec && ec != std::errc::no_such_file_or_directory ? ec.message()
                                                            : "file not found";
    return false;
  }
  if (fs::is_directory(st)) {
    *why = "is a directory, not a file";
    return false;
  }
  if (!fs::is_regular_file(st)) {
    *why = "is not a regular file";
    return false;
  }
  uint64_t size = fs::file_size(path, ec);
  if (ec) {
    *why = "cannot get its size: " + ec.message();
    return false;
  }
  if (size > cap) {
    *why = "is " + std::to_string(size) + " bytes, more than the limit of " +
           std::to_string(cap) + " bytes";
    return false;
  }
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) {
    *why = std::string("cannot open: ") + std::strerror(errno);
    return false;
  }
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> guard(f, &std::fclose);
  out->assign(size_t(size), 0);
  size_t got = size ? std::fread(out->data(), 1, size_t(size), f) : 0;
  if (got != size || std::ferror(f)) {
    *why = std::string("cannot read: ") + (std::ferror(f) ? std::strerror(errno) : "file shrank");
    return false;
  }
  return true;
}

int hex_value(unsigned char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

// RFC 3986 percent-decoding ('+' is a plus sign in a path).
std::string percent_decode(const std::string& s) {
  std::string out;
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '%' && i + 2 < s.size()) {
      int hi = hex_value(static_cast<unsigned char>(s[i + 1]));
      int lo = hex_value(static_cast<unsigned char>(s[i + 2]));
      if (hi >= 0 && lo >= 0) {
        out += char(hi * 16 + lo);
        i += 2;
        continue;
      }
    }
    out += s[i];
  }
  return out;
}

// What tinygltf 2.7 (dlib::urldecode) makes of a URI before it asks the file-system callbacks:
// '+' becomes a space and bad hex digits become 0. The callbacks map this back to the
// RFC 3986 decoding above, so "a+b.bin" still opens a+b.bin.
std::string tinygltf_urldecode(const std::string& s) {
  auto from_hex = [](unsigned char c) -> unsigned char {
    int v = hex_value(c);
    return v < 0 ? 0 : static_cast<unsigned char>(v);
  };
  std::string out;
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '+') {
      out += ' ';
    } else if (s[i] == '%' && s.size() > i + 2) {
      out += char((from_hex(static_cast<unsigned char>(s[i + 1])) << 4) |
                  from_hex(static_cast<unsigned char>(s[i + 2])));
      i += 2;
    } else {
      out += s[i];
    }
  }
  return out;
}

// Returns why a (decoded) external URI may not be opened, or "" when it is a relative path
// that stays inside the scene's folder.
std::string uri_problem(const std::string& uri) {
  const char* allowed = "; only relative paths inside the scene's folder and data: URIs are allowed";
  if (uri.empty()) return "is empty";
  if (uri.find('\0') != std::string::npos) return "contains a NUL character";
  size_t colon = uri.find(':');
  size_t sep = uri.find_first_of("/\\?#");
  if (colon != std::string::npos && (sep == std::string::npos || colon < sep)) {
    std::string scheme = uri.substr(0, colon);
    if (scheme == "data")
      return "is a data: URI tinygltf cannot decode (it must be base64 with a media type such "
             "as application/octet-stream, image/png or image/jpeg)";
    if (scheme.size() == 1) return "is an absolute path" + std::string(allowed);
    return "uses the URI scheme '" + scheme + ":'" + allowed;
  }
  if (uri[0] == '/' || uri[0] == '\\') return "is an absolute path" + std::string(allowed);
  long depth = 0;
  size_t start = 0;
  while (start <= uri.size()) {
    size_t end = uri.find_first_of("/\\", start);
    if (end == std::string::npos) end = uri.size();
    std::string seg = uri.substr(start, end - start);
    if (seg == "..") {
      if (--depth < 0) return "has '..' components that leave the scene's folder" + std::string(allowed);
    } else if (!seg.empty() && seg != ".") {
      ++depth;
    }
    start = end + 1;
  }
  return "";
}

// State shared with tinygltf's file-system callbacks.
struct FsContext {
  const LoadLimits* limits = nullptr;
  std::string prefix;  // scene folder + '/', as tinygltf joins it with a URI
  fs::path base;
  std::map<std::string, std::string> rewrite;  // tinygltf's URI decoding -> RFC 3986 decoding
  std::set<std::string> skip;                   // image data: URIs tinygltf cannot decode (ignored)
  std::string refusal;                         // first refused URI and why
  uint64_t bytes_read = 0;                     // the scene file included
};

// Turns the path tinygltf built (folder + "/" + decoded URI) back into a checked path inside
// the folder. Its second guess ("./" + URI, the current directory) is never allowed.
bool resolve_in_folder(FsContext& ctx, const std::string& joined, fs::path* out) {
  if (joined.size() < ctx.prefix.size() || joined.compare(0, ctx.prefix.size(), ctx.prefix) != 0)
    return false;
  std::string uri = joined.substr(ctx.prefix.size());
  if (ctx.skip.count(uri)) return false;  // tinygltf then warns and keeps the image undecoded
  auto it = ctx.rewrite.find(uri);
  if (it != ctx.rewrite.end()) uri = it->second;
  std::string why = uri_problem(uri);
  if (!why.empty()) {
    if (ctx.refusal.empty()) ctx.refusal = "external file " + printable(uri) + " " + why;
    return false;
  }
  *out = ctx.base / uri;
  return true;
}

bool fs_file_exists(const std::string& abs_filename, void* user) {
  try {
    auto& ctx = *static_cast<FsContext*>(user);
    fs::path path;
    if (!resolve_in_folder(ctx, abs_filename, &path)) return false;
    std::error_code ec;
    return fs::is_regular_file(path, ec);
  } catch (...) {
    return false;
  }
}

std::string fs_expand_file_path(const std::string& path, void*) { return path; }

bool fs_read_whole_file(std::vector<unsigned char>* out, std::string* err,
                        const std::string& filepath, void* user) {
  try {
    auto& ctx = *static_cast<FsContext*>(user);
    fs::path path;
    if (!resolve_in_folder(ctx, filepath, &path)) {
      if (err) *err += "refused to open " + filepath + "\n";
      return false;
    }
    std::string why;
    const LoadLimits& lim = *ctx.limits;
    uint64_t cap = std::min(lim.file_bytes, lim.total_bytes - std::min(lim.total_bytes, ctx.bytes_read));
    if (!read_whole_file(path, cap, out, &why)) {
      if (err) *err += why + "\n";
      return false;
    }
    ctx.bytes_read += out->size();
    return true;
  } catch (const std::exception& e) {
    if (err) *err += std::string(e.what()) + "\n";
    return false;
  }
}

bool fs_write_whole_file(std::string* err, const std::string&, const std::vector<unsigned char>&,
                         void*) {
  if (err) *err += "clpt never writes files while loading a scene\n";
  return false;
}

// What the loader knows about each glTF image before conversion: the encoded bytes of external
// files and data: URIs (copied by keep_image_undecoded), and why an image has none.
struct ImageSources {
  std::map<int, std::vector<unsigned char>> bytes;
  std::map<int, std::string> problem;
  bool lenient = false;
};

// tinygltf's image callback: decode nothing, keep a copy of the bytes of external and data:
// URI images. Images in a bufferView are skipped here (tinygltf does not range-check the
// pointer it passes for them); the converter reads them through its checked buffer_view().
bool keep_image_undecoded(tinygltf::Image* image, const int image_idx, std::string*, std::string*, int, int,
                          const unsigned char* bytes, int size, void* user) {
  if (!image || !user || image->bufferView >= 0 || !bytes || size <= 0) return true;
  static_cast<ImageSources*>(user)->bytes[image_idx].assign(bytes, bytes + size);
  return true;
}

// ------------------------------------------------------------------------------------------
// GLB container and JSON pre-scan

constexpr uint32_t kGlbMagic = 0x46546C67;  // "glTF"
constexpr uint32_t kChunkJson = 0x4E4F534A;
constexpr uint32_t kChunkBin = 0x004E4942;

uint32_t read_u32le(const unsigned char* p) {
  return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

std::string hex32(uint32_t v) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "0x%08X", v);
  return buf;
}

// Checks the GLB header and chunk table (tinygltf checks less, and says only "Invalid glTF
// binary."). Returns the JSON chunk. `fail` throws.
template <class Fail>
std::pair<const char*, size_t> check_glb(const std::vector<unsigned char>& d, Fail&& fail) {
  const uint64_t size = d.size();
  if (size < 12) fail("truncated GLB: the file is " + std::to_string(size) + " bytes, shorter than the 12-byte header");
  uint32_t version = read_u32le(&d[4]);
  uint32_t length = read_u32le(&d[8]);
  if (version != 2) fail("GLB version " + std::to_string(version) + " is not supported (only 2)");
  if (length != size)
    fail("GLB header says the file is " + std::to_string(length) + " bytes, but it is " +
         std::to_string(size) + " bytes");
  if (size < 20) fail("truncated GLB: no room for the JSON chunk header");
  uint64_t json_len = read_u32le(&d[12]);
  uint32_t json_type = read_u32le(&d[16]);
  if (json_type != kChunkJson)
    fail("GLB chunk 0 has type " + hex32(json_type) + ", expected JSON (" + hex32(kChunkJson) + ")");
  if (json_len == 0) fail("GLB JSON chunk is empty");
  if (20 + json_len > size)
    fail("GLB JSON chunk (" + std::to_string(json_len) + " bytes at offset 20) runs past the end of the file (" +
         std::to_string(size) + " bytes)");
  uint64_t pos = 20 + json_len;
  if (pos % 4 != 0) log::verbose("GLB JSON chunk is not padded to 4 bytes");
  if (pos < size) {
    if (size - pos < 8)
      fail("GLB chunk 1 header is truncated (" + std::to_string(size - pos) + " bytes left at offset " +
           std::to_string(pos) + ")");
    uint64_t bin_len = read_u32le(&d[pos]);
    uint32_t bin_type = read_u32le(&d[pos + 4]);
    if (bin_type != kChunkBin)
      fail("GLB chunk 1 has type " + hex32(bin_type) + ", expected BIN (" + hex32(kChunkBin) + ")");
    if (pos + 8 + bin_len > size)
      fail("GLB BIN chunk (" + std::to_string(bin_len) + " bytes at offset " + std::to_string(pos + 8) +
           ") runs past the end of the file (" + std::to_string(size) + " bytes)");
    if (bin_len < 4 || bin_len % 4 != 0)
      fail("GLB BIN chunk length " + std::to_string(bin_len) + " is not a positive multiple of 4");
    // Chunks after BIN are allowed and ignored.
  }
  return {reinterpret_cast<const char*>(d.data() + 20), size_t(json_len)};
}

// Nesting depth of JSON arrays/objects, stopping early past `limit`.
size_t json_depth(const char* p, size_t n, size_t limit) {
  size_t depth = 0, max_depth = 0;
  bool in_string = false, escaped = false;
  for (size_t i = 0; i < n; ++i) {
    char c = p[i];
    if (in_string) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      max_depth = std::max(max_depth, ++depth);
      if (max_depth > limit) return max_depth;
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return max_depth;
}

// ------------------------------------------------------------------------------------------
// Conversion of the tinygltf model

struct LocalPrimitive {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;  // empty when the primitive has none
  std::vector<glm::vec2> uvs;      // empty when the primitive has none
  std::vector<glm::vec2> uvs1;     // TEXCOORD_1, empty when the primitive has none
  std::vector<glm::vec4> tangents; // TANGENT or generated, empty when none
  std::vector<glm::vec4> colors;   // COLOR_0 as linear RGBA, empty when none
  std::vector<glm::uvec3> triangles;
};

bool finite(const glm::dmat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) return false;
  return true;
}

bool finite(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

size_t component_size(int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;  // INT and DOUBLE are not glTF 2.0 accessor types
  }
}

const char* component_type_name(int ct) {
  switch (ct) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: return "BYTE";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return "UNSIGNED_BYTE";
    case TINYGLTF_COMPONENT_TYPE_SHORT: return "SHORT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return "UNSIGNED_SHORT";
    case TINYGLTF_COMPONENT_TYPE_INT: return "INT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return "UNSIGNED_INT";
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return "FLOAT";
    case TINYGLTF_COMPONENT_TYPE_DOUBLE: return "DOUBLE";
    default: return "unknown";
  }
}

int type_components(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4: return 4;
    case TINYGLTF_TYPE_MAT2: return 4;
    case TINYGLTF_TYPE_MAT3: return 9;
    case TINYGLTF_TYPE_MAT4: return 16;
    default: return 0;
  }
}

const char* type_name(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return "SCALAR";
    case TINYGLTF_TYPE_VEC2: return "VEC2";
    case TINYGLTF_TYPE_VEC3: return "VEC3";
    case TINYGLTF_TYPE_VEC4: return "VEC4";
    case TINYGLTF_TYPE_MAT2: return "MAT2";
    case TINYGLTF_TYPE_MAT3: return "MAT3";
    case TINYGLTF_TYPE_MAT4: return "MAT4";
    default: return "unknown";
  }
}

// One component at p (little-endian host; glTF data is little-endian).
double decode_component(const unsigned char* p, int ct, bool normalized) {
  switch (ct) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
      float f;
      std::memcpy(&f, p, 4);
      return f;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? p[0] / 255.0 : p[0];
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      int8_t v;
      std::memcpy(&v, p, 1);
      return normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? v / 65535.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    default: return 0.0;
  }
}

uint32_t decode_index(const unsigned char* p, int ct) {
  switch (ct) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return p[0];
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    default: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
  }
}

// What a component type may be for one use of an accessor.
enum class Components {
  Float,              // FLOAT only
  FloatOrUNorm,       // FLOAT, normalized UNSIGNED_BYTE / UNSIGNED_SHORT (TEXCOORD_n)
  FloatOrSNorm,       // FLOAT, normalized BYTE / SHORT (instance ROTATION)
  Index,              // UNSIGNED_BYTE / UNSIGNED_SHORT / UNSIGNED_INT
};

class Converter {
 public:
  Converter(const tinygltf::Model& model, std::string display, ImageSources& images,
            const LoadLimits& limits)
      : m_(model), display_(std::move(display)), images_(images), limits_(limits) {}

  Scene convert();

 private:
  [[noreturn]] void fail(const std::string& message) const {
    throw Error(ExitCode::BadInput, display_ + ": " + message);
  }

  std::string accessor_desc(int index, const std::string& what) const {
    return "accessor " + std::to_string(index) + " (" + what + ")";
  }

  // A checked byte range of a buffer view: data[0..length).
  struct ViewBytes {
    const unsigned char* data;
    uint64_t length;
    uint64_t stride;  // byteStride, 0 when not given
  };
  ViewBytes buffer_view(int index, const std::string& user) const;

  // Validated element layout of an accessor.
  struct Elements {
    const tinygltf::Accessor* acc;
    const unsigned char* data;  // nullptr: no bufferView, all zeros before sparse
    uint64_t stride;
    uint64_t count;
    int ncomp;
    size_t comp_size;
  };
  Elements accessor_elements(int index, const std::string& what, int type, Components allowed) const;

  template <class Sink>
  void for_each_component(const Elements& e, int index, const std::string& what, Sink&& sink) const;
  std::vector<float> read_values(int index, const std::string& what, int type, Components allowed) const;
  std::vector<uint32_t> read_indices(int index, const std::string& what) const;

  void convert_materials();
  TextureRef texture_ref(int index, int texcoord, const tinygltf::Value* transform, const std::string& where);
  TextureRef texture_info(const tinygltf::Value& info, const std::string& where);
  int scene_texture(int texture, const std::string& where);
  const DecodedImage& image(int index, const std::string& where);
  uint32_t material_for(int gltf_material, const std::string& where);
  const LocalPrimitive& local_primitive(int mesh, int prim);
  void add_instance(const LocalPrimitive& lp, const glm::dmat4& world, uint32_t material, int node,
                    int mesh, int prim);
  void add_mesh(int node, int mesh, const glm::dmat4& world);
  std::vector<glm::dmat4> instance_transforms(int node);
  void add_camera(int node, const glm::dmat4& world);
  glm::dmat4 local_transform(int node) const;
  void visit(int node, int parent, const glm::dmat4& parent_world, int depth);

  const tinygltf::Model& m_;
  std::string display_;
  ImageSources& images_;
  const LoadLimits& limits_;
  std::map<int, DecodedImage> decoded_;                  // by glTF image
  std::map<std::tuple<int, int, int, bool>, int> textures_;  // (image, wrapS, wrapT, nearest) -> scene texture
  std::map<int, int> texture_of_;                        // glTF texture -> scene texture (-1: none)
  uint64_t total_texels_ = 0;
  Scene scene_;
  int default_material_ = -1;
  std::map<std::pair<int, int>, LocalPrimitive> cache_;
  std::vector<char> on_path_;
  GltfLights lights_{m_, [this](const std::string& message) { fail(message); }};  // KHR_lights_punctual
  uint64_t visits_ = 0;
  uint64_t skipped_primitives_ = 0;  // points and lines
  std::set<int> skipped_modes_;
  uint64_t leftover_primitives_ = 0;  // index counts not a multiple of 3
};

Converter::ViewBytes Converter::buffer_view(int index, const std::string& user) const {
  if (index < 0 || size_t(index) >= m_.bufferViews.size())
    fail(user + " refers to bufferView " + std::to_string(index) + ", which does not exist (the file has " +
         std::to_string(m_.bufferViews.size()) + ")");
  const tinygltf::BufferView& bv = m_.bufferViews[size_t(index)];
  if (bv.buffer < 0 || size_t(bv.buffer) >= m_.buffers.size())
    fail("bufferView " + std::to_string(index) + " refers to buffer " + std::to_string(bv.buffer) +
         ", which does not exist (the file has " + std::to_string(m_.buffers.size()) + ")");
  const tinygltf::Buffer& buf = m_.buffers[size_t(bv.buffer)];
  const u128 end = u128(bv.byteOffset) + u128(bv.byteLength);
  if (end > u128(buf.data.size()))
    fail("bufferView " + std::to_string(index) + " reads bytes " + std::to_string(bv.byteOffset) + ".." +
         to_string_u128(end) + " past the end of buffer " + std::to_string(bv.buffer) + " (" +
         std::to_string(buf.data.size()) + " bytes)");
  return {buf.data.data() + bv.byteOffset, bv.byteLength, bv.byteStride};
}

Converter::Elements Converter::accessor_elements(int index, const std::string& what, int type,
                                                 Components allowed) const {
  if (index < 0 || size_t(index) >= m_.accessors.size())
    fail(what + " refers to accessor " + std::to_string(index) + ", which does not exist (the file has " +
         std::to_string(m_.accessors.size()) + ")");
  const tinygltf::Accessor& acc = m_.accessors[size_t(index)];
  const std::string desc = accessor_desc(index, what);

  if (acc.type != type)
    fail(desc + " has type " + type_name(acc.type) + ", expected " + type_name(type));
  const int ct = acc.componentType;
  bool ok = false;
  switch (allowed) {
    case Components::Float: ok = ct == TINYGLTF_COMPONENT_TYPE_FLOAT; break;
    case Components::FloatOrUNorm:
      ok = ct == TINYGLTF_COMPONENT_TYPE_FLOAT ||
           (acc.normalized && (ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                               ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT));
      break;
    case Components::FloatOrSNorm:
      ok = ct == TINYGLTF_COMPONENT_TYPE_FLOAT ||
           (acc.normalized && (ct == TINYGLTF_COMPONENT_TYPE_BYTE || ct == TINYGLTF_COMPONENT_TYPE_SHORT));
      break;
    case Components::Index:
      ok = ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE || ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
           ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
      break;
  }
  if (!ok)
    fail(desc + " has component type " + component_type_name(ct) + (acc.normalized ? " (normalized)" : "") +
         ", which is not allowed there");

  Elements e{&acc, nullptr, 0, acc.count, type_components(type), component_size(ct)};
  const uint64_t elem_size = uint64_t(e.ncomp) * e.comp_size;
  if (acc.count > limits_.accessor_count)
    fail(desc + " has count " + std::to_string(acc.count) + ", more than the limit of " +
         std::to_string(limits_.accessor_count) + " (--limit accessor-count=N)");

  if (acc.bufferView < 0) {
    if (acc.count > limits_.zero_accessor_count)
      fail(desc + " has no bufferView and count " + std::to_string(acc.count) + ", more than the limit of " +
           std::to_string(limits_.zero_accessor_count) + " for such accessors (--limit zero-accessor-count=N)");
    return e;  // zeros (then sparse values, if any)
  }
  ViewBytes view = buffer_view(acc.bufferView, desc);
  e.stride = view.stride ? view.stride : elem_size;
  if (e.stride < elem_size)
    fail(desc + " has elements of " + std::to_string(elem_size) + " bytes, but bufferView " +
         std::to_string(acc.bufferView) + " has byteStride " + std::to_string(view.stride));
  if (acc.count > 0) {
    const u128 end = u128(acc.byteOffset) + u128(e.stride) * u128(acc.count - 1) + u128(elem_size);
    if (end > u128(view.length))
      fail(desc + " reads bytes " + std::to_string(acc.byteOffset) + ".." + to_string_u128(end) +
           " past the end of bufferView " + std::to_string(acc.bufferView) + " (" +
           std::to_string(view.length) + " bytes)");
    e.data = view.data + acc.byteOffset;
  }
  return e;
}

// Calls sink(element, component, bytes) for every component of an accessor's data, then again
// for the components that its sparse substitution overrides. Elements of an accessor without a
// bufferView are left to the caller (zeros).
template <class Sink>
void Converter::for_each_component(const Elements& e, int index, const std::string& what, Sink&& sink) const {
  const tinygltf::Accessor& acc = *e.acc;
  const size_t ncomp = size_t(e.ncomp);
  if (e.data) {
    for (uint64_t i = 0; i < e.count; ++i) {
      const unsigned char* p = e.data + i * e.stride;
      for (size_t c = 0; c < ncomp; ++c) sink(size_t(i), c, p + c * e.comp_size);
    }
  }
  if (!acc.sparse.isSparse) return;
  const auto& sp = acc.sparse;
  const std::string desc = accessor_desc(index, what);
  if (sp.count < 1 || uint64_t(sp.count) > e.count)
    fail(desc + " has sparse count " + std::to_string(sp.count) + ", not in 1.." + std::to_string(e.count));
  const int ict = sp.indices.componentType;
  if (ict != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && ict != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
      ict != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
    fail(desc + " has sparse indices of component type " + component_type_name(ict) +
         ", expected UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT");
  if (sp.indices.byteOffset < 0 || sp.values.byteOffset < 0) fail(desc + " has a negative sparse byteOffset");
  const uint64_t n = uint64_t(sp.count);
  const size_t isize = component_size(ict);
  const uint64_t elem_size = uint64_t(ncomp) * e.comp_size;

  const ViewBytes iview = buffer_view(sp.indices.bufferView, desc + " sparse indices");
  const u128 iend = u128(uint64_t(sp.indices.byteOffset)) + u128(n) * isize;
  if (iend > u128(iview.length))
    fail(desc + " sparse indices read bytes " + std::to_string(sp.indices.byteOffset) + ".." +
         to_string_u128(iend) + " past the end of bufferView " + std::to_string(sp.indices.bufferView) + " (" +
         std::to_string(iview.length) + " bytes)");
  const ViewBytes vview = buffer_view(sp.values.bufferView, desc + " sparse values");
  const u128 vend = u128(uint64_t(sp.values.byteOffset)) + u128(n) * elem_size;
  if (vend > u128(vview.length))
    fail(desc + " sparse values read bytes " + std::to_string(sp.values.byteOffset) + ".." +
         to_string_u128(vend) + " past the end of bufferView " + std::to_string(sp.values.bufferView) + " (" +
         std::to_string(vview.length) + " bytes)");
  const unsigned char* ip = iview.data + sp.indices.byteOffset;
  const unsigned char* vp = vview.data + sp.values.byteOffset;
  for (uint64_t k = 0; k < n; ++k) {
    const uint32_t target = decode_index(ip + k * isize, ict);
    if (target >= e.count)
      fail(desc + " sparse index " + std::to_string(target) + " (entry " + std::to_string(k) +
           ") is not less than its count " + std::to_string(e.count));
    for (size_t c = 0; c < ncomp; ++c) sink(size_t(target), c, vp + k * elem_size + c * e.comp_size);
  }
}

std::vector<float> Converter::read_values(int index, const std::string& what, int type, Components allowed) const {
  const Elements e = accessor_elements(index, what, type, allowed);
  const size_t ncomp = size_t(e.ncomp);
  const int ct = e.acc->componentType;
  const bool normalized = e.acc->normalized;
  std::vector<float> out(size_t(e.count) * ncomp, 0.0f);
  for_each_component(e, index, what, [&](size_t i, size_t c, const unsigned char* p) {
    out[i * ncomp + c] = float(decode_component(p, ct, normalized));
  });
  return out;
}

std::vector<uint32_t> Converter::read_indices(int index, const std::string& what) const {
  const Elements e = accessor_elements(index, what, TINYGLTF_TYPE_SCALAR, Components::Index);
  const int ct = e.acc->componentType;
  std::vector<uint32_t> out(size_t(e.count), 0);
  for_each_component(e, index, what,
                     [&](size_t i, size_t, const unsigned char* p) { out[i] = decode_index(p, ct); });
  return out;
}

// ---- textures

const DecodedImage& Converter::image(int index, const std::string& where) {
  auto found = decoded_.find(index);
  if (found != decoded_.end()) return found->second;
  const tinygltf::Image& gi = m_.images[size_t(index)];
  std::string label = "image " + std::to_string(index);
  if (!gi.name.empty()) label += " " + printable(gi.name);
  else if (!gi.uri.empty() && gi.uri.rfind("data:", 0) != 0) label += " " + printable(gi.uri);
  DecodedImage img;
  std::string why;
  bool ok = false;
  if (gi.bufferView >= 0) {
    const ViewBytes v = buffer_view(gi.bufferView, label);
    ok = decode_image(v.data, size_t(v.length), &img, &why, limits_.image_dimension, limits_.image_pixels);
  } else {
    auto bytes = images_.bytes.find(index);
    if (bytes != images_.bytes.end()) {
      ok = decode_image(bytes->second.data(), bytes->second.size(), &img, &why, limits_.image_dimension,
                        limits_.image_pixels);
      images_.bytes.erase(bytes);  // decoded once; the encoded copy is no longer needed
    } else {
      auto p = images_.problem.find(index);
      why = p != images_.problem.end() ? p->second : "its data could not be read";
    }
  }
  if (ok && total_texels_ + uint64_t(img.width) * img.height > limits_.total_texels) {
    ok = false;
    why = "the scene's textures together exceed the limit of " + std::to_string(limits_.total_texels) + " texels";
  }
  if (!ok) {
    if (!images_.lenient)
      fail(label + " (used by " + where + "): " + why + " (--lenient: warn and use a magenta texture)");
    log::warn(display_ + ": " + label + " (used by " + where + "): " + why + "; using a magenta texture");
    img = placeholder_image();
  }
  return decoded_.emplace(index, std::move(img)).first->second;
}

// The scene texture for glTF texture `texture` (decoded image + its sampler), or -1 when the
// texture has no image clpt can use. Textures with the same image and sampler settings share.
int Converter::scene_texture(int texture, const std::string& where) {
  if (texture < 0 || size_t(texture) >= m_.textures.size())
    fail(where + " refers to texture " + std::to_string(texture) + ", which does not exist (the file has " +
         std::to_string(m_.textures.size()) + ")");
  auto known = texture_of_.find(texture);
  if (known != texture_of_.end()) return known->second;
  const tinygltf::Texture& gt = m_.textures[size_t(texture)];
  const std::string tdesc = "texture " + std::to_string(texture);
  if (gt.source < 0) {
    log::warn(display_ + ": " + tdesc + " has no PNG/JPEG source (e.g. only a KTX2 or WebP one); " + where +
              " is rendered without it");
    return texture_of_[texture] = -1;
  }
  if (size_t(gt.source) >= m_.images.size())
    fail(tdesc + " refers to image " + std::to_string(gt.source) + ", which does not exist (the file has " +
         std::to_string(m_.images.size()) + ")");
  Texture::Wrap ws = Texture::Wrap::Repeat, wt = Texture::Wrap::Repeat;
  bool nearest = false;
  if (gt.sampler >= 0) {
    if (size_t(gt.sampler) >= m_.samplers.size())
      fail(tdesc + " refers to sampler " + std::to_string(gt.sampler) + ", which does not exist (the file has " +
           std::to_string(m_.samplers.size()) + ")");
    const tinygltf::Sampler& sm = m_.samplers[size_t(gt.sampler)];
    auto wrap = [&](int mode, const char* name) {
      switch (mode) {
        case TINYGLTF_TEXTURE_WRAP_REPEAT: return Texture::Wrap::Repeat;
        case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return Texture::Wrap::Clamp;
        case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return Texture::Wrap::Mirror;
        default:
          log::warn(display_ + ": sampler " + std::to_string(gt.sampler) + " has " + name + " " +
                    std::to_string(mode) + ", not a glTF wrap mode; using REPEAT");
          return Texture::Wrap::Repeat;
      }
    };
    ws = wrap(sm.wrapS, "wrapS");
    wt = wrap(sm.wrapT, "wrapT");
    nearest = sm.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST;
  }
  const auto key = std::make_tuple(gt.source, int(ws), int(wt), nearest);
  auto shared = textures_.find(key);
  if (shared != textures_.end()) return texture_of_[texture] = shared->second;
  const DecodedImage& img = image(gt.source, where);
  total_texels_ += uint64_t(img.width) * img.height;
  Texture t;
  const tinygltf::Image& gi = m_.images[size_t(gt.source)];
  t.name = !gi.name.empty() ? gi.name : (!gi.uri.empty() && gi.uri.rfind("data:", 0) != 0 ? gi.uri
                                                                                          : "image " + std::to_string(gt.source));
  t.width = img.width;
  t.height = img.height;
  t.texels = img.texels;
  t.wrap_s = ws;
  t.wrap_t = wt;
  t.nearest = nearest;
  const int id = int(scene_.textures.size());
  scene_.textures.push_back(std::move(t));
  textures_.emplace(key, id);
  return texture_of_[texture] = id;
}

// A textureInfo: texture, UV set and KHR_texture_transform (offset, rotation, scale, texCoord
// override) folded into uv' = T * R * S * (u, v, 1), as the extension defines it.
TextureRef Converter::texture_ref(int index, int texcoord, const tinygltf::Value* transform,
                                  const std::string& where) {
  TextureRef ref;
  if (index < 0) return ref;
  double ox = 0, oy = 0, rot = 0, sx = 1, sy = 1;
  if (transform) {
    const std::string tw = where + " KHR_texture_transform";
    if (!transform->IsObject()) fail(tw + " is not an object");
    auto vec2 = [&](const char* key, double* x, double* y) {
      if (!transform->Has(key)) return;
      const tinygltf::Value& v = transform->Get(key);
      if (!v.IsArray() || v.ArrayLen() != 2 || !v.Get(0).IsNumber() || !v.Get(1).IsNumber())
        fail(tw + " " + key + " is not an array of 2 numbers");
      *x = v.Get(0).GetNumberAsDouble();
      *y = v.Get(1).GetNumberAsDouble();
      if (!std::isfinite(*x) || !std::isfinite(*y)) fail(tw + " " + key + " is not finite");
    };
    vec2("offset", &ox, &oy);
    vec2("scale", &sx, &sy);
    if (transform->Has("rotation")) {
      const tinygltf::Value& r = transform->Get("rotation");
      if (!r.IsNumber() || !std::isfinite(r.GetNumberAsDouble())) fail(tw + " rotation is not a finite number");
      rot = r.GetNumberAsDouble();
    }
    if (transform->Has("texCoord")) {
      const tinygltf::Value& t = transform->Get("texCoord");
      if (!t.IsInt()) fail(tw + " texCoord is not an integer");
      texcoord = t.GetNumberAsInt();
    }
  }
  if (texcoord != 0 && texcoord != 1) {
    const std::string msg = where + " uses texCoord " + std::to_string(texcoord) +
                            "; clpt reads TEXCOORD_0 and TEXCOORD_1 only";
    if (!images_.lenient) fail(msg + " (--lenient: use TEXCOORD_0)");
    log::warn(display_ + ": " + msg + "; using TEXCOORD_0");
    texcoord = 0;
  }
  ref.texture = scene_texture(index, where);
  if (ref.texture < 0) return TextureRef{};
  ref.texcoord = uint32_t(texcoord);
  const double c = std::cos(rot), s = std::sin(rot);
  // glm::mat3x2: column 0 multiplies u, column 1 v, column 2 is the offset.
  ref.transform = glm::mat3x2(glm::vec2(float(sx * c), float(-sx * s)), glm::vec2(float(sy * s), float(sy * c)),
                              glm::vec2(float(ox), float(oy)));
  return ref;
}

// A textureInfo inside an extension (a JSON value tinygltf does not interpret).
TextureRef Converter::texture_info(const tinygltf::Value& info, const std::string& where) {
  if (!info.IsObject()) fail(where + " is not an object");
  if (!info.Has("index") || !info.Get("index").IsInt()) fail(where + " has no integer index");
  const int index = info.Get("index").GetNumberAsInt();
  int texcoord = 0;
  if (info.Has("texCoord")) {
    if (!info.Get("texCoord").IsInt()) fail(where + " texCoord is not an integer");
    texcoord = info.Get("texCoord").GetNumberAsInt();
  }
  const tinygltf::Value* transform = nullptr;
  if (info.Has("extensions") && info.Get("extensions").IsObject() &&
      info.Get("extensions").Has("KHR_texture_transform"))
    transform = &info.Get("extensions").Get("KHR_texture_transform");
  if (index < 0)
    fail(where + " refers to texture " + std::to_string(index) + ", which does not exist (the file has " +
         std::to_string(m_.textures.size()) + ")");
  return texture_ref(index, texcoord, transform, where);
}

// ---- materials

namespace {
const tinygltf::Value* find_extension(const tinygltf::ExtensionMap& ext, const char* name) {
  auto it = ext.find(name);
  return it == ext.end() ? nullptr : &it->second;
}
}  // namespace

void Converter::convert_materials() {
  scene_.materials.reserve(m_.materials.size() + 1);
  size_t occlusion = 0;
  for (size_t i = 0; i < m_.materials.size(); ++i) {
    const tinygltf::Material& gm = m_.materials[i];
    const std::string where = "material " + std::to_string(i);
    Material mat;
    mat.name = gm.name;
    const auto& pbr = gm.pbrMetallicRoughness;
    auto check = [&](double v, const char* field) {
      if (!std::isfinite(v)) fail(where + " has a non-finite " + field);
      return v;
    };
    // A textureInfo of the core material.
    auto core_texture = [&](int index, int texcoord, const tinygltf::ExtensionMap& ext, const char* name) {
      return texture_ref(index, texcoord, find_extension(ext, "KHR_texture_transform"), where + " " + name);
    };
    // The members of an extension object.
    auto ext_number = [&](const tinygltf::Value& e, const char* ext_name, const char* key, double def) {
      if (!e.Has(key)) return def;
      const tinygltf::Value& v = e.Get(key);
      if (!v.IsNumber()) fail(where + " " + ext_name + " " + key + " is not a number");
      const double d = v.GetNumberAsDouble();
      if (!std::isfinite(d)) fail(where + " " + ext_name + " " + key + " is not finite");
      return d;
    };
    auto ext_color = [&](const tinygltf::Value& e, const char* ext_name, const char* key) {
      glm::vec3 c(1.0f);
      if (!e.Has(key)) return c;
      const tinygltf::Value& v = e.Get(key);
      if (!v.IsArray() || v.ArrayLen() != 3) fail(where + " " + ext_name + " " + key + " is not an array of 3 numbers");
      for (int k = 0; k < 3; ++k) {
        if (!v.Get(k).IsNumber() || !std::isfinite(v.Get(k).GetNumberAsDouble()))
          fail(where + " " + ext_name + " " + key + " is not an array of 3 finite numbers");
        c[k] = float(std::max(v.Get(k).GetNumberAsDouble(), 0.0));
      }
      return c;
    };
    auto ext_texture = [&](const tinygltf::Value& e, const char* ext_name, const char* key) {
      if (!e.Has(key)) return TextureRef{};
      return texture_info(e.Get(key), where + " " + ext_name + " " + key);
    };
    auto extension = [&](const char* name) -> const tinygltf::Value* {
      const tinygltf::Value* e = find_extension(gm.extensions, name);
      if (e && !e->IsObject()) fail(where + " " + name + " is not an object");
      return e;
    };

    if (pbr.baseColorFactor.size() == 4)
      for (int c = 0; c < 4; ++c)
        mat.base_color[c] = float(std::clamp(check(pbr.baseColorFactor[size_t(c)], "baseColorFactor"), 0.0, 1.0));
    mat.metallic = float(std::clamp(check(pbr.metallicFactor, "metallicFactor"), 0.0, 1.0));
    mat.roughness = float(std::clamp(check(pbr.roughnessFactor, "roughnessFactor"), 0.0, 1.0));
    mat.base_color_texture = core_texture(pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord,
                                          pbr.baseColorTexture.extensions, "baseColorTexture");
    mat.metallic_roughness_texture =
        core_texture(pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord,
                     pbr.metallicRoughnessTexture.extensions, "metallicRoughnessTexture");
    mat.normal_texture = core_texture(gm.normalTexture.index, gm.normalTexture.texCoord,
                                      gm.normalTexture.extensions, "normalTexture");
    if (mat.normal_texture.used()) mat.normal_scale = float(check(gm.normalTexture.scale, "normalTexture.scale"));
    mat.emissive_texture = core_texture(gm.emissiveTexture.index, gm.emissiveTexture.texCoord,
                                        gm.emissiveTexture.extensions, "emissiveTexture");
    if (gm.occlusionTexture.index >= 0) ++occlusion;

    double strength = 1.0;
    if (const tinygltf::Value* e = extension("KHR_materials_emissive_strength")) {
      strength = ext_number(*e, "KHR_materials_emissive_strength", "emissiveStrength", 1.0);
      if (strength < 0) fail(where + " has a negative emissiveStrength " + number(strength));
    }
    if (gm.emissiveFactor.size() == 3)
      for (int c = 0; c < 3; ++c) {
        double e = std::max(check(gm.emissiveFactor[size_t(c)], "emissiveFactor"), 0.0) * strength;
        if (!std::isfinite(float(e))) fail(where + " has an emission too large for a float");
        mat.emission[c] = float(e);
      }
    mat.double_sided = gm.doubleSided;

    if (gm.alphaMode == "MASK") {
      mat.alpha_mode = Material::AlphaMode::Mask;
    } else if (gm.alphaMode == "BLEND") {
      mat.alpha_mode = Material::AlphaMode::Blend;
    } else if (!gm.alphaMode.empty() && gm.alphaMode != "OPAQUE") {
      log::warn(display_ + ": " + where + " has alphaMode " + printable(gm.alphaMode) + "; treated as OPAQUE");
    }
    mat.alpha_cutoff = float(check(gm.alphaCutoff, "alphaCutoff"));

    if (const tinygltf::Value* e = extension("KHR_materials_transmission")) {
      const char* n = "KHR_materials_transmission";
      mat.transmission = float(std::clamp(ext_number(*e, n, "transmissionFactor", 0.0), 0.0, 1.0));
      mat.transmission_texture = ext_texture(*e, n, "transmissionTexture");
    }
    if (const tinygltf::Value* e = extension("KHR_materials_ior")) {
      const double ior = ext_number(*e, "KHR_materials_ior", "ior", 1.5);
      // The extension allows 0 ("no refraction"); clpt keeps indices in [1, 10].
      mat.ior = float(std::clamp(ior, 1.0, 10.0));
    }
    if (const tinygltf::Value* e = extension("KHR_materials_specular")) {
      const char* n = "KHR_materials_specular";
      mat.specular = float(std::clamp(ext_number(*e, n, "specularFactor", 1.0), 0.0, 1.0));
      mat.specular_color = ext_color(*e, n, "specularColorFactor");
      mat.specular_texture = ext_texture(*e, n, "specularTexture");
      mat.specular_color_texture = ext_texture(*e, n, "specularColorTexture");
    }
    if (const tinygltf::Value* e = extension("KHR_materials_volume")) {
      const char* n = "KHR_materials_volume";
      const double inf = std::numeric_limits<double>::infinity();
      double dist = inf;
      if (e->Has("attenuationDistance")) {
        dist = ext_number(*e, n, "attenuationDistance", inf);
        if (!(dist > 0.0)) fail(where + " " + n + " attenuationDistance " + number(dist) + " is not positive");
      }
      mat.attenuation_distance = float(dist);
      mat.attenuation_color = glm::clamp(ext_color(*e, n, "attenuationColor"), 0.0f, 1.0f);
      mat.volume = std::isfinite(mat.attenuation_distance);
    }
    scene_.materials.push_back(std::move(mat));
  }
  if (occlusion > 0)
    log::verbose(display_ + ": " + std::to_string(occlusion) +
                 " material(s) have an occlusion texture; ignored (a path tracer computes occlusion)");
}

uint32_t Converter::material_for(int gltf_material, const std::string& where) {
  if (gltf_material >= 0) {
    if (size_t(gltf_material) >= m_.materials.size())
      fail(where + " refers to material " + std::to_string(gltf_material) +
           ", which does not exist (the file has " + std::to_string(m_.materials.size()) + ")");
    return uint32_t(gltf_material);
  }
  if (default_material_ < 0) {
    Material def;  // glTF defaults: base colour 1, metallic 1, roughness 1
    def.name = "default";
    default_material_ = int(scene_.materials.size());
    scene_.materials.push_back(def);
  }
  return uint32_t(default_material_);
}

// ---- geometry

const LocalPrimitive& Converter::local_primitive(int mesh, int prim) {
  auto key = std::make_pair(mesh, prim);
  auto found = cache_.find(key);
  if (found != cache_.end()) return found->second;

  const tinygltf::Primitive& p = m_.meshes[size_t(mesh)].primitives[size_t(prim)];
  const std::string where = "mesh " + std::to_string(mesh) + " primitive " + std::to_string(prim);
  LocalPrimitive lp;

  auto pos_it = p.attributes.find("POSITION");
  if (pos_it == p.attributes.end()) fail(where + " has no POSITION attribute");
  {
    std::vector<float> v = read_values(pos_it->second, "POSITION of " + where, TINYGLTF_TYPE_VEC3, Components::Float);
    const size_t n = v.size() / 3;
    lp.positions.resize(n);
    for (size_t i = 0; i < n; ++i) {
      glm::dvec3 q(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
      if (!finite(q))
        fail(where + ": POSITION " + std::to_string(i) + " is not finite (" + number(q.x) + ", " + number(q.y) +
           ", " + number(q.z) + ")");
      lp.positions[i] = glm::vec3(q);
    }
  }
  const size_t nverts = lp.positions.size();
  if (nverts > limits_.vertices)
    fail(where + " has " + std::to_string(nverts) + " vertices, more than the limit of " + std::to_string(limits_.vertices) +
         " (--limit vertices=N)");
  auto check_count = [&](const char* name, size_t n) {
    if (n != nverts)
      fail(where + " has " + std::to_string(n) + " " + name + " values but " + std::to_string(nverts) + " positions");
  };
  auto nrm_it = p.attributes.find("NORMAL");
  if (nrm_it != p.attributes.end()) {
    std::vector<float> v = read_values(nrm_it->second, "NORMAL of " + where, TINYGLTF_TYPE_VEC3, Components::Float);
    check_count("NORMAL", v.size() / 3);
    lp.normals.resize(nverts);
    for (size_t i = 0; i < nverts; ++i) {
      glm::dvec3 q(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
      lp.normals[i] = finite(q) ? glm::vec3(q) : glm::vec3(0.0f);
    }
  }
  auto uv_it = p.attributes.find("TEXCOORD_0");
  if (uv_it != p.attributes.end()) {
    std::vector<float> v =
        read_values(uv_it->second, "TEXCOORD_0 of " + where, TINYGLTF_TYPE_VEC2, Components::FloatOrUNorm);
    check_count("TEXCOORD_0", v.size() / 2);
    lp.uvs.resize(nverts);
    for (size_t i = 0; i < nverts; ++i) {
      glm::dvec2 q(v[2 * i], v[2 * i + 1]);
      lp.uvs[i] = std::isfinite(q.x) && std::isfinite(q.y) ? glm::vec2(q) : glm::vec2(0.0f);
    }
  }
  auto uv1_it = p.attributes.find("TEXCOORD_1");
  if (uv1_it != p.attributes.end()) {
    std::vector<float> v =
        read_values(uv1_it->second, "TEXCOORD_1 of " + where, TINYGLTF_TYPE_VEC2, Components::FloatOrUNorm);
    check_count("TEXCOORD_1", v.size() / 2);
    lp.uvs1.resize(nverts);
    for (size_t i = 0; i < nverts; ++i) {
      glm::dvec2 q(v[2 * i], v[2 * i + 1]);
      lp.uvs1[i] = std::isfinite(q.x) && std::isfinite(q.y) ? glm::vec2(q) : glm::vec2(0.0f);
    }
  }
  auto tan_it = p.attributes.find("TANGENT");
  if (tan_it != p.attributes.end()) {
    std::vector<float> v = read_values(tan_it->second, "TANGENT of " + where, TINYGLTF_TYPE_VEC4, Components::Float);
    check_count("TANGENT", v.size() / 4);
    lp.tangents.resize(nverts);
    for (size_t i = 0; i < nverts; ++i) {
      glm::dvec3 t(v[4 * i], v[4 * i + 1], v[4 * i + 2]);
      const double len = glm::length(t);
      // A tangent that is not finite or zero means "no normal mapping here", not an error.
      if (finite(t) && len > 0.0 && std::isfinite(len))
        lp.tangents[i] = glm::vec4(glm::vec3(t / len), v[4 * i + 3] < 0.0f ? -1.0f : 1.0f);
    }
  }
  auto col_it = p.attributes.find("COLOR_0");
  if (col_it != p.attributes.end()) {
    if (col_it->second < 0 || size_t(col_it->second) >= m_.accessors.size())
      fail("COLOR_0 of " + where + " refers to accessor " + std::to_string(col_it->second) +
           ", which does not exist (the file has " + std::to_string(m_.accessors.size()) + ")");
    const int type = m_.accessors[size_t(col_it->second)].type == TINYGLTF_TYPE_VEC3 ? TINYGLTF_TYPE_VEC3
                                                                                      : TINYGLTF_TYPE_VEC4;
    const size_t nc = type == TINYGLTF_TYPE_VEC3 ? 3 : 4;
    std::vector<float> v = read_values(col_it->second, "COLOR_0 of " + where, type, Components::FloatOrUNorm);
    check_count("COLOR_0", v.size() / nc);
    lp.colors.resize(nverts);
    for (size_t i = 0; i < nverts; ++i) {
      glm::vec4 c(1.0f);
      for (size_t k = 0; k < nc; ++k) {
        const float x = v[nc * i + k];
        c[int(k)] = std::isfinite(x) ? std::clamp(x, 0.0f, 1.0f) : 1.0f;
      }
      lp.colors[i] = c;
    }
  }

  std::vector<uint32_t> idx;
  if (p.indices >= 0) {
    idx = read_indices(p.indices, "indices of " + where);
    for (size_t i = 0; i < idx.size(); ++i)
      if (idx[i] >= nverts)
        fail(where + ": index " + std::to_string(idx[i]) + " (entry " + std::to_string(i) +
             " of accessor " + std::to_string(p.indices) + ") is not less than the vertex count " +
             std::to_string(nverts));
  } else {
    idx.resize(nverts);
    for (size_t i = 0; i < nverts; ++i) idx[i] = uint32_t(i);
  }

  const size_t n = idx.size();
  const uint64_t ntri = p.mode == TINYGLTF_MODE_TRIANGLES ? n / 3 : (n >= 3 ? n - 2 : 0);
  if (ntri > limits_.triangles)
    fail(where + " has " + std::to_string(ntri) + " triangles, more than the limit of " + std::to_string(limits_.triangles) +
         " (--limit triangles=N)");
  switch (p.mode) {
    case TINYGLTF_MODE_TRIANGLES:
      if (n % 3 != 0) ++leftover_primitives_;
      lp.triangles.reserve(n / 3);
      for (size_t i = 0; i + 2 < n; i += 3) lp.triangles.emplace_back(idx[i], idx[i + 1], idx[i + 2]);
      break;
    case TINYGLTF_MODE_TRIANGLE_STRIP:
      // glTF: triangle i is (v_i, v_{i+1+i%2}, v_{i+2-i%2}): every other one flips so all
      // keep the winding of the first.
      if (n >= 3) lp.triangles.reserve(n - 2);
      for (size_t i = 0; i + 2 < n; ++i)
        lp.triangles.emplace_back(idx[i], idx[i + 1 + i % 2], idx[i + 2 - i % 2]);
      break;
    case TINYGLTF_MODE_TRIANGLE_FAN:
      // glTF: triangle i is (v_{i+1}, v_{i+2}, v_0).
      if (n >= 3) lp.triangles.reserve(n - 2);
      for (size_t i = 0; i + 2 < n; ++i) lp.triangles.emplace_back(idx[i + 1], idx[i + 2], idx[0]);
      break;
    default:
      fail(where + " has mode " + std::to_string(p.mode) + ", which is not a triangle mode");
  }
  // A normal map needs tangents: generate them from the normal map's UV set when the file
  // gives none (the material index is checked by material_for before this is called).
  if (lp.tangents.empty() && p.material >= 0 && size_t(p.material) < scene_.materials.size() &&
      scene_.materials[size_t(p.material)].normal_texture.used()) {
    const bool set1 = scene_.materials[size_t(p.material)].normal_texture.texcoord == 1;
    const std::vector<glm::vec2>& uv = set1 ? lp.uvs1 : lp.uvs;
    if (uv.empty()) {
      log::warn(display_ + ": " + where + " has a normal map but no TEXCOORD_" + (set1 ? "1" : "0") +
                "; the normal map is ignored");
    } else {
      lp.tangents = generate_tangents(lp.positions, lp.normals, uv, lp.triangles);
      log::verbose(display_ + ": " + where + ": generated tangents (no TANGENT attribute)");
    }
  }
  return cache_.emplace(key, std::move(lp)).first->second;
}

void Converter::add_instance(const LocalPrimitive& lp, const glm::dmat4& world, uint32_t material, int node,
                             int mesh, int prim) {
  if (scene_.positions.size() + lp.positions.size() > limits_.vertices)
    fail("the scene has more than " + std::to_string(limits_.vertices) + " vertices (the limit; --limit vertices=N)");
  if (scene_.triangles.size() + lp.triangles.size() > limits_.triangles)
    fail("the scene has more than " + std::to_string(limits_.triangles) + " triangles (the limit; --limit triangles=N)");
  {
    // The host memory the geometry will need up to upload (scene arrays, flattened arrays, BVH
    // build), so that a small file cannot make clpt allocate until the system kills it.
    const uint64_t v = scene_.positions.size() + lp.positions.size(),
                   t = scene_.triangles.size() + lp.triangles.size();
    const uint64_t need = v * kHostBytesPerVertex + t * kHostBytesPerTriangle,
                   budget = limits_.memory_budget();
    if (need > budget)
      fail("the scene needs about " + bytes_text(need) + " of memory for " + std::to_string(v) +
           " vertices and " + std::to_string(t) + " triangles (after instancing), more than the budget of " +
           bytes_text(budget) + " (" +
           (limits_.memory_bytes ? std::string("--limit memory") : std::string("80 % of this machine's memory")) +
           "; --limit memory=BYTES changes it)");
  }
  if (lp.triangles.empty()) return;

  const glm::dmat3 linear(world);
  const double det = glm::determinant(linear);
  glm::dmat3 normal_matrix = glm::inverseTranspose(linear);
  bool normals_ok = std::isfinite(det) && det != 0.0;
  for (int c = 0; c < 3 && normals_ok; ++c) normals_ok = finite(normal_matrix[c]);

  const uint32_t base = uint32_t(scene_.positions.size());
  for (size_t i = 0; i < lp.positions.size(); ++i) {
    glm::dvec3 p = glm::dvec3(world * glm::dvec4(glm::dvec3(lp.positions[i]), 1.0));
    glm::vec3 pf(p);
    if (!finite(glm::dvec3(pf)))
      fail("node " + std::to_string(node) + " transforms mesh " + std::to_string(mesh) + " primitive " +
           std::to_string(prim) + " to non-finite positions");
    scene_.positions.push_back(pf);
    glm::vec3 n(0.0f);
    if (normals_ok && !lp.normals.empty()) {
      glm::dvec3 t = normal_matrix * glm::dvec3(lp.normals[i]);
      double len = glm::length(t);
      if (std::isfinite(len) && len > 0.0) n = glm::vec3(t / len);
      if (!finite(glm::dvec3(n))) n = glm::vec3(0.0f);
    }
    scene_.normals.push_back(n);
    scene_.uvs.push_back(lp.uvs.empty() ? glm::vec2(0.0f) : lp.uvs[i]);
  }
  // Optional attributes: the scene's array stays empty until some primitive has one, then
  // holds a default for every vertex that has none.
  auto append = [&](auto& dst, const auto& src, auto def, auto&& convert) {
    if (src.empty() && dst.empty()) return;
    if (dst.empty()) dst.assign(base, def);
    for (size_t i = 0; i < lp.positions.size(); ++i) dst.push_back(src.empty() ? def : convert(src[i]));
  };
  const bool mirror = det < 0.0;
  append(scene_.uvs1, lp.uvs1, glm::vec2(0.0f), [](const glm::vec2& v) { return v; });
  append(scene_.colors, lp.colors, glm::vec4(1.0f), [](const glm::vec4& v) { return v; });
  // Tangents follow the surface: the linear part, not the normal matrix; a mirror flips the
  // handedness (cross(n', t') turns against the transformed bitangent).
  append(scene_.tangents, lp.tangents, glm::vec4(0.0f), [&](const glm::vec4& t) {
    if (t == glm::vec4(0.0f)) return t;
    const glm::dvec3 v = linear * glm::dvec3(t);
    const double len = glm::length(v);
    if (!(len > 0.0) || !std::isfinite(len)) return glm::vec4(0.0f);
    return glm::vec4(glm::vec3(v / len), mirror ? -t.w : t.w);
  });
  for (const glm::uvec3& t : lp.triangles) {
    glm::uvec3 w = t + glm::uvec3(base);
    if (mirror) std::swap(w.y, w.z);
    scene_.triangles.push_back(w);
    scene_.triangle_materials.push_back(material);
  }
}

// EXT_mesh_gpu_instancing: one transform per instance (TRS from accessors), applied before
// the node's own world transform. Empty when the node has no such extension.
std::vector<glm::dmat4> Converter::instance_transforms(int node) {
  const tinygltf::Node& n = m_.nodes[size_t(node)];
  auto ext = n.extensions.find("EXT_mesh_gpu_instancing");
  if (ext == n.extensions.end()) return {};
  const std::string where = "node " + std::to_string(node) + " EXT_mesh_gpu_instancing";
  if (!ext->second.IsObject() || !ext->second.Has("attributes") || !ext->second.Get("attributes").IsObject())
    fail(where + " has no attributes object");
  const tinygltf::Value& attrs = ext->second.Get("attributes");
  std::vector<float> t, r, s;
  uint64_t count = 0;
  bool any = false;
  auto read = [&](const char* name, int type, Components allowed, std::vector<float>* out) {
    if (!attrs.Has(name)) return;
    const tinygltf::Value& v = attrs.Get(name);
    if (!v.IsInt()) fail(where + " attribute " + name + " is not an accessor index");
    *out = read_values(v.GetNumberAsInt(), std::string(name) + " of " + where, type, allowed);
    uint64_t c = out->size() / size_t(type_components(type));
    if (any && c != count)
      fail(where + " attributes have different counts (" + std::to_string(count) + " and " + std::to_string(c) + ")");
    count = c;
    any = true;
  };
  read("TRANSLATION", TINYGLTF_TYPE_VEC3, Components::Float, &t);
  read("ROTATION", TINYGLTF_TYPE_VEC4, Components::FloatOrSNorm, &r);
  read("SCALE", TINYGLTF_TYPE_VEC3, Components::Float, &s);
  if (!any) fail(where + " has none of the attributes TRANSLATION, ROTATION, SCALE");

  std::vector<glm::dmat4> out(size_t(count), glm::dmat4(1.0));
  for (size_t i = 0; i < count; ++i) {
    glm::dmat4 m(1.0);
    if (!r.empty()) {
      glm::dvec4 q(r[4 * i], r[4 * i + 1], r[4 * i + 2], r[4 * i + 3]);
      double len = glm::length(q);
      if (!std::isfinite(len) || len < 1e-6) fail(where + " rotation " + std::to_string(i) + " is not a unit quaternion");
      q /= len;
      const double x = q.x, y = q.y, z = q.z, w = q.w;
      m[0] = glm::dvec4(1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y), 0);
      m[1] = glm::dvec4(2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x), 0);
      m[2] = glm::dvec4(2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y), 0);
    }
    if (!s.empty()) {
      m[0] *= s[3 * i];
      m[1] *= s[3 * i + 1];
      m[2] *= s[3 * i + 2];
    }
    if (!t.empty()) m[3] = glm::dvec4(t[3 * i], t[3 * i + 1], t[3 * i + 2], 1.0);
    if (!finite(m)) fail(where + " instance " + std::to_string(i) + " has a non-finite transform");
    out[i] = m;
  }
  return out;
}

void Converter::add_mesh(int node, int mesh, const glm::dmat4& world) {
  if (mesh < 0 || size_t(mesh) >= m_.meshes.size())
    fail("node " + std::to_string(node) + " refers to mesh " + std::to_string(mesh) +
         ", which does not exist (the file has " + std::to_string(m_.meshes.size()) + ")");
  std::vector<glm::dmat4> instances = instance_transforms(node);
  const auto& prims = m_.meshes[size_t(mesh)].primitives;
  for (size_t pi = 0; pi < prims.size(); ++pi) {
    const tinygltf::Primitive& p = prims[pi];
    if (p.mode >= TINYGLTF_MODE_POINTS && p.mode <= TINYGLTF_MODE_LINE_STRIP) {
      ++skipped_primitives_;
      skipped_modes_.insert(p.mode);
      continue;
    }
    const std::string where = "mesh " + std::to_string(mesh) + " primitive " + std::to_string(pi);
    const LocalPrimitive& lp = local_primitive(mesh, int(pi));
    const uint32_t material = material_for(p.material, where);
    if (instances.empty()) {
      add_instance(lp, world, material, node, mesh, int(pi));
    } else {
      for (const glm::dmat4& inst : instances) add_instance(lp, world * inst, material, node, mesh, int(pi));
    }
  }
}

void Converter::add_camera(int node, const glm::dmat4& world) {
  const tinygltf::Node& n = m_.nodes[size_t(node)];
  if (n.camera < 0 || size_t(n.camera) >= m_.cameras.size())
    fail("node " + std::to_string(node) + " refers to camera " + std::to_string(n.camera) +
         ", which does not exist (the file has " + std::to_string(m_.cameras.size()) + ")");
  const tinygltf::Camera& gc = m_.cameras[size_t(n.camera)];
  const std::string where = "camera " + std::to_string(n.camera);
  Camera cam;
  cam.name = !gc.name.empty() ? gc.name : n.name;
  if (gc.type == "orthographic") {
    cam.type = Camera::Type::Orthographic;
    const double xm = gc.orthographic.xmag, ym = gc.orthographic.ymag;
    if (!std::isfinite(xm) || !std::isfinite(ym) || xm == 0.0 || ym == 0.0)
      fail(where + " has an invalid xmag/ymag (" + number(xm) + ", " + number(ym) + ")");
    cam.xmag = float(std::fabs(xm));
    cam.ymag = float(std::fabs(ym));
  } else {
    cam.type = Camera::Type::Perspective;
    const double yfov = gc.perspective.yfov;
    if (!std::isfinite(yfov) || yfov <= 0.0 || yfov >= kPi)
      fail(where + " has yfov " + number(yfov) + ", which is not in (0, pi)");
    cam.yfov = float(yfov);
    const double aspect = gc.perspective.aspectRatio;
    cam.aspect = std::isfinite(aspect) && aspect > 0.0 ? float(aspect) : 0.0f;
  }
  // Rigid camera_to_world: keep the viewing direction (-Z) and the up vector (+Y) of the node,
  // drop scale and shear, and rebuild X so that the frame is right-handed even under a mirror.
  glm::dvec3 z(world[2]), y(world[1]);
  const double zl = glm::length(z);
  if (!std::isfinite(zl) || zl < 1e-12) {
    log::warn(display_ + ": camera on node " + std::to_string(node) + " has a degenerate transform; ignored");
    return;
  }
  z /= zl;
  y -= glm::dot(y, z) * z;
  double yl = glm::length(y);
  if (!std::isfinite(yl) || yl < 1e-12) {
    // No usable up vector: take any perpendicular one.
    y = std::fabs(z.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
    y -= glm::dot(y, z) * z;
    yl = glm::length(y);
  }
  y /= yl;
  const glm::dvec3 x = glm::cross(y, z);
  glm::dmat4 c2w(1.0);
  c2w[0] = glm::dvec4(x, 0.0);
  c2w[1] = glm::dvec4(y, 0.0);
  c2w[2] = glm::dvec4(z, 0.0);
  c2w[3] = glm::dvec4(glm::dvec3(world[3]), 1.0);
  cam.camera_to_world = glm::mat4(c2w);
  scene_.cameras.push_back(std::move(cam));
}

glm::dmat4 Converter::local_transform(int node) const {
  const tinygltf::Node& n = m_.nodes[size_t(node)];
  const std::string where = "node " + std::to_string(node);
  glm::dmat4 m(1.0);
  if (!n.matrix.empty()) {
    if (n.matrix.size() != 16) fail(where + " has a matrix of " + std::to_string(n.matrix.size()) + " numbers, expected 16");
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) m[c][r] = n.matrix[size_t(c * 4 + r)];
    if (!finite(m)) fail(where + " has a non-finite matrix");
    return m;
  }
  auto check_size = [&](const std::vector<double>& v, size_t want, const char* name) {
    if (!v.empty() && v.size() != want)
      fail(where + " has a " + name + " of " + std::to_string(v.size()) + " numbers, expected " + std::to_string(want));
    for (double d : v)
      if (!std::isfinite(d)) fail(where + " has a non-finite " + name);
  };
  check_size(n.translation, 3, "translation");
  check_size(n.rotation, 4, "rotation");
  check_size(n.scale, 3, "scale");
  if (!n.rotation.empty()) {
    glm::dvec4 q(n.rotation[0], n.rotation[1], n.rotation[2], n.rotation[3]);
    const double len = glm::length(q);
    if (len < 1e-6) fail(where + " has a rotation that is not a unit quaternion");
    q /= len;
    const double x = q.x, y = q.y, z = q.z, w = q.w;
    m[0] = glm::dvec4(1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y), 0);
    m[1] = glm::dvec4(2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x), 0);
    m[2] = glm::dvec4(2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y), 0);
  }
  if (!n.scale.empty()) {
    m[0] *= n.scale[0];
    m[1] *= n.scale[1];
    m[2] *= n.scale[2];
  }
  if (!n.translation.empty()) m[3] = glm::dvec4(n.translation[0], n.translation[1], n.translation[2], 1.0);
  return m;
}

void Converter::visit(int node, int parent, const glm::dmat4& parent_world, int depth) {
  if (node < 0 || size_t(node) >= m_.nodes.size())
    fail((parent < 0 ? std::string("the scene") : "node " + std::to_string(parent)) + " refers to node " +
         std::to_string(node) + ", which does not exist (the file has " + std::to_string(m_.nodes.size()) + ")");
  if (on_path_[size_t(node)])
    fail("the node graph has a cycle: node " + std::to_string(node) + " is its own ancestor");
  if (uint64_t(depth) > limits_.node_depth)
    fail("the node hierarchy is deeper than " + std::to_string(limits_.node_depth) + " levels");
  if (++visits_ > limits_.node_visits)
    fail("walking the node graph visits more than " + std::to_string(limits_.node_visits) + " nodes (the limit; --limit node-visits=N)");

  const glm::dmat4 world = parent_world * local_transform(node);
  if (!finite(world)) fail("node " + std::to_string(node) + " has a non-finite world transform");

  const tinygltf::Node& n = m_.nodes[size_t(node)];
  if (n.camera >= 0) add_camera(node, world);
  if (const int light = lights_.node_light(node); light >= 0) {  // KHR_lights_punctual
    PunctualLight placed;
    if (lights_.place(light, world, &placed)) scene_.lights.push_back(placed);
    else log::warn(display_ + ": light on node " + std::to_string(node) + " has a degenerate transform; ignored");
  }
  if (n.mesh >= 0) add_mesh(node, n.mesh, world);
  on_path_[size_t(node)] = 1;
  for (int child : n.children) visit(child, node, world, depth + 1);
  on_path_[size_t(node)] = 0;
}

Scene Converter::convert() {
  std::vector<int> roots;
  if (m_.defaultScene >= 0) {
    if (size_t(m_.defaultScene) >= m_.scenes.size())
      fail("the default scene " + std::to_string(m_.defaultScene) + " does not exist (the file has " +
           std::to_string(m_.scenes.size()) + " scenes)");
    roots = m_.scenes[size_t(m_.defaultScene)].nodes;
    log::verbose(display_ + ": rendering scene " + std::to_string(m_.defaultScene) + " (the file's default)");
  } else if (!m_.scenes.empty()) {
    roots = m_.scenes[0].nodes;
    log::verbose(display_ + ": the file names no default scene; rendering scenes[0]");
  } else if (!m_.nodes.empty()) {
    // No scenes at all: render every node that is nobody's child.
    std::vector<char> is_child(m_.nodes.size(), 0);
    for (const auto& n : m_.nodes)
      for (int c : n.children)
        if (c >= 0 && size_t(c) < m_.nodes.size()) is_child[size_t(c)] = 1;
    for (size_t i = 0; i < m_.nodes.size(); ++i)
      if (!is_child[i]) roots.push_back(int(i));
    log::verbose(display_ + ": the file has no scenes; rendering its " + std::to_string(roots.size()) + " root nodes");
  } else {
    fail("nothing to render: the file has no scenes and no nodes");
  }

  convert_materials();
  on_path_.assign(m_.nodes.size(), 0);
  for (int root : roots) visit(root, -1, glm::dmat4(1.0), 0);

  if (skipped_primitives_ > 0) {
    static const char* names[] = {"POINTS", "LINES", "LINE_LOOP", "LINE_STRIP"};
    std::vector<std::string> modes;
    for (int mode : skipped_modes_) modes.push_back(names[mode]);
    log::warn(display_ + ": skipped " + std::to_string(skipped_primitives_) + " primitive(s) of mode " +
              join(modes, "/") + " (clpt renders triangles only)");
  }
  if (leftover_primitives_ > 0)
    log::warn(display_ + ": " + std::to_string(leftover_primitives_) +
              " TRIANGLES primitive(s) have an index count that is not a multiple of 3; the extra indices were ignored");
  if (scene_.triangles.empty()) fail("nothing to render: the scene has no triangles");
  if (scene_.materials.empty()) material_for(-1, "");  // cannot happen with triangles, but keep the promise
  return std::move(scene_);
}

}  // namespace

Scene load_gltf(const std::filesystem::path& file, const LoadOptions& options) {
  const std::string display = file.string();
  auto fail = [&](const std::string& message) -> void {
    throw Error(ExitCode::BadInput, display + ": " + message);
  };

  try {
    std::vector<unsigned char> bytes;
    std::string why;
    if (!read_whole_file(file, options.limits.file_bytes, &bytes, &why)) fail(why);
    if (bytes.empty()) fail("the file is empty (0 bytes)");

    // GLB or JSON, by the first bytes.
    const bool binary = bytes.size() >= 4 && read_u32le(bytes.data()) == kGlbMagic;
    const char* json_text;
    size_t json_size;
    if (binary) {
      std::tie(json_text, json_size) = check_glb(bytes, fail);
    } else {
      json_text = reinterpret_cast<const char*>(bytes.data());
      json_size = bytes.size();
    }
    const size_t max_depth = size_t(std::min<uint64_t>(options.limits.json_depth, SIZE_MAX - 1));
    if (json_depth(json_text, json_size, max_depth) > max_depth)
      fail("JSON nesting is deeper than " + std::to_string(max_depth) + " levels");

    nlohmann::json doc;
    try {
      doc = nlohmann::json::parse(json_text, json_text + json_size);
    } catch (const nlohmann::json::exception& e) {
      std::string what = e.what();
      size_t close = what.find("] ");
      if (what.rfind("[json.exception", 0) == 0 && close != std::string::npos) what = what.substr(close + 2);
      fail(std::string(binary ? "invalid JSON chunk: " : "invalid JSON: ") + what);
    }
    if (!doc.is_object()) fail("the JSON root is not an object, so this is not a glTF file");
    {
      auto asset = doc.find("asset");
      if (asset == doc.end() || !asset->is_object() || !asset->contains("version") ||
          !(*asset)["version"].is_string())
        fail("missing asset.version, so this is not a glTF 2.0 file");
      std::string version = (*asset)["version"].get<std::string>();
      if (version.rfind("2.", 0) != 0) fail("glTF version " + printable(version) + " is not supported (only 2.x)");
    }

    // Extensions: refuse unsupported required ones before anything else looks at the data.
    std::vector<std::string> unsupported_required, unsupported_used;
    auto collect = [&](const char* key, std::vector<std::string>* out) {
      auto it = doc.find(key);
      if (it == doc.end() || !it->is_array()) return;
      for (const auto& e : *it)
        if (e.is_string() && !is_supported_extension(e.get<std::string>()) &&
            std::find(out->begin(), out->end(), e.get<std::string>()) == out->end())
          out->push_back(e.get<std::string>());
    };
    collect("extensionsRequired", &unsupported_required);
    collect("extensionsUsed", &unsupported_used);
    if (!unsupported_required.empty())
      fail(std::string("requires extension") + (unsupported_required.size() > 1 ? "s " : " ") +
           join(unsupported_required, ", ") + ", which clpt does not support");

    // URIs: data: or relative inside the folder.
    ImageSources images;
    images.lenient = options.lenient;
    FsContext ctx;
    ctx.limits = &options.limits;
    {
      std::error_code ec;
      fs::path abs = fs::absolute(file, ec);
      ctx.base = (ec ? file : abs).parent_path();
      std::string base = ctx.base.string();
      ctx.prefix = base.empty() || base.back() == '/' ? base : base + "/";
      ctx.bytes_read = bytes.size();
    }
    auto check_uris = [&](const char* key, const char* what, bool required) {
      auto it = doc.find(key);
      if (it == doc.end() || !it->is_array()) return;
      for (size_t i = 0; i < it->size(); ++i) {
        const auto& item = (*it)[i];
        if (!item.is_object()) continue;
        auto u = item.find("uri");
        if (u == item.end()) {
          if (required && !binary && !item.contains("bufferView"))
            fail(std::string(what) + " " + std::to_string(i) + " has no uri (only a .glb can embed a buffer)");
          continue;
        }
        if (!u->is_string()) fail(std::string(what) + " " + std::to_string(i) + " has a uri that is not a string");
        const std::string raw = u->get<std::string>();
        if (tinygltf::IsDataURI(raw)) continue;
        const std::string label = std::string(what) + " " + std::to_string(i) + " uri " + printable(raw);
        if (!required && raw.rfind("data:", 0) == 0) {
          // E.g. image/webp or a URI that is not base64: tinygltf would take it for a file name.
          ctx.skip.insert(tinygltf_urldecode(raw));
          images.problem[int(i)] =
              "its data: URI cannot be decoded (base64 image/png or image/jpeg are supported)";
          continue;
        }
        std::string problem = uri_problem(raw);
        const std::string decoded = percent_decode(raw);
        if (problem.empty()) problem = uri_problem(decoded);
        if (!problem.empty()) fail(label + " " + problem);
        ctx.rewrite.emplace(tinygltf_urldecode(raw), decoded);
        std::error_code ec;
        if (!fs::is_regular_file(ctx.base / decoded, ec)) {
          if (required) fail(label + ": file " + printable(decoded) + " not found next to the scene file");
          images.problem[int(i)] = "file " + printable(decoded) + " not found next to the scene file";
        }
      }
    };
    check_uris("buffers", "buffer", true);
    check_uris("images", "image", false);

    // Parse for real.
    tinygltf::TinyGLTF loader;
    tinygltf::FsCallbacks callbacks{&fs_file_exists, &fs_expand_file_path, &fs_read_whole_file,
                                    &fs_write_whole_file, &ctx};
    loader.SetFsCallbacks(callbacks);
    loader.SetImageLoader(&keep_image_undecoded, &images);
    tinygltf::Model model;
    std::string err, warn;
    bool ok = false;
    try {
      ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(), unsigned(bytes.size()),
                                                ctx.base.string(), tinygltf::REQUIRE_VERSION)
                  : loader.LoadASCIIFromString(&model, &err, &warn, json_text, unsigned(json_size),
                                               ctx.base.string(), tinygltf::REQUIRE_VERSION);
    } catch (const std::bad_alloc&) {
      throw;
    } catch (const std::exception& e) {
      fail(std::string("glTF parse error: ") + e.what());
    }
    if (!ctx.refusal.empty()) fail(ctx.refusal);
    for (const std::string& line : {warn, ok ? err : std::string()}) {
      std::string text = one_line(line);
      if (!text.empty()) log::verbose(display + ": tinygltf: " + text);
    }
    if (!ok) {
      std::string text = one_line(err);
      fail(text.empty() ? "tinygltf could not parse the file" : text);
    }
    bytes.clear();
    bytes.shrink_to_fit();

    if (!unsupported_used.empty())
      log::warn(display + ": ignoring unsupported extension" + (unsupported_used.size() > 1 ? "s " : " ") +
                join(unsupported_used, ", "));

    Scene scene = Converter(model, display, images, options.limits).convert();
    log::verbose(display + ": " + std::to_string(scene.triangles.size()) + " triangles, " +
                 std::to_string(scene.positions.size()) + " vertices, " + std::to_string(scene.materials.size()) +
                 " materials, " + std::to_string(scene.cameras.size()) + " cameras");
    return scene;
  } catch (const Error&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw Error(ExitCode::BadInput, display + ": out of memory while loading the scene");
  } catch (const std::exception& e) {
    throw Error(ExitCode::BadInput, display + ": " + e.what());
  }
}

}  // namespace clpt
