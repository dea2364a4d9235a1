// Camera rays (kernels/camera/camera.cl) run on the device, and the host's thin-lens setup
// (host/render/camera_setup.cpp):
//   ThinLens.RaysMeetOnTheFocusPlane  every ray of one film point, whatever its lens sample,
//                                     passes through the point the pinhole ray reaches on the
//                                     plane in focus; origins lie on the aperture disk;
//   ThinLens.ZeroApertureIsAPinhole   lens samples change nothing without an aperture;
//   ThinLens.DefaultFocus             focus at the scene's centre along the view.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include <glm/glm.hpp>

#include "render/camera_setup.h"
#include "support/device.h"

namespace clpt::camera_test {
namespace {

const cl::Program& camera_program() {
  return test::test_program("kernels/camera_test.cl");
}

struct RaySet {
  std::vector<glm::vec4> org, dir;
};

RaySet trace_camera(const dev::CameraData& cam, const std::vector<glm::vec4>& film_lens) {
  cl::Context& ctx = test::device_context();
  const uint32_t n = uint32_t(film_lens.size());
  cl::Buffer cam_buf = cl::Buffer::from_vector(ctx, std::vector<dev::CameraData>{cam});
  cl::Buffer in = cl::Buffer::from_vector(ctx, film_lens);
  cl::Buffer org(ctx, n * sizeof(glm::vec4), CL_MEM_WRITE_ONLY, nullptr, "origins");
  cl::Buffer dir(ctx, n * sizeof(glm::vec4), CL_MEM_WRITE_ONLY, nullptr, "directions");
  cl::Kernel kernel(camera_program(), "camera_rays");
  kernel.args(0, cam_buf, in, n, org, dir);
  kernel.launch(ctx, n);
  return {org.read_vector<glm::vec4>(n), dir.read_vector<glm::vec4>(n)};
}

// A perspective camera at (1, 2, 3) looking along a tilted direction, 40 degrees vertical.
Camera tilted_camera(Camera::Type type) {
  Camera c;
  c.type = type;
  c.yfov = 0.7f;
  c.xmag = 2.0f;
  c.ymag = 1.5f;
  const glm::vec3 z = glm::normalize(glm::vec3(0.3f, 0.2f, 1.0f));  // camera +Z (looks down -Z)
  const glm::vec3 x = glm::normalize(glm::cross(glm::vec3(0, 1, 0), z));
  const glm::vec3 y = glm::cross(z, x);
  c.camera_to_world = glm::mat4(glm::vec4(x, 0), glm::vec4(y, 0), glm::vec4(z, 0), glm::vec4(1, 2, 3, 1));
  return c;
}

glm::vec3 v3(const float* f) { return {f[0], f[1], f[2]}; }

void expect_rays_meet_on_focus_plane(Camera::Type type) {
  dev::CameraData cam = camera_data(tilted_camera(type), 320, 240);
  const float radius = 0.25f, focus = 4.0f;
  set_thin_lens(cam, radius, focus, Bounds{});
  dev::CameraData pinhole = cam;
  pinhole.lens_radius = 0.0f;
  const glm::vec3 forward = v3(cam.forward), center = v3(cam.origin);

  std::mt19937 rng(7);
  std::uniform_real_distribution<float> film(-1.0f, 1.0f), lens(0.0f, 1.0f);
  const int films = 16, lenses = 256;
  std::vector<glm::vec4> in, in_pinhole;
  for (int f = 0; f < films; ++f) {
    const float fx = film(rng), fy = film(rng);
    in_pinhole.emplace_back(fx, fy, 0.5f, 0.5f);
    for (int l = 0; l < lenses; ++l) in.emplace_back(fx, fy, lens(rng), lens(rng));
  }
  const RaySet rays = trace_camera(cam, in), ref = trace_camera(pinhole, in_pinhole);
  double max_miss = 0.0, max_radius = 0.0, max_off_plane = 0.0, max_dir_len_err = 0.0;
  bool lens_moves_origin = false;
  for (int f = 0; f < films; ++f) {
    const glm::vec3 o0 = glm::vec3(ref.org[size_t(f)]), d0 = glm::vec3(ref.dir[size_t(f)]);
    // The pinhole ray's point on the plane in focus.
    const glm::vec3 target = o0 + d0 * (focus / glm::dot(d0, forward));
    for (int l = 0; l < lenses; ++l) {
      const size_t i = size_t(f * lenses + l);
      const glm::vec3 o = glm::vec3(rays.org[i]), d = glm::vec3(rays.dir[i]);
      max_dir_len_err = std::max(max_dir_len_err, double(std::fabs(glm::length(d) - 1.0f)));
      const glm::vec3 lens_offset = o - o0;
      max_radius = std::max(max_radius, double(glm::length(lens_offset)));
      max_off_plane = std::max(max_off_plane, double(std::fabs(glm::dot(lens_offset, forward))));
      lens_moves_origin = lens_moves_origin || glm::length(lens_offset) > 0.1f * radius;
      const float t = glm::dot(target - o, forward) / glm::dot(d, forward);
      max_miss = std::max(max_miss, double(glm::length(o + t * d - target)));
    }
  }
  (void)center;
  EXPECT_LT(max_miss, 2e-5 * focus) << "rays of one film point must meet on the focus plane";
  EXPECT_LE(max_radius, radius * (1.0 + 1e-5)) << "origins must lie on the aperture disk";
  EXPECT_LT(max_off_plane, 1e-5) << "the aperture disk is perpendicular to the view";
  EXPECT_LT(max_dir_len_err, 1e-5);
  EXPECT_TRUE(lens_moves_origin) << "the lens sample must move the origin";
}

TEST(ThinLens, RaysMeetOnTheFocusPlane) { expect_rays_meet_on_focus_plane(Camera::Type::Perspective); }
TEST(ThinLens, OrthographicRaysMeetOnTheFocusPlane) {
  expect_rays_meet_on_focus_plane(Camera::Type::Orthographic);
}

TEST(ThinLens, ZeroApertureIsAPinhole) {
  dev::CameraData cam = camera_data(tilted_camera(Camera::Type::Perspective), 64, 64);
  set_thin_lens(cam, 0.0f, 3.0f, Bounds{});
  const RaySet a = trace_camera(cam, {{0.3f, -0.2f, 0.5f, 0.5f}, {0.3f, -0.2f, 0.01f, 0.97f}});
  EXPECT_EQ(a.org[0], a.org[1]);
  EXPECT_EQ(a.dir[0], a.dir[1]);
}

TEST(ThinLens, DefaultFocusIsTheSceneCentreAlongTheView) {
  dev::CameraData cam = camera_data(tilted_camera(Camera::Type::Perspective), 64, 64);
  Bounds b;
  const glm::vec3 c = v3(cam.origin) + 7.0f * v3(cam.forward) + glm::vec3(0.5f, -0.25f, 0.0f) -
                      glm::dot(glm::vec3(0.5f, -0.25f, 0.0f), v3(cam.forward)) * v3(cam.forward);
  b.extend(c - glm::vec3(1.0f));
  b.extend(c + glm::vec3(1.0f));
  set_thin_lens(cam, 0.1f, 0.0f, b);
  EXPECT_NEAR(cam.focus_distance, 7.0f, 1e-4f);
  set_thin_lens(cam, 0.1f, 2.5f, b);
  EXPECT_FLOAT_EQ(cam.focus_distance, 2.5f);
}

}  // namespace
}  // namespace clpt::camera_test
