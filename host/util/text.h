// Text for messages.
#pragma once

#include <string>

namespace clpt {

// A library's message (tinygltf, OpenImageIO, OpenEXR: often several "\n"-ended lines) as one
// line for clpt's errors: each line trimmed, empty ones dropped, the rest joined with "; ",
// each cut at 300 characters (a whole data: URI, say).
std::string one_line(const std::string& text);

}  // namespace clpt
