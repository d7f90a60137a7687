// Loader of sequence files.

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <string>
#include <system_error>
#include <utility>

#include "count_text.hpp"
#include "hrgbench/config/config_bounds.hpp"
#include "hrgbench/config/decision_rule.hpp"
#include "hrgbench/config/sequence_config.hpp"
#include "hrgbench/config/sha256.hpp"
#include "hrgbench/config/toml_reader.hpp"
#include "hrgbench/hw/gyro_electronics.hpp"

namespace hrgbench::bench {
namespace {

using namespace config_file;  // NOLINT(google-build-using-namespace): the loader's vocabulary

// The fastest any gyro link carries (CAN FD); the station's own link is judged by the cross-check.
constexpr double kMaxSampleRateHz = hw::kMaxSampleRateCanFdHz;
constexpr Range kWait{0.0, kMaxWaitS, false, "in (0, 3600] s (an hour)"};
constexpr Range kLongWaitPositive{0.0, kMaxLongWaitS, false, "in (0, 86400] s (a day)"};
constexpr Range kLongWaitNonNegative{0.0, kMaxLongWaitS, true, "in [0, 86400] s (a day)"};
constexpr std::string_view kRunKeysText =
    "omega_rad_s, a, b, theta_rad, free_run_s, sample_rate_hz";
constexpr std::string_view kDefaultKeysText = "a, b, theta_rad, free_run_s, sample_rate_hz";

// Shortest fixed-point text of a total (seconds, samples): "100000", not "1e+05".
std::string Shortest(double v) {
  char text[400];
  const auto result = std::to_chars(text, text + sizeof(text), v, std::chars_format::fixed);
  return std::string(text, result.ptr);
}

// The run keys; [defaults] may supply any of them but Ω (a rate is what makes a run a run).
enum RunKey { kOmega, kA, kB, kTheta, kFreeRun, kSampleRate, kRunKeyCount };
constexpr std::string_view kRunKeyNames[kRunKeyCount] = {
    "omega_rad_s", "a", "b", "theta_rad", "free_run_s", "sample_rate_hz"};

std::expected<double, ConfigError> RunValue(const TableReader& reader, const toml::node& node,
                                            RunKey key) {
  const std::string_view name = kRunKeyNames[key];
  switch (key) {
    case kOmega:
      return NumberFrom(reader, node, name, kAnyFinite);
    case kA:
      return NumberFrom(reader, node, name,
                        {0.0, kMaxWaveAmplitude, false, "in (0, 6.5535] (the protocol's range)"});
    case kB:
      return NumberFrom(reader, node, name,
                        {-kMaxWaveQuadrature, kMaxWaveQuadrature, true, "in [-3.2767, 3.2767]"});
    case kTheta:
      return NumberFrom(reader, node, name,
                        {-kMaxWaveAngleRad, kMaxWaveAngleRad, true, "in [-3.2767, 3.2767] rad"});
    case kFreeRun:  // also bounded by the total over the runs (a day), checked after each run
      return NumberFrom(reader, node, name, kPositive);
    case kSampleRate: {
      constexpr std::string_view kWhat = "a whole number of Hz in [1, 10000]";
      auto v = NumberFrom(reader, node, name, {1.0, kMaxSampleRateHz, true, kWhat});
      if (v && *v != std::floor(*v))
        return std::unexpected(
            reader.Error(node, name, "out of range: must be " + std::string(kWhat)));
      return v;
    }
    case kRunKeyCount:
      break;
  }
  return std::unexpected(reader.Error(node, name, "internal: unknown run key"));
}

struct Defaults {
  const toml::node* node[kRunKeyCount] = {};
};

std::expected<Defaults, ConfigError> ReadDefaults(TableReader& reader) {
  Defaults defaults;
  for (int k = kA; k < kRunKeyCount; ++k) {
    const toml::node* node = reader.Find(kRunKeyNames[k]);
    if (node == nullptr) continue;
    HRG_TRY(v, RunValue(reader, *node, static_cast<RunKey>(k)));
    defaults.node[k] = node;
  }
  HRG_CHECK(reader.Unknown(kDefaultKeysText));
  return defaults;
}

std::expected<SequenceRun, ConfigError> ReadRun(TableReader& reader, const Defaults& defaults,
                                                TableReader* defaults_reader) {
  double values[kRunKeyCount] = {};
  const toml::node* nodes[kRunKeyCount] = {};
  for (int k = 0; k < kRunKeyCount; ++k) {
    const RunKey key = static_cast<RunKey>(k);
    const toml::node* node = reader.Find(kRunKeyNames[k]);
    const TableReader* from = &reader;
    if (node == nullptr && defaults.node[k] != nullptr) {
      node = defaults.node[k];
      from = defaults_reader;
    }
    if (node == nullptr) {
      return std::unexpected(reader.Missing(
          kRunKeyNames[k], k == kOmega ? "a number, per run" : "a number, here or in [defaults]"));
    }
    HRG_TRY(v, RunValue(*from, *node, key));
    values[k] = *v;
    nodes[k] = node;
  }
  SequenceRun run;
  run.omega_rad_s = values[kOmega];
  run.a = values[kA];
  run.b = values[kB];
  run.theta_rad = values[kTheta];
  run.free_run_s = values[kFreeRun];
  run.sample_rate_hz = static_cast<std::uint32_t>(values[kSampleRate]);
  run.omega_line = LineOf(*nodes[kOmega]);
  run.sample_rate_line = LineOf(*nodes[kSampleRate]);
  // The electronics hold |b| < a (a = |b| is a circular orbit: no wave angle to excite).
  if (std::abs(run.b) >= run.a) {
    const TableReader& from =
        nodes[kB] == defaults.node[kB] && defaults_reader != nullptr ? *defaults_reader : reader;
    return std::unexpected(from.Error(
        *nodes[kB], "b",
        "out of range: must satisfy |b| < a (a = " + from.source().Render(*nodes[kA]) + ")"));
  }
  const double samples = std::round(run.free_run_s * values[kSampleRate]);
  if (samples < 2.0 || samples > kMaxSamplesPerRun) {
    const TableReader& from =
        nodes[kFreeRun] == defaults.node[kFreeRun] && defaults_reader != nullptr ? *defaults_reader
                                                                                 : reader;
    return std::unexpected(from.Error(
        *nodes[kFreeRun], "free_run_s",
        "out of range: free_run_s * sample_rate_hz gives " + config_file::CountText(samples) +
            " samples; a run needs at least 2 and at most 1e7 (a typo in a rate or a length?)"));
  }
  HRG_CHECK(reader.Unknown(kRunKeysText));
  return run;
}

// A prompt's image: a PNG, JPEG or SVG file at or below the sequence file's folder (so a
// session's config copy can hold it at the same relative place), of bounded size.
std::expected<void, ConfigError> ReadPromptImage(TableReader& reader, SequencePrompt& prompt,
                                                 const std::filesystem::path& file) {
  const toml::node* node = reader.Find("image");
  if (node == nullptr) return {};
  HRG_TRY(image, OptionalString(reader, "image", "", true));
  const std::filesystem::path relative(*image);
  const bool escapes = std::any_of(relative.begin(), relative.end(),
                                   [](const std::filesystem::path& part) { return part == ".."; });
  if (relative.is_absolute() || escapes) {
    return std::unexpected(reader.Error(
        *node, "image", "must be a path relative to the sequence file's folder, without \"..\""));
  }
  std::string extension = relative.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension != ".png" && extension != ".jpg" && extension != ".jpeg" && extension != ".svg")
    return std::unexpected(
        reader.Error(*node, "image", "must be a .png, .jpg, .jpeg or .svg file"));
  const std::filesystem::path resolved = file.parent_path() / relative;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(resolved, ec))
    return std::unexpected(reader.Error(*node, "image", "no such file: " + resolved.string()));
  const std::uintmax_t bytes = std::filesystem::file_size(resolved, ec);
  if (ec || bytes > kMaxPromptImageBytes) {
    return std::unexpected(
        reader.Error(*node, "image",
                     "out of range: " + resolved.string() + " is " +
                         (ec ? "unreadable" : CountText(static_cast<double>(bytes))) +
                         " bytes; a prompt's image has at most " +
                         CountText(static_cast<double>(kMaxPromptImageBytes))));
  }
  auto sha = Sha256FileHex(resolved);
  if (!sha) return std::unexpected(reader.Error(*node, "image", sha.error()));
  prompt.image = relative.generic_string();
  prompt.image_file = resolved;
  prompt.image_sha256 = *sha;
  return {};
}

