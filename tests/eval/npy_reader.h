// Test helper: reads a 1-D little-endian float64 NumPy .npy file (format 1.0/2.0), e.g. evo's
// error_array. The header is a Python dict literal; the data follow as raw doubles.
#pragma once

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

namespace slamkit::testing {

inline std::vector<double> read_npy_f8(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open " + path);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.size() < 10 || bytes.compare(0, 6, "\x93NUMPY") != 0) throw std::runtime_error(path + ": not a .npy file");
  const int major = static_cast<unsigned char>(bytes[6]);
  std::size_t header_len = 0, offset = 0;
  if (major == 1) {
    header_len = static_cast<unsigned char>(bytes[8]) | (static_cast<std::size_t>(static_cast<unsigned char>(bytes[9])) << 8);
    offset = 10;
  } else if (major == 2 || major == 3) {
    if (bytes.size() < 12) throw std::runtime_error(path + ": truncated header");
    for (int k = 3; k >= 0; --k) header_len = (header_len << 8) | static_cast<unsigned char>(bytes[8 + static_cast<std::size_t>(k)]);
    offset = 12;
  } else {
    throw std::runtime_error(path + ": unsupported .npy version");
  }
  if (bytes.size() < offset + header_len) throw std::runtime_error(path + ": truncated header");
  const std::string header = bytes.substr(offset, header_len);
  if (header.find("'descr': '<f8'") == std::string::npos || header.find("'fortran_order': False") == std::string::npos)
    throw std::runtime_error(path + ": expected a C-order little-endian float64 array, header " + header);
  const std::size_t shape = header.find("'shape': (");
  if (shape == std::string::npos) throw std::runtime_error(path + ": no shape");
  const std::size_t n = std::stoul(header.substr(shape + 10));
  const std::size_t data = offset + header_len;
  if (bytes.size() != data + 8 * n) throw std::runtime_error(path + ": size does not match shape");
  std::vector<double> v(n);
  std::memcpy(v.data(), bytes.data() + data, 8 * n);  // little-endian host assumed (x86-64, arm64)
  return v;
}

}  // namespace slamkit::testing
