// 64-bit FNV-1a hash over byte spans: the model fingerprint of a checkpoint and the seal of
// model.h5 and checkpoint.h5 (sealed_h5.hpp). Detects accidental change, not deliberate forgery.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace sphfem {

struct Fnv1a {
  std::uint64_t hash = 0xcbf29ce484222325ull;
  void add(std::span<const std::byte> bytes) {
    for (const std::byte byte : bytes) {
      hash ^= static_cast<std::uint64_t>(byte);
      hash *= 0x100000001b3ull;
    }
  }
  template <class T> void add(const std::vector<T>& v) { add(std::as_bytes(std::span(v))); }
};

} // namespace sphfem
