#pragma once
// StoreError: why the results store did not answer. The kind is what a caller decides on (a
// program's exit code, whether an upload is worth retrying); the message is what a person reads
// and always names the database (never a password: URLs carry none).

#include <ostream>
#include <string>

namespace hrgbench::results {

struct StoreError {
  enum class Kind {
    kBadUrl,          // the URL names no database this program can open: fix the command/config
    kUnavailable,     // the database cannot be reached or opened now (server down, refused login,
                      // unreadable file, connection lost): the same request may work later
    kSchemaMismatch,  // written by a newer program, or older and opened read-only: upgrade/migrate
    kBusy,            // another writer held the lock past the busy timeout: retry later
    kFailed,          // the database refused a statement (disk full, constraint, corrupt file)
  };
  Kind kind = Kind::kFailed;
  std::string message;

  const std::string& ToString() const { return message; }
  // Whether the same request can succeed later without anything being changed by a person.
  bool Transient() const { return kind == Kind::kUnavailable || kind == Kind::kBusy; }
};

const char* ToString(StoreError::Kind kind);

inline std::ostream& operator<<(std::ostream& out, const StoreError& error) {
  return out << error.message;
}

}  // namespace hrgbench::results
