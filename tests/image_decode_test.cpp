// ImageDecode (host/scene/image_decode.*): PNG, JPEG and WebP bytes to RGBA8, and the PNG chunk
// check in front of OpenImageIO: a valid PNG written by OpenImageIO decodes to its pixels;
// the same file truncated anywhere, or with one byte of a chunk flipped, is refused with a
// message saying which chunk (before libpng sees it: OIIO 2.4 leaks when libpng longjmps
// out of a truncated read, found by the fuzzer).
#include <gtest/gtest.h>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <unistd.h>

#include "io/image.h"
#include "io/image_io.h"
#include "scene/image_decode.h"

namespace clpt::image_decode_test {
namespace {

std::vector<unsigned char> small_png() {
  std::vector<unsigned char> bytes;
  OIIO::Filesystem::IOVecOutput out(bytes);
  auto writer = OIIO::ImageOutput::create("png");
  OIIO::ImageSpec spec(3, 2, 4, OIIO::TypeDesc::UINT8);
  OIIO::Filesystem::IOProxy* proxy = &out;
  spec.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
  // Opaque: OpenImageIO's PNG writer would unpremultiply colours under alpha < 1.
  const unsigned char pixels[3 * 2 * 4] = {255, 0,  0,  255, 0,  255, 0,   255, 0,  0,   255, 255,
                                           10,  20, 30, 255, 50, 60,  70,  255, 90, 100, 110, 255};
  EXPECT_TRUE(writer && writer->open("mem.png", spec));
  EXPECT_TRUE(writer->write_image(OIIO::TypeDesc::UINT8, pixels));
  writer->close();
  return bytes;
}

TEST(ImageDecode, PngDecodesToItsPixels) {
  const std::vector<unsigned char> png = small_png();
  ASSERT_GT(png.size(), 50u);
  DecodedImage img;
  std::string why;
  ASSERT_TRUE(decode_image(png.data(), png.size(), &img, &why)) << why;
  ASSERT_EQ(img.width, 3u);
  ASSERT_EQ(img.height, 2u);
  EXPECT_EQ(img.texels[0], 0xff0000ffu);  // red, R in the low byte
  EXPECT_EQ(img.texels[3], (255u << 24) | (30u << 16) | (20u << 8) | 10u);
  EXPECT_EQ(img.texels[5], (255u << 24) | (110u << 16) | (100u << 8) | 90u);
}

TEST(ImageDecode, TruncatedOrDamagedPngIsRefusedWithTheChunk) {
  const std::vector<unsigned char> png = small_png();
  for (size_t cut : {size_t(8), size_t(20), png.size() / 2, png.size() - 1}) {
    DecodedImage img;
    std::string why;
    EXPECT_FALSE(decode_image(png.data(), cut, &img, &why)) << "cut at " << cut;
    EXPECT_NE(why.find("truncated PNG"), std::string::npos) << why;
  }
  for (size_t at = 8; at < png.size(); at += 7) {
    std::vector<unsigned char> bad = png;
    bad[at] ^= 0x40;
    DecodedImage img;
    std::string why;
    EXPECT_FALSE(decode_image(bad.data(), bad.size(), &img, &why)) << "byte " << at << " flipped";
    EXPECT_TRUE(why.find("PNG") != std::string::npos) << why;
  }
}

// A w x h grey JPEG written by OpenImageIO (baseline, Huffman coded).
std::vector<unsigned char> grey_jpeg(int w, int h) {
  std::vector<unsigned char> bytes;
  OIIO::Filesystem::IOVecOutput out(bytes);
  auto writer = OIIO::ImageOutput::create("jpeg");
  OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::UINT8);
  OIIO::Filesystem::IOProxy* proxy = &out;
  spec.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
  const std::vector<unsigned char> pixels(size_t(w) * size_t(h) * 3, 128);
  EXPECT_TRUE(writer && writer->open("mem.jpg", spec));
  EXPECT_TRUE(writer->write_image(OIIO::TypeDesc::UINT8, pixels.data()));
  writer->close();
  return bytes;
}

// issue 23, class 7: an 8x8 JPEG whose frame header claims 16384x4096 decoded (libjpeg pads
// the missing data with grey, OpenImageIO reports success): 977 MB and a grey texture.
TEST(ImageDecode, JpegWhoseHeaderClaimsMoreThanItsBytesIsRefused) {
  std::vector<unsigned char> jpg = grey_jpeg(8, 8);
  DecodedImage img;
  std::string why;
  ASSERT_TRUE(decode_image(jpg.data(), jpg.size(), &img, &why)) << why;
  EXPECT_EQ(img.width, 8u);
  // A constant 1024x1024 JPEG, about the fewest bytes per pixel a real one has, still decodes.
  const std::vector<unsigned char> big = grey_jpeg(1024, 1024);
  ASSERT_TRUE(decode_image(big.data(), big.size(), &img, &why)) << why << " (" << big.size() << " bytes)";
  EXPECT_EQ(img.width, 1024u);
  size_t sof = 0;
  for (size_t i = 2; i + 9 < jpg.size(); ++i)
    if (jpg[i] == 0xFF && jpg[i + 1] == 0xC0) {
      sof = i;
      break;
    }
  ASSERT_GT(sof, 0u) << "no baseline frame header";
  jpg[sof + 5] = 0x10, jpg[sof + 6] = 0x00;  // height 4096
  jpg[sof + 7] = 0x40, jpg[sof + 8] = 0x00;  // width 16384
  EXPECT_FALSE(decode_image(jpg.data(), jpg.size(), &img, &why));
  EXPECT_NE(why.find("16384x4096"), std::string::npos) << why;
  EXPECT_NE(why.find("lying header"), std::string::npos) << why;
  // A header that claims only a little more than the data holds passes that bound; libjpeg
  // then pads the missing rows with grey and warns, which is refused too (the file fuzzer).
  jpg = grey_jpeg(8, 8);
  jpg[sof + 5] = 0x01, jpg[sof + 6] = 0x00;  // height 256
  EXPECT_FALSE(decode_image(jpg.data(), jpg.size(), &img, &why));
  EXPECT_NE(why.find("premature end"), std::string::npos) << why;
}


// A 5 x 3 WebP written by OpenImageIO (through a file: its WebP writer takes no I/O proxy),
// and the pixels OpenImageIO reads back from that file as RGBA8 (the reference: its writer
// is lossy even when asked for lossless, and drops an opaque alpha channel).
std::vector<unsigned char> small_webp(const unsigned char* pixels, std::vector<uint32_t>* reference) {
  char name[] = "/tmp/clpt-webp-XXXXXX";
  const int fd = ::mkstemp(name);
  EXPECT_GE(fd, 0);
  ::close(fd);
  const std::string path = std::string(name) + ".webp";
  std::rename(name, path.c_str());
  auto writer = OIIO::ImageOutput::create("webp");
  OIIO::ImageSpec spec(5, 3, 4, OIIO::TypeDesc::UINT8);
  EXPECT_TRUE(writer && writer->open(path, spec)) << OIIO::geterror();
  EXPECT_TRUE(writer->write_image(OIIO::TypeDesc::UINT8, pixels));
  writer->close();
  auto in = OIIO::ImageInput::open(path);
  EXPECT_TRUE(in);
  const int nc = in->spec().nchannels;
  std::vector<unsigned char> back(size_t(5 * 3 * nc));
  EXPECT_TRUE(in->read_image(0, 0, 0, nc, OIIO::TypeDesc::UINT8, back.data()));
  in->close();
  reference->clear();
  for (int i = 0; i < 5 * 3; ++i) {
    const unsigned char* p = &back[size_t(i * nc)];
    reference->push_back(uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 |
                         uint32_t(nc == 4 ? p[3] : 255) << 24);
  }
  std::ifstream file(path, std::ios::binary);
  std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(file)), {});
  std::remove(path.c_str());
  return bytes;
}

