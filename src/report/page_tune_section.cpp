// The page's tuning section (<section id="tuning">): what `hrg-bench tune` wrote to tune.json — its
// verdict, the rate error per verified rate before and after (the paper's criterion, beside the
// prediction), the scale factor over the rates and the zero-rate hold — with the figures of
// tune_data.hpp. Values of tune.json carry data-tune-source, the report's °/h data-derived.

#include <string>

#include "page.hpp"

namespace hrgbench::report::internal {

void Page::Tuning() {
  if (!in_.tune) return;
  const json& tune = *in_.tune;
  const std::string outcome = tune.value("/verdict/outcome"_json_pointer, std::string("ERROR"));
  out_ += "<section id=\"tuning\">\n<h2>Tuning (tune.json)</h2>\n";
  const std::string reason = tune.value("/verdict/reason"_json_pointer, std::string());
  out_ += "<div id=\"tune-outcome\" data-kind=\"" + Attr(outcome) + "\">tune " +
          HtmlEscape(outcome) + (reason.empty() ? std::string() : ": " + HtmlEscape(reason)) +
          "</div>\n";
  const std::string block = tune.value("block_at_end", std::string());
  out_ += "<p>The electronics hold the block " + TextOrMissing(block) +
          (tune.value("restored", false) ? " (the block held before was restored)" : "") +
          ". The paper's criterion: the angle-dependent rate error (the RMS of each hold's fitted "
          "harmonics of 2θ) before and after, beside what the estimate's covariance predicts "
          "(χ² " +
          TuneSrc("/verification/chi2") + " on " + TuneSrc("/verification/chi2_dof") +
          " degrees of freedom, limit " + TuneSrc("/verification/chi2_limit") + ").</p>\n";
  out_ +=
      "<table id=\"tune-rates\"><tr><th>Ω (rad/s)</th><th>before (°/h)</th><th>with p from the "
      "free runs (°/h)</th><th>after (°/h)</th><th>predicted (°/h)</th><th>before / after</th>"
      "<th>χ²</th></tr>\n";
  for (std::size_t i = 0; i < DerivedSize("/derived/tune/rates"); ++i) {
    const std::string d = "/derived/tune/rates/" + std::to_string(i);
    const std::string v = "/verification/rates/" + std::to_string(i);
    out_ += "<tr><td>" + TuneSrc(v + "/omega_rad_s") + "</td><td>" + Der(d + "/before_deg_h") +
            "</td><td>" + Der(d + "/with_p_deg_h") + "</td><td>" + Der(d + "/after_deg_h") +
            "</td><td>" + Der(d + "/predicted_deg_h") + "</td><td>" + Der(d + "/factor") +
            "</td><td>" + TuneSrc(v + "/chi2") + "</td></tr>\n";
  }
  out_ += "</table>\n";
  Figure("tune-rate-error-before", 960, 320);
  Figure("tune-rate-error-after", 960, 320);
  if (tune.contains("scale_factor") && tune["scale_factor"].is_object()) {
    const auto [bias, bias_std] = DerWithStd("/derived/tune/scale_factor/bias_deg_h",
                                             "/derived/tune/scale_factor/bias_std_deg_h");
    const ValueWithStd sf = Metrological(NumberAt(tune, "/scale_factor/error_ppm"),
                                         NumberAt(tune, "/scale_factor/error_std_ppm"));
    out_ += "<p id=\"tune-scale-factor\">Over the rates: bias " + bias + " ± " + bias_std +
            " °/h, scale-factor error " + TuneSrc("/scale_factor/error_ppm", sf.value) + " ± " +
            TuneSrc("/scale_factor/error_std_ppm", sf.std) + " ppm, asymmetry " +
            TuneSrc("/scale_factor/asymmetry_ppm") + " ± " +
            TuneSrc("/scale_factor/asymmetry_std_ppm") + " ppm, nonlinearity " +
            TuneSrc("/scale_factor/nonlinearity_ppm") + " ppm (χ² " +
            TuneSrc("/scale_factor/chi2") + " on " + TuneSrc("/scale_factor/dof") + ").</p>\n";
    Figure("tune-scale-factor", 960, 300);
  }
  if (tune.contains("zero_rate") && tune["zero_rate"].is_object()) {
    const bool reached = tune.value("/zero_rate/bias_instability_reached"_json_pointer, false);
    out_ += "<p id=\"tune-zero-rate\">Zero-rate hold of " + TuneSrc("/zero_rate/hold/duration_s") +
            " s: angle random walk " + Der("/derived/tune/zero_rate/arw_deg_per_sqrt_h") +
            " °/√h [" + Der("/derived/tune/zero_rate/arw_lower_deg_per_sqrt_h") + ", " +
            Der("/derived/tune/zero_rate/arw_upper_deg_per_sqrt_h") + "] (σ at τ = 1 s); bias " +
            "instability " + (reached ? "" : "below ") +
            Der("/derived/tune/zero_rate/bias_instability_deg_h") + " °/h [" +
            Der("/derived/tune/zero_rate/bias_instability_lower_deg_h") + ", " +
            Der("/derived/tune/zero_rate/bias_instability_upper_deg_h") + "] at τ " +
            TuneSrc("/zero_rate/bias_instability_tau_s") + " s" +
            (reached ? "" : " (σ(τ) still falls: no floor within the hold)") + ".</p>\n";
    Figure("tune-allan", 960, 360);
  }
  // The verdict's checks, each as the limits file's [tune] names it, in its units.
  const json* checks = At(tune, "/verdict/checks");
  if (checks != nullptr && checks->is_array() && !checks->empty()) {
    out_ +=
        "<table id=\"tune-checks\"><tr><th>check</th><th>value</th><th>std</th><th>max</th>"
        "<th>status</th><th>U (k = 2)</th><th>message</th></tr>\n";
    for (std::size_t i = 0; i < checks->size() && i < 64; ++i) {
      const std::string c = "/verdict/checks/" + std::to_string(i);
      const json& check = (*checks)[i];
      const std::string status = check.value("status", std::string());
      out_ += "<tr><td>" + HtmlEscape(check.value("name", std::string())) + "</td><td>" +
              TuneSrc(c + "/value") + "</td><td>" + TuneSrc(c + "/std") + "</td><td>" +
              TuneSrc(c + "/max") + "</td><td class=\"status-" + Attr(status) + "\">" +
              HtmlEscape(status) + "</td><td>" + TuneSrc(c + "/expanded_uncertainty") +
              "</td><td>" + HtmlEscape(check.value("message", std::string())) + "</td></tr>\n";
    }
    out_ += "</table>\n";
  }
  out_ += "</section>\n";
}

}  // namespace hrgbench::report::internal
