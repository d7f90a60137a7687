// Sessions as short as the verdict allows, measured as a line would (issue 27 §2): simulated units
// drawn good, marginal and bad around bench_configs/limits-example.toml, in slow and carrier
// physics, each measured twice on the simulated station through bench::RunSession exactly as
// `hrg-bench run` drives it: with the full production sequence (sequence-production.toml) and
// with the adaptive one (sequence-production-adaptive.toml: the same design in two passes,
// stopped once the unit's verdict is decided). Per unit: the table time (the simulated clock's,
// from the start to the table at rest before the estimate: what a real table would take), the runs
// made, the outcome and every limit's decision zone under the limits' rule (guarded acceptance, k =
// 2).
//
//   adaptive_session_table --rows FILE [--units N] [--seed S] [--shard K/M] [--carrier-every C]
//                          [--excite-s S] [--settle-time-constant-s S] [--keep]
//                          [--look-interval-s S] [--next-run plan|most_informative] [--only CLASS]
//   adaptive_session_table --summary FILE...
//
// The first form measures the units whose index i (0 … N−1) has i % M == K and writes one CSV row
// per unit (run two shards side by side on two cores); the second prints the Markdown tables of
// docs/measurements/ from the rows of every shard.
//
// Realistic table times: the station's simulated excitation takes 5 s and the table settles with
// a 1 s time constant (--excite-s, --settle-time-constant-s) (station-sim.toml's 0.2 s and 0.05 s
// are for fast tests); the sequences' own warm-up (600 s), settling dwell (1 s) and free runs are
// as shipped. The warm-up is reported apart: a line that soaks its units warm before mounting them
// does not spend it on the table. A fixture of N units is the N units in index order on one table:
// the table makes each run while a unit on it still needs it, so its time is one warm-up plus the
// longest of its units' measuring times (bench_adaptive_test's fixture case shows the table
// stopping at the last unit's decision; fixture_throughput_table that the units' excitations
// overlap).
//
// The truth, per unit (index i; class by i % 4: 0, 1 good, 2 marginal, 3 bad; physics carrier
// when i % C == C − 1, default C = 5; otherwise the slow model's δ and ξ of the same physical
// unit, estimator::DeltaFromResonator and XiFromPickoff):
//   good      τ ∈ [700, 1500] s, Bryan factor ∈ [0.29, 0.31], Δ(1/τ) ∈ [0, 4e-5] 1/s,
//             Δf ∈ [0, 2e-4] Hz, axes anywhere, gain ratio ∈ [0.985, 1.015], phase mismatch,
//             cross-talk and electrode angle error ∈ ±5e-3: everything well inside its limits
//   marginal  a good unit with one of τ, the Bryan factor or the gain ratio within a few of the
//             full sequence's U of a limit's edge, inside or out (AtTheEdge)
//   bad       a good unit with one of them 2 … 20 % beyond a limit's edge
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "app/station_factory.hpp"
#include "hrgbench/bench/sequencer/operator_prompts.hpp"
#include "hrgbench/bench/sequencer/sequencer.hpp"
#include "hrgbench/config/bench_configs.hpp"
#include "hrgbench/estimator/physical_parameters.hpp"
#include "hrgbench/estimator/pickoff_frame.hpp"
#include "hrgbench/session/session_record.hpp"

