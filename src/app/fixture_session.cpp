#include "app/fixture_session.hpp"

#include <algorithm>
#include <fstream>
#include <set>
#include <sstream>
#include <system_error>

#include "app/serial_check.hpp"
#include "app/utc_now.hpp"
#include "hrgbench/analysis/session_judge.hpp"
#include "hrgbench/session/kill_point.hpp"
#include "hrgbench/session/session.hpp"
#include "hrgbench/session/session_record.hpp"
#include "hrgbench/session/session_record_keys.hpp"

namespace hrgbench::app {
namespace {

std::string FixtureFileName(const std::filesystem::path& dir) {
  return (dir / kFixtureFile).string();
}

// A string field of an object, or an error naming it.
std::expected<std::string, std::string> StringField(const nlohmann::json& object,
                                                    const std::string& key,
                                                    const std::string& where) {
  if (!object.is_object() || !object.contains(key) || !object.at(key).is_string())
    return std::unexpected(where + "." + key + ": missing or not a string");
  return object.at(key).get<std::string>();
}

// <dir>/fixture.json as JSON, within its bound.
std::expected<nlohmann::json, std::string> ReadFixtureJson(const std::filesystem::path& dir) {
  const std::string file = FixtureFileName(dir);
  std::error_code ec;
  const auto size = std::filesystem::file_size(dir / kFixtureFile, ec);
  if (ec) return std::unexpected(file + ": cannot read: " + ec.message());
  if (size > kMaxFixtureFileBytes)
    return std::unexpected(file + ": " + std::to_string(size) + " bytes; a fixture record has " +
                           "at most " + std::to_string(kMaxFixtureFileBytes));
  std::ifstream in(dir / kFixtureFile);
  std::stringstream text;
  text << in.rdbuf();
  nlohmann::json doc = nlohmann::json::parse(text.str(), nullptr, false);
  if (!doc.is_object()) return std::unexpected(file + ": not a JSON object");
  return doc;
}

}  // namespace

std::expected<FixtureRecord, std::string> PlanFixture(const bench::StationConfig& station,
                                                      const std::vector<std::string>& serials) {
  const std::vector<const bench::FixturePosition*> fitted = bench::FittedPositions(station);
  FixtureRecord record;
  record.station = station.name;
  const bool named = std::any_of(serials.begin(), serials.end(), [](const std::string& s) {
    return s.find('=') != std::string::npos;
  });
  std::vector<std::string> by_position(fitted.size());
  // "POSITION=" (no serial): the operator left the position empty on purpose (no unit in it).
  std::vector<bool> left_empty(fitted.size(), false);
  if (named) {
    for (const std::string& entry : serials) {
      const std::size_t eq = entry.find('=');
      if (eq == std::string::npos)
        return std::unexpected("--serial " + entry +
                               ": give every serial as POSITION=SERIAL, or none of them");
      const std::string position = entry.substr(0, eq);
      const auto at = std::find_if(fitted.begin(), fitted.end(),
                                   [&](const auto* p) { return p->name == position; });
      if (at == fitted.end())
        return std::unexpected("--serial " + entry + ": no fitted position '" + position +
                               "' on station '" + station.name + "'");
      const auto index = static_cast<std::size_t>(at - fitted.begin());
      std::string& slot = by_position[index];
      if (!slot.empty() || left_empty[index])
        return std::unexpected("--serial " + entry + ": position '" + position +
                               "' is given twice");
      slot = entry.substr(eq + 1);
      left_empty[index] = slot.empty();
    }
  } else {
    if (serials.size() != fitted.size()) {
      std::string names;
      for (const auto* p : fitted) names += (names.empty() ? "" : ", ") + p->name;
      return std::unexpected("--serial: " + std::to_string(serials.size()) + " serial(s) for " +
                             std::to_string(fitted.size()) + " fitted position(s) (" + names +
                             ") on station '" + station.name +
                             "': give one per position, in order, or as POSITION=SERIAL");
    }
    by_position = serials;
  }
  std::set<std::string> seen;
  for (std::size_t i = 0; i < fitted.size(); ++i) {
    const std::string& serial = by_position[i];
    if (left_empty[i]) continue;
    if (serial.empty())
      return std::unexpected("--serial: no serial for position '" + fitted[i]->name + "' (give " +
                             fitted[i]->name + "= to leave it empty)");
    if (auto problem = SerialProblem(serial))
      return std::unexpected("--serial (position " + fitted[i]->name + "): " + *problem);
    if (!seen.insert(serial).second)
      return std::unexpected("--serial " + serial + ": the same unit in two positions");
    record.units.push_back({fitted[i]->name, serial, fitted[i]->name + "-" + serial,
                            fitted[i]->can_interface, fitted[i]->inverted, fitted[i]->can_node});
  }
  if (record.units.empty())
    return std::unexpected("--serial: every position is left empty: no unit to run");
  return record;
}

std::vector<bench::UnitSession> FixtureUnitSessions(const FixtureRecord& record,
                                                    const std::filesystem::path& dir) {
  nlohmann::json beside = nlohmann::json::array();
  for (const FixtureUnit& unit : record.units)
    beside.push_back({{"position", unit.position}, {"serial", unit.serial}});
  std::vector<bench::UnitSession> sessions;
  for (const FixtureUnit& unit : record.units) {
    bench::UnitSession session;
    session.serial = unit.serial;
    session.dir = dir / unit.folder;
    session.fixture = nlohmann::json{{session::keys::kFixturePosition, unit.position},
                                     {"inverted", unit.inverted},
                                     {"folder", dir.filename().string()},
                                     {"units", beside}};
    sessions.push_back(std::move(session));
  }
  return sessions;
}

std::expected<void, std::string> WriteFixtureRecord(
    const std::filesystem::path& dir, const FixtureRecord& record,
    const std::vector<bench::SessionResult>& results, const std::string& software_version) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return std::unexpected(dir.string() + ": cannot create: " + ec.message());
  nlohmann::json doc = nlohmann::json::object();
  // A rewrite keeps what the first one wrote (the start time).
  if (IsFixtureFolder(dir)) {
    if (auto earlier = ReadFixtureJson(dir)) doc = std::move(*earlier);
  }
  doc["format"] = "hrgbench-fixture";
  doc["version"] = 1;
  doc["station"] = record.station;
  doc["software"] = software_version;
  if (!doc.contains("started")) doc["started"] = UtcNowText();
  doc["updated"] = UtcNowText();
  nlohmann::json units = nlohmann::json::array();
  for (std::size_t i = 0; i < record.units.size(); ++i) {
    const FixtureUnit& unit = record.units[i];
    nlohmann::json entry{{"position", unit.position}, {"serial", unit.serial},
                         {"folder", unit.folder},     {"can_interface", unit.can_interface},
                         {"can_node", unit.can_node}, {"inverted", unit.inverted},
                         {"outcome", nullptr}};
    if (i < results.size()) {
      entry["outcome"] = {{"kind", std::string(bench::ToString(results[i].outcome))},
                          {"exit_code", results[i].exit_code},
                          {"reason", results[i].reason}};
    }
    units.push_back(std::move(entry));
  }
  doc["units"] = std::move(units);
  if (!record.config_sha256.is_null()) doc["config_sha256"] = record.config_sha256;
  // Durably (temporary, fsync, rename, fsync of the folder): a kill or power cut leaves the old
  // record or the new one, never a torn one.
  if (auto written = session::WriteFileAtomic(dir / kFixtureFile, doc.dump(1) + "\n"); !written)
    return std::unexpected(written.error().ToString());
  session::KillPoint("fixture.record");
  return {};
}

