#include "core/atomic_file.h"

#include <cstdio>
#include <fstream>
#include <unistd.h>

#include "core/error.h"

namespace facesr {

void write_file_atomically(const std::string& path,
                           const std::function<void(std::ostream&)>& writer) {
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  try {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    require(out.good(), "cannot open '" + tmp + "' for writing");
    writer(out);
    out.flush();
    require(out.good(), "write to '" + tmp + "' failed (disk full?)");
    out.close();
  } catch (...) {
    std::remove(tmp.c_str());
    throw;
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw Error("cannot rename '" + tmp + "' to '" + path + "'");
  }
}

}  // namespace facesr
