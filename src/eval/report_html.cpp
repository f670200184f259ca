#include "report_html.h"

#include <cmath>
#include <cstdio>

#include "slamkit/eval/svg.h"

namespace slamkit::report_html {

Cell text_cell(const std::string& raw) { return Cell{xml_escape(raw), true, false}; }

Cell number_cell(std::string formatted, bool best) { return Cell{std::move(formatted), false, best}; }

std::string fixed(double v, int decimals) {
  if (!std::isfinite(v)) return "–";
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

std::string table_head(const std::vector<Column>& columns) {
  std::string h = "<table class=\"runs\">\n<tr>";
  for (const Column& c : columns) h += (c.text ? "<th class=\"text\">" : "<th>") + c.html + "</th>";
  return h + "</tr>\n";
}

std::string run_row(std::size_t k, const std::string& label, const std::vector<Cell>& cells) {
  std::string h = "<tr><td class=\"text\"><span class=\"swatch\" style=\"background:" + palette(k).hex() +
                  "\"></span>" + xml_escape(label) + "</td>";
  for (const Cell& c : cells)
    h += std::string(c.text ? "<td class=\"text\">" : c.best ? "<td class=\"best\">" : "<td>") + c.html + "</td>";
  return h + "</tr>\n";
}

}  // namespace slamkit::report_html
