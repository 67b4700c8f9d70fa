#include "engines/liggghts_deck.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace demcal::engines {
namespace {

std::string n(double v) { return deck_number(v); }

constexpr double kMinPeriodicMeshExtentDiameters = 6.0;

const char* const kAxis[3] = {"x", "y", "z"};

// LIGGGHTS wants its random seeds prime and above 10000.
std::uint64_t prime_seed(std::uint64_t seed, std::uint64_t salt) {
  std::uint64_t p = 10007 + (seed * 7919 + salt * 104729) % 900000;
  auto prime = [](std::uint64_t x) {
    if (x % 2 == 0) return false;
    for (std::uint64_t f = 3; f * f <= x; f += 2)
      if (x % f == 0) return false;
    return true;
  };
  while (!prime(p)) ++p;
  return p;
}

std::string box_words(const BoxRegion& b) {
  return n(b.lower_m.x) + " " + n(b.upper_m.x) + " " + n(b.lower_m.y) + " " + n(b.upper_m.y) + " " +
         n(b.lower_m.z) + " " + n(b.upper_m.z);
}

long steps_for(double seconds, double dt) {
  return std::max(1L, static_cast<long>(std::llround(seconds / dt)));
}

void phase_loop(std::ostringstream& s, const std::string& phase, const std::string& condition,
                double max_s, const ApparatusLayout& l) {
  const long chunk = steps_for(l.protocol.check_interval_s, l.time_step_s);
  const long chunks =
      std::max(1L, static_cast<long>(std::ceil(max_s / l.protocol.check_interval_s)));
  s << "\n# --- " << phase << ": until " << condition << ", checked every "
    << n(l.protocol.check_interval_s) << " s, at most " << n(max_s) << " s\n"
    << "variable        " << phase << "_done equal " << condition << "\n"
    << "variable        " << phase << "_chunk loop " << chunks << "\n"
    << "label           " << phase << "_loop\n"
    << "run             " << chunk << " post no\n"
    << "if              \"${" << phase << "_done} > 0\" then \"jump SELF " << phase << "_end\"\n"
    << "next            " << phase << "_chunk\n"
    << "jump            SELF " << phase << "_loop\n"
    << "label           " << phase << "_end\n"
    << "print           \"DEMCAL_PHASE " << phase << " at_rest ${" << phase
    << "_done} atoms ${n_atoms} rms_speed_m_s ${rms_speed}\"\n";
}

}  // namespace

std::string block_stl(const SolidBlock& b) {
  const double x0 = b.lower_m.x, x1 = b.upper_m.x, y0 = b.lower_m.y, y1 = b.upper_m.y,
               z0 = b.lower_m.z, z1 = b.upper_m.z;
  struct P {
    double x, y, z;
  };
  std::ostringstream s;
  s << "solid " << b.name << "\n";
  auto tri = [&](P a, P c, P d, P nrm) {
    s << "  facet normal " << n(nrm.x) << " " << n(nrm.y) << " " << n(nrm.z)
      << "\n    outer loop\n";
    for (const P& p : {a, c, d})
      s << "      vertex " << n(p.x) << " " << n(p.y) << " " << n(p.z) << "\n";
    s << "    endloop\n  endfacet\n";
  };
  auto quad = [&](P a, P c, P d, P e, P nrm) {
    tri(a, c, d, nrm);
    tri(a, d, e, nrm);
  };
  quad({x0, y0, z1}, {x1, y0, z1}, {x1, y1, z1}, {x0, y1, z1}, {0, 0, 1});   // top
  quad({x0, y0, z0}, {x0, y1, z0}, {x1, y1, z0}, {x1, y0, z0}, {0, 0, -1});  // bottom
  quad({x0, y0, z0}, {x0, y0, z1}, {x0, y1, z1}, {x0, y1, z0}, {-1, 0, 0});  // -x
  quad({x1, y0, z0}, {x1, y1, z0}, {x1, y1, z1}, {x1, y0, z1}, {1, 0, 0});   // +x
  s << "endsolid " << b.name << "\n";
  return s.str();
}

