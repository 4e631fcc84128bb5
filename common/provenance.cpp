#include "common/provenance.hpp"

#include "common/version_info.hpp"

namespace shapepress {

std::string shapepress_version() {
  return SHAPEPRESS_VERSION;
}
std::string shapepress_git_revision() {
  return SHAPEPRESS_GIT_REVISION;
}

}  // namespace shapepress
