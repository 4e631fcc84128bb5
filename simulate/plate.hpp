#pragma once
// The single-particle rig: one sphere between two plates, the top plate approaching at a
// prescribed speed (DESIGN.md `shapepress plate`; the BMS and multi-contact issues extend it to
// one agglomerate). Quasi-static when the speed is small against the sphere's wave speed.
#include <vector>

#include "simulate/materials.hpp"

namespace shapepress::simulate {

struct PlateSetup {
  double radius = 0.0;  // m
  int sphere_material = 0;
  int plate_material = 0;
  double speed = 0.0;             // m/s, top plate approach speed
  double max_deformation = 0.01;  // total approach / diameter at the end
  int records = 50;               // rows, evenly spaced in approach
  double time_step = 0.0;         // s
};

struct PlateRow {
  double time = 0.0;          // s
  double deformation = 0.0;   // approach / diameter
  double approach = 0.0;      // Δ, m: decrease of the plate gap from 2R
  double top_force = 0.0;     // N, compressive
  double bottom_force = 0.0;  // N
  double hertz_force = 0.0;   // N, (√2/3) E* √R Δ^{3/2}, E* of the sphere–plate pair
};

// Hertz between a sphere and two identical plates: each contact carries Δ/2 (models.md).
double hertz_plate_force(double effective_modulus, double radius, double approach);

std::vector<PlateRow> run_plate(const MaterialTable& materials, const PlateSetup& setup);

}  // namespace shapepress::simulate
