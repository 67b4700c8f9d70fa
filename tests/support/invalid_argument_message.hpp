#pragma once
// The message of the std::invalid_argument a callable throws, "" when it throws none: how
// the tests check that a bad argument is refused by name.

#include <stdexcept>
#include <string>

namespace demcal::testing {

template <class F>
inline std::string invalid_argument_message(F&& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

}  // namespace demcal::testing
