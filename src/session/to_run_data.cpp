#include <map>
#include <type_traits>
#include <utility>

#include "hrgbench/session/session.hpp"

namespace hrgbench::session {

namespace {

// A non-const `session` has its samples taken out, each run's as it is converted (so at no time
// do two copies of a run exist); a const one is copied. Each run as the one-run ToRunData makes it.
template <typename SessionRef>
std::vector<estimator::RunData> Convert(SessionRef& session) {
  std::map<int, const RunEntry*> entry_of_id;
  for (const RunEntry& run : session.runs) entry_of_id[run.id] = &run;
  std::vector<estimator::RunData> out;
  out.reserve(session.loaded_run_ids.size());
  for (std::size_t i = 0; i < session.loaded_run_ids.size() && i < session.loaded_samples.size();
       ++i) {
    RunEntry entry;  // a loaded id missing from `runs` (a hand-built Session): Ω = 0
    entry.id = session.loaded_run_ids[i];
    if (const auto found = entry_of_id.find(entry.id); found != entry_of_id.end())
      entry = *found->second;
    auto& samples = session.loaded_samples[i];
    if constexpr (std::is_const_v<SessionRef>) {
      RunSamples copy;
      copy.t_s = samples.t_s;
      copy.y = samples.y;
      out.push_back(ToRunData(entry, std::move(copy), session.iq_convention));
    } else {
      out.push_back(ToRunData(entry, std::move(samples), session.iq_convention));
    }
  }
  return out;
}

}  // namespace

std::vector<estimator::RunData> ToRunData(const Session& session) { return Convert(session); }

estimator::RunData ToRunData(const RunEntry& entry, RunSamples&& samples,
                             estimator::IqConvention convention) {
  estimator::RunData run;
  run.id = entry.id;
  run.omega_rad_s = entry.omega_rad_s;
  run.omega_std_rad_s = entry.omega_std_rad_s;
  run.t_s = std::move(samples.t_s);
  run.y = std::move(samples.y);
  samples = RunSamples();
  estimator::ToModelConvention(convention, run.y);
  return run;
}

std::vector<estimator::RunData> ToRunData(Session&& session) {
  std::vector<estimator::RunData> out = Convert(session);
  session.loaded_samples.clear();
  session.loaded_run_ids.clear();
  return out;
}

}  // namespace hrgbench::session
