// Image files through the format libraries (io/*_codec: OpenEXR, libpng, libjpeg-turbo,
// libwebp, and clpt's own Radiance HDR reader). EXR: linear float RGB with metadata. PNG/JPEG: sRGB,
// 8 bits, clamped. Every write goes to a temporary file in the same folder and is renamed
// over the destination only once complete, so a failure never leaves a half-written image
// or destroys an existing one.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "io/image.h"
#include "io/view_transform.h"

namespace clpt {

// Checks the output path before any rendering: a known extension (.exr, .png, .jpg, .jpeg)
// and a folder that exists and is writable. Throws Error(Usage) or Error(Output).
void check_output_path(const std::filesystem::path& path);

// Throws Error(ExitCode::Output) naming the file when it cannot be written.
void write_image(const std::filesystem::path& path, const Image& image, const ImageMetadata& meta);

// The largest image a reader accepts, checked against the file's header before any pixel
// is read or allocated (issue 23, class 3: a 55-byte .hdr whose header claimed 8000 x 8000
// took 954 MB before it was refused). The defaults are the glTF loader's image limits.
struct ImageLimits {
  uint64_t max_dimension = 16384;          // width or height
  uint64_t max_pixels = uint64_t{1} << 26;  // width x height
  std::string raise = "--limit image-dimension=N, image-pixels=N";  // how to raise them
};

// The limits of an image compared with a film (--reference, clpt-diff, clpt.diff): no larger
// than the largest film (kMaxFilmSide per side); `raise` says why.
ImageLimits film_image_limits(const std::string& raise);

// A file's size from its header alone (nothing else is read). Throws Error(BadInput) naming
// the file when it is not a regular file, no image, an empty one or one past `limits`.
struct ImageSize {
  uint32_t width = 0, height = 0;
};
ImageSize read_image_size(const std::filesystem::path& path, const ImageLimits& limits = {});

// Reads an OpenEXR, Radiance HDR, PNG or JPEG file (told by its first bytes; other formats
// are refused) as linear float RGB (8-bit files are decoded from sRGB). PNG and JPEG pass the
// texture decoder's byte checks first (io/image_bytes.h). The header is checked against `limits` first, and the pixels are read in strips into
// memory that grows with what the file really holds, so a header that lies about the size
// costs no more than the bytes behind it. Throws Error(ExitCode::BadInput) naming the file.
Image read_image(const std::filesystem::path& path, const ImageLimits& limits = {});

// ---- Extra named layers (EXR only) ----------------------------------------------------
//
// An EXR can carry RGB layers besides the image: a layer named "variance" is stored as the
// channels "variance.R", "variance.G", "variance.B" beside "R", "G", "B". clpt's convention
// for that layer is the per-pixel variance of the MEAN estimate, i.e. the sample variance of
// one sample divided by the samples per pixel (`variance_of_mean` in stats/image_stats.h),
// so that z = |v − r| / sqrt(var_v + var_r) compares two images directly.

inline constexpr const char* kVarianceLayer = "variance";

struct NamedChannel {
  std::string name;  // layer name, e.g. kVarianceLayer; written as name.R, name.G, name.B
  Image image;       // the same size as the main image
  // The channels' suffixes: R, G, B (colours), X, Y, Z (vectors), or one (Z for depth, X
  // for an index) written from the image's first component (the reader repeats it in all
  // three).
  std::vector<std::string> channels = {"R", "G", "B"};
};

// As write_image above, plus the layers as extra float channels when the format is EXR;
// PNG and JPEG ignore them. Layer names must be non-empty, unique, without '.', and each
// layer the size of the image: Error(ExitCode::Output) naming the file otherwise. The write
// is atomic in the same way (temporary file, then rename).
void write_image(const std::filesystem::path& path, const Image& image, const ImageMetadata& meta,
                 const std::vector<NamedChannel>& aovs);
// As above; PNG and JPEG show the image through `display` (view transform and exposure;
// io/view_transform.h), an EXR stays linear.
void write_image(const std::filesystem::path& path, const Image& image, const ImageMetadata& meta,
                 const std::vector<NamedChannel>& aovs, const DisplaySettings& display);

struct ImageChannels {
  Image image;                      // RGB, as read_image returns it
  std::vector<NamedChannel> layers; // every layer L with L.R, L.G, L.B or L.X, L.Y, L.Z, or one channel L.c
  ImageMetadata meta;               // the file's int, float and string attributes

  // The layer of that name, or nullptr.
  const Image* layer(const std::string& name) const;
  const Image* variance() const { return layer(kVarianceLayer); }
  // An int attribute such as "clpt:spp", or `fallback` when the file has none.
  int int_attribute(const std::string& name, int fallback = 0) const;
};

// Reads the image (as read_image does) plus its extra layers and metadata. The main image
// is taken from the channels named R, G, B when the file has them, else from the first
// channels (a one-channel file gives grey). Limits and reading as read_image. Throws
// Error(ExitCode::BadInput) naming the file.
ImageChannels read_image_channels(const std::filesystem::path& path, const ImageLimits& limits = {});

}  // namespace clpt
