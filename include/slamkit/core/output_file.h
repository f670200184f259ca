// Output files: checked before the work starts, replaced atomically when it ends.
//
// A run that takes minutes must not discover at the end that it cannot write its result, and
// an interrupted or failed write must never leave half a file where a good one stood. So:
//   * check_writable(path) at start-up: the directory exists and a file can be created in it
//     (tested by creating and removing a temporary file), and path is not a directory;
//   * write_file_atomically(path, text): the text goes to a temporary file in the same
//     directory ("<path>.tmp-XXXXXX"), is flushed to disk (fsync), and is renamed over path.
//     rename(2) within one file system is atomic: readers see the old file or the new one.
//     On any failure (ENOSPC, EFBIG, EIO, ...) the temporary file is removed, path keeps its
//     previous content, and InputError(path, 0, field, reason) is thrown.
// The new file gets the mode of the file it replaces, or 0666 & ~umask for a new file.
// "-" names standard output: check_writable accepts it, write_file_atomically writes to stdout.
#pragma once

#include <string>
#include <string_view>

namespace slamkit {

/// Throws InputError(path, 0, field, ...) unless a file can be written at `path`.
void check_writable(const std::string& path, const std::string& field = "");

/// Replaces `path` by `contents` atomically (see above). Throws InputError on failure.
void write_file_atomically(const std::string& path, std::string_view contents, const std::string& field = "");

}  // namespace slamkit
