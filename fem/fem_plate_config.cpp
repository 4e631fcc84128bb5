#include "fem/fem_plate_config.hpp"

#include <cmath>

#include <fmt/format.h>

#include "common/error.hpp"
#include "common/units.hpp"
#include "fem/cli.hpp"

namespace shapepress::fem {
namespace {

// The solid's von Mises plasticity, the same keys in [sphere] and [particle].
void plasticity_rows(OptionTable<FemPlateConfig>& table) {
  table
      .quantity("yield_stress", &FemPlateConfig::yield_stress, dim::pressure, Range::positive(),
                "σy: the solid yields by von Mises at this uniaxial stress and hardens "
                "isotropically (CalculiX *PLASTIC; needs material_model = \"linear-elastic\")")
      .default_text("none (elastic)")
      .quantity("hardening_modulus", &FemPlateConfig::hardening_modulus, dim::pressure,
                Range::non_negative(),
                "H = dσ/dεp, the slope of the yield stress against the equivalent plastic strain "
                "(0: perfectly plastic)")
      .when([](const FemPlateConfig& c) { return c.plastic(); }, "without yield_stress");
}

const OptionTable<FemPlateConfig>& sphere_table() {
  static const OptionTable<FemPlateConfig> t = [] {
    OptionTable<FemPlateConfig> s("sphere", "the elastic sphere and its material law");
    s.quantity("radius", &FemPlateConfig::radius, dim::length, Range::positive(),
               "R (a spheroid's equatorial semi-axis)")
        .quantity("polar_radius", &FemPlateConfig::polar_radius, dim::length, Range::positive(),
                  "a spheroid's semi-axis along the plates' axis (its axis of revolution): the "
                  "particle is then a spheroid pressed along that axis, deformation = Δ/(2c)")
        .default_text("radius (a sphere)")
        .write_when([](const FemPlateConfig& c) { return c.polar_radius > 0.0; })
        .quantity("youngs_modulus", &FemPlateConfig::youngs_modulus, dim::pressure,
                  Range::positive(), "E, small-strain")
        .required()
        .number("poisson_ratio", &FemPlateConfig::poisson_ratio, Range{0.0, 0.5, true, false},
                "ν, small-strain (neo-Hookean: sets the bulk modulus K = E/(3(1 − 2ν)))")
        .required()
        .choice("material_model", &FemPlateConfig::material,
                std::vector<std::pair<std::string, MaterialModel>>{
                    {"neo-hookean", MaterialModel::neo_hookean},
                    {"linear-elastic", MaterialModel::linear_elastic}},
                "compressible neo-Hookean (the paper's MPFEM material) or linear elastic (with "
                "nonlinear geometry: St Venant–Kirchhoff)");
    plasticity_rows(s);
    return s;
  }();
  return t;
}

const OptionTable<FemPlateConfig>& particle_table() {
  static const OptionTable<FemPlateConfig> t = [] {
    OptionTable<FemPlateConfig> s("particle",
                                  "any closed triangle mesh as a 3D model of quadratic "
                                  "tetrahedra (C3D10, meshed by Gmsh), instead of [sphere]");
    s.string("mesh", &FemPlateConfig::mesh,
             "the particle's surface: STL (binary or ASCII), OFF or PLY, closed, 2-manifold and "
             "free of self-intersections (generate's particles)")
        .required()
        .quantity("mesh_unit", &FemPlateConfig::mesh_unit, dim::length, Range::positive(),
                  "the length of one coordinate unit of the mesh file")
        .default_text("1 m")
        .choice("axis", &FemPlateConfig::axis,
                std::vector<std::pair<std::string, PressAxis>>{{"short", PressAxis::short_axis},
                                                               {"middle", PressAxis::middle_axis},
                                                               {"long", PressAxis::long_axis},
                                                               {"direction", PressAxis::direction}},
                "the plates' axis: a principal axis of the particle's inertia (short: the "
                "largest moment, long: the smallest) or `direction`")
        .numbers("direction", &FemPlateConfig::direction, dim::dimensionless, Range::any(),
                 "the plates' axis in the mesh's frame (any length)")
        .when([](const FemPlateConfig& c) { return c.axis == PressAxis::direction; },
              "unless particle.axis = \"direction\"")
        .quantity("youngs_modulus", &FemPlateConfig::youngs_modulus, dim::pressure,
                  Range::positive(), "E, small-strain")
        .required()
        .number("poisson_ratio", &FemPlateConfig::poisson_ratio, Range{0.0, 0.5, true, false},
                "ν, small-strain (neo-Hookean: sets the bulk modulus K = E/(3(1 − 2ν)))")
        .required()
        .choice("material_model", &FemPlateConfig::material,
                std::vector<std::pair<std::string, MaterialModel>>{
                    {"neo-hookean", MaterialModel::neo_hookean},
                    {"linear-elastic", MaterialModel::linear_elastic}},
                "compressible neo-Hookean or linear elastic (with nonlinear geometry)");
    plasticity_rows(s);
    return s;
  }();
  return t;
}

const OptionTable<FemPlateConfig>& plate_table() {
  static const OptionTable<FemPlateConfig> t = [] {
    OptionTable<FemPlateConfig> p("plate", "the two rigid flat plates");
    p.number("max_deformation", &FemPlateConfig::max_deformation, Range::open_closed(0.0, 0.8),
             "total plate approach over the diameter, Δ/(2R), at the end of the step")
        .number("friction", &FemPlateConfig::friction, Range::non_negative(),
                "Coulomb friction coefficient between sphere and plates (0: frictionless)")
        .boolean("unload", &FemPlateConfig::unload,
                 "a second step takes the plates back to where they first touched: the unloading "
                 "curve in force.csv (step 2) and the approach at which the force falls to zero "
                 "(run.json residual_deformation)");
    return p;
  }();
  return t;
}

const OptionTable<FemPlateConfig>& fem_table() {
  static const OptionTable<FemPlateConfig> t = [] {
    OptionTable<FemPlateConfig> f("fem", "the mesh and the CalculiX step");
    f.integer("arc_elements", &FemPlateConfig::arc_elements, Range{2, 400},
              "elements along each 45° of the sphere's outline (the run's resolution; "
              "--arc-elements overrides); [particle]: the tetrahedra at the plates are "
              "(π/4) R_c / this, R_c the smaller principal radius of curvature there (3 to 8)")
        .integer("coarse_arc_elements", &FemPlateConfig::coarse_arc_elements, Range{0, 400},
                 "the mesh convergence check's second resolution (0: no check)")
        .integer("increments", &FemPlateConfig::increments, Range{1, 100000},
                 "the step in this many equal increments at most (force.csv rows); CalculiX "
                 "cuts one back when it does not converge")
        .number("minimum_increment", &FemPlateConfig::minimum_increment,
                Range::open_closed(0.0, 1.0),
                "smallest cut-back increment, as a fraction of the step: below it the run stops "
                "(exit 1) and keeps the converged part")
        .boolean("nonlinear_geometry", &FemPlateConfig::nonlinear_geometry,
                 "finite strains and rotations (NLGEOM); false: small-strain theory, as Hertz")
        .number("penalty_factor", &FemPlateConfig::penalty_factor, Range::positive(),
                "contact stiffness (pressure per overclosure) = this × E / the element size "
                "at the pole");
    return f;
  }();
  return t;
}

}  // namespace

const char* material_model_name(MaterialModel model) {
  return model == MaterialModel::neo_hookean ? "neo-hookean" : "linear-elastic";
}

void FemPlateConfig::check() const {
  const char* section = solid() ? "particle" : "sphere";
  if (plastic() && material != MaterialModel::linear_elastic)
    throw InputError(fmt::format(
        "{0}.yield_stress needs {0}.material_model = \"linear-elastic\" (CalculiX's *PLASTIC "
        "extends *ELASTIC, not the neo-Hookean *HYPERELASTIC)",
        section));
  if (plastic() && !(*yield_stress > 0.0 && std::isfinite(*yield_stress)))
    throw InputError(
        fmt::format("{}.yield_stress {} must be positive and finite", section, *yield_stress));
  if (!(hardening_modulus >= 0.0 && std::isfinite(hardening_modulus)))
    throw InputError(fmt::format("{}.hardening_modulus {} must be non-negative and finite", section,
                                 hardening_modulus));
  if (coarse_arc_elements != 0 && coarse_arc_elements >= arc_elements)
    throw InputError(
        fmt::format("fem.coarse_arc_elements {} must be below fem.arc_elements {} (or 0: no check)",
                    coarse_arc_elements, arc_elements));
  if (coarse_arc_elements == 1)
    throw InputError("fem.coarse_arc_elements 1: at least 2 (or 0: no check)");
  if (minimum_increment > 1.0 / increments)
    throw InputError(fmt::format("fem.minimum_increment {} is above the increment 1/{}",
                                 minimum_increment, increments));
}

FemPlateConfig read_fem_plate_config(const ConfigTable& root) {
  FemPlateConfig config;
  if (root.has("particle") && root.has("sphere"))
    throw InputError(fmt::format("{}: [sphere] and [particle] both given: one particle is pressed",
                                 root.source_name()));
  if (root.has("particle"))
    particle_table().read(root.table("particle"), config);
  else
    sphere_table().read(root.table("sphere"), config);
  if (root.has("plate")) plate_table().read(root.table("plate"), config);
  if (root.has("fem")) fem_table().read(root.table("fem"), config);
  try {
    config.check();
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", root.source_name(), e.what()));
  }
  return config;
}

std::string fem_plate_config_toml(const FemPlateConfig& config) {
  return (config.solid() ? particle_table().write(config) : sphere_table().write(config)) + "\n" +
         plate_table().write(config) + "\n" + fem_table().write(config);
}

StageOptions fem_plate_options() {
  return StageOptions{
      "fem-plate",
      "one elastic (or elastic–plastic) sphere between rigid plates by the finite element "
      "method (CalculiX: a sphere or spheroid axisymmetric, any closed mesh in 3D), loaded and, "
      "if asked, unloaded",
      {sphere_table().docs(), particle_table().docs(), plate_table().docs(), fem_table().docs()}};
}

}  // namespace shapepress::fem
