#include <map>
#include <type_traits>
#include <utility>

#include "hrgbench/session/session.hpp"

namespace hrgbench::session {

namespace {

// A non-const `session` has its samples taken out, each run's as it is converted (so at no time
// do two copies of a run exist); a const one is copied.
template <typename SessionRef>
std::vector<estimator::RunData> Convert(SessionRef& session) {
  std::map<int, const RunEntry*> entry_of_id;
  for (const RunEntry& run : session.runs) entry_of_id[run.id] = &run;
  std::vector<estimator::RunData> out;
  out.reserve(session.loaded_run_ids.size());
  for (std::size_t i = 0; i < session.loaded_run_ids.size() && i < session.loaded_samples.size();
       ++i) {
    estimator::RunData run;
    run.id = session.loaded_run_ids[i];
    if (const auto entry = entry_of_id.find(run.id); entry != entry_of_id.end()) {
      run.omega_rad_s = entry->second->omega_rad_s;
      run.omega_std_rad_s = entry->second->omega_std_rad_s;
    }
    auto& samples = session.loaded_samples[i];
    if constexpr (std::is_const_v<SessionRef>) {
      run.t_s = samples.t_s;
      run.y = samples.y;
    } else {
      run.t_s = std::move(samples.t_s);
      run.y = std::move(samples.y);
      samples = RunSamples();  // its extra columns too
    }
    estimator::ToModelConvention(session.iq_convention, run.y);
    out.push_back(std::move(run));
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
