#include <map>

#include "hrgbench/session/session.hpp"

namespace hrgbench::session {

std::vector<estimator::RunData> ToRunData(const Session& session) {
  std::map<int, double> omega_of_id;
  for (const RunEntry& run : session.runs) omega_of_id[run.id] = run.omega_rad_s;
  std::vector<estimator::RunData> out;
  out.reserve(session.loaded_run_ids.size());
  for (std::size_t i = 0; i < session.loaded_run_ids.size() && i < session.loaded_samples.size();
       ++i) {
    estimator::RunData run;
    run.id = session.loaded_run_ids[i];
    const auto omega = omega_of_id.find(run.id);
    run.omega_rad_s = omega != omega_of_id.end() ? omega->second : 0.0;
    run.t_s = session.loaded_samples[i].t_s;
    run.y = session.loaded_samples[i].y;
    out.push_back(std::move(run));
  }
  return out;
}

}  // namespace hrgbench::session