std::expected<void, ConfigError> ReadPrompts(TableReader& root, SequenceConfig& sequence,
                                             const Source& source,
                                             const std::filesystem::path& file) {
  const toml::node* prompts_node = root.Find("prompts");
  if (prompts_node == nullptr) return {};
  const toml::array* prompts = prompts_node->as_array();
  if (prompts == nullptr || !prompts->is_array_of_tables()) {
    return std::unexpected(
        root.Error(*prompts_node, "prompts", "wrong type: expected [[prompts]] tables"));
  }
  if (prompts->size() > kMaxPrompts) {
    return std::unexpected(ConfigError{file, LineOf(*prompts->get(0)), "prompts", "",
                                       "out of range: " + std::to_string(prompts->size()) +
                                           " [[prompts]] tables; a sequence has at most " +
                                           std::to_string(kMaxPrompts)});
  }
  for (std::size_t i = 0; i < prompts->size(); ++i) {
    TableReader reader(*prompts->get(i)->as_table(), "prompts[" + std::to_string(i) + "]", source);
    SequencePrompt prompt;
    HRG_TRY(id, RequiredString(reader, "id"));
    for (const SequencePrompt& earlier : sequence.prompts) {
      if (earlier.id == *id) {
        return std::unexpected(
            reader.Error(*reader.Find("id"), "id", "repeated: every prompt needs its own id"));
      }
    }
    prompt.id = *id;
    HRG_TRY(at, Choice(reader, "at", {"start", "before_run", "end"}, -1));
    prompt.at = *at == 0   ? PromptPoint::kStart
                : *at == 1 ? PromptPoint::kBeforeRun
                           : PromptPoint::kEnd;
    if (prompt.at == PromptPoint::kBeforeRun) {
      HRG_TRY(run,
              RequiredInteger(reader, "run", 1, static_cast<std::int64_t>(sequence.runs.size())));
      prompt.before_run = static_cast<int>(*run);
    } else if (auto forbidden = Forbid(reader, "run", "only with at = \"before_run\"")) {
      return std::unexpected(*forbidden);
    }
    HRG_TRY(text, OptionalString(reader, "text", "", true, StringKind::kDescription));
    if (text->empty()) return std::unexpected(reader.Missing("text", "what the operator must do"));
    prompt.text = *text;
    if (auto image = ReadPromptImage(reader, prompt, file); !image)
      return std::unexpected(image.error());
    HRG_CHECK(reader.Unknown("id, at, run, text, image"));
    sequence.prompts.push_back(std::move(prompt));
  }
  return {};
}

