// The store's one text form of a time (utc_text.hpp) and the lower bound of --since: fixed width,
// so SQLite's text order is time order, and what PostgreSQL's to_char gives back.
#include "hrgbench/results/utc_text.hpp"

#include <gtest/gtest.h>

#include "hrgbench/results/since_utc.hpp"

namespace {

using namespace hrgbench::results;

TEST(CanonicalUtc, SixFractionDigitsInUtc) {
  EXPECT_EQ(CanonicalUtc("2026-11-23T19:18:19.582862Z"), "2026-11-23T19:18:19.582862Z");
  EXPECT_EQ(CanonicalUtc("2026-11-02T08:00:00Z"), "2026-11-02T08:00:00.000000Z");
  EXPECT_EQ(CanonicalUtc("2026-11-02T08:00:00.5Z"), "2026-11-02T08:00:00.500000Z");
  EXPECT_EQ(CanonicalUtc("2026-11-02 08:00:00.123456789Z"), "2026-11-02T08:00:00.123456Z");
  // Offsets across midnight and a year end.
  EXPECT_EQ(CanonicalUtc("2027-01-01T01:30:00+03:00"), "2026-12-31T22:30:00.000000Z");
  EXPECT_EQ(CanonicalUtc("2026-12-31T23:00:00-02:00"), "2027-01-01T01:00:00.000000Z");
}

TEST(CanonicalUtc, AnythingElseIsNone) {
  for (const char* bad : {"", "yesterday", "2026-11-02", "2026-11-02T08:00:00",
                          "2026-02-30T08:00:00Z", "2026-11-02T24:00:00Z", "2026-11-02T08:00:00.Z",
                          "2026-11-02T08:00:00+3", "2026-11-02T08:00:00Zjunk"})
    EXPECT_FALSE(CanonicalUtc(bad).has_value()) << bad;
}

TEST(SinceLowerBound, APrefixIsItsFirstInstant) {
  EXPECT_EQ(SinceLowerBound("2026"), "2026-01-01T00:00:00.000000Z");
  EXPECT_EQ(SinceLowerBound("2026-11"), "2026-11-01T00:00:00.000000Z");
  EXPECT_EQ(SinceLowerBound("2026-11-23T14"), "2026-11-23T14:00:00.000000Z");
  EXPECT_EQ(SinceLowerBound("2026-11-23T14:05:00Z"), "2026-11-23T14:05:00.000000Z");
}

}  // namespace