// EXT_texture_webp: WebP through OpenImageIO, by its RIFF signature.
TEST(ImageDecode, WebpDecodesToItsPixels) {
  unsigned char pixels[5 * 3 * 4];
  for (int i = 0; i < 5 * 3 * 4; ++i) pixels[i] = (unsigned char)((i * 37) % 256);
  for (int i = 0; i < 5 * 3; ++i) pixels[4 * i + 3] = 255;
  std::vector<uint32_t> reference;
  const std::vector<unsigned char> webp = small_webp(pixels, &reference);
  ASSERT_GT(webp.size(), 20u);
  ASSERT_EQ(std::string(webp.begin() + 8, webp.begin() + 12), "WEBP");
  DecodedImage img;
  std::string why;
  ASSERT_TRUE(decode_image(webp.data(), webp.size(), &img, &why)) << why;
  ASSERT_EQ(img.width, 5u);
  ASSERT_EQ(img.height, 3u);
  for (int i = 0; i < 5 * 3; ++i) EXPECT_EQ(img.texels[size_t(i)], reference[size_t(i)]) << "texel " << i;
  // Cut short: the RIFF size says so before libwebp reads anything.
  EXPECT_FALSE(decode_image(webp.data(), webp.size() - 3, &img, &why));
  EXPECT_NE(why.find("truncated WebP"), std::string::npos) << why;
  // Damaged bytes: refused or decoded, never a crash (run under ASan by test-sanitize.sh).
  for (size_t at = 12; at < webp.size(); ++at) {
    std::vector<unsigned char> bad = webp;
    bad[at] ^= 0x5A;
    DecodedImage out;
    std::string reason;
    if (!decode_image(bad.data(), bad.size(), &out, &reason)) {
      EXPECT_FALSE(reason.empty());
    }
  }
}

