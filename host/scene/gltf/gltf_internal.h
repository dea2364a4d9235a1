// Internal to the glTF loader: what host/scene/gltf_loader.cpp (the load_gltf flow) and its
// parts in host/scene/gltf/ share. Nothing else includes this header.
//
//   text.cpp       message text: numbers, sizes, one-line and printable strings
//   uri.cpp        URI sandbox and file resolution; tinygltf's file-system and image callbacks
//   document.cpp   GLB container, JSON pre-scan and parse, asset version, supported extensions
//   compression.cpp  EXT_meshopt_compression bufferViews and KHR_draco_mesh_compression primitives
//   accessors.cpp  buffer views and accessors (sparse included), range-checked
//   materials.cpp  materials and textures (images, samplers, KHR_texture_transform)
//   geometry.cpp   mesh primitives to world-space triangles, EXT_mesh_gpu_instancing
//   cameras.cpp    cameras
//   nodes.cpp      the node graph walk and Converter::convert
#pragma once

#include <tiny_gltf.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <algorithm>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "scene/gltf_lights.h"
#include "scene/image_decode.h"
#include "scene/load_limits.h"
#include "util/text.h"
#include "scene/scene.h"
#include "util/error.h"

namespace clpt::gltf {

namespace fs = std::filesystem;

// Reports a problem with the file: throws Error(BadInput) with the file's name and `message`.
using Fail = std::function<void(const std::string&)>;  // must throw

// Each section declares what one file defines and others use; the comments on what each
// function does are with its code.

// ------------------------------------------------------------------------------------------
// Message text (text.cpp)

using u128 = unsigned __int128;

std::string to_string_u128(u128 v);
std::string number(double v);
std::string bytes_text(uint64_t b);
std::string join(const std::vector<std::string>& items, const char* sep);
std::string printable(const std::string& s);  // quoted, control characters escaped

// ------------------------------------------------------------------------------------------
// Files and URIs (uri.cpp)

bool read_whole_file(const fs::path& path, uint64_t cap, std::vector<unsigned char>* out,
                     std::string* why);

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

// What the loader knows about each glTF image before conversion: the encoded bytes of external
// files and data: URIs (copied by keep_image_undecoded), and why an image has none.
struct ImageSources {
  std::map<int, std::vector<unsigned char>> bytes;
  std::map<int, std::string> problem;
  bool lenient = false;
};

void check_uris(const nlohmann::json& doc, bool binary, FsContext& ctx, ImageSources& images, const Fail& fail);

// tinygltf's FsCallbacks (user data: the FsContext).
bool fs_file_exists(const std::string& abs_filename, void* user);
std::string fs_expand_file_path(const std::string& path, void*);
bool fs_read_whole_file(std::vector<unsigned char>* out, std::string* err, const std::string& filepath,
                        void* user);
bool fs_write_whole_file(std::string* err, const std::string&, const std::vector<unsigned char>&, void*);

// tinygltf's image callback (user data: the ImageSources).
bool keep_image_undecoded(tinygltf::Image* image, const int image_idx, std::string*, std::string*, int, int,
                          const unsigned char* bytes, int size, void* user);

// ------------------------------------------------------------------------------------------
// GLB container and JSON (document.cpp)

constexpr uint32_t kGlbMagic = 0x46546C67;  // "glTF"
constexpr uint32_t kChunkJson = 0x4E4F534A;
constexpr uint32_t kChunkBin = 0x004E4942;

uint32_t read_u32le(const unsigned char* p);
std::pair<const char*, size_t> check_glb(const std::vector<unsigned char>& d, const Fail& fail);
size_t json_depth(const char* p, size_t n, size_t limit);
nlohmann::json parse_json(const char* json_text, size_t json_size, bool binary, const Fail& fail);
std::vector<std::string> check_extensions(const nlohmann::json& doc, const Fail& fail);
std::vector<unsigned char> replace_glb_json(const std::vector<unsigned char>& glb, const std::string& json);
// Every glTFid of the document (scene, node, mesh, accessor, texture ... references) is an
// integer in [0, 2^31 - 1]: tinygltf keeps them in int, so 4294967296 became 0 and "scene": -5
// the absent default (issue 23, class 6). Fails naming the field and its value.
void check_indices(const nlohmann::json& doc, const Fail& fail);

// ------------------------------------------------------------------------------------------
// Compressed geometry before tinygltf sees it (compression.cpp)

// tinygltf 2.7 cannot load two kinds of valid compressed files, so the JSON it reads is
// adapted: EXT_meshopt_compression's fallback buffers (no uri, "fallback": true, no data)
// become 1-byte data: URIs, which no compressed bufferView reads; a Draco primitive's
// "indices" (an accessor without a bufferView, which tinygltf refuses) moves into its
// KHR_draco_mesh_compression object under kDracoIndicesKey. Returns whether the document changed.
constexpr const char* kDracoIndicesKey = "clpt:indices";
bool adapt_compressed_for_tinygltf(nlohmann::json& doc);

// ------------------------------------------------------------------------------------------
// Conversion of the tinygltf model (accessors.cpp, materials.cpp, geometry.cpp, cameras.cpp,
// nodes.cpp)

struct LocalPrimitive {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;  // empty when the primitive has none
  std::vector<glm::vec2> uvs;      // empty when the primitive has none
  std::vector<glm::vec2> uvs1;     // TEXCOORD_1, empty when the primitive has none
  std::vector<glm::vec4> tangents; // TANGENT or generated, empty when none
  std::vector<glm::vec4> colors;   // COLOR_0 as linear RGBA, empty when none
  std::vector<glm::uvec3> triangles;
};

// All components finite (geometry.cpp).
bool finite(const glm::dmat4& m);
bool finite(const glm::dvec3& v);

// Components per element of an accessor type: 3 for VEC3, ... (accessors.cpp).
int type_components(int type);

// What a component type may be for one use of an accessor.
// Position, Direction and TexCoord widen under KHR_mesh_quantization, as that extension's
// table of attribute types says.
enum class Components {
  Float,              // FLOAT only
  FloatOrUNorm,       // FLOAT, normalized UNSIGNED_BYTE / UNSIGNED_SHORT (COLOR_0)
  FloatOrSNorm,       // FLOAT, normalized BYTE / SHORT (instance ROTATION)
  Index,              // UNSIGNED_BYTE / UNSIGNED_SHORT / UNSIGNED_INT
  Position,           // FLOAT; quantized: (normalized or not) BYTE, UNSIGNED_BYTE, SHORT, UNSIGNED_SHORT
  Direction,          // FLOAT; quantized: normalized BYTE / SHORT (NORMAL, TANGENT)
  TexCoord,           // FLOAT, normalized UNSIGNED_BYTE / UNSIGNED_SHORT; quantized: as Position
};

class Converter {
 public:
  // file_bytes: the scene's files together (glTF, buffers, images), for the memory budget.
  Converter(const tinygltf::Model& model, std::string display, ImageSources& images,
            const LoadLimits& limits, uint64_t file_bytes)
      : m_(model), display_(std::move(display)), images_(images), limits_(limits), file_bytes_(file_bytes),
        quantized_(std::find(model.extensionsUsed.begin(), model.extensionsUsed.end(),
                             "KHR_mesh_quantization") != model.extensionsUsed.end()) {}

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

