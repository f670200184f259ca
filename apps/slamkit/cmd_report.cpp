// slamkit report RUN.json... -o report.html: one self-contained HTML page (inline SVG and
// CSS, no scripts, no network) comparing eval runs (ate/rpe) and optimizer runs.
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "commands.h"
#include "slamkit/core/error.h"
#include "slamkit/eval/report.h"

namespace slamkit::cli {

namespace {

struct ReportCliOptions {
  std::vector<std::string> runs;
  std::string output = "report.html";
  std::string title = "slamkit evaluation report";
};

void run_report(const ReportCliOptions& o) {
  check_outputs({{&o.output, "--output"}});
  std::vector<ReportInput> inputs;
  for (const auto& path : o.runs) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path, 0, "", "cannot open file");
    ReportInput input;
    input.path = path;
    try {
      input.document = nlohmann::json::parse(in);
    } catch (const nlohmann::json::parse_error& e) {
      throw InputError(path, 0, "", std::string("not valid JSON: ") + e.what());
    }
    inputs.push_back(std::move(input));
  }
  ReportOptions options;
  options.title = o.title;
  options.generator = std::string("slamkit ") + SLAMKIT_VERSION;
  const std::string html = render_html_report(inputs, options);
  write_file_atomically(o.output, html, "--output");
  std::cout << "wrote " << o.output << " (" << inputs.size() << " runs, " << html.size() / 1024 << " KiB)\n";
}

}  // namespace

void add_report_command(CLI::App& app) {
  CLI::App* sub = app.add_subcommand("report", "HTML report comparing eval and optimizer runs (JSON files)");
  auto o = std::make_shared<ReportCliOptions>();
  sub->add_option("RUN", o->runs, "run documents: `slamkit eval --json` outputs, optimizer summaries")
      ->required()->check(CLI::ExistingFile);
  sub->add_option("-o,--output", o->output, "HTML file to write")->capture_default_str();
  sub->add_option("--title", o->title, "page title")->capture_default_str();
  sub->callback([o]() { run_report(*o); });
}

}  // namespace slamkit::cli
