// Key: a 64-bit variable identifier. Plain integers work (pose-graph vertex ids);
// symbol() packs a character and an index, GTSAM-style, for readable mixed problems:
// symbol('x', 3) for pose 3, symbol('l', 7) for landmark 7.
#pragma once

#include <cstdint>
#include <string>

namespace slamkit {

using Key = std::uint64_t;

constexpr int kSymbolIndexBits = 56;
constexpr Key kSymbolIndexMask = (Key{1} << kSymbolIndexBits) - 1;

constexpr Key symbol(char c, std::uint64_t index) {
  return (static_cast<Key>(static_cast<unsigned char>(c)) << kSymbolIndexBits) | (index & kSymbolIndexMask);
}
constexpr char symbol_char(Key k) { return static_cast<char>(k >> kSymbolIndexBits); }
constexpr std::uint64_t symbol_index(Key k) { return k & kSymbolIndexMask; }

/// "x3" for symbol keys, the plain number otherwise.
inline std::string key_to_string(Key k) {
  const char c = symbol_char(k);
  if (c >= 'A' && c <= 'z') return std::string(1, c) + std::to_string(symbol_index(k));
  return std::to_string(k);
}

}  // namespace slamkit
