#pragma once
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "core/error.h"

namespace facesr {

// Little-endian byte buffer writer for the engine's versioned file formats.
class ByteWriter {
 public:
  template <class T>
  void put(const T& v) {
    static_assert(std::is_trivially_copyable<T>::value, "POD only");
    const auto* p = reinterpret_cast<const uint8_t*>(&v);
    bytes_.insert(bytes_.end(), p, p + sizeof(T));
  }
  template <class T>
  void put_array(const T* data, size_t count) {
    put<uint64_t>(count);
    const auto* p = reinterpret_cast<const uint8_t*>(data);
    bytes_.insert(bytes_.end(), p, p + count * sizeof(T));
  }
  template <class T>
  void put_vector(const std::vector<T>& v) { put_array(v.data(), v.size()); }
  void put_string(const std::string& s) { put_array(s.data(), s.size()); }
  std::vector<uint8_t>& bytes() { return bytes_; }

 private:
  std::vector<uint8_t> bytes_;
};

// Bounds-checked reader: every read names the file and what was truncated.
class ByteReader {
 public:
  ByteReader(const uint8_t* data, size_t size, std::string source)
      : data_(data), size_(size), source_(std::move(source)) {}
  template <class T>
  T get(const char* what) {
    need(sizeof(T), what);
    T v;
    std::memcpy(&v, data_ + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  template <class T>
  std::vector<T> get_vector(const char* what, uint64_t max_count = (1ull << 34)) {
    const auto n = get<uint64_t>(what);
    require(n <= max_count, source_ + ": " + what + " has an implausible count " + std::to_string(n));
    require(n <= (size_ - pos_) / (sizeof(T) ? sizeof(T) : 1),
            source_ + ": truncated while reading " + what);
    std::vector<T> v(n);
    if (n) std::memcpy(v.data(), data_ + pos_, n * sizeof(T));
    pos_ += n * sizeof(T);
    return v;
  }
  std::string get_string(const char* what) {
    auto v = get_vector<char>(what, 1u << 20);
    return std::string(v.begin(), v.end());
  }
  size_t position() const { return pos_; }
  size_t remaining() const { return size_ - pos_; }
  const std::string& source() const { return source_; }

 private:
  void need(size_t n, const char* what) {
    require(size_ - pos_ >= n, source_ + ": truncated while reading " + std::string(what));
  }
  const uint8_t* data_;
  size_t size_;
  size_t pos_ = 0;
  std::string source_;
};

std::vector<uint8_t> read_file_bytes(const std::string& path);

}  // namespace facesr
