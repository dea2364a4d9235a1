#include "support/thin_film.h"

#include <cstdint>

#include "cl/buffer.h"
#include "support/device.h"

namespace clpt::test {

std::vector<glm::vec4> thin_film_reflectance(const std::vector<glm::vec4>& in) {
  cl::Context& ctx = device_context();
  const uint32_t n = uint32_t(in.size());
  cl::Buffer input = cl::Buffer::from_vector(ctx, in);
  cl::Buffer output(ctx, n * sizeof(glm::vec4), CL_MEM_WRITE_ONLY, nullptr, "output");
  cl::Kernel k(test_program("kernels/thin_film_test.cl"), "thin_film_eval");
  k.args(0, input, output, n);
  k.launch(ctx, n);
  return output.read_vector<glm::vec4>(n);
}

}  // namespace clpt::test
