#pragma once
// The angle of repose of a DEM pile, read from its free surface the way a
// laboratory reads it from a photograph or a laser profile: the measurement
// behind `observables.angle_of_repose_deg`.
//
// Two geometries, gravity along -z in both:
//  * slice — a quasi-2D ridge in a slab that is thin (possibly periodic) along
//    one horizontal axis. Surface profile h(s) along the long axis s: in bins of
//    bin_width_diameters median diameters d, h = max(z + r) - base_height_m
//    over the particles whose centre falls in the bin (the max runs over the
//    slab's thickness, like a side-wall photograph). Two sides: "left" (s below
//    the crest) and "right".
//  * cone — a 3D heap around a vertical axis through (x0, y0). The surface is a
//    height map: square columns of the bin width, each topped by its highest
//    particle (max(z + r) - base). The plane is cut into `sectors` equal
//    azimuthal sectors (sector k spans azimuths [k, k+1) * 360 deg / sectors,
//    counter-clockwise from +x) and radial bins of the bin width; a sector's
//    profile in a bin is the mean height of the column tops that fall in it, at
//    their mean radius. (Not the single highest grain of the bin: the bin's
//    arc grows with the radius, so ever more rough grains compete for its
//    maximum and the outer bins come out higher — measured -0.3 deg at 45 deg
//    on a 20 d pile. Columns have one area at every radius.) Each sector is one
//    side, "sector_k".
//
// Rules (the same for every side; the result repeats them in `rules`):
//  * Heights are measured from the base (base_height_m): every *_height_m is
//    above the base, never an absolute z.
//  * Bins (and cone columns) without particles hold no data; walks step over
//    them rather than read them as floor: near the axis a cone sector's bin
//    may be too small to catch a column, and a cell cut by a wall or the
//    selection box may be empty right next to a standing slope. The floor is
//    seen where grains lie on it (the toe rule below).
//  * Fit positions: a bin's height is fitted at the position where it was
//    taken — the long-axis coordinate of the particle that set the maximum
//    (slice), the mean radius of the averaged column tops (cone) — not at the
//    bin centre: a 1.5 d bin on a 40 deg slope spans more than a diameter of
//    height, and bin-centre positions add that as noise (it doubled the
//    worst side error on the synthetic piles of the tests).
//  * Crest: 3-bin running mean of the profile (over the occupied bins in the
//    window); its maximum locates the crest; the crest height is the largest
//    raw height among the three bins around it (the peer tool's rule:
//    smoothing only picks the place, so one grain perched on the slope cannot
//    become the crest, while the height stays that of the real top).
//    Cone: the same on the column grid (3x3 mean); each sector then walks
//    outward from its own highest (smoothed) radial bin, since near the axis
//    a sector's bins are too small to be sure of holding a column.
//  * Cone axis when not given: the centroid (x, y) of the top particles of the
//    "cap" — the columns at least upper_fraction of the crest height high that
//    are connected (8-neighbour) to the highest column. The cap is a disc
//    around the apex, so its centroid averages out the roughness of any single
//    grain at the top.
//  * Fit zone: walking outward from the crest, a side ends at the first bin
//    below max(lower_fraction * crest height, 1.25 d) (or at the end of the
//    profile); of the bins passed, those with lower_fraction * H <= h <=
//    upper_fraction * H are fitted (H = crest height). Excludes the rounded
//    crest and the toe's run-out, as /work/shared/peers/tools/aor.py does with
//    the same default fractions 0.15 / 0.85; the walk keeps stray grains and
//    neighbouring heaps beyond the toe out of the fit.
//  * Fit: robust straight line h = a + b s (IRLS, Tukey bisquare 4.685,
//    MAD scale, from OLS; see robust_line_fit.hpp); s = long-axis coordinate
//    (slice) or radius (cone). angle = atan(descent of h per unit of outward
//    distance), in degrees; its std error = SE(b) / (1 + b^2), propagated
//    through atan, in degrees.
//  * A side is valid when it has at least min_points fitted bins and its
//    fitted line descends, across the fitted range, by at least
//    min_drop_fraction of the fit band's height ((upper - lower) * H): a flat
//    layer has bins in the band but no slope through it. Invalid sides stay
//    in the result with the reason; fewer than 2 valid sides throws
//    std::runtime_error naming each invalid side and its count.
//  * mean_deg: plain mean over the valid sides. uncertainty_deg =
//    sqrt(SEM^2 + fit^2): SEM = sample standard deviation of the side angles
//    / sqrt(n) (the sides' disagreement: asymmetry, roughness), fit =
//    sqrt(sum se_i^2) / n (the fit errors propagated through the mean). The two
//    overlap — fit noise also shows in the scatter — so the sum is
//    conservative; with only 2 sides the SEM alone would itself be too noisy.
//  * Toe (base half-width): walking outward from the crest, the first bin at
//    or below 1.25 d above the base (a grain resting on the floor tops out at
//    d; the quarter diameter allows for polydispersity). base_half_width_m is
//    the mean crest-to-toe distance over the sides whose toe was found.
//  * d is the median diameter of the selected particles.

