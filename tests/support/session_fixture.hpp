#pragma once
// Closed session folders written directly (no bench run): session.json with the keys the results
// database reads, and known values, so each query's answer can be derived by hand. Provenance:
// every value is a function of the arguments below, nothing random.

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

namespace hrgbench::testing {

struct FixtureSession {
  std::string serial = "SN-0001";
  std::string station = "st-1";
  std::string started_utc = "2026-11-02T08:00:00Z";  // a Monday of ISO week 45
  long long started_ns = 1;
  std::string outcome = "PASS";
  double delta1 = -1e-3;
  double tau_s = 1000.0;
  std::string delta1_status = "PASS";  // its limit verdict; "" for none
  double delta1_min = -1.2e-3, delta1_max = -0.8e-3;
  std::string operator_name = "";
  int runs = 3;
  std::string reason = "";            // "" : "fixture " + outcome
  std::string fixture_position = "";  // a fixture's unit: fixture.position
  // Config copies written beside session.json (config/sequence.toml, config/limits.toml), as the
  // bench saves them; "" writes none.
  std::string sequence_toml = "", limits_toml = "";
  std::string sequence_sha256 = "bb";
};

inline nlohmann::json FixtureDocument(const FixtureSession& f) {
  using nlohmann::json;
  json doc;
  doc["format"] = "hrgbench-session";
  doc["version"] = 1;
  doc["unit"] = {{"serial", f.serial}};
  doc["station"] = {{"name", f.station}};
  if (!f.operator_name.empty()) doc["operator"] = {{"name", f.operator_name}};
  doc["software"] = {{"version", "fixture"}};
  doc["config_sha256"] = {{"station", "aa"}, {"sequence", f.sequence_sha256}, {"limits", "cc"}};
  if (!f.fixture_position.empty()) doc["fixture"] = {{"position", f.fixture_position}};
  doc["started"] = {{"utc", f.started_utc}, {"monotonic_ns", f.started_ns}};
  doc["ended"] = {{"utc", f.started_utc}, {"monotonic_ns", f.started_ns + 1000}};
  doc["sample_rate_hz"] = 100.0;
  doc["state"] = "closed";
  json runs = json::array();
  for (int i = 1; i <= f.runs; ++i) {
    char file[32];
    std::snprintf(file, sizeof file, "runs/run-%03d.csv", i);
    runs.push_back({{"id", i},
                    {"file", file},
                    {"omega_rad_s", 0.1 * i},
                    {"status", "complete"},
                    {"plan", {{"commanded_omega_rad_s", 0.1 * i}, {"free_run_s", 10.0}}},
                    {"start", {{"earth_rate_rad_s", 6e-5}, {"temperature_c", 25.0}}},
                    {"end",
                     {{"samples", 1000},
                      {"sequence_gaps", i - 1},
                      {"kernel_drops", 0},
                      {"bad_frames", 0},
                      {"omega_std_error_rad_s", 1e-9},
                      {"temperature_start_c", 25.0},
                      {"temperature_end_c", 25.5},
                      {"frequency_start_hz", 5000.0},
                      {"frequency_end_hz", 5000.1}}}});
  }
  doc["runs"] = runs;
  json estimate = {{"delta", {f.delta1, 0.3, 0.0, 0.0, 0.0, 0.0}},
                   {"delta_std", {1e-9, 1e-9, 1e-9, 1e-9, 1e-9, 1e-9}},
                   {"xi", {0.01, 0.0, 0.0, 0.0}},
                   {"xi_std", {1e-8, 1e-8, 1e-8, 1e-8}},
                   {"residual_rms", 1e-4},
                   {"warnings", {"fixture warning"}},
                   {"engineering",
                    {{"quantities",
                      {{{"name", "tau_s"}, {"value", f.tau_s}, {"std", 0.5}, {"unit", "s"}},
                       {{"name", "frequency_axis_deg"},
                        {"value", nullptr},
                        {"std", nullptr},
                        {"unit", "deg"}}}}}}};
  json limits = json::array();
  if (!f.delta1_status.empty()) {
    limits.push_back({{"quantity", "delta1"},
                      {"min", f.delta1_min},
                      {"max", f.delta1_max},
                      {"value", f.delta1},
                      {"std", 1e-9},
                      {"status", f.delta1_status},
                      {"message", "fixture"}});
  }
  doc["outcome"] = {{"kind", f.outcome},
                    {"reason", f.reason.empty() ? "fixture " + f.outcome : f.reason},
                    {"exit_code", f.outcome == "PASS" ? 0 : 1},
                    {"estimate", estimate},
                    {"verdict", {{"limits", limits}}}};
  return doc;
}

// Writes <dir>/session.json as the bench's writer does (sorted keys, 2-space indent, newline).
inline void WriteFixtureSession(const std::filesystem::path& dir, const FixtureSession& f) {
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "session.json") << FixtureDocument(f).dump(2) << '\n';
  if (!f.sequence_toml.empty() || !f.limits_toml.empty())
    std::filesystem::create_directories(dir / "config");
  if (!f.sequence_toml.empty()) std::ofstream(dir / "config" / "sequence.toml") << f.sequence_toml;
  if (!f.limits_toml.empty()) std::ofstream(dir / "config" / "limits.toml") << f.limits_toml;
}

}  // namespace hrgbench::testing
