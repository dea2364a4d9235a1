#include "render/camera_setup.h"

#include <algorithm>
#include <cmath>

#include "io/image.h"
#include "util/error.h"

namespace clpt {

Camera choose_camera(const Scene& scene, const std::string& spec) {
  if (spec.empty()) return scene.cameras.empty() ? default_camera(scene.bounds()) : scene.cameras[0];
  if (spec.find_first_not_of("0123456789") == std::string::npos) {
    // An index of more digits than any count can need is out of range, not an overflow.
    const bool small = spec.size() <= 9;
    const size_t i = small ? size_t(std::stoul(spec)) : size_t(-1);
    if (small && i < scene.cameras.size()) return scene.cameras[i];
    throw Error(ExitCode::Usage, "--camera " + spec + ": the scene has " +
                                     std::to_string(scene.cameras.size()) + " camera(s)");
  }
  for (const Camera& c : scene.cameras)
    if (c.name == spec) return c;
  std::string names;
  for (const Camera& c : scene.cameras) names += (names.empty() ? "" : ", ") + ("'" + c.name + "'");
  throw Error(ExitCode::Usage, "--camera " + spec + ": no camera of that name (cameras: " +
                                   (names.empty() ? "none" : names) + ")");
}

void default_resolution(const Camera& camera, uint32_t* width, uint32_t* height) {
  float aspect = camera.aspect;
  if (camera.type == Camera::Type::Orthographic && camera.ymag > 0.0f)
    aspect = camera.xmag / camera.ymag;
  if (!(aspect > 0.0f) || !std::isfinite(aspect)) aspect = 4.0f / 3.0f;
  // 640 wide: an extreme aspect ratio asks for an image no film holds (0.001: 640 x 640 000,
  // which used to fail as a device error, exit 3). The scene's problem: exit 2, with what to do.
  const double h = std::round(640.0 / double(aspect));
  if (h > double(kMaxFilmSide))
    throw Error(ExitCode::BadInput, "camera '" + camera.name + "' has aspect ratio " +
                                        std::to_string(aspect) + ": its default image, 640x" +
                                        std::to_string(uint64_t(std::min(h, 1e18))) +
                                        ", is taller than " + std::to_string(kMaxFilmSide) +
                                        " pixels (give --resolution)");
  *width = 640;
  *height = std::max<uint32_t>(1, static_cast<uint32_t>(h));
}

dev::CameraData camera_data(const Camera& camera, uint32_t width, uint32_t height) {
  dev::CameraData c{};
  const glm::mat4& m = camera.camera_to_world;
  const glm::vec3 origin(m[3]);
  const glm::vec3 x = glm::normalize(glm::vec3(m[0]));
  const glm::vec3 y = glm::normalize(glm::vec3(m[1]));
  const glm::vec3 forward = -glm::normalize(glm::vec3(m[2]));
  const float aspect = float(width) / float(height);
  glm::vec3 right, up;
  if (camera.type == Camera::Type::Orthographic) {
    c.type = dev::CAMERA_ORTHOGRAPHIC;
    up = y * camera.ymag;
    right = x * (camera.ymag * aspect);
  } else {
    c.type = dev::CAMERA_PERSPECTIVE;
    const float t = std::tan(0.5f * camera.yfov);
    up = y * t;
    right = x * (t * aspect);
  }
  for (int i = 0; i < 3; ++i) {
    c.origin[i] = origin[i];
    c.right[i] = right[i];
    c.up[i] = up[i];
    c.forward[i] = forward[i];
  }
  return c;
}

void set_thin_lens(dev::CameraData& camera, float aperture, float focus_distance,
                   const Bounds& bounds) {
  camera.lens_radius = aperture;
  if (!(focus_distance > 0.0f) && !bounds.empty()) {
    const glm::vec3 origin(camera.origin[0], camera.origin[1], camera.origin[2]);
    const glm::vec3 forward(camera.forward[0], camera.forward[1], camera.forward[2]);
    focus_distance = glm::dot(bounds.center() - origin, forward);
    if (!(focus_distance > 0.0f)) focus_distance = 0.5f * glm::length(bounds.extent());
  }
  camera.focus_distance = focus_distance > 0.0f && std::isfinite(focus_distance) ? focus_distance : 1.0f;
}

float pixel_footprint(const dev::CameraData& camera, uint32_t height, const Bounds& bounds) {
  const float up = glm::length(glm::vec3(camera.up[0], camera.up[1], camera.up[2]));
  const float pixel = 2.0f * up / float(std::max<uint32_t>(height, 1));
  if (camera.type == dev::CAMERA_ORTHOGRAPHIC || bounds.empty()) return pixel;
  const glm::vec3 origin(camera.origin[0], camera.origin[1], camera.origin[2]);
  const glm::vec3 forward(camera.forward[0], camera.forward[1], camera.forward[2]);
  float depth = glm::dot(bounds.center() - origin, forward);
  if (!(depth > 0.0f)) depth = 0.5f * glm::length(bounds.extent());
  return pixel * depth;
}

}  // namespace clpt