#include "dem/vec3.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace demcal::dem {

// Particles whose centre lies outside [min_m, max_m] (componentwise,
// inclusive) are ignored: grains that bounced away, a hopper's content above.
struct SelectionBox {
  Vec3 min_m;
  Vec3 max_m;
};

// Options shared by both geometries.
struct AoRCommonOptions {
  double base_height_m = 0.0;        // z of the floor the pile stands on
  double bin_width_diameters = 1.5;  // bin width in median particle diameters
  double lower_fraction = 0.15;      // fit band, fractions of the crest height
  double upper_fraction = 0.85;
  int min_points = 4;              // fitted bins a side needs to count
  double min_drop_fraction = 0.5;  // of the band height, see the header comment
  std::optional<SelectionBox> selection;
};

struct SliceAoROptions : AoRCommonOptions {
  int long_axis = 0;  // 0 = x, 1 = y; the other horizontal axis is the slab's thin one
};

struct ConicalAoROptions : AoRCommonOptions {
  int sectors = 8;
  // (x0, y0) of the vertical pile axis; unset = the cap centroid (see above).
  std::optional<std::array<double, 2>> axis_centre_m;
};

struct AoRSide {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

  std::string name;  // "left", "right", "sector_0", ...
  bool valid = false;
  std::string invalid_reason;  // empty when valid
  double angle_deg = kNaN;     // NaN when no line could be fitted
  double std_error_deg = kNaN;
  int points = 0;           // bins inside the fit band (fitted when valid)
  int rejected_points = 0;  // of those, given zero weight by the robust fit
  // The fitted line h = intercept + slope * s, s = long-axis coordinate
  // (slice) or radial distance from the axis (cone); h above the base.
  double slope = kNaN;
  double intercept_m = kNaN;
  double fit_from_m = kNaN;  // s range of the fitted bins
  double fit_to_m = kNaN;
  bool toe_found = false;
  double toe_position_m = kNaN;  // s of the toe bin's centre
  // Cone sectors only: azimuth range, degrees counter-clockwise from +x.
  double azimuth_from_deg = kNaN;
  double azimuth_to_deg = kNaN;
};

struct AngleOfRepose {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

  std::string geometry;  // "slice" or "cone"
  double mean_deg = kNaN;
  double uncertainty_deg = kNaN;
  double sem_deg = kNaN;        // the scatter part of the uncertainty
  double fit_error_deg = kNaN;  // the fit part
  int valid_sides = 0;
  std::vector<AoRSide> sides;

  double crest_height_m = kNaN;                     // above the base
  double crest_position_m = kNaN;                   // slice: long-axis coordinate of the crest
  std::array<double, 2> axis_centre_m{kNaN, kNaN};  // cone: (x0, y0)
  bool axis_centre_given = false;
  double base_half_width_m = kNaN;  // mean crest-to-toe distance

  double diameter_m = kNaN;  // median diameter of the selected particles
  double bin_width_m = kNaN;
  double base_height_m = kNaN;
  std::size_t particles_used = 0;

  // The surface profile: bin centres (slice: long-axis coordinate; cone:
  // radius) and heights above the base (cone: the median over the sectors
  // with data at that radius). NaN (JSON null) where no particle is.
  std::vector<double> profile_position_m;
  std::vector<double> profile_height_m;

  std::vector<std::string> rules;  // the rules above, with this run's numbers
};

// Both throw std::invalid_argument for inconsistent inputs or options, and
// std::runtime_error when no pile can be measured (no particles selected,
// fewer than 2 valid sides; the message names every invalid side).
AngleOfRepose measure_slice_angle_of_repose(const std::vector<Vec3>& position_m,
                                            const std::vector<double>& radius_m,
                                            const SliceAoROptions& options = {});
AngleOfRepose measure_conical_angle_of_repose(const std::vector<Vec3>& position_m,
                                              const std::vector<double>& radius_m,
                                              const ConicalAoROptions& options = {});

// The slice rules applied to a measured surface profile (a laser line or a
// photograph's edge across a quasi-2D pile): heights height_m (above z = 0;
// base_height_m is subtracted as for particles) at long-axis positions
// position_m, in any order; a NaN height is a point without a reading. Bins
// are bin_width_diameters * diameter_m wide (the grains' median diameter,
// given); each bin's height is its highest reading, fitted at that reading's
// position, as a bin's highest particle is. A selection box does not apply.
// Throws as the particle versions do.
AngleOfRepose measure_profile_angle_of_repose(const std::vector<double>& position_m,
                                              const std::vector<double>& height_m,
                                              double diameter_m,
                                              const AoRCommonOptions& options = {});

// Stable names: angle_of_repose_deg, angle_of_repose_uncertainty_deg,
// sides: [{name, valid, angle_deg, std_error_deg, points, ...}],
// crest_height_m, crest_position_m (slice: number; cone: [x0, y0]),
// base_half_width_m, profile: {position_m: [...], height_m: [...]}, rules.
// NaN comes out as null.
nlohmann::json to_json(const AngleOfRepose& result);

}  // namespace demcal::dem
