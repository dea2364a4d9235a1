// The glTF loader's URI sandbox and file resolution: reading files (size-capped), the URI
// policy, the check of every buffer/image URI of the document, tinygltf's file-system
// callbacks that only open files inside the scene's folder, and its image callback that keeps
// the encoded bytes for scene/image_decode.
//
// URI policy: `data:` URIs (base64, the media types tinygltf knows) and relative paths that
// stay inside the folder of the scene file (percent-encoding decoded, `..` allowed only while
// it stays inside). Absolute paths, `..` escaping the folder and any other scheme (http:,
// file:, C:, ...) are refused. The check is on the URI text: a symlink inside the folder that
// points elsewhere is followed.
#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <memory>
#include <system_error>

#include "scene/gltf/gltf_internal.h"

namespace clpt::gltf {

// Why `path` cannot be read as a file ("" when it is a regular file, or a symlink to one):
// missing, a folder, or something that is not a regular file (a FIFO or a device would block
// or never end). Errors other than "no such file" are named as the system names them.
static std::string not_a_readable_file(const fs::path& path) {
  std::error_code ec;
  fs::file_status st = fs::status(path, ec);
  if (ec || !fs::exists(st))
    return ec && ec != std::errc::no_such_file_or_directory ? ec.message() : "file not found";
  if (fs::is_directory(st)) return "is a directory, not a file";
  if (!fs::is_regular_file(st)) return "is not a regular file (a FIFO, device or socket)";
  return "";
}

// Reads a whole regular file of at most `cap` bytes. On failure returns false and a reason.
bool read_whole_file(const fs::path& path, uint64_t cap, std::vector<unsigned char>* out,
                     std::string* why) {
  *why = not_a_readable_file(path);
  if (!why->empty()) return false;
  std::error_code ec;
  uint64_t size = fs::file_size(path, ec);
  if (ec) {
    *why = "cannot get its size: " + ec.message();
    return false;
  }
  if (size > cap) {
    *why = "is " + std::to_string(size) + " bytes, more than the limit of " +
           std::to_string(cap) + " bytes";
    return false;
  }
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) {
    *why = std::string("cannot open: ") + std::strerror(errno);
    return false;
  }
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> guard(f, &std::fclose);
  out->assign(size_t(size), 0);
  size_t got = size ? std::fread(out->data(), 1, size_t(size), f) : 0;
  if (got != size || std::ferror(f)) {
    *why = std::string("cannot read: ") + (std::ferror(f) ? std::strerror(errno) : "file shrank");
    return false;
  }
  return true;
}

namespace {

int hex_value(unsigned char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

// RFC 3986 percent-decoding ('+' is a plus sign in a path).
std::string percent_decode(const std::string& s) {
  std::string out;
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '%' && i + 2 < s.size()) {
      int hi = hex_value(static_cast<unsigned char>(s[i + 1]));
      int lo = hex_value(static_cast<unsigned char>(s[i + 2]));
      if (hi >= 0 && lo >= 0) {
        out += char(hi * 16 + lo);
        i += 2;
        continue;
      }
    }
    out += s[i];
  }
  return out;
}

// What tinygltf 2.7 (dlib::urldecode) makes of a URI before it asks the file-system callbacks:
// '+' becomes a space and bad hex digits become 0. The callbacks map this back to the
// RFC 3986 decoding above, so "a+b.bin" still opens a+b.bin.
std::string tinygltf_urldecode(const std::string& s) {
  auto from_hex = [](unsigned char c) -> unsigned char {
    int v = hex_value(c);
    return v < 0 ? 0 : static_cast<unsigned char>(v);
  };
  std::string out;
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '+') {
      out += ' ';
    } else if (s[i] == '%' && s.size() > i + 2) {
      out += char((from_hex(static_cast<unsigned char>(s[i + 1])) << 4) |
                  from_hex(static_cast<unsigned char>(s[i + 2])));
      i += 2;
    } else {
      out += s[i];
    }
  }
  return out;
}

// Returns why a (decoded) external URI may not be opened, or "" when it is a relative path
// that stays inside the scene's folder.
std::string uri_problem(const std::string& uri) {
  const char* allowed = "; only relative paths inside the scene's folder and data: URIs are allowed";
  if (uri.empty()) return "is empty";
  if (uri.find('\0') != std::string::npos) return "contains a NUL character";
  size_t colon = uri.find(':');
  size_t sep = uri.find_first_of("/\\?#");
  if (colon != std::string::npos && (sep == std::string::npos || colon < sep)) {
    std::string scheme = uri.substr(0, colon);
    if (scheme == "data")
      return "is a data: URI tinygltf cannot decode (it must be base64 with a media type such "
             "as application/octet-stream, image/png or image/jpeg)";
    if (scheme.size() == 1) return "is an absolute path" + std::string(allowed);
    return "uses the URI scheme '" + scheme + ":'" + allowed;
  }
  if (uri[0] == '/' || uri[0] == '\\') return "is an absolute path" + std::string(allowed);
  long depth = 0;
  size_t start = 0;
  while (start <= uri.size()) {
    size_t end = uri.find_first_of("/\\", start);
    if (end == std::string::npos) end = uri.size();
    std::string seg = uri.substr(start, end - start);
    if (seg == "..") {
      if (--depth < 0) return "has '..' components that leave the scene's folder" + std::string(allowed);
    } else if (!seg.empty() && seg != ".") {
      ++depth;
    }
    start = end + 1;
  }
  return "";
}

