// The glTF loader's node graph: the scene to render (default scene, scenes[0] or the root
// nodes), node transforms, and the walk that places meshes, cameras and lights, with its
// cycle, depth and visit limits; then the conversion's summary warnings.
#include <cmath>

#include "scene/gltf/gltf_internal.h"
#include "util/log.h"

namespace clpt::gltf {

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
  // Cameras, lights and vertices are placed in floats: a world transform finite as a double
  // but past a float's range (a camera at x = 1e39) would place them at infinity (issue 23,
  // class 9: a black image, exit 0).
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(float(world[c][r])))
        fail("node " + std::to_string(node) + " has a world transform too large for a float (" +
             number(world[c][r]) + ")");

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

}  // namespace clpt::gltf
