#include "app/panel/panel_server.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <thread>
#include <vector>

#include "app/fixture_session.hpp"
#include "app/panel/interrupted_session.hpp"
#include "app/panel/panel_assets.hpp"
#include "app/panel/panel_catalog.hpp"
#include "app/panel/panel_gate.hpp"
#include "app/panel/panel_origin.hpp"
#include "app/panel/session_process.hpp"
#include "app/report_job.hpp"
#include "app/serial_check.hpp"
#include "app/session_folder.hpp"
#include "hrgbench/report/html_escape.hpp"
#include "hrgbench/report/session_report.hpp"
#include "hrgbench/session/exit_codes.hpp"
// Last: it brings <httplib.h> and so <resolv.h>, whose `_res` macro breaks Eigen's headers
// (bench_configs.hpp).
#include "app/panel/panel_http.hpp"  // NOLINT(llvm-include-order)

namespace hrgbench::app {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kMaxBodyBytes = 64 * 1024;  // a start request is < 200 bytes
// A report is sent from its file in pieces of this size (a report of 300 runs is ~200 MB; eight
// browsers reading it whole would hold it eight times).
constexpr std::size_t kReportChunkBytes = 64 * 1024;
constexpr std::size_t kRecentSessions = 20;
constexpr auto kKeepAlive = std::chrono::seconds(5);  // also how long a stop waits for a stream

struct Listen {
  std::string host;
  int port = 0;
};

std::expected<Listen, std::string> ParseListen(const std::string& text) {
  const std::size_t colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0)
    return std::unexpected("--listen " + text + ": expected HOST:PORT (127.0.0.1:8080)");
  Listen listen;
  listen.host = text.substr(0, colon);
  const std::string port = text.substr(colon + 1);
  if (port.empty() || port.size() > 5 || port.find_first_not_of("0123456789") != std::string::npos)
    return std::unexpected("--listen " + text + ": the port must be a number in [1, 65535]");
  listen.port = std::stoi(port);
  if (listen.port < 1 || listen.port > 65535)
    return std::unexpected("--listen " + text + ": the port must be a number in [1, 65535]");
  return listen;
}

bool IsLoopbackListen(const std::string& host) {
  return host == "localhost" || IsLoopbackAddress(host);
}

// True when `path` (canonical) is `root` (canonical) or inside it, compared element by element
// (never as text: "/srv/sessions-old" is not inside "/srv/sessions").
bool IsInside(const fs::path& path, const fs::path& root) {
  auto p = path.begin();
  for (auto r = root.begin(); r != root.end(); ++r, ++p)
    if (p == path.end() || *p != *r) return false;
  return true;
}

std::expected<std::string, std::string> ReadToken(const fs::path& file) {
  std::error_code ec;
  if (fs::file_size(file, ec) > 4096 || ec)
    return std::unexpected("--token-file " + file.string() + ": missing or larger than 4 kB");
  std::ifstream in(file);
  std::string token;
  std::getline(in, token);
  while (!token.empty() && (token.back() == '\r' || token.back() == ' ')) token.pop_back();
  if (token.size() < 16)
    return std::unexpected("--token-file " + file.string() +
                           ": the token must be at least 16 characters on the first line");
  for (char c : token)
    if (static_cast<unsigned char>(c) < 0x21 || static_cast<unsigned char>(c) > 0x7e)
      return std::unexpected("--token-file " + file.string() +
                             ": the token must be printable ASCII without spaces");
  return token;
}

// Compares without an early exit, so the time taken does not say how much of a guess was right.
bool SameToken(const std::string& given, const std::string& token) {
  unsigned char diff = given.size() == token.size() ? 0 : 1;
  for (std::size_t i = 0; i < token.size(); ++i)
    diff |= static_cast<unsigned char>(token[i] ^ (i < given.size() ? given[i] : 0));
  return diff == 0;
}

void Error(httplib::Response& res, int status, const std::string& message) {
  res.status = status;
  res.set_content(nlohmann::json({{"error", message}}).dump(), "application/json");
}

std::string ContentType(const fs::path& file) {
  const std::string ext = file.extension().string();
  if (ext == ".html") return "text/html; charset=utf-8";
  if (ext == ".svg") return "image/svg+xml";
  if (ext == ".pdf") return "application/pdf";
  if (ext == ".png") return "image/png";
  if (ext == ".json") return "application/json";
  return "application/octet-stream";
}

