#pragma once
// Test-only kill points: the places where a record is being written, named, so a test can kill the
// process (SIGKILL, as a power cut or kill -9 would) at exactly one of them instead of guessing
// with wall-clock sleeps. Off unless HRGBENCH_TEST_KILL_AT is set:
//
//   HRGBENCH_TEST_KILL_AT=record.json      the first time "record.json" is passed
//   HRGBENCH_TEST_KILL_AT=record.json#3    the third time
//   HRGBENCH_TEST_KILL_AT=#7               the seventh kill point passed, whatever its name
//
// HRGBENCH_TEST_KILL_LOG=FILE appends the name of every kill point passed to FILE (to list them).
// The names (docs/bench/resume.md lists them): fixture.config, fixture.record, record.dirs,
// record.can_log, record.json, atomic.written (a temporary written, not yet renamed), run.begin,
// run.end, report (before the report is written, or its job started), report.job (hrg-report
// --job: its record says running, nothing written yet). Thread-safe (a counter and a string read
// once).

#include <string_view>

namespace hrgbench::session {

// Raises SIGKILL when this is the kill point HRGBENCH_TEST_KILL_AT names; returns otherwise.
void KillPoint(std::string_view name);

}  // namespace hrgbench::session
