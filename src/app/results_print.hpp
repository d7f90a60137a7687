#pragma once
// hrg-results' output: aligned tables for a terminal, RFC 4180 CSV for a spreadsheet, JSON for
// scripts. Pure formatting of what the store returned; writes to the stream given.

#include <ostream>
#include <string>
#include <vector>

#include "hrgbench/results/parameter_stats.hpp"
#include "hrgbench/results/results_store.hpp"

namespace hrgbench::app {

enum class OutputFormat { kTable, kCsv, kJson };

// One CSV field: quoted (with "" for ") when it holds a comma, quote, CR or LF, or starts with
// =, +, - or @ followed by a non-digit (a spreadsheet would run it as a formula).
std::string CsvField(const std::string& text);
// The session columns every CSV starts with (id ... complete_runs), and one session's fields.
std::string SessionCsvHeader();
std::string SessionCsvFields(const results::SessionSummary& session);
// Shortest round-trip text of a double; "" for none.
std::string NumberText(std::optional<double> value);

void PrintSessions(std::ostream& out, const std::vector<results::SessionSummary>& sessions,
                   OutputFormat format);
// Key quantities per session of one unit, oldest first.
void PrintHistory(std::ostream& out, const std::string& serial,
                  const std::vector<results::SessionWithParameters>& sessions, OutputFormat format);
// One parameter's statistics per group (stats --by: the key holds one value per GroupBy; no
// grouping: one group with an empty key).
struct GroupStats {
  std::vector<std::string> key;
  results::ParameterStats stats;
};
void PrintStats(std::ostream& out, const std::vector<results::GroupBy>& by,
                const std::vector<GroupStats>& groups, OutputFormat format);
// One row per session: its fields, then per quantity (the union of names, sorted) its value, std,
// unit and the limit verdict's min, max, status and message.
void PrintExport(std::ostream& out, const std::vector<results::SessionExport>& sessions);

// `text` in at most `width` display columns (UTF-8 code points), on one line: line breaks and tabs
// become spaces, and a longer text is cut with "…". A table row never spans two lines.
std::string Cell(const std::string& text, std::size_t width);

}  // namespace hrgbench::app