// A string field of a JSON object, "" when absent or not a string (json::value with a string
// default trips GCC 12's -Wnull-dereference).
std::string StringField(const nlohmann::json& object, const char* key) {
  if (!object.is_object() || !object.contains(key) || !object[key].is_string()) return "";
  return object[key].get<std::string>();
}

std::expected<std::string, std::string> ReadBounded(const fs::path& file, std::uintmax_t max) {
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(file, ec);
  if (ec || size > max) return std::unexpected(file.string() + ": missing or too large");
  std::ifstream in(file, std::ios::binary);
  std::string text(size, '\0');
  in.read(text.data(), static_cast<std::streamsize>(size));
  if (!in) return std::unexpected(file.string() + ": cannot read");
  return text;
}

// The gate's lanes (panel_gate.hpp): Abort on threads of its own, start and state on the control
// threads, the event stream on the bounded stream threads.
Lane ClassifyRequest(std::string_view method, std::string_view path) {
  if (method == "POST" && path == "/api/abort") return Lane::kAbort;
  if ((method == "POST" &&
       (path == "/api/start" || path == "/api/resume" || path == "/api/prompt")) ||
      path == "/api/state")
    return Lane::kControl;
  if (path == "/api/events") return Lane::kStream;
  return Lane::kGeneral;
}

class Panel {
 public:
  Panel(const PanelOptions& options, Listen listen, PanelCatalog catalog, fs::path sessions,
        std::string token, std::string chart_js)
      : options_(options),
        listen_(std::move(listen)),
        catalog_(std::move(catalog)),
        sessions_(std::move(sessions)),
        token_(std::move(token)),
        chart_js_(std::move(chart_js)) {}

  void Route(httplib::Server& server) {
    // Covers a body with a Content-Length only (cpp-httplib 0.11); a chunked one is bounded as it
    // is read (ReadBody), and BoundedServer bounds the raw bytes of both.
    server.set_payload_max_length(kMaxBodyBytes);
    server.set_pre_routing_handler(
        [this](const httplib::Request& req, httplib::Response& res) { return Guard(req, res); });
    server.Get("/", [](const httplib::Request&, httplib::Response& res) {
      res.set_content(std::string(kPanelHtml), "text/html; charset=utf-8");
    });
    server.Get("/panel.js", [](const httplib::Request&, httplib::Response& res) {
      res.set_content(std::string(kPanelJs), "text/javascript; charset=utf-8");
    });
    server.Get("/panel_station.js", [](const httplib::Request&, httplib::Response& res) {
      res.set_content(std::string(kPanelStationJs), "text/javascript; charset=utf-8");
    });
    server.Get("/panel.css", [](const httplib::Request&, httplib::Response& res) {
      res.set_content(std::string(kPanelCss), "text/css; charset=utf-8");
    });
    // Browsers ask for it on every page (the report's too): no icon, and no 404 in their console.
    server.Get("/favicon.ico",
               [](const httplib::Request&, httplib::Response& res) { res.status = 204; });
    server.Get("/chart.js", [this](const httplib::Request&, httplib::Response& res) {
      res.set_content(chart_js_, "text/javascript; charset=utf-8");
    });
    server.Get("/api/state", [this](const httplib::Request&, httplib::Response& res) {
      res.set_content(State().dump(), "application/json");
    });
    server.Get("/api/events",
               [this](const httplib::Request& req, httplib::Response& res) { Events(req, res); });
    server.Post("/api/start", [this](const httplib::Request&, httplib::Response& res,
                                     const httplib::ContentReader& reader) {
      const auto body = ReadBody(res, reader);
      if (body) Start(*body, res);
    });
    server.Post("/api/resume", [this](const httplib::Request&, httplib::Response& res,
                                      const httplib::ContentReader& reader) {
      const auto body = ReadBody(res, reader);
      if (body) Resume(*body, res);
    });
    server.Post("/api/abort", [this](const httplib::Request&, httplib::Response& res,
                                     const httplib::ContentReader& reader) {
      if (!ReadBody(res, reader)) return;
      if (auto refused = process_.Abort()) return Error(res, 409, *refused);
      res.set_content(R"({"aborting":true})", "application/json");
    });
    server.Post("/api/prompt", [this](const httplib::Request&, httplib::Response& res,
                                      const httplib::ContentReader& reader) {
      const auto body = ReadBody(res, reader);
      if (body) AnswerPrompt(*body, res);
    });
    server.Get(R"(/sessions/([^/]+)/report/([^/]+))",
               [this](const httplib::Request& req, httplib::Response& res) {
                 Report(req.matches[1], "", req.matches[2], res);
               });
    // A fixture's unit: its folder in the fixture's folder.
    server.Get(R"(/sessions/([^/]+)/([^/]+)/report/([^/]+))",
               [this](const httplib::Request& req, httplib::Response& res) {
                 Report(req.matches[1], req.matches[2], req.matches[3], res);
               });
    server.set_error_handler([](const httplib::Request&, httplib::Response& res) {
      // A refused request's unread rest must not be taken for the next request.
      BoundedServer::CloseConnectionAfterResponse();
      res.set_header("Connection", "close");
      const BoundHit hit = BoundedServer::CurrentRequestHit();
      if (hit == BoundHit::kHead)
        return Error(res, 431,
                     "the request's line and headers are too large (at most " +
                         std::to_string(RequestBounds{}.head_bytes / 1024) + " kB)");
      if (hit == BoundHit::kBody) return Error(res, 413, "the request is too large");
      if (res.body.empty()) {
        const char* what = res.status == 413   ? "the request is too large"
                           : res.status == 404 ? "not found"
                                               : "refused";
        Error(res, res.status, what);
      }
    });
  }

