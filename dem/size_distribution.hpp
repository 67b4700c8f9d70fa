#pragma once
// Particle size distributions. Each draws particle *diameters by number*: the
// probability that the next inserted particle has a given size. Sieve curves
// are measured by mass, so SieveCurve converts mass fractions to number
// fractions (weight 1/d^3) before drawing.

#include "dem/random.hpp"

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace demcal::dem {

class SizeDistribution {
 public:
  virtual ~SizeDistribution() = default;
  virtual double sample_diameter_m(Random& rng) const = 0;
  virtual double min_diameter_m() const = 0;
  virtual double max_diameter_m() const = 0;
  // Mean of d^3 by number; with the density gives the mean particle mass.
  virtual double mean_diameter_cubed_m3() const = 0;
  virtual std::string describe() const = 0;
};

// All particles the same size.
std::unique_ptr<SizeDistribution> make_monodisperse(double diameter_m);
// Diameter uniform by number in [min, max].
std::unique_ptr<SizeDistribution> make_uniform(double min_diameter_m, double max_diameter_m);
// The same written as a centre and a width: uniform in [mean (1 - w), mean (1 + w)],
// 0 <= w < 1, so that the width of the distribution is one number a design of
// experiments can vary while the mean diameter (by number) stays where it is.
// (The volume-equivalent mean, (mean d^3)^(1/3) = mean (1 + w^2)^(1/3), moves a
// little: +3.5 % at w = 0.33.)
std::unique_ptr<SizeDistribution> make_uniform_about_mean(double mean_diameter_m,
                                                          double relative_half_width);
// Normal by number, truncated to [min, max] (resampled, not clipped).
std::unique_ptr<SizeDistribution> make_truncated_normal(double mean_diameter_m,
                                                        double std_dev_m, double min_diameter_m,
                                                        double max_diameter_m);
// Log-normal by number: ln d ~ N(ln median, sigma_ln^2), truncated to [min, max].
std::unique_ptr<SizeDistribution> make_log_normal(double median_diameter_m, double sigma_ln,
                                                  double min_diameter_m, double max_diameter_m);
// A sieve analysis: pairs (sieve opening d, cumulative mass fraction passing),
// openings strictly increasing, fractions non-decreasing from 0 (the finest
// opening is the smallest particle) to 1. Within each sieve class the mass is
// spread uniformly in d; the class's number weight follows from its mass.
std::unique_ptr<SizeDistribution> make_sieve_curve(
    std::vector<std::pair<double, double>> opening_m_and_fraction_passing);

}  // namespace demcal::dem
