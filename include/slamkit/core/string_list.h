#pragma once
// A comma-separated option value ("gn,lm,dogleg") as its items. Empty items ("a,,b", a trailing
// comma) are dropped, so "" gives an empty list.
#include <algorithm>
#include <string>
#include <vector>

namespace slamkit {

inline std::vector<std::string> split_list(const std::string& s, char separator = ',') {
  std::vector<std::string> items;
  std::string::size_type begin = 0;
  while (begin <= s.size()) {
    const auto end = std::min(s.find(separator, begin), s.size());
    if (end > begin) items.push_back(s.substr(begin, end - begin));
    begin = end + 1;
  }
  return items;
}

}  // namespace slamkit