namespace {

using namespace hrgbench;  // NOLINT(google-build-using-namespace): a one-file program

constexpr const char* kClassNames[] = {"good", "marginal", "bad"};

struct Unit {
  int index = 0;
  int unit_class = 0;  // 0 good, 1 marginal, 2 bad
  bool carrier = false;
  std::string what;  // the parameter a marginal or bad unit has at or beyond its limit
  estimator::ResonatorParameters resonator;
  estimator::PickoffParameters pickoff;
  std::uint64_t seed = 0;
};

// One of τ (limits [500, 2000] s), the Bryan factor ([0.28, 0.32]) or the gain ratio (the gain
// mismatch's ±4 %) put at one of its limit's edges: `beyond` (relative; > 0 outside) for a bad
// unit, or for a marginal one (`beyond` NaN) within a few of the full sequence's expanded
// uncertainties U of the edge (relative ±5e-4 for τ, ±5e-6 for the Bryan factor, ±2e-5 for the
// gain ratio: U is about 8e-5, 3e-6 and 5e-6 of them at σ = 1e-4), inside or out.
void AtTheEdge(Unit& unit, std::mt19937_64& rng, double beyond) {
  std::uniform_int_distribution<int> which(0, 5);
  const int parameter = which(rng);
  const double widths[] = {5e-4, 5e-6, 2e-5};
  const double relative =
      std::isnan(beyond)
          ? widths[parameter / 2] * std::uniform_real_distribution<double>(-1.0, 1.0)(rng)
          : beyond;
  switch (parameter) {
    case 0:
      unit.resonator.decay_time_s = 500.0 * (1.0 - relative);
      unit.what = "tau_s at 500 s";
      break;
    case 1:
      unit.resonator.decay_time_s = 2000.0 * (1.0 + relative);
      unit.what = "tau_s at 2000 s";
      break;
    case 2:
      unit.resonator.angular_gain = 0.28 * (1.0 - relative);
      unit.what = "angular_gain at 0.28";
      break;
    case 3:
      unit.resonator.angular_gain = 0.32 * (1.0 + relative);
      unit.what = "angular_gain at 0.32";
      break;
    case 4:
      unit.pickoff.gain_ratio = 0.96 * (1.0 - relative);
      unit.what = "gain ratio at 0.96";
      break;
    default:
      unit.pickoff.gain_ratio = 1.04 * (1.0 + relative);
      unit.what = "gain ratio at 1.04";
      break;
  }
}

Unit Draw(int index, int carrier_every, std::uint64_t seed) {
  std::mt19937_64 rng(seed * 1'000'003ULL + static_cast<std::uint64_t>(index));
  auto uniform = [&rng](double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
  };
  Unit unit;
  unit.index = index;
  unit.unit_class = index % 4 < 2 ? 0 : index % 4 - 1;
  unit.carrier = carrier_every > 0 && index % carrier_every == carrier_every - 1;
  unit.seed = 1000 + 7919ULL * static_cast<std::uint64_t>(index) + seed;
  estimator::ResonatorParameters& r = unit.resonator;
  r.frequency_hz = 5000.0;
  r.decay_time_s = uniform(700.0, 1500.0);
  r.angular_gain = uniform(0.29, 0.31);
  r.damping_anisotropy_per_s = uniform(0.0, 4e-5);
  r.damping_axis_rad = uniform(-std::numbers::pi / 4, std::numbers::pi / 4);
  r.frequency_split_hz = uniform(0.0, 2e-4);
  r.frequency_axis_rad = uniform(-std::numbers::pi / 4, std::numbers::pi / 4);
  estimator::PickoffParameters& p = unit.pickoff;
  p.gain_ratio = uniform(0.985, 1.015);
  p.phase_mismatch_rad = uniform(-5e-3, 5e-3);
  p.cross_talk = uniform(-5e-3, 5e-3);
  p.electrode_angle_error_rad = uniform(-5e-3, 5e-3);
  if (unit.unit_class == 1) AtTheEdge(unit, rng, NAN);
  if (unit.unit_class == 2) AtTheEdge(unit, rng, uniform(0.02, 0.2));
  return unit;
}

// Answers every operator prompt at once, as `hrg-bench run --prompts confirm`.
class ConfirmEveryPrompt final : public bench::PromptAnswers {
 public:
  void Show(const bench::PromptRequest&) override {}
  std::optional<bench::PromptReply> Wait(std::chrono::milliseconds) override {
    return bench::PromptReply{true, "adaptive_session_table", "auto"};
  }
};

struct Measured {
  std::string outcome;  // PASS, FAIL, ERROR, ABORTED
  bool retest = false;
  int runs = 0;
  double free_run_s = 0.0;
  double warmup_s = 0.0;  // on the table, before the first run
  double table_s = 0.0;   // start to the table at rest before the estimate
  std::string zones;      // one letter per limit, in the file's order: C, N, U (undecided), -
  double cpu_s = 0.0;
  std::string reason;  // the outcome's (on the log, not in the rows)
};

double CpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

char ZoneLetter(const bench::LimitResult& limit) {
  switch (limit.zone) {
    case bench::DecisionZone::kConforming:
      return 'C';
    case bench::DecisionZone::kNonConforming:
      return 'N';
    case bench::DecisionZone::kUndecided:
      return 'U';
    default:
      return '-';
  }
}

// The station's simulated excitation time and the table's settling time constant, s.
struct StationTimes {
  double excite_s = 5.0;
  double settle_time_constant_s = 1.0;
  bool keep = false;  // --keep: the session folders stay (their paths on the log)
  // The adaptive sequence's [adaptive] as shipped unless set: --look-interval-s (0: after runs
  // only), --next-run most_informative.
  std::optional<double> look_interval_s;
  bool most_informative_next = false;
};

Measured Measure(const Unit& unit, const StationTimes& times, const std::string& sequence,
                 const std::filesystem::path& dir) {
  const std::filesystem::path configs_dir =
      std::filesystem::path(HRGBENCH_SOURCE_DIR) / "bench_configs";
  auto configs = bench::LoadBenchConfigs(
      configs_dir / (unit.carrier ? "station-sim-carrier.toml" : "station-sim.toml"),
      configs_dir / sequence, configs_dir / "limits-example.toml");
  if (!configs) {
    std::fprintf(stderr, "%s\n", configs.error().ToString().c_str());
    std::exit(2);
  }
  configs->station.results_url.clear();
  if (configs->sequence.adaptive.stop_when_decided) {
    if (times.look_interval_s) configs->sequence.adaptive.look_interval_s = *times.look_interval_s;
    if (times.most_informative_next) configs->sequence.adaptive.most_informative_next = true;
  }
  bench::SimulatedStationConfig& sim = configs->station.simulated;
  sim.seed = unit.seed;
  sim.excite_time_s = times.excite_s;
  sim.table_settle_time_constant_s = times.settle_time_constant_s;
  if (unit.carrier) {
    sim.carrier.resonator = unit.resonator;
    sim.carrier.pickoff = unit.pickoff;
  } else {
    sim.delta = estimator::DeltaFromResonator(unit.resonator);
    sim.xi = estimator::XiFromPickoff(unit.pickoff);
    sim.resonant_frequency_hz = unit.resonator.frequency_hz;
  }
  auto station = app::OpenStation(configs->station);
  if (!station) {
    std::fprintf(stderr, "unit %d: %s\n", unit.index, station.error().c_str());
    std::exit(2);
  }
  ConfirmEveryPrompt confirm;
  Measured m;
  bool warm = false;
  bench::RunnerOptions options;
  options.unit_serial = "AD-" + std::to_string(unit.index);
  options.software_version = "adaptive_session_table";
  options.simulation = (*station)->simulation();
  options.prompts = &confirm;
  options.on_progress = [&](const bench::Progress& p) {
    if (!warm && p.phase == "table") {
      warm = true;
      m.warmup_s = p.elapsed_s;
    }
    if (p.phase == "estimate" && m.table_s == 0.0) m.table_s = p.elapsed_s;
  };
  const bench::BenchHardware& hardware = (*station)->hardware();
  const std::int64_t start_ns = hardware.clock->NowNs();
  const double cpu0 = CpuSeconds();
  const bench::SessionResult result = bench::RunSession(*configs, hardware, dir, options);
  m.cpu_s = CpuSeconds() - cpu0;
  if (m.table_s == 0.0) m.table_s = static_cast<double>(hardware.clock->NowNs() - start_ns) * 1e-9;
  m.outcome = std::string(bench::ToString(result.outcome));
  m.runs = result.complete_runs;
  m.reason = result.reason;
  // The free run the record holds: a run decided within stopped short, and the runs made need
  // not be the plan's first ones (next_run = "most_informative").
  if (auto record = session::ReadSessionRecord(dir); record) {
    for (const session::RunRecord& run : record->runs) {
      if (run.status == bench::kRunComplete && run.plan && run.end && run.end->samples)
        m.free_run_s += static_cast<double>(*run.end->samples) / run.plan->sample_rate_hz;
    }
  }
  if (result.verdict) {
    m.retest = result.verdict->retest;
    for (const bench::LimitResult& limit : result.verdict->results) m.zones += ZoneLetter(limit);
  }
  if (!times.keep) std::filesystem::remove_all(dir);
  return m;
}

// ---- rows (one CSV line per unit) ----

constexpr const char* kHeader =
    "index,class,physics,what,full_outcome,full_retest,full_runs,full_free_run_s,full_warmup_s,"
    "full_table_s,full_zones,full_cpu_s,adaptive_outcome,adaptive_retest,adaptive_runs,"
    "adaptive_free_run_s,adaptive_warmup_s,adaptive_table_s,adaptive_zones,adaptive_cpu_s";

struct Row {
  int index = 0;
  std::string unit_class, physics, what;
  Measured full, adaptive;
};

void WriteMeasured(std::ostream& out, const Measured& m) {
  out << m.outcome << ',' << (m.retest ? 1 : 0) << ',' << m.runs << ',' << m.free_run_s << ','
      << m.warmup_s << ',' << m.table_s << ',' << (m.zones.empty() ? "none" : m.zones) << ','
      << m.cpu_s;
}

std::vector<std::string> SplitCsv(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream in(line);
  for (std::string cell; std::getline(in, cell, ',');) cells.push_back(cell);
  return cells;
}

Measured ReadMeasured(const std::vector<std::string>& c, std::size_t at) {
  Measured m;
  m.outcome = c.at(at);
  m.retest = c.at(at + 1) == "1";
  m.runs = std::stoi(c.at(at + 2));
  m.free_run_s = std::stod(c.at(at + 3));
  m.warmup_s = std::stod(c.at(at + 4));
  m.table_s = std::stod(c.at(at + 5));
  m.zones = c.at(at + 6) == "none" ? "" : c.at(at + 6);
  m.cpu_s = std::stod(c.at(at + 7));
  return m;
}

std::vector<Row> ReadRows(const std::vector<std::string>& files) {
  std::vector<Row> rows;
  for (const std::string& file : files) {
    std::ifstream in(file);
    if (!in) {
      std::fprintf(stderr, "cannot read %s\n", file.c_str());
      std::exit(2);
    }
    std::string line;
    while (std::getline(in, line)) {
      if (line.empty() || line.starts_with("index")) continue;
      const std::vector<std::string> c = SplitCsv(line);
      if (c.size() != 20) {
        std::fprintf(stderr, "%s: a row of %zu cells, not 20: %s\n", file.c_str(), c.size(),
                     line.c_str());
        std::exit(2);
      }
      Row row;
      row.index = std::stoi(c[0]);
      row.unit_class = c[1];
      row.physics = c[2];
      row.what = c[3];
      row.full = ReadMeasured(c, 4);
      row.adaptive = ReadMeasured(c, 12);
      rows.push_back(row);
    }
  }
  std::sort(rows.begin(), rows.end(), [](const Row& a, const Row& b) { return a.index < b.index; });
  return rows;
}

// ---- the summary ----

double Quantile(std::vector<double> v, double q) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const double at = q * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(at));
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (at - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

// Agreement of the adaptive verdict with the full one: the same outcome; a different outcome
// where no limit is proven conforming by one and non-conforming by the other (an undecided
// limit, inside its guard band, against a decided one: the guard band explains it); one of the
// two not judged at all (ERROR: a fit outside its model, or the bench's fault; the log says
// which); or a contradiction (a limit proven on both sides).
enum class Agreement { kSame, kGuardBand, kOneNotJudged, kContradiction };

Agreement Compare(const Measured& full, const Measured& adaptive) {
  for (std::size_t i = 0; i < std::min(full.zones.size(), adaptive.zones.size()); ++i) {
    const char f = full.zones[i], a = adaptive.zones[i];
    if ((f == 'C' && a == 'N') || (f == 'N' && a == 'C')) return Agreement::kContradiction;
  }
  if (full.outcome == adaptive.outcome && full.retest == adaptive.retest) return Agreement::kSame;
  if ((full.outcome == "ERROR") != (adaptive.outcome == "ERROR")) return Agreement::kOneNotJudged;
  return Agreement::kGuardBand;
}

// Units per table-hour with `per_table` units on each table (consecutive units), the warm-up on
// the table (`soaked` false) or done before mounting.
double UnitsPerTableHour(const std::vector<Row>& rows, bool adaptive, int per_table, bool soaked) {
  double total_s = 0.0;
  int units = 0;
  for (std::size_t first = 0; first < rows.size(); first += static_cast<std::size_t>(per_table)) {
    const std::size_t end = std::min(rows.size(), first + static_cast<std::size_t>(per_table));
    double longest = 0.0, warmup = 0.0;
    for (std::size_t i = first; i < end; ++i) {
      const Measured& m = adaptive ? rows[i].adaptive : rows[i].full;
      longest = std::max(longest, m.table_s - m.warmup_s);
      warmup = std::max(warmup, m.warmup_s);
    }
    total_s += longest + (soaked ? 0.0 : warmup);
    units += static_cast<int>(end - first);
  }
  return total_s > 0.0 ? 3600.0 * units / total_s : NAN;
}

int Summary(const std::vector<std::string>& files) {
  const std::vector<Row> rows = ReadRows(files);
  if (rows.empty()) {
    std::fprintf(stderr, "no rows\n");
    return 1;
  }
  std::printf("%zu units.\n\n", rows.size());
  std::printf(
      "| physics | class | units | full: table s, median / p95 | adaptive: table s, median / p95 "
      "| adaptive runs, median (max) | free run s, median | same verdict | differ in the guard "
      "band | one not judged | contradicted "
      "|\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
      "\n");
  std::map<std::string, std::vector<const Row*>> groups;
  for (const Row& row : rows) {
    groups[row.physics + "/" + row.unit_class].push_back(&row);
    groups["all/all"].push_back(&row);
  }
  for (const std::string physics : {"slow", "carrier", "all"}) {
    for (const std::string cls : {"good", "marginal", "bad", "all"}) {
      const auto it = groups.find(physics + "/" + cls);
      if (it == groups.end()) continue;
      std::vector<double> full_t, adaptive_t, runs, free_run;
      int same = 0, band = 0, not_judged = 0, contradicted = 0, max_runs = 0;
      for (const Row* row : it->second) {
        full_t.push_back(row->full.table_s);
        adaptive_t.push_back(row->adaptive.table_s);
        runs.push_back(row->adaptive.runs);
        free_run.push_back(row->adaptive.free_run_s);
        max_runs = std::max(max_runs, row->adaptive.runs);
        switch (Compare(row->full, row->adaptive)) {
          case Agreement::kSame:
            ++same;
            break;
          case Agreement::kGuardBand:
            ++band;
            break;
          case Agreement::kOneNotJudged:
            ++not_judged;
            break;
          case Agreement::kContradiction:
            ++contradicted;
            break;
        }
      }
      std::printf(
          "| %s | %s | %zu | %.0f / %.0f | %.0f / %.0f | %.0f (%d) | %.0f | %d | %d | %d | %d |\n",
          physics.c_str(), cls.c_str(), it->second.size(), Quantile(full_t, 0.5),
          Quantile(full_t, 0.95), Quantile(adaptive_t, 0.5), Quantile(adaptive_t, 0.95),
          Quantile(runs, 0.5), max_runs, Quantile(free_run, 0.5), same, band, not_judged,
          contradicted);
    }
  }
  std::printf(
      "\n| units per table | full, warm-up on the table | adaptive | ratio | full, units soaked "
      "warm "
      "before mounting | adaptive | ratio |\n|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const int n : {1, 4, 8}) {
    const double f = UnitsPerTableHour(rows, false, n, false);
    const double a = UnitsPerTableHour(rows, true, n, false);
    const double fs = UnitsPerTableHour(rows, false, n, true);
    const double as = UnitsPerTableHour(rows, true, n, true);
    std::printf("| %d | %.1f | %.1f | %.2f× | %.1f | %.1f | %.2f× |\n", n, f, a, a / f, fs, as,
                as / fs);
  }
  std::printf(
      "\nOutcomes (full → adaptive), units:\n\n| full | adaptive | units |\n|---|---|---:|\n");
  std::map<std::string, int> pairs;
  for (const Row& row : rows) {
    auto name = [](const Measured& m) { return m.outcome + (m.retest ? " (retest)" : ""); };
    pairs[name(row.full) + " | " + name(row.adaptive)]++;
  }
  for (const auto& [pair, n] : pairs) std::printf("| %s | %d |\n", pair.c_str(), n);
  std::printf(
      "\nEvery unit whose verdicts differ:\n\n| unit | class | physics | what | full | "
      "adaptive (runs) | limits full / adaptive |\n|---:|---|---|---|---|---|---|\n");
  for (const Row& row : rows) {
    if (Compare(row.full, row.adaptive) == Agreement::kSame) continue;
    std::printf("| %d | %s | %s | %s | %s%s | %s%s (%d) | %s / %s |\n", row.index,
                row.unit_class.c_str(), row.physics.c_str(), row.what.c_str(),
                row.full.outcome.c_str(), row.full.retest ? " retest" : "",
                row.adaptive.outcome.c_str(), row.adaptive.retest ? " retest" : "",
                row.adaptive.runs, row.full.zones.c_str(), row.adaptive.zones.c_str());
  }
  double full_cpu = 0.0, adaptive_cpu = 0.0;
  for (const Row& row : rows) {
    full_cpu += row.full.cpu_s;
    adaptive_cpu += row.adaptive.cpu_s;
  }
  std::printf("\nCPU here: %.0f s for the full sessions, %.0f s for the adaptive ones.\n", full_cpu,
              adaptive_cpu);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  int units = 200, carrier_every = 5, shard = 0, shards = 1;
  std::uint64_t seed = 1;
  std::string rows_file;
  StationTimes times;
  std::vector<std::string> summary;
  std::string only;  // --only good|marginal|bad: the units of one class (the same draws)
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "%s needs a value\n", arg.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (arg == "--units") {
      units = std::stoi(next());
    } else if (arg == "--seed") {
      seed = std::stoull(next());
    } else if (arg == "--excite-s") {
      times.excite_s = std::stod(next());
    } else if (arg == "--settle-time-constant-s") {
      times.settle_time_constant_s = std::stod(next());
    } else if (arg == "--keep") {
      times.keep = true;
    } else if (arg == "--only") {
      only = next();
    } else if (arg == "--look-interval-s") {
      times.look_interval_s = std::stod(next());
    } else if (arg == "--next-run") {
      const std::string value = next();
      if (value != "plan" && value != "most_informative") {
        std::fprintf(stderr, "--next-run plan|most_informative, not %s\n", value.c_str());
        return 2;
      }
      times.most_informative_next = value == "most_informative";
    } else if (arg == "--carrier-every") {
      carrier_every = std::stoi(next());
    } else if (arg == "--shard") {
      const std::string value = next();
      if (std::sscanf(value.c_str(), "%d/%d", &shard, &shards) != 2 || shards < 1 || shard < 0 ||
          shard >= shards) {
        std::fprintf(stderr, "--shard K/M with 0 <= K < M, not %s\n", value.c_str());
        return 2;
      }
    } else if (arg == "--rows") {
      rows_file = next();
    } else if (arg == "--summary") {
      while (i + 1 < argc) summary.emplace_back(argv[++i]);
    } else {
      std::fprintf(
          stderr,
          "usage: adaptive_session_table --rows FILE [--units N] [--seed S] [--shard K/M] "
          "[--carrier-every C] [--excite-s S] [--settle-time-constant-s S] [--keep] "
          "[--look-interval-s S] [--next-run plan|most_informative] [--only CLASS] | --summary "
          "FILE...\n");
      return 2;
    }
  }
  if (!summary.empty()) return Summary(summary);
  if (rows_file.empty()) {
    std::fprintf(stderr, "--rows FILE or --summary FILE... is required\n");
    return 2;
  }
  std::ofstream out(rows_file);
  out << kHeader << '\n';
  std::random_device rd;
  const std::filesystem::path work =
      std::filesystem::temp_directory_path() / ("hrgbench-adaptive-table-" + std::to_string(rd()));
  for (int i = shard; i < units; i += shards) {
    const Unit unit = Draw(i, carrier_every, seed);
    if (!only.empty() && only != kClassNames[unit.unit_class]) continue;
    const std::string name = "unit-" + std::to_string(i);
    const Measured full = Measure(unit, times, "sequence-production.toml", work / name / "full");
    const Measured adaptive =
        Measure(unit, times, "sequence-production-adaptive.toml", work / name / "adaptive");
    if (times.keep) std::fprintf(stderr, "kept %s\n", (work / name).c_str());
    out << i << ',' << kClassNames[unit.unit_class] << ',' << (unit.carrier ? "carrier" : "slow")
        << ',' << (unit.what.empty() ? "-" : unit.what) << ',';
    WriteMeasured(out, full);
    out << ',';
    WriteMeasured(out, adaptive);
    out << '\n' << std::flush;
    std::fprintf(stderr, "unit %d %s %s: full %s %d runs %.0f s, adaptive %s %d runs %.0f s\n", i,
                 kClassNames[unit.unit_class], unit.carrier ? "carrier" : "slow",
                 full.outcome.c_str(), full.runs, full.table_s, adaptive.outcome.c_str(),
                 adaptive.runs, adaptive.table_s);
    for (const Measured* m : {&full, &adaptive}) {
      if (m->outcome != "PASS" && m->outcome != "FAIL")
        std::fprintf(stderr, "  %s: %s\n", m == &full ? "full" : "adaptive", m->reason.c_str());
    }
  }
  if (!times.keep) std::filesystem::remove_all(work);
  return 0;
}
