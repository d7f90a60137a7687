#include "hrgbench/results/utc_text.hpp"

#include <chrono>
#include <cstdio>

namespace hrgbench::results {
namespace {

// The digits at [at, at + n) as a number; -1 when any is not a digit.
int Digits(std::string_view text, std::size_t at, std::size_t n) {
  if (at + n > text.size()) return -1;
  int value = 0;
  for (std::size_t i = at; i < at + n; ++i) {
    if (text[i] < '0' || text[i] > '9') return -1;
    value = value * 10 + (text[i] - '0');
  }
  return value;
}

}  // namespace

std::optional<std::string> CanonicalUtc(std::string_view iso) {
  using namespace std::chrono;
  if (iso.size() < 19 || iso[4] != '-' || iso[7] != '-' || (iso[10] != 'T' && iso[10] != ' ') ||
      iso[13] != ':' || iso[16] != ':')
    return std::nullopt;
  const int y = Digits(iso, 0, 4), mo = Digits(iso, 5, 2), d = Digits(iso, 8, 2);
  const int h = Digits(iso, 11, 2), mi = Digits(iso, 14, 2), s = Digits(iso, 17, 2);
  if (y < 0 || mo < 0 || d < 0 || h < 0 || h > 23 || mi < 0 || mi > 59 || s < 0 || s > 59)
    return std::nullopt;
  const year_month_day ymd{year{y}, month{static_cast<unsigned>(mo)},
                           day{static_cast<unsigned>(d)}};
  if (!ymd.ok()) return std::nullopt;
  std::size_t at = 19;
  long long micros = 0;
  if (at < iso.size() && iso[at] == '.') {
    ++at;
    int scale = 100000, digits = 0;
    while (at < iso.size() && iso[at] >= '0' && iso[at] <= '9') {
      if (scale > 0) micros += (iso[at] - '0') * scale;
      scale /= 10;
      ++at;
      ++digits;
    }
    if (digits == 0) return std::nullopt;
  }
  int offset_min = 0;
  const std::string_view zone = iso.substr(at);
  if (zone == "Z" || zone == "z") {
  } else if (zone.size() == 6 && (zone[0] == '+' || zone[0] == '-') && zone[3] == ':') {
    const int oh = Digits(zone, 1, 2), om = Digits(zone, 4, 2);
    if (oh < 0 || oh > 23 || om < 0 || om > 59) return std::nullopt;
    offset_min = (zone[0] == '-' ? -1 : 1) * (oh * 60 + om);
  } else {
    return std::nullopt;  // no zone: local time of an unknown place, not a UTC time
  }
  const sys_time<microseconds> t = sys_days{ymd} + hours{h} + minutes{mi} + seconds{s} +
                                   microseconds{micros} - minutes{offset_min};
  const sys_days day_of_t = floor<days>(t);
  const year_month_day out{day_of_t};
  const hh_mm_ss<microseconds> clock{t - day_of_t};
  char text[40];
  std::snprintf(text, sizeof text, "%04d-%02u-%02uT%02d:%02d:%02d.%06lldZ",
                static_cast<int>(out.year()), static_cast<unsigned>(out.month()),
                static_cast<unsigned>(out.day()), static_cast<int>(clock.hours().count()),
                static_cast<int>(clock.minutes().count()),
                static_cast<int>(clock.seconds().count()),
                static_cast<long long>(clock.subseconds().count()));
  return std::string(text);
}

}  // namespace hrgbench::results
