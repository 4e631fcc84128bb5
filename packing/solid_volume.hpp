#pragma once
// The volume a bed's solid fraction is stated by: pack's press.solid_fraction_volume and
// compact's punch.solid_fraction_volume (docs/models.md, "Which volume a study states its solid
// fractions by").
#include <string>
#include <utility>
#include <vector>

namespace shapepress::packing {

// The bodies' volume in the bed (BodyTemplate::body_volume) or their shapes' (meshes'); one and
// the same for spheres.
enum class SolidVolume { body, shape };

// The config's and run.json's name of each.
inline const std::vector<std::pair<std::string, SolidVolume>>& solid_volume_choices() {
  static const std::vector<std::pair<std::string, SolidVolume>> choices = {
      {"body", SolidVolume::body}, {"shape", SolidVolume::shape}};
  return choices;
}

inline const char* solid_volume_name(SolidVolume volume) {
  return volume == SolidVolume::shape ? "shape" : "body";
}

}  // namespace shapepress::packing
