// Hash64: a small streaming 64-bit hash for checksums and fingerprints, identical on every machine.
//
// Word at a time: each little-endian 8-byte word goes through an xxHash64-style round (multiply,
// rotate, multiply) into one accumulator, the tail is padded and the total length mixed in, and a
// final avalanche spreads every input bit over the result. Not cryptographic: it catches corruption
// and tells scenes apart, it does not resist an adversary.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string_view>

namespace pbs {

class Hash64 {
 public:
  explicit Hash64(std::uint64_t seed = 0) : state_(seed + kPrime5) {}

  // Bytes in order; the result depends only on the concatenation of all bytes fed, not on how they
  // were split between calls.
  void bytes(const void* data, std::size_t size) {
    if (size == 0) return;  // an empty vector's data() may be null, which memcpy must not be given
    const auto* p = static_cast<const std::uint8_t*>(data);
    length_ += size;
    if (buffered_ > 0) {
      while (buffered_ < 8 && size > 0) {
        buffer_[buffered_++] = *p++;
        --size;
      }
      if (buffered_ < 8) return;
      word(load64(buffer_));
      buffered_ = 0;
    }
    for (; size >= 8; size -= 8, p += 8) word(load64(p));
    // Here the buffer is empty and fewer than 8 bytes remain (a copy GCC can see is in bounds).
    std::memcpy(buffer_, p, size);
    buffered_ = size;
  }
  void bytes(std::span<const std::uint8_t> data) { bytes(data.data(), data.size()); }

  // Fixed-width values as little-endian bytes, floating point by its exact bits.
  void u8(std::uint8_t v) { bytes(&v, 1); }
  void u32(std::uint32_t v) {
    std::uint8_t b[4];
    for (int i = 0; i < 4; ++i) b[i] = std::uint8_t(v >> (8 * i));
    bytes(b, 4);
  }
  void u64(std::uint64_t v) {
    std::uint8_t b[8];
    for (int i = 0; i < 8; ++i) b[i] = std::uint8_t(v >> (8 * i));
    bytes(b, 8);
  }
  void i32(std::int32_t v) { u32(static_cast<std::uint32_t>(v)); }
  void f32(float v) { u32(std::bit_cast<std::uint32_t>(v)); }
  void f64(double v) { u64(std::bit_cast<std::uint64_t>(v)); }
  // Length first, so that ("ab", "c") and ("a", "bc") differ.
  void string(std::string_view s) {
    u64(s.size());
    bytes(s.data(), s.size());
  }

  std::uint64_t digest() const {
    std::uint64_t h = state_;
    if (buffered_ > 0) {
      std::uint8_t tail[8] = {};
      std::memcpy(tail, buffer_, buffered_);
      h ^= round(load64(tail));
      h = std::rotl(h, 27) * kPrime1 + kPrime4;
    }
    // The length tells a zero-padded tail from real zero bytes.
    h ^= length_ * kPrime3;
    h ^= h >> 33;
    h *= kPrime2;
    h ^= h >> 29;
    h *= kPrime3;
    h ^= h >> 32;
    return h;
  }

  // The hash of one byte range in one call.
  static std::uint64_t of(const void* data, std::size_t size, std::uint64_t seed = 0) {
    Hash64 h(seed);
    h.bytes(data, size);
    return h.digest();
  }

 private:
  static constexpr std::uint64_t kPrime1 = 0x9E3779B185EBCA87ull;
  static constexpr std::uint64_t kPrime2 = 0xC2B2AE3D27D4EB4Full;
  static constexpr std::uint64_t kPrime3 = 0x165667B19E3779F9ull;
  static constexpr std::uint64_t kPrime4 = 0x85EBCA77C2B2AE63ull;
  static constexpr std::uint64_t kPrime5 = 0x27D4EB2F165667C5ull;

  static std::uint64_t load64(const std::uint8_t* p) {
    std::uint64_t v = 0;
    for (int i = 7; i >= 0; --i) v = (v << 8) | p[i];
    return v;
  }
  static std::uint64_t round(std::uint64_t w) { return std::rotl(w * kPrime2, 31) * kPrime1; }
  void word(std::uint64_t w) {
    state_ ^= round(w);
    state_ = std::rotl(state_, 27) * kPrime1 + kPrime4;
  }

  std::uint64_t state_;
  std::uint64_t length_ = 0;
  std::uint8_t buffer_[8] = {};
  std::size_t buffered_ = 0;
};

}  // namespace pbs
