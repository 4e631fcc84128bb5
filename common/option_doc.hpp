#pragma once
// One row of a config reference: what a key means, in which unit, over which range, with which
// default. Readers that own their keys list them this way so the reference is generated from the
// code that reads them, not kept beside it.
#include <string>

namespace shapepress {

struct OptionDoc {
  std::string key;
  std::string unit;           // "" for dimensionless
  std::string range;          // as Range::describe() words it: "in (0, 1]", ">= 0"
  std::string default_value;  // "" when the key is required or its absence means something
  std::string help;
};

}  // namespace shapepress
