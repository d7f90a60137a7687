#pragma once
// Turning a simulation spec and its simulated runs into a session directory, with the truth and the
// provenance recorded beside the data (STYLE rule 12): session.json "simulation" holds δ, ξ, σ,
// seed, the generator and every run's plan; "software_version" and "spec_sha256" say what produced
// it.

#include <expected>
#include <filesystem>
#include <string>
#include <vector>

#include "hrgbench/config/sim_spec.hpp"
#include "hrgbench/estimator/run_data.hpp"
#include "hrgbench/session/session.hpp"

namespace hrgbench::app {

// Name of the generator recorded in the session.
inline constexpr const char* kSimGenerator =
    "hrgbench estimator::SimulateRuns: closed-form exp(A t) propagation, xoshiro256** + Box-Muller "
    "noise, runs on consecutive sub-streams of the seed";

struct SimProvenance {
  std::string software_version;  // git describe of the build
  std::string spec_sha256;       // hex SHA-256 of the spec file's bytes
};

// The session (typed fields and document) for `runs`, simulated from `spec`; runs are numbered 1..n
// and stored as runs/run-NNN.csv.
session::Session MakeSimSession(const SimSpec& spec, const std::vector<estimator::RunData>& runs,
                                const SimProvenance& provenance);

// Writes the run CSVs, then session.json (last, so a session.json never lists a missing file).
// Refuses a non-empty existing directory unless `force`; with `force`, an earlier session.json and
// runs/run-*.csv there are removed first (nothing else is touched). The error is one line for the
// operator.
std::expected<void, std::string> WriteSimSession(const std::filesystem::path& dir,
                                                 const session::Session& session,
                                                 const std::vector<estimator::RunData>& runs,
                                                 bool force);

}  // namespace hrgbench::app
