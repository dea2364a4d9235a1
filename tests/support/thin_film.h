// The thin film's reflectance (kernels/bsdf/thin_film.cl) evaluated on the test device
// through tests/kernels/thin_film_test.cl: in[i] = (cos, film ior, thickness nm, grey base
// f0), out[i] = (R, G, B, 0).
#pragma once

#include <vector>

#include <glm/glm.hpp>

namespace clpt::test {

std::vector<glm::vec4> thin_film_reflectance(const std::vector<glm::vec4>& in);

}  // namespace clpt::test
