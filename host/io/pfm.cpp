#include "io/pfm.h"

#include <cstring>
#include <string>
#include <vector>

#include "util/atomic_file.h"
#include "util/error.h"

namespace clpt {

void write_pfm(const std::filesystem::path& path, const Image& image) {
  static_assert(sizeof(float) == 4, "PFM holds 32-bit floats");
  std::string why;
  const bool ok = write_file_atomically(
      path,
      [&](std::ostream& out) {
        out << "PF\n" << image.width << " " << image.height << "\n-1.0\n";
        const size_t row = size_t(image.width) * 3;
        std::vector<unsigned char> bytes(row * 4);
        for (uint32_t y = image.height; y-- > 0;) {  // bottom row first
          const float* src = &image.rgb[size_t(y) * row];
          for (size_t i = 0; i < row; ++i) {
            uint32_t bits;
            std::memcpy(&bits, &src[i], 4);
            for (int b = 0; b < 4; ++b) bytes[i * 4 + size_t(b)] = static_cast<unsigned char>(bits >> (8 * b));
          }
          out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
        }
      },
      &why);
  if (!ok) throw Error(ExitCode::Output, "cannot write " + path.string() + (why.empty() ? "" : ": " + why));
}

}  // namespace clpt
