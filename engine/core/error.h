#pragma once
#include <stdexcept>
#include <string>

namespace facesr {

// Every recoverable failure in the engine is an Error whose message names the
// file or object and the problem; the CLI prints it and exits non-zero, the C
// ABI turns it into a status code plus facesr_last_error_message().
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what) : std::runtime_error(what) {}
};

inline void require(bool ok, const std::string& message) {
  if (!ok) throw Error(message);
}

}  // namespace facesr
