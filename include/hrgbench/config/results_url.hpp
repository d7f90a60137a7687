#pragma once
// Where a station's results go: the [results] url of a station file, or hrg-results --db.
//
//   sqlite:///abs/path/results.sqlite   an SQLite file (created with its parent directory when
//   sqlite://relative/results.sqlite    absent); a relative path is taken from the current
//   directory postgresql://host:port/db?opts       a PostgreSQL server, handed to libpq as written
//   (so postgres://...                       sslmode, sslrootcert, service=..., host=/socket/dir
//   work)
//
// Credentials never live in a config file: a URL that carries a password ("user:secret@host" or a
// "password=" option) is refused. libpq finds the password itself (PGPASSFILE or ~/.pgpass, a
// service file, PGPASSWORD in the environment). A user name alone is allowed.
//
// Pure string checks, no I/O; thread-safe; never throws (except std::bad_alloc).

#include <cstddef>
#include <expected>
#include <string>
#include <string_view>

namespace hrgbench::results {

// A URL longer than this is a paste accident, not a database address.
inline constexpr std::size_t kMaxResultsUrlBytes = 1024;

enum class Engine { kSqlite, kPostgres };

struct ResultsUrl {
  Engine engine = Engine::kSqlite;
  std::string sqlite_path;  // kSqlite: the file
  std::string conninfo;     // kPostgres: the URL exactly as given, for PQconnectdb
  std::string text;         // the URL as given, for messages
};

// Parses and checks `url`. The error says what is wrong and quotes the URL (without a password).
std::expected<ResultsUrl, std::string> ParseResultsUrl(std::string_view url);

}  // namespace hrgbench::results
