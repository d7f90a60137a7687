#pragma once
// What any config file may say at most (station, sequence, limits, simulation specs): bounds far
// above every real bench and plan, so that only a typo or a hostile file reaches them. Without
// them a 1e12 s timeout, a 1 MB name with a NUL in it or 100 000 runs loaded without a word and
// surfaced later as a bench that waits forever, a garbled session.json or a run out of memory.
// Documented in bench_configs/README.md ("Bounds on every file"); each is checked by the loaders
// with an error naming file, line, key and value.

#include <cstddef>

namespace hrgbench::config_file {

// A config file's size. The shipped files are under 4 KiB; a sequence of kMaxRuns runs written
// out one key per line is about 150 KiB.
inline constexpr std::size_t kMaxConfigFileBytes = std::size_t{1} << 20;

// A name (station, sequence, limits, unit serial, host, device, interface): printable text, no
// control characters (U+0000..U+001F, U+007F), at most this many bytes. 255 holds any DNS host
// name (253) and any device path a bench uses; a name is printed on one line of a report.
inline constexpr std::size_t kMaxNameBytes = 255;
// A description: free text, tab and line feed allowed, no other control character.
inline constexpr std::size_t kMaxDescriptionBytes = 4096;

// Runs of one sequence or simulation spec. The production sequence has 6; a day of 100 s runs
// with their settling is under 1000.
inline constexpr std::size_t kMaxRuns = 1000;
// Total free-run time of a sequence or spec: a day. The production sequence is 600 s.
inline constexpr double kMaxTotalFreeRunS = 86'400.0;
// Total samples of a sequence or spec (each run is also bounded by kMaxSamplesPerRun = 1e7):
// 1e8 samples of t and four channels are 4 GB of doubles for the estimator.
inline constexpr double kMaxTotalSamples = 1e8;

// Waits of the sequencer ([settle] dwell_s, [timeouts] settle_s, excite_s, run_margin_s): an hour.
// A table settles in seconds and an excitation takes well under a minute; longer is a unit typo
// (ms for s).
inline constexpr double kMaxWaitS = 3'600.0;
// Warm-up ([warmup] min_s, window_s; timeout_s up to twice this, as it must cover both) and the
// fault-injection times of the simulated station: a day.
inline constexpr double kMaxLongWaitS = 86'400.0;

}  // namespace hrgbench::config_file
