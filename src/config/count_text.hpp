#pragma once
// A count or a length computed from a config file's numbers, as text for an error message. The
// value may be anything a file can make it (1e300 s × 1 Hz, an infinity): casting such a double to
// an integer is undefined behaviour (GCC printed "-9223372036854775808 samples"), so only a value
// an integer holds is printed as one; any other is printed as the double it is ("1e+300", "inf").
// Thread-safe; throws only std::bad_alloc.

#include <string>

namespace hrgbench::config_file {

std::string CountText(double value);

}  // namespace hrgbench::config_file
