#pragma once
// A bonded multi-sphere (BMS) particle for the plate rig: the sphere filled with touching
// sub-spheres by the geometry stage's filler (geometry/sphere_fill.hpp, the same mechanism
// `shapepress fill` uses), bonded by Eq. 10 (create_bonds).
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include "scenarios/namespaces.hpp"

#include "scenarios/config_io.hpp"
#include "scenarios/plate.hpp"

namespace shapepress::scenarios {

struct BmsParticleInfo {
  double sub_sphere_radius = 0.0;  // m
  std::size_t spheres = 0;
  std::size_t bonds = 0;
};

// The sub-spheres of fills already made, by what a fill depends on (count, lattice, placement,
// seed, the filler's m_b, the sphere's radius, the sub-spheres' material and density), not on
// the bonds' parameters: calibrate presses the same fills at every evaluation, and a carved fill
// costs about as much as its run. Safe to share between the threads that run fills side by side.
class BmsFillCache {
 public:
  // The cached sub-spheres for `key`, or those `fill` makes (once per key).
  template <class Fill>
  SphereState get(const std::string& key, Fill&& fill) {
    std::shared_ptr<std::once_flag> once;
    std::shared_ptr<SphereState> slot;
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      Entry& e = entries_[key];
      if (!e.once)
        e.once = std::make_shared<std::once_flag>(), e.state = std::make_shared<SphereState>();
      once = e.once, slot = e.state;
    }
    std::call_once(*once, [&] { *slot = fill(); });
    return *slot;
  }
  std::size_t size() const {
    const std::lock_guard<std::mutex> lock(mutex_);
    return entries_.size();
  }

 private:
  struct Entry {
    std::shared_ptr<std::once_flag> once;
    std::shared_ptr<SphereState> state;
  };
  mutable std::mutex mutex_;
  std::map<std::string, Entry> entries_;
};

// Sub-spheres of `config.material` (default: the sphere's) filling a sphere of `radius` centred
// at (0, 0, radius), all of body 0 named `name`. InputError for a bad count, m_b, stiffness, or
// a sub-sphere left unbonded. With a `cache`, a fill made before for the same inputs is reused.
PlateParticle bms_sphere(const MaterialTable& materials, double radius, const BmsConfig& config,
                         const std::string& name, BmsParticleInfo* info = nullptr,
                         BmsFillCache* cache = nullptr, int stack = 1);

// `config.templates`' BMS template (bms.template, or the file's only one) turned so that its
// axis (bms.axis, bms.direction) is z, resting on z = 0, bonded by Eq. 10 with the config's m_b
// and bond: InputError naming the file and the template when it has no such template.
PlateParticle bms_template(const MaterialTable& materials, const BmsConfig& config,
                           const std::string& name, BmsParticleInfo* info = nullptr, int stack = 1);
// Half the height of that template along its axis (the plate rig's R: deformation = Δ/(2R)).
double bms_template_half_height(const BmsConfig& config);

// bms_template when the config names templates, else bms_sphere; `stack` copies one on another
// (stacked), each bonded within itself. info counts one copy.
PlateParticle bms_particle(const MaterialTable& materials, double radius, const BmsConfig& config,
                           const std::string& name, BmsParticleInfo* info = nullptr,
                           BmsFillCache* cache = nullptr, int stack = 1);

}  // namespace shapepress::scenarios
