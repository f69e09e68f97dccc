#pragma once
// How the bench's reports print a number (the table, report.md's sections, the size sweep):
// a printf format, and "n/a" for a figure that does not exist (a median of no steps is NaN).
#include <string>

namespace dc::bench {

/// One number by a printf format (e.g. "%.3f"); "n/a" when it is not finite.
std::string fmt(const char* format, double v);

}  // namespace dc::bench
