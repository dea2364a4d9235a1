#include "io/exr_codec.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFloatAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStdIO.h>
#include <OpenEXR/ImfStringAttribute.h>

#include <algorithm>
#include <cstdint>
#include <exception>
#include <fstream>

#include "util/text.h"

namespace clpt {

bool read_exr(const std::filesystem::path& file, const SizeCheck& check, ExrImage* out, DecodeFailure* fail) {
  int64_t row = -1;
  try {
    Imf::InputFile in(file.c_str());
    const Imf::Header& header = in.header();
    const Imath::Box2i window = header.dataWindow();
    const int64_t w = int64_t(window.max.x) - window.min.x + 1, h = int64_t(window.max.y) - window.min.y + 1;
    if (w <= 0 || h <= 0) return fail->set("empty image (the data window is " + std::to_string(w) + "x" + std::to_string(h) + ")", -1);
    if (std::string why = check(uint64_t(w), uint64_t(h)); !why.empty()) return fail->set(why, -1);
    out->channels.clear();
    for (auto c = header.channels().begin(); c != header.channels().end(); ++c) {
      if (c.channel().xSampling != 1 || c.channel().ySampling != 1)
        return fail->set("channel '" + one_line(c.name()) + "' is subsampled, which clpt does not read", -1);
      out->channels.push_back(c.name());
    }
    if (out->channels.empty()) return fail->set("the EXR has no channels", -1);
    Raster& r = out->raster;
    r.width = uint32_t(w);
    r.height = uint32_t(h);
    r.channels = uint32_t(out->channels.size());
    r.type = SampleType::F32;
    r.bytes.clear();
    const size_t x_stride = size_t(r.channels) * sizeof(float), y_stride = r.row_bytes();
    for (uint32_t y = 0; y < r.height; y += kDecodeStripRows) {
      row = y;
      const uint32_t n = std::min(kDecodeStripRows, r.height - y);
      r.bytes.resize(size_t(y + n) * y_stride);
      // OpenEXR addresses pixel (x, y) of the window at base + x x_stride + y y_stride.
      const intptr_t base = reinterpret_cast<intptr_t>(r.bytes.data()) - intptr_t(window.min.x) * intptr_t(x_stride) -
                            intptr_t(window.min.y) * intptr_t(y_stride);
      Imf::FrameBuffer fb;
      for (size_t c = 0; c < out->channels.size(); ++c)
        fb.insert(out->channels[c], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(base + intptr_t(c * sizeof(float))),
                                               x_stride, y_stride));
      in.setFrameBuffer(fb);
      in.readPixels(window.min.y + int(y), window.min.y + int(y + n) - 1);
    }
    row = -1;
    out->meta = {};
    for (auto a = header.begin(); a != header.end(); ++a) {
      if (const auto* s = dynamic_cast<const Imf::StringAttribute*>(&a.attribute()))
        out->meta.strings.emplace_back(a.name(), s->value());
      else if (const auto* i = dynamic_cast<const Imf::IntAttribute*>(&a.attribute()))
        out->meta.ints.emplace_back(a.name(), i->value());
      else if (const auto* f = dynamic_cast<const Imf::FloatAttribute*>(&a.attribute()))
        out->meta.floats.emplace_back(a.name(), f->value());
    }
    return true;
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    return fail->set("OpenEXR exception: " + one_line(e.what()), row);
  }
}

bool read_exr_size(const std::filesystem::path& file, uint64_t* width, uint64_t* height, DecodeFailure* fail) {
  try {
    Imf::InputFile in(file.c_str());
    const Imath::Box2i window = in.header().dataWindow();
    const int64_t w = int64_t(window.max.x) - window.min.x + 1, h = int64_t(window.max.y) - window.min.y + 1;
    *width = w > 0 ? uint64_t(w) : 0;
    *height = h > 0 ? uint64_t(h) : 0;
    return true;
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    return fail->set("OpenEXR exception: " + one_line(e.what()), -1);
  }
}

bool write_exr(const std::filesystem::path& file, uint32_t width, uint32_t height,
               const std::vector<std::string>& channels, const float* pixels, const ImageMetadata& meta,
               std::string* why) {
  try {
    Imf::Header header(static_cast<int>(width), static_cast<int>(height));
    header.compression() = Imf::ZIP_COMPRESSION;
    for (const std::string& c : channels) header.channels().insert(c, Imf::Channel(Imf::FLOAT));
    for (const auto& [k, v] : meta.strings) header.insert(k, Imf::StringAttribute(v));
    for (const auto& [k, v] : meta.ints) header.insert(k, Imf::IntAttribute(v));
    for (const auto& [k, v] : meta.floats) header.insert(k, Imf::FloatAttribute(v));
    const size_t x_stride = channels.size() * sizeof(float), y_stride = x_stride * width;
    Imf::FrameBuffer fb;
    for (size_t c = 0; c < channels.size(); ++c)
      fb.insert(channels[c], Imf::Slice(Imf::FLOAT, const_cast<char*>(reinterpret_cast<const char*>(pixels + c)),
                                        x_stride, y_stride));
    // Through a stream of clpt's own, whose state says whether every byte reached the file:
    // OutputFile's destructor writes the line offsets and swallows any failure.
    std::ofstream os(file, std::ios::binary | std::ios::trunc);
    if (!os) {
      *why = "cannot create the file";
      return false;
    }
    {
      Imf::StdOFStream stream(os, file.c_str());
      Imf::OutputFile out(stream, header);
      out.setFrameBuffer(fb);
      out.writePixels(int(height));
    }
    os.flush();
    if (!os) {
      *why = "cannot write the file (disk full?)";
      return false;
    }
    return true;
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    *why = "OpenEXR exception: " + one_line(e.what());
    return false;
  }
}

}  // namespace clpt
