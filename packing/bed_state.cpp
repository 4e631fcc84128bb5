#include "packing/bed_state.hpp"

#include <fmt/format.h>

#include <cmath>
#include <numbers>

#include "common/error.hpp"

namespace shapepress::packing {

Bed bed_from_packing(const BodyPacking& packing, const BedRequest& request) {
  if (!(request.density > 0.0)) throw InputError("packing: the particles' density must be > 0");
  Bed bed;
  std::vector<Vector3> body_centres;
  for (std::size_t b = 0; b < packing.size(); ++b) {
    const PackedBody& body = packing.bodies[b];
    const BodyTemplate& shape = packing.templates[static_cast<std::size_t>(body.template_index)];
    bed.body_volume += body.body_volume;
    bed.shape_volume += body.shape_volume;
    bed.sphere_volume += body.sphere_volume;
    const auto first = static_cast<std::size_t>(packing.first_particle[b]);
    const auto last = static_cast<std::size_t>(packing.first_particle[b + 1]);
    const bool rigid =
        shape.kind == BodyKind::cms || (shape.kind == BodyKind::bms && request.bms_as_clumps);
    if (rigid) {
      const double s = body.scale, s3 = s * s * s, s5 = s3 * s * s;
      body_centres.clear();
      for (const Vector3& c : shape.centres)
        body_centres.push_back({s * c[0], s * c[1], s * c[2]});
      const std::vector<double> radii(packing.particles.radius.begin() + static_cast<long>(first),
                                      packing.particles.radius.begin() + static_cast<long>(last));
      const Vector3 inertia = {request.density * s5 * shape.body_inertia[0],
                               request.density * s5 * shape.body_inertia[1],
                               request.density * s5 * shape.body_inertia[2]};
      add_rigid_clump(bed.state, bed.clumps, body_centres, radii, body.centre, body.orientation,
                      request.density * s3 * shape.body_volume, s3 * shape.body_volume, inertia,
                      request.material, fmt::format("{} (body {})", shape.name, b));
      continue;
    }
    // A plain sphere's body volume is its own (the factor is 1 to the bit).
    const double density = request.density * (shape.body_volume / shape.sphere_volume);
    // The particle's size is its shape's: the mesh volume, whatever N fills it.
    const double body_radius = std::cbrt(3.0 * body.shape_volume / (4.0 * std::numbers::pi));
    for (std::size_t i = first; i < last; ++i) {
      bed.state.add_sphere(packing.particles.x[i], packing.particles.y[i], packing.particles.z[i],
                           packing.particles.radius[i], density, request.material);
      bed.state.body.back() = static_cast<std::int32_t>(first);
      if (last - first > 1) bed.state.body_radius.back() = body_radius;
    }
  }
  if (!packing.bonds.empty() && !request.bms_as_clumps) {
    if (!request.bond)
      throw InputError(fmt::format(
          "the packing holds {} bonds of BMS bodies: give their parameters in a [bond] table",
          packing.bonds.size()));
    bed.bonds = bonds_from_pairs(bed.state, packing.bonds, packing.bond_rest_length, *request.bond);
  }
  return bed;
}

}  // namespace shapepress::packing
