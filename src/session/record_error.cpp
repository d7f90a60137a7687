#include "hrgbench/session/session_record_types.hpp"

namespace hrgbench::bench {

std::string RecordError::ToString() const {
  if (file.empty()) return message;
  return file.string() + ": " + message;
}

}  // namespace hrgbench::bench
