#include "hrgbench/bench/output_filter.hpp"

#include <cmath>

namespace hrgbench::bench {

nlohmann::json OutputFilterJson(const OutputFilter& filter) {
  if (filter.kind == OutputFilterKind::kNone) return {{"kind", "none"}};
  return {{"kind", "butterworth"}, {"order", filter.order}, {"cutoff_hz", filter.cutoff_hz}};
}

std::expected<estimator::NoiseShape, std::string> NoiseShapeOf(const OutputFilter& filter,
                                                               double sample_rate_hz) {
  if (filter.kind == OutputFilterKind::kNone) return estimator::NoiseShape{};
  const auto shape = estimator::ButterworthNoiseShape(static_cast<int>(filter.order),
                                                      filter.cutoff_hz, sample_rate_hz);
  if (!shape) {
    return std::unexpected(
        "output filter: a Butterworth of order " + std::to_string(filter.order) + " at " +
        std::to_string(filter.cutoff_hz) + " Hz sampled at " + std::to_string(sample_rate_hz) +
        " Hz has a memory longer than " + std::to_string(estimator::kMaxNoiseShapeLags) +
        " samples (or the values are out of range): raise the cutoff or lower the rate");
  }
  return *shape;
}

namespace {

// The member `key` of an object, or nullptr.
const nlohmann::json* Member(const nlohmann::json& object, const char* key) {
  return object.is_object() && object.contains(key) ? &object.at(key) : nullptr;
}

// " = <value>" as recorded (at most 64 characters), or nothing when absent.
std::string Shown(const nlohmann::json* value) {
  if (value == nullptr) return "";
  std::string text = value->dump();
  if (text.size() > 64) text = text.substr(0, 61) + "...";
  return " = " + text;
}

}  // namespace

std::expected<estimator::NoiseShape, std::string> RecordedNoiseShape(
    const nlohmann::json& session_document, double sample_rate_hz) {
  const nlohmann::json* electronics = Member(session_document, "electronics");
  const nlohmann::json* filter = electronics ? Member(*electronics, "output_filter") : nullptr;
  if (filter == nullptr) return estimator::NoiseShape{};
  const std::string field = "electronics.output_filter";
  if (!filter->is_object()) return std::unexpected(field + Shown(filter) + ": not an object");
  const nlohmann::json* kind = Member(*filter, "kind");
  if (kind == nullptr || !kind->is_string())
    return std::unexpected(field + ".kind" + Shown(kind) + ": missing or not a string");
  if (*kind == "none") return estimator::NoiseShape{};
  if (*kind != "butterworth")
    return std::unexpected(field + ".kind: '" + kind->get<std::string>() +
                           "' is not none or butterworth");
  OutputFilter declared;
  declared.kind = OutputFilterKind::kButterworth;
  const nlohmann::json* order = Member(*filter, "order");
  if (order == nullptr || !order->is_number_integer() || *order < 1 ||
      *order > estimator::kMaxButterworthOrder)
    return std::unexpected(field + ".order" + Shown(order) + ": missing or not an integer 1 ... " +
                           std::to_string(estimator::kMaxButterworthOrder));
  declared.order = order->get<std::int64_t>();
  const nlohmann::json* cutoff = Member(*filter, "cutoff_hz");
  if (cutoff == nullptr || !cutoff->is_number() || !(cutoff->get<double>() > 0.0) ||
      !std::isfinite(cutoff->get<double>()))
    return std::unexpected(field + ".cutoff_hz" + Shown(cutoff) +
                           ": missing or not a positive number");
  declared.cutoff_hz = cutoff->get<double>();
  if (!(sample_rate_hz > 0.0))
    return std::unexpected(field + ": the session has no sample rate to sample the filter at");
  return NoiseShapeOf(declared, sample_rate_hz);
}

}  // namespace hrgbench::bench
