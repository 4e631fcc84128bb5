#include "simulate/hertz_law.hpp"

namespace shapepress::simulate {

std::vector<OptionDoc> HertzLaw::options() {
  return {};
}

HertzLaw HertzLaw::read(const ConfigTable&) {
  return {};
}

void HertzLaw::write_toml(std::string&) const {}

void HertzLaw::check(const std::string&) const {}

HertzLaw::Constants HertzLaw::constants(const Material&, const Material&) const {
  return {};
}

std::string HertzLaw::describe(const ElasticPair&, const Constants&) {
  return "hertz";
}

}  // namespace shapepress::simulate
