#pragma once
// One limit's decision drawn as a small horizontal bar (inline SVG, no script): the tolerance
// [min, max], its guard bands (the tolerance outside the acceptance zone [min + U, max − U],
// analysis/verdict.hpp), the value with its expanded interval v ± U, coloured by the decision's
// zone. For the report's limits table; the panel draws the same from the limit event
// (src/app/panel/web/panel.js, guardBandBar). Internal to src/report. Pure function.

#include <string>

#include "hrgbench/session/session_record.hpp"

namespace hrgbench::report::internal {

// The <svg class="guard-band" data-zone="..."> element, with a <title> that says it in words;
// "" when the row has no finite value or limits (nothing to draw). A record from before the
// decision rule (no interval) draws the value alone.
std::string GuardBandBar(const session::LimitRowRecord& limit);

}  // namespace hrgbench::report::internal