// The size from the header alone (issue 23, class 3: what the loader adds up before decoding
// any image): PNG, JPEG and each of WebP's three chunk kinds; cut-off headers answer false.
TEST(ImageDecode, HeaderSizeWithoutDecoding) {
  uint64_t w = 0, h = 0;
  const std::vector<unsigned char> png = small_png();
  ASSERT_TRUE(image_header_size(png.data(), png.size(), &w, &h));
  EXPECT_EQ(w, 3u);
  EXPECT_EQ(h, 2u);
  const std::vector<unsigned char> jpg = grey_jpeg(40, 24);
  ASSERT_TRUE(image_header_size(jpg.data(), jpg.size(), &w, &h));
  EXPECT_EQ(w, 40u);
  EXPECT_EQ(h, 24u);
  unsigned char pixels[5 * 3 * 4] = {};
  std::vector<uint32_t> reference;
  const std::vector<unsigned char> webp = small_webp(pixels, &reference);
  ASSERT_TRUE(image_header_size(webp.data(), webp.size(), &w, &h));
  EXPECT_EQ(w, 5u);
  EXPECT_EQ(h, 3u);
  // WebP's extended (VP8X: 24-bit sizes minus one) and lossless (VP8L: 14-bit) headers, by hand.
  std::vector<unsigned char> vp8x = {'R', 'I', 'F', 'F', 22, 0, 0, 0, 'W', 'E', 'B', 'P', 'V', 'P', '8', 'X',
                                     10,  0,   0,   0,   0,  0, 0, 0, 0x3F, 0x1F, 0, 0xFF, 0x3F, 0};
  ASSERT_TRUE(image_header_size(vp8x.data(), vp8x.size(), &w, &h));
  EXPECT_EQ(w, 8000u);   // 0x001F3F + 1
  EXPECT_EQ(h, 16384u);  // 0x003FFF + 1
  const uint32_t bits = (1000u - 1) | (700u - 1) << 14;
  std::vector<unsigned char> vp8l = {'R', 'I', 'F', 'F', 22, 0, 0, 0, 'W', 'E', 'B', 'P', 'V', 'P', '8', 'L',
                                     10,  0,   0,   0,   0x2F, (unsigned char)bits, (unsigned char)(bits >> 8),
                                     (unsigned char)(bits >> 16), (unsigned char)(bits >> 24), 0, 0, 0, 0, 0};
  ASSERT_TRUE(image_header_size(vp8l.data(), vp8l.size(), &w, &h));
  EXPECT_EQ(w, 1000u);
  EXPECT_EQ(h, 700u);
  // A WebP header past the per-image limit is refused before any decoder sees it.
  DecodedImage img;
  std::string why;
  EXPECT_FALSE(decode_image(vp8x.data(), vp8x.size(), &img, &why, 16384, uint64_t{1} << 26));
  EXPECT_NE(why.find("8000x16384, larger than the limit"), std::string::npos) << why;
  for (const std::vector<unsigned char>* bytes : {&png, &jpg, &webp}) {
    EXPECT_FALSE(image_header_size(bytes->data(), 12, &w, &h));
    EXPECT_FALSE(image_header_size(bytes->data() + 1, bytes->size() - 1, &w, &h));
  }
}

