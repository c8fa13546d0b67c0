// SHA-256 (FIPS 180-4), for the names that must not collide even for someone who tries: a
// kernel's key (a spec crafted so that its kernel's key matches another K's would otherwise have
// that K's later runs load its kernel) and a custom scene's type name. FNV-1a, which the
// checksums and run identities use, is no defence against a chosen collision.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

namespace cs {

class Sha256 {
 public:
  Sha256();
  Sha256& add(std::string_view bytes);
  std::array<std::uint8_t, 32> digest();  // once; the object is spent after it

 private:
  void compress(const std::uint8_t* block);
  std::array<std::uint32_t, 8> h_;
  std::array<std::uint8_t, 64> buffer_{};
  std::size_t buffered_ = 0;
  std::uint64_t bytes_ = 0;
};

// The first `hex_digits` (at most 64) hexadecimal digits of SHA-256(bytes).
std::string sha256_hex(std::string_view bytes, std::size_t hex_digits = 64);
std::string hex_of(const std::array<std::uint8_t, 32>& digest, std::size_t hex_digits = 64);

}  // namespace cs