std::expected<SequenceConfig, ConfigError> ReadSequence(const TomlDocument& document,
                                                        const std::filesystem::path& file) {
  const Source source(file, document.text);
  SequenceConfig sequence;
  sequence.file = file;
  sequence.sha256_hex = document.sha256_hex;
  TableReader root(document.root, "", source);

  HRG_TRY(header, SubTable(root, "sequence", true));
  {
    TableReader reader(**header, "sequence", source);
    HRG_TRY(name, RequiredString(reader, "name"));
    sequence.name = *name;
    HRG_TRY(description,
            OptionalString(reader, "description", "", false, StringKind::kDescription));
    sequence.description = *description;
    HRG_CHECK(reader.Unknown("name, description"));
  }

  HRG_TRY(settle_table, SubTable(root, "settle", false));
  if (*settle_table != nullptr) {
    TableReader reader(**settle_table, "settle", source);
    SettleCriteria& s = sequence.settle;
    HRG_TRY(tolerance,
            OptionalNumber(reader, "rate_tolerance_rad_s", kPositive, s.rate_tolerance_rad_s));
    s.rate_tolerance_rad_s = *tolerance;
    HRG_TRY(dwell, OptionalNumber(reader, "dwell_s", kWait, s.dwell_s));
    s.dwell_s = *dwell;
    HRG_TRY(poll, OptionalNumber(reader, "poll_period_s", {0.0, 10.0, false, "in (0, 10]"},
                                 s.poll_period_s));
    s.poll_period_s = *poll;
    HRG_CHECK(reader.Unknown("rate_tolerance_rad_s, dwell_s, poll_period_s"));
  }

  HRG_TRY(timeouts_table, SubTable(root, "timeouts", false));
  if (*timeouts_table != nullptr) {
    TableReader reader(**timeouts_table, "timeouts", source);
    SequenceTimeouts& t = sequence.timeouts;
    HRG_TRY(settle, OptionalNumber(reader, "settle_s", kWait, t.settle_s));
    t.settle_s = *settle;
    if (sequence.settle.dwell_s > t.settle_s) {
      const toml::node* node = reader.table().get("settle_s");
      const std::string message = "out of range: must be >= settle.dwell_s (" +
                                  std::to_string(sequence.settle.dwell_s) +
                                  "), else the table can never count as settled";
      if (node == nullptr) return std::unexpected(reader.Missing("settle_s", message));
      return std::unexpected(reader.Error(*node, "settle_s", message));
    }
    HRG_TRY(excite, OptionalNumber(reader, "excite_s", kWait, t.excite_s));
    t.excite_s = *excite;
    HRG_TRY(margin, OptionalNumber(reader, "run_margin_s", kWait, t.run_margin_s));
    t.run_margin_s = *margin;
    HRG_CHECK(reader.Unknown("settle_s, excite_s, run_margin_s"));
  } else if (sequence.settle.dwell_s > sequence.timeouts.settle_s) {
    return std::unexpected(root.Missing(
        "timeouts", "[timeouts] settle_s >= settle.dwell_s (the default 60 s is shorter)"));
  }

  HRG_TRY(warmup_table, SubTable(root, "warmup", false));
  if (*warmup_table != nullptr) {
    TableReader reader(**warmup_table, "warmup", source);
    WarmupCriteria& w = sequence.warmup;
    HRG_TRY(min_s, OptionalNumber(reader, "min_s", kLongWaitNonNegative, w.min_s));
    w.min_s = *min_s;
    HRG_TRY(window, OptionalNumber(reader, "window_s", kLongWaitPositive, w.window_s));
    w.window_s = *window;
    HRG_TRY(drift, OptionalNumber(reader, "max_drift_c", kPositive, w.max_drift_c));
    w.max_drift_c = *drift;
    HRG_TRY(timeout,
            OptionalNumber(reader, "timeout_s",
                           {0.0, 2.0 * kMaxLongWaitS, false, "in (0, 172800] s (two days)"},
                           w.timeout_s));
    w.timeout_s = *timeout;
    if (w.timeout_s < w.min_s + w.window_s) {
      const toml::node* node = reader.table().get("timeout_s");
      const std::string message = "out of range: must be >= min_s + window_s (" +
                                  std::to_string(w.min_s + w.window_s) + ")";
      if (node == nullptr) return std::unexpected(reader.Missing("timeout_s", message));
      return std::unexpected(reader.Error(*node, "timeout_s", message));
    }
    HRG_CHECK(reader.Unknown("min_s, window_s, max_drift_c, timeout_s"));
  }

  HRG_TRY(drift_table, SubTable(root, "drift", false));
  if (*drift_table != nullptr) {
    TableReader reader(**drift_table, "drift", source);
    DriftCriteria& d = sequence.drift;
    HRG_TRY(temperature,
            OptionalNumber(reader, "max_temperature_change_rel", {0.0, 1.0, false, "in (0, 1]"},
                           d.max_temperature_change_rel));
    d.max_temperature_change_rel = *temperature;
    HRG_TRY(frequency,
            MaybeNumber(reader, "max_frequency_change_rel", {0.0, 1.0, false, "in (0, 1]"}));
    d.max_frequency_change_rel = *frequency;
    HRG_TRY(action, Choice(reader, "action", {"flag", "reject"}, 0));
    d.action = *action == 0 ? DriftAction::kFlag : DriftAction::kReject;
    HRG_CHECK(reader.Unknown("max_temperature_change_rel, max_frequency_change_rel, action"));
  }

  HRG_TRY(capture_table, SubTable(root, "capture", false));
  if (*capture_table != nullptr) {
    TableReader reader(**capture_table, "capture", source);
    constexpr std::int64_t kMax = std::numeric_limits<std::int32_t>::max();
    HRG_TRY(gaps, OptionalInteger(reader, "max_sequence_gaps", 0, kMax, 0));
    sequence.capture.max_sequence_gaps = *gaps;
    HRG_TRY(lost, OptionalInteger(reader, "max_samples_lost", 0, kMax, 0));
    sequence.capture.max_samples_lost = *lost;
    if (sequence.capture.max_samples_lost < sequence.capture.max_sequence_gaps) {
      constexpr std::string_view kWhy =
          "out of range: must be >= max_sequence_gaps (every gap loses at least one sample)";
      const toml::node* node = reader.table().get("max_samples_lost");
      if (node == nullptr) return std::unexpected(reader.Missing("max_samples_lost", kWhy));
      return std::unexpected(reader.Error(*node, "max_samples_lost", std::string(kWhy)));
    }
    HRG_CHECK(reader.Unknown("max_sequence_gaps, max_samples_lost"));
  }

  HRG_TRY(defaults_table, SubTable(root, "defaults", false));
  std::optional<TableReader> defaults_reader;
  Defaults defaults;
  if (*defaults_table != nullptr) {
    defaults_reader.emplace(**defaults_table, "defaults", source);
    HRG_TRY(d, ReadDefaults(*defaults_reader));
    defaults = *d;
  }

  const toml::node* runs_node = root.Find("runs");
  if (runs_node == nullptr)
    return std::unexpected(root.Missing("runs", "one [[runs]] table per run"));
  const toml::array* runs = runs_node->as_array();
  if (runs == nullptr || !runs->is_array_of_tables() || runs->empty()) {
    return std::unexpected(
        root.Error(*runs_node, "runs", "wrong type: expected one or more [[runs]] tables"));
  }
  // Checked before reading any run: 100 000 runs would otherwise all be read first.
  if (runs->size() > kMaxRuns) {
    // At the first [[runs]] header; the value (every run) is too long to quote.
    return std::unexpected(ConfigError{file, LineOf(*runs->get(0)), "runs", "",
                                       "out of range: " + std::to_string(runs->size()) +
                                           " [[runs]] tables; a sequence has at most " +
                                           std::to_string(kMaxRuns)});
  }
  double total_free_run_s = 0.0;
  double total_samples = 0.0;
  for (std::size_t i = 0; i < runs->size(); ++i) {
    const toml::table& table = *runs->get(i)->as_table();
    TableReader reader(table, "runs[" + std::to_string(i) + "]", source);
    HRG_TRY(run, ReadRun(reader, defaults, defaults_reader ? &*defaults_reader : nullptr));
    total_free_run_s += run->free_run_s;
    total_samples += static_cast<double>(run->Samples());
    if (total_free_run_s > kMaxTotalFreeRunS || total_samples > kMaxTotalSamples) {
      // Named at this run's free_run_s (or the default it took): the run that crossed the bound.
      const toml::node* node = table.get("free_run_s");
      const TableReader& from = node != nullptr || !defaults_reader ? reader : *defaults_reader;
      if (node == nullptr) node = defaults.node[kFreeRun];
      const std::string what =
          total_free_run_s > kMaxTotalFreeRunS
              ? "runs[0.." + std::to_string(i) + "] free-run " + Shortest(total_free_run_s) +
                    " s in total; a sequence free-runs at most 86400 s (a day)"
              : "runs[0.." + std::to_string(i) + "] capture " + Shortest(total_samples) +
                    " samples in total; a sequence captures at most 1e8";
      return std::unexpected(from.Error(*node, "free_run_s", "out of range: " + what));
    }
    sequence.runs.push_back(*run);
  }

  HRG_TRY(adaptive_table, SubTable(root, "adaptive", false));
  if (*adaptive_table != nullptr) {
    TableReader reader(**adaptive_table, "adaptive", source);
    HRG_TRY(stop, OptionalBool(reader, "stop_when_decided", false));
    sequence.adaptive.stop_when_decided = *stop;
    HRG_TRY(min_runs, OptionalInteger(reader, "min_runs", 1,
                                      static_cast<std::int64_t>(sequence.runs.size()), 1));
    sequence.adaptive.min_runs = static_cast<int>(*min_runs);
    // The limits' k is not known here (another file): that the interim k is not below it is
    // checked where both are (CheckAdaptiveAgainstLimits).
    HRG_TRY(interim, MaybeNumber(reader, "interim_coverage_factor",
                                 {kMinCoverageFactor, kMaxCoverageFactor, true, "in [1, 6]"}));
    sequence.adaptive.interim_coverage_factor = *interim;
    HRG_TRY(every, MaybeNumber(reader, "look_interval_s", {1.0, 3600.0, true, "in [1, 3600] s"}));
    sequence.adaptive.look_interval_s = every->value_or(0.0);
    if (const std::size_t looks = sequence.InterimLookFractions().size(); looks > kMaxInterimLooks)
      return std::unexpected(reader.Error(
          *reader.Find("look_interval_s"), "look_interval_s",
          "out of range: " + Shortest(sequence.adaptive.look_interval_s) + " s plans " +
              std::to_string(looks) + " interim looks over the runs; at most " +
              std::to_string(kMaxInterimLooks) + " (each is an estimate): look less often"));
    HRG_TRY(next, Choice(reader, "next_run", {"plan", "most_informative"}, 0));
    sequence.adaptive.most_informative_next = *next == 1;
    HRG_CHECK(
        reader.Unknown("stop_when_decided, min_runs, interim_coverage_factor, "
                       "look_interval_s, next_run"));
  }

  if (auto prompts = ReadPrompts(root, sequence, source, file); !prompts)
    return std::unexpected(prompts.error());
  HRG_CHECK(
      root.Unknown("[sequence], [settle], [timeouts], [warmup], [drift], [capture], "
                   "[adaptive], [defaults], [[runs]], [[prompts]]"));
  return sequence;
}

}  // namespace

