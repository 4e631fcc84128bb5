#pragma once
// What `fem-plate` presses and how: the sphere and its material law, the plates, the mesh and the
// increments of the CalculiX run (docs/stages.md "fem-plate", docs/models.md "The finite-element
// reference").
#include <array>
#include <optional>
#include <string>

#include "common/config.hpp"
#include "common/options.hpp"
#include "geometry/press_frame.hpp"

namespace shapepress::fem {

using geometry::contact_curvature_radii;
using geometry::press_axis_name;
using geometry::PressAxis;
using geometry::pressed_particle;
using geometry::PressedParticle;

enum class MaterialModel {
  neo_hookean,     // compressible neo-Hookean, C10 = μ/2, D1 = 2/K (CalculiX *HYPERELASTIC)
  linear_elastic,  // Hooke (with nonlinear geometry: St Venant–Kirchhoff)
};
const char* material_model_name(MaterialModel model);  // "neo-hookean", "linear-elastic"

struct FemPlateConfig {
  // [particle]: any closed triangle mesh as a 3D tetrahedral model (empty: the [sphere] or
  // spheroid, axisymmetric).
  std::string mesh;
  double mesh_unit = 1.0;  // metres per coordinate unit of the mesh file
  PressAxis axis = PressAxis::short_axis;
  std::array<double, 3> direction = {0.0, 0.0, 1.0};  // in the mesh's frame (axis = direction)
  std::string gmsh = "gmsh";                          // the mesher (not a config key: --gmsh)
  double radius = 0.01;                               // R [m] (a spheroid's equatorial semi-axis a)
  double polar_radius = 0.0;    // c [m]: a spheroid's semi-axis along the plates' axis; 0: R
  double youngs_modulus = 0.0;  // E [Pa] (small-strain)
  double poisson_ratio = 0.0;   // ν (small-strain)
  MaterialModel material = MaterialModel::neo_hookean;
  // Von Mises plasticity with linear isotropic hardening (CalculiX *PLASTIC): the uniaxial yield
  // stress σy [Pa] and the hardening modulus H = dσ/dεp [Pa] (0: perfectly plastic). Empty:
  // elastic. Needs the linear-elastic material (ccx joins *PLASTIC to *ELASTIC only).
  std::optional<double> yield_stress;
  double hardening_modulus = 0.0;
  double max_deformation = 0.4;  // Δ/(2c) at the end of the loading step
  // A second step takes the plates back to where they first touched: the unloading curve, and
  // the approach at which the force falls to zero (the plastic deformation left).
  bool unload = false;
  double friction = 0.0;            // Coulomb coefficient between sphere and plates (0: none)
  int arc_elements = 24;            // mesh resolution: elements per 45° of the outline
  int coarse_arc_elements = 16;     // the convergence check's second mesh (0: none)
  int increments = 40;              // the step in at most this many equal increments
  double minimum_increment = 1e-4;  // smallest cut-back increment, fraction of the step
  bool nonlinear_geometry = true;   // NLGEOM (off: small-strain theory, Hertz's assumption)
  double penalty_factor = 100.0;    // contact stiffness = factor × E / (pole element size)

  bool solid() const { return !mesh.empty(); }
  bool plastic() const { return yield_stress.has_value(); }
  void check() const;  // InputError naming the key
  // c: polar_radius, or R for the sphere.
  double pressed_radius() const { return polar_radius > 0.0 ? polar_radius : radius; }
  // The radius of curvature at the pole, where the plates touch: R²/c (c = R: the sphere's R),
  // the R of Hertz's solution for the pole's two equal principal curvatures.
  double pole_curvature_radius() const { return radius * radius / pressed_radius(); }
};

// Reads [sphere] or [particle], [plate] and [fem] of a fem-plate config (the caller checks unknown
// keys).
FemPlateConfig read_fem_plate_config(const ConfigTable& root);
// The effective config as TOML that reads back to the same values.
std::string fem_plate_config_toml(const FemPlateConfig& config);

}  // namespace shapepress::fem
