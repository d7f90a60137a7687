// hrg-results serve: the line view over HTTP (line_view.hpp), loopback only, read-only.
#include <csignal>
#include <ctime>
#include <iostream>

#include "app/line_view.hpp"
#include "hrgbench/session/exit_codes.hpp"
// Last: <httplib.h> brings <resolv.h>, whose `_res` macro breaks Eigen's headers.
#include <httplib.h>

namespace hrgbench::app {
namespace {

httplib::Server* g_server = nullptr;

extern "C" void StopServer(int) {
  if (g_server != nullptr) g_server->stop();
}

std::string TodayUtc() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[16];
  std::strftime(text, sizeof text, "%Y-%m-%d", &utc);
  return text;
}

// The view now, or why not (the store down, an older schema: said on the page, status 503).
std::expected<nlohmann::json, std::string> View(const std::string& url, const std::string& day) {
  auto store = results::ResultsStore::OpenExisting(url);
  if (!store) return std::unexpected(store.error().message);
  if (*store == nullptr) return std::unexpected("no results store at " + url);
  auto latest = (*store)->LatestPerStation();
  if (!latest) return std::unexpected(latest.error().message);
  results::SessionFilter filter;
  filter.since_utc = day.empty() ? TodayUtc() : day;
  auto today = (*store)->Sessions(filter);
  if (!today) return std::unexpected(today.error().message);
  // Only that day: --today names a day, not "since".
  std::erase_if(*today, [&](const results::SessionSummary& s) {
    return s.started_utc.compare(0, filter.since_utc.size(), filter.since_utc) != 0;
  });
  return LineViewJson(filter.since_utc, *latest, *today);
}

}  // namespace

int ServeLineView(const std::string& url, int port, const std::string& day) {
  httplib::Server server;
  server.Get("/", [&](const httplib::Request&, httplib::Response& response) {
    auto view = View(url, day);
    if (!view) {
      response.status = 503;
      response.set_content("line view not available: " + view.error() + "\n", "text/plain");
      return;
    }
    response.set_content(LineViewHtml(*view, url), "text/html; charset=utf-8");
  });
  server.Get("/api/line", [&](const httplib::Request&, httplib::Response& response) {
    auto view = View(url, day);
    if (!view) {
      response.status = 503;
      response.set_content(nlohmann::json{{"error", view.error()}}.dump(), "application/json");
      return;
    }
    response.set_content(view->dump(-1, ' ', false, nlohmann::json::error_handler_t::replace),
                         "application/json");
  });
  const int bound = port == 0 ? server.bind_to_any_port("127.0.0.1")
                              : (server.bind_to_port("127.0.0.1", port) ? port : -1);
  if (bound < 0) {
    std::cerr << "hrg-results: serve: cannot listen on 127.0.0.1:" << port << '\n';
    return kExitError;
  }
  g_server = &server;
  std::signal(SIGINT, StopServer);
  std::signal(SIGTERM, StopServer);
  std::cout << "line view: http://127.0.0.1:" << bound << "/" << std::endl;
  const bool ok = server.listen_after_bind();
  g_server = nullptr;
  return ok ? kExitOk : kExitError;
}

}  // namespace hrgbench::app
