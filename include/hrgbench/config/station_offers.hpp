#pragma once
// What a station offers its operator: the sequence and limits files its panel lists, which of each
// is selected when the page loads, and whether a session may run without limits ([offers] in the
// station file; bench_configs/README.md). Issue 26 §1: a panel that defaulted to the research
// sequence, or offered "no limits" (a green PASS with nothing judged), failed good units and
// passed unjudged ones on a production line.
//
//   [offers]
//   sequences = ["sequence-production.toml", "sequence-paper.toml"]  # beside the station file
//   default_sequence = "sequence-production.toml"   # absent: the first of sequences
//   limits = ["limits-example.toml"]
//   default_limits = "limits-example.toml"          # absent: the first of limits
//   no_limits = false   # offer a session without limits; refused on kind = "real" (production)
//
// Every name is a .toml file name in the station file's own folder (no folder part); a default
// that is not in its list is an error naming the file, line, key and value, and so is a name with
// no such file when the panel starts on the station (`hrg-bench serve`: a copy of a station file
// elsewhere still runs `hrg-bench run`). Without
// [offers], or without one of its lists: every sequence-*.toml (limits-*.toml) beside the station,
// in name order, and the first of them the default.

#include <string>
#include <vector>

namespace hrgbench::bench {

struct StationOffers {
  bool declared = false;               // [offers] was in the station file
  std::vector<std::string> sequences;  // file names; empty: every sequence-*.toml beside
  std::string default_sequence;        // a name of `sequences`; empty: the first offered
  std::vector<std::string> limits;     // file names; empty: every limits-*.toml beside
  std::string default_limits;          // a name of `limits`; empty: the first offered
  bool no_limits = false;              // "no limits" may be chosen (never on a real station)
};

}  // namespace hrgbench::bench
