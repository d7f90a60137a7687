// Run CSV reader. Speed matters (a capture is 10^5..10^6 lines), so the file is read in one go and
// parsed in place with std::from_chars; storage is sized once from the line count.

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "hrgbench/session/number_text.hpp"
#include "hrgbench/session/session.hpp"
#include "whole_file.hpp"

namespace hrgbench::session {
namespace {

namespace fs = std::filesystem;

constexpr std::string_view kRequiredColumns[] = {"t_s", "y1", "y2", "y3", "y4"};
constexpr int kExtraBase = 5;  // destination codes: 0 = t_s, 1..4 = y1..y4, 5+ = extra column
constexpr std::size_t kMaxQuoted = 60;

std::string Quote(std::string_view text) {
  if (text.size() > kMaxQuoted) return "'" + std::string(text.substr(0, kMaxQuoted)) + "...'";
  return "'" + std::string(text) + "'";
}

std::unexpected<SessionError> Fail(const fs::path& file, std::size_t line, std::string field,
                                   std::string message) {
  return std::unexpected(SessionError{file, line, std::move(field), std::move(message)});
}

std::string LineTooLong(std::size_t bytes) {
  return "line is " + std::to_string(bytes) + " bytes long (at most " +
         std::to_string(kMaxRunCsvLineBytes) + ")";
}

std::string_view NextLine(std::string_view& rest) {
  const std::size_t eol = rest.find('\n');
  std::string_view line = rest.substr(0, eol);
  rest = eol == std::string_view::npos ? std::string_view() : rest.substr(eol + 1);
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  return line;
}

std::size_t CountFields(std::string_view line) {
  return 1 + static_cast<std::size_t>(std::count(line.begin(), line.end(), ','));
}

std::expected<RunSamples, SessionError> ParseRunCsv(std::string_view text, const fs::path& file,
                                                    std::size_t min_samples,
                                                    bool keep_extra_columns) {
  if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);
  if (text.empty()) return Fail(file, 1, "", "empty file: no header line");

