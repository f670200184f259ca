#pragma once
// Building blocks of the HTML report's tables (private to eval): every run table has a first
// column with the run's palette swatch and label, then text columns (left-aligned) and number
// columns (right-aligned, the best one of a column highlighted).
#include <cstddef>
#include <string>
#include <vector>

namespace slamkit::report_html {

struct Cell {
  std::string html;   // escaped content
  bool text = false;  // left-aligned text column
  bool best = false;  // highlighted (class="best")
};

/// A text cell: `raw` escaped, left-aligned.
Cell text_cell(const std::string& raw);
/// A number cell from its formatted value.
Cell number_cell(std::string formatted, bool best = false);

/// `v` with `decimals` after the point; "–" when not finite.
std::string fixed(double v, int decimals);

struct Column {
  std::string html;   // the heading (HTML)
  bool text = false;  // left-aligned text column
};

/// `<table class="runs">` and its header row.
std::string table_head(const std::vector<Column>& columns);

/// One row: swatch of palette colour `k` + escaped `label`, then `cells`.
std::string run_row(std::size_t k, const std::string& label, const std::vector<Cell>& cells);

}  // namespace slamkit::report_html
