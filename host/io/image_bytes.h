// Encoded image files as bytes, before any decoder sees them: the format by its signature,
// the size its header gives, and the checks and clean-ups that keep a hostile file away from
// the decoders' weak spots (OpenImageIO 2.4 leaks when libpng longjmps out of a truncated PNG,
// and crashes on a damaged JPEG ICC profile: both found by tests/fuzz/file_fuzzer.cpp).
// Used by the texture decoder (scene/image_decode) and the image reader (io/image_io).
#pragma once

#include <cstddef>
#include <cstdint>
#include <istream>
#include <string>
#include <vector>

namespace clpt {

enum class ImageFormat { Unknown, Png, Jpeg, Webp, Ktx2, Exr, Hdr };

// The format by its first bytes (not by a name or media type).
ImageFormat sniff_image(const unsigned char* data, size_t size);
// The format's short name ("png", "jpeg", "webp", "openexr", "hdr") for messages, or
// nullptr (Unknown, Ktx2).
const char* image_format_name(ImageFormat format);

// The width and height a PNG (IHDR), JPEG (the first SOF) or WebP (VP8, VP8L or VP8X) header
// gives, read from the header bytes alone without decoding. False when the bytes are none of
// these or the header is cut off.
bool image_header_size(const unsigned char* data, size_t size, uint64_t* width, uint64_t* height);

// Empty when a width x height image is within max_dimension per side and max_pixels in all;
// else the one message every reader gives ("the image is WxH, larger than the limit of ...
// (RAISE)"), `raise` saying how to raise the limits.
std::string image_size_refusal(uint64_t width, uint64_t height, uint64_t max_dimension, uint64_t max_pixels,
                               const std::string& raise);

// A PNG's chunk structure (after its signature): every chunk within the data, with a correct
// CRC-32, IHDR first, IEND present. False with a reason naming the chunk otherwise.
bool check_png_chunks(const unsigned char* data, size_t size, std::string* why);

// An OpenEXR file's headers (one, or a multi-part file's several): every attribute's name,
// type and size within the file. OpenEXR 3.1 allocates an attribute's declared size before
// reading it: a 190-byte file asked for 1.9 GB (found by tests/fuzz/file_fuzzer.cpp). False
// with a reason naming the attribute otherwise.
// `largest` gets the widest and tallest data window and the most channels of any part, which
// the caller checks against its limits before OpenEXR sizes its buffers by them (a 574-byte
// file whose window was 1 048 577 pixels wide asked for 403 MB).
struct ExrExtent {
  uint64_t width = 0, height = 0, channels = 0;
};
bool check_exr_headers(std::istream& in, uint64_t file_size, std::string* why, ExrExtent* largest);

// Whether a JPEG's frame is Huffman coded (SOF0 to SOF3, SOF5 to SOF7; arithmetic: false).
bool jpeg_is_huffman(const unsigned char* data, size_t size);

// The bytes without their embedded ICC profiles (JPEG APP2 "ICC_PROFILE" segments, PNG iCCP
// chunks; other formats are returned as they are). clpt manages no colour, and OpenImageIO
// 2.4 parses these profiles without checking their offsets. False with a reason when a JPEG's
// marker segments run past the end before its scan starts (a PNG must have passed
// check_png_chunks).
bool without_icc_profiles(const unsigned char* data, size_t size, ImageFormat format,
                          std::vector<unsigned char>* out, std::string* why);

}  // namespace clpt
