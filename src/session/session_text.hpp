#pragma once
// Internal: the checks of session.json that ReadSession makes (format, version, unit.serial,
// sample_rate_hz, electronics.iq_convention, runs[].{id, file, omega_rad_s, status, end.omega_std_
// error_rad_s}, the depth bound before parsing), on text already read within kMaxSessionJsonBytes.
// Shared by ReadSession and ReadSessionRecord so the bounds and the checks exist once.

#include <expected>
#include <filesystem>
#include <string>
#include <vector>

#include "hrgbench/session/session.hpp"

namespace hrgbench::session::internal {

std::expected<Session, SessionError> ReadSessionJson(const std::string& text,
                                                     const std::filesystem::path& file);

// "run 3 skipped: status 'aborted'" per run not complete; runs left "planned" of a plan cut short
// (the sequence's [adaptive]) are not warned about.
std::vector<std::string> RunStatusWarnings(const std::vector<RunEntry>& runs, bool plan_cut_short);

}  // namespace hrgbench::session::internal
