// The bonded network's highest frequency by Lanczos iteration, and the stable step it gives
// (bonds.hpp: bond_top_frequency, bond_stability_step).
// The elastic springs are the stiffest a bond gets under every bond model: a yielding mode's
// tangent is k H/(1 + H) < k past yield and k on unloading (bond_models.hpp), so the step that is
// stable for the elastic network is stable for the plastic one.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <vector>

#include "simulate/bonds.hpp"

namespace shapepress::simulate {

namespace {

// A bond's direction i → j (nearest image) and the arms from each centre to the bond's centre.
struct BondFrame {
  double n[3];
  double arm_first, arm_second;
};

std::vector<BondFrame> bond_frames(const BondSet& bonds, const SphereState& s, const Box& box) {
  std::vector<BondFrame> frames(bonds.size());
  for (std::size_t b = 0; b < bonds.size(); ++b) {
    const auto i = static_cast<std::size_t>(bonds.first[b]);
    const auto j = static_cast<std::size_t>(bonds.second[b]);
    double x[3] = {s.position.x[j] - s.position.x[i], s.position.y[j] - s.position.y[i],
                   s.position.z[j] - s.position.z[i]};
    if (box.periodic_x()) x[0] -= box.length_x * std::nearbyint(x[0] / box.length_x);
    if (box.periodic_y()) x[1] -= box.length_y * std::nearbyint(x[1] / box.length_y);
    const double d = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    BondFrame& f = frames[b];
    for (int c = 0; c < 3; ++c)
      f.n[c] = d > 0.0 ? x[c] / d : (c == 2 ? 1.0 : 0.0);
    // The bond's centre divides the centre distance in the ratio of the radii (bonds.cpp).
    const double ri = s.radius[i], rj = s.radius[j];
    f.arm_first = d * ri / (ri + rj);
    f.arm_second = d * rj / (ri + rj);
  }
  return frames;
}

void cross(const double a[3], const double b[3], double out[3]) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}

double dot(const double a[3], const double b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// Which matrix a product takes: the bonds' springs, or their dampers (the matrix of damping
// rates).
enum class Operator { stiffness, damping };

// The linearised network: S's entries and every bond's direction and arms, built once for any
// number of products.
struct LinearisedBonds {
  std::vector<double> scale;
  std::vector<BondFrame> frames;
};

LinearisedBonds linearise(const BondSet& bonds, const SphereState& state, const Box& box) {
  LinearisedBonds out{std::vector<double>(6 * state.size()), bond_frames(bonds, state, box)};
  for (std::size_t i = 0; i < state.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      out.scale[6 * i + c] = std::sqrt(state.inverse_mass[i]);
      out.scale[6 * i + 3 + c] = std::sqrt(state.inverse_inertia[i]);
    }
  return out;
}

// Per bond the operator's coefficients of the normal, shear, twist and bending modes: the springs,
// or the dampers the bond loop applies (bond_damper_coefficients).
std::vector<std::array<double, 4>> mode_coefficients(Operator op, const BondSet& bonds,
                                                     const SphereState& state) {
  std::vector<std::array<double, 4>> k(bonds.size());
  for (std::size_t b = 0; b < bonds.size(); ++b)
    k[b] = op == Operator::damping
               ? bond_damper_coefficients(bonds, b, state)
               : std::array<double, 4>{bonds.normal_spring[b], bonds.shear_spring[b],
                                       bonds.twist_spring[b], bonds.bend_spring[b]};
  return k;
}

// y = S K S x over six entries per sphere (translation, then rotation), K the bonds' stiffness
// linearised about the present state and S = diag(1/√m, 1/√I). A bond's energy is
//   ½ kn (δ·n)² + ½ ks |δ − (δ·n) n|² + ½ kt (Δθ·n)² + ½ kb |Δθ − (Δθ·n) n|²,
//   δ = uj − ui − (rcj θj + rci θi) × n,   Δθ = θj − θi,
// the relative displacement at the bond's centre and the relative turn that advance_springs
// integrates as increments; y is its gradient.
// With the dampers' coefficients in place of the springs, y = S C S x.
void apply(const BondSet& bonds, const LinearisedBonds& network,
           const std::vector<std::array<double, 4>>& coefficients, const std::vector<double>& x,
           std::vector<double>& y) {
  const std::vector<double>& scale = network.scale;
  std::fill(y.begin(), y.end(), 0.0);
  for (std::size_t b = 0; b < bonds.size(); ++b) {
    if (!bonds.intact[b]) continue;
    const auto i = static_cast<std::size_t>(bonds.first[b]);
    const auto j = static_cast<std::size_t>(bonds.second[b]);
    const BondFrame& f = network.frames[b];
    double ui[3], uj[3], ti[3], tj[3];
    for (int c = 0; c < 3; ++c) {
      ui[c] = scale[6 * i + c] * x[6 * i + c];
      uj[c] = scale[6 * j + c] * x[6 * j + c];
      ti[c] = scale[6 * i + 3 + c] * x[6 * i + 3 + c];
      tj[c] = scale[6 * j + 3 + c] * x[6 * j + 3 + c];
    }
    double arm_turn[3], slip[3], delta[3], turn[3];
    for (int c = 0; c < 3; ++c)
      arm_turn[c] = f.arm_second * tj[c] + f.arm_first * ti[c];
    cross(arm_turn, f.n, slip);
    for (int c = 0; c < 3; ++c) {
      delta[c] = uj[c] - ui[c] - slip[c];
      turn[c] = tj[c] - ti[c];
    }
    const double dn = dot(delta, f.n), tn = dot(turn, f.n);
    const auto [kn, ks, kt, kb] = coefficients[b];
    double g[3], h[3], ng[3];
    for (int c = 0; c < 3; ++c) {
      g[c] = kn * dn * f.n[c] + ks * (delta[c] - dn * f.n[c]);
      h[c] = kt * tn * f.n[c] + kb * (turn[c] - tn * f.n[c]);
    }
    cross(f.n, g, ng);
    for (int c = 0; c < 3; ++c) {
      y[6 * j + c] += scale[6 * j + c] * g[c];
      y[6 * i + c] -= scale[6 * i + c] * g[c];
      y[6 * j + 3 + c] += scale[6 * j + 3 + c] * (h[c] - f.arm_second * ng[c]);
      y[6 * i + 3 + c] += scale[6 * i + 3 + c] * (-h[c] - f.arm_first * ng[c]);
    }
  }
}

// The number of eigenvalues below `x` of the symmetric tridiagonal matrix (alpha, beta): the
// negative pivots of its LDLᵀ factorisation (Sylvester's law of inertia).
std::size_t eigenvalues_below(const std::vector<double>& alpha, const std::vector<double>& beta,
                              double x) {
  std::size_t below = 0;
  double pivot = 1.0;
  for (std::size_t k = 0; k < alpha.size(); ++k) {
    const double coupling = k > 0 ? beta[k - 1] * beta[k - 1] / pivot : 0.0;
    pivot = alpha[k] - x - coupling;
    if (pivot == 0.0) pivot = -std::numeric_limits<double>::min();
    if (pivot < 0.0) ++below;
  }
  return below;
}

// The largest eigenvalue of the tridiagonal matrix, by bisection on the count of eigenvalues
// below a point, between its Gershgorin interval's ends.
double largest_eigenvalue(const std::vector<double>& alpha, const std::vector<double>& beta) {
  double low = 0.0, high = 0.0;
  for (std::size_t k = 0; k < alpha.size(); ++k) {
    const double off =
        (k > 0 ? std::fabs(beta[k - 1]) : 0.0) + (k + 1 < alpha.size() ? std::fabs(beta[k]) : 0.0);
    low = std::min(low, alpha[k] - off);
    high = std::max(high, alpha[k] + off);
  }
  const std::size_t m = alpha.size();
  for (int it = 0; it < 200 && high - low > 1e-15 * std::fabs(high); ++it) {
    const double mid = 0.5 * (low + high);
    if (eigenvalues_below(alpha, beta, mid) == m)
      high = mid;
    else
      low = mid;
  }
  return high;
}

// A start vector of every sphere's every mode: a fixed hash of the entry's index in [-1, 1], so
// the estimate is the same on every run and thread count.
double start_entry(std::size_t k) {
  std::uint64_t z = (static_cast<std::uint64_t>(k) + 1) * 0x9E3779B97F4A7C15ULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * 0x1.0p-52 - 1.0;
}

// The largest eigenvalue of S·op·S by Lanczos (Paige 1972): the largest Ritz value rises to it
// fastest of all the spectrum, so a few dozen products give it without re-orthogonalisation
// (lost orthogonality repeats a converged Ritz value; it does not move the largest). It stops
// when that value has settled to 1e-7 over ten iterations.
double top_eigenvalue(const BondSet& bonds, const LinearisedBonds& network,
                      const std::vector<std::array<double, 4>>& coefficients) {
  const std::size_t n = network.scale.size();
  if (bonds.intact_count() == 0 || n == 0) return 0.0;
  std::vector<double> v(n), previous(n, 0.0), w(n);
  double norm = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    v[k] = start_entry(k);
    norm += v[k] * v[k];
  }
  for (double& e : v)
    e /= std::sqrt(norm);
  std::vector<double> alpha, beta, ritz;
  constexpr int most_iterations = 400, settle = 10;
  for (int it = 0; it < most_iterations; ++it) {
    apply(bonds, network, coefficients, v, w);
    double a = 0.0;
    for (std::size_t k = 0; k < n; ++k)
      a += w[k] * v[k];
    const double b_before = beta.empty() ? 0.0 : beta.back();
    double b = 0.0;
    for (std::size_t k = 0; k < n; ++k) {
      w[k] -= a * v[k] + b_before * previous[k];
      b += w[k] * w[k];
    }
    b = std::sqrt(b);
    alpha.push_back(a);
    ritz.push_back(largest_eigenvalue(alpha, beta));
    const int m = static_cast<int>(ritz.size());
    if (m > settle &&
        ritz.back() - ritz[static_cast<std::size_t>(m - 1 - settle)] <= 1e-7 * ritz.back())
      break;
    // An invariant subspace: its largest Ritz value is an eigenvalue; with a start vector that
    // has every mode, the largest.
    if (b <= 1e-12 * std::max(std::fabs(a), ritz.back())) break;
    beta.push_back(b);
    std::swap(previous, v);
    for (std::size_t k = 0; k < n; ++k)
      v[k] = w[k] / b;
  }
  return std::max(0.0, ritz.back());
}

}  // namespace

