#include "simulate/plate.hpp"

#include <cmath>

#include "common/error.hpp"
#include "simulate/engine.hpp"

namespace shapepress::simulate {

double hertz_plate_force(double effective_modulus, double radius, double approach) {
  return std::sqrt(2.0) / 3.0 * effective_modulus * std::sqrt(radius) * approach *
         std::sqrt(approach);
}

std::vector<PlateRow> run_plate(const MaterialTable& materials, const PlateSetup& setup) {
  if (!(setup.radius > 0.0)) throw InputError("plate: sphere radius must be > 0");
  if (!(setup.speed > 0.0)) throw InputError("plate: speed must be > 0");
  if (!(setup.max_deformation > 0.0 && setup.max_deformation < 0.5))
    throw InputError("plate: max_deformation must be in (0, 0.5)");
  if (setup.records < 1) throw InputError("plate: records must be >= 1");
  const double r = setup.radius;
  SphereState state;
  state.add_sphere(0.0, 0.0, r, r, materials.material(setup.sphere_material).density,
                   setup.sphere_material);
  std::vector<PlaneWall> walls = {PlaneWall{0.0, 1, 0.0, setup.plate_material},
                                  PlaneWall{2.0 * r, -1, -setup.speed, setup.plate_material}};
  EngineSettings settings{setup.time_step, {0.0, 0.0, 0.0}, 0.1 * r};
  settings.check_every = 1000;
  Engine engine(std::move(state), Box{}, materials, std::move(walls), settings);
  const double e_star =
      materials.pair(setup.sphere_material, setup.plate_material).effective_modulus;
  const double final_approach = setup.max_deformation * 2.0 * r;
  std::vector<PlateRow> rows;
  int next = 1;
  while (next <= setup.records) {
    engine.step();
    const double approach = 2.0 * r - (engine.walls()[1].position - engine.walls()[0].position);
    if (approach >= final_approach * next / setup.records) {
      PlateRow row;
      row.time = engine.time();
      row.approach = approach;
      row.deformation = approach / (2.0 * r);
      row.top_force = engine.wall_load(1);
      row.bottom_force = engine.wall_load(0);
      row.hertz_force = hertz_plate_force(e_star, r, approach);
      rows.push_back(row);
      ++next;
    }
  }
  return rows;
}

}  // namespace shapepress::simulate
