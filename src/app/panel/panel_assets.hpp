#pragma once
// The operator panel's page, embedded at build time from src/app/panel/web/ (embed_assets.cmake),
// so the program needs no files of its own at run time (Chart.js comes from Debian's package).

#include <string_view>

namespace hrgbench::app {

extern const std::string_view kPanelHtml;  // web/panel.html
extern const std::string_view kPanelJs;    // web/panel.js
extern const std::string_view kPanelCss;   // web/panel.css
// web/panel_station.js: the operator, a fixture's positions, the plan (issue 26 §1)
extern const std::string_view kPanelStationJs;

}  // namespace hrgbench::app
