#include "tune_data.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <system_error>
#include <vector>

#include "figure_spec.hpp"
#include "hrgbench/session/json_depth.hpp"
#include "report_data.hpp"

namespace hrgbench::report::internal {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

double DegH(double rad_s) { return rad_s * kDegPerHourPerRadPerS; }

json Finite(double x) { return std::isfinite(x) ? json(x) : json(nullptr); }

// The fitted rate error of a hold at wave angle θ (rad): bias + Σ c_n·cos 2nθ + s_n·sin 2nθ.
double FittedError(const json& hold, double theta) {
  double e = NumberAt(hold, "/bias_rad_s");
  const json* c = At(hold, "/cos_rad_s");
  const json* s = At(hold, "/sin_rad_s");
  if (c == nullptr || s == nullptr || !c->is_array() || !s->is_array()) return NAN;
  for (std::size_t n = 0; n < c->size() && n < s->size() && n < 8; ++n) {
    const double a = (*c)[n].is_number() ? (*c)[n].get<double>() : NAN;
    const double b = (*s)[n].is_number() ? (*s)[n].get<double>() : NAN;
    const double k = 2.0 * static_cast<double>(n + 1);
    e += a * std::cos(k * theta) + b * std::sin(k * theta);
  }
  return e;
}

std::string RateLabel(const char* what, const json& hold) {
  char text[64];
  std::snprintf(text, sizeof text, "%s %+.3g rad/s", what, NumberAt(hold, "/omega_set_rad_s"));
  return text;
}

// One figure of the rate error against the wave angle (0 … 180°, where every form repeats), a
// series per hold of each named group.
struct HoldGroup {
  const char* pointer;  // into tune.json: an array of holds
  const char* label;
  bool dashed;
};
json RateErrorFigure(const std::string& name, const std::string& caption, const json& tune,
                     std::initializer_list<HoldGroup> groups) {
  constexpr int kPoints = 181;
  std::vector<double> degrees(kPoints);
  for (int i = 0; i < kPoints; ++i) degrees[static_cast<std::size_t>(i)] = i;
  json figure =
      LineFigure(name, caption, "wave angle θ (electrical, °)", "rate error (°/h)", degrees);
  for (const auto& [pointer, label, dashed] : groups) {
    const json* holds = At(tune, pointer);
    if (holds == nullptr || !holds->is_array()) continue;
    for (std::size_t h = 0; h < holds->size() && h < 16; ++h) {
      std::vector<double> y(kPoints);
      for (int i = 0; i < kPoints; ++i)
        y[static_cast<std::size_t>(i)] = DegH(FittedError((*holds)[h], i / analysis::kDegPerRad));
      figure["series"].push_back(Series(RateLabel(label, (*holds)[h]), y, dashed));
    }
  }
  return figure;
}

}  // namespace

TuneRead ReadTuneRecord(const fs::path& session_dir) {
  const fs::path file = session_dir / "tune.json";
  const std::string where = file.string() + ": ";
  std::error_code ec;
  if (!fs::exists(file, ec)) return {};
  const auto size = fs::file_size(file, ec);
  if (ec) return {std::nullopt, where + "cannot read: " + ec.message()};
  if (size > kMaxTuneJsonBytes)
    return {std::nullopt, where + std::to_string(size) + " bytes; a tuning record has at most " +
                              std::to_string(kMaxTuneJsonBytes)};
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in && !in.eof()) return {std::nullopt, where + "cannot read"};
  const std::string content = text.str();
  if (const auto excess = session::FindJsonDepthExcess(content, kMaxTuneJsonDepth))
    return {std::nullopt, where + "line " + std::to_string(excess->line) + ": nested deeper than " +
                              std::to_string(kMaxTuneJsonDepth) + " levels"};
  json doc = json::parse(content, nullptr, false);
  if (!doc.is_object()) return {std::nullopt, where + "not a JSON object"};
  if (doc.value("format", "") != "hrgbench-tune")
    return {std::nullopt, where + "format: not \"hrgbench-tune\""};
  if (!doc.contains("version") || !doc["version"].is_number_integer() || doc["version"] != 1)
    return {std::nullopt, where + "version: not 1 (this report reads version 1)"};
  for (const char* key : {"verdict", "verification", "holds"}) {
    if (!doc.contains(key) || !doc[key].is_object())
      return {std::nullopt, where + key + ": missing or not an object"};
  }
  return {std::move(doc), {}};
}

