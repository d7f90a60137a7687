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
// Shortest round-trip text of a double; "" for none.
std::string NumberText(std::optional<double> value);

void PrintSessions(std::ostream& out, const std::vector<results::SessionSummary>& sessions,
                   OutputFormat format);
// Key quantities per session of one unit, oldest first.
void PrintHistory(std::ostream& out, const std::string& serial,
                  const std::vector<results::SessionWithParameters>& sessions, OutputFormat format);
void PrintStats(std::ostream& out, const results::ParameterStats& stats, OutputFormat format);
// One row per session, one column per quantity (the union of names, sorted).
void PrintExport(std::ostream& out, const std::vector<results::SessionWithParameters>& sessions);

}  // namespace hrgbench::app
