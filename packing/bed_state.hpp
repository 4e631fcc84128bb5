#pragma once
// A packed bed of bodies (body_packing.hpp) as the engine's state: plain spheres, the bonded
// sub-spheres of BMS bodies with their bonds, and CMS bodies as rigid clumps. Sub-sphere i of the
// engine is particle i of the packing; every sub-sphere of a body carries the body's first
// particle index as its body id (state.hpp), as add_clump does.
#include <optional>

#include "packing/body_packing.hpp"
#include "simulate/bonds.hpp"
#include "simulate/clumps.hpp"

namespace shapepress::packing {

struct BedRequest {
  double density = 0.0;  // kg/m³ of the particles' material
  int material = 0;
  // The bonds of BMS bodies; required when the packing has any.
  std::optional<BondParameters> bond;
  // Every BMS body moves as a rigid clump of its template's mass properties instead (pack: a
  // bed is placed and settled without resolving the bodies' deformation).
  bool bms_as_clumps = false;
};

struct Bed {
  SphereState state;
  BondSet bonds;
  ClumpSet clumps;
  // Σ of the bodies' volumes in the bed (BodyTemplate::body_volume), of their shape (mesh)
  // volumes and of their sub-sphere volumes (CMS: union volumes), m³: the solid fraction of a bed
  // of bodies is by body volume; a BMS body's sub-spheres fill only part of it.
  double body_volume = 0.0;
  double shape_volume = 0.0;
  double sphere_volume = 0.0;
};

// A body weighs ρ × its body volume, with the inertia of that volume: a BMS body's sub-spheres
// carry it at ρ × body_volume / Σ sub-sphere volumes each (the body's inertia is then its
// sub-spheres' distribution scaled to that mass), a rigid clump its template's body_inertia.
// InputError when the packing has BMS bodies and no bond parameters are given.
Bed bed_from_packing(const BodyPacking& packing, const BedRequest& request);

}  // namespace shapepress::packing
