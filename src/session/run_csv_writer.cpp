// Run CSV writer. It refuses anything the reader would refuse, so a session written by the bench
// is always readable by the estimator side.

#include <algorithm>
#include <charconv>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "hrgbench/session/number_text.hpp"
#include "hrgbench/session/session.hpp"

namespace hrgbench::session {
namespace {

namespace fs = std::filesystem;

constexpr std::string_view kRequiredColumns[] = {"t_s", "y1", "y2", "y3", "y4"};
std::unexpected<SessionError> Fail(const fs::path& file, std::size_t line, std::string field,
                                   std::string message) {
  return std::unexpected(SessionError{file, line, std::move(field), std::move(message)});
}

}  // namespace

std::expected<void, SessionError> WriteRunCsv(const fs::path& path, const RunSamples& samples) {
  const std::size_t n = samples.t_s.size();
  if (static_cast<std::size_t>(samples.y.cols()) != n) {
    return Fail(
        path, 0, "y",
        "y has " + std::to_string(samples.y.cols()) + " samples, t_s has " + std::to_string(n));
  }
  std::vector<const double*> columns;
  std::vector<std::string_view> names(std::begin(kRequiredColumns), std::end(kRequiredColumns));
  for (const auto& [name, values] : samples.extra_columns) {
    if (name.empty() || name.find_first_of(",\r\n") != std::string::npos) {
      return Fail(path, 0, name, "invalid column name '" + name + "'");
    }
    if (std::find(std::begin(kRequiredColumns), std::end(kRequiredColumns), name) !=
        std::end(kRequiredColumns)) {
      return Fail(path, 0, name, "extra column '" + name + "' repeats a required column");
    }
    if (values.size() != n) {
      return Fail(
          path, 0, name,
          "column has " + std::to_string(values.size()) + " values, t_s has " + std::to_string(n));
    }
    names.push_back(name);
    columns.push_back(values.data());
  }

  if (names.size() > kMaxRunCsvColumns) {
    return Fail(path, 0, "",
                std::to_string(names.size()) + " columns (at most " +
                    std::to_string(kMaxRunCsvColumns) + ")");
  }
  if (n > kMaxRunCsvSamples) {
    return Fail(path, 0, "t_s",
                std::to_string(n) + " samples (at most " + std::to_string(kMaxRunCsvSamples) + ")");
  }

  std::string out;
  out.reserve(64 + n * names.size() * 24);
  for (std::size_t c = 0; c < names.size(); ++c) {
    if (c > 0) out += ',';
    out += names[c];
  }
  if (out.size() > kMaxRunCsvLineBytes) {
    return Fail(path, 1, "",
                "header line is " + std::to_string(out.size()) + " bytes long (at most " +
                    std::to_string(kMaxRunCsvLineBytes) + ")");
  }
  out += '\n';
  const double* const y = samples.y.data();
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t line = k + 2;
    const double t = samples.t_s[k];
    if (k > 0 && !(t > samples.t_s[k - 1])) {
      return Fail(path, line, "t_s",
                  "time not strictly increasing: " + NumberText(t) + " after " +
                      NumberText(samples.t_s[k - 1]));
    }
    for (std::size_t c = 0; c < names.size(); ++c) {
      const double value = c == 0 ? t : c < 5 ? y[4 * k + (c - 1)] : columns[c - 5][k];
      if (!std::isfinite(value)) {
        return Fail(path, line, std::string(names[c]), "non-finite value " + NumberText(value));
      }
      if (c > 0) out += ',';
      AppendNumber(out, value);
    }
    out += '\n';
  }

  if (out.size() > kMaxRunCsvBytes) {
    return Fail(path, 0, "",
                "file would be " + std::to_string(out.size()) + " bytes (at most " +
                    std::to_string(kMaxRunCsvBytes) + ")");
  }
  if (auto created = CreateDirectoriesDurably(path.parent_path()); !created) {
    return created;
  }
  return WriteFileAtomic(path, out);
}

}  // namespace hrgbench::session