DeckResult write_liggghts_deck(const ApparatusLayout& l, const DeckOptions& o) {
  const auto mapped = map_to_liggghts(l.material, l.reduction, o.mapping);
  if (!mapped.ok()) return {std::nullopt, mapped.refusal};
  const LiggghtsMapping& m = *mapped.mapping;
  if (!l.shells.empty() || !l.discs.empty() || !l.closing_discs.empty())
    return {std::nullopt, "LIGGGHTS deck: cones, cylinders and discs (" + l.apparatus +
                              ") are not written as STL meshes yet"};
  if (!l.slanted_plates.empty())
    return {std::nullopt, "LIGGGHTS deck: the sandglass's conical (hopper) bottom (" + l.apparatus +
                              "): its slanted plates are not written as STL meshes yet; use "
                              "bottom = \"flat\""};
  if (l.lattice && l.size_classes.size() > 1)
    return {std::nullopt, "LIGGGHTS deck: the lattice fill (" + l.apparatus +
                              ") is written for one diameter; a polydisperse lattice fill is "
                              "written for LAMMPS only"};
  const std::string model = m.model_words();
  double d_max = 0.0;
  for (const auto& [d, p] : l.size_classes) d_max = std::max(d_max, d);
  // Measured with LIGGGHTS 3.8 (Debian): mesh walls in a periodic slab fail an
  // assertion (region_neighbor_list_I.h:165) at setup when the slab is 5 d
  // thick and run at 6 d (d = 1 mm, skin 0.3 d).
  const bool meshes = !l.blocks.empty() || !l.closing_blocks.empty() || !l.opened_blocks.empty();
  for (int a = 0; a < 3; ++a) {
    const double extent = a == 0   ? l.box.upper_m.x - l.box.lower_m.x
                          : a == 1 ? l.box.upper_m.y - l.box.lower_m.y
                                   : l.box.upper_m.z - l.box.lower_m.z;
    if (meshes && l.periodic[a] && extent < (kMinPeriodicMeshExtentDiameters - 1e-6) * d_max)
      return {std::nullopt,
              "LIGGGHTS 3.8 cannot run mesh walls in a periodic slab thinner than " +
                  n(kMinPeriodicMeshExtentDiameters) +
                  " diameters (this one: " + n(extent / d_max) +
                  "; its region neighbour list fails an assertion); thicken the slice "
                  "(slice_thickness_diameters)"};
  }
  Deck deck;
  deck.engine = "liggghts";

  std::ostringstream s;
  s << "# LIGGGHTS input written by demcal from its " << l.apparatus << " description ("
    << l.variant << ").\n"
    << "# Regenerated by demcal; the run record holds the parameter mapping\n"
    << "# (engines/parameter_mapping.hpp) and the layout this deck was written from.\n"
    << "# demcal contact law: normal " << l.material.contact.normal << ", tangential "
    << l.material.contact.tangential << ", rolling " << l.material.contact.rolling << "\n";
  for (const auto& a : m.approximations) s << "# approximation: " << a << "\n";
  auto pair2 = [](double a, double b) { return n(a) + " " + n(b) + " " + n(b) + " " + n(b); };
  s << "\natom_style      granular\n"
    << "boundary        " << (l.periodic[0] ? "p" : "f") << " " << (l.periodic[1] ? "p" : "f")
    << " " << (l.periodic[2] ? "p" : "f") << "\n"
    << "newton          off\n"
    << "communicate     single vel yes\n"
    << "units           si\n"
    << "region          box block " << box_words(l.box) << " units box\n"
    << "create_box      2 box\n"
    << "neighbor        " << n(o.skin_fraction_of_diameter * d_max) << " bin\n"
    << "neigh_modify    delay 0\n\n";
  // LIGGGHTS refuses a modulus above 1 GPa in SI units unless told (glass and
  // steel walls are harder than that).
  if (std::max(m.particle_youngs_modulus_pa, m.wall_youngs_modulus_pa) > 1e9)
    s << "hard_particles  yes\n";
  s << "# materials: type 1 grains, type 2 walls (mapped from demcal's, see the header)\n"
    << "fix             m1 all property/global youngsModulus peratomtype "
    << n(m.particle_youngs_modulus_pa) << " " << n(m.wall_youngs_modulus_pa) << "\n"
    << "fix             m2 all property/global poissonsRatio peratomtype "
    << n(m.particle_poisson_ratio) << " " << n(m.wall_poisson_ratio) << "\n"
    << "fix             m3 all property/global coefficientRestitution peratomtypepair 2 "
    << pair2(m.particle_particle.restitution, m.particle_wall.restitution) << "\n"
    << "fix             m4 all property/global coefficientFriction peratomtypepair 2 "
    << pair2(m.particle_particle.sliding_friction, m.particle_wall.sliding_friction) << "\n";
  if (m.rolling_model != "off")
    s << "fix             m5 all property/global coefficientRollingFriction peratomtypepair 2 "
      << pair2(m.particle_particle.rolling_friction, m.particle_wall.rolling_friction) << "\n";
  if (m.rolling_model == "epsd")
    s << "fix             m6 all property/global coefficientRollingViscousDamping peratomtypepair "
         "2 "
      << pair2(m.particle_particle.rolling_damping_ratio, m.particle_wall.rolling_damping_ratio)
      << "\n";
  s << "pair_style      gran " << m.pair_style_words() << "\n"
    << "pair_coeff      * *\n"
    << "timestep        " << n(l.time_step_s) << "\n"
    << "fix             gravity all gravity 9.81 vector 0.0 0.0 -1.0\n\n"
    << "# walls\n";
  for (const auto& p : l.planes)
    s << "fix             wall_" << p.name << " all wall/gran " << model << " primitive type 2 "
      << kAxis[p.axis] << "plane " << n(p.position_m) << "\n";
  auto mesh = [&](const SolidBlock& b) {
    deck.files.emplace_back("mesh_" + b.name + ".stl", block_stl(b));
    s << "fix             mesh_" << b.name << " all mesh/surface file mesh_" << b.name
      << ".stl type 2\n";
  };
  auto mesh_wall = [&](const std::string& name, const std::vector<const SolidBlock*>& bs) {
    if (bs.empty()) return;
    s << "fix             " << name << " all wall/gran " << model << " mesh n_meshes " << bs.size()
      << " meshes";
    for (const auto* b : bs) s << " mesh_" << b->name;
    s << "\n";
  };
  std::vector<const SolidBlock*> standing;
  for (const auto& b : l.blocks) {
    mesh(b);
    standing.push_back(&b);
  }
  std::vector<const SolidBlock*> before = standing;
  for (const auto& b : l.closing_blocks) {
    mesh(b);
    before.push_back(&b);
  }
  mesh_wall("wall_meshes", before);

  s << "\nfix             integrate all nve/sphere\n"
    << "# demcal's rest rule: rms translational speed\n"
    << "variable        speed2 atom vx*vx+vy*vy+vz*vz\n"
    << "compute         speed2_sum all reduce sum v_speed2\n"
    << "variable        n_atoms equal atoms\n"
    << "variable        rms_speed equal sqrt(c_speed2_sum/(atoms+1.0e-300))\n"
    << "thermo_style    custom step time atoms v_rms_speed cpu\n"
    << "thermo_modify   norm no lost ignore\n"
    << "thermo          " << o.thermo_every_steps << "\n";

  if (l.pour) {
    const auto& in = *l.pour;
    // LAMMPS's fix pour (and demcal's pour): a batch filling the inlet to the
    // volume fraction each time the last one has fallen clear of it. LIGGGHTS
    // 3.8 has no pour; insert/rate/region at the same mean rate, batch by batch.
    const double height = in.region.upper_m.z - in.region.lower_m.z;
    const double fall_s =
        (-in.speed_m_s + std::sqrt(in.speed_m_s * in.speed_m_s + 2.0 * 9.81 * height)) / 9.81;
    const long every = steps_for(fall_s, l.time_step_s);
    const double volume = (in.region.upper_m.x - in.region.lower_m.x) *
                          (in.region.upper_m.y - in.region.lower_m.y) * height;
    const double grain_volume = l.mean_particle_mass_kg() / l.density_kg_m3;
    const double rate = in.batch_volume_fraction * volume / grain_volume /
                        (static_cast<double>(every) * l.time_step_s);
    s << "\n# insertion: poured from the inlet, " << l.particles << " particles, a batch of "
      << n(std::round(rate * static_cast<double>(every) * l.time_step_s)) << " every " << every
      << " steps (the fall time through the inlet)\n";
    double mass_sum = 0.0;
    for (const auto& [d, p] : l.size_classes) mass_sum += p * d * d * d;
    for (std::size_t c = 0; c < l.size_classes.size(); ++c)
      s << "fix             grain" << c << " all particletemplate/sphere "
        << prime_seed(l.seed, 10 + c) << " atom_type 1 density constant " << n(l.density_kg_m3)
        << " radius constant " << n(0.5 * l.size_classes[c].first) << "\n";
    // LIGGGHTS's distribution fractions are by mass; demcal's classes by number.
    s << "fix             sizes all particledistribution/discrete " << prime_seed(l.seed, 2) << " "
      << l.size_classes.size();
    for (std::size_t c = 0; c < l.size_classes.size(); ++c) {
      const double d = l.size_classes[c].first;
      s << " grain" << c << " " << n(l.size_classes[c].second * d * d * d / mass_sum);
    }
    s << "\n"
      << "region          inlet block " << box_words(in.region) << " units box\n"
      << "fix             pour all insert/rate/region seed " << prime_seed(l.seed, 3)
      << " distributiontemplate sizes nparticles " << l.particles << " particlerate "
      << n(std::round(rate)) << " insert_every " << every
      << " overlapcheck yes all_in yes vel constant 0. 0. " << n(-in.speed_m_s)
      << " region inlet\n";
    phase_loop(s, "pour",
               "(atoms>=" + std::to_string(l.particles) + ")*(v_rms_speed<" +
                   n(l.protocol.rest_speed_m_s) + ")",
               l.discharge ? l.protocol.max_settle_s : l.protocol.max_flow_s, l);
  } else if (l.lattice) {
    const auto& f = *l.lattice;
    const std::size_t surplus = f.layers * f.sites_per_layer - f.count;
    s << "\n# insertion: jittered cubic lattice, " << f.layers << " layers of " << f.sites_per_layer
      << " sites, the top layer thinned to " << f.count << " particles\n"
      << "lattice         sc " << n(f.spacing_m) << " origin 0.5 0.5 0.5\n"
      << "region          fill block " << box_words(f.region) << " units box\n"
      << "create_atoms    1 region fill\n";
    if (surplus > 0) {
      BoxRegion topl = f.region;
      topl.lower_m.z = f.region.upper_m.z - f.spacing_m;
      s << "region          fill_top block " << box_words(topl) << " units box\n"
        << "delete_atoms    porosity fill_top "
        << n(static_cast<double>(surplus) / static_cast<double>(f.sites_per_layer)) << " "
        << prime_seed(l.seed, 4) << "\n";
    }
    s << "set             type 1 diameter " << n(l.size_classes[0].first) << "\n"
      << "set             type 1 density " << n(l.density_kg_m3) << "\n"
      << "displace_atoms  all random " << n(f.jitter_m) << " " << n(f.jitter_m) << " "
      << n(f.jitter_m) << " " << prime_seed(l.seed, 5) << " units box\n";
    phase_loop(s, "fill", "(step>0)*(v_rms_speed<" + n(l.protocol.rest_speed_m_s) + ")",
               l.protocol.max_settle_s, l);
  }

  if (l.discharge) {
    const long sample = steps_for(l.protocol.sample_interval_s, l.time_step_s);
    const long stall = steps_for(l.protocol.stall_time_s, l.time_step_s);
    const long chunks =
        std::max(1L, static_cast<long>(std::ceil(l.protocol.max_flow_s / l.protocol.stall_time_s)));
    s << "\n# --- open the orifice: the shut plate goes, the plate with the opening comes\n"
      << "unfix           wall_meshes\n";
    for (const auto& b : l.closing_blocks) s << "unfix           mesh_" << b.name << "\n";
    std::vector<const SolidBlock*> after = standing;
    for (const auto& b : l.opened_blocks) {
      mesh(b);
      after.push_back(&b);
    }
    mesh_wall("wall_meshes_open", after);
    s << "region          upper_chamber block " << box_words(l.upper_chamber) << " units box\n"
      << "variable        t_open equal time\n"
      << "variable        t_open_s equal ${t_open}\n"
      << "variable        fill_mass_all equal mass(all)\n"
      << "variable        fill_mass equal ${fill_mass_all}\n"
      << "variable        t_since_open equal time-${t_open_s}\n"
      << "variable        m_above equal mass(all,upper_chamber)\n"
      << "variable        m_discharged equal ${fill_mass}-v_m_above\n"
      << "print           \"# t_since_opening_s discharged_mass_kg mass_above_orifice_kg\" file "
      << o.mass_series_name << "\n"
      << "fix             mass_series all print " << sample
      << " \"${t_since_open} ${m_discharged} ${m_above}\" append " << o.mass_series_name
      << " screen no\n"
      << "variable        flow_chunk loop " << chunks << "\n"
      << "label           flow_loop\n"
      << "variable        m_before equal ${m_above}\n"
      << "run             " << stall << " post no\n"
      << "if              \"${m_above} <= 0 || ${m_above} == ${m_before}\" then \"jump SELF "
         "flow_end\"\n"
      << "next            flow_chunk\n"
      << "jump            SELF flow_loop\n"
      << "label           flow_end\n"
      << "unfix           mass_series\n";
    if (l.form_pile)
      phase_loop(s, "pile", "v_rms_speed<" + n(l.protocol.rest_speed_m_s), l.protocol.max_settle_s,
                 l);
  }

  s << "\n# the particles at the end, for demcal's measurement\n"
    << "dump            final all custom 1 " << o.final_dump_name
    << " id type x y z radius vx vy vz\n"
    << "dump_modify     final sort id\n"
    << "run             0\n"
    << "undump          final\n"
    << "print           \"DEMCAL_DONE atoms ${n_atoms}\"\n";

  deck.script_name = o.script_name;
  deck.script = s.str();
  deck.final_dump_name = o.final_dump_name;
  if (l.discharge) deck.mass_series_name = o.mass_series_name;
  deck.record = {{"engine", "liggghts"},
                 {"mapping", m.to_json()},
                 {"layout", l.to_json()},
                 {"measurement", l.measurement}};
  return {std::move(deck), ""};
}

namespace {
DeckResult from_layout(const LayoutResult& r, const DeckOptions& o) {
  if (!r.ok()) return {std::nullopt, "LIGGGHTS deck: " + r.refusal};
  return write_liggghts_deck(*r.layout, o);
}
}  // namespace

DeckResult write_liggghts_deck(const dem::PouredSlabPileOptions& a, const DeckOptions& o) {
  return from_layout(layout_poured_slab_pile(a), o);
}
DeckResult write_liggghts_deck(const dem::RectangularContainerOptions& a,
                               const dem::GranularMaterial& m, const dem::RunProtocol& p,
                               const DeckOptions& o) {
  return from_layout(layout_rectangular_container(a, m, p), o);
}
DeckResult write_liggghts_deck(const dem::SandglassOptions& a, const dem::GranularMaterial& m,
                               const dem::RunProtocol& p, const DeckOptions& o) {
  return from_layout(layout_sandglass(a, m, p), o);
}
DeckResult write_liggghts_deck(const dem::ConicalPileOptions& a, const dem::GranularMaterial& m,
                               const dem::RunProtocol& p, const DeckOptions& o) {
  return from_layout(layout_conical_pile(a, m, p), o);
}

}  // namespace demcal::engines
