#include "hrgbench/config/results_url.hpp"

#include <algorithm>
#include <cctype>

namespace hrgbench::results {
namespace {

bool StartsWith(std::string_view text, std::string_view prefix) {
  return text.substr(0, prefix.size()) == prefix;
}

std::string Lower(std::string_view text) {
  std::string out(text);
  std::ranges::transform(out, out.begin(),
                         [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

}  // namespace

std::expected<ResultsUrl, std::string> ParseResultsUrl(std::string_view url) {
  if (url.empty()) return std::unexpected("results url is empty");
  if (url.size() > kMaxResultsUrlBytes) {
    return std::unexpected("results url is " + std::to_string(url.size()) + " bytes; at most " +
                           std::to_string(kMaxResultsUrlBytes));
  }
  for (unsigned char c : url) {
    if (c < 0x20 || c == 0x7f) return std::unexpected("results url contains a control character");
  }
  ResultsUrl parsed;
  parsed.text = std::string(url);
  if (StartsWith(url, "sqlite://")) {
    parsed.engine = Engine::kSqlite;
    parsed.sqlite_path = std::string(url.substr(9));
    if (parsed.sqlite_path.empty() || parsed.sqlite_path.back() == '/') {
      return std::unexpected(
          "results url '" + parsed.text +
          "': no file name after sqlite:// (e.g. sqlite:///var/hrg/results.sqlite)");
    }
    if (parsed.sqlite_path.find('?') != std::string::npos) {
      return std::unexpected("results url '" + parsed.text +
                             "': sqlite:// takes a plain path, no '?' options");
    }
    return parsed;
  }
  if (StartsWith(url, "postgresql://") || StartsWith(url, "postgres://")) {
    parsed.engine = Engine::kPostgres;
    parsed.conninfo = parsed.text;
    const std::string_view rest = url.substr(url.find("://") + 3);
    const std::string_view authority = rest.substr(0, rest.find_first_of("/?"));
    const std::size_t at = authority.rfind('@');
    if (at != std::string_view::npos &&
        authority.substr(0, at).find(':') != std::string_view::npos) {
      return std::unexpected(
          "results url '" + std::string(url.substr(0, url.find("://") + 3)) +
          "...': carries a "
          "password; credentials never go in a config file: use ~/.pgpass or PGPASSFILE, a "
          "service file (PGSERVICEFILE) or PGPASSWORD");
    }
    const std::string lower = Lower(rest);
    const std::size_t query = lower.find('?');
    if (query != std::string::npos) {
      const std::string options = "&" + lower.substr(query + 1);
      if (options.find("&password=") != std::string::npos) {
        return std::unexpected(
            "results url: carries a password= option; credentials never go in a config file: "
            "use ~/.pgpass or PGPASSFILE, a service file (PGSERVICEFILE) or PGPASSWORD");
      }
    }
    return parsed;
  }
  return std::unexpected("results url '" + parsed.text +
                         "': unknown scheme; expected sqlite:///path or postgresql://host/db");
}

}  // namespace hrgbench::results