// An ICC profile whose 'cprt' tag is a multi-localised string (mluc) with one record whose
// offset runs 2 GiB past the profile, as an APP2 segment. OpenImageIO 2.4's JPEG reader
// parses embedded profiles when it opens a file and copies from that offset: SEGV (found by
// tests/fuzz/file_fuzzer.cpp from a mutated texture; this one was written by hand after it).
std::vector<unsigned char> damaged_icc_segment() {
  auto be32 = [](std::vector<unsigned char>& v, uint32_t x) {
    for (int k = 3; k >= 0; --k) v.push_back((unsigned char)(x >> (8 * k)));
  };
  std::vector<unsigned char> mluc = {'m', 'l', 'u', 'c', 0, 0, 0, 0};
  be32(mluc, 1), be32(mluc, 12);
  for (char c : {'e', 'n', 'U', 'S'}) mluc.push_back((unsigned char)c);
  be32(mluc, 0x100), be32(mluc, 0x7FFF0000);
  const uint32_t tag_at = 128 + 4 + 12;
  std::vector<unsigned char> icc(128, 0);
  icc[0] = (unsigned char)((tag_at + mluc.size()) >> 24), icc[1] = (unsigned char)((tag_at + mluc.size()) >> 16);
  icc[2] = (unsigned char)((tag_at + mluc.size()) >> 8), icc[3] = (unsigned char)(tag_at + mluc.size());
  icc[36] = 'a', icc[37] = 'c', icc[38] = 's', icc[39] = 'p';
  be32(icc, 1);
  for (char c : {'c', 'p', 'r', 't'}) icc.push_back((unsigned char)c);
  be32(icc, tag_at), be32(icc, uint32_t(mluc.size()));
  icc.insert(icc.end(), mluc.begin(), mluc.end());
  const std::string magic("ICC_PROFILE\0\x01\x01", 14);
  std::vector<unsigned char> seg = {0xFF, 0xE2, 0, 0};
  seg.insert(seg.end(), magic.begin(), magic.end());
  seg.insert(seg.end(), icc.begin(), icc.end());
  seg[2] = (unsigned char)((seg.size() - 2) >> 8), seg[3] = (unsigned char)(seg.size() - 2);
  return seg;
}

