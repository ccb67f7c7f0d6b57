// Reads typed values off a fuzz input, front to back; past the end every read gives zeros, so a
// harness can build a whole structure from any number of bytes. Numbers favour the values that
// break decoders (NaN, infinities, signed zero, the extremes) over uniformly random bits.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>

namespace skyroute::fuzz {

class FuzzBytes {
 public:
  FuzzBytes(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}

  bool exhausted() const { return offset_ >= size_; }

  std::uint8_t byte() { return offset_ < size_ ? data_[offset_++] : 0; }
  bool flag() { return (byte() & 1) != 0; }

  // sizeof(T) bytes as they are (any bit pattern, e.g. an enum value no enumerator has).
  template <class T>
  T raw() {
    unsigned char bytes[sizeof(T)] = {};
    for (unsigned char& b : bytes) b = byte();
    T value;
    std::memcpy(&value, bytes, sizeof(T));
    return value;
  }

  double number() {
    using limits = std::numeric_limits<double>;
    switch (byte() % 16) {
      case 0: return limits::quiet_NaN();
      case 1: return limits::infinity();
      case 2: return -limits::infinity();
      case 3: return 0.0;
      case 4: return -0.0;
      case 5: return limits::max();
      case 6: return limits::lowest();
      case 7: return limits::denorm_min();
      case 8: return raw<double>();
      case 9: return static_cast<double>(raw<std::int64_t>());
      default: return raw<std::int16_t>() * 0.25;  // ordinary values: in and just out of range
    }
  }

  // Up to max_length bytes (any byte, NUL included), length first.
  std::string text(std::size_t max_length) {
    const std::size_t length = byte() % (max_length + 1);
    std::string s;
    for (std::size_t i = 0; i < length && !exhausted(); ++i) s.push_back(static_cast<char>(byte()));
    return s;
  }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t offset_ = 0;
};

}  // namespace skyroute::fuzz
