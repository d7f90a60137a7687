#pragma once
// Who may talk to the panel (issue 25 row 2): the decisions on a request's origin, as pure
// functions of text, so they are tested without a server.
//
// Without a token the panel answers only a connection that comes from this machine (the socket's
// remote address, which a web page cannot forge) and only a Host header that names the panel
// exactly: 127.0.0.1, [::1] or localhost, with the panel's port. A page served by a rebinding
// name (127.attacker.example resolving to 127.0.0.1) sends its own name as Host and is refused;
// a prefix is never enough. A state-changing request (a POST) must further carry the token or
// an Origin equal to "http://" + the accepted Host, which a page of another site cannot send.
// Nothing here allocates beyond the strings returned; none throws.

#include <optional>
#include <string>
#include <string_view>

namespace hrgbench::app {

// A Host header split into its host and port: "localhost:8080" -> {"localhost", 8080},
// "[::1]:80" -> {"[::1]", 80}, "127.0.0.1" -> {"127.0.0.1", nullopt}. nullopt when the text is
// not a host with an optional decimal port in [1, 65535] (empty, a stray ':', "[::1" without its
// ']', a port with other characters than digits, more than one ':' outside brackets).
struct HostPort {
  std::string host;
  std::optional<int> port;
};
std::optional<HostPort> ParseHostHeader(std::string_view header);

// True for an address the kernel reports for a connection from this machine: 127.0.0.0/8
// (dotted quad, each part 0-255), ::1, and ::ffff:127.x.y.z (IPv4 on an IPv6 socket).
bool IsLoopbackAddress(std::string_view remote_addr);

// True when `header` names the panel listening on `listen_host`:`port` exactly: 127.0.0.1, [::1],
// localhost (any case) or `listen_host` itself when it is a loopback address (127.0.0.2),
// followed by ":port"; the port may be left out only when it is 80 (HTTP's default, which
// browsers then omit).
bool IsPanelHost(std::string_view header, std::string_view listen_host, int port);

// True when `origin` is exactly the origin of a page served at the accepted Host `host_header`.
bool IsPanelOrigin(std::string_view origin, std::string_view host_header);

}  // namespace hrgbench::app
