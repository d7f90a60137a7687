#include "guard_band_bar.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "html_text.hpp"

namespace hrgbench::report::internal {
namespace {

constexpr double kWidth = 240.0;
constexpr double kHeight = 20.0;
constexpr double kMargin = 6.0;

std::string Px(double x) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.1f", x);
  return text;
}

const char* ZoneColour(const std::string& zone) {
  if (zone == "conforming") return "#1b7f3b";
  if (zone == "non_conforming") return "#b3261e";
  if (zone == "undecided") return "#c77700";
  return "#555";
}

}  // namespace

std::string GuardBandBar(const session::LimitRowRecord& l) {
  if (!std::isfinite(l.value) || !std::isfinite(l.min) || !std::isfinite(l.max)) return {};
  const bool has_interval = std::isfinite(l.interval_min) && std::isfinite(l.interval_max);
  double lo = std::min(l.min, l.value), hi = std::max(l.max, l.value);
  if (has_interval) {
    lo = std::min(lo, l.interval_min);
    hi = std::max(hi, l.interval_max);
  }
  // A point tolerance or value still gets a visible scale.
  const double span = hi > lo ? hi - lo : std::max(std::abs(hi), 1.0);
  lo -= 0.05 * span;
  hi += 0.05 * span;
  const auto x = [&](double v) {
    return kMargin + (v - lo) / (hi - lo) * (kWidth - 2.0 * kMargin);
  };
  const std::string zone = l.zone.empty() ? std::string("not_recorded") : l.zone;
  std::string title = l.quantity + " = " + Readable(l.value);
  if (has_interval)
    title +=
        " ± " + Readable(l.expanded_uncertainty) + " (k = " + Readable(l.coverage_factor) + ")";
  title += " against [" + Readable(l.min) + ", " + Readable(l.max) + "]";
  const bool has_acceptance = std::isfinite(l.acceptance_min) && std::isfinite(l.acceptance_max);
  if (has_acceptance)
    title += ", accepted within [" + Readable(l.acceptance_min) + ", " +
             Readable(l.acceptance_max) + "]";
  title += ": " + (l.zone.empty() ? std::string("decision not recorded") : l.zone);
  std::string svg = "<svg class=\"guard-band\" data-quantity=\"" + HtmlEscape(l.quantity) +
                    "\" data-zone=\"" + HtmlEscape(zone) + "\" width=\"" + Px(kWidth) +
                    "\" height=\"" + Px(kHeight) + "\" viewBox=\"0 0 " + Px(kWidth) + " " +
                    Px(kHeight) + "\" role=\"img\"><title>" + HtmlEscape(title) + "</title>";
  // The tolerance, then its guard bands over it (the whole tolerance when the acceptance zone is
  // empty: no value proves conformance).
  svg += "<rect class=\"tolerance\" x=\"" + Px(x(l.min)) + "\" y=\"4\" width=\"" +
         Px(std::max(x(l.max) - x(l.min), 1.0)) +
         "\" height=\"12\" fill=\"#e3f1e6\" stroke=\"#1b7f3b\"/>";
  if (has_acceptance) {
    const bool empty = l.acceptance_min > l.acceptance_max;
    const double a = empty ? l.max : std::clamp(l.acceptance_min, l.min, l.max);
    const double b = empty ? l.max : std::clamp(l.acceptance_max, l.min, l.max);
    const auto band = [&](double from, double to) {
      if (x(to) - x(from) < 0.05) return std::string();
      return "<rect class=\"guard\" x=\"" + Px(x(from)) + "\" y=\"4\" width=\"" +
             Px(x(to) - x(from)) + "\" height=\"12\" fill=\"#f6d9a8\"/>";
    };
    svg += band(l.min, empty ? l.max : a) + band(b, l.max);
  }
  const char* colour = ZoneColour(l.zone);
  if (has_interval) {
    svg += "<line class=\"interval\" x1=\"" + Px(x(l.interval_min)) + "\" x2=\"" +
           Px(x(l.interval_max)) + "\" y1=\"10\" y2=\"10\" stroke=\"" + colour +
           "\" stroke-width=\"2\"/>";
    for (const double end : {l.interval_min, l.interval_max})
      svg += "<line x1=\"" + Px(x(end)) + "\" x2=\"" + Px(x(end)) +
             "\" y1=\"5\" y2=\"15\" stroke=\"" + colour + "\" stroke-width=\"2\"/>";
  }
  svg += "<circle class=\"value\" cx=\"" + Px(x(l.value)) + "\" cy=\"10\" r=\"3.5\" fill=\"" +
         colour + "\"/></svg>";
  return svg;
}

}  // namespace hrgbench::report::internal
