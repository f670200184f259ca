#include <CLI/CLI.hpp>
#include <iostream>

int main(int argc, char** argv) {
  CLI::App app{"slamkit: SLAM back-end toolkit"};
  app.set_version_flag("--version", std::string("slamkit ") + SLAMKIT_VERSION);
  CLI11_PARSE(app, argc, argv);
  return 0;
}
