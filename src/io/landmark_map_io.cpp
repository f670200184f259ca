#include "slamkit/io/landmark_map_io.h"

#include <fstream>

#include "slamkit/core/error.h"
#include "slamkit/io/text_reader.h"

namespace slamkit {

LandmarkMap read_landmark_map(std::istream& in, const std::string& source) {
  TextReader reader(in, source);
  LandmarkMap map;
  bool have_lm = false, have_wp = false;
  while (reader.next_line()) {
    reader.expect_fields(3, "section header 'lm|wp 2 ROWS'");
    std::string type(reader.field(0));
    if (type != "lm" && type != "wp") reader.fail("type", "expected 'lm' or 'wp', got '" + type + "'");
    if (reader.integer(1, "columns") != 2) reader.fail("columns", "must be 2");
    std::int64_t rows = reader.integer(2, "rows");
    if (rows < 0) reader.fail("rows", "must be >= 0");
    bool& seen = type == "lm" ? have_lm : have_wp;
    if (seen) reader.fail("type", "duplicate section '" + type + "'");
    seen = true;
    auto& out = type == "lm" ? map.landmarks : map.waypoints;
    for (std::int64_t i = 0; i < rows; ++i) {
      if (!reader.next_line())
        throw InputError(source, reader.line_number(), "rows",
                         "section '" + type + "' ends after " + std::to_string(i) + " of " +
                             std::to_string(rows) + " rows");
      reader.expect_fields(2, type + " row 'x y'");
      out.emplace_back(reader.number(0, "x"), reader.number(1, "y"));
    }
  }
  if (!have_lm) throw InputError(source, reader.line_number(), "lm", "no landmark section");
  if (!have_wp || map.waypoints.empty())
    throw InputError(source, reader.line_number(), "wp", "no waypoints");
  return map;
}

LandmarkMap read_landmark_map(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "", "cannot open file");
  return read_landmark_map(in, path);
}

}  // namespace slamkit
