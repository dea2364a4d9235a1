#include "io/jpeg_codec.h"

#include <algorithm>
#include <csetjmp>
#include <cstdio>
#include <memory>
#include <vector>

// jpeglib.h needs size_t and FILE declared first.
#include <jpeglib.h>

namespace clpt {

namespace {

struct JpegErrors {
  jpeg_error_mgr mgr;  // first: libjpeg hands back a pointer to it
  jmp_buf jump;
  char message[JMSG_LENGTH_MAX] = {};
  bool warned = false;
};

[[noreturn]] void on_error(j_common_ptr cinfo) {
  auto* e = reinterpret_cast<JpegErrors*>(cinfo->err);
  (*cinfo->err->format_message)(cinfo, e->message);
  longjmp(e->jump, 1);
}

// Level -1 is a warning (corrupt data that libjpeg patches up); 0 and above are traces.
void on_message(j_common_ptr cinfo, int level) {
  auto* e = reinterpret_cast<JpegErrors*>(cinfo->err);
  if (level >= 0 || e->warned) return;
  (*cinfo->err->format_message)(cinfo, e->message);
  e->warned = true;
}

struct JpegHeader {
  uint32_t width, height;
  int components;
  bool cmyk;
};

bool read_header(jpeg_decompress_struct* cinfo, JpegErrors* e, const unsigned char* data, size_t size,
                 JpegHeader* h) {
  if (setjmp(e->jump)) return false;
  jpeg_mem_src(cinfo, data, static_cast<unsigned long>(size));
  jpeg_read_header(cinfo, TRUE);
  h->width = cinfo->image_width;
  h->height = cinfo->image_height;
  h->components = cinfo->num_components;
  h->cmyk = cinfo->jpeg_color_space == JCS_CMYK || cinfo->jpeg_color_space == JCS_YCCK;
  return true;
}

bool start(jpeg_decompress_struct* cinfo, JpegErrors* e, bool grey) {
  if (setjmp(e->jump)) return false;
  cinfo->out_color_space = grey ? JCS_GRAYSCALE : JCS_RGB;
  jpeg_start_decompress(cinfo);
  return true;
}

// Reads n rows; false where libjpeg failed or stopped giving rows.
bool read_rows(jpeg_decompress_struct* cinfo, JpegErrors* e, unsigned char** rows, uint32_t n) {
  if (setjmp(e->jump)) return false;
  uint32_t done = 0;
  while (done < n) {
    const JDIMENSION got = jpeg_read_scanlines(cinfo, rows + done, n - done);
    if (got == 0) {
      std::snprintf(e->message, sizeof e->message, "no more rows in the data");
      return false;
    }
    done += got;
  }
  return true;
}

struct Decompress {
  jpeg_decompress_struct cinfo{};
  JpegErrors errors;
  bool created = false;
  ~Decompress() {
    if (created) jpeg_destroy_decompress(&cinfo);
  }
};

bool create(Decompress* d) {
  if (setjmp(d->errors.jump)) return false;
  jpeg_create_decompress(&d->cinfo);
  d->created = true;
  return true;
}

}  // namespace

bool decode_jpeg(const unsigned char* data, size_t size, const SizeCheck& check, Raster* out, DecodeFailure* fail) {
  auto d = std::make_unique<Decompress>();
  d->cinfo.err = jpeg_std_error(&d->errors.mgr);
  d->errors.mgr.error_exit = on_error;
  d->errors.mgr.emit_message = on_message;
  const auto libjpeg = [&] { return std::string("JPEG error: ") + d->errors.message; };
  if (!create(d.get())) return fail->set(libjpeg(), -1);
  JpegHeader h{};
  if (!read_header(&d->cinfo, &d->errors, data, size, &h)) return fail->set(libjpeg(), -1);
  if (h.width == 0 || h.height == 0) return fail->set("the JPEG header gives a size of 0", -1);
  if (h.cmyk) return fail->set("a CMYK JPEG, which clpt does not read (give the image as RGB)", -1);
  if (std::string why = check(h.width, h.height); !why.empty()) return fail->set(why, -1);
  if (!start(&d->cinfo, &d->errors, h.components == 1)) return fail->set(libjpeg(), -1);
  out->width = d->cinfo.output_width;
  out->height = d->cinfo.output_height;
  out->channels = uint32_t(d->cinfo.output_components);
  out->type = SampleType::U8;
  if (out->width != h.width || out->height != h.height || (out->channels != 1 && out->channels != 3))
    return fail->set("unexpected JPEG layout after decoding", -1);
  const size_t row = out->row_bytes();
  std::vector<unsigned char*> rows;
  out->bytes.clear();
  for (uint32_t y = 0; y < out->height; y += kDecodeStripRows) {
    const uint32_t n = std::min(kDecodeStripRows, out->height - y);
    out->bytes.resize(size_t(y + n) * row);
    rows.resize(n);
    for (uint32_t k = 0; k < n; ++k) rows[k] = out->bytes.data() + size_t(y + k) * row;
    if (!read_rows(&d->cinfo, &d->errors, rows.data(), n) || d->errors.warned) return fail->set(libjpeg(), y);
  }
  return true;
}

namespace {

struct Compress {
  jpeg_compress_struct cinfo{};
  JpegErrors errors;
  bool created = false;
  FILE* file = nullptr;
  ~Compress() {
    if (created) jpeg_destroy_compress(&cinfo);
    if (file) std::fclose(file);
  }
};

bool compress_all(Compress* c, uint32_t w, uint32_t h, int quality, unsigned char** rows) {
  if (setjmp(c->errors.jump)) return false;
  jpeg_create_compress(&c->cinfo);
  c->created = true;
  jpeg_stdio_dest(&c->cinfo, c->file);
  c->cinfo.image_width = w;
  c->cinfo.image_height = h;
  c->cinfo.input_components = 3;
  c->cinfo.in_color_space = JCS_RGB;
  jpeg_set_defaults(&c->cinfo);
  jpeg_set_quality(&c->cinfo, quality, TRUE);
  jpeg_start_compress(&c->cinfo, TRUE);
  while (c->cinfo.next_scanline < h) jpeg_write_scanlines(&c->cinfo, rows + c->cinfo.next_scanline, h - c->cinfo.next_scanline);
  jpeg_finish_compress(&c->cinfo);
  return true;
}

}  // namespace

bool write_jpeg(const std::filesystem::path& file, uint32_t width, uint32_t height, const unsigned char* rgb,
                int quality, std::string* why) {
  auto c = std::make_unique<Compress>();
  c->cinfo.err = jpeg_std_error(&c->errors.mgr);
  c->errors.mgr.error_exit = on_error;
  c->errors.mgr.emit_message = on_message;
  c->file = std::fopen(file.c_str(), "wb");
  if (!c->file) {
    *why = "cannot create the file";
    return false;
  }
  std::vector<unsigned char*> rows(height);
  for (uint32_t y = 0; y < height; ++y) rows[y] = const_cast<unsigned char*>(rgb) + size_t(y) * width * 3;
  if (!compress_all(c.get(), width, height, quality, rows.data())) {
    *why = std::string("JPEG error: ") + c->errors.message;
    return false;
  }
  const bool ok = std::fflush(c->file) == 0 && !std::ferror(c->file);
  const int closed = std::fclose(c->file);
  c->file = nullptr;
  if (!ok || closed != 0) {
    *why = "cannot write the file (disk full?)";
    return false;
  }
  return true;
}

}  // namespace clpt
