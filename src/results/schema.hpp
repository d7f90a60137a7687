#pragma once
// The schema as migrations: Migrations()[v - 1] takes a database from version v - 1 to v. A new
// version appends a migration; a released migration never changes (stations in the field have
// applied it). Version 1 is plain SQL that SQLite and PostgreSQL both accept (TEXT, BIGINT, DOUBLE
// PRECISION); later versions have steps for one engine only where the engines differ (PostgreSQL's
// timestamptz, which SQLite does not have) and steps run by the program (SQLite's times rewritten
// into the canonical text, the new columns filled from the session folders).

#include <string_view>
#include <vector>

namespace hrgbench::results::internal {

struct MigrationStep {
  enum class Kind {
    kBoth,             // `sql` on either engine
    kSqliteOnly,       // `sql` on SQLite only
    kPostgresOnly,     // `sql` on PostgreSQL only
    kSqliteTimes,      // SQLite: every stored time rewritten as CanonicalUtc (utc_text.hpp)
    kFillFromFolders,  // the version-2 session columns read again from each session's folder
  };
  Kind kind = Kind::kBoth;
  std::string_view sql;
};

const std::vector<std::vector<MigrationStep>>& Migrations();

}  // namespace hrgbench::results::internal
