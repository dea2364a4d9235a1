#include "scene/gltf_lights.h"

#include <tiny_gltf.h>

#include <cmath>
#include <sstream>

namespace clpt {
namespace {

constexpr double kHalfPi = 1.57079632679489661923;

std::string number(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

const tinygltf::Value* find_extension(const tinygltf::ExtensionMap& ext, const char* name) {
  auto it = ext.find(name);
  return it == ext.end() ? nullptr : &it->second;
}

}  // namespace

GltfLights::GltfLights(const tinygltf::Model& model, Fail fail) : model_(model), fail_(std::move(fail)) {
  const tinygltf::Value* ext = find_extension(model.extensions, "KHR_lights_punctual");
  if (!ext) return;
  if (!ext->IsObject()) fail_("extension KHR_lights_punctual is not an object");
  if (!ext->Has("lights")) return;
  const tinygltf::Value& lights = ext->Get("lights");
  if (!lights.IsArray()) fail_("KHR_lights_punctual.lights is not an array");
  for (size_t i = 0; i < lights.ArrayLen(); ++i) {
    const std::string where = "KHR_lights_punctual light " + std::to_string(i);
    const tinygltf::Value& l = lights.Get(int(i));
    if (!l.IsObject()) fail_(where + " is not an object");
    PunctualLight light;
    if (l.Has("name") && l.Get("name").IsString()) light.name = l.Get("name").Get<std::string>();

    if (!l.Has("type") || !l.Get("type").IsString()) fail_(where + " has no type (point, spot or directional)");
    const std::string type = l.Get("type").Get<std::string>();
    if (type == "point") light.type = PunctualLight::Type::Point;
    else if (type == "spot") light.type = PunctualLight::Type::Spot;
    else if (type == "directional") light.type = PunctualLight::Type::Directional;
    else fail_(where + " has type '" + type + "', expected point, spot or directional");

    auto finite_number = [&](const tinygltf::Value& v, const std::string& what) {
      if (!v.IsNumber()) fail_(where + ": " + what + " is not a number");
      const double d = v.GetNumberAsDouble();
      if (!std::isfinite(d) || !std::isfinite(float(d))) fail_(where + ": " + what + " is not finite");
      return d;
    };
    if (l.Has("color")) {
      const tinygltf::Value& c = l.Get("color");
      if (!c.IsArray() || c.ArrayLen() != 3) fail_(where + " has a color that is not an array of 3 numbers");
      for (int k = 0; k < 3; ++k) {
        const double v = finite_number(c.Get(k), "color");
        if (v < 0.0) fail_(where + " has a negative color component " + number(v));
        light.color[k] = float(v);
      }
    }
    if (l.Has("intensity")) {
      const double v = finite_number(l.Get("intensity"), "intensity");
      if (v < 0.0) fail_(where + " has a negative intensity " + number(v));
      light.intensity = float(v);
    }
    // The kernels take color x intensity: each may fit a float while the product does not
    // (issue 23, class 9: samples were then dropped without a word).
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite(float(double(light.color[k]) * double(light.intensity))))
        fail_(where + ": color x intensity (" + number(double(light.color[k]) * light.intensity) +
              ") is too large for a float");
    if (l.Has("range")) {
      const double v = finite_number(l.Get("range"), "range");
      if (!(v > 0.0)) fail_(where + " has range " + number(v) + ", which is not positive");
      light.range = float(v);  // a culling hint in glTF; clpt keeps the physical 1/d^2 falloff
    }
    if (light.type == PunctualLight::Type::Spot) {
      // tinygltf has already refused a spot light without a "spot" object; an empty one
      // arrives here as a null Value: the defaults.
      double inner = 0.0, outer = kHalfPi / 2.0;
      if (l.Has("spot") && l.Get("spot").IsObject()) {
        const tinygltf::Value& s = l.Get("spot");
        if (s.Has("innerConeAngle")) inner = finite_number(s.Get("innerConeAngle"), "innerConeAngle");
        if (s.Has("outerConeAngle")) outer = finite_number(s.Get("outerConeAngle"), "outerConeAngle");
      }
      if (!(inner >= 0.0 && inner < outer && outer <= kHalfPi))
        fail_(where + " has cone angles inner " + number(inner) + " and outer " + number(outer) +
              ", which do not satisfy 0 <= inner < outer <= pi/2");
      light.inner_cone = float(inner);
      light.outer_cone = float(outer);
    }
    lights_.push_back(light);
  }
}

int GltfLights::node_light(int node) const {
  const tinygltf::Node& n = model_.nodes[size_t(node)];
  const tinygltf::Value* ext = find_extension(n.extensions, "KHR_lights_punctual");
  if (!ext) return -1;
  const std::string where = "node " + std::to_string(node);
  if (!ext->IsObject() || !ext->Has("light"))
    fail_(where + " has a KHR_lights_punctual extension without a light index");
  const tinygltf::Value& v = ext->Get("light");
  if (!v.IsInt() && !(v.IsNumber() && v.GetNumberAsDouble() == std::floor(v.GetNumberAsDouble())))
    fail_(where + " refers to a light that is not an integer index");
  const double index = v.GetNumberAsDouble();
  if (!(index >= 0.0 && index < double(lights_.size())))
    fail_(where + " refers to light " + number(index) + ", which does not exist (the file has " +
          std::to_string(lights_.size()) + ")");
  return int(index);
}

bool GltfLights::place(int index, const glm::dmat4& world, PunctualLight* out) const {
  PunctualLight light = lights_[size_t(index)];
  const glm::dvec3 z(world[2]);
  const double len = glm::length(z);
  if (!std::isfinite(len) || len < 1e-12) return false;
  light.direction = glm::vec3(-z / len);
  light.position = glm::vec3(glm::dvec3(world[3]));
  *out = light;
  return true;
}

}  // namespace clpt
