#include "yaml_subset.h"

#include <string_view>

#include "slamkit/core/error.h"

namespace slamkit::yaml_subset {
namespace {

struct Line {
  int number = 0;
  int indent = 0;
  std::string text;  ///< without indentation, comment and trailing spaces
};

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

// Removes a '#' comment that starts the text or follows a space, outside quotes.
std::string strip_comment(const std::string& s) {
  char quote = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const char c = s[i];
    if (quote) {
      if (c == quote) quote = 0;
    } else if (c == '"' || c == '\'') {
      quote = c;
    } else if (c == '#' && (i == 0 || s[i - 1] == ' ' || s[i - 1] == '\t')) {
      return s.substr(0, i);
    }
  }
  return s;
}

class Parser {
 public:
  Parser(std::vector<Line> lines, std::string source) : lines_(std::move(lines)), source_(std::move(source)) {}

  Node document() {
    Node root;
    root.kind = Node::Kind::kMap;
    root.line = 1;
    if (lines_.empty()) return root;
    if (lines_[0].indent != 0) fail(lines_[0].number, "the document must start at column 1");
    root = block(0);
    if (root.kind != Node::Kind::kMap) fail(lines_[0].number, "the document must be a map of 'key: value' lines");
    if (pos_ < lines_.size()) fail(lines_[pos_].number, "unexpected indentation");
    return root;
  }

 private:
  [[noreturn]] void fail(int line, const std::string& message) const { throw InputError(source_, line, "", message); }

  static bool is_item(const std::string& t) { return t == "-" || t.rfind("- ", 0) == 0; }

  Node block(int indent) {
    const Line& first = lines_[pos_];
    Node node;
    node.line = first.number;
    if (is_item(first.text)) {
      node.kind = Node::Kind::kSequence;
      while (pos_ < lines_.size() && lines_[pos_].indent == indent && is_item(lines_[pos_].text)) {
        const Line& l = lines_[pos_++];
        const std::string rest(trim(std::string_view(l.text).substr(1)));
        if (rest.empty()) {
          if (pos_ >= lines_.size() || lines_[pos_].indent <= indent) fail(l.number, "empty sequence item");
          node.items.push_back(block(lines_[pos_].indent));
        } else {
          if (rest.find(": ") != std::string::npos || rest.back() == ':')
            fail(l.number, "maps inside sequence items are not supported");
          node.items.push_back(inline_value(rest, l.number));
        }
      }
      return node;
    }
    node.kind = Node::Kind::kMap;
    while (pos_ < lines_.size() && lines_[pos_].indent == indent) {
      const Line& l = lines_[pos_++];
      if (is_item(l.text)) fail(l.number, "a sequence item where a 'key: value' line was expected");
      std::size_t colon = l.text.find(": ");
      if (colon == std::string::npos) {
        if (l.text.back() != ':') fail(l.number, "expected 'key: value', got '" + l.text.substr(0, 40) + "'");
        colon = l.text.size() - 1;
      }
      const std::string key(trim(std::string_view(l.text).substr(0, colon)));
      const std::string rest(trim(std::string_view(l.text).substr(colon + 1)));
      if (key.empty()) fail(l.number, "empty key");
      if (node.find(key)) fail(l.number, "duplicate key '" + key + "'");
      Node value;
      if (!rest.empty()) {
        value = inline_value(rest, l.number);
      } else if (pos_ < lines_.size() && lines_[pos_].indent > indent) {
        value = block(lines_[pos_].indent);
        value.line = l.number;  // a block value is reported at its key
      } else if (pos_ < lines_.size() && lines_[pos_].indent == indent && is_item(lines_[pos_].text)) {
        value = block(indent);  // "key:\n- a\n- b" at the same indentation
        value.line = l.number;
      } else {
        value.line = l.number;  // empty scalar
      }
      node.entries.emplace_back(key, std::move(value));
    }
    if (pos_ < lines_.size() && lines_[pos_].indent > indent) fail(lines_[pos_].number, "unexpected indentation");
    return node;
  }

  Node inline_value(const std::string& text, int line) {
    std::size_t i = 0;
    Node n = flow(text, &i, line);
    while (i < text.size() && text[i] == ' ') ++i;
    if (i != text.size()) fail(line, "unexpected text after the value: '" + text.substr(i, 40) + "'");
    return n;
  }

  // A flow value starting at *i: "[a, b, [c]]", a quoted string or a plain scalar.
  Node flow(const std::string& s, std::size_t* i, int line) {
    while (*i < s.size() && s[*i] == ' ') ++*i;
    Node n;
    n.line = line;
    if (*i >= s.size()) fail(line, "missing value");
    const char c = s[*i];
    if (c == '&' || c == '*' || c == '!' || c == '{' || c == '|' || c == '>')
      fail(line, std::string("unsupported YAML syntax '") + c + "'");
    if (c == '[') {
      n.kind = Node::Kind::kSequence;
      ++*i;
      while (*i < s.size() && s[*i] == ' ') ++*i;
      if (*i < s.size() && s[*i] == ']') return ++*i, n;
      while (true) {
        n.items.push_back(flow(s, i, line));
        while (*i < s.size() && s[*i] == ' ') ++*i;
        if (*i >= s.size()) fail(line, "unterminated '['");
        if (s[*i] == ']') return ++*i, n;
        if (s[*i] != ',') fail(line, "expected ',' or ']' in a flow sequence");
        ++*i;
      }
    }
    if (c == '"' || c == '\'') {
      const std::size_t end = s.find(c, *i + 1);
      if (end == std::string::npos) fail(line, "unterminated quoted string");
      n.scalar = s.substr(*i + 1, end - *i - 1);
      *i = end + 1;
      return n;
    }
    const std::size_t start = *i;
    while (*i < s.size() && s[*i] != ',' && s[*i] != ']' && s[*i] != '[') ++*i;
    n.scalar = std::string(trim(std::string_view(s).substr(start, *i - start)));
    if (n.scalar.empty()) fail(line, "empty value");
    return n;
  }

  std::vector<Line> lines_;
  std::string source_;
  std::size_t pos_ = 0;
};

}  // namespace

const Node* Node::find(const std::string& key) const {
  for (const auto& [k, v] : entries)
    if (k == key) return &v;
  return nullptr;
}

Node parse(std::istream& in, const std::string& source) {
  std::vector<Line> lines;
  std::string raw;
  int number = 0;
  while (std::getline(in, raw)) {
    ++number;
    if (!raw.empty() && raw.back() == '\r') raw.pop_back();
    if (number == 1 && raw.rfind("%YAML", 0) == 0) continue;  // "%YAML:1.0 # comment"
    if (raw == "---") continue;
    const std::string text = strip_comment(raw);
    const std::size_t first = text.find_first_not_of(' ');
    if (first == std::string::npos || std::string_view(trim(text)).empty()) continue;
    if (text[first] == '\t' || text.substr(0, first).find('\t') != std::string::npos)
      throw InputError(source, number, "", "tab in indentation");
    Line l;
    l.number = number;
    l.indent = static_cast<int>(first);
    l.text = std::string(trim(std::string_view(text).substr(first)));
    lines.push_back(std::move(l));
  }
  if (in.bad()) throw InputError(source, number, "", "read error");
  return Parser(std::move(lines), source).document();
}

}  // namespace slamkit::yaml_subset
