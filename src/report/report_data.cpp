#include "report_data.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "figure_spec.hpp"
#include "hrgbench/analysis/estimate_report_json.hpp"
#include "hrgbench/estimator/cramer_rao.hpp"
#include "hrgbench/estimator/model.hpp"
#include "hrgbench/estimator/physical_parameters.hpp"
#include "hrgbench/report/decimate.hpp"
#include "hrgbench/session/session_record_keys.hpp"
#include "html_text.hpp"
#include "page_pointer.hpp"
#include "residual_figures.hpp"
#include "run_conditions.hpp"
#include "sample_timing.hpp"
#include "tune_data.hpp"

namespace hrgbench::report::internal {
namespace {

using estimator::kNaN;
using nlohmann::json;

// One run's figures: channels with the model, residuals, orbit elements and principal forms, each
// data series next to the model's.
void RunFigures(const RunView& run, const estimator::Xi& xi, std::size_t max_points,
                const session::SessionRecord& record, double noise_sigma, json* figures) {
  const estimator::RunData& d = run.data;
  const auto n = static_cast<Eigen::Index>(d.t_s.size());
  const MinMaxDecimator decimator(d.t_s, max_points);
  const bool have_model = run.fitted_y.rows() == n && n > 0;
  const std::string id = std::to_string(run.id);
  const std::string of_run = " of run " + id;

  json channels = LineFigure("channels-run-" + id,
                             "Run " + id +
                                 ": the four channels y1…y4 as recorded and the fitted "
                                 "model (dashed)",
                             "t [s]", "y", decimator.Times());
  json residuals = LineFigure("residuals-run-" + id,
                              "Run " + id + ": residuals y − ŷ of the fitted model, per channel",
                              "t [s]", "y − ŷ", decimator.Times());
  json orbit = LineFigure(
      "orbit-run-" + id,
      "Run " + id +
          ": orbit elements a, b (amplitude, quadrature; left) and the wave angle θ on the shell "
          "(half the model's electrical angle, degrees, unwrapped; right) from the data "
          "(undistorted by ξ̂, solid) and the model (dashed)",
      "t [s]", "a, b", decimator.Times());
  orbit["y2_label"] = "θ on the shell [°]";
  json forms = LineFigure("forms-run-" + id,
                          "Run " + id +
                              ": principal forms Ac, As, K, S (MODEL.md) from the data "
                              "and the model (dashed)",
                          "t [s]", "Ac, As, K, S", decimator.Times());
  const char* y_names[] = {"y1", "y2", "y3", "y4"};
  for (int c = 0; c < 4; ++c)
    channels["series"].push_back(Series(y_names[c], decimator.Apply(d.y.data() + c, 4)));
  // Orbit elements and forms of the data: x = (I + C(ξ̂))⁻¹·y, exact.
  Eigen::Matrix<double, 7, Eigen::Dynamic> data_elements(7, n);
  Eigen::Matrix<double, 7, Eigen::Dynamic> model_elements(7, have_model ? n : 0);
  const estimator::Xi xi_used = xi.allFinite() ? xi : estimator::Xi::Zero();
  // (I + C(ξ̂))⁻¹ once: the same linear map as UndistortExact's per-sample complex solve, whose
  // checked complex division was a tenth of the page's time over 600 000 samples.
  const Eigen::Matrix4d undistort =
      (Eigen::Matrix4d::Identity() + estimator::DistortionMatrix(xi_used)).inverse();
  for (Eigen::Index k = 0; k < n; ++k) {
    const estimator::State x = undistort * d.y.col(k);
    const estimator::Orbit o = estimator::StateToOrbit(x);
    const estimator::Forms z = estimator::QuadraticForms(x);
    data_elements.col(k) << o.a, o.b, o.theta_rad, z;
    if (have_model) {
      const estimator::State xm = run.fitted_x.row(k).transpose();
      const estimator::Orbit om = estimator::StateToOrbit(xm);
      model_elements.col(k) << om.a, om.b, om.theta_rad, estimator::QuadraticForms(xm);
    }
  }
  // θ is defined modulo π (StateToOrbit returns (−π/2, π/2]): unwrapped along the run, so a
  // precessing wave is a line, not a saw-tooth.
  const auto unwrap = [n](Eigen::Matrix<double, 7, Eigen::Dynamic>* elements) {
    for (Eigen::Index k = 1; k < n && elements->cols() == n; ++k) {
      const double step = (*elements)(2, k) - (*elements)(2, k - 1);
      (*elements)(2, k) -= std::numbers::pi * std::round(step / std::numbers::pi);
    }
  };
  unwrap(&data_elements);
  unwrap(&model_elements);
  // θ on the shell in degrees: the standing wave turns half the electrical angle.
  constexpr double kShellDegPerRad = 0.5 * 180.0 / std::numbers::pi;
  data_elements.row(2) *= kShellDegPerRad;
  model_elements.row(2) *= kShellDegPerRad;
  const char* orbit_names[] = {"a", "b", "θ"};
  const char* form_names[] = {"Ac", "As", "K", "S"};
  for (int e = 0; e < 2; ++e)
    orbit["series"].push_back(Series(orbit_names[e], decimator.Apply(data_elements.data() + e, 7)));
  orbit["series"].push_back(RightSeries("θ", decimator.Apply(data_elements.data() + 2, 7)));
  for (int e = 0; e < 4; ++e)
    forms["series"].push_back(
        Series(form_names[e], decimator.Apply(data_elements.data() + 3 + e, 7)));
  // What moves in a run, at the scale it moves: with a long decay time the channels look flat,
  // but the amplitude's relative decay and the wave's turn are what δ is estimated from. Both
  // relative to the model's start (the data's first sample carries its noise into every point).
  json motion = LineFigure("motion-run-" + id,
                           "Run " + id +
                               ": what moves — the amplitude's relative change a(t)/a(0) − 1 "
                               "(left) and the wave's turn θ(t) − θ(0) on the shell in degrees "
                               "(right), data (solid) and model (dashed); a(0), θ(0) of the " +
                               std::string(have_model ? "fitted model" : "first sample"),
                           "t [s]", "a(t)/a(0) − 1", decimator.Times());
  motion["y2_label"] = "θ(t) − θ(0) on the shell [°]";
  if (n > 0) {
    const auto& reference = have_model ? model_elements : data_elements;
    const double a0 = reference(0, 0), theta0 = reference(2, 0);
    const auto relative = [&](const Eigen::Matrix<double, 7, Eigen::Dynamic>& elements) {
      Eigen::Matrix<double, 2, Eigen::Dynamic> out(2, n);
      out.row(0) = (elements.row(0).array() / a0 - 1.0).matrix();
      out.row(1) = (elements.row(2).array() - theta0).matrix();
      return out;
    };
    const Eigen::Matrix<double, 2, Eigen::Dynamic> data_motion = relative(data_elements);
    motion["series"].push_back(Series("a/a(0) − 1", decimator.Apply(data_motion.data(), 2)));
    motion["series"].push_back(RightSeries("θ − θ(0)", decimator.Apply(data_motion.data() + 1, 2)));
    if (have_model) {
      const Eigen::Matrix<double, 2, Eigen::Dynamic> model_motion = relative(model_elements);
      motion["series"].push_back(
          Series("a/a(0) − 1 model", decimator.Apply(model_motion.data(), 2), true));
      motion["series"].push_back(
          RightSeries("θ − θ(0) model", decimator.Apply(model_motion.data() + 1, 2), true));
    }
  }
  json what_the_fit_left = json::array();  // the residual histogram and spectrum
  if (have_model) {
    for (int c = 0; c < 4; ++c)
      channels["series"].push_back(Series(std::string(y_names[c]) + " model",
                                          decimator.Apply(run.fitted_y.data() + c * n, 1), true));
    const Eigen::Matrix4Xd e = d.y - run.fitted_y.transpose();
    for (int c = 0; c < 4; ++c)
      residuals["series"].push_back(Series(std::string(y_names[c]) + " − ŷ" + std::to_string(c + 1),
                                           decimator.Apply(e.data() + c, 4)));
    // σ̂ of this run as its fit recorded it, else the session's; the sample rate as recorded, else
    // the run's own mean step.
    double sigma = noise_sigma;
    const session::EstimateRecord* estimate =
        record.outcome && record.outcome->estimate ? &*record.outcome->estimate : nullptr;
    for (std::size_t k = 0; estimate != nullptr && k < estimate->fit_runs.size(); ++k)
      if (estimate->fit_runs[k].run == run.id && std::isfinite(estimate->fit_runs[k].noise_sigma))
        sigma = estimate->fit_runs[k].noise_sigma;
    double fs = record.sample_rate_hz;
    if (!(fs > 0.0) && n > 1) fs = static_cast<double>(n - 1) / (d.t_s.back() - d.t_s.front());
    AddResidualFigures(run.id, e, sigma, fs, &what_the_fit_left);
    for (int k = 0; k < 2; ++k)
      orbit["series"].push_back(Series(std::string(orbit_names[k]) + " model",
                                       decimator.Apply(model_elements.data() + k, 7), true));
    orbit["series"].push_back(
        RightSeries("θ model", decimator.Apply(model_elements.data() + 2, 7), true));
    for (int k = 0; k < 4; ++k)
      forms["series"].push_back(Series(std::string(form_names[k]) + " model",
                                       decimator.Apply(model_elements.data() + 3 + k, 7), true));
  } else {
    residuals["caption"] = "Run " + id + ": no fitted model" + of_run + ", so no residuals";
  }
  figures->push_back(std::move(channels));
  figures->push_back(std::move(motion));
  figures->push_back(std::move(residuals));
  for (json& f : what_the_fit_left) figures->push_back(std::move(f));
  figures->push_back(std::move(orbit));
  figures->push_back(std::move(forms));
  if (run.index < record.runs.size())
    AddConditionsFigure(run, record.runs[run.index], decimator, figures);
}

// Capture quality the report computes from the samples and the record (the recorded counters
// themselves are shown from session.json).
json CaptureQuality(const RunView& run, const session::SessionRecord& record) {
  json q = json::object();
  const std::vector<double>& t = run.data.t_s;
  q["samples_loaded"] = t.size();
  if (t.size() >= 2) {
    const SampleTiming timing = MeasureSampleTiming(t, record.sample_rate_hz);
    q["sample_interval_s"] = bench::NumberOrNull(timing.interval_s);
    q["sample_time_jitter_std_s"] = bench::NumberOrNull(timing.jitter_std_s);
    q["sample_time_jitter_max_s"] = bench::NumberOrNull(timing.jitter_max_s);
    q["time_gaps"] = timing.long_steps;  // steps longer than 1.5 nominal intervals
  }
  // NaN (not measured, or no end recorded) gives null.
  bench::RunEnd end;
  if (run.index < record.runs.size() && record.runs[run.index].end)
    end = record.runs[run.index].end->values;
  q["temperature_drift_c"] = bench::NumberOrNull(end.temperature_end_c - end.temperature_start_c);
  q["frequency_drift_hz"] = bench::NumberOrNull(end.frequency_end_hz - end.frequency_start_hz);
  AddRunConditions(run, &q);
  return q;
}

// δ for the anisotropy: the recorded estimate when there is one, else the re-run's.
// The estimate of record, or nullptr.
const session::EstimateRecord* OfRecord(const session::SessionRecord& record) {
  return record.outcome && record.outcome->estimate ? &*record.outcome->estimate : nullptr;
}

bool RecordedDelta(const session::SessionRecord& record, estimator::Delta* delta) {
  const session::EstimateRecord* estimate = OfRecord(record);
  if (estimate == nullptr) return false;
  for (int j = 0; j < 6; ++j) {
    const double v = estimate->delta[static_cast<std::size_t>(j)];
    if (!std::isfinite(v)) return false;
    (*delta)[j] = v;
  }
  return true;
}

double MeanResonantFrequency(const session::SessionRecord& record) {
  const session::EstimateRecord* estimate = OfRecord(record);
  const double engineering = estimate != nullptr ? estimate->engineering_frequency_hz : kNaN;
  if (std::isfinite(engineering) && engineering > 0.0) return engineering;
  double sum = 0.0;
  int count = 0;
  for (const session::RunRecord& run : record.runs) {
    const double f = run.start ? run.start->values.resonant_frequency_hz : kNaN;
    if (std::isfinite(f) && f > 0.0) {
      sum += f;
      ++count;
    }
  }
  return count > 0 ? sum / count : kNaN;
}

// The engineering quantity named `name` in the record, or nullptr.
const session::EngineeringQuantityRecord* EngineeringQuantity(const session::SessionRecord& record,
                                                              const std::string& name) {
  const session::EstimateRecord* estimate = OfRecord(record);
  if (estimate == nullptr) return nullptr;
  for (const session::EngineeringQuantityRecord& q : estimate->engineering)
    if (q.name == name) return &q;
  return nullptr;
}

// "value ± std unit" of an engineering quantity, written to the std's precision.
std::string MetrologicalText(const session::EngineeringQuantityRecord& quantity) {
  const ValueWithStd t = Metrological(quantity.value, quantity.std);
  std::string unit = quantity.unit;
  if (unit == "deg") unit = "°";
  const std::string space = unit.empty() || unit == "°" ? "" : " ";
  return std::isfinite(quantity.std) ? t.value + " ± " + t.std + space + unit
                                     : t.value + space + unit;
}

json Anisotropy(const ReportInputs& inputs, json* figures) {
  estimator::Delta delta;
  std::string source = EstimatePointer(session::keys::kDelta);
  if (!RecordedDelta(inputs.record, &delta)) {
    if (!inputs.summary || !inputs.summary->delta.allFinite()) return nullptr;
    delta = inputs.summary->delta;
    source = Pointer("derived", session::keys::kEstimate, session::keys::kDelta);
  }
  const double f0 = MeanResonantFrequency(inputs.record);
  const estimator::ResonatorParameters r =
      estimator::ResonatorFromDelta(delta, std::isfinite(f0) ? f0 : 1.0);
  json a{{"delta_source", source},
         {"frequency_hz", bench::NumberOrNull(f0)},
         {"decay_time_s", bench::NumberOrNull(r.decay_time_s)},
         {"quality_factor", bench::NumberOrNull(std::isfinite(f0) ? r.QualityFactor() : kNaN)},
         {"frequency_split_hz", bench::NumberOrNull(r.frequency_split_hz)},
         {"frequency_axis_electrical_rad", bench::NumberOrNull(r.frequency_axis_rad)},
         {"frequency_axis_shell_deg",
          bench::NumberOrNull(r.frequency_axis_rad / 2 * 180 / std::numbers::pi)},
         {"damping_anisotropy_per_s", bench::NumberOrNull(r.damping_anisotropy_per_s)},
         {"damping_axis_electrical_rad", bench::NumberOrNull(r.damping_axis_rad)},
         {"damping_axis_shell_deg",
          bench::NumberOrNull(r.damping_axis_rad / 2 * 180 / std::numbers::pi)}};
  // The polar picture, on the shell (angles half the electrical ones): the two frequency axes
  // (unit length) and the two damping axes (0.75), a circle for the shell. An axis the record
  // calls undetermined (its split not significantly different from zero) is not drawn: its angle
  // is noise. Without the record's engineering list the report's own axes are drawn, marked so.
  std::string caption = "Anisotropy on the shell (angles half the model's electrical ones)";
  json figure{{"name", "anisotropy"}, {"type", "line"},         {"x_label", "x"},
              {"y_label", "y"},       {"y_log", false},         {"equal_aspect", true},
              {"x", json::array()},   {"series", json::array()}};
  const auto axis = [&](const std::string& label, double angle_rad, double length, bool model) {
    const double c = length * std::cos(angle_rad), s = length * std::sin(angle_rad);
    figure["series"].push_back(json{{"label", label},
                                    {"x", Numbers({-c, 0.0, c})},
                                    {"y", Numbers({-s, 0.0, s})},
                                    {"model", model}});
  };
  const double quarter = std::numbers::pi / 4;  // 90° electrical = 45° on the shell
  const double deg = std::numbers::pi / 180;
  struct AxisPair {
    const char* split_name;  // engineering quantity names
    const char* axis_name;
    const char* what;  // "frequency", "damping"
    const char* split_symbol;
    const char* angle_symbol;
    const char* first;  // the axis the angle names, and the other one 45° on
    const char* second;
    double derived_split;
    const char* derived_unit;
    double derived_axis_shell_rad;
    double length;
  };
  const AxisPair pairs[] = {
      {"frequency_split_mhz", "frequency_axis_deg", "frequency", "Δf", "θω", "high-frequency axis",
       "low-frequency axis", r.frequency_split_hz, "Hz", r.frequency_axis_rad / 2, 1.0},
      {"damping_split_per_s", "damping_axis_deg", "damping", "Δ(1/τ)", "θτ", "fast-decay axis",
       "slow-decay axis", r.damping_anisotropy_per_s, "1/s", r.damping_axis_rad / 2, 0.75}};
  for (const AxisPair& p : pairs) {
    const session::EngineeringQuantityRecord* split =
        EngineeringQuantity(inputs.record, p.split_name);
    const session::EngineeringQuantityRecord* angle =
        EngineeringQuantity(inputs.record, p.axis_name);
    // The legend names the axes only: their numbers go into the caption, which wraps. A legend
    // label as long as "high-frequency axis: Δf = … ± … mHz at θω = … ± …° on the shell" is
    // wider than the square chart once its plot area is padded square, and was cut off.
    if (angle == nullptr || split == nullptr) {
      axis(p.first, p.derived_axis_shell_rad, p.length, false);
      axis(std::string(p.second) + " (+45°)", p.derived_axis_shell_rad + quarter, p.length, false);
      caption += "; " + std::string(p.first) + " at " +
                 Readable(p.derived_axis_shell_rad * 180 / std::numbers::pi) + "° on the shell, " +
                 p.split_symbol + " = " + Readable(p.derived_split) + " " + p.derived_unit +
                 " (derived by the report; significance not recorded)";
      continue;
    }
    const double angle_deg = angle->value;
    if (!angle->determined || !std::isfinite(angle_deg)) {
      caption += "; " + std::string(p.what) +
                 " axis undetermined (split not significant: " + p.split_symbol + " = " +
                 MetrologicalText(*split) + ")";
      continue;
    }
    axis(p.first, angle_deg * deg, p.length, false);
    axis(std::string(p.second) + " (+45°)", angle_deg * deg + quarter, p.length, false);
    caption += "; " + std::string(p.first) + " at " + p.angle_symbol + " = " +
               MetrologicalText(*angle) + " on the shell, " + p.split_symbol + " = " +
               MetrologicalText(*split) + " (the " + p.second + " at " + p.angle_symbol + " + 45°)";
  }
  caption += "; from δ at " + source;
  if (OfRecord(inputs.record) != nullptr && !OfRecord(inputs.record)->engineering.empty())
    caption += " and outcome.estimate.engineering";
  figure["caption"] = caption;
  std::vector<double> cx, cy;
  for (int k = 0; k <= 72; ++k) {
    cx.push_back(std::cos(k * std::numbers::pi / 36));
    cy.push_back(std::sin(k * std::numbers::pi / 36));
  }
  figure["series"].push_back(
      json{{"label", "shell"}, {"x", Numbers(cx)}, {"y", Numbers(cy)}, {"model", true}});
  figures->push_back(std::move(figure));
  return a;
}

// The Cramér–Rao bound of the session's own design: the runs as recorded (Ω, duration, sample
// rate), their fitted initial orbits, the estimate as the truth and σ̂ as the noise.
json CramerRao(const ReportInputs& inputs, json* figures) {
  if (!inputs.summary || !inputs.summary->IsUsable()) return nullptr;
  const estimator::EstimateSummary& s = *inputs.summary;
  estimator::DesignSpec design;
  design.delta = s.delta;
  design.xi = s.xi;
  design.sigma = s.noise_sigma;
  design.xi_unknown = s.xi_estimated;
  design.phase_degree = s.diagnostics.phase_degree;
  for (const RunView& run : inputs.runs) {
    if (!run.loaded) continue;
    const std::size_t n = run.samples;  // the samples themselves are gone by now
    const auto nuisance =
        std::find_if(s.run_nuisance.begin(), s.run_nuisance.end(),
                     [&](const estimator::RunNuisanceEstimate& e) { return e.run_id == run.id; });
    if (n < 2 || nuisance == s.run_nuisance.end()) continue;
    estimator::RunPlan plan;
    const estimator::Orbit o = estimator::StateToOrbit(nuisance->initial_state);
    plan.omega_rad_s = run.data.omega_rad_s;
    plan.a = o.a;
    plan.b = o.b;
    plan.theta_rad = o.theta_rad;
    plan.phi_rad = o.phi_rad;
    const double span = run.last_t_s - run.first_t_s;
    plan.sample_rate_hz = static_cast<double>(n - 1) / span;
    plan.duration_s = static_cast<double>(n) / plan.sample_rate_hz;
    design.runs.push_back(plan);
  }
  std::string why;
  if (design.runs.empty() || !design.IsValid(&why))
    return json{{"valid", false}, {"message", why.empty() ? "no run to design from" : why}};
  const estimator::CrlbResult bound = estimator::CramerRaoBound(design);
  json out{{"valid", bound.valid},
           {"message", bound.message},
           {"sigma", bench::NumberOrNull(design.sigma)}};
  out["delta_std"] = json::array();
  out["xi_std"] = json::array();
  for (int j = 0; j < 6; ++j) out["delta_std"].push_back(bench::NumberOrNull(bound.delta_std[j]));
  for (int k = 0; k < 4; ++k) out["xi_std"].push_back(bench::NumberOrNull(bound.xi_std[k]));
  if (!bound.valid) return out;
  // The achieved std: recorded when the record has it, else the re-run's. The bound is for white
  // noise of σ̂; a sandwich std (coloured residuals) is above it by the noise's colour, which says
  // nothing of the estimator's efficiency, so the caption only claims efficiency for white noise.
  const session::EstimateRecord* recorded = OfRecord(inputs.record);
  const std::string covariance = recorded != nullptr && !recorded->covariance_kind.empty()
                                     ? recorded->covariance_kind
                                     : s.diagnostics.covariance_kind;
  const bool white = covariance == "white";
  out["covariance"] = covariance;
  out["comparison"] = white ? "efficiency" : "noise colour";
  json figure{{"name", "std-vs-bound"},
              {"caption",
               "Achieved std of every estimated parameter against the Cramér–Rao bound of the "
               "session's own design (its runs, fitted orbits, white noise of σ̂ = " +
                   Readable(design.sigma) + "); " +
                   (white ? std::string("the std is the white-noise covariance's, so a ratio near "
                                        "1 is an efficient estimate")
                          : "the std is the " + covariance +
                                " covariance's (the residuals are not white), so its ratio to "
                                "the white-noise bound measures the noise's colour, not the "
                                "estimator's efficiency")},
              {"type", "bar"},
              {"x_label", "parameter"},
              {"y_label", "std"},
              {"y_log", true},
              {"equal_aspect", false},
              {"labels", json::array()},
              {"series", json::array()}};
  std::vector<double> achieved, crlb;
  for (int p = 0; p < 10; ++p) {
    const bool is_delta = p < 6;
    const int i = is_delta ? p : p - 6;
    const bool estimated = is_delta ? s.delta_estimated[i] : s.xi_estimated[i];
    if (!estimated) continue;
    double value = recorded == nullptr ? kNaN
                   : is_delta          ? recorded->delta_std[static_cast<std::size_t>(i)]
                                       : recorded->xi_std[static_cast<std::size_t>(i)];
    if (!std::isfinite(value)) value = is_delta ? s.delta_std[i] : s.xi_std[i];
    figure["labels"].push_back((is_delta ? "δ" : "ξ") + std::to_string(i + 1));
    achieved.push_back(value);
    crlb.push_back(is_delta ? bound.delta_std[i] : bound.xi_std[i]);
  }
  figure["series"].push_back(Series("achieved std", achieved));
  figure["series"].push_back(Series("Cramér–Rao bound", crlb, true));
  figures->push_back(std::move(figure));
  return out;
}

// derived.unit_history: {store, unavailable, count, sessions: [{started_utc, station, outcome,
// path, values {name: number}, stds {name: number}}]}, the newest kMaxUnitHistoryRows, oldest
// first; null without one.
json UnitHistoryJson(const std::optional<UnitHistory>& history) {
  if (!history) return nullptr;
  json sessions = json::array();
  const std::size_t n = history->sessions.size();
  for (std::size_t i = n > kMaxUnitHistoryRows ? n - kMaxUnitHistoryRows : 0; i < n; ++i) {
    const UnitHistoryEntry& e = history->sessions[i];
    json values = json::object(), stds = json::object();
    for (const auto& [name, value] : e.values)
      if (std::isfinite(value)) values[name] = value;
    for (const auto& [name, value] : e.stds)
      if (std::isfinite(value)) stds[name] = value;
    sessions.push_back({{"started_utc", e.started_utc},
                        {"station", e.station},
                        {"outcome", e.outcome},
                        {"path", e.path},
                        {"values", std::move(values)},
                        {"stds", std::move(stds)}});
  }
  return {{"store", history->store},
          {"unavailable", history->unavailable},
          {"count", n},
          {"sessions", std::move(sessions)}};
}

// (estimate − truth)/std of every δ and ξ when the session is simulated (the truth recorded under
// outcome.estimate.truth, or the simulation spec), with the estimate and std the page shows (the
// record's, else the re-run's); null where any of the three is missing or the std is not positive.
json TruthDeviation(const ReportInputs& inputs) {
  const session::EstimateRecord* of_record = OfRecord(inputs.record);
  std::array<double, 6> truth_delta;
  std::array<double, 4> truth_xi;
  truth_delta.fill(kNaN);
  truth_xi.fill(kNaN);
  if (of_record != nullptr && of_record->truth_delta) {
    truth_delta = *of_record->truth_delta;
    if (of_record->truth_xi) truth_xi = *of_record->truth_xi;
  } else if (inputs.record.simulation_delta) {  // the simulator's own section
    truth_delta = *inputs.record.simulation_delta;
    if (inputs.record.simulation_xi) truth_xi = *inputs.record.simulation_xi;
  } else {
    return nullptr;
  }
  const bool recorded =
      of_record != nullptr && std::any_of(of_record->delta.begin(), of_record->delta.end(),
                                          [](double v) { return std::isfinite(v); });
  json out = json::object();
  for (const char* key : {"delta", "xi"}) {
    const bool is_delta = std::string(key) == "delta";
    const int count = is_delta ? 6 : 4;
    json z = json::array();
    for (int i = 0; i < count; ++i) {
      const auto u = static_cast<std::size_t>(i);
      const std::string k = std::string(key) + "/" + std::to_string(i);
      const std::string s = std::string(key) + "_std/" + std::to_string(i);
      const double estimate = !recorded  ? NumberAt(inputs.estimate_json, "/" + k)
                              : is_delta ? of_record->delta[u]
                                         : of_record->xi[u];
      const double std_dev = !recorded  ? NumberAt(inputs.estimate_json, "/" + s)
                             : is_delta ? of_record->delta_std[u]
                                        : of_record->xi_std[u];
      const double truth = is_delta ? truth_delta[u] : truth_xi[u];
      z.push_back(std_dev > 0.0 ? bench::NumberOrNull((estimate - truth) / std_dev)
                                : json(nullptr));
    }
    out[key] = std::move(z);
  }
  return out;
}

}  // namespace

const json* At(const json& doc, const std::string& pointer) {
  try {
    const json::json_pointer p(pointer);
    if (!doc.contains(p)) return nullptr;
    return &doc.at(p);
  } catch (const json::exception&) {
    return nullptr;  // a malformed pointer or an index into a non-array
  }
}

double NumberAt(const json& doc, const std::string& pointer) {
  const json* v = At(doc, pointer);
  return v != nullptr && v->is_number() ? v->get<double>() : kNaN;
}

RunPart BuildRunPart(const RunView& run, const session::SessionRecord& record,
                     const estimator::Xi& xi, double noise_sigma,
                     std::size_t max_points_per_series) {
  RunPart part;
  if (!run.loaded) return part;
  part.quality = CaptureQuality(run, record);
  if (run.figures) RunFigures(run, xi, max_points_per_series, record, noise_sigma, &part.figures);
  return part;
}

json BuildReportData(const ReportInputs& inputs, std::vector<RunPart> run_parts) {
  json data{{"figures", json::array()}, {"derived", json::object()}};
  json& figures = data["figures"];
  json& derived = data["derived"];
  derived["estimate"] = inputs.estimate_json;
  derived["anisotropy"] = Anisotropy(inputs, &figures);
  derived["truth_deviation"] = TruthDeviation(inputs);
  json crlb_figures = json::array();
  derived["crlb"] = CramerRao(inputs, &crlb_figures);
  for (json& f : crlb_figures) figures.push_back(std::move(f));
  derived["unit_history"] = UnitHistoryJson(inputs.unit_history);
  derived["tune"] = TuneDerived(inputs.tune ? &*inputs.tune : nullptr, &figures);
  derived["runs"] = json::object();
  for (std::size_t r = 0; r < inputs.runs.size() && r < run_parts.size(); ++r) {
    if (!inputs.runs[r].loaded) continue;
    derived["runs"][std::to_string(inputs.runs[r].id)] = std::move(run_parts[r].quality);
    for (json& f : run_parts[r].figures) figures.push_back(std::move(f));
  }
  return data;
}

}  // namespace hrgbench::report::internal
