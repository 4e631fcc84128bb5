// The cost of one contact-step of the whole contact law (normal law, damping, Mindlin, CDT) for
// each registered normal law on the same contacts: 1000 pairs of 0.5 mm Avicel-like spheres
// (E = 8 GPa, ν = 0.3; MDR with Y = 160 MPa) at side strains 0.01–0.16, past yield, half loading
// (δ = δm) and half unloading (δ just below δm). Count instructions with callgrind at two pass
// counts, so that set-up cancels (docs/models.md, "Contact law: MDR", Cost):
//   valgrind --tool=callgrind build/tests/bench/contact_law_cost mdr 100
//   valgrind --tool=callgrind build/tests/bench/contact_law_cost mdr 200
// (I refs of the second minus the first) / 1e5 = instructions per contact-step; likewise hertz.
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "simulate/contact_law.hpp"

using namespace shapepress::simulate;

namespace {

template <class Law>
double run(const PairConstants& p, const std::vector<ContactKinematics>& contacts,
           std::vector<ContactHistory>& histories, int passes) {
  double sum = 0.0;
  for (int pass = 0; pass < passes; ++pass)
    for (std::size_t k = 0; k < contacts.size(); ++k)
      sum += contact_force<Law>(contacts[k], p, histories[k], 1e-8).normal_force;
  return sum;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: contact_law_cost hertz|multicontact|mdr PASSES\n");
    return 2;
  }
  const std::string law = argv[1];
  const int passes = std::atoi(argv[2]);
  const Material avicel{"avicel", 8e9, 0.3, 1560.0};
  const auto table = [&](NormalLawChoice choice) {
    return MaterialTable({avicel}, {{"avicel", "avicel", 0.5, 0.5, 0.0, choice}});
  };
  const MaterialTable hertz = table(HertzLaw{}), multicontact = table(MulticontactLaw{}),
                      mdr = table(MdrLaw{1.6e8});
  std::mt19937_64 random(1);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const int count = 1000;
  const double radius = 5e-4;
  std::vector<ContactKinematics> contacts(count);
  std::vector<ContactHistory> histories(count);
  for (int k = 0; k < count; ++k) {
    ContactKinematics& c = contacts[k];
    c = ContactKinematics{};
    c.normal[2] = 1.0;
    c.radius_first = c.radius_second = radius;
    c.effective_radius = 0.5 * radius;
    c.effective_mass = 1e-6;
    c.inverse_inertia_sum = 1e10;
    const double largest = radius * (0.02 + 0.3 * uniform(random));
    c.overlap = k % 2 ? largest : largest * (1.0 - 0.01 * uniform(random));
    c.relative_velocity[0] = 1e-3 * (uniform(random) - 0.5);
    c.relative_velocity[2] = 1e-3 * (uniform(random) - 0.5);
    law_history<MdrLaw>(histories[k])[0] = largest;
  }
  double sum = 0.0;
  if (law == "hertz")
    sum = run<HertzLaw>(hertz.pair(0, 0), contacts, histories, passes);
  else if (law == "multicontact")
    sum = run<MulticontactLaw>(multicontact.pair(0, 0), contacts, histories, passes);
  else if (law == "mdr")
    sum = run<MdrLaw>(mdr.pair(0, 0), contacts, histories, passes);
  else {
    std::fprintf(stderr, "contact_law_cost: unknown law '%s'\n", law.c_str());
    return 2;
  }
  std::printf("%s: %d passes over %d contacts, sum of normal forces %.6g N\n", law.c_str(), passes,
              count, sum);
  return 0;
}
