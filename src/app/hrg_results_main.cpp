// hrg-results: the production line's view of its results database (issue 10).
//
//   hrg-results [--db URL | --station S.toml] import DIR...
//   hrg-results ... sync --sessions-root DIR
//   hrg-results ... migrate
//   hrg-results ... history SERIAL [--json|--csv]
//   hrg-results ... sessions [filters] [--json|--csv]
//   hrg-results ... stats PARAM [filters] [--by sequence,limits,product] [--json|--csv]
//   hrg-results ... export [filters]
//   hrg-results ... serve [--port P] [--today YYYY-MM-DD]   (the read-only line view)
//   filters: --since T --at-station N --sequence S --limits L --product P (sessions and export
//   also --outcome O --serial-like P)
//
// Writers (import, sync, migrate) create and migrate the store; readers (history, sessions, stats,
// export) never create one: a SQLite path with no file is "no results store at <path>".
//
// Exit codes (hrgbench/session/exit_codes.hpp): 0 done; 1 some session could not be imported or
// synced (each is named), or stats found no value of the parameter; 2 the database cannot be
// reached or failed; 4 bad command line, unusable URL or station file, an unknown parameter, no
// store at the path, or a database of another schema (an older one: `migrate` it).
// GCC 12 at -O2 reports a "potential null pointer dereference" inside CLI11's detail::split
// (std::vector<std::string> relocation) as inlined here: a false positive in library code.
#pragma GCC diagnostic ignored "-Wnull-dereference"
#include <CLI/CLI.hpp>
#include <algorithm>
#include <iostream>
#include <set>
#include <string>
#include <vector>

#include "app/cli_exit.hpp"
#include "app/line_view.hpp"
#include "app/logging.hpp"
#include "app/results_print.hpp"
#include "hrgbench/config/limits_config.hpp"
#include "hrgbench/config/station_config.hpp"
#include "hrgbench/results/parameter_stats.hpp"
#include "hrgbench/results/since_utc.hpp"
#include "hrgbench/results/upload.hpp"

namespace {

using namespace hrgbench;
namespace fs = std::filesystem;

int Import(results::ResultsStore& store, const std::vector<std::string>& dirs) {
  int failed = 0;
  std::size_t counts[3] = {0, 0, 0};
  for (const std::string& dir : dirs) {
    const results::UploadOutcome outcome = results::UploadSession(store, dir);
    if (!outcome.uploaded) {
      std::cerr << "error: " << outcome.reason << '\n';
      ++failed;
      continue;
    }
    ++counts[static_cast<int>(outcome.status)];
  }
  std::cout << "import: " << counts[0] << " inserted, " << counts[1] << " replaced, " << counts[2]
            << " unchanged, " << failed << " failed\n";
  return failed == 0 ? kExitOk : kExitFail;
}

// Every closed session under `root` that the database does not hold as it is on disk; each
// uploaded one gets its "results" mark. Sessions still open are skipped (they upload when closed).
int Sync(results::ResultsStore& store, const fs::path& root) {
  int uploaded = 0, current = 0, skipped = 0, failed = 0;
  for (const fs::path& dir : results::FindSessionDirs(root)) {
    auto record = results::ReadSessionRow(dir);
    if (!record) {
      std::cerr << "skipped: " << record.error() << '\n';
      ++skipped;
      continue;
    }
    auto stored = store.StoredContentHash(record->id);
    if (stored && *stored == record->content_sha256) {
      ++current;
      continue;
    }
    const results::UploadOutcome outcome = results::UploadSession(store, dir);
    if (!outcome.uploaded) {
      std::cerr << "error: " << outcome.reason << '\n';
      ++failed;
    } else {
      ++uploaded;
    }
    if (auto marked = results::MarkUpload(dir, store.url(), outcome); !marked)
      std::cerr << "warning: " << marked.error() << '\n';
  }
  std::cout << "sync: " << uploaded << " uploaded, " << current << " already stored, " << skipped
            << " skipped, " << failed << " failed\n";
  return failed == 0 ? kExitOk : kExitFail;
}

// A database the command named but that cannot be used is the user's to fix (4); one that is down,
// busy or failing is the station's problem, like any other I/O error (2): a line's script retries
// the second and not the first.
int StoreFailure(const results::StoreError& error) {
  std::cerr << "hrg-results: " << error.message << '\n';
  switch (error.kind) {
    case results::StoreError::Kind::kBadUrl:
    case results::StoreError::Kind::kSchemaMismatch:
      return kExitBadInput;
    case results::StoreError::Kind::kUnavailable:
    case results::StoreError::Kind::kBusy:
    case results::StoreError::Kind::kFailed:
      return kExitError;
  }
  return kExitError;
}

// The names stats accepts: every quantity a limits file may judge (the estimator's) and every
// name the store holds (a name of an older or newer estimator included), sorted.
std::vector<std::string> KnownParameters(const std::vector<std::string>& stored) {
  std::set<std::string> names(stored.begin(), stored.end());
  for (std::size_t q = 0; q < bench::kLimitedQuantityCount; ++q)
    names.insert(std::string(bench::ToString(static_cast<bench::LimitedQuantity>(q))));
  return {names.begin(), names.end()};
}

std::string Joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& name : names) out += (out.empty() ? "" : ", ") + name;
  return out;
}

