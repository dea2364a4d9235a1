#include "io/webp_codec.h"

#include <webp/decode.h>

#include <string>

namespace clpt {

bool decode_webp(const unsigned char* data, size_t size, const SizeCheck& check, Raster* out, DecodeFailure* fail) {
  WebPBitstreamFeatures f;
  const VP8StatusCode status = WebPGetFeatures(data, size, &f);
  if (status != VP8_STATUS_OK)
    return fail->set("WebP error: the header cannot be read (status " + std::to_string(int(status)) + ")", -1);
  if (f.has_animation) return fail->set("an animated WebP, which clpt does not read", -1);
  if (f.width <= 0 || f.height <= 0) return fail->set("the WebP header gives a size of 0", -1);
  if (std::string why = check(uint64_t(f.width), uint64_t(f.height)); !why.empty()) return fail->set(why, -1);
  out->width = uint32_t(f.width);
  out->height = uint32_t(f.height);
  out->channels = f.has_alpha ? 4 : 3;
  out->type = SampleType::U8;
  out->bytes.assign(out->row_bytes() * out->height, 0);
  const int stride = int(out->row_bytes());
  const uint8_t* done = f.has_alpha ? WebPDecodeRGBAInto(data, size, out->bytes.data(), out->bytes.size(), stride)
                                    : WebPDecodeRGBInto(data, size, out->bytes.data(), out->bytes.size(), stride);
  if (!done) return fail->set("WebP error: the image data cannot be decoded", 0);
  return true;
}

}  // namespace clpt
