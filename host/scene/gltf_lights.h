// KHR_lights_punctual for the glTF loader: the model's light definitions (point, spot,
// directional), validated once, and the nodes that place them. Only the glTF loader
// (host/scene/gltf/) uses this; like the loader, it treats everything in the file as
// untrusted and reports problems through the loader's fail(), which throws Error(BadInput)
// naming the file.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace tinygltf {
class Model;
}

namespace clpt {

class GltfLights {
 public:
  using Fail = std::function<void(const std::string&)>;  // must throw

  // Parses and validates model.extensions.KHR_lights_punctual.lights: type point, spot or
  // directional; color three finite numbers >= 0 (default 1, 1, 1); intensity a finite
  // number >= 0 (default 1); range > 0 when given; spot cone angles 0 <= inner < outer <= pi/2
  // (defaults 0 and pi/4).
  GltfLights(const tinygltf::Model& model, Fail fail);

  // The light node `node` refers to through its KHR_lights_punctual extension, or -1.
  // The index is checked against the lights array.
  int node_light(int node) const;

  // Light `index` placed by the world transform of `node`: position = the transform's
  // translation, direction = its -Z axis (normalised). Returns false (and leaves *out alone)
  // when the transform squashes -Z to nothing.
  bool place(int index, const glm::dmat4& world, PunctualLight* out) const;

  size_t size() const { return lights_.size(); }

 private:
  const tinygltf::Model& model_;
  Fail fail_;
  std::vector<PunctualLight> lights_;  // definitions, not yet placed
};

}  // namespace clpt