  std::atomic<bool> stopping{false};
  SessionProcess process_;

 private:
  httplib::Server::HandlerResponse Guard(const httplib::Request& req, httplib::Response& res) {
    using HR = httplib::Server::HandlerResponse;
    // The page's own files hold nothing of the station's: a browser loads them before the page's
    // script can add the token. Everything else (state, events, start, abort, reports) needs it.
    const bool page_file =
        req.method == "GET" &&
        (req.path == "/" || req.path == "/panel.js" || req.path == "/panel_station.js" ||
         req.path == "/panel.css" || req.path == "/chart.js" || req.path == "/favicon.ico");
    const std::string host = req.get_header_value("Host");
    bool with_token = false;
    if (!token_.empty()) {
      std::string given = req.get_param_value("token");
      const std::string auth = req.get_header_value("Authorization");
      if (given.empty() && auth.rfind("Bearer ", 0) == 0) given = auth.substr(7);
      with_token = SameToken(given, token_);
      if (!with_token && !page_file) {
        Error(res, 401,
              "this panel needs its access token: open it with ?token=... (the token is in the "
              "panel's --token-file)");
        return HR::Handled;
      }
    } else if (!IsLoopbackAddress(req.remote_addr) ||
               !IsPanelHost(host, listen_.host, listen_.port)) {
      // Without a token: a connection from this machine (the socket says so, not a header),
      // addressed to the panel by its exact name; a rebinding name is refused, prefix or not.
      Error(res, 403,
            "this panel answers requests addressed to localhost only (http://127.0.0.1:" +
                std::to_string(listen_.port) +
                "/ or http://localhost:" + std::to_string(listen_.port) + "/)");
      return HR::Handled;
    }
    if (req.method == "POST") {
      const std::string type = req.get_header_value("Content-Type");
      if (type.rfind("application/json", 0) != 0) {
        Error(res, 415, "a request to the panel must be application/json");
        return HR::Handled;
      }
      // A change to the station needs the token or the panel's own Origin (a browser sends it
      // with every POST and a page of another site cannot forge it); a different Origin is
      // refused even with the token.
      const std::string origin = req.get_header_value("Origin");
      if (!origin.empty() && !IsPanelOrigin(origin, host)) {
        Error(res, 403,
              "a request from another site is refused (Origin " + origin.substr(0, 80) + ")");
        return HR::Handled;
      }
      if (origin.empty() && !with_token) {
        Error(res, 403,
              "a request that changes the station needs the panel's own Origin (as its page "
              "sends) or its access token");
        return HR::Handled;
      }
    }
    return HR::Unhandled;
  }

