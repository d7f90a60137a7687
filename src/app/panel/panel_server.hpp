#pragma once
// `hrg-bench serve`: the operator panel (issue 11 §2). One page (web/, embedded in the program;
// Chart.js from Debian's libjs-chart.js, served from the disk; nothing from a network), a small
// JSON API and the running session's events as Server-Sent Events.
//
//   GET  /                     the page
//   GET  /panel.js /panel_station.js /panel.css /chart.js
//   GET  /api/state            station, allowed sequences and limits with the station's defaults
//                              (default_sequence, default_limits: ids; no_limits: whether a
//                              session may run without), positions (a fixture's, else []), the
//                              current session, recent sessions; "interrupted": {session, unit,
//                              reason} when the panel's last session's process ended and left
//                              its record open, else null
//   GET  /api/events           text/event-stream: the current session's events from its start (or
//                              after Last-Event-ID), then live; ": keep-alive" every 5 s
//   POST /api/start            {"serial", "sequence": id, "limits": id | null, "operator"} ->
//                              {"session"}; a fixture: "serials": {POSITION: SERIAL} (every
//                              fitted position, "" = left empty) instead of "serial". The operator
//                              id is required; limits null only when the station offers it.
//   POST /api/resume           {} | {"session": NAME} (+ "operator") -> {"session", "resume":
//   true}: `hrg-bench
//                              resume` of the interrupted session (or of NAME, a folder directly
//                              in the sessions folder whose record is open) as the new session
//   POST /api/abort            {} -> {"aborting": true}
//   GET  /sessions/NAME/report/FILE   a session's report (only its report folder)
//   GET  /sessions/NAME/UNIT/report/FILE   a fixture unit's report (UNIT: its folder in NAME)
// Every refusal is a JSON {"error": "..."} with 4xx: 400 bad input, 401 no or wrong token, 403
// wrong Host/Origin, 404, 409 a session running (or none to abort, nothing to resume), 413 too
// large, 415 not JSON, 431 headers too large; a refused request's connection is closed.
//
// Security: listens on localhost by default; any other address needs an access token (a file of
// at least 16 printable characters, --token-file), which every request but the page's own files
// must then carry (?token= or "Authorization: Bearer"). Without a token a request must come from
// a loopback address (the socket's, not a header) and its Host must name the panel exactly
// (127.0.0.1, [::1] or localhost with the panel's port; panel_origin.hpp), so a page elsewhere
// cannot reach the panel through DNS rebinding. POSTs must be application/json and carry the
// token or the panel's own Origin (no cross-site posts; a different Origin is refused even with
// the token). What is read is bounded (panel_http.hpp): request line and headers 32 kB, a body
// 64 kB whether it has a Content-Length or comes in chunks. A report is streamed from its file,
// and served only when the file, links resolved, lies in that session's report folder inside the
// sessions folder. One panel per port: the listening socket is not shared (no SO_REUSEPORT); a
// second panel on the port fails with exit code 2. A serial is checked (serial_check.hpp) before
// it becomes a folder name; sequences and limits are chosen by id from the allowed list
// (panel_catalog.hpp); nothing the page sends becomes a path otherwise.
//
// Threads: RunPanel blocks the caller until `stop` becomes non-zero (the panel then aborts a
// running session, waits for it, and returns). Connections are admitted and read by the gate
// (panel_gate.hpp: bounds per client address and in all, head and idle timeouts, 405 for other
// methods) and each complete request is served on its lane's threads: Abort on its own, start,
// resume and state on the control threads, at most GateLimits::max_streams event streams, the rest
// on the general pool; so no stream, report or slow client can make an Abort wait.

#include <atomic>
#include <filesystem>
#include <string>

namespace hrgbench::app {

struct PanelOptions {
  std::filesystem::path station;
  std::string listen = "127.0.0.1:8080";  // host:port; host an IPv4 address or "localhost"
  std::filesystem::path sessions = "sessions";
  std::filesystem::path token_file;  // required when the host is not a loopback address
  std::filesystem::path program;     // hrg-bench itself (a session is `hrg-bench run`)
};

// Exit code (exit_codes.hpp): kExitOk after a stop; kExitBadInput (4) when the options are refused
// (message on stderr); kExitError (2) when the port cannot be bound (another panel or program holds
// it: the message names the port).
int RunPanel(const PanelOptions& options, const std::atomic<int>& stop);

}  // namespace hrgbench::app
