#pragma once
// A throwaway PostgreSQL server for a test: Debian's postgresql-15 binaries, initdb and pg_ctl in a
// fresh temporary directory, listening only on a Unix socket in that directory (no TCP port, so
// parallel tests never collide), trust authentication for local connections, fsync off (the tests
// check transactions, not durability across power loss). As root the server runs as the
// `postgres` user (PostgreSQL refuses root). Stopped and removed by the destructor.

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

namespace hrgbench::testing {

class PostgresServer {
 public:
  static constexpr const char* kBin = "/usr/lib/postgresql/15/bin";

  static bool Installed() {
    return std::filesystem::exists(std::string(kBin) + "/initdb") &&
           std::filesystem::exists(std::string(kBin) + "/pg_ctl") &&
           std::filesystem::exists("/usr/bin/psql");
  }

  PostgresServer() = default;
  PostgresServer(const PostgresServer&) = delete;
  PostgresServer& operator=(const PostgresServer&) = delete;
  ~PostgresServer() {
    if (dir_.empty()) return;
    Stop();
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }

  // initdb + start; false (with `error()`) when a step fails.
  bool Start() {
    std::random_device rd;
    dir_ = std::filesystem::temp_directory_path() / ("hrgbench-pg-" + std::to_string(rd()));
    std::filesystem::create_directories(dir_);
    if (::geteuid() == 0 && std::system(("chown postgres " + dir_.string()).c_str()) != 0)
      return Fail("chown postgres failed");
    if (!Run(std::string(kBin) + "/initdb -D " + Data() +
             " -A trust -U postgres -E UTF8 --locale=C --no-sync > " + dir_.string() +
             "/initdb.log 2>&1"))
      return Fail("initdb failed (see " + dir_.string() + "/initdb.log)");
    return Resume();
  }
  // Starts the (stopped) server again on the same data.
  bool Resume() {
    if (!Run(std::string(kBin) + "/pg_ctl -D " + Data() + " -l " + dir_.string() +
             "/server.log -w -t 120 -o \"-k " + dir_.string() +
             " -c listen_addresses='' -p 5432 -c fsync=off -c max_connections=40\" start "
             "> /dev/null 2>&1"))
      return Fail("pg_ctl start failed (see " + dir_.string() + "/server.log)");
    return true;
  }
  // Immediate stop: open connections are cut, open transactions roll back on restart.
  void Stop() {
    Run(std::string(kBin) + "/pg_ctl -D " + Data() +
        " -m immediate -w -t 120 stop > /dev/null 2>&1");
  }
  bool CreateDatabase(const std::string& name) {
    return Psql("postgres", "CREATE DATABASE " + name);
  }
  // Runs one SQL command with psql as the superuser.
  bool Psql(const std::string& db, const std::string& sql) {
    return std::system(("psql -X -q -v ON_ERROR_STOP=1 -h " + dir_.string() +
                        " -p 5432 -U postgres -d " + db + " -c \"" + sql + "\" > /dev/null 2>&1")
                           .c_str()) == 0;
  }
  // Runs one SQL query with psql (unaligned, tuples only, '|' between columns) and returns what
  // it printed; "" when psql fails.
  std::string Query(const std::string& db, const std::string& sql) {
    const std::filesystem::path out = dir_ / "query.out";
    if (std::system(("psql -X -A -t -q -v ON_ERROR_STOP=1 -h " + dir_.string() +
                     " -p 5432 -U postgres -d " + db + " -c \"" + sql + "\" > " + out.string() +
                     " 2>&1")
                        .c_str()) != 0)
      return "";
    std::ifstream in(out);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
  }
  // Runs a file of SQL statements with psql (one transaction).
  bool PsqlFile(const std::string& db, const std::filesystem::path& file) {
    return std::system(("psql -X -q -1 -v ON_ERROR_STOP=1 -h " + dir_.string() +
                        " -p 5432 -U postgres -d " + db + " -f " + file.string() +
                        " > /dev/null 2>&1")
                           .c_str()) == 0;
  }
  std::string Url(const std::string& db, const std::string& user = "postgres") const {
    return "postgresql:///" + db + "?host=" + dir_.string() + "&port=5432&user=" + user;
  }
  const std::string& error() const { return error_; }

 private:
  std::string Data() const { return dir_.string() + "/data"; }
  bool Run(const std::string& command) {
    const std::string full =
        ::geteuid() == 0 ? "runuser -u postgres -- sh -c '" + Escape(command) + "'" : command;
    return std::system(full.c_str()) == 0;
  }
  static std::string Escape(const std::string& text) {  // inside '...'
    std::string out;
    for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out;
  }
  bool Fail(std::string why) {
    error_ = std::move(why);
    return false;
  }
  std::filesystem::path dir_;
  std::string error_;
};

}  // namespace hrgbench::testing
