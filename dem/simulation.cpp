#include "dem/simulation.hpp"

#include "dem/pair_scan.hpp"
#include "dem/verlet_kicks.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>

namespace demcal::dem {

struct Simulation::WallCandidates {
  std::vector<std::uint32_t> particle;  // ascending
  std::vector<ContactHistory> history;
  std::vector<std::uint8_t> touching;
};

Simulation::Simulation(SimulationOptions options)
    : options_(std::move(options)), law_(make_contact_law(options_.contact)), rng_(options_.seed) {
  options_.domain.validate();
  if (options_.threads < 1) throw std::invalid_argument("threads must be >= 1");
  if (options_.time_step_s < 0.0) throw std::invalid_argument("time_step_s must be >= 0");
  if (!(options_.time_step_fraction_of_rayleigh > 0.0 &&
        options_.time_step_fraction_of_rayleigh <= 1.0))
    throw std::invalid_argument("time_step_fraction_of_rayleigh must lie in (0, 1]");
  if (!(options_.skin_fraction_of_diameter > 0.0))
    throw std::invalid_argument("skin_fraction_of_diameter must be > 0");
  if (norm2(options_.gravity_m_s2) > 0.0)
    body_forces_.push_back(std::make_unique<Gravity>(options_.gravity_m_s2));
}

Simulation::~Simulation() = default;

int Simulation::add_material(const Material& material) {
  if (prepared_) throw std::logic_error("add_material after the first step");
  material.validate();
  for (const auto& m : materials_)
    if (m.name == material.name)
      throw std::invalid_argument("material '" + material.name + "' is defined twice");
  materials_.push_back(material);
  const std::size_t n = materials_.size();
  std::vector<std::optional<InteractionParameters>> grown(n * n);
  for (std::size_t a = 0; a + 1 < n; ++a)
    for (std::size_t b = 0; b + 1 < n; ++b) grown[a * n + b] = interactions_[a * (n - 1) + b];
  interactions_ = std::move(grown);
  return static_cast<int>(n - 1);
}

int Simulation::material_index(const std::string& name) const {
  for (std::size_t i = 0; i < materials_.size(); ++i)
    if (materials_[i].name == name) return static_cast<int>(i);
  std::string known;
  for (const auto& m : materials_) known += (known.empty() ? "'" : ", '") + m.name + "'";
  throw std::invalid_argument("unknown material '" + name + "'; defined: " + known);
}

void Simulation::set_interaction(int a, int b, const InteractionParameters& params) {
  const int n = static_cast<int>(materials_.size());
  if (a < 0 || b < 0 || a >= n || b >= n) throw std::out_of_range("interaction: material index");
  params.validate("interaction " + materials_[a].name + "-" + materials_[b].name + ": ");
  interactions_[a * n + b] = params;
  interactions_[b * n + a] = params;
}

int Simulation::add_wall(std::unique_ptr<Wall> wall, int material) {
  if (material < 0 || material >= static_cast<int>(materials_.size()))
    throw std::out_of_range("wall material index");
  walls_.push_back(std::move(wall));
  wall_material_.push_back(material);
  rebuild_requested_ = true;
  return static_cast<int>(walls_.size() - 1);
}

void Simulation::add_inserter(std::unique_ptr<Inserter> inserter) {
  if (inserter->material() < 0 || inserter->material() >= static_cast<int>(materials_.size()))
    throw std::out_of_range("inserter material index");
  inserters_.push_back(std::move(inserter));
}

void Simulation::add_body_force(std::unique_ptr<BodyForce> force) {
  body_forces_.push_back(std::move(force));
}

std::size_t Simulation::add_particle(const Vec3& position, double radius, int material,
                                     const Vec3& velocity, const Vec3& omega) {
  if (material < 0 || material >= static_cast<int>(materials_.size()))
    throw std::out_of_range("particle material index");
  if (!(radius > 0.0)) throw std::invalid_argument("particle radius must be > 0");
  const std::size_t i = particles_.add(position, radius, materials_[material].density_kg_m3,
                                       material, next_id_++, velocity, omega);
  // Until the next force evaluation the new particle feels its body forces only.
  for (const auto& bf : body_forces_)
    bf->add(particles_, i, i + 1, particles_.force_n, particles_.torque_nm);
  rebuild_requested_ = true;
  return i;
}

bool Simulation::insertion_finished() const {
  for (const auto& ins : inserters_)
    if (!ins->finished()) return false;
  return true;
}

double Simulation::time_step_s() {
  if (!prepared_) prepare();
  return dt_;
}

void Simulation::prepare() {
  if (prepared_) return;
  const int nm = static_cast<int>(materials_.size());
  // Which materials can meet: particle materials with each other and with wall materials.
  std::set<int> particle_materials(particles_.material.begin(), particles_.material.end());
  for (const auto& ins : inserters_) particle_materials.insert(ins->material());
  std::set<int> wall_materials(wall_material_.begin(), wall_material_.end());
  auto require = [&](int a, int b) {
    if (!interactions_[a * nm + b])
      throw std::invalid_argument("no interaction given for materials '" + materials_[a].name +
                                  "' and '" + materials_[b].name + "'");
  };
  for (int a : particle_materials) {
    for (int b : particle_materials) require(a, b);
    for (int b : wall_materials) require(a, b);
  }
  coefficients_.assign(static_cast<std::size_t>(nm * nm), PairCoefficients{});
  for (int a = 0; a < nm; ++a)
    for (int b = a; b < nm; ++b)
      if (interactions_[a * nm + b]) {
        const auto c = resolve_pair(materials_[a], materials_[b], *interactions_[a * nm + b],
                                    options_.restitution_model);
        coefficients_[a * nm + b] = c;
        coefficients_[b * nm + a] = c;
      }

  double r_min = std::numeric_limits<double>::infinity();
  double r_max = 0.0;
  double t_rayleigh = std::numeric_limits<double>::infinity();
  auto consider = [&](double r, int material) {
    r_min = std::min(r_min, r);
    r_max = std::max(r_max, r);
    t_rayleigh = std::min(t_rayleigh, rayleigh_time_s(materials_[material], r));
  };
  for (std::size_t i = 0; i < particles_.size(); ++i)
    consider(particles_.radius_m[i], particles_.material[i]);
  for (const auto& ins : inserters_) {
    consider(0.5 * ins->sizes().min_diameter_m(), ins->material());
    consider(0.5 * ins->sizes().max_diameter_m(), ins->material());
  }
  if (r_max == 0.0) throw std::invalid_argument("the simulation has no particles and no inserter");
  dt_ = options_.time_step_s > 0.0 ? options_.time_step_s
                                   : options_.time_step_fraction_of_rayleigh * t_rayleigh;
  skin_m_ = options_.skin_fraction_of_diameter * 2.0 * r_max;
  check_hold_range(particle_materials, wall_materials, r_max);
  max_speed_m_s_ = options_.max_speed_m_s;
  if (max_speed_m_s_ <= 0.0) {
    const Vec3 len = options_.domain.length_m();
    const double extent = std::max({len.x, len.y, len.z});
    const double g = std::max(norm(options_.gravity_m_s2), 1.0);
    max_speed_m_s_ = 10.0 * std::sqrt(2.0 * g * extent) + 10.0;
  }
  for (const auto& w : walls_) {
    const auto times = w->change_times_s();
    wall_change_times_.insert(wall_change_times_.end(), times.begin(), times.end());
  }
  std::sort(wall_change_times_.begin(), wall_change_times_.end());
  wall_loads_.assign(walls_.size(), WallLoad{});
  wall_candidates_.resize(walls_.size());
  team_ = std::make_unique<ThreadTeam>(options_.threads, options_.worker_parking,
                                       options_.worker_parking_options);
  chunk_scratch_.assign(static_cast<std::size_t>(options_.threads), ChunkScratch{});
  contact_batches_.resize(static_cast<std::size_t>(options_.threads));
  wall_contact_batches_.resize(static_cast<std::size_t>(options_.threads));
  thread_force_.resize(options_.threads);
  thread_torque_.resize(options_.threads);
  thread_wall_loads_.resize(options_.threads);
  prepared_ = true;
  run_inserters();
  rebuild_neighbors();
  compute_forces();
}

// A contact held beyond touching must stay in the Verlet list: the list keeps
// pairs closer than the skin at each build, so the largest gap at which a part
// holds a contact must be below it. The gap grows with R*, so the largest
// particles bound it: R* = r_max / 2 between two of them, r_max against a wall.
void Simulation::check_hold_range(const std::set<int>& particle_materials,
                                  const std::set<int>& wall_materials, double r_max) {
  hold_range_m_ = 0.0;
  with_contact_kernel(law_, [&](const auto& kernel) {
    if constexpr (std::decay_t<decltype(kernel)>::kHoldsBeyondTouching) {
      const int nm = static_cast<int>(materials_.size());
      auto check = [&](int a, int b, double radius_eff_m) {
        const double gap = kernel.max_separation_m(coefficients_[a * nm + b], radius_eff_m);
        if (gap >= skin_m_) {
          std::ostringstream msg;
          msg << "materials '" << materials_[a].name << "' and '" << materials_[b].name
              << "': the contact law holds a touching contact up to a gap of " << gap
              << " m (its critical separation at the largest particles), which the Verlet skin of "
              << skin_m_ << " m does not cover; raise skin_fraction_of_diameter above "
              << gap / (2.0 * r_max) << " (it is " << options_.skin_fraction_of_diameter << ")";
          throw std::invalid_argument(msg.str());
        }
        hold_range_m_ = std::max(hold_range_m_, gap);
      };
      for (int a : particle_materials) {
        for (int b : particle_materials) check(a, b, 0.5 * r_max);
        for (int b : wall_materials) check(a, b, r_max);
      }
    }
  });
}

void Simulation::run_inserters() {
  // Asked every step; almost always nothing is due, so nothing is built then.
  bool any_due = false;
  for (const auto& ins : inserters_) any_due = any_due || ins->due(time_s_);
  if (!any_due) return;
  std::vector<const Wall*> walls;
  for (const auto& w : walls_) walls.push_back(w.get());
  for (auto& ins : inserters_) {
    if (!ins->due(time_s_)) continue;
    const double r_max = 0.5 * ins->sizes().max_diameter_m();
    InsertionContext ctx(
        time_s_, options_.domain, particles_, walls, rng_, ins->region().lower_m(),
        ins->region().upper_m(), r_max,
        [this](const Vec3& c, double r, int m, const Vec3& v) { add_particle(c, r, m, v); });
    ins->insert(ctx);
  }
}

void Simulation::rebuild_neighbors() {
  const Domain& dom = options_.domain;
  const Vec3 len = dom.length_m();
  auto& x = particles_.position_m;
  for (int k = 0; k < 3; ++k) {
    if (!dom.periodic[k]) continue;
    for (auto& p : x) p[k] -= len[k] * std::floor((p[k] - dom.lower_m[k]) / len[k]);
  }
  if (options_.particle_order == ParticleOrder::kSpatial) reorder_particles();
  neighbors_.build(x, particles_.radius_m, dom, skin_m_, team_.get());

  // Wall candidates: particles within skin of each wall; history follows the particle.
  wall_offset_at_build_.resize(walls_.size());
  for (std::size_t w = 0; w < walls_.size(); ++w) {
    WallCandidates next;
    const WallCandidates& prev = wall_candidates_[w];
    std::size_t q = 0;
    for (std::size_t i = 0; i < particles_.size(); ++i) {
      WallContactPoint cp;
      if (!walls_[w]->nearest_point(x[i], particles_.radius_m[i] + skin_m_, time_s_, cp)) continue;
      next.particle.push_back(static_cast<std::uint32_t>(i));
      while (q < prev.particle.size() && prev.particle[q] < i) ++q;
      if (q < prev.particle.size() && prev.particle[q] == i && prev.touching[q]) {
        next.history.push_back(prev.history[q]);
        next.touching.push_back(1);
      } else {
        next.history.push_back({});
        next.touching.push_back(0);
      }
    }
    wall_candidates_[w] = std::move(next);
    wall_offset_at_build_[w] = walls_[w]->motion().displacement_m(time_s_);
  }
  rebuild_requested_ = false;
  split_ownership();
}

void Simulation::reorder_particles() {
  const std::size_t n = particles_.size();
  if (n < 2) return;
  double r_max = 0.0;
  for (double r : particles_.radius_m) r_max = std::max(r_max, r);
  // The neighbour grid's cell: a particle's partners are in its own or an adjacent cell.
  const std::vector<std::uint32_t> order =
      spatial_order(particles_.position_m, options_.domain, 2.0 * r_max + skin_m_);
  std::vector<std::uint32_t> new_index(n);
  bool identity = true;
  for (std::size_t k = 0; k < n; ++k) {
    new_index[order[k]] = static_cast<std::uint32_t>(k);
    identity = identity && order[k] == k;
  }
  if (identity) return;
  particles_.permute(order);
  // The drift stored the last step's forces to undo the velocity prediction
  // (the reorder falls between drift and the new forces): they move too.
  for (std::vector<Vec3>* before : {&force_before_, &torque_before_}) {
    if (before->size() != n) continue;
    std::vector<Vec3> moved(n);
    for (std::size_t k = 0; k < n; ++k) moved[k] = (*before)[order[k]];
    before->swap(moved);
  }
  neighbors_.renumber(new_index);
  // Wall contact histories follow their particle; candidates stay ascending.
  for (WallCandidates& cand : wall_candidates_) {
    std::vector<std::size_t> by_new(cand.particle.size());
    for (std::size_t c = 0; c < by_new.size(); ++c) by_new[c] = c;
    std::sort(by_new.begin(), by_new.end(), [&](std::size_t a, std::size_t b) {
      return new_index[cand.particle[a]] < new_index[cand.particle[b]];
    });
    WallCandidates moved;
    moved.particle.reserve(by_new.size());
    moved.history.reserve(by_new.size());
    moved.touching.reserve(by_new.size());
    for (std::size_t c : by_new) {
      moved.particle.push_back(new_index[cand.particle[c]]);
      moved.history.push_back(cand.history[c]);
      moved.touching.push_back(cand.touching[c]);
    }
    cand = std::move(moved);
  }
}

void Simulation::split_ownership() {
  const int chunks = team_->size();
  const std::size_t n = particles_.size();
  owner_begin_.assign(static_cast<std::size_t>(chunks) + 1, n);
  owner_begin_[0] = 0;
  window_end_.assign(static_cast<std::size_t>(chunks), n);
  if (chunks == 1) return;
  // Each chunk gets an equal share of the force run's cost, estimated per
  // particle in units of one listed pair's distance test: each listed pair 1,
  // each of them in contact 3 more (copy into the batch, the law, adding the
  // forces), each wall candidate 2 (its nearest point), each wall contact 8
  // more (the law one contact at a time), the particle itself 1. The weights
  // are the quick Sandglass's profile (BENCHMARKS.md, 2026-12-05 (night));
  // counting pairs alone put a pile's floor contacts, all in the lowest
  // particles, on one chunk. The contacts are the last step's (the flags the
  // build carried over): state, not timing, so a run still repeats bit for
  // bit at a given thread count.
  std::vector<double>& prefix = ownership_cost_prefix_;
  prefix.assign(n + 1, 0.0);
  {
    const NeighborList::Arrays list = neighbors_.arrays();
    for (std::size_t i = 0; i < n; ++i) {
      double w = 1.0;
      for (std::uint32_t p = list.first[i]; p < list.first[i + 1]; ++p)
        w += list.touching[p] ? 4.0 : 1.0;
      prefix[i + 1] = w;
    }
    for (const WallCandidates& cand : wall_candidates_)
      for (std::size_t c = 0; c < cand.particle.size(); ++c)
        prefix[cand.particle[c] + 1] += cand.touching[c] ? 10.0 : 2.0;
    for (std::size_t i = 0; i < n; ++i) prefix[i + 1] += prefix[i];
  }
  auto cost = [&](std::size_t i) { return prefix[i]; };
  const double total = cost(n);
  std::size_t lo = 0;
  for (int m = 1; m < chunks; ++m) {
    const double target = total * m / chunks;
    std::size_t a = lo, b = n;
    while (a < b) {
      const std::size_t mid = a + (b - a) / 2;
      if (cost(mid) < target)
        a = mid + 1;
      else
        b = mid;
    }
    owner_begin_[static_cast<std::size_t>(m)] = a;
    lo = a;
  }
  for (int m = 0; m < chunks; ++m) {
    std::size_t end = owner_begin_[static_cast<std::size_t>(m) + 1];
    for (std::size_t i = owner_begin_[static_cast<std::size_t>(m)];
         i < owner_begin_[static_cast<std::size_t>(m) + 1]; ++i)
      for (std::uint32_t p = neighbors_.first(i); p < neighbors_.first(i + 1); ++p)
        end = std::max<std::size_t>(end, neighbors_.partner(p) + 1);
    window_end_[static_cast<std::size_t>(m)] = end;
  }
}

std::size_t Simulation::slice_begin(int m) const {
  // The kicks give chunk m the particles it owns in the force run while that
  // split is current (no particle was added since the build): the core that
  // moves a particle is then the one that reads it next, and positions and
  // velocities need not travel between the cores' caches at every step.
  // Which chunk updates a particle changes no result.
  const std::size_t n = particles_.size();
  if (owner_begin_.size() == static_cast<std::size_t>(team_->size()) + 1 &&
      owner_begin_.back() == n)
    return owner_begin_[static_cast<std::size_t>(m)];
  return ThreadTeam::split(n, team_->size(), m);
}

void Simulation::step() {
  if (!prepared_) prepare();
  const std::size_t before = particles_.size();
  run_inserters();
  if (particles_.size() != before) rebuild_requested_ = true;

  const std::size_t n = particles_.size();
  auto& x = particles_.position_m;
  auto& v = particles_.velocity_m_s;
  auto& w = particles_.omega_rad_s;
  const auto& f = particles_.force_n;
  const auto& t = particles_.torque_nm;
  const auto& im = particles_.inv_mass_kg;
  const auto& ii = particles_.inv_inertia_kg_m2;
  // Velocity Verlet: half kick, drift, forces, half kick. The forces depend on
  // velocity (damping, the tangential spring's increment), and evaluating them
  // with the half-step velocity, as plain Verlet does, makes the restitution of
  // a strongly damped contact wrong to first order in dt (-13 % at e = 0.1 with
  // the default step). So they are evaluated with the full-step velocity
  // predicted from the last force, and the second kick corrects the prediction:
  // positions, and velocities in conservative systems, are plain Verlet's.
  // Each parallel region is a fork and a join; the displacement check for the
  // Verlet list rides along in the drift's team run (dem/verlet_kicks.hpp).
  // The kick needs the last step's force and torque after the new ones are
  // computed: the buffers are swapped rather than copied (compute_forces()
  // writes every particle's force and torque).
  force_before_.resize(n);
  torque_before_.resize(n);
  const auto& x_build = neighbors_.positions_at_build();
  const Vec3* const x_build_or_null = x_build.size() == n ? x_build.data() : nullptr;
  const bool comparable = x_build_or_null != nullptr;
  const int chunks = team_->size();
  const KickArrays before_build{x.data(), v.data(), w.data(), im.data(), ii.data()};
  const double half_skin = 0.5 * neighbors_.skin_m();
  team_->run([&](int m) {
    chunk_scratch_[m].moved_beyond_half_skin =
        kick_and_drift(before_build, f.data(), t.data(), x_build_or_null, half_skin, slice_begin(m),
                       slice_begin(m + 1), dt_);
  });
  particles_.force_n.swap(force_before_);
  particles_.torque_nm.swap(torque_before_);
  bool rebuild = rebuild_requested_ || !comparable;
  for (int m = 0; m < chunks; ++m) rebuild = rebuild || chunk_scratch_[m].moved_beyond_half_skin;
  time_s_ += dt_;

  for (std::size_t k = 0; k < walls_.size() && !rebuild; ++k)
    if (walls_[k]->motion().moves() && norm(walls_[k]->motion().displacement_m(time_s_) -
                                            wall_offset_at_build_[k]) > 0.5 * skin_m_)
      rebuild = true;
  while (!wall_change_times_.empty() && wall_change_times_.front() <= time_s_) {
    wall_change_times_.erase(wall_change_times_.begin());
    rebuild = true;
  }
  if (rebuild) rebuild_neighbors();

  // Forces, then the second kick and the stability check on the same pass
  // over the particles, inside the force computation's team run.
  const Domain& dom = options_.domain;
  StabilityBounds bounds;
  for (int k = 0; k < 3; ++k) {
    bounds.lower_m[k] = dom.periodic[k] ? -DBL_MAX : dom.lower_m[k];
    bounds.upper_m[k] = dom.periodic[k] ? DBL_MAX : dom.upper_m[k];
  }
  bounds.max_speed2_m2_s2 = max_speed_m_s_ * max_speed_m_s_;
  // A build may have reordered the particles: their arrays are new.
  const KickArrays arrays{x.data(), v.data(), w.data(), im.data(), ii.data()};
  compute_forces([&](std::size_t begin, std::size_t end) {
    return correct_and_check(arrays, f.data(), force_before_.data(), t.data(),
                             torque_before_.data(), begin, end, dt_, bounds, n);
  });
  std::size_t first_bad = n;
  for (int m = 0; m < chunks; ++m) first_bad = std::min(first_bad, chunk_scratch_[m].first_bad);
  ++steps_;
  particle_steps_ += static_cast<double>(n);
  if (first_bad < n) report_instability(first_bad);
}

void Simulation::run_steps(std::int64_t steps) {
  for (std::int64_t s = 0; s < steps; ++s) step();
}

void Simulation::run_until(double time_s) {
  if (!prepared_) prepare();
  // Half a step of tolerance so that run_until(k * dt) takes exactly k steps.
  while (time_s_ + 0.5 * dt_ < time_s) step();
}

void Simulation::report_instability(std::size_t i) const {
  const auto& x = particles_.position_m;
  const auto& v = particles_.velocity_m_s;
  const Domain& dom = options_.domain;
  const double vmax2 = max_speed_m_s_ * max_speed_m_s_;
  std::ostringstream msg;
  msg << "unstable run at t = " << time_s_ << " s (step " << steps_ << "): particle id "
      << particles_.id[i] << " ";
  if (!is_finite(x[i]) || !is_finite(v[i])) {
    msg << "has a non-finite position or velocity (NaN). ";
  } else if (norm2(v[i]) > vmax2) {
    msg << "moves at " << norm(v[i]) << " m/s, above the limit " << max_speed_m_s_
        << " m/s (kinetic energy blow-up). ";
  } else {
    msg << "left the domain at (" << x[i].x << ", " << x[i].y << ", " << x[i].z
        << ") m; the box is [" << dom.lower_m.x << ", " << dom.lower_m.y << ", " << dom.lower_m.z
        << "] - [" << dom.upper_m.x << ", " << dom.upper_m.y << ", " << dom.upper_m.z
        << "] m. A wall is missing or was passed through. ";
  }
  msg << "The time step is " << dt_
      << " s; if the contacts are under-resolved, lower time_step_fraction_of_rayleigh (or "
         "time_step_s); if a particle escaped, check that the walls close the box.";
  throw InstabilityError(msg.str());
}

template <class Finish>
void Simulation::compute_forces(Finish&& finish) {
  with_contact_kernel(law_, [&](const auto& kernel) { compute_contact_forces(kernel, finish); });
}

void Simulation::compute_forces() {
  compute_forces([n = particles_.size()](std::size_t, std::size_t) { return n; });
}

template <class Kernel, class Finish>
void Simulation::compute_contact_forces(const Kernel& kernel, Finish& finish) {
  const std::size_t n = particles_.size();
  const int chunks = team_->size();
  const auto& x = particles_.position_m;
  const auto& v = particles_.velocity_m_s;
  const auto& om = particles_.omega_rad_s;
  const auto& rad = particles_.radius_m;
  const auto& mass = particles_.mass_kg;
  const auto& im = particles_.inv_mass_kg;
  const auto& ii = particles_.inv_inertia_kg_m2;
  const auto& mat = particles_.material;
  const int nm = static_cast<int>(materials_.size());
  const double dt = dt_;
  const double now = time_s_;
  const std::size_t nwalls = walls_.size();
  if (chunks > 1) {
    for (int m = 0; m < chunks; ++m) {
      thread_force_[m].resize(n);
      thread_torque_[m].resize(n);
    }
  }
  for (auto& l : thread_wall_loads_) l.assign(nwalls, WallLoad{});
  // Decided by the bed's size, not by timing: a run repeats bit for bit
  // whatever the choice (a prefetch changes no value).
  const bool prefetch = worth_prefetching(n, neighbors_.pair_count());

  team_->run([&](int m) {
    // Chunk m owns the particles [own_begin, own_end): their pairs with
    // higher-indexed partners and their wall contacts. What it adds to its
    // own particles goes straight into the particle arrays (no other chunk
    // writes there); what it adds to partners beyond its range, which
    // follow their owner in the list's order up to window_end_[m], goes into
    // its buffer, summed in after every chunk is done (below). With one chunk
    // every partner is its own.
    const std::size_t own_begin = owner_begin_[m], own_end = owner_begin_[m + 1];
    const std::size_t beyond_end = std::max(window_end_[m], own_end);
    Vec3* const force_own = particles_.force_n.data();
    Vec3* const torque_own = particles_.torque_nm.data();
    std::fill(force_own + own_begin, force_own + own_end, Vec3{});
    std::fill(torque_own + own_begin, torque_own + own_end, Vec3{});
    Vec3* force_beyond = force_own;
    Vec3* torque_beyond = torque_own;
    if (chunks > 1) {
      force_beyond = thread_force_[m].data();
      torque_beyond = thread_torque_[m].data();
      std::fill(force_beyond + own_end, force_beyond + beyond_end, Vec3{});
      std::fill(torque_beyond + own_end, torque_beyond + beyond_end, Vec3{});
    }
    std::vector<WallLoad>& my_loads = thread_wall_loads_[m];
    double elastic = 0.0;
    std::size_t contacts = 0;

    // The pair loop reads raw arrays held in registers: it stores a byte per
    // pair (the touching flag), and through the vectors every data pointer
    // would be reloaded from memory at every pair (a byte may alias anything).
    const NeighborList::Arrays list = neighbors_.arrays();
    const Vec3* const xp = x.data();
    const Vec3* const vp = v.data();
    const Vec3* const wp = om.data();
    const double* const rp = rad.data();
    const double* const mp = mass.data();
    const double* const imp = im.data();
    const double* const iip = ii.data();
    const int* const matp = mat.data();
    const PairCoefficients* const coef = coefficients_.data();
    // Contacts are evaluated a batch at a time (dem/contact_batch.hpp) and
    // added to the particles in the order they were found.
    const ParticleArrays pa{xp, vp, wp, rp, mp, imp, iip, matp};
    const ListedPairs listed{list.partner, list.shift_code, list.shift_table, list.history};
    const PartnerForceTargets targets{force_own, torque_own, force_beyond, torque_beyond, own_end};
    const PartnerForceTargets* const prefetch_for = prefetch ? &targets : nullptr;
    ContactBatch& batch = contact_batches_[static_cast<std::size_t>(m)];
    batch.size = 0;
    auto flush = [&] {
      batch.gather(pa, listed, nm);
      evaluate(kernel, batch, coef, dt);
      for (int l = 0; l < batch.size; ++l) {
        const auto i = static_cast<std::size_t>(batch.i[l]);
        const auto j = static_cast<std::size_t>(batch.j[l]);
        list.history[batch.pair[l]] = batch.history(l);
        const Vec3 fi = batch.force_on_i(l);
        force_own[i] += fi;
        *targets.force_n(j) -= fi;
        torque_own[i] += batch.torque_on_i(l);
        *targets.torque_nm(j) += batch.torque_on_j(l);
        elastic += batch.energy_j[l];
      }
      contacts += static_cast<std::size_t>(batch.size);
      batch.size = 0;
    };
    if constexpr (!Kernel::kHoldsBeyondTouching) {
      PairScanCursor cursor{own_begin, own_begin < own_end ? list.first[own_begin] : 0};
      for (;;) {
        stage_touching_pairs(list, xp, rp, own_end, cursor, batch, prefetch_for);
        if (!batch.full()) break;
        flush();
      }
      flush();
    } else {
      int taken = 0;  // batch.size, kept out of memory in the loop
      for (std::size_t i = own_begin; i < own_end; ++i) {
        const Vec3 xi = xp[i];
        const double ri = rp[i];
        const std::uint32_t end = list.first[i + 1];
        for (std::uint32_t p = list.first[i]; p < end; ++p) {
          const std::uint32_t j = list.partner[p];
          const Vec3 d = xi - (xp[j] + list.shift_table[list.shift_code[p]]);
          const double rsum = ri + rp[j];
          const double dist2 = norm2(d);
          // As in stage_touching_pairs (dem/pair_scan.hpp); then a part of
          // the law may still hold a contact that touched (adhesion).
          bool on = !(dist2 >= rsum * rsum);
          if (!on && list.touching[p])
            on = kernel.holds(coef[matp[i] * nm + matp[j]], ri * rp[j] / rsum,
                              rsum - std::sqrt(dist2));
          batch.stage(taken, static_cast<std::uint32_t>(i), p, list.touching[p] != 0);
          if (prefetch) prefetch_for_flush(list, p, j, targets);
          list.touching[p] = on ? 1 : 0;
          taken += on ? 1 : 0;
          if (taken == ContactBatch::kCapacity) {
            batch.size = taken;
            flush();
            taken = 0;
          }
        }
      }
      batch.size = taken;
      flush();
    }

    // Wall contacts: found one candidate at a time (the nearest point is a
    // virtual call), evaluated a batch at a time (dem/wall_contact_batch.hpp),
    // added in the order they were found.
    WallContactBatch& wall_batch = wall_contact_batches_[static_cast<std::size_t>(m)];
    for (std::size_t wi = 0; wi < nwalls; ++wi) {
      const Wall& wall = *walls_[wi];
      WallCandidates& cand = wall_candidates_[wi];
      const Vec3 wall_velocity = wall.velocity_at(now);
      const Vec3 ref = wall.reference_point(now);
      const int mw = wall_material_[wi];
      // Summed here and stored once: the chunks' load buffers are small
      // vectors that may share a cache line.
      WallLoad load;
      auto flush_wall = [&] {
        WallContactBatch& b = wall_batch;
        b.gather(pa, wall_velocity, nm, mw, cand.history.data());
        evaluate_walls(kernel, b, coef, dt);
        for (int l = 0; l < b.size; ++l) {
          const std::uint32_t i = b.i[l];
          cand.history[b.candidate[l]] = b.history(l);
          const Vec3 fi = b.force_on_i(l);
          force_own[i] += fi;
          torque_own[i] += b.torque_on_i(l);
          load.force_n -= fi;
          load.torque_nm += cross(b.point(l) - ref, -fi) - b.law_torque_on_i(l);
          elastic += b.energy_j[l];
        }
        load.contacts += static_cast<std::size_t>(b.size);
        contacts += static_cast<std::size_t>(b.size);
        b.size = 0;
      };
      wall_batch.size = 0;
      // The candidates of this chunk's particles (candidates are ascending).
      const auto c_begin = static_cast<std::size_t>(
          std::lower_bound(cand.particle.begin(), cand.particle.end(), own_begin) -
          cand.particle.begin());
      const auto c_end = static_cast<std::size_t>(
          std::lower_bound(cand.particle.begin(), cand.particle.end(), own_end) -
          cand.particle.begin());
      for (std::size_t c = c_begin; c < c_end; ++c) {
        const std::uint32_t i = cand.particle[c];
        WallContactPoint cp;
        bool on;
        if constexpr (Kernel::kHoldsBeyondTouching) {
          // A contact that touched is looked for up to the hold range and kept while held.
          const bool touched = cand.touching[c] != 0;
          on = wall.nearest_point(x[i], touched ? rad[i] + hold_range_m_ : rad[i], now, cp);
          if (on && cp.distance_m >= rad[i])
            on = touched &&
                 kernel.holds(coefficients_[mat[i] * nm + mw], rad[i], rad[i] - cp.distance_m);
        } else {
          on = wall.nearest_point(x[i], rad[i], now, cp) && cp.distance_m < rad[i];
        }
        if (!on) {
          if (cand.touching[c]) {
            cand.touching[c] = 0;
            cand.history[c] = ContactHistory{};
          }
          continue;
        }
        cand.touching[c] = 1;
        wall_batch.stage(static_cast<std::uint32_t>(c), i, cp.normal, cp.distance_m, cp.point_m);
        if (wall_batch.full()) flush_wall();
      }
      flush_wall();
      my_loads[wi] = load;
    }
    ChunkScratch& scratch = chunk_scratch_[m];
    scratch.elastic_j = elastic;
    scratch.contacts = contacts;
  });

  // Every chunk's contributions are in; each chunk now finishes a slice of the
  // particles: the earlier chunks' buffered contributions to a particle, in
  // chunk order, then its owner's own (so a run repeats bit for bit at a
  // given thread count, parked or not), the body forces, and what the caller
  // does with the new forces (the second kick). Only the particles some
  // earlier chunk reached are visited: a narrow band after each chunk's range.
  team_->run([&](int m) {
    const std::size_t begin = slice_begin(m), end = slice_begin(m + 1);
    for (int q = 0; q + 1 < chunks; ++q) {
      // The band chunk q buffered, [own end, window end), within this slice;
      // a particle there that an even earlier chunk reached too was summed
      // with that chunk's band (the bands are visited in chunk order).
      const std::size_t band_begin = std::max(begin, owner_begin_[q + 1]);
      const std::size_t band_end = std::min(end, window_end_[q]);
      for (std::size_t i = band_begin; i < band_end; ++i) {
        bool earlier = false;
        for (int e = 0; e < q; ++e)
          earlier = earlier || (i >= owner_begin_[e + 1] && i < window_end_[e]);
        if (earlier) continue;
        Vec3 fs = thread_force_[q][i], ts = thread_torque_[q][i];
        for (int r = q + 1; r + 1 < chunks && owner_begin_[r + 1] <= i; ++r) {
          if (i >= window_end_[r]) continue;
          fs += thread_force_[r][i];
          ts += thread_torque_[r][i];
        }
        particles_.force_n[i] = fs + particles_.force_n[i];
        particles_.torque_nm[i] = ts + particles_.torque_nm[i];
      }
    }
    for (const auto& bf : body_forces_)
      bf->add(particles_, begin, end, particles_.force_n, particles_.torque_nm);
    chunk_scratch_[m].first_bad = finish(begin, end);
  });

  double elastic = 0.0;
  std::size_t contacts = 0;
  for (int m = 0; m < chunks; ++m) {
    elastic += chunk_scratch_[m].elastic_j;
    contacts += chunk_scratch_[m].contacts;
  }
  for (std::size_t w = 0; w < nwalls; ++w) {
    WallLoad total;
    for (int m = 0; m < chunks; ++m) {
      total.force_n += thread_wall_loads_[m][w].force_n;
      total.torque_nm += thread_wall_loads_[m][w].torque_nm;
      total.contacts += thread_wall_loads_[m][w].contacts;
    }
    wall_loads_[w] = total;
  }
  elastic_energy_j_ = elastic;
  contacts_ = contacts;
}

EnergyBudget Simulation::energy() const {
  EnergyBudget e;
  const auto& p = particles_;
  for (std::size_t i = 0; i < p.size(); ++i) {
    e.translational_j += 0.5 * p.mass_kg[i] * norm2(p.velocity_m_s[i]);
    e.rotational_j += 0.5 / p.inv_inertia_kg_m2[i] * norm2(p.omega_rad_s[i]);
  }
  for (const auto& bf : body_forces_) e.potential_j += bf->potential_energy_j(p);
  e.elastic_j = elastic_energy_j_;
  return e;
}

double Simulation::kinetic_energy_j() const {
  const EnergyBudget e = energy();
  return e.translational_j + e.rotational_j;
}

double Simulation::rms_speed_m_s() const {
  const auto& p = particles_;
  if (p.empty()) return 0.0;
  double s = 0.0;
  for (const auto& vi : p.velocity_m_s) s += norm2(vi);
  return std::sqrt(s / static_cast<double>(p.size()));
}

}  // namespace demcal::dem