// Turns the path tinygltf built (folder + "/" + decoded URI) back into a checked path inside
// the folder. Its second guess ("./" + URI, the current directory) is never allowed.
bool resolve_in_folder(FsContext& ctx, const std::string& joined, fs::path* out) {
  if (joined.size() < ctx.prefix.size() || joined.compare(0, ctx.prefix.size(), ctx.prefix) != 0)
    return false;
  std::string uri = joined.substr(ctx.prefix.size());
  if (ctx.skip.count(uri)) return false;  // tinygltf then warns and keeps the image undecoded
  auto it = ctx.rewrite.find(uri);
  if (it != ctx.rewrite.end()) uri = it->second;
  std::string why = uri_problem(uri);
  if (!why.empty()) {
    if (ctx.refusal.empty()) ctx.refusal = "external file " + printable(uri) + " " + why;
    return false;
  }
  *out = ctx.base / uri;
  return true;
}

}  // namespace

// URIs: data: or relative inside the folder. Fills ctx.rewrite and ctx.skip for the
// file-system callbacks and images.problem for images that have no usable data.
void check_uris(const nlohmann::json& doc, bool binary, FsContext& ctx, ImageSources& images, const Fail& fail) {
  auto check_array = [&](const char* key, const char* what, bool required) {
    auto it = doc.find(key);
    if (it == doc.end() || !it->is_array()) return;
    for (size_t i = 0; i < it->size(); ++i) {
      const auto& item = (*it)[i];
      if (!item.is_object()) continue;
      auto u = item.find("uri");
      if (u == item.end()) {
        if (required && !binary && !item.contains("bufferView"))
          fail(std::string(what) + " " + std::to_string(i) + " has no uri (only a .glb can embed a buffer)");
        continue;
      }
      if (!u->is_string()) fail(std::string(what) + " " + std::to_string(i) + " has a uri that is not a string");
      const std::string raw = u->get<std::string>();
      if (tinygltf::IsDataURI(raw)) continue;
      const std::string label = std::string(what) + " " + std::to_string(i) + " uri " + printable(raw);
      if (!required && raw.rfind("data:", 0) == 0) {
        // E.g. image/webp or a URI that is not base64: tinygltf would take it for a file name.
        ctx.skip.insert(tinygltf_urldecode(raw));
        images.problem[int(i)] =
            "its data: URI cannot be decoded (base64 image/png or image/jpeg are supported)";
        continue;
      }
      std::string problem = uri_problem(raw);
      const std::string decoded = percent_decode(raw);
      if (problem.empty()) problem = uri_problem(decoded);
      if (!problem.empty()) fail(label + " " + problem);
      ctx.rewrite.emplace(tinygltf_urldecode(raw), decoded);
      std::string why = not_a_readable_file(ctx.base / decoded);
      if (!why.empty()) {
        why = why == "file not found" ? "not found next to the scene file" : why;
        if (required) fail(label + ": file " + printable(decoded) + " " + why);
        images.problem[int(i)] = "file " + printable(decoded) + " " + why;
      }
    }
  };
  check_array("buffers", "buffer", true);
  check_array("images", "image", false);
}

bool fs_file_exists(const std::string& abs_filename, void* user) {
  try {
    auto& ctx = *static_cast<FsContext*>(user);
    fs::path path;
    if (!resolve_in_folder(ctx, abs_filename, &path)) return false;
    std::error_code ec;
    return fs::is_regular_file(path, ec);
  } catch (...) {
    return false;
  }
}

std::string fs_expand_file_path(const std::string& path, void*) { return path; }

bool fs_read_whole_file(std::vector<unsigned char>* out, std::string* err,
                        const std::string& filepath, void* user) {
  try {
    auto& ctx = *static_cast<FsContext*>(user);
    fs::path path;
    if (!resolve_in_folder(ctx, filepath, &path)) {
      if (err) *err += "refused to open " + filepath + "\n";
      return false;
    }
    std::string why;
    const LoadLimits& lim = *ctx.limits;
    uint64_t cap = std::min(lim.file_bytes, lim.total_bytes - std::min(lim.total_bytes, ctx.bytes_read));
    if (!read_whole_file(path, cap, out, &why)) {
      if (err) *err += why + "\n";
      return false;
    }
    ctx.bytes_read += out->size();
    return true;
  } catch (const std::exception& e) {
    if (err) *err += std::string(e.what()) + "\n";
    return false;
  }
}

bool fs_write_whole_file(std::string* err, const std::string&, const std::vector<unsigned char>&,
                         void*) {
  if (err) *err += "clpt never writes files while loading a scene\n";
  return false;
}

// tinygltf's image callback: decode nothing, keep a copy of the bytes of external and data:
// URI images. Images in a bufferView are skipped here (tinygltf does not range-check the
// pointer it passes for them); the converter reads them through its checked buffer_view().
bool keep_image_undecoded(tinygltf::Image* image, const int image_idx, std::string*, std::string*, int, int,
                          const unsigned char* bytes, int size, void* user) {
  if (!image || !user || image->bufferView >= 0 || !bytes || size <= 0) return true;
  static_cast<ImageSources*>(user)->bytes[image_idx].assign(bytes, bytes + size);
  return true;
}

}  // namespace clpt::gltf
