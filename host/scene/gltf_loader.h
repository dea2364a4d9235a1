// glTF 2.0 (.gltf / .glb) to clpt::Scene. The only place in clpt that knows glTF.
#pragma once

#include <filesystem>

#include "scene/load_limits.h"
#include "scene/scene.h"

namespace clpt {

// Loads the default scene of a .gltf or .glb file (recognised by its first bytes, not its
// extension) into world-space triangles, materials and cameras.
//
// Throws clpt::Error(ExitCode::BadInput, message) when the file cannot be read, is malformed,
// needs an extension clpt does not support, reaches outside its folder, exceeds one of the
// limits of options.limits, or has nothing to render. The message is one line that
// names the file and the problem. Never crashes or reads out of bounds on hostile input.
//
// Textures: PNG and JPEG images are decoded (scene/image_decode.h). An image that cannot be read
// or decoded is an error, or with `lenient` a warning and a 1x1 magenta texture; so is a
// texCoord other than 0 or 1 (lenient: TEXCOORD_0).
struct LoadOptions {
  bool lenient = false;
  LoadLimits limits;  // scene/load_limits.h; --limit NAME=VALUE
};
Scene load_gltf(const std::filesystem::path& file, const LoadOptions& options = {});

}  // namespace clpt
