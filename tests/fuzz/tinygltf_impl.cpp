// tinygltf's implementation for the fuzzer only, compiled from Debian's tiny_gltf.h (2.7.0,
// the same source as libtinygltf.so) so that libFuzzer's coverage and ASan/UBSan reach into
// it. The production build links Debian's libtinygltf.so instead.
//
// Debian builds the shared library with stb_image; its headers (libstb-dev) are not a
// dependency of clpt, and the loader installs its own image callback (it keeps no pixels), so
// stb is left out here and the two default callbacks the header's inline TinyGLTF constructor
// refers to are defined as refusing stubs.
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#include <tiny_gltf.h>

namespace tinygltf {

bool LoadImageData(Image*, const int, std::string* err, std::string*, int, int,
                   const unsigned char*, int, void*) {
  if (err) *err += "gltf_fuzzer: no default image decoder\n";
  return false;
}

bool WriteImageData(const std::string*, const std::string*, const Image*, bool, std::string*,
                    void*) {
  return false;
}

}  // namespace tinygltf
