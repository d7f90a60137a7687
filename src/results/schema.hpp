#pragma once
// The schema as migrations: kMigrations[v - 1] takes a database from version v - 1 to v. A new
// version appends a migration; a released migration never changes (stations in the field have
// applied it). Plain SQL that SQLite and PostgreSQL both accept (TEXT, BIGINT, DOUBLE PRECISION).

#include <string_view>
#include <vector>

namespace hrgbench::results::internal {

const std::vector<std::vector<std::string_view>>& Migrations();

}  // namespace hrgbench::results::internal
