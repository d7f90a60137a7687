#pragma once
// The interface the kernel tests use: $HRGBENCH_VCAN, else $HRGBENCH_CAN_IFACE (set by
// scripts/run-in-kernel.sh), else vcan0. With HRGBENCH_REQUIRE_VCAN=1 (set inside the QEMU guest)
// an unavailable interface is a failure, not a skip: nothing may pass by skipping there.

#include <cstdlib>
#include <string>
#include <string_view>

namespace hrgbench::testing {

inline std::string VcanName() {
  for (const char* variable : {"HRGBENCH_VCAN", "HRGBENCH_CAN_IFACE"}) {
    const char* name = std::getenv(variable);
    if (name != nullptr && *name != '\0') return name;
  }
  return "vcan0";
}

inline bool VcanRequired() {
  const char* required = std::getenv("HRGBENCH_REQUIRE_VCAN");
  return required != nullptr && std::string_view(required) == "1";
}

}  // namespace hrgbench::testing
