#include <dem/lab/toolkit/grading.hpp>

#include <cmath>

#include <dem/core/errors.hpp>
#include <dem/core/math.hpp>

namespace dem::lab {

void Grading::validate(const std::string& where) const {
  require_positive(where + ".scale", scale);
  if (sampling == Sampling::NumberUniform) {
    require_positive(where + ".d_min", d_min);
    require(d_max >= d_min, where + ".d_max", d_max, ">= " + where + ".d_min (" + std::to_string(d_min) + ")");
    return;
  }
  require(sieve_diameters.size() >= 2 && sieve_diameters.size() == passing_fraction.size(), where + ".sieves",
          sieve_diameters.size(), "at least 2, as many as passing fractions");
  for (std::size_t k = 0; k < sieve_diameters.size(); ++k) {
    const std::string at = where + ".sieve_diameters[" + std::to_string(k) + "]";
    require_positive(at, sieve_diameters[k]);
    require(passing_fraction[k] >= 0.0 && passing_fraction[k] <= 1.0,
            where + ".passing_fraction[" + std::to_string(k) + "]", passing_fraction[k], "in [0, 1]");
    if (k > 0) {
      require(sieve_diameters[k] > sieve_diameters[k - 1], at, sieve_diameters[k], "increasing");
      require(passing_fraction[k] >= passing_fraction[k - 1], where + ".passing_fraction[" + std::to_string(k) + "]",
              passing_fraction[k], "non-decreasing");
    }
  }
  require(passing_fraction.front() == 0.0 && passing_fraction.back() == 1.0, where + ".passing_fraction",
          "first " + std::to_string(passing_fraction.front()) + ", last " + std::to_string(passing_fraction.back()),
          "from 0 to 1");
}

double Grading::smallest() const {
  return scale * (sampling == Sampling::NumberUniform ? d_min : sieve_diameters.front());
}
double Grading::largest() const {
  return scale * (sampling == Sampling::NumberUniform ? d_max : sieve_diameters.back());
}

Grading leighton_buzzard_b_by_mass() {
  Grading g;
  g.sampling = Sampling::MassGrading;
  g.sieve_diameters = {0.60e-3, 0.65e-3, 0.82e-3, 0.897e-3, 1.20e-3};
  g.passing_fraction = {0.0, 0.10, 0.50, 0.60, 1.0};
  return g;
}

namespace {

/// Inverse of the mass-passing curve, log-linear in diameter between sieves.
double diameter_at_mass_fraction(const Grading& g, double fraction) {
  for (std::size_t k = 1; k < g.sieve_diameters.size(); ++k) {
    if (fraction <= g.passing_fraction[k] && g.passing_fraction[k] > g.passing_fraction[k - 1]) {
      const double t = (fraction - g.passing_fraction[k - 1]) / (g.passing_fraction[k] - g.passing_fraction[k - 1]);
      return std::exp(std::log(g.sieve_diameters[k - 1]) + t * std::log(g.sieve_diameters[k] / g.sieve_diameters[k - 1]));
    }
  }
  return g.sieve_diameters.back();
}

}  // namespace

std::vector<double> sample_diameters(const Grading& g, double solid_volume, std::mt19937_64& rng) {
  g.validate();
  require_positive("solid volume", solid_volume);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<double> diameters;
  double volume = 0.0;
  const double d_small = g.smallest();
  while (volume < solid_volume) {
    double d;
    if (g.sampling == Sampling::NumberUniform) {
      d = g.scale * (g.d_min + (g.d_max - g.d_min) * unit(rng));
    } else {
      // A diameter drawn from the mass curve, kept with probability (d_small/d)^3: the number
      // distribution whose mass distribution is the sieve curve.
      do {
        d = g.scale * diameter_at_mass_fraction(g, unit(rng));
      } while (unit(rng) > std::pow(d_small / d, 3));
    }
    diameters.push_back(d);
    volume += pi / 6.0 * d * d * d;
    require(diameters.size() < 50'000'000, "ball count", diameters.size(), "< 5e7 (check the grading scale and the volume)");
  }
  return diameters;
}

}  // namespace dem::lab
