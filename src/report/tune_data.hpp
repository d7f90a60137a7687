#pragma once
// The tuning's part of the report: <session>/tune.json (hrg-bench tune, docs/bench/tuning.md) read
// with its bounds, and what the page shows of it — the per-rate rate errors in °/h, the scale
// factor over the rates, the zero-rate hold's Allan deviation — as derived numbers and figure
// specs of the report-data block (derived.tune; figures tune-rate-error-before,
// tune-rate-error-after, tune-scale-factor, tune-allan). Internal to src/report.
//
// The rate error against the wave angle is drawn from each hold's fitted bias and harmonics of 2θ
// (tune.json keeps the fits, not the samples): what the verification measured, as a curve.

#include <cstddef>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "hrgbench/analysis/gyro_units.hpp"

namespace hrgbench::report::internal {

// tune.json's bounds: a record of a few holds is ~20 kB; the depth of its deepest value is 4.
inline constexpr std::size_t kMaxTuneJsonBytes = std::size_t{4} << 20;
inline constexpr std::size_t kMaxTuneJsonDepth = 16;

struct TuneRead {
  std::optional<nlohmann::json> record;  // the document, when there is a readable one
  std::string warning;                   // non-empty: one that is there and cannot be read, why
};
// nullopt record and no warning: the session was not tuned.
TuneRead ReadTuneRecord(const std::filesystem::path& session_dir);

// derived.tune (null without a record) and the figures, appended to `figures`.
nlohmann::json TuneDerived(const nlohmann::json* tune, nlohmann::json* figures);

using analysis::kDegPerHourPerRadPerS;

}  // namespace hrgbench::report::internal