std::string_view ToString(DriftAction action) noexcept {
  return action == DriftAction::kReject ? "reject" : "flag";
}

std::size_t SequenceRun::Samples() const {
  return static_cast<std::size_t>(std::llround(free_run_s * static_cast<double>(sample_rate_hz)));
}

std::vector<estimator::RunPlan> SequenceConfig::ToRunPlans(double omega_offset_rad_s) const {
  std::vector<estimator::RunPlan> plans;
  plans.reserve(runs.size());
  for (const SequenceRun& run : runs) {
    estimator::RunPlan plan;
    plan.omega_rad_s = run.omega_rad_s + omega_offset_rad_s;
    plan.a = run.a;
    plan.b = run.b;
    plan.theta_rad = run.theta_rad;
    plan.phi_rad = 0.0;
    plan.sample_rate_hz = static_cast<double>(run.sample_rate_hz);
    plan.duration_s = run.free_run_s;
    plans.push_back(plan);
  }
  return plans;
}

std::string SequencePrompt::Where() const {
  switch (at) {
    case PromptPoint::kStart:
      return "start";
    case PromptPoint::kBeforeRun:
      return "before run " + std::to_string(before_run);
    case PromptPoint::kEnd:
      return "end";
  }
  return "start";
}

std::vector<const SequencePrompt*> SequenceConfig::PromptsAt(PromptPoint point, int run_id) const {
  std::vector<const SequencePrompt*> out;
  for (const SequencePrompt& prompt : prompts)
    if (prompt.at == point && (point != PromptPoint::kBeforeRun || prompt.before_run == run_id))
      out.push_back(&prompt);
  return out;
}

