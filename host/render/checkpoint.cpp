#include "render/checkpoint.h"


#include <cstring>
#include <fstream>

#include "io/image.h"
#include "io/output_path.h"
#include "util/hash.h"
#include "util/atomic_file.h"
#include "util/error.h"

namespace clpt {
namespace fs = std::filesystem;

namespace {

// Format 2: the checksum covers the header too (format 1's covered only the signature and
// the sums, so a changed sample count was accepted: the image came out that many times
// darker).
constexpr char kMagic[8] = {'C', 'L', 'P', 'T', 'C', 'K', 'P', '2'};
constexpr char kMagicV1[8] = {'C', 'L', 'P', 'T', 'C', 'K', 'P', '1'};

struct Header {
  char magic[8];
  uint32_t width, height;
  uint64_t samples_per_pixel;
  uint64_t signature_bytes;
  uint64_t payload_hash;  // xxhash64 of the header (this field 0), signature and arrays
};
static_assert(sizeof(Header) == 40, "the header has no padding: every byte is hashed");

uint64_t payload_hash(const Header& header, const std::string& signature, const FilmState& s) {
  Header zeroed = header;
  zeroed.payload_hash = 0;
  uint64_t h = hash64(&zeroed, sizeof zeroed, 0);
  h = hash64(signature.data(), signature.size(), h);
  h = hash64(s.sum.data(), s.sum.size() * sizeof(float), h);
  h = hash64(s.sum_sq.data(), s.sum_sq.size() * sizeof(float), h);
  return hash64(s.ray_counts.data(), s.ray_counts.size() * sizeof(uint32_t), h);
}

}  // namespace

void write_checkpoint(const fs::path& path, const std::string& signature, const FilmState& s) {
  const size_t pixels = size_t(s.width) * s.height;
  if (s.sum.size() != pixels * 4 || s.sum_sq.size() != pixels * 4 || s.ray_counts.size() != pixels)
    throw Error(ExitCode::Output, "checkpoint " + path.string() + ": inconsistent film state");
  Header h{};
  std::memcpy(h.magic, kMagic, 8);
  h.width = s.width;
  h.height = s.height;
  h.samples_per_pixel = s.samples_per_pixel;
  h.signature_bytes = signature.size();
  h.payload_hash = payload_hash(h, signature, s);
  std::string why;
  const bool written = write_file_atomically(path, [&](std::ostream& f) {
    f.write(reinterpret_cast<const char*>(&h), sizeof h);
    f.write(signature.data(), std::streamsize(signature.size()));
    f.write(reinterpret_cast<const char*>(s.sum.data()), std::streamsize(s.sum.size() * 4));
    f.write(reinterpret_cast<const char*>(s.sum_sq.data()), std::streamsize(s.sum_sq.size() * 4));
    f.write(reinterpret_cast<const char*>(s.ray_counts.data()),
            std::streamsize(s.ray_counts.size() * 4));
  }, &why);
  if (!written)
    throw Error(ExitCode::Output,
                "cannot write checkpoint " + path.string() + (why.empty() ? "" : ": " + why));
}

FilmState read_checkpoint(const fs::path& path, const std::string& signature) {
  auto bad = [&](const std::string& why) {
    return Error(ExitCode::BadInput, "checkpoint " + path.string() + ": " + why);
  };
  check_regular_input(path, "checkpoint ");  // a FIFO would block the open
  std::ifstream f(path, std::ios::binary);
  if (!f) throw bad("cannot open the file");
  std::error_code ec;
  const uint64_t file_size = fs::file_size(path, ec);
  Header h{};
  if (ec || !f.read(reinterpret_cast<char*>(&h), sizeof h)) throw bad("not a clpt checkpoint");
  if (std::memcmp(h.magic, kMagicV1, 8) == 0)
    throw bad("written by an older clpt (checkpoint format 1, whose header is not checksummed); "
              "render again without --resume");
  if (std::memcmp(h.magic, kMagic, 8) != 0) throw bad("not a clpt checkpoint");
  const uint64_t pixels = uint64_t(h.width) * h.height;
  if (h.width == 0 || h.height == 0 || h.width > kMaxFilmSide || h.height > kMaxFilmSide ||
      h.signature_bytes > (1u << 20) ||
      file_size != sizeof h + h.signature_bytes + pixels * 4 * (4 + 4 + 1))
    throw bad("truncated or damaged (its size does not match its header)");
  std::string stored(h.signature_bytes, '\0');
  f.read(stored.data(), std::streamsize(stored.size()));
  FilmState s;
  s.width = h.width;
  s.height = h.height;
  s.samples_per_pixel = h.samples_per_pixel;
  s.sum.resize(pixels * 4);
  s.sum_sq.resize(pixels * 4);
  s.ray_counts.resize(pixels);
  f.read(reinterpret_cast<char*>(s.sum.data()), std::streamsize(s.sum.size() * 4));
  f.read(reinterpret_cast<char*>(s.sum_sq.data()), std::streamsize(s.sum_sq.size() * 4));
  f.read(reinterpret_cast<char*>(s.ray_counts.data()), std::streamsize(s.ray_counts.size() * 4));
  if (!f || payload_hash(h, stored, s) != h.payload_hash) throw bad("damaged (checksum mismatch)");
  if (stored != signature)
    throw Error(ExitCode::Usage, "checkpoint " + path.string() +
                                     " was made with other settings and cannot be resumed:\n"
                                     "  checkpoint: " + stored + "\n  this render: " + signature);
  return s;
}

}  // namespace clpt
