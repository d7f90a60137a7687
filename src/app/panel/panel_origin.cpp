#include "app/panel/panel_origin.hpp"

#include <algorithm>
#include <cctype>

namespace hrgbench::app {
namespace {

bool AllDigits(std::string_view text) {
  return !text.empty() &&
         std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
}

std::optional<int> ParsePort(std::string_view text) {
  if (!AllDigits(text) || text.size() > 5) return std::nullopt;
  int port = 0;
  for (char c : text) port = port * 10 + (c - '0');
  if (port < 1 || port > 65535) return std::nullopt;
  return port;
}

// A dotted quad whose first part is 127, each part 0-255 without a sign or spaces.
bool IsLoopbackIpv4(std::string_view text) {
  int parts = 0;
  while (true) {
    const std::size_t dot = text.find('.');
    const std::string_view part = text.substr(0, dot);
    if (!AllDigits(part) || part.size() > 3) return false;
    const int value = std::stoi(std::string(part));
    if (value > 255 || (parts == 0 && value != 127)) return false;
    ++parts;
    if (dot == std::string_view::npos) break;
    text.remove_prefix(dot + 1);
  }
  return parts == 4;
}

std::string Lower(std::string_view text) {
  std::string out(text);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

}  // namespace

std::optional<HostPort> ParseHostHeader(std::string_view header) {
  if (header.empty()) return std::nullopt;
  HostPort out;
  std::string_view rest;
  if (header.front() == '[') {
    const std::size_t end = header.find(']');
    if (end == std::string_view::npos) return std::nullopt;
    out.host = std::string(header.substr(0, end + 1));
    rest = header.substr(end + 1);
  } else {
    const std::size_t colon = header.find(':');
    out.host = std::string(header.substr(0, colon));
    rest = colon == std::string_view::npos ? std::string_view() : header.substr(colon);
  }
  if (out.host.empty()) return std::nullopt;
  if (!rest.empty()) {
    if (rest.front() != ':') return std::nullopt;
    out.port = ParsePort(rest.substr(1));
    if (!out.port) return std::nullopt;
  }
  return out;
}

bool IsLoopbackAddress(std::string_view remote_addr) {
  if (remote_addr == "::1") return true;
  constexpr std::string_view kMapped = "::ffff:";
  if (remote_addr.size() > kMapped.size() &&
      Lower(remote_addr.substr(0, kMapped.size())) == kMapped)
    remote_addr.remove_prefix(kMapped.size());
  return IsLoopbackIpv4(remote_addr);
}

bool IsPanelHost(std::string_view header, std::string_view listen_host, int port) {
  const auto parsed = ParseHostHeader(header);
  if (!parsed) return false;
  const std::string host = Lower(parsed->host);
  const bool named = host == "127.0.0.1" || host == "[::1]" || host == "localhost" ||
                     (IsLoopbackAddress(listen_host) && host == Lower(listen_host));
  if (!named) return false;
  return parsed->port ? *parsed->port == port : port == 80;
}

bool IsPanelOrigin(std::string_view origin, std::string_view host_header) {
  // Browsers send the origin as they send the Host (scheme, host, port as typed), so an exact
  // comparison is the rule; only the host's case may differ.
  constexpr std::string_view kScheme = "http://";
  if (origin.size() <= kScheme.size() || origin.substr(0, kScheme.size()) != kScheme) return false;
  return Lower(origin.substr(kScheme.size())) == Lower(host_header);
}

}  // namespace hrgbench::app
