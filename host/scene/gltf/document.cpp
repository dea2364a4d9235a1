// The glTF document before tinygltf sees it: the GLB container (header and chunk table), the
// JSON nesting pre-scan, the JSON parse with clear messages, the asset version, and the
// extensions clpt supports (unsupported required ones are refused up front).
#include <algorithm>
#include <cstdio>

#include "scene/gltf/gltf_internal.h"
#include "util/log.h"

namespace clpt::gltf {
namespace {

// Extensions clpt implements. Anything else in extensionsRequired is refused; anything else in
// extensionsUsed is ignored with one warning.
const char* const kSupportedExtensions[] = {
    "KHR_materials_emissive_strength",
    "KHR_materials_transmission",
    "KHR_materials_ior",
    "KHR_materials_specular",
    "KHR_materials_volume",
    "KHR_materials_clearcoat",  // materials.cpp, kernels/bsdf/gltf_bsdf.cl
    "KHR_materials_dispersion",  // materials.cpp, kernels/integrators/stages/walk.cl (walk_disperse)
    "KHR_materials_iridescence",  // materials.cpp, kernels/bsdf/thin_film.cl
    "KHR_materials_diffuse_transmission",  // materials.cpp, kernels/bsdf/gltf_bsdf.cl
    "KHR_materials_sheen",  // materials.cpp, kernels/bsdf/sheen.cl
    "KHR_materials_anisotropy",  // materials.cpp, material.cl, kernels/bsdf/microfacet.cl
    "KHR_texture_transform",
    "EXT_mesh_gpu_instancing",
    "KHR_lights_punctual",
    "KHR_mesh_quantization",       // accessors.cpp: integer attribute types
    "EXT_meshopt_compression",     // compression.cpp: bufferViews decoded by meshoptimizer
    "KHR_draco_mesh_compression",  // compression.cpp: primitives decoded by Draco
    "EXT_texture_webp",            // materials.cpp, image_decode.cpp: WebP through OpenImageIO
};

// Extensions clpt knows and cannot support, with the reason given when a file requires one.
struct Refusal {
  const char* name;
  const char* why;
};
const Refusal kRefused[] = {
    {"KHR_texture_basisu",
     "KTX2 / Basis Universal textures need a transcoder, which Debian does not package; "
     "files that list it only in extensionsUsed render from their PNG/JPEG fallback images"},
};

bool is_supported_extension(const std::string& name) {
  for (const char* s : kSupportedExtensions)
    if (name == s) return true;
  return false;
}

std::string hex32(uint32_t v) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "0x%08X", v);
  return buf;
}

}  // namespace

