// The glTF loader's message text: numbers, sizes, lists, and strings from the file made into
// one printable line. clpt's errors are one line that names the file and the problem.
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <sstream>

#include "scene/gltf/gltf_internal.h"

namespace clpt::gltf {

std::string to_string_u128(u128 v) {
  if (v == 0) return "0";
  std::string s;
  while (v != 0) {
    s.push_back(char('0' + int(v % 10)));
    v /= 10;
  }
  std::reverse(s.begin(), s.end());
  return s;
}

std::string number(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

// 1536 -> "1.5 KiB": sizes in messages.
std::string bytes_text(uint64_t b) {
  const char* units[] = {"bytes", "KiB", "MiB", "GiB", "TiB"};
  double v = double(b);
  int u = 0;
  while (v >= 1024.0 && u < 4) v /= 1024.0, ++u;
  char buf[48];
  std::snprintf(buf, sizeof buf, u == 0 ? "%.0f %s" : "%.1f %s", v, units[u]);
  return buf;
}

std::string join(const std::vector<std::string>& items, const char* sep) {
  std::string out;
  for (size_t i = 0; i < items.size(); ++i) {
    if (i) out += sep;
    out += items[i];
  }
  return out;
}


std::string printable(const std::string& s) {
  // Keep messages on one line and printable whatever the file contains.
  std::string out = "'";
  for (unsigned char c : s.substr(0, 200)) {
    if (c < 0x20 || c == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", c);
      out += buf;
    } else {
      out += char(c);
    }
  }
  if (s.size() > 200) out += "...";
  return out + "'";
}

}  // namespace clpt::gltf
