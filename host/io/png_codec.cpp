#include "io/png_codec.h"

#include <png.h>

#include <algorithm>
#include <csetjmp>
#include <cstdio>
#include <memory>

namespace clpt {

namespace {

// What libpng's callbacks share with the calls that set the jump.
struct PngState {
  jmp_buf jump;
  char message[256] = {};
  const unsigned char* data = nullptr;  // reading: the file in memory
  size_t size = 0, at = 0;
};

[[noreturn]] void on_error(png_structp png, png_const_charp msg) {
  auto* s = static_cast<PngState*>(png_get_error_ptr(png));
  std::snprintf(s->message, sizeof s->message, "%s", msg ? msg : "libpng error");
  longjmp(s->jump, 1);
}
void on_warning(png_structp, png_const_charp) {}  // benign (gamma, profiles); errors jump

void read_bytes(png_structp png, png_bytep dst, size_t n) {
  auto* s = static_cast<PngState*>(png_get_io_ptr(png));
  if (n > s->size - s->at) png_error(png, "the PNG data ends early");
  std::memcpy(dst, s->data + s->at, n);
  s->at += n;
}

struct PngHeader {
  uint32_t width, height;
  int bit_depth, passes;
};

// Each function below sets the jump first and holds only plain data: false where libpng
// jumped (the reason in state->message).
bool read_header(png_structp png, png_infop info, PngState* state, PngHeader* h) {
  if (setjmp(state->jump)) return false;
  png_read_info(png, info);
  h->width = png_get_image_width(png, info);
  h->height = png_get_image_height(png, info);
  h->bit_depth = png_get_bit_depth(png, info);
  return true;
}

bool set_transforms(png_structp png, png_infop info, PngState* state, bool keep16, PngHeader* h) {
  if (setjmp(state->jump)) return false;
  png_set_expand(png);  // palette -> RGB, grey below 8 bits -> 8, tRNS -> alpha
  if (h->bit_depth == 16) {
    if (!keep16) png_set_scale_16(png);
#if __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
    else png_set_swap(png);  // PNG stores 16-bit samples big-endian
#endif
  }
  h->passes = png_set_interlace_handling(png);
  png_read_update_info(png, info);
  return true;
}

bool read_rows(png_structp png, PngState* state, unsigned char** rows, uint32_t n) {
  if (setjmp(state->jump)) return false;
  png_read_rows(png, rows, nullptr, n);
  return true;
}

struct ReadStructs {
  png_structp png = nullptr;
  png_infop info = nullptr;
  ~ReadStructs() { png_destroy_read_struct(&png, info ? &info : nullptr, nullptr); }
};

}  // namespace

bool decode_png(const unsigned char* data, size_t size, bool keep16, const SizeCheck& check, Raster* out,
                DecodeFailure* fail) {
  auto state = std::make_unique<PngState>();
  state->data = data;
  state->size = size;
  ReadStructs s;
  s.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, state.get(), on_error, on_warning);
  if (!s.png) return fail->set("libpng could not start", -1);
  s.info = png_create_info_struct(s.png);
  if (!s.info) return fail->set("libpng could not start", -1);
  png_set_read_fn(s.png, state.get(), read_bytes);
  PngHeader h{};
  if (!read_header(s.png, s.info, state.get(), &h)) return fail->set(std::string("PNG error: ") + state->message, -1);
  if (h.width == 0 || h.height == 0) return fail->set("the PNG header gives a size of 0", -1);
  if (std::string why = check(h.width, h.height); !why.empty()) return fail->set(why, -1);
  if (!set_transforms(s.png, s.info, state.get(), keep16, &h))
    return fail->set(std::string("PNG error: ") + state->message, -1);

