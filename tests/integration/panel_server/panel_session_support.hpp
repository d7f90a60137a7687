#pragma once
// A panel that runs real sessions: hrg-bench (HRGBENCH_BIN_DIR) on the simulated station at real
// time, for the tests that need a session to abort.

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "panel_test_client.hpp"

namespace hrgbench::testing::panel {

inline const fs::path kBench = fs::path(HRGBENCH_BIN_DIR) / "hrg-bench";

// The simulated station paced at `time_scale` simulated seconds per wall-clock second (its shipped
// file runs as fast as it can). Its results go to a store in `dir`.
inline fs::path PacedStation(const fs::path& dir, double time_scale,
                             const std::string& shipped = "station-sim.toml") {
  std::ifstream in(kConfigs / shipped);
  std::stringstream text;
  text << in.rdbuf();
  std::string toml = text.str();
  const std::string fast = "faster_than_real_time = true";
  toml.replace(toml.find(fast), fast.size(),
               "faster_than_real_time = false\ntime_scale = " + std::to_string(time_scale));
  const std::string store = "sqlite://../build/out/results.sqlite";
  toml.replace(toml.find(store), store.size(), "sqlite://" + (dir / "results.sqlite").string());
  fs::create_directories(dir);
  const fs::path path = dir / "station-paced.toml";
  std::ofstream(path) << toml;
  return path;
}

// At real time a session lasts minutes, so an Abort always finds it running.
inline fs::path RealTimeStation(const fs::path& dir) { return PacedStation(dir, 1.0); }

inline nlohmann::json Json(const std::string& text) {
  return nlohmann::json::parse(text, nullptr, false);
}

// The panel's session as /api/state says, or null when the panel did not answer.
inline nlohmann::json SessionState(const Panel& panel) {
  const Reply reply = Exchange(panel.port(), Get("/api/state", panel.port()));
  const nlohmann::json state = Json(reply.body);
  return reply.status == 200 && state.is_object() ? state["session"] : nlohmann::json();
}

// Waits (hang guard: `guard`) until the panel's session has ended; its state then, or null.
inline nlohmann::json WaitForSessionEnd(const Panel& panel, std::chrono::seconds guard) {
  nlohmann::json session;
  const auto end = std::chrono::steady_clock::now() + guard;
  while (std::chrono::steady_clock::now() < end) {
    session = SessionState(panel);
    if (session.is_object() && !session.value("running", true)) break;
    std::this_thread::sleep_for(100ms);
  }
  return session;
}

inline nlohmann::json ReadRecord(const fs::path& folder) {
  std::ifstream in(folder / "session.json");
  return nlohmann::json::parse(in, nullptr, false);
}

}  // namespace hrgbench::testing::panel