uint32_t read_u32le(const unsigned char* p) {
  return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

// Checks the GLB header and chunk table (tinygltf checks less, and says only "Invalid glTF
// binary."). Returns the JSON chunk. `fail` throws.
std::pair<const char*, size_t> check_glb(const std::vector<unsigned char>& d, const Fail& fail) {
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

// The GLB `glb` with its JSON chunk replaced by `json` (padded with spaces to 4 bytes); the
// chunks after it are copied as they are. `glb` has passed check_glb.
std::vector<unsigned char> replace_glb_json(const std::vector<unsigned char>& glb, const std::string& json) {
  const size_t old_end = 20 + size_t(read_u32le(&glb[12]));
  const size_t json_len = (json.size() + 3) / 4 * 4;
  std::vector<unsigned char> out;
  out.reserve(20 + json_len + (glb.size() - old_end));
  auto put32 = [&](uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back((unsigned char)(v >> (8 * i)));
  };
  put32(kGlbMagic);
  put32(2);
  put32(uint32_t(20 + json_len + (glb.size() - old_end)));
  put32(uint32_t(json_len));
  put32(kChunkJson);
  out.insert(out.end(), json.begin(), json.end());
  out.resize(20 + json_len, ' ');
  out.insert(out.end(), glb.begin() + long(old_end), glb.end());
  return out;
}

// Parses the JSON text (the file, or the GLB's JSON chunk) with nlohmann, for a clear message
// when it is invalid, and checks that it is a glTF 2.x document (asset.version).
nlohmann::json parse_json(const char* json_text, size_t json_size, bool binary, const Fail& fail) {
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
  return doc;
}

// Extensions: refuses unsupported required ones before anything else looks at the data.
// Returns the unsupported ones of extensionsUsed, ignored with one warning once parsed.
std::vector<std::string> check_extensions(const nlohmann::json& doc, const Fail& fail) {
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
  for (const Refusal& r : kRefused)
    if (std::find(unsupported_required.begin(), unsupported_required.end(), r.name) != unsupported_required.end())
      fail(std::string("requires extension ") + r.name + ", which clpt does not support (" + r.why + ")");
  if (!unsupported_required.empty())
    fail(std::string("requires extension") + (unsupported_required.size() > 1 ? "s " : " ") +
         join(unsupported_required, ", ") + ", which clpt does not support");
  return unsupported_used;
}

namespace {

constexpr int64_t kMaxIndex = 2147483647;  // tinygltf keeps indices in int

// One glTFid: an integer in [0, 2^31 - 1]; `where` names it ("nodes[3].mesh").
void check_index(const nlohmann::json& v, const std::string& where, const Fail& fail) {
  if (v.is_number_unsigned() ? v.get<uint64_t>() <= uint64_t(kMaxIndex)
      : v.is_number_integer() ? v.get<int64_t>() >= 0 && v.get<int64_t>() <= kMaxIndex
                              : !v.is_number())
    return;  // an index, or not a number at all (tinygltf's message says what it expected)
  fail(where + " is " + v.dump() + ", which is not an index (an integer from 0 to 2147483647)");
}

// obj[key], when obj is an object that has it.
const nlohmann::json* member(const nlohmann::json& obj, const char* key) {
  if (!obj.is_object()) return nullptr;
  auto it = obj.find(key);
  return it == obj.end() ? nullptr : &*it;
}

// Each element of the array doc[key] (none when it is not an array), with its name.
template <class F>
void each(const nlohmann::json& doc, const char* key, F&& f) {
  const nlohmann::json* a = member(doc, key);
  if (!a || !a->is_array()) return;
  for (size_t i = 0; i < a->size(); ++i) f((*a)[i], std::string(key) + "[" + std::to_string(i) + "]");
}

void check_field(const nlohmann::json& obj, const char* key, const std::string& where, const Fail& fail) {
  if (const nlohmann::json* v = member(obj, key)) check_index(*v, where + "." + key, fail);
}

void check_list(const nlohmann::json& obj, const char* key, const std::string& where, const Fail& fail) {
  const nlohmann::json* a = member(obj, key);
  if (!a || !a->is_array()) return;
  for (size_t i = 0; i < a->size(); ++i)
    check_index((*a)[i], where + "." + key + "[" + std::to_string(i) + "]", fail);
}

void check_map(const nlohmann::json& obj, const char* key, const std::string& where, const Fail& fail) {
  const nlohmann::json* m = member(obj, key);
  if (!m || !m->is_object()) return;
  for (auto it = m->begin(); it != m->end(); ++it) check_index(*it, where + "." + key + "." + it.key(), fail);
}

// A material's texture references, core and extensions alike: the "index" of every object
// held under a key that ends in "Texture".
void check_textures(const nlohmann::json& v, const std::string& where, const Fail& fail) {
  if (!v.is_object()) return;
  for (auto it = v.begin(); it != v.end(); ++it) {
    const std::string& key = it.key();
    const std::string at = where + "." + key;
    if (key.size() >= 7 && key.compare(key.size() - 7, 7, "Texture") == 0 && it->is_object())
      check_field(*it, "index", at, fail);
    else
      check_textures(*it, at, fail);
  }
}

}  // namespace

void check_indices(const nlohmann::json& doc, const Fail& fail) {
  if (const nlohmann::json* scene = member(doc, "scene")) check_index(*scene, "scene", fail);
  each(doc, "scenes", [&](const nlohmann::json& s, const std::string& w) { check_list(s, "nodes", w, fail); });
  each(doc, "nodes", [&](const nlohmann::json& n, const std::string& w) {
    check_list(n, "children", w, fail);
    for (const char* k : {"mesh", "camera", "skin"}) check_field(n, k, w, fail);
    if (const nlohmann::json* ext = member(n, "extensions"))
      if (const nlohmann::json* l = member(*ext, "KHR_lights_punctual"))
        check_field(*l, "light", w + ".extensions.KHR_lights_punctual", fail);
  });
  each(doc, "skins", [&](const nlohmann::json& s, const std::string& w) {
    check_field(s, "skeleton", w, fail);
    check_field(s, "inverseBindMatrices", w, fail);
    check_list(s, "joints", w, fail);
  });
  each(doc, "meshes", [&](const nlohmann::json& m, const std::string& w) {
    each(m, "primitives", [&](const nlohmann::json& p, const std::string& pw) {
      const std::string at = w + "." + pw;
      check_map(p, "attributes", at, fail);
      check_field(p, "indices", at, fail);
      check_field(p, "material", at, fail);
      if (const nlohmann::json* e = member(p, "extensions"))
        if (const nlohmann::json* d = member(*e, "KHR_draco_mesh_compression")) {
          const std::string dw = at + ".extensions.KHR_draco_mesh_compression";
          check_field(*d, "bufferView", dw, fail);
          check_map(*d, "attributes", dw, fail);
        }
      each(p, "targets", [&](const nlohmann::json& t, const std::string& tw) {
        if (t.is_object())
          for (auto it = t.begin(); it != t.end(); ++it) check_index(*it, at + "." + tw + "." + it.key(), fail);
      });
    });
  });
  each(doc, "accessors", [&](const nlohmann::json& a, const std::string& w) {
    check_field(a, "bufferView", w, fail);
    if (const nlohmann::json* sp = member(a, "sparse")) {
      if (const nlohmann::json* i = member(*sp, "indices")) check_field(*i, "bufferView", w + ".sparse.indices", fail);
      if (const nlohmann::json* v = member(*sp, "values")) check_field(*v, "bufferView", w + ".sparse.values", fail);
    }
  });
  each(doc, "bufferViews", [&](const nlohmann::json& b, const std::string& w) {
    check_field(b, "buffer", w, fail);
    // EXT_meshopt_compression's sizes reach the Converter through tinygltf's int as well.
    if (const nlohmann::json* e = member(b, "extensions"))
      if (const nlohmann::json* m = member(*e, "EXT_meshopt_compression"))
        for (const char* key : {"buffer", "byteOffset", "byteLength", "byteStride", "count"})
          check_field(*m, key, w + ".extensions.EXT_meshopt_compression", fail);
  });
  each(doc, "textures", [&](const nlohmann::json& t, const std::string& w) {
    check_field(t, "sampler", w, fail);
    check_field(t, "source", w, fail);
    if (const nlohmann::json* e = member(t, "extensions"))
      for (const char* ext : {"EXT_texture_webp", "KHR_texture_basisu"})
        if (const nlohmann::json* x = member(*e, ext)) check_field(*x, "source", w + ".extensions." + ext, fail);
  });
  each(doc, "images", [&](const nlohmann::json& i, const std::string& w) { check_field(i, "bufferView", w, fail); });
  each(doc, "materials", [&](const nlohmann::json& m, const std::string& w) { check_textures(m, w, fail); });
  each(doc, "animations", [&](const nlohmann::json& a, const std::string& w) {
    each(a, "channels", [&](const nlohmann::json& c, const std::string& cw) {
      check_field(c, "sampler", w + "." + cw, fail);
      if (const nlohmann::json* t = member(c, "target")) check_field(*t, "node", w + "." + cw + ".target", fail);
    });
    each(a, "samplers", [&](const nlohmann::json& s, const std::string& sw) {
      check_field(s, "input", w + "." + sw, fail);
      check_field(s, "output", w + "." + sw, fail);
    });
  });
}

}  // namespace clpt::gltf