int Stats(results::ResultsStore& store, const std::string& parameter,
          const results::SessionFilter& filter, const std::vector<results::GroupBy>& by,
          app::OutputFormat format) {
  auto stored = store.ParameterNames();
  if (!stored) return StoreFailure(stored.error());
  const std::vector<std::string> known = KnownParameters(*stored);
  if (!std::ranges::binary_search(known, parameter)) {
    std::cerr << "hrg-results: stats: unknown parameter '" << parameter
              << "'; known: " << Joined(known) << '\n';
    return kExitBadInput;
  }
  auto samples = store.ParameterValues(parameter, filter);
  if (!samples) return StoreFailure(samples.error());
  std::vector<app::GroupStats> groups;
  for (const results::SampleGroup& g : results::GroupSamples(*samples, by))
    groups.push_back({g.key, results::ComputeParameterStats(parameter, g.samples)});
  if (groups.empty()) groups.push_back({{}, results::ComputeParameterStats(parameter, {})});
  app::PrintStats(std::cout, by, groups, format);
  if (samples->empty()) {
    // A statistic of nothing is no answer: a script must not read "n = 0" as a line in spec.
    std::cerr << "hrg-results: stats: no stored session matching the filters has a value of '"
              << parameter << "'\n";
    return kExitFail;
  }
  return kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{
      "hrg-results: the results database of a bench station or a line (SQLite or PostgreSQL).\n"
      "Here 1: a session could not be imported or synced, or stats found no value; 2: the "
      "database cannot be reached or failed; 4: bad command line, URL, station file, unknown "
      "parameter, no store at the path, or a database of another schema (migrate an older "
      "one).\n" +
      std::string(hrgbench::kExitCodesHelp)};
  cli.require_subcommand(1);
  bool quiet = false;
  app::AddCommonFlags(cli, &quiet);
  std::string db_url, station_file;
  cli.add_option("--db", db_url, "database URL: sqlite:///path or postgresql://host/db");
  cli.add_option("--station", station_file, "station file whose [results] url to use");

  results::SessionFilter filter;
  bool json = false, csv = false;
  auto add_filters = [&](CLI::App* sub, bool with_outcome) {
    sub->add_option("--since", filter.since_utc, "sessions started at or after (UTC, ISO 8601)")
        ->check(
            [](const std::string& since) { return results::WhyNotSinceUtc(since).value_or(""); },
            "UTC, ISO 8601");
    sub->add_option("--at-station", filter.station, "sessions of this station name");
    sub->add_option("--sequence", filter.sequence, "sessions run with this sequence (its name)");
    sub->add_option("--limits", filter.limits, "sessions judged with these limits (their name)");
    sub->add_option("--product", filter.product, "sessions of this product (limits' product)");
    if (with_outcome) {
      sub->add_option("--outcome", filter.outcome, "PASS, FAIL, ERROR or ABORTED");
      sub->add_option("--serial-like", filter.serial_like, "serial LIKE pattern (% and _)");
    }
  };
  std::vector<std::string> import_dirs;
  CLI::App* import = cli.add_subcommand("import", "import (or re-import) session folders");
  import->add_option("dirs", import_dirs, "session folders")
      ->required()
      ->check(CLI::ExistingDirectory);
  std::string sessions_root;
  CLI::App* sync = cli.add_subcommand("sync", "upload every session not yet in the database");
  sync->add_option("--sessions-root", sessions_root, "folder holding session folders")
      ->required()
      ->check(CLI::ExistingDirectory);
  CLI::App* migrate = cli.add_subcommand(
      "migrate", "bring the store to this program's schema (an upload does too)");
  int serve_port = 8090;
  std::string serve_day;
  CLI::App* serve = cli.add_subcommand(
      "serve", "the line view: every station's last session and today's yield, read-only page");
  serve->add_option("--port", serve_port, "port on 127.0.0.1 (0: any free one)")
      ->check(CLI::Range(0, 65535));
  serve->add_option("--today", serve_day, "the day shown as today (UTC, YYYY-MM-DD)")
      ->check(
          [](const std::string& day) {
            return day.size() == 10 && !results::WhyNotSinceUtc(day) ? std::string()
                                                                     : "expected YYYY-MM-DD";
          },
          "YYYY-MM-DD");
  std::string serial;
  CLI::App* history = cli.add_subcommand("history", "every session of one unit");
  history->add_option("serial", serial, "unit serial")->required();
  history->add_flag("--json", json, "JSON")->excludes(history->add_flag("--csv", csv, "CSV"));
  CLI::App* sessions = cli.add_subcommand("sessions", "list sessions");
  add_filters(sessions, true);
  sessions->add_flag("--json", json, "JSON")->excludes(sessions->add_flag("--csv", csv, "CSV"));
  std::string parameter;
  CLI::App* stats = cli.add_subcommand("stats", "line statistics of one parameter");
  stats->add_option("param", parameter, "parameter name (delta1, xi2, tau_s, q_factor, ...)")
      ->required();
  add_filters(stats, false);
  std::vector<std::string> group_by;
  stats->add_option("--by", group_by, "one statistic per sequence, limits and/or product")
      ->delimiter(',')
      ->check(
          [](const std::string& by) {
            return results::ParseGroupBy(by) ? std::string()
                                             : "'" + by + "': expected sequence, limits or product";
          },
          "sequence|limits|product");
  stats->add_flag("--json", json, "JSON")->excludes(stats->add_flag("--csv", csv, "CSV"));
  CLI::App* export_cmd =
      cli.add_subcommand("export", "CSV: one row per session, one column per quantity");
  add_filters(export_cmd, true);

  try {
    cli.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    return app::ExitForParseError(cli, error);
  }
  app::SetUpStderrLogging("hrg-results", quiet ? -1 : 0);
  if (!filter.outcome.empty() && filter.outcome != "PASS" && filter.outcome != "FAIL" &&
      filter.outcome != "ERROR" && filter.outcome != "ABORTED") {
    std::cerr << "hrg-results: --outcome '" << filter.outcome
              << "': expected PASS, FAIL, ERROR or ABORTED\n";
    return kExitBadInput;
  }

  try {
    if (db_url.empty() && !station_file.empty()) {
      auto station = bench::LoadStationConfig(station_file);
      if (!station) {
        std::cerr << station.error().ToString() << '\n';
        return kExitBadInput;
      }
      if (station->results_url.empty()) {
        std::cerr << station_file << ": no [results] url\n";
        return kExitBadInput;
      }
      db_url = station->results_url;
    }
    if (db_url.empty()) {
      std::cerr << "hrg-results: give --db URL or --station FILE (with a [results] url)\n";
      return kExitBadInput;
    }
    if (*serve) return app::ServeLineView(db_url, serve_port, serve_day);
    const bool writer = *import || *sync || *migrate;
    auto store =
        writer ? results::ResultsStore::Open(db_url) : results::ResultsStore::OpenExisting(db_url);
    if (!store) return StoreFailure(store.error());
    if (*store == nullptr) {
      // A reader names the file it looked for, as the working directory made it.
      const auto parsed = results::ParseResultsUrl(db_url);
      std::error_code ec;
      const fs::path path = fs::absolute(parsed ? parsed->sqlite_path : db_url, ec);
      std::cerr << "hrg-results: no results store at " << path.lexically_normal().string()
                << " (nothing created; `import` or `sync` makes one)\n";
      return kExitBadInput;
    }
    const app::OutputFormat format =
        json ? app::OutputFormat::kJson
             : (csv ? app::OutputFormat::kCsv : app::OutputFormat::kTable);
    if (*import) return Import(**store, import_dirs);
    if (*sync) return Sync(**store, sessions_root);
    if (*migrate) {
      const int found = (*store)->found_version();
      if (found == results::kSchemaVersion) {
        std::cout << "migrate: schema version " << found << " already\n";
      } else {
        std::cout << "migrate: schema version " << found << " -> " << results::kSchemaVersion
                  << '\n';
      }
      return kExitOk;
    }
    if (*history) {
      filter.serial = serial;
      auto rows = (*store)->SessionsWithParameters(filter);
      if (!rows) return StoreFailure(rows.error());
      app::PrintHistory(std::cout, serial, *rows, format);
      return kExitOk;
    }
    if (*sessions) {
      auto rows = (*store)->Sessions(filter);
      if (!rows) return StoreFailure(rows.error());
      app::PrintSessions(std::cout, *rows, format);
      return kExitOk;
    }
    if (*stats) {
      std::vector<results::GroupBy> by;
      for (const std::string& b : group_by) by.push_back(*results::ParseGroupBy(b));
      return Stats(**store, parameter, filter, by, format);
    }
    auto rows = (*store)->ExportRows(filter);
    if (!rows) return StoreFailure(rows.error());
    app::PrintExport(std::cout, *rows);
    return kExitOk;
  } catch (const std::exception& error) {
    std::cerr << "hrg-results: unexpected failure: " << error.what() << '\n';
    return kExitError;
  }
}
