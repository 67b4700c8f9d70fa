#pragma once
// What was measured in the laboratory: one value per setup and observable,
// with its standard uncertainty. (Reading the CSV is the command line's job,
// config/recordings_csv.hpp; the calibration sees only these.)

#include <string>
#include <vector>

namespace demcal::calibrate {

struct Recording {
  std::string setup;       // the apparatus it was measured on, e.g. "sandglass"
  std::string observable;  // a stable observable name, e.g. "angle_of_repose_deg"
  double value = 0.0;      // SI units, as the observable's name says
  double sigma = 0.0;      // the measurement's own standard uncertainty (> 0), same units
  // How many tests the value is the mean of. The test-to-test scatter is not
  // part of sigma: the DEM's replicate scatter stands for it, divided by
  // sqrt(repeats), so that a mean of several tests is not charged a single
  // test's scatter, nor the scatter counted twice.
  int repeats = 1;
  std::string unit;        // as written, checked against the observable
  // Where it was read, for messages: the recordings CSV and its row, or the study file and
  // the line of its [raw_recordings.<setup>] table for a value measured from raw series.
  std::size_t line = 0;
  std::string file = {};
};

// A measured time series, e.g. m(t) of a discharge (time_s, value).
struct RecordedSeries {
  std::string setup;
  std::string quantity;  // e.g. "discharged_mass_kg"
  std::vector<double> time_s, value;
  std::string file;
};

}  // namespace demcal::calibrate