double SequenceConfig::TotalFreeRunS() const {
  double total = 0.0;
  for (const SequenceRun& run : runs) total += run.free_run_s;
  return total;
}

double FirstLookWithinRunS(double look_interval_s, double shortest_run_before_s) {
  if (!(look_interval_s > 0.0)) return 0.0;
  const double intervals = std::max(1.0, std::ceil(shortest_run_before_s / look_interval_s - 1e-9));
  return intervals * look_interval_s;
}

std::vector<double> SequenceConfig::InterimLookFractions() const {
  std::vector<double> looks;
  const double total = TotalFreeRunS();
  if (!adaptive.stop_when_decided || !(total > 0.0)) return looks;
  const double every = adaptive.look_interval_s;
  double before = 0.0;
  double shortest = 0.0;  // of the runs before
  for (std::size_t r = 0; r < runs.size(); ++r) {
    const double length = runs[r].free_run_s;
    const bool may_decide = static_cast<int>(r) + 1 >= adaptive.min_runs;
    // From FirstLookWithinRunS on; not within half an interval of the run's end, where the look
    // after it comes anyway.
    for (double at = FirstLookWithinRunS(every, shortest);
         may_decide && every > 0.0 && at <= length - 0.5 * every; at += every)
      looks.push_back((before + at) / total);
    shortest = r == 0 ? length : std::min(shortest, length);
    before += length;
    if (may_decide && r + 1 < runs.size()) looks.push_back(before / total);
  }
  return looks;
}

std::expected<SequenceConfig, ConfigError> ParseSequenceConfig(std::string_view toml_text,
                                                               const std::filesystem::path& file) {
  HRG_TRY(document, ParseTomlText(toml_text, file));
  return ReadSequence(*document, file);
}

std::expected<SequenceConfig, ConfigError> LoadSequenceConfig(const std::filesystem::path& file) {
  HRG_TRY(document, LoadTomlFile(file));
  return ReadSequence(*document, file);
}

}  // namespace hrgbench::bench
