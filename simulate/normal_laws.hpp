#pragma once
// The registry of normal contact laws (the normal sub-model of contact_law.hpp, after LAMMPS
// GRANULAR's normal/damping/tangential/rolling split). Everything that depends on which laws
// exist derives from the one list below: the `normal_law` config choice and `plate --model`
// (contact_law_config.hpp), the pair constants (PairConstants::law and ::constants), the contact
// history and its snapshot datasets, the energy check, the time step's stiffness bound and the
// per-scene dispatch of the pair loop (forces.cpp instantiates it once per law).
//
// A law is a value type holding its parameters, with
//   name, needs_pair_pressure, history_fields, Constants,
//   options(), read(ConfigTable), write_toml(out), check(where), constants(Material, Material),
//   describe(ElasticPair, Constants), stiffness_ratio(ElasticPair, Constants, R*),
//   force(ElasticPair, Constants, ContactKinematics, √(R*δ), √(√(R*δ) m*), vn, history),
//   elastic_energy(ElasticPair, Constants, R*, ri, rj (a wall: 0), δ, history);
// tests/unit/simulate/contact_law_reference_test.cpp replays tests/data/contact_laws/<name>.csv
// for every law listed here.
#include <cstddef>
#include <tuple>
#include <type_traits>
#include <utility>
#include <variant>

#include "simulate/hertz_law.hpp"
#include "simulate/mdr_law.hpp"
#include "simulate/multicontact_law.hpp"

namespace shapepress::simulate {

template <class... Laws>
struct LawList {};

// The registration: one entry per law, the first the default of `normal_law`.
using NormalLaws = LawList<HertzLaw, MulticontactLaw, MdrLaw>;

namespace law_detail {

template <class List>
struct Registry;

template <class... Laws>
struct Registry<LawList<Laws...>> {
  using Choice = std::variant<Laws...>;
  using Constants = std::tuple<typename Laws::Constants...>;
  static constexpr std::size_t count = sizeof...(Laws);
  static constexpr std::size_t history_size = (std::size_t{0} + ... + Laws::history_fields.size());

  template <class Law>
  static constexpr std::size_t index() {
    std::size_t k = 0, found = count;
    ((std::is_same_v<Law, Laws> ? (found = k, ++k) : ++k), ...);
    return found;
  }
  // The first history slot of `Law` in ContactHistory::normal: the laws' fields one after another.
  template <class Law>
  static constexpr std::size_t history_offset() {
    std::size_t offset = 0, k = 0;
    const std::size_t stop = index<Law>();
    ((k++ < stop ? offset += Laws::history_fields.size() : offset), ...);
    return offset;
  }
  template <class F>
  static void for_each(F&& f) {
    (f.template operator()<Laws>(), ...);
  }
  // f.operator()<Law>() for the law of index `index`: a chain of compares on a small integer,
  // not a virtual call; the pair loop calls it only for a scene that mixes laws.
  template <class F>
  [[gnu::always_inline]] static auto with(std::size_t index, F&& f) {
    using Result = decltype(f.template operator()<std::tuple_element_t<0, std::tuple<Laws...>>>());
    if constexpr (std::is_void_v<Result>) {
      std::size_t k = 0;
      (void)((index == k++ ? (f.template operator()<Laws>(), true) : false) || ...);
    } else {
      Result out{};
      std::size_t k = 0;
      (void)((index == k++ ? (out = f.template operator()<Laws>(), true) : false) || ...);
      return out;
    }
  }
};

using Normal = Registry<NormalLaws>;

}  // namespace law_detail

// A pair's normal law with its parameters, as an Interaction states it.
using NormalLawChoice = law_detail::Normal::Choice;
// Every law's pair constants side by side (the pair table is materials², so the unused ones cost
// nothing that matters); PairConstants::law says which one applies.
using NormalLawConstants = law_detail::Normal::Constants;
inline constexpr std::size_t normal_law_count = law_detail::Normal::count;
// Doubles of normal-law history per contact, over all laws.
inline constexpr std::size_t normal_history_size = law_detail::Normal::history_size;

template <class Law>
inline constexpr std::size_t normal_law_index = law_detail::Normal::index<Law>();
template <class Law>
inline constexpr std::size_t normal_history_offset = law_detail::Normal::history_offset<Law>();

// f.template operator()<Law>() for every registered law, in order.
template <class F>
void for_each_normal_law(F&& f) {
  law_detail::Normal::for_each(std::forward<F>(f));
}

// f.template operator()<Law>() for the law of index `index` (PairConstants::law,
// NormalLawChoice::index()); returns what f returns.
template <class F>
[[gnu::always_inline]] inline auto with_normal_law(std::size_t index, F&& f) {
  return law_detail::Normal::with(index, std::forward<F>(f));
}

}  // namespace shapepress::simulate