  out->width = h.width;
  out->height = h.height;
  out->channels = png_get_channels(s.png, s.info);
  out->type = png_get_bit_depth(s.png, s.info) == 16 ? SampleType::U16 : SampleType::U8;
  const size_t row = out->row_bytes();
  if (out->channels < 1 || out->channels > 4 || png_get_rowbytes(s.png, s.info) != row)
    return fail->set("unexpected PNG layout after expansion", -1);
  std::vector<unsigned char*> rows;
  out->bytes.clear();
  if (h.passes > 1) {  // interlaced: every pass writes into every row
    out->bytes.resize(row * h.height);
    rows.resize(h.height);
    for (uint32_t y = 0; y < h.height; ++y) rows[y] = out->bytes.data() + size_t(y) * row;
    for (int p = 0; p < h.passes; ++p)
      if (!read_rows(s.png, state.get(), rows.data(), h.height))
        return fail->set(std::string("PNG error: ") + state->message, 0);
    return true;
  }
  for (uint32_t y = 0; y < h.height; y += kDecodeStripRows) {
    const uint32_t n = std::min(kDecodeStripRows, h.height - y);
    out->bytes.resize(size_t(y + n) * row);
    rows.resize(n);
    for (uint32_t k = 0; k < n; ++k) rows[k] = out->bytes.data() + size_t(y + k) * row;
    if (!read_rows(s.png, state.get(), rows.data(), n)) return fail->set(std::string("PNG error: ") + state->message, y);
  }
  return true;
}

namespace {

bool write_all(png_structp png, png_infop info, PngState* state, uint32_t w, uint32_t h, int bits, int color_type,
               png_textp text, int n_text, unsigned char** rows) {
  if (setjmp(state->jump)) return false;
  png_set_IHDR(png, info, w, h, bits, color_type, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  if (n_text > 0) png_set_text(png, info, text, n_text);
  png_write_info(png, info);
#if __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
  if (bits == 16) png_set_swap(png);  // PNG stores 16-bit samples big-endian
#endif
  png_write_image(png, rows);
  png_write_end(png, nullptr);
  return true;
}

struct WriteStructs {
  png_structp png = nullptr;
  png_infop info = nullptr;
  FILE* file = nullptr;
  ~WriteStructs() {
    png_destroy_write_struct(&png, info ? &info : nullptr);
    if (file) std::fclose(file);
  }
};

}  // namespace

bool write_png(const std::filesystem::path& file, uint32_t width, uint32_t height, uint32_t channels, int bits,
               const void* samples, const std::vector<std::pair<std::string, std::string>>& text,
               std::string* why) {
  static constexpr int kColorTypes[4] = {PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB,
                                         PNG_COLOR_TYPE_RGB_ALPHA};
  if (channels < 1 || channels > 4 || (bits != 8 && bits != 16) || width == 0 || height == 0) {
    *why = "no PNG of " + std::to_string(width) + "x" + std::to_string(height) + ", " + std::to_string(channels) +
           " channels of " + std::to_string(bits) + " bits";
    return false;
  }
  auto state = std::make_unique<PngState>();
  WriteStructs s;
  s.file = std::fopen(file.c_str(), "wb");
  if (!s.file) {
    *why = "cannot create the file";
    return false;
  }
  s.png = png_create_write_struct(PNG_LIBPNG_VER_STRING, state.get(), on_error, on_warning);
  if (s.png) s.info = png_create_info_struct(s.png);
  if (!s.png || !s.info) {
    *why = "libpng could not start";
    return false;
  }
  png_init_io(s.png, s.file);
  std::vector<png_text> chunks(text.size());
  for (size_t i = 0; i < text.size(); ++i) {
    chunks[i].compression = PNG_TEXT_COMPRESSION_NONE;
    chunks[i].key = const_cast<char*>(text[i].first.c_str());
    chunks[i].text = const_cast<char*>(text[i].second.c_str());
    chunks[i].text_length = text[i].second.size();
  }
  std::vector<unsigned char*> rows(height);
  const size_t row = size_t(width) * channels * size_t(bits / 8);
  for (uint32_t y = 0; y < height; ++y)
    rows[y] = const_cast<unsigned char*>(static_cast<const unsigned char*>(samples)) + size_t(y) * row;
  if (!write_all(s.png, s.info, state.get(), width, height, bits, kColorTypes[channels - 1], chunks.data(),
                 int(chunks.size()), rows.data())) {
    *why = std::string("PNG error: ") + state->message;
    return false;
  }
  const bool ok = std::fflush(s.file) == 0 && !std::ferror(s.file);
  const int closed = std::fclose(s.file);
  s.file = nullptr;
  if (!ok || closed != 0) {
    *why = "cannot write the file (disk full?)";
    return false;
  }
  return true;
}

}  // namespace clpt
