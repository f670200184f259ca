// Filesystem queries for user-given paths that answer "no" instead of throwing: a name the OS
// refuses (longer than NAME_MAX, no permission, a component that is a file) is neither a file
// nor a folder, so readers report it as missing with an InputError rather than letting a
// std::filesystem_error escape as an internal error.
#pragma once

#include <filesystem>
#include <system_error>

namespace slamkit {

inline bool path_exists(const std::filesystem::path& path) {
  std::error_code ec;
  return std::filesystem::exists(path, ec) && !ec;
}
inline bool is_file_path(const std::filesystem::path& path) {
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec) && !ec;
}
inline bool is_directory_path(const std::filesystem::path& path) {
  std::error_code ec;
  return std::filesystem::is_directory(path, ec) && !ec;
}

}  // namespace slamkit
