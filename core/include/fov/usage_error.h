// A value the user gave (a flag, a setting bound to one) cannot be used: the tools print
// one line and exit 2. Libraries throw it only for such values (e.g. camera overrides).
#pragma once

#include <stdexcept>

namespace fov {

struct usage_error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace fov