  // Compressed geometry (compression.cpp): an EXT_meshopt_compression bufferView decoded on
  // first use; a KHR_draco_mesh_compression primitive decoded into draco_accessors_.
  const std::vector<unsigned char>& meshopt_view(int index, const tinygltf::Value& ext) const;
  void decode_draco(const tinygltf::Primitive& p, const tinygltf::Value& ext, const std::string& where);
  int indices_accessor(const tinygltf::Primitive& p) const;  // p.indices, or a Draco primitive's
  // Counts decoded bytes against the memory budget before they are allocated.
  void reserve_decoded(uint64_t bytes, const std::string& what) const;
  // Fails unless the geometry's host memory for `vertices` and `triangles` (the scene's so
  // far plus what is about to be added) is within the budget (LoadLimits::memory_budget).
  void check_geometry_memory(uint64_t vertices, uint64_t triangles) const;

  void convert_materials();
  TextureRef texture_ref(int index, int texcoord, const tinygltf::Value* transform, const std::string& where);
  TextureRef texture_info(const tinygltf::Value& info, const std::string& where);
  int scene_texture(int texture, const std::string& where);
  std::string image_label(int index) const;
  bool image_bytes(int index, const unsigned char** data, size_t* size, std::string* why);
  void decode_textures();
  uint32_t material_for(int gltf_material, const std::string& where);
  const LocalPrimitive& local_primitive(int mesh, int prim);
  void add_instance(const LocalPrimitive& lp, const glm::dmat4& world, uint32_t material, int node,
                    int mesh, int prim);
  void add_mesh(int node, int mesh, const glm::dmat4& world);
  // vertices, triangles: one instance's, checked times the instance count against the limits.
  std::vector<glm::dmat4> instance_transforms(int node, uint64_t vertices, uint64_t triangles);
  void add_camera(int node, const glm::dmat4& world);
  glm::dmat4 local_transform(int node) const;
  void visit(int node, int parent, const glm::dmat4& parent_world, int depth);

  const tinygltf::Model& m_;
  std::string display_;
  ImageSources& images_;
  const LoadLimits& limits_;
  const uint64_t file_bytes_;
  struct PendingTexture {
    int source;         // glTF image
    std::string where;  // its first user, for messages
  };
  std::map<int, PendingTexture> pending_textures_;  // scene texture -> its image, until decoded
  std::map<std::tuple<int, int, int, bool>, int> textures_;  // (image, wrapS, wrapT, nearest) -> scene texture
  std::map<int, int> texture_of_;                        // glTF texture -> scene texture (-1: none)
  uint64_t total_texels_ = 0;  // texels of the scene's textures decoded so far
  Scene scene_;
  int default_material_ = -1;
  std::map<std::pair<int, int>, LocalPrimitive> cache_;
  std::vector<char> on_path_;
  GltfLights lights_{m_, [this](const std::string& message) { fail(message); }};  // KHR_lights_punctual
  const bool quantized_;                                   // KHR_mesh_quantization in extensionsUsed
  mutable std::map<int, std::vector<unsigned char>> meshopt_views_;  // decoded, by bufferView
  std::map<int, std::vector<unsigned char>> draco_accessors_;  // decoded elements, tightly packed, by accessor
  mutable uint64_t decoded_bytes_ = 0;
  mutable uint64_t zero_elements_ = 0;  // read from accessors without bufferView, all reads
  uint64_t visits_ = 0;
  uint64_t skipped_primitives_ = 0;  // points and lines
  std::set<int> skipped_modes_;
  uint64_t leftover_primitives_ = 0;  // index counts not a multiple of 3
};

}  // namespace clpt::gltf