json TuneDerived(const json* tune, json* figures) {
  if (tune == nullptr) return nullptr;
  json derived = json::object();
  // Per verified rate, in °/h: before, with p from the free runs (the refine hold at that rate),
  // after and the prediction.
  json rates = json::array();
  const json* verified = At(*tune, "/verification/rates");
  const json* refine = At(*tune, "/holds/refine");
  if (verified != nullptr && verified->is_array()) {
    for (std::size_t i = 0; i < verified->size() && i < 64; ++i) {
      const json& v = (*verified)[i];
      const double omega = NumberAt(v, "/omega_rad_s");
      double with_p = NAN;
      if (refine != nullptr && refine->is_array())
        for (const json& h : *refine)
          if (std::signbit(NumberAt(h, "/omega_set_rad_s")) == std::signbit(omega) &&
              std::abs(NumberAt(h, "/omega_rad_s") - omega) < 1e-3 * std::abs(omega) + 1e-6)
            with_p = NumberAt(h, "/angle_dependent_rms_rad_s");
      const auto& value = Finite;
      rates.push_back(
          {{"omega_rad_s", value(omega)},
           {"before_deg_h", value(DegH(NumberAt(v, "/before_rms_rad_s")))},
           {"with_p_deg_h", value(DegH(with_p))},
           {"after_deg_h", value(DegH(NumberAt(v, "/after_rms_rad_s")))},
           {"predicted_deg_h", value(DegH(NumberAt(v, "/predicted_rms_rad_s")))},
           {"factor", value(NumberAt(v, "/before_rms_rad_s") / NumberAt(v, "/after_rms_rad_s"))}});
    }
  }
  derived["rates"] = rates;
  const auto& value = Finite;
  derived["scale_factor"] = {
      {"bias_deg_h", value(DegH(NumberAt(*tune, "/scale_factor/bias_rad_s")))},
      {"bias_std_deg_h", value(DegH(NumberAt(*tune, "/scale_factor/bias_std_rad_s")))}};
  const double arw = analysis::kDegPerSqrtHourPerRadPerSqrtS;
  derived["zero_rate"] = {
      {"arw_deg_per_sqrt_h", value(arw * NumberAt(*tune, "/zero_rate/arw_rad_per_sqrt_s"))},
      {"arw_lower_deg_per_sqrt_h", value(arw * NumberAt(*tune, "/zero_rate/arw_interval/0"))},
      {"arw_upper_deg_per_sqrt_h", value(arw * NumberAt(*tune, "/zero_rate/arw_interval/1"))},
      {"bias_instability_deg_h", value(DegH(NumberAt(*tune, "/zero_rate/bias_instability_rad_s")))},
      {"bias_instability_lower_deg_h",
       value(DegH(NumberAt(*tune, "/zero_rate/bias_instability_interval/0")))},
      {"bias_instability_upper_deg_h",
       value(DegH(NumberAt(*tune, "/zero_rate/bias_instability_interval/1")))}};
  figures->push_back(RateErrorFigure(
      "tune-rate-error-before",
      "Rate error against the wave angle before tuning (each hold's fitted bias and 2θ harmonics)",
      *tune, {{"/holds/before", "before", false}}));
  figures->push_back(RateErrorFigure(
      "tune-rate-error-after",
      "Rate error against the wave angle after tuning; dashed: with p from the free runs alone",
      *tune,
      {{"/holds/after", "after", false}, {"/holds/refine", "with p from the free runs", true}}));
  // The scale factor: each after hold's mean rate error against the table's rate, and the fit.
  const json* after = At(*tune, "/holds/after");
  if (after != nullptr && after->is_array() && !after->empty()) {
    std::vector<double> omega, error, line;
    const double bias = NumberAt(*tune, "/scale_factor/bias_rad_s");
    const double ppm = NumberAt(*tune, "/scale_factor/error_ppm");
    for (std::size_t i = 0; i < after->size() && i < 64; ++i) {
      const double w = NumberAt((*after)[i], "/omega_rad_s");
      omega.push_back(w * analysis::kDegPerRad);
      error.push_back(DegH(NumberAt((*after)[i], "/bias_rad_s")));
      line.push_back(DegH(bias + ppm * 1e-6 * w));
    }
    json figure = LineFigure("tune-scale-factor",
                             "Mean rate error of each after hold against the table's rate, and "
                             "bias + scale-factor error·Ω",
                             "table rate Ω (°/s)", "mean rate error (°/h)", omega);
    json measured = Series("after holds", error);
    measured["points"] = true;
    figure["series"].push_back(std::move(measured));
    if (std::isfinite(bias) && std::isfinite(ppm))
      figure["series"].push_back(Series("bias + scale-factor error·Ω", line, true));
    figures->push_back(std::move(figure));
  }
  // The zero-rate hold's overlapping Allan deviation with its interval.
  const json* allan = At(*tune, "/zero_rate/allan");
  if (allan != nullptr && allan->is_array() && !allan->empty()) {
    std::vector<double> tau, sigma, lower, upper;
    for (std::size_t i = 0; i < allan->size() && i < 64; ++i) {
      tau.push_back(NumberAt((*allan)[i], "/tau_s"));
      sigma.push_back(DegH(NumberAt((*allan)[i], "/deviation_rad_s")));
      lower.push_back(DegH(NumberAt((*allan)[i], "/lower_rad_s")));
      upper.push_back(DegH(NumberAt((*allan)[i], "/upper_rad_s")));
    }
    json figure = LineFigure("tune-allan",
                             "Zero-rate hold: overlapping Allan deviation σ(τ) of the rate output "
                             "and its 68 % interval (dashed)",
                             "averaging time τ (s)", "σ(τ) (°/h)", tau);
    figure["x_log"] = true;
    figure["y_log"] = true;
    figure["series"].push_back(Series("σ(τ)", sigma));
    figure["series"].push_back(Series("lower", lower, true));
    figure["series"].push_back(Series("upper", upper, true));
    figures->push_back(std::move(figure));
  }
  return derived;
}

}  // namespace hrgbench::report::internal