  std::string_view rest = text;
  const std::string_view header = NextLine(rest);
  if (header.size() > kMaxRunCsvLineBytes) return Fail(file, 1, "", LineTooLong(header.size()));
  if (CountFields(header) > kMaxRunCsvColumns) {
    return Fail(file, 1, "",
                std::to_string(CountFields(header)) + " columns in the header (at most " +
                    std::to_string(kMaxRunCsvColumns) + ")");
  }
  std::vector<std::string_view> names;
  for (std::size_t start = 0;;) {
    const std::size_t comma = header.find(',', start);
    names.push_back(header.substr(start, comma - start));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  const std::size_t column_count = names.size();

  RunSamples samples;
  std::vector<int> destination(column_count);
  std::vector<std::string_view> extra_names;
  for (std::size_t c = 0; c < column_count; ++c) {
    const std::string_view name = names[c];
    if (name.empty()) {
      return Fail(file, 1, "column " + std::to_string(c + 1),
                  "empty column name in header " + Quote(header));
    }
    for (std::size_t previous = 0; previous < c; ++previous) {
      if (names[previous] == name) {
        return Fail(file, 1, std::string(name),
                    "duplicate column " + Quote(name) + " (columns " +
                        std::to_string(previous + 1) + " and " + std::to_string(c + 1) + ")");
      }
    }
    int code = -1;
    for (int r = 0; r < kExtraBase; ++r) {
      if (name == kRequiredColumns[r]) code = r;
    }
    if (code < 0) {
      code = kExtraBase + static_cast<int>(extra_names.size());
      extra_names.push_back(name);
    }
    destination[c] = code;
  }
  for (const std::string_view required : kRequiredColumns) {
    if (std::find(names.begin(), names.end(), required) == names.end()) {
      return Fail(file, 1, std::string(required),
                  "header lacks required column " + Quote(required) + ": " + Quote(header));
    }
  }

  // One sample per line; the final line ending is optional.
  const std::size_t sample_count =
      static_cast<std::size_t>(std::count(rest.begin(), rest.end(), '\n')) +
      (!rest.empty() && rest.back() != '\n' ? 1 : 0);
  if (sample_count > kMaxRunCsvSamples) {
    return Fail(file, kMaxRunCsvSamples + 2, "t_s",
                std::to_string(sample_count) + " sample lines (at most " +
                    std::to_string(kMaxRunCsvSamples) + ")");
  }
  // Storage for the lines that can be valid: a valid line has at least 2·columns bytes (one
  // character per field, the commas, the line end), so a file of bare line ends (a few bytes per
  // line, 40+ bytes of doubles each) cannot make us allocate many times its size. For a valid file
  // this is sample_count; the first short line is an error before its index reaches the end.
  const std::size_t storage = std::min(sample_count, rest.size() / (2 * column_count) + 1);
  samples.t_s.resize(storage);
  samples.y.resize(4, static_cast<Eigen::Index>(storage));
  std::vector<double*> extra_data;
  // Not kept: each extra value is still parsed and checked, then written to one scratch slot (the
  // estimate needs t_s and y only, and the extra columns would be 8 bytes per sample each).
  double scratch = 0.0;
  for (const std::string_view name : extra_names) {
    if (!keep_extra_columns) {
      extra_data.push_back(&scratch);
      continue;
    }
    auto& column = samples.extra_columns[std::string(name)];
    column.resize(storage);
    extra_data.push_back(column.data());
  }
  const std::size_t extra_step = keep_extra_columns ? 1 : 0;
  double* const t = samples.t_s.data();
  double* const y = samples.y.data();

  const char* p = rest.data();
  const char* const end = p + rest.size();
  for (std::size_t k = 0; k < sample_count; ++k) {
    const std::size_t line_number = k + 2;
    const char* newline = static_cast<const char*>(std::memchr(p, '\n', end - p));
    const char* line_end = newline != nullptr ? newline : end;
    const char* const next = newline != nullptr ? newline + 1 : end;
    if (line_end > p && line_end[-1] == '\r') --line_end;
    const std::string_view line(p, static_cast<std::size_t>(line_end - p));
    if (line.size() > kMaxRunCsvLineBytes)
      return Fail(file, line_number, "", LineTooLong(line.size()));
    if (k >= storage) {  // unreachable (see `storage`); kept so that no write can pass the end
      return Fail(file, line_number, std::string(names[0]), "line too short for its fields");
    }
    if (line.empty()) {
      return Fail(file, line_number, std::string(names[0]),
                  "empty line (expected " + std::to_string(column_count) + " fields)");
    }
    for (std::size_t c = 0; c < column_count; ++c) {
      double value = 0.0;
      const auto [stop, ec] = std::from_chars(p, line_end, value);
      const bool last = c + 1 == column_count;
      const bool well_ended =
          ec == std::errc() && (last ? stop == line_end : stop < line_end && *stop == ',');
      if (!well_ended || !std::isfinite(value)) {
        const std::size_t field_count = CountFields(line);
        if (field_count != column_count) {
          const std::string field = field_count < column_count
                                        ? std::string(names[field_count])
                                        : "column " + std::to_string(column_count + 1);
          return Fail(file, line_number, field,
                      "line has " + std::to_string(field_count) + " fields, header has " +
                          std::to_string(column_count) + ": " + Quote(line));
        }
        const char* field_end = static_cast<const char*>(std::memchr(p, ',', line_end - p));
        if (field_end == nullptr) field_end = line_end;
        const std::string_view text_value(p, static_cast<std::size_t>(field_end - p));
        std::string why = "not a number";
        if (ec == std::errc::result_out_of_range) {
          why = "number out of the range of double";
        } else if (ec == std::errc() && stop == field_end) {
          why = "non-finite value";
        }
        return Fail(file, line_number, std::string(names[c]), why + " " + Quote(text_value));
      }
      const int code = destination[c];
      if (code == 0) {
        t[k] = value;
      } else if (code < kExtraBase) {
        y[4 * k + static_cast<std::size_t>(code - 1)] = value;
      } else {
        extra_data[static_cast<std::size_t>(code - kExtraBase)][k * extra_step] = value;
      }
      p = stop + 1;  // past the comma (or the line end, reset below)
    }
    if (k > 0 && !(t[k] > t[k - 1])) {
      return Fail(file, line_number, "t_s",
                  "time not strictly increasing: " + NumberText(t[k]) + " after " +
                      NumberText(t[k - 1]) + " on line " + std::to_string(line_number - 1));
    }
    p = next;
  }

  if (sample_count < min_samples) {
    return Fail(file, 0, "t_s",
                std::to_string(sample_count) + " sample(s), at least " +
                    std::to_string(min_samples) + " required");
  }
  return samples;
}

}  // namespace

std::expected<RunSamples, SessionError> ReadRunCsv(const fs::path& path,
                                                   std::size_t min_samples_per_run,
                                                   bool keep_extra_columns) {
  auto text = internal::ReadWholeFile(path, kMaxRunCsvBytes);
  if (!text) return std::unexpected(text.error());
  return ParseRunCsv(*text, path, min_samples_per_run, keep_extra_columns);
}

}  // namespace hrgbench::session