  nlohmann::json State() const {
    nlohmann::json sequences = nlohmann::json::array();
    for (std::size_t i = 0; i < catalog_.sequences.size(); ++i)
      sequences.push_back({{"id", i},
                           {"name", catalog_.sequences[i].name},
                           {"description", catalog_.sequences[i].description},
                           {"plan", catalog_.sequences[i].plan}});
    nlohmann::json limits = nlohmann::json::array();
    for (std::size_t i = 0; i < catalog_.limits.size(); ++i)
      limits.push_back(
          {{"id", i}, {"name", catalog_.limits[i].name}, {"plan", catalog_.limits[i].plan}});
    // A fixture's positions, in the station's order: the page shows one serial field each.
    nlohmann::json positions = nlohmann::json::array();
    const auto fitted = bench::FittedPositions(catalog_.station);
    if (fitted.size() > 1)
      for (const auto* position : fitted) positions.push_back(position->name);
    // The station's last sessions: from its results store when it has one, else this folder.
    nlohmann::json recent;
    std::string recent_source;
    if (!catalog_.station.results_url.empty()) {
      auto stored = RecentSessionsFromStore(catalog_.station.results_url, catalog_.station.name,
                                            sessions_, kRecentSessions);
      if (stored) {
        recent = std::move(*stored);
        recent_source = catalog_.station.results_url;
      } else {
        spdlog::warn("panel: recent sessions from the folder: {}", stored.error());
        recent_source = "the sessions folder (the results store: " + stored.error() + ")";
      }
    }
    if (recent.is_null()) {
      recent = RecentSessions(sessions_, kRecentSessions);
      if (recent_source.empty()) recent_source = "the sessions folder";
    }
    const nlohmann::json session = nlohmann::json::parse(process_.StatusJson());
    const auto interrupted = Interrupted(session);
    return {{"station", catalog_.station.name},
            {"station_kind", std::string(bench::ToString(catalog_.station.kind))},
            {"sequences", sequences},
            {"limits", limits},
            {"default_sequence", catalog_.default_sequence},
            {"default_limits",
             catalog_.limits.empty() ? nlohmann::json() : nlohmann::json(catalog_.default_limits)},
            {"no_limits", catalog_.no_limits},
            {"positions", positions},
            {"session", session},
            {"interrupted", interrupted ? nlohmann::json({{"session", interrupted->session},
                                                          {"unit", interrupted->serial},
                                                          {"reason", interrupted->reason}})
                                        : nlohmann::json()},
            {"recent", recent},
            {"recent_source", recent_source}};
  }

  // A POST's body, at most kMaxBodyBytes whatever its framing (a Content-Length or chunks);
  // nullopt after answering 413 (too large) or 400 (cut short).
  static std::optional<std::string> ReadBody(httplib::Response& res,
                                             const httplib::ContentReader& reader) {
    std::string body;
    bool too_large = false;
    const bool read = reader([&](const char* data, std::size_t size) {
      if (body.size() + size > kMaxBodyBytes) {
        too_large = true;
        return false;
      }
      body.append(data, size);
      return true;
    });
    if (too_large || res.status == 413 || BoundedServer::CurrentRequestHit() == BoundHit::kBody) {
      Error(res, 413,
            "the request is too large (at most " + std::to_string(kMaxBodyBytes / 1024) + " kB)");
      return std::nullopt;
    }
    if (!read) {
      Error(res, 400, "the request's body could not be read");
      return std::nullopt;
    }
    return body;
  }

  // {"id", "answer": "confirm" | "abort", "operator"}: the open prompt answered by the operator
  // at the page (recorded as who answered it, so the operator is required as for a start).
  void AnswerPrompt(const std::string& text, httplib::Response& res) {
    const nlohmann::json body = nlohmann::json::parse(text, nullptr, false);
    if (body.is_discarded() || !body.is_object())
      return Error(res, 400, "the request is not a JSON object");
    for (const auto& [key, value] : body.items())
      if (key != "id" && key != "answer" && key != "operator")
        return Error(
            res, 400,
            "unknown field \"" + key.substr(0, 32) + "\": expected id, answer and operator");
    const std::string id = StringField(body, "id");
    const std::string answer = StringField(body, "answer");
    if (id.empty()) return Error(res, 400, "id: the prompt's id is required");
    if (answer != "confirm" && answer != "abort")
      return Error(res, 400, "answer: \"confirm\" or \"abort\"");
    const std::string operator_id = StringField(body, "operator");
    if (auto problem = OperatorProblem(operator_id))
      return Error(res, 400,
                   "operator: " + *problem + " (enter or scan your operator id once per shift)");
    if (auto refused = process_.AnswerPrompt(id, answer == "confirm", operator_id))
      return Error(res, 409, *refused);
    res.set_content(R"({"answered":true})", "application/json");
  }

