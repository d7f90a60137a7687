#include "hrgbench/bench/verdict_json.hpp"

#include <cmath>
#include <string>

namespace hrgbench::bench {
namespace {

nlohmann::json Number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); }

}  // namespace

nlohmann::json VerdictJson(const Verdict& verdict) {
  nlohmann::json checks = nlohmann::json::array();
  for (const FitCheck& c : verdict.fit_checks) {
    checks.push_back({{"run", c.run_id},
                      {"name", c.name},
                      {"status", std::string(ToString(c.status))},
                      {"value", Number(c.value)},
                      {"max", Number(c.max)},
                      {"message", c.message}});
  }
  nlohmann::json limits = nlohmann::json::array();
  for (const LimitResult& r : verdict.results) {
    limits.push_back({{"quantity", std::string(ToString(r.quantity))},
                      {"status", std::string(ToString(r.status))},
                      {"value", Number(r.value)},
                      {"std", Number(r.std)},
                      {"min", Number(r.min)},
                      {"max", Number(r.max)},
                      {"message", r.message}});
  }
  return {{"overall", std::string(ToString(verdict.overall))},
          {"fit_acceptable", verdict.fit_acceptable},
          {"fit_checks", checks},
          {"limits", limits}};
}

}  // namespace hrgbench::bench
