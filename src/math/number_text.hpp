// format_number: a double as messages print it ("%g": 6 significant digits, exponent when small or
// large), so that a time step of 1e-7 reads "1e-07" rather than "0.000000". One definition for the
// scene readers' and the solver's messages. Host only.
#pragma once
#include <cstdio>
#include <string>

namespace dipc {

inline std::string format_number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

}  // namespace dipc
