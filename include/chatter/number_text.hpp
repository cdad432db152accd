// The one text of a number in messages, reports and notes (not tables: their
// cells are io's table_number, 10 significant digits and inf): x with
// `significant` significant digits, as printf's %.*g in the C locale
// ("0.35", "2.4e+09", "nan", "inf"). Every library file formats through it
// rather than a local helper (issue 43: 26 local copies before).
#pragma once

#include <string>

namespace chatter {

/// x with `significant` (>= 1) significant digits, %.*g. Cost: one snprintf.
std::string number_text(double x, int significant = 6);

}  // namespace chatter
