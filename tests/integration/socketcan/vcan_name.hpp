#pragma once
// The interface the kernel tests use: $HRGBENCH_VCAN, else vcan0.

#include <cstdlib>
#include <string>

namespace hrgbench::testing {

inline std::string VcanName() {
  const char* name = std::getenv("HRGBENCH_VCAN");
  return name != nullptr && *name != '\0' ? name : "vcan0";
}

}  // namespace hrgbench::testing
