#include "core/binary_io.h"

#include <filesystem>
#include <fstream>
#include <iterator>

namespace facesr {

std::vector<uint8_t> read_file_bytes(const std::string& path) {
  std::error_code ec;
  require(!std::filesystem::is_directory(path, ec), "cannot read '" + path + "': it is a folder, not a file");
  std::ifstream in(path, std::ios::binary);
  require(in.good(), "cannot open '" + path + "': no such file or not readable");
  in.seekg(0, std::ios::end);
  const auto size = in.tellg();
  require(size >= 0, "cannot read '" + path + "'");
  in.seekg(0);
  std::vector<uint8_t> bytes(static_cast<size_t>(size));
  if (size > 0) in.read(reinterpret_cast<char*>(bytes.data()), size);
  require(in.good() || in.eof(), "read of '" + path + "' failed");
  return bytes;
}

}  // namespace facesr
