#pragma once
// Minimal binary serialisation for checkpoints: little-endian host layout (the checkpoint
// header records the byte order and refuses a foreign one), plain-old-data values and vectors
// of them. Eigen fixed-size vectors are stored as their coefficients.
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "granule/core/error.hpp"

namespace granule::io {

class BinaryWriter {
 public:
  template <class T>
  void pod(const T& v) {
    const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
    bytes_.insert(bytes_.end(), p, p + sizeof(T));
  }
  template <class T>
  void vec(const std::vector<T>& v) {
    pod<std::uint64_t>(v.size());
    if (v.empty()) return;
    const auto* p = reinterpret_cast<const std::uint8_t*>(v.data());
    bytes_.insert(bytes_.end(), p, p + sizeof(T) * v.size());
  }
  void str(const std::string& s) {
    pod<std::uint64_t>(s.size());
    bytes_.insert(bytes_.end(), s.begin(), s.end());
  }
  const std::vector<std::uint8_t>& bytes() const { return bytes_; }

 private:
  std::vector<std::uint8_t> bytes_;
};

class BinaryReader {
 public:
  BinaryReader(const std::uint8_t* data, std::size_t size, std::string source)
      : data_(data), size_(size), source_(std::move(source)) {}

  template <class T>
  T pod() {
    T v;
    need(sizeof(T));
    std::memcpy(reinterpret_cast<void*>(&v), data_ + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  template <class T>
  void vec(std::vector<T>& v) {
    const auto n = pod<std::uint64_t>();
    if (n > size_ / (sizeof(T) ? sizeof(T) : 1) + 1) fail("a vector length is larger than the file");
    v.resize(n);
    if (n == 0) return;
    need(sizeof(T) * n);
    std::memcpy(reinterpret_cast<void*>(v.data()), data_ + pos_, sizeof(T) * n);
    pos_ += sizeof(T) * n;
  }
  std::string str() {
    const auto n = pod<std::uint64_t>();
    need(n);
    std::string s(reinterpret_cast<const char*>(data_ + pos_), n);
    pos_ += n;
    return s;
  }
  /// Moves past n bytes.
  void skip(std::size_t n) {
    need(n);
    pos_ += n;
  }
  std::size_t position() const { return pos_; }
  std::size_t size() const { return size_; }
  [[noreturn]] void fail(const std::string& why) const {
    throw IoError("checkpoint '" + source_ + "': " + why);
  }

 private:
  void need(std::size_t n) const {
    if (pos_ + n > size_) fail("truncated (needs " + std::to_string(pos_ + n) + " bytes, has " + std::to_string(size_) + ")");
  }
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
  std::string source_;
};

}  // namespace granule::io
