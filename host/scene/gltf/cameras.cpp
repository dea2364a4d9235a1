// The glTF loader's cameras: perspective and orthographic projections, and a rigid
// camera_to_world frame from the node's world transform.
#include <cmath>

#include "scene/gltf/gltf_internal.h"
#include "util/log.h"

namespace clpt::gltf {
namespace {

constexpr double kPi = 3.14159265358979323846;

}  // namespace

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

}  // namespace clpt::gltf
