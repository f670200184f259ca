// TextReader: the strict line tokenizer under every text parser in slamkit.
//
// Reads a stream line by line, splits each line on whitespace (or on a delimiter such as
// ',' for CSV), skips blank lines and comment lines, and parses fields strictly: a number
// must be the whole token and finite. Every failure throws InputError naming the source,
// the 1-based line and the field, e.g. "graph.g2o:17: field 'x': not a number: '1.0abc'".
// Not thread-safe; one reader per stream.
#pragma once

#include <cstdint>
#include <istream>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace slamkit {

class TextReader {
 public:
  struct Options {
    char delimiter = '\0';          ///< '\0': any run of spaces/tabs; otherwise that character
    std::string comment_prefix = "#";  ///< lines starting with it (after spaces) are skipped
  };

  TextReader(std::istream& in, std::string source);
  TextReader(std::istream& in, std::string source, Options options);

  /// Opens a file; throws InputError(path, 0, "", "cannot open ...") on failure.
  static std::unique_ptr<TextReader> open(const std::string& path);
  static std::unique_ptr<TextReader> open(const std::string& path, Options options);

  /// Advances to the next non-blank, non-comment line. False at end of input.
  bool next_line();

  const std::string& source() const { return source_; }
  int line_number() const { return line_number_; }
  const std::string& line() const { return line_; }
  std::size_t num_fields() const { return fields_.size(); }
  std::string_view field(std::size_t i) const { return fields_.at(i); }

  /// Field i as a finite double; `name` is used in the error message.
  double number(std::size_t i, std::string_view name) const;
  /// Field i as an integer (no fraction, no exponent, in range).
  std::int64_t integer(std::size_t i, std::string_view name) const;
  /// Throws unless the line has exactly n fields; `what` names the record (e.g. "EDGE_SE2").
  void expect_fields(std::size_t n, std::string_view what) const;
  /// Throws unless the line has at least n fields.
  void expect_min_fields(std::size_t n, std::string_view what) const;

  /// Throws InputError at the current line.
  [[noreturn]] void fail(std::string_view field, const std::string& message) const;

 private:
  void split();

  std::unique_ptr<std::istream> owned_;
  std::istream& in_;
  std::string source_;
  Options options_;
  std::string line_;
  std::vector<std::string_view> fields_;
  int line_number_ = 0;
};

}  // namespace slamkit
