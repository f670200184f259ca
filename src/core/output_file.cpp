#include "slamkit/core/output_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <vector>

#include "slamkit/core/error.h"

namespace slamkit {

namespace {

std::string reason(int err) { return std::strerror(err); }

/// "<path>.tmp-XXXXXX" in path's directory, created with mkstemp; returns its descriptor.
int make_temporary(const std::string& path, std::string* temp_path) {
  std::vector<char> name(path.begin(), path.end());
  const char suffix[] = ".tmp-XXXXXX";
  name.insert(name.end(), suffix, suffix + sizeof suffix);  // includes the terminating NUL
  const int fd = ::mkstemp(name.data());
  if (fd >= 0) *temp_path = name.data();
  return fd;
}

/// Mode for the new file: the old file's, or 0666 minus the process umask.
mode_t new_file_mode(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0) return st.st_mode & 07777;
  const mode_t mask = ::umask(0);
  ::umask(mask);
  return 0666 & ~mask;
}

void check_not_directory(const std::string& path, const std::string& field) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(path, 0, field, "cannot write: is a directory");
}

bool write_all(int fd, std::string_view text, int* err) {
  while (!text.empty()) {
    const ssize_t n = ::write(fd, text.data(), text.size());
    if (n < 0) {
      if (errno == EINTR) continue;
      *err = errno;
      return false;
    }
    text.remove_prefix(static_cast<std::size_t>(n));
  }
  return true;
}

}  // namespace

void check_writable(const std::string& path, const std::string& field) {
  if (path == "-") return;
  if (path.empty()) throw InputError(path, 0, field, "cannot write: empty file name");
  check_not_directory(path, field);
  std::string temp;
  const int fd = make_temporary(path, &temp);
  if (fd < 0) throw InputError(path, 0, field, "cannot write: " + reason(errno));
  ::close(fd);
  ::unlink(temp.c_str());
}

void write_file_atomically(const std::string& path, std::string_view contents, const std::string& field) {
  if (path == "-") {
    std::cout.write(contents.data(), static_cast<std::streamsize>(contents.size()));
    std::cout.flush();
    if (!std::cout) throw InputError(path, 0, field, "error while writing to standard output");
    return;
  }
  check_not_directory(path, field);
  std::string temp;
  const int fd = make_temporary(path, &temp);
  if (fd < 0) throw InputError(path, 0, field, "cannot write: " + reason(errno));
  int err = 0;
  bool ok = ::fchmod(fd, new_file_mode(path)) == 0 || (err = errno, false);
  ok = ok && write_all(fd, contents, &err);
  ok = ok && (::fsync(fd) == 0 || (err = errno, false));
  if (::close(fd) != 0 && ok) ok = false, err = errno;
  ok = ok && (::rename(temp.c_str(), path.c_str()) == 0 || (err = errno, false));
  if (!ok) {
    ::unlink(temp.c_str());
    throw InputError(path, 0, field, "error while writing (previous file kept): " + reason(err));
  }
}

}  // namespace slamkit
