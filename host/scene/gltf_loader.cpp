// glTF 2.0 loader: .gltf / .glb -> clpt::Scene (world-space triangles, materials, cameras).
// This file is the top-level load_gltf flow; each step lives in host/scene/gltf/, one job a
// file (the list is in scene/gltf/gltf_internal.h).
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
// URI policy: data: URIs and relative paths that stay inside the scene's folder; the policy
// and its checks are in scene/gltf/uri.cpp.
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
#include <cstdint>
#include <exception>
#include <new>
#include <string>
#include <system_error>
#include <tuple>
#include <vector>

#include <nlohmann/json.hpp>

#include "scene/gltf/gltf_internal.h"
#include "util/error.h"
#include "util/log.h"

namespace clpt {

Scene load_gltf(const std::filesystem::path& file, const LoadOptions& options) {
  using namespace gltf;  // the loader's parts: scene/gltf/gltf_internal.h
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

    nlohmann::json doc = parse_json(json_text, json_size, binary, fail);

    // Extensions: refuse unsupported required ones before anything else looks at the data.
    const std::vector<std::string> unsupported_used = check_extensions(doc, fail);
    check_indices(doc, fail);

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
    std::string rewritten_json;
    if (adapt_compressed_for_tinygltf(doc)) {
      rewritten_json = doc.dump();
      if (binary) {
        bytes = replace_glb_json(bytes, rewritten_json);
        json_text = reinterpret_cast<const char*>(bytes.data() + 20);
      } else {
        json_text = rewritten_json.data();
        json_size = rewritten_json.size();
      }
    }
    check_uris(doc, binary, ctx, images, fail);

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

    Scene scene = Converter(model, display, images, options.limits, ctx.bytes_read).convert();
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
