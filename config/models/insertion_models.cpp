// The inserters and insertion regions of [[insertion]]: a section per model
// (its reader and its declaration), then the registries that list them.

#include "config/models/insertion_models.hpp"

#include <limits>
#include <utility>

namespace demcal::config {

namespace {

using reader::Table;
using reader::Vec3;
using reader::above;
using reader::at_least;
using reader::between;
using reader::guarded;
using reader::require_above;

// ---------------------------------------------------------------- region: box

std::unique_ptr<dem::Region> read_box(Table& r) {
  const Vec3 lo = r.vec3("lower_m");
  const Vec3 hi = r.vec3("upper_m");
  require_above(r, "upper_m", lo, hi, "lower_m");
  r.finish();
  return guarded(r, [&] { return dem::make_box_region(lo, hi); });
}

ModelInfo box_info() {
  return {"box",
          "an axis-aligned box",
          {{"lower_m", "m", "required", "[x, y, z]", "its lower corner"},
           {"upper_m", "m", "required", "[x, y, z], each above lower_m's", "its upper corner"}}};
}

// ---------------------------------------------------------------- region: cylinder

std::unique_ptr<dem::Region> read_cylinder_region(Table& r) {
  const Vec3 base = r.vec3("base_centre_m");
  const double radius = r.number("radius_m", above(0));
  const double height = r.number("height_m", above(0));
  r.finish();
  return guarded(r, [&] { return dem::make_cylinder_region(base, radius, height); });
}

ModelInfo cylinder_region_info() {
  return {"cylinder",
          "a vertical (z-axis) cylinder",
          {{"base_centre_m", "m", "required", "[x, y, z]", "the centre of its base"},
           {"radius_m", "m", "required", range_of(above(0)), "its radius"},
           {"height_m", "m", "required", range_of(above(0)), "its height"}}};
}

// ---------------------------------------------------------------- inserter: pour

const reader::Range kBatchFraction = between(0, true, 0.6, true);

std::unique_ptr<dem::Inserter> read_pour(Table& t, const InsertionCommon& c,
                                         std::unique_ptr<dem::Region> region,
                                         std::unique_ptr<dem::SizeDistribution> sizes) {
  dem::PourOptions o;
  o.material = c.material;
  o.density_kg_m3 = c.density_kg_m3;
  o.amount = c.amount;
  o.gravity_m_s2 = c.gravity_m_s2;
  o.velocity_m_s = t.vec3_or("velocity_m_s", Vec3{});
  o.start_s = t.number_or("start_s", 0.0, at_least(0));
  const bool has_rate = t.has("rate_particles_per_s");
  if (has_rate && t.has("batch_volume_fraction"))
    t.fail("batch_volume_fraction",
           "give rate_particles_per_s (a steady rate) or batch_volume_fraction (batches), not "
           "both");
  if (has_rate) {
    o.rate_particles_per_s = t.number("rate_particles_per_s", above(0));
  } else {
    o.batch_volume_fraction = t.number_or("batch_volume_fraction", 0.3, kBatchFraction);
  }
  o.attempts_per_particle = static_cast<int>(t.integer_or("attempts_per_particle", 200, 1, 1000000));
  t.finish();
  return guarded(t, [&] {
    return dem::make_pour_inserter(std::move(region), std::move(sizes), o);
  });
}

ModelInfo pour_info() {
  return {"pour",
          "pours particles from its region, at a steady rate or in batches (LAMMPS's fix pour)",
          {{"velocity_m_s", "m/s", "[0, 0, 0]", "[x, y, z]", "each particle's initial velocity"},
           {"start_s", "s", "0", range_of(at_least(0)), "when pouring starts"},
           {"rate_particles_per_s", "1/s", "absent: batches", range_of(above(0)),
            "a steady rate; not with batch_volume_fraction"},
           {"batch_volume_fraction", "1", "0.3 (without a rate)", range_of(kBatchFraction),
            "each batch fills the region to this solid fraction"},
           {"attempts_per_particle", "", "200", "an integer in [1, 1000000]",
            "placement attempts before a particle is given up"}}};
}

// ---------------------------------------------------------------- inserter: fill

std::unique_ptr<dem::Inserter> read_fill(Table& t, const InsertionCommon& c,
                                         std::unique_ptr<dem::Region> region,
                                         std::unique_ptr<dem::SizeDistribution> sizes) {
  dem::FillOptions o;
  o.material = c.material;
  o.density_kg_m3 = c.density_kg_m3;
  o.amount = c.amount;
  o.time_s = t.number_or("time_s", 0.0, at_least(0));
  o.method = t.choice_or("method", {"random", "lattice"}, "random");
  o.lattice_gap = t.number_or("lattice_gap", 0.05, at_least(0));
  o.attempts_per_particle = static_cast<int>(t.integer_or("attempts_per_particle", 400, 1, 1000000));
  t.finish();
  return guarded(t, [&] {
    return dem::make_fill_inserter(std::move(region), std::move(sizes), o);
  });
}

ModelInfo fill_info() {
  return {"fill",
          "fills its region at one instant",
          {{"time_s", "s", "0", range_of(at_least(0)), "when to fill"},
           {"method", "", "\"random\"", "\"random\" | \"lattice\"",
            "random sequential addition, or a jittered cubic lattice (denser)"},
           {"lattice_gap", "1", "0.05", range_of(at_least(0)),
            "the lattice's spacing over the largest diameter, minus 1"},
           {"attempts_per_particle", "", "400", "an integer in [1, 1000000]",
            "placement attempts before a particle is given up"}}};
}

}  // namespace

const RegionRegistry& region_models() {
  static const RegionRegistry registry = [] {
    RegionRegistry r({"region", "", "[insertion.region] shape = \"<name>\""});
    r.add(box_info(), &read_box);
    r.add(cylinder_region_info(), &read_cylinder_region);
    return r;
  }();
  return registry;
}

const InserterRegistry& inserter_models() {
  static const InserterRegistry registry = [] {
    InserterRegistry r({"insertion", "", "[[insertion]] type = \"<name>\""});
    r.add(pour_info(), &read_pour);
    r.add(fill_info(), &read_fill);
    return r;
  }();
  return registry;
}

}  // namespace demcal::config
