// A strict reader for the small YAML subset of Kalibr / OpenVINS calibration files:
// block maps ("key: value", "key:" + indented block), block sequences ("- item"), flow
// sequences ("[1, 2, [3]]"), plain and quoted scalars, '#' comments, a leading "%YAML" line.
// Anything else (tabs in indentation, anchors, multi-line scalars, duplicate keys, bad
// indentation) throws InputError naming the file and line. Private to io.
#pragma once

#include <istream>
#include <string>
#include <utility>
#include <vector>

namespace slamkit::yaml_subset {

struct Node {
  enum class Kind { kScalar, kSequence, kMap };
  Kind kind = Kind::kScalar;
  int line = 0;                                     ///< 1-based line where the node starts
  std::string scalar;                               ///< kScalar (quotes removed)
  std::vector<Node> items;                          ///< kSequence
  std::vector<std::pair<std::string, Node>> entries;  ///< kMap, in file order

  /// The entry `key` of a map, or nullptr.
  const Node* find(const std::string& key) const;
};

/// Parses a whole document; the root is a map (an empty document gives an empty map).
Node parse(std::istream& in, const std::string& source);

}  // namespace slamkit::yaml_subset
