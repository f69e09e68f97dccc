#pragma once
// Numbers in messages: `%g` (six significant digits, exponent when needed), so that a residual
// of 4.4e-7 reads as 4.4e-07 and not as the 0.000000 of std::to_string.
#include <string>

namespace dc {

/// `v` formatted with printf's `%g` ("4.4e-07", "0.5", "1e+300", "inf", "nan").
std::string g_text(double v);

}  // namespace dc
