#include "hrgbench/analysis/verdict_json.hpp"

#include <string>

#include "hrgbench/analysis/estimate_report_json.hpp"

namespace hrgbench::bench {

nlohmann::json VerdictJson(const Verdict& verdict) {
  nlohmann::json checks = nlohmann::json::array();
  for (const FitCheck& c : verdict.fit_checks) {
    checks.push_back({{"run", c.run_id},
                      {"name", c.name},
                      {"status", std::string(ToString(c.status))},
                      {"value", NumberOrNull(c.value)},
                      {"max", NumberOrNull(c.max)},
                      {"message", c.message}});
  }
  nlohmann::json limits = nlohmann::json::array();
  for (const LimitResult& r : verdict.results) {
    limits.push_back({{"quantity", std::string(ToString(r.quantity))},
                      {"status", std::string(ToString(r.status))},
                      {"value", NumberOrNull(r.value)},
                      {"std", NumberOrNull(r.std)},
                      {"min", NumberOrNull(r.min)},
                      {"max", NumberOrNull(r.max)},
                      {"message", r.message}});
  }
  return {{"overall", std::string(ToString(verdict.overall))},
          {"fit_acceptable", verdict.fit_acceptable},
          {"fit_checks", checks},
          {"limits", limits}};
}

}  // namespace hrgbench::bench
