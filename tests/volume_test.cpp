// Volume: KHR_materials_volume absorption (kernels/material/volume.cl). A closed cube of
// index-matched glass (ior 1: no refraction, no Fresnel reflection, so every path goes
// straight through with weight 1) in front of a uniform white background, seen by an
// orthographic camera along an axis: every pixel shows attenuation_color^(d / distance) for
// the cube's thickness d. All paths are the same, so the image is exact up to float rounding.
// The same cube without the volume extension shows the background unchanged.
#include <gtest/gtest.h>

#include <cmath>

#include "render/renderer.h"
#include "support/device.h"
#include "support/scenes.h"

namespace clpt::volume_test {
namespace {

Image render_cube(bool volume) {
  Scene scene;
  Material m = test::glass_material(0.0f, 1.0f);
  m.volume = volume;
  m.attenuation_color = glm::vec3(0.5f, 0.25f, 0.8f);
  m.attenuation_distance = volume ? 2.0f : std::numeric_limits<float>::infinity();
  test::add_mesh(scene, test::grid_cube(glm::vec3(0.0f), 0.5f, 1), m);  // 1 m thick
  Camera cam;
  cam.type = Camera::Type::Orthographic;
  cam.xmag = cam.ymag = 0.25f;  // inside the cube's 1 x 1 face
  cam.camera_to_world = glm::mat4(1.0f);
  cam.camera_to_world[3] = glm::vec4(0.0f, 0.0f, 3.0f, 1.0f);
  scene.cameras.push_back(cam);
  RenderSettings s;
  s.width = s.height = 8;
  s.spp = 4;
  s.background = glm::vec3(1.0f);
  Renderer r(test::device_context(), scene, s);
  return r.render().film.mean;
}

TEST(Volume, BeerLambertThroughIndexMatchedCube) {
  const Image with = render_cube(true), without = render_cube(false);
  const double expected[3] = {std::pow(0.5, 0.5), std::pow(0.25, 0.5), std::pow(0.8, 0.5)};
  for (uint32_t i = 0; i < with.width * with.height; ++i)
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(with.rgb[i * 3 + c], expected[c], 1e-4) << "pixel " << i << " channel " << c;
      EXPECT_NEAR(without.rgb[i * 3 + c], 1.0, 1e-4) << "pixel " << i << " channel " << c;
    }
}

}  // namespace
}  // namespace clpt::volume_test