  // {"serial" | "serials", "sequence", "limits", "operator"}: one unit ("serial"), or a fixture
  // station's units by position ("serials": {POSITION: SERIAL}, every fitted position named, ""
  // for one left empty on purpose). Everything the child would refuse is refused here first
  // (PlanFixture, the serial and operator checks, the station's offers): a start the page is told
  // succeeded does not end in a refusal only the server's log would show.
  void Start(const std::string& text, httplib::Response& res) {
    const nlohmann::json body = nlohmann::json::parse(text, nullptr, false);
    if (body.is_discarded() || !body.is_object())
      return Error(res, 400, "the request is not a JSON object");
    for (const auto& [key, value] : body.items())
      if (key != "serial" && key != "serials" && key != "sequence" && key != "limits" &&
          key != "operator")
        return Error(res, 400,
                     "unknown field \"" + key.substr(0, 32) +
                         "\": expected serial (or serials), sequence, limits and operator");
    const bool fixture = bench::FittedPositions(catalog_.station).size() > 1;
    std::vector<std::string> serial_arguments;
    std::vector<std::pair<std::string, std::string>> units;
    std::string serial;
    if (fixture) {
      if (body.contains("serial"))
        return Error(res, 400,
                     "serials: station '" + catalog_.station.name +
                         "' is a fixture: one serial per position ({POSITION: SERIAL})");
      if (!body.contains("serials") || !body["serials"].is_object() ||
          body["serials"].size() > bench::kMaxFixturePositions)
        return Error(res, 400, "serials: an object {POSITION: SERIAL} is required");
      for (const auto& [position, value] : body["serials"].items()) {
        if (!value.is_string())
          return Error(res, 400, "serials: position " + position.substr(0, 32) + ": a string");
        serial_arguments.push_back(position + "=" + value.get<std::string>());
      }
      auto plan = PlanFixture(catalog_.station, serial_arguments);
      if (!plan) return Error(res, 400, plan.error());
      for (const FixtureUnit& unit : plan->units) units.emplace_back(unit.position, unit.serial);
      serial = "fixture";
    } else {
      if (body.contains("serials"))
        return Error(
            res, 400,
            "serials: station '" + catalog_.station.name + "' has one position: give serial");
      if (!body.contains("serial") || !body["serial"].is_string())
        return Error(res, 400, "serial: a string is required");
      serial = body["serial"];
      if (auto problem = SerialProblem(serial)) return Error(res, 400, *problem);
      serial_arguments.push_back(serial);
    }
    if (!body.contains("sequence") || !body["sequence"].is_number_unsigned() ||
        body["sequence"].get<std::size_t>() >= catalog_.sequences.size())
      return Error(res, 400,
                   "sequence: one of the station's allowed sequences (by id) is required");
    const AllowedConfig& sequence = catalog_.sequences[body["sequence"].get<std::size_t>()];
    const AllowedConfig* limits = nullptr;
    if (body.contains("limits") && !body["limits"].is_null()) {
      if (!body["limits"].is_number_unsigned() ||
          body["limits"].get<std::size_t>() >= catalog_.limits.size())
        return Error(res, 400, "limits: one of the station's allowed limits (by id) or null");
      limits = &catalog_.limits[body["limits"].get<std::size_t>()];
    }
    if (limits == nullptr && !catalog_.no_limits)
      return Error(res, 400,
                   "limits: station '" + catalog_.station.name +
                       "' judges every session: choose one of its limits (no session without)");
    const std::string operator_id = StringField(body, "operator");
    if (auto problem = OperatorProblem(operator_id))
      return Error(res, 400,
                   "operator: " + *problem + " (enter or scan your operator id once per shift)");
    if (process_.Running())
      return Error(res, 409,
                   "a session is already running on this station: one session at a time; wait "
                   "for it to end or abort it");
    // The folder: the checked serial (a fixture: "fixture") and a time stamp, directly in the
    // sessions folder.
    const auto folder = NewSessionFolder(sessions_, serial, std::time(nullptr));
    if (!folder || folder->parent_path() != sessions_)
      return Error(res, 409, "cannot choose a new session folder for " + serial);
    const fs::path& dir = *folder;
    const std::string name = dir.filename().string();
    SessionLaunch launch;
    launch.program = options_.program.string();
    launch.arguments = {"run", "--station", catalog_.station_file.string(), "--sequence",
                        sequence.file.string()};
    for (const std::string& s : serial_arguments) {
      launch.arguments.push_back("--serial");
      launch.arguments.push_back(s);
    }
    // --report background: the station is free for the next unit while this one's report (and
    // Chromium's PDF) is written; its link answers "being written" until then.
    for (const char* a : {"--operator", operator_id.c_str(), "-o", dir.c_str(), "--events",
                          "/dev/fd/3", "--report", "background"})
      launch.arguments.emplace_back(a);
    if (limits != nullptr) {
      launch.arguments.push_back("--limits");
      launch.arguments.push_back(limits->file.string());
    }
    launch.serial = serial;
    launch.sequence = sequence.name;
    launch.limits = limits != nullptr ? limits->name : "";
    launch.session_name = name;
    launch.operator_id = operator_id;
    launch.units = std::move(units);
    if (auto refused = process_.Start(launch)) return Error(res, 409, *refused);
    res.set_content(nlohmann::json({{"session", name}}).dump(), "application/json");
  }

