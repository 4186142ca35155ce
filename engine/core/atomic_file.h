#pragma once
#include <functional>
#include <ostream>
#include <string>

namespace facesr {

// Writes a file through a temporary sibling and renames it into place, so a
// crash or an exception never leaves a half-written file under the real name.
void write_file_atomically(const std::string& path,
                           const std::function<void(std::ostream&)>& writer);

}  // namespace facesr
