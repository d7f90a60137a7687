#pragma once
// Hand-made session records for tests of what reads a record: a test writes the few keys it is
// about, and reads the document through the record's one reader (session::ReadSessionRecord), as
// every program does. CompleteSessionDocument adds what the reader requires and the test does not
// care about (format, version, unit.serial, sample_rate_hz; each run's file, omega_rad_s and
// status), never overriding a key the test wrote. Header-only; the test links hrgbench_session.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "hrgbench/session/session.hpp"
#include "hrgbench/session/session_record.hpp"

namespace hrgbench::testing {

// `partial` (an object) with the keys the reader requires added where absent.
inline nlohmann::json CompleteSessionDocument(nlohmann::json partial) {
  if (!partial.is_object()) partial = nlohmann::json::object();
  const auto fill = [](nlohmann::json& object, const char* key, nlohmann::json value) {
    if (!object.contains(key)) object[key] = std::move(value);
  };
  fill(partial, "format", session::kFormatName);
  fill(partial, "version", session::kFormatVersion);
  fill(partial, "unit", {{"serial", "HRG-TEST"}});
  fill(partial, "sample_rate_hz", 1000.0);
  fill(partial, "runs", nlohmann::json::array());
  int next_id = 1;
  for (nlohmann::json& run : partial["runs"]) {
    fill(run, "id", next_id);
    const int id = run["id"].is_number_integer() ? run["id"].get<int>() : next_id;
    next_id = id + 1;
    fill(run, "file", "runs/run-" + std::to_string(id) + ".csv");
    fill(run, "omega_rad_s", 0.0);
    fill(run, "status", "complete");
  }
  return partial;
}

// The record of CompleteSessionDocument(partial); a test failure (and an empty record) when the
// reader rejects it.
inline session::SessionRecord RecordOf(const nlohmann::json& partial) {
  auto record = session::ReadSessionRecord(CompleteSessionDocument(partial), "test/session.json");
  if (!record) {
    ADD_FAILURE() << "the record's reader rejected the test's document: "
                  << record.error().ToString();
    return session::SessionRecord{};
  }
  return *std::move(record);
}

}  // namespace hrgbench::testing