// Embedded ICC profiles never reach OpenImageIO: clpt manages no colour, and OpenImageIO 2.4
// trusts their offsets. A JPEG texture (and a JPEG --reference) with the damaged profile
// above decodes to its pixels; a PNG's iCCP chunk is dropped the same way.
TEST(ImageDecode, EmbeddedIccProfilesAreDroppedBeforeDecoding) {
  const std::vector<unsigned char> plain = grey_jpeg(8, 8);
  const std::vector<unsigned char> seg = damaged_icc_segment();
  std::vector<unsigned char> jpg(plain.begin(), plain.begin() + 2);
  jpg.insert(jpg.end(), seg.begin(), seg.end());
  jpg.insert(jpg.end(), plain.begin() + 2, plain.end());
  std::vector<unsigned char> clean;
  std::string why;
  ASSERT_TRUE(without_icc_profiles(jpg.data(), jpg.size(), ImageFormat::Jpeg, &clean, &why)) << why;
  EXPECT_EQ(clean, plain) << "the APP2 ICC_PROFILE segment, and only it, is removed";
  DecodedImage img;
  ASSERT_TRUE(decode_image(jpg.data(), jpg.size(), &img, &why)) << why;
  EXPECT_EQ(img.width, 8u);
  EXPECT_EQ(img.texels.size(), 64u);
  // The file reader behind --env, --reference and clpt-diff.
  char name[] = "/tmp/clpt-icc-XXXXXX";
  const int fd = ::mkstemp(name);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::write(fd, jpg.data(), jpg.size()), ssize_t(jpg.size()));
  ::close(fd);
  const Image read = read_image(name);
  std::remove(name);
  EXPECT_EQ(read.width, 8u);
  // A marker segment running past the end before the scan: refused, naming it.
  std::vector<unsigned char> cut(jpg.begin(), jpg.begin() + 2 + 40);
  EXPECT_FALSE(without_icc_profiles(cut.data(), cut.size(), ImageFormat::Jpeg, &clean, &why));
  EXPECT_NE(why.find("past the end of the data"), std::string::npos) << why;

  // PNG: an iCCP chunk (made here: libpng's writer refuses a profile this broken) after
  // IHDR is dropped, the other chunks kept, and the file decodes as before.
  const std::vector<unsigned char> plain_png = small_png();
  std::vector<unsigned char> chunk = {0, 0, 0, 0, 'i', 'C', 'C', 'P', 'x', 0, 0};
  chunk.insert(chunk.end(), seg.begin() + 18, seg.end());  // the profile, not even deflated
  const uint32_t length = uint32_t(chunk.size() - 8);
  for (int k = 0; k < 4; ++k) chunk[size_t(k)] = (unsigned char)(length >> (24 - 8 * k));
  uint32_t crc = 0xFFFFFFFFu;  // CRC-32 (ISO 3309) over type and data
  for (size_t i = 4; i < chunk.size(); ++i) {
    crc ^= chunk[i];
    for (int k = 0; k < 8; ++k) crc = (crc & 1u) ? 0xEDB88320u ^ (crc >> 1) : crc >> 1;
  }
  crc ^= 0xFFFFFFFFu;
  for (int k = 0; k < 4; ++k) chunk.push_back((unsigned char)(crc >> (24 - 8 * k)));
  std::vector<unsigned char> png(plain_png.begin(), plain_png.begin() + 8 + 25);  // signature, IHDR
  png.insert(png.end(), chunk.begin(), chunk.end());
  png.insert(png.end(), plain_png.begin() + 8 + 25, plain_png.end());
  ASSERT_TRUE(check_png_chunks(png.data(), png.size(), &why)) << why;
  const std::string as_text(png.begin(), png.end());
  ASSERT_NE(as_text.find("iCCP"), std::string::npos) << "OpenImageIO wrote no iCCP chunk";
  ASSERT_TRUE(without_icc_profiles(png.data(), png.size(), ImageFormat::Png, &clean, &why)) << why;
  EXPECT_EQ(clean, plain_png);
  ASSERT_TRUE(decode_image(png.data(), png.size(), &img, &why)) << why;
  EXPECT_EQ(img.texels[0], 0xFF0000FFu);
}

// KHR_texture_basisu's KTX2 images are named as such (no transcoder in Debian).
TEST(ImageDecode, Ktx2IsNamed) {
  const unsigned char ktx2[16] = {0xAB, 'K', 'T', 'X', ' ', '2', '0', 0xBB, 0x0D, 0x0A, 0x1A, 0x0A, 0, 0, 0, 0};
  DecodedImage img;
  std::string why;
  EXPECT_FALSE(decode_image(ktx2, sizeof ktx2, &img, &why));
  EXPECT_NE(why.find("a KTX2 (Basis Universal) image"), std::string::npos) << why;
}

}  // namespace
}  // namespace clpt::image_decode_test
