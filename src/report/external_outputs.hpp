#pragma once
// The report's outputs drawn by other programs: every figure as SVG by gnuplot, the page as PDF
// by headless Chromium. Both run as subprocesses with their input in a temporary directory; what
// they produce is moved into place atomically. A missing or failing program is a returned warning,
// never an exception. Internal to src/report.

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace hrgbench::report::internal {

struct FiguresResult {
  std::vector<std::filesystem::path> written;
  std::vector<std::string> warnings;
};

// Each figure spec of `data` (report_data.hpp) as <out_dir>/<name>.svg.
FiguresResult WriteGnuplotFigures(const nlohmann::json& data, const std::filesystem::path& out_dir,
                                  double timeout_s);

// Prints `html` to `pdf` with `chromium` (a binary name or path). Empty on success, else why not.
std::string PrintPdf(const std::string& chromium, const std::filesystem::path& html,
                     const std::filesystem::path& pdf, double timeout_s);

}  // namespace hrgbench::report::internal
