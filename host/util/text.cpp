#include "util/text.h"

#include <cctype>
#include <sstream>

namespace clpt {

std::string one_line(const std::string& text) {
  std::string out, line;
  std::istringstream in(text);
  while (std::getline(in, line)) {
    while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) line.pop_back();
    size_t start = 0;
    while (start < line.size() && std::isspace(static_cast<unsigned char>(line[start]))) ++start;
    if (start >= line.size()) continue;
    line = line.substr(start);
    if (line.size() > 300) line = line.substr(0, 300) + "...";
    out += (out.empty() ? "" : "; ") + line;
  }
  return out;
}

}  // namespace clpt
