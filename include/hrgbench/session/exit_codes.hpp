#pragma once
// The exit codes of every hrgbench program (hrg-bench, hrg-estimate, hrg-compare, hrg-design,
// hrg-report, hrg-results, hrg-sim): one table, each program's --help prints it (kExitCodesHelp)
// and says what its 1 means. session.json "outcome.exit_code" and fixture.json's units hold the
// code for the outcome's kind (session_outcome.hpp: ExitCode); a reader goes by "kind".
//
//   0  kExitOk        PASS: every declared limit judged and met; for the other tools: done
//   1  kExitFail      FAIL: the unit's fault (a parameter outside its declared limits, or not
//                     accepted within its guard band: the record's outcome.verdict.retest says
//                     when the unit is to be measured again); for the other tools: ran, but the
//                     result is not usable (an estimate that did not converge, a replay that
//                     differs, a session that could not be imported)
//   2  kExitError     ERROR: the bench's fault, saying nothing about the unit (timeout, bus-off,
//                     Modbus failure, too many drops, disk full, a limit the bench could not
//                     judge), or an unexpected failure of the program (only main catches
//                     everything); a port that cannot be bound
//   3  kExitAborted   ABORTED: the operator stopped the session (Ctrl-C, SIGTERM, the panel)
//   4  kExitBadInput  bad input: the command line, a config, a session folder or a file the
//                     program was given is refused before anything started or was written. Never
//                     in a record: there is no session to write it into
//
// Why this table: it keeps hrg-bench's codes (the production line's contract, and every record
// written so far) and moves the tools' bad input (2 before) to hrg-bench's 4, as pytest's table
// does (0 ok, 1 failed, 2 interrupted, 3 internal error, 4 usage).

#include <string_view>

namespace hrgbench {

inline constexpr int kExitOk = 0;
inline constexpr int kExitFail = 1;
inline constexpr int kExitError = 2;
inline constexpr int kExitAborted = 3;
inline constexpr int kExitBadInput = 4;

// The table as every program's --help ends.
inline constexpr std::string_view kExitCodesHelp =
    "Exit codes (every hrgbench program): 0 PASS / done; 1 FAIL / the result is not usable; "
    "2 ERROR (the bench's or the program's own failure: hardware, I/O, an unexpected error); "
    "3 ABORTED (the operator stopped it); 4 bad input (command line, config or session refused; "
    "nothing started or written).";

}  // namespace hrgbench
