#include <map>

#include "hrgbench/session/session.hpp"

namespace hrgbench::session {

std::vector<estimator::RunData> ToRunData(const Session& session) {
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
    run.t_s = session.loaded_samples[i].t_s;
    run.y = session.loaded_samples[i].y;
    estimator::ToModelConvention(session.iq_convention, run.y);
    out.push_back(std::move(run));
  }
  return out;
}

}  // namespace hrgbench::session
