#include "trend_plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include "html_text.hpp"

namespace hrgbench::report::internal {
namespace {

constexpr double kWidth = 300.0;
constexpr double kHeight = 150.0;
constexpr double kLeft = 62.0;  // room for the axis' numbers (4 significant digits)
constexpr double kRight = 8.0;
constexpr double kTop = 18.0;  // the label
constexpr double kBottom = 10.0;

std::string Px(double x) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.1f", x);
  return text;
}

// The axis' numbers: 4 significant digits fit the margin ("1.571e+07"); more (up to 7) when the
// two ends would otherwise read the same.
std::string AxisNumber(double v, int digits) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.*g", digits, v);
  return text;
}

}  // namespace

std::string TrendPlot(const std::string& quantity, const std::string& label,
                      const std::vector<TrendPoint>& points, double k,
                      std::optional<double> limit_min, std::optional<double> limit_max) {
  const bool bars = std::isfinite(k) && k > 0.0;
  double lo = INFINITY, hi = -INFINITY;
  std::size_t with_value = 0;
  for (const TrendPoint& p : points) {
    if (!std::isfinite(p.value)) continue;
    ++with_value;
    const double u = bars && std::isfinite(p.std_dev) ? k * p.std_dev : 0.0;
    lo = std::min(lo, p.value - u);
    hi = std::max(hi, p.value + u);
  }
  if (with_value == 0) return {};
  // The limits are drawn when near the values (within their span again): a limit far off would
  // flatten every point onto one line, and its title still names it.
  const double values_span = hi > lo ? hi - lo : std::max(std::abs(hi), 1e-300);
  std::vector<double> limits;
  std::vector<std::pair<bool, std::string>> off_scale;  // (above, text)
  for (const bool is_min : {true, false}) {
    const std::optional<double>& l = is_min ? limit_min : limit_max;
    if (!l || !std::isfinite(*l)) continue;
    if (*l >= lo - values_span && *l <= hi + values_span) {
      limits.push_back(*l);
      lo = std::min(lo, *l);
      hi = std::max(hi, *l);
    } else {
      const bool above = *l > hi;
      off_scale.emplace_back(above, std::string(above ? "\u2191 " : "\u2193 ") +
                                        (is_min ? "min " : "max ") + Readable(*l));
    }
  }
  const double span = hi > lo ? hi - lo : std::max(std::abs(hi), 1e-300);
  const double top = hi, bottom = lo;  // the axis is numbered there
  lo -= 0.08 * span;
  hi += 0.08 * span;
  const double plot_w = kWidth - kLeft - kRight, plot_h = kHeight - kTop - kBottom;
  const auto y = [&](double v) { return kTop + (hi - v) / (hi - lo) * plot_h; };
  const std::size_t n = points.size();
  // The points inset from the frame, so the first and the last bar are not on it.
  const auto x = [&](std::size_t i) {
    const double inset = 10.0;
    return kLeft + inset +
           (n == 1 ? 0.5 : static_cast<double>(i) / static_cast<double>(n - 1)) *
               (plot_w - 2 * inset);
  };
  std::string title = label + " in this unit's sessions (oldest left, this session last)";
  if (bars) title += ", bars ± " + Readable(k) + "·u";
  if (limit_min || limit_max)
    title += "; limits [" + (limit_min ? Readable(*limit_min) : std::string("—")) + ", " +
             (limit_max ? Readable(*limit_max) : std::string("—")) + "]";
  std::string svg = "<svg class=\"trend\" data-quantity=\"" + HtmlEscape(quantity) +
                    "\" data-points=\"" + std::to_string(with_value) + "\" width=\"" + Px(kWidth) +
                    "\" height=\"" + Px(kHeight) + "\" viewBox=\"0 0 " + Px(kWidth) + " " +
                    Px(kHeight) + "\" role=\"img\"><title>" + HtmlEscape(title) + "</title>";
  svg += "<text x=\"" + Px(kLeft) + "\" y=\"12\" font-size=\"11\">" + HtmlEscape(label) + "</text>";
  svg += "<rect x=\"" + Px(kLeft) + "\" y=\"" + Px(kTop) + "\" width=\"" + Px(plot_w) +
         "\" height=\"" + Px(plot_h) + "\" fill=\"none\" stroke=\"#ccc\"/>";
  int digits = 4;
  while (digits < 7 && AxisNumber(top, digits) == AxisNumber(bottom, digits)) ++digits;
  for (const double v :
       top == bottom ? std::vector<double>{top} : std::vector<double>{top, bottom}) {
    svg += "<text x=\"" + Px(kLeft - 4) + "\" y=\"" + Px(y(v) + 4) +
           "\" font-size=\"9\" text-anchor=\"end\">" + HtmlEscape(AxisNumber(v, digits)) +
           "</text>";
  }
  for (const double l : limits)
    svg += "<line class=\"limit\" x1=\"" + Px(kLeft) + "\" x2=\"" + Px(kLeft + plot_w) +
           "\" y1=\"" + Px(y(l)) + "\" y2=\"" + Px(y(l)) +
           "\" stroke=\"#b3261e\" stroke-dasharray=\"4 3\"/>";
  for (const auto& [above, text] : off_scale)
    svg += "<text class=\"limit-off-scale\" x=\"" + Px(kLeft + plot_w - 2) + "\" y=\"" +
           Px(above ? kTop + 10 : kTop + plot_h - 3) +
           "\" font-size=\"10\" fill=\"#b3261e\" text-anchor=\"end\">" + HtmlEscape(text) +
           "</text>";
  for (std::size_t i = 0; i < n; ++i) {
    const TrendPoint& p = points[i];
    if (!std::isfinite(p.value)) continue;
    const char* colour = p.this_session ? "#1f4e9c" : "#555";
    std::string tip = p.label + ": " + Readable(p.value);
    if (bars && std::isfinite(p.std_dev)) {
      const double u = k * p.std_dev;
      tip += " ± " + Readable(u);
      svg += "<line class=\"uncertainty\" x1=\"" + Px(x(i)) + "\" x2=\"" + Px(x(i)) + "\" y1=\"" +
             Px(y(p.value - u)) + "\" y2=\"" + Px(y(p.value + u)) + "\" stroke=\"" + colour +
             "\"/>";
    }
    svg += "<circle class=\"session\" cx=\"" + Px(x(i)) + "\" cy=\"" + Px(y(p.value)) +
           "\" r=\"3\" fill=\"" + (p.this_session ? colour : "#fff") + "\" stroke=\"" + colour +
           "\"><title>" + HtmlEscape(tip) + "</title></circle>";
  }
  return svg + "</svg>";
}

}  // namespace hrgbench::report::internal