  // The panel's last session when its process has ended and left the record open (`session` is
  // SessionProcess::StatusJson parsed); nullopt while it runs, when it closed its record, or when
  // the panel has run none.
  std::optional<InterruptedSession> Interrupted(const nlohmann::json& session) const {
    if (!session.is_object() || !session.contains("running") || session["running"] != false ||
        !session.contains("exit") || session["exit"].is_null())
      return std::nullopt;
    return OpenSession(sessions_, StringField(session, "session"),
                       ProcessEndReason(session["exit"]));
  }

  // `hrg-bench resume` of an interrupted session as the new child: {} resumes the panel's own
  // (the one /api/state calls interrupted); {"session": NAME} one directly in the sessions folder
  // whose record is open (a panel restarted after its session's process died). Nothing else:
  // the name is checked as a folder of the sessions folder, links resolved, never used as a path.
  void Resume(const std::string& text, httplib::Response& res) {
    const nlohmann::json body = nlohmann::json::parse(text, nullptr, false);
    if (body.is_discarded() || !body.is_object())
      return Error(res, 400, "the request is not a JSON object");
    for (const auto& [key, value] : body.items())
      if (key != "session" && key != "operator")
        return Error(
            res, 400,
            "unknown field \"" + key.substr(0, 32) + "\": expected at most session and operator");
    if (body.contains("session") && !body["session"].is_string())
      return Error(res, 400, "session: the name of a session folder (a string)");
    const std::string operator_id = StringField(body, "operator");
    if (body.contains("operator"))
      if (auto problem = OperatorProblem(operator_id))
        return Error(res, 400, "operator: " + *problem);
    if (process_.Running())
      return Error(res, 409,
                   "a session is already running on this station: one session at a time; wait "
                   "for it to end or abort it");
    const nlohmann::json last = nlohmann::json::parse(process_.StatusJson());
    const auto own = Interrupted(last);
    std::string name = StringField(body, "session");
    if (name.empty()) {
      if (!own)
        return Error(res, 409,
                     "no interrupted session to resume: the panel's last session closed its "
                     "record, or the panel has run none");
      name = own->session;
    }
    std::error_code ec;
    const fs::path dir = fs::canonical(sessions_ / name, ec);
    if (!IsSessionName(sessions_, name) || ec || dir.parent_path() != sessions_)
      return Error(res, 404, "no session folder " + name.substr(0, 80) + " in the sessions folder");
    const auto open =
        own && own->session == name ? own : OpenSession(sessions_, name, std::string());
    if (!open)
      return Error(res, 409,
                   "session " + name +
                       " has nothing to resume: its record is closed, or it has "
                       "no readable session.json");
    SessionLaunch launch;
    launch.program = options_.program.string();
    launch.arguments = {"resume", dir.string(), "--events", "/dev/fd/3", "--report", "background"};
    if (!operator_id.empty()) {
      launch.arguments.push_back("--operator");
      launch.arguments.push_back(operator_id);
    }
    launch.operator_id = operator_id;
    launch.serial = open->serial;
    launch.units = open->units;  // a fixture's: the page shows each unit again
    // The names the page showed for it, when it was the panel's own; the record keeps the rest.
    const bool same = StringField(last, "session") == name;
    launch.sequence = same ? StringField(last, "sequence") : "";
    launch.limits = same ? StringField(last, "limits") : "";
    launch.session_name = name;
    launch.resume = true;
    if (auto refused = process_.Start(launch)) return Error(res, 409, *refused);
    spdlog::info("panel: resuming {} ({})", name, open->reason);
    res.set_content(nlohmann::json({{"session", name}, {"resume", true}}).dump(),
                    "application/json");
  }