double bond_top_frequency(const BondSet& bonds, const SphereState& state, const Box& box) {
  return std::sqrt(top_eigenvalue(bonds, linearise(bonds, state, box),
                                  mode_coefficients(Operator::stiffness, bonds, state)));
}

double bond_top_damping_rate(const BondSet& bonds, const SphereState& state, const Box& box) {
  return top_eigenvalue(bonds, linearise(bonds, state, box),
                        mode_coefficients(Operator::damping, bonds, state));
}

double bond_stability_step(const BondSet& bonds, const SphereState& state, const Box& box) {
  const LinearisedBonds network = linearise(bonds, state, box);
  const double omega = std::sqrt(
      top_eigenvalue(bonds, network, mode_coefficients(Operator::stiffness, bonds, state)));
  if (!(omega > 0.0)) return std::numeric_limits<double>::infinity();
  // The engine's dampers read the predicted end-of-step velocity v(t+dt/2) + dt/2 a(t)
  // (forces.cpp), for which an oscillator x'' = -ω²x - γx' is stable while (ω dt)² + 4 γ dt ≤ 4
  // (its amplification matrix; central differences, which damp with the mean velocity, allow
  // (ω dt)² + 2 γ dt ≤ 4 (Belytschko, Liu & Moran 2000, §6.3)). ω² and γ of every mode are at
  // most the largest eigenvalues of M^-1/2 K M^-1/2 and M^-1/2 C M^-1/2 (each mode's Rayleigh
  // quotient), so dt = 2(√(γ² + ω²) − γ)/ω² with both largest keeps every mode stable.
  const bool damped = std::any_of(bonds.damping_ratio.begin(), bonds.damping_ratio.end(),
                                  [](double zeta) { return zeta > 0.0; });
  const double gamma =
      damped ? top_eigenvalue(bonds, network, mode_coefficients(Operator::damping, bonds, state))
             : 0.0;
  const double step = 2.0 * (std::sqrt(gamma * gamma + omega * omega) - gamma) / (omega * omega);
  return bond_stability_margin * step;
}

}  // namespace shapepress::simulate
