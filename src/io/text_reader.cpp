#include "slamkit/io/text_reader.h"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>

#include "slamkit/core/error.h"

namespace slamkit {

TextReader::TextReader(std::istream& in, std::string source) : TextReader(in, std::move(source), Options{}) {}

TextReader::TextReader(std::istream& in, std::string source, Options options)
    : in_(in), source_(std::move(source)), options_(std::move(options)) {}

std::unique_ptr<TextReader> TextReader::open(const std::string& path) { return open(path, Options{}); }

std::unique_ptr<TextReader> TextReader::open(const std::string& path, Options options) {
  auto file = std::make_unique<std::ifstream>(path, std::ios::binary);
  if (!*file) throw InputError(path, 0, "", std::string("cannot open file: ") + std::strerror(errno));
  std::istream& ref = *file;
  auto reader = std::unique_ptr<TextReader>(new TextReader(ref, path, std::move(options)));
  reader->owned_ = std::move(file);
  return reader;
}

bool TextReader::next_line() {
  while (std::getline(in_, line_)) {
    ++line_number_;
    if (!line_.empty() && line_.back() == '\r') line_.pop_back();
    const std::size_t first = line_.find_first_not_of(" \t");
    if (first == std::string::npos) continue;
    if (!options_.comment_prefix.empty() && line_.compare(first, options_.comment_prefix.size(), options_.comment_prefix) == 0)
      continue;
    split();
    return true;
  }
  if (in_.bad()) fail("", "read error");
  fields_.clear();
  return false;
}

void TextReader::split() {
  fields_.clear();
  const std::string_view s(line_);
  if (options_.delimiter == '\0') {
    std::size_t i = 0;
    while (i < s.size()) {
      while (i < s.size() && (s[i] == ' ' || s[i] == '\t')) ++i;
      const std::size_t start = i;
      while (i < s.size() && s[i] != ' ' && s[i] != '\t') ++i;
      if (i > start) fields_.push_back(s.substr(start, i - start));
    }
    return;
  }
  std::size_t start = 0;
  while (true) {
    const std::size_t end = s.find(options_.delimiter, start);
    std::string_view f = s.substr(start, end == std::string_view::npos ? std::string_view::npos : end - start);
    while (!f.empty() && (f.front() == ' ' || f.front() == '\t')) f.remove_prefix(1);
    while (!f.empty() && (f.back() == ' ' || f.back() == '\t')) f.remove_suffix(1);
    fields_.push_back(f);
    if (end == std::string_view::npos) break;
    start = end + 1;
  }
}

namespace {
std::string quoted(std::string_view f) {
  std::string s(f.substr(0, 40));
  if (f.size() > 40) s += "...";
  return "'" + s + "'";
}
}  // namespace

double TextReader::number(std::size_t i, std::string_view name) const {
  if (i >= fields_.size()) fail(name, "missing (line has " + std::to_string(fields_.size()) + " fields)");
  std::string_view f = fields_[i];
  if (!f.empty() && f.front() == '+') f.remove_prefix(1);
  double v = 0.0;
  const auto [ptr, ec] = std::from_chars(f.data(), f.data() + f.size(), v);
  if (ec == std::errc::result_out_of_range) fail(name, "number out of range: " + quoted(fields_[i]));
  if (ec != std::errc() || ptr != f.data() + f.size() || f.empty())
    fail(name, "not a number: " + quoted(fields_[i]));
  if (!std::isfinite(v)) fail(name, "not finite: " + quoted(fields_[i]));
  return v;
}

std::int64_t TextReader::integer(std::size_t i, std::string_view name) const {
  if (i >= fields_.size()) fail(name, "missing (line has " + std::to_string(fields_.size()) + " fields)");
  std::string_view f = fields_[i];
  if (!f.empty() && f.front() == '+') f.remove_prefix(1);
  std::int64_t v = 0;
  const auto [ptr, ec] = std::from_chars(f.data(), f.data() + f.size(), v);
  if (ec == std::errc::result_out_of_range) fail(name, "integer out of range: " + quoted(fields_[i]));
  if (ec != std::errc() || ptr != f.data() + f.size() || f.empty())
    fail(name, "not an integer: " + quoted(fields_[i]));
  return v;
}

void TextReader::expect_fields(std::size_t n, std::string_view what) const {
  if (fields_.size() != n)
    fail("", std::string(what) + " needs " + std::to_string(n) + " fields, line has " +
                 std::to_string(fields_.size()));
}

void TextReader::expect_min_fields(std::size_t n, std::string_view what) const {
  if (fields_.size() < n)
    fail("", std::string(what) + " needs at least " + std::to_string(n) + " fields, line has " +
                 std::to_string(fields_.size()));
}

void TextReader::fail(std::string_view field, const std::string& message) const {
  throw InputError(source_, line_number_, std::string(field), message);
}

}  // namespace slamkit