bool IsFixtureFolder(const std::filesystem::path& dir) {
  std::error_code ec;
  return std::filesystem::is_regular_file(dir / kFixtureFile, ec);
}

std::expected<bench::BenchConfigs, std::string> FixtureConfigs(const std::filesystem::path& dir,
                                                               const FixtureRecord& record) {
  if (record.config_sha256.is_object())
    return bench::LoadSavedConfigs(dir, record.config_sha256, FixtureFileName(dir));
  std::string tried;
  for (const FixtureUnit& unit : record.units) {
    auto configs = bench::LoadSavedConfigs(dir / unit.folder);
    if (configs) return configs;
    tried += "\n  " + configs.error();
  }
  return std::unexpected(FixtureFileName(dir) +
                         ": no config copies beside it (a record from before they were kept "
                         "there) and none in a unit's folder:" +
                         tried +
                         "\nThe fixture was stopped before any unit's record was written, so "
                         "nothing was run: remove the folder and start the fixture again");
}

std::expected<FixtureRecord, std::string> ReadFixtureRecord(const std::filesystem::path& dir) {
  const std::string file = FixtureFileName(dir);
  auto read = ReadFixtureJson(dir);
  if (!read) return std::unexpected(read.error());
  const nlohmann::json& doc = *read;
  if (!doc.contains("format") || doc.at("format") != "hrgbench-fixture")
    return std::unexpected(file + ": format: not \"hrgbench-fixture\"");
  FixtureRecord record;
  auto station = StringField(doc, "station", file + ": ");
  if (!station) return std::unexpected(station.error());
  record.station = *station;
  if (doc.contains("config_sha256")) {
    if (!doc.at("config_sha256").is_object())
      return std::unexpected(file + ": config_sha256: not an object");
    record.config_sha256 = doc.at("config_sha256");
  }
  if (!doc.contains("units") || !doc.at("units").is_array() || doc.at("units").empty() ||
      doc.at("units").size() > bench::kMaxFixturePositions)
    return std::unexpected(file + ": units: expected 1 to " +
                           std::to_string(bench::kMaxFixturePositions) + " units");
  const nlohmann::json& units = doc.at("units");
  for (std::size_t i = 0; i < units.size(); ++i) {
    const std::string where = file + ": units[" + std::to_string(i) + "]";
    FixtureUnit unit;
    auto position = StringField(units[i], "position", where);
    auto serial = StringField(units[i], "serial", where);
    auto folder = StringField(units[i], "folder", where);
    auto iface = StringField(units[i], "can_interface", where);
    if (!position) return std::unexpected(position.error());
    if (!serial) return std::unexpected(serial.error());
    if (!folder) return std::unexpected(folder.error());
    if (!iface) return std::unexpected(iface.error());
    // The folder is followed: it must be the one this program names, inside the fixture's.
    if (*folder != *position + "-" + *serial || SerialProblem(*serial))
      return std::unexpected(where + ".folder: '" + *folder + "' is not <position>-<serial>");
    const bool inverted = units[i].contains("inverted") && units[i].at("inverted").is_boolean() &&
                          units[i].at("inverted").get<bool>();
    // Recorded since gyro CAN protocol v2 (several units on one bus); 0 before.
    const int can_node =
        units[i].contains("can_node") && units[i].at("can_node").is_number_integer()
            ? units[i].at("can_node").get<int>()
            : 0;
    record.units.push_back({*position, *serial, *folder, *iface, inverted, can_node});
  }
  return record;
}

std::optional<KeptVerdict> ClosedVerdict(const std::filesystem::path& unit_dir) {
  const auto recorded = session::ReadSessionRecord(unit_dir);
  if (!recorded || !recorded->outcome) return std::nullopt;
  const bench::OutcomeKind kind = recorded->outcome->kind;
  if (!bench::KeepsVerdict(recorded->state == session::keys::kStateClosed, kind))
    return std::nullopt;
  return KeptVerdict{kind == bench::OutcomeKind::kPass, recorded->outcome->reason};
}

}  // namespace hrgbench::app
