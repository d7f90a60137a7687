#pragma once
// A fixture session: several units on one table, sequenced together (bench::RunSessions), each
// with its own session folder under the fixture's, and a record that ties them together:
//
//   <dir>/config/*.toml           the configs, copied before fixture.json is written
//   <dir>/fixture.json            {"format": "hrgbench-fixture", "version": 1, "station",
//                                  "software", "started", "config_sha256": {"station",
//                                  "sequence", "limits"}, "units": [{"position", "serial",
//                                  "folder", "can_interface", "inverted", "outcome": null until the
//                                  unit's session closes, then {"kind", "exit_code", "reason"}}]}
//   <dir>/<position>-<serial>/    each unit's session, in the one-unit format; its session.json
//                                 says under "fixture" where it sat and who sat beside it
//
// A station with one fitted position runs a plain session instead (no fixture.json).
// Not thread-safe; files only (no hardware).

#include <cstddef>
#include <expected>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "hrgbench/bench/sequencer/sequencer.hpp"
#include "hrgbench/config/bench_configs.hpp"
#include "hrgbench/config/station_config.hpp"

namespace hrgbench::app {

inline constexpr const char* kFixtureFile = "fixture.json";
// fixture.json is small (16 units of a few hundred bytes); anything far larger is not ours.
inline constexpr std::size_t kMaxFixtureFileBytes = 1 << 20;

struct FixtureUnit {
  std::string position;
  std::string serial;
  std::string folder;  // relative to the fixture's folder: "<position>-<serial>"
  std::string can_interface;
  bool inverted = false;  // mounted against the table's axis (recorded in its session.json)
  int can_node = 0;       // its node id on can_interface (units may share one bus)
};

struct FixtureRecord {
  std::string station;
  std::vector<FixtureUnit> units;  // the fitted positions, in the station's order
  // SHA-256 of the config copies in <dir>/config/ ({"station", "sequence", "limits"}), which are
  // written before fixture.json; null in a record from before they were.
  nlohmann::json config_sha256;
};

// Maps the operator's serials onto the station's fitted positions: either one serial per fitted
// position, in their order ("SN1", "SN2", ...), or each as "POSITION=SERIAL" naming every fitted
// position once; "POSITION=" leaves that position empty on purpose (it is not in the record; at
// least one unit is). Errors name the serial, the position or the counts.
std::expected<FixtureRecord, std::string> PlanFixture(const bench::StationConfig& station,
                                                      const std::vector<std::string>& serials);

// The units' sessions: folders under `dir`, and what each records under "fixture".
std::vector<bench::UnitSession> FixtureUnitSessions(const FixtureRecord& record,
                                                    const std::filesystem::path& dir);

// Writes <dir>/fixture.json (creating dir), replacing it whole (a temporary file renamed), with
// each unit's outcome from `results` (parallel to record.units; empty: none yet).
std::expected<void, std::string> WriteFixtureRecord(
    const std::filesystem::path& dir, const FixtureRecord& record,
    const std::vector<bench::SessionResult>& results, const std::string& software_version);

bool IsFixtureFolder(const std::filesystem::path& dir);

// The configs a fixture ran with, for its resume: <dir>/config/ checked against fixture.json's
// config_sha256; for a record from before those were written, the first unit folder that holds
// its copies. The error says why none can be used and what to do.
std::expected<bench::BenchConfigs, std::string> FixtureConfigs(const std::filesystem::path& dir,
                                                               const FixtureRecord& record);
// Reads <dir>/fixture.json; errors name the file and the field.
std::expected<FixtureRecord, std::string> ReadFixtureRecord(const std::filesystem::path& dir);

// The verdict a unit's session closed with (PASS or FAIL, its reason), which a resume keeps; none
// when the session is to be continued: it is running (interrupted), closed as ERROR or ABORTED, or
// cannot be read (ResumeSessions says why). The rule is bench::KeepsVerdict (session_judge.hpp).
struct KeptVerdict {
  bool pass = false;
  std::string reason;
};
std::optional<KeptVerdict> ClosedVerdict(const std::filesystem::path& unit_dir);

}  // namespace hrgbench::app