  void Events(const httplib::Request& req, httplib::Response& res) {
    std::uint64_t after = 0;
    const std::string last = req.get_header_value("Last-Event-ID");
    if (!last.empty() && last.size() < 20 &&
        last.find_first_not_of("0123456789") == std::string::npos)
      after = std::stoull(last);
    // A browser that comes back after a new session started gets that session from its start.
    const std::uint64_t first = process_.FirstId();
    if (first > 0 && after + 1 < first) after = first - 1;
    res.set_header("Cache-Control", "no-cache");
    res.set_header("X-Accel-Buffering", "no");
    res.set_chunked_content_provider(
        "text/event-stream", [this, after](std::size_t, httplib::DataSink& sink) mutable {
          if (stopping) {
            sink.done();
            return true;
          }
          const std::vector<KeptEvent> events = process_.WaitForEvents(after, kKeepAlive);
          if (events.empty()) {
            const std::string ping = ": keep-alive\n\n";
            return sink.write(ping.data(), ping.size());
          }
          std::string chunk;
          for (const KeptEvent& e : events) {
            chunk += "id: " + std::to_string(e.id) + "\ndata: " + e.json + "\n\n";
            after = e.id;
          }
          return sink.write(chunk.data(), chunk.size());
        });
  }

  // `unit`: empty, or a fixture unit's folder inside the session folder `name`.
  void Report(const std::string& name, const std::string& unit, const std::string& file,
              httplib::Response& res) {
    if (!IsSessionName(sessions_, name) ||
        (!unit.empty() && !IsSessionName(sessions_ / name, unit)) || file.empty() ||
        file.front() == '.' ||
        file.find_first_not_of(
            "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789._-") !=
            std::string::npos)
      return Error(res, 404, "no such session report");
    // Resolved, links and all, and served only when both the report folder and the file lie
    // inside the sessions folder (a link to /etc/passwd, or a report folder that is a link to
    // elsewhere, is not found). What is opened is the resolved path, which has no links left.
    std::error_code ec;
    const fs::path session_dir = unit.empty() ? sessions_ / name : sessions_ / name / unit;
    const fs::path report_dir = fs::canonical(session_dir / "report", ec);
    if (ec || !IsInside(report_dir, sessions_)) return Error(res, 404, "no such session report");
    const fs::path path = fs::canonical(session_dir / "report" / file, ec);
    if (ec || !IsInside(path, report_dir) || !fs::is_regular_file(path, ec)) {
      if (file == "report.html") return ReportNotYet(report_dir, res);
      return Error(res, 404, "no such session report");
    }
    auto stream = std::make_shared<ReportStream>();
    stream->in.open(path, std::ios::binary);
    const std::uintmax_t size = fs::file_size(path, ec);
    if (ec || !stream->in) return Error(res, 404, "no such session report");
    if (size == 0)
      return res.set_content(std::string(), ContentType(file));  // a provider needs bytes
    // Streamed from the file: one buffer per response, whatever the file's size.
    res.set_content_provider(
        static_cast<std::size_t>(size), ContentType(file),
        [stream](std::size_t offset, std::size_t length, httplib::DataSink& sink) {
          stream->buffer.resize(kReportChunkBytes);
          stream->in.seekg(static_cast<std::streamoff>(offset));
          stream->in.read(stream->buffer.data(),
                          static_cast<std::streamsize>(std::min(length, kReportChunkBytes)));
          const auto got = static_cast<std::size_t>(stream->in.gcount());
          // A file that shrank since it was opened: the response is cut (its length was sent).
          return got > 0 && sink.write(stream->buffer.data(), got);
        });
  }

