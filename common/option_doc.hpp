#pragma once
// One documented config key: what `--help-config` prints and docs/config-reference.md lists.
// Plain strings so that any table of keys (common/options.hpp, the contact laws' parameters)
// can hand its rows to the one generator.
#include <string>

namespace shapepress {

struct OptionDoc {
  std::string key, unit, range, default_value, help;
};

}  // namespace shapepress
