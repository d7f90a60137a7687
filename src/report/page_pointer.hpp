#pragma once
// The JSON pointers (RFC 6901) into session.json that the page writes as data-source (the HTML
// contract, hrgbench/report/session_report.hpp), built from the record's key names
// (session/session_record_keys.hpp) so a key is spelled once: Pointer(keys::kOutcome, keys::kKind)
// is the pointer /outcome/kind, RunPointer(2, keys::kEnd, keys::kSamples) is /runs/2/end/samples.
// The keys hold no '~' or '/', so no escaping is needed. Internal to src/report; pure functions.

#include <cstddef>
#include <string>
#include <string_view>

#include "hrgbench/session/session_record_keys.hpp"

namespace hrgbench::report::internal {

inline void AppendPointerPart(std::string& out, std::string_view key) {
  out += '/';
  out += key;
}
inline void AppendPointerPart(std::string& out, std::size_t index) {
  out += '/';
  out += std::to_string(index);
}

// "/part/part/...": a key (const char*, std::string) or an array index (std::size_t).
template <typename... Parts>
std::string Pointer(const Parts&... parts) {
  std::string out;
  (AppendPointerPart(out, parts), ...);
  return out;
}

// A pointer under runs[index] (the run's position in session.json, RunView::index).
template <typename... Parts>
std::string RunPointer(std::size_t index, const Parts&... parts) {
  return Pointer(session::keys::kRuns, index, parts...);
}

// A pointer under outcome.estimate.
template <typename... Parts>
std::string EstimatePointer(const Parts&... parts) {
  return Pointer(session::keys::kOutcome, session::keys::kEstimate, parts...);
}

}  // namespace hrgbench::report::internal