  // A report not (yet) there: a job still writing it answers 202 with a page that reloads until
  // it is (an operator who opens the link at the session's end gets the report seconds later);
  // a job that failed or was killed says why and how to make the report again.
  static void ReportNotYet(const fs::path& report_dir, httplib::Response& res) {
    std::error_code ec;
    const fs::path job_file = fs::canonical(report_dir / "job.json", ec);
    if (ec || !IsInside(job_file, report_dir)) return Error(res, 404, "no such session report");
    const auto job = ReadReportJob(report_dir.parent_path());
    if (!job || !*job) return Error(res, 404, "no such session report");
    if ((*job)->state == ReportJobState::kRunning) {
      res.status = 202;
      res.set_header("Retry-After", "2");
      res.set_content(
          "<!doctype html><html><head><meta charset=\"utf-8\"><meta http-equiv=\"refresh\" "
          "content=\"2\"><title>report being written</title></head><body><p id=\"report-job\" "
          "data-state=\"running\">The report is being written (job " +
              std::to_string((*job)->pid) + ", started " + report::HtmlEscape((*job)->started) +
              "); this page reloads until it is there.</p></body></html>",
          "text/html; charset=utf-8");
      return;
    }
    Error(res, 404,
          "the report was not written (" + std::string(ToString((*job)->state)) + ": " +
              (*job)->reason + "); `hrg-report " + report_dir.parent_path().string() +
              "` writes it");
  }

  struct ReportStream {
    std::ifstream in;
    std::vector<char> buffer;
  };

  PanelOptions options_;
  Listen listen_;
  PanelCatalog catalog_;
  fs::path sessions_;
  std::string token_;
  std::string chart_js_;
};

}  // namespace

int RunPanel(const PanelOptions& options, const std::atomic<int>& stop) {
  auto listen = ParseListen(options.listen);
  if (!listen) {
    std::cerr << listen.error() << '\n';
    return kExitBadInput;
  }
  std::string token;
  if (!options.token_file.empty()) {
    auto read = ReadToken(options.token_file);
    if (!read) {
      std::cerr << read.error() << '\n';
      return kExitBadInput;
    }
    token = *read;
  } else if (!IsLoopbackListen(listen->host)) {
    std::cerr << "--listen " << options.listen
              << ": another address than localhost needs an access token (--token-file FILE), "
                 "or listen on localhost behind a reverse proxy\n";
    return kExitBadInput;
  }
  auto catalog = LoadPanelCatalog(options.station);
  if (!catalog) {
    std::cerr << catalog.error() << '\n';
    return kExitBadInput;
  }
  std::error_code ec;
  fs::create_directories(options.sessions, ec);
  const fs::path sessions = fs::weakly_canonical(options.sessions, ec);
  if (ec || !fs::is_directory(sessions, ec)) {
    std::cerr << "--sessions " << options.sessions.string() << ": not a usable folder\n";
    return kExitBadInput;
  }
  std::string chart_js;
  for (const char* candidate : report::kChartJsCandidates) {
    if (auto text = ReadBounded(candidate, 16u << 20)) {
      chart_js = std::move(*text);
      break;
    }
  }
  if (chart_js.empty()) {
    std::cerr << "Chart.js not found (Debian's libjs-chart.js: " << report::kChartJsCandidates[0]
              << ")\n";
    return kExitBadInput;
  }

  Panel panel(options, *listen, std::move(*catalog), sessions, token, std::move(chart_js));
  BoundedServer server{RequestBounds{}};
  server.set_socket_options(ExclusiveListenSocket);  // one panel per port
  panel.Route(server);
  const GateLimits limits;
  if (!server.Bind(listen->host, listen->port, limits.backlog)) {
    std::cerr << "--listen " << options.listen << ": cannot listen on port " << listen->port
              << " of " << listen->host
              << ": the port is in use (another panel or program on this station?) or the "
                 "address is not this machine's\n";
    return kExitError;
  }
  PanelGate gate(server, limits, ClassifyRequest);
  std::thread watcher([&] {
    while (stop.load() == 0) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    panel.stopping = true;
    if (panel.process_.Running()) (void)panel.process_.Abort();
    while (panel.process_.Running()) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    gate.Stop();
  });
  spdlog::info("panel: station '{}' on http://{}:{}/ (sessions in {})", options.station.string(),
               listen->host, listen->port, sessions.string());
  std::cout << "panel: http://" << listen->host << ":" << listen->port << "/" << std::endl;
  gate.Serve();
  watcher.join();
  return kExitOk;
}

}  // namespace hrgbench::app
