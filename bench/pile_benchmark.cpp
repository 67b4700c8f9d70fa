// Throughput of the engine on the peer case ../shared/peers/lammps/pile.in: the
// poured quasi-2D pile (make_poured_slab_pile), measured the way the peer's
// tools measure LAMMPS, so the two figures can be put side by side as a ratio.
//
//   --mode pour    the whole run, pouring until at rest (rms speed < 2e-3 m/s,
//                  checked every 1000 steps like LAMMPS's fix halt 1000);
//                  particle-steps integrated over the run / loop wall time.
//   --mode static  pour and settle first (reported as the pour figure, not part
//                  of the static one), 500 warm-up steps (as bench_static.in's
//                  "run 500"), then time --static-steps steps at fixed N.
//   --tile-y K     (static mode) the larger case: the settled pile is copied K
//                  times across the periodic slab thickness into a K times
//                  thicker slab, with positions and velocities only (no spin,
//                  no contact history), as LAMMPS's read_dump of the peer's
//                  tiled dump builds it (bench/run_side_by_side.sh, tile cases).
//
// Prints one machine-readable line per figure (pour; in static mode also static)
//   BENCH demcal mode pour threads 1 N 6000 steps ... particle_steps ... loop_s ...
//         PS/s ... PS/s/core ... maxRSS_MiB ...
// and one AOR line computed like ../shared/peers/tools/aor.py (a port of it; with
// --dump FILE the final pile is also written as "x z radius" for aor.py itself).
#include "dem/apparatus/poured_slab_pile.hpp"

#include <CLI/CLI.hpp>
#include <omp.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "demcal_version.hpp"  // DEMCAL_VERSION, written at build time (cmake/version.cmake)

namespace {

using demcal::dem::Particles;

double peak_rss_mib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

// Least-squares slope of h against x over the bins with lo*hmax <= h <= hi*hmax
// (np.polyfit(x, h, 1)[0]); NaN with fewer than three bins, as aor.py.
double fit_side_deg(const std::vector<double>& xc, const std::vector<double>& h, std::size_t from,
                    std::size_t to, double hmax, double lo, double hi) {
  double sx = 0, sy = 0, n = 0;
  for (std::size_t b = from; b < to; ++b)
    if (h[b] >= lo * hmax && h[b] <= hi * hmax) {
      sx += xc[b];
      sy += h[b];
      n += 1;
    }
  if (n < 3) return std::numeric_limits<double>::quiet_NaN();
  const double mx = sx / n, my = sy / n;
  double sxx = 0, sxy = 0;
  for (std::size_t b = from; b < to; ++b)
    if (h[b] >= lo * hmax && h[b] <= hi * hmax) {
      sxx += (xc[b] - mx) * (xc[b] - mx);
      sxy += (xc[b] - mx) * (h[b] - my);
    }
  return std::atan(std::abs(sxy / sxx)) * 180.0 / std::numbers::pi;
}

struct Aor {
  double left = 0, right = 0, mean = 0, height_m = 0;
};

// Port of aor.py (bin 1.5 d, fit window 0.15..0.85 of the height).
Aor angle_of_repose(const Particles& p, double bin_d = 1.5, double lo = 0.15, double hi = 0.85) {
  const std::size_t n = p.size();
  std::vector<double> r = p.radius_m;
  std::sort(r.begin(), r.end());
  const double median_r = n % 2 ? r[n / 2] : 0.5 * (r[n / 2 - 1] + r[n / 2]);
  const double binw = bin_d * 2.0 * median_r;
  double xmin = std::numeric_limits<double>::infinity(), xmax = -xmin;
  for (const auto& x : p.position_m) {
    xmin = std::min(xmin, x.x);
    xmax = std::max(xmax, x.x);
  }
  const double x0 = xmin - r.back(), x1 = xmax + r.back();
  const auto nb = static_cast<std::size_t>(std::ceil((x1 - x0) / binw));
  std::vector<double> h(nb, 0.0), xc(nb);
  for (std::size_t i = 0; i < n; ++i) {
    const auto b = std::clamp<long>(static_cast<long>((p.position_m[i].x - x0) / binw), 0,
                                    static_cast<long>(nb) - 1);
    h[b] = std::max(h[b], p.position_m[i].z + p.radius_m[i]);
  }
  for (std::size_t b = 0; b < nb; ++b) xc[b] = x0 + (static_cast<double>(b) + 0.5) * binw;
  // np.convolve(h, ones(3)/3, mode="same"), then the first maximum.
  std::size_t ip = 0;
  double best = -1.0;
  for (std::size_t b = 0; b < nb; ++b) {
    const double s = ((b > 0 ? h[b - 1] : 0.0) + h[b] + (b + 1 < nb ? h[b + 1] : 0.0)) / 3.0;
    if (s > best) {
      best = s;
      ip = b;
    }
  }
  double hmax = 0.0;
  for (std::size_t b = ip > 0 ? ip - 1 : 0; b < std::min(ip + 2, nb); ++b) hmax = std::max(hmax, h[b]);
  Aor a;
  a.left = fit_side_deg(xc, h, 0, ip + 1, hmax, lo, hi);
  a.right = fit_side_deg(xc, h, ip, nb, hmax, lo, hi);
  a.mean = 0.5 * (a.left + a.right);
  a.height_m = hmax;
  return a;
}

void write_dump(const std::string& path, const Particles& p) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write " + path);
  out << "x z radius\n";
  char line[96];
  for (std::size_t i = 0; i < p.size(); ++i) {
    std::snprintf(line, sizeof line, "%.9e %.9e %.9e\n", p.position_m[i].x, p.position_m[i].z,
                  p.radius_m[i]);
    out << line;
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"demcal pile benchmark: the peer case pile.in (poured quasi-2D pile), throughput"};
  app.set_version_flag("--version", DEMCAL_VERSION);
  std::size_t particles = 6000;
  int threads = 1;
  std::string mode = "pour";
  std::int64_t static_steps = 20000;
  std::int64_t warmup_steps = 500;
  std::uint64_t seed = 4767;
  double mus = 0.5, mur = 0.1;
  double rest_speed = 2e-3;
  double max_time = 3.0;  // pile.in's maxsteps 600000 at dt 5e-6
  std::string dump;
  std::string order = "insertion";
  int tile_y = 1;
  std::string parking = "adaptive";
  app.add_option("--particles,-N", particles, "number of particles")->check(CLI::PositiveNumber);
  app.add_option("--threads,-t", threads, "OpenMP threads")->check(CLI::PositiveNumber);
  app.add_option("--mode", mode, "pour: whole run to rest; static: fixed-N steps on the settled pile")
      ->check(CLI::IsMember({"pour", "static"}));
  app.add_option("--static-steps", static_steps, "timed steps in static mode")->check(CLI::PositiveNumber);
  app.add_option("--warmup-steps", warmup_steps, "untimed steps before the static timing (bench_static.in: 500)");
  app.add_option("--seed", seed, "random seed of the pour");
  app.add_option("--mus", mus, "sliding friction particle-particle");
  app.add_option("--mur", mur, "rolling friction particle-particle");
  app.add_option("--rest-speed", rest_speed, "at rest when the rms speed falls below this [m/s]");
  app.add_option("--max-time", max_time, "give up pouring/settling after this simulated time [s]");
  app.add_option("--dump", dump, "write the final pile as 'x z radius' (for tools/aor.py)");
  app.add_option("--particle-order", order,
                 "how the engine stores particles: insertion, or spatial (re-sorted by neighbour "
                 "cell at every neighbour build; dem/particle_order.hpp)")
      ->check(CLI::IsMember(demcal::dem::particle_order_names()));
  app.add_option("--worker-parking", parking,
                 "whether the thread team may park its workers when they slow it down: adaptive "
                 "(default), never (up to 2026-12-03), always (dem/worker_parking.hpp)")
      ->check(CLI::IsMember(demcal::dem::worker_parking_names()));
  app.add_option("--tile-y", tile_y,
                 "static mode: copy the settled pile this many times across the periodic slab "
                 "thickness before the static timing (the larger case)")
      ->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);
  if (tile_y > 1 && mode != "static") {
    std::fprintf(stderr, "error: --tile-y needs --mode static\n");
    return 1;
  }

  // OpenMP's default thread count is set to --threads, so that T threads means T
  // threads in any loop without a num_threads clause. Up to cffe346 the
  // neighbour-list loops had none: a "1 thread" run forked 2 threads at every
  // step's displacement check and, on a loaded 2-core machine, ran 20x slower
  // (BENCHMARKS.md). The engine now passes its thread count; this stays as a guard.
  omp_set_num_threads(threads);

  try {
    demcal::dem::PouredSlabPileOptions o;
    o.particles = particles;
    o.threads = threads;
    o.seed = seed;
    o.sliding_friction = mus;
    o.rolling_friction = mur;
    o.particle_order = demcal::dem::parse_particle_order(order);
    o.worker_parking = demcal::dem::parse_worker_parking(parking);
    auto sim = demcal::dem::make_poured_slab_pile(o);
    using clock = std::chrono::steady_clock;

    const auto t0 = clock::now();
    const bool at_rest = demcal::dem::run_until_at_rest(*sim, rest_speed, max_time);
    const double pour_s = std::chrono::duration<double>(clock::now() - t0).count();
    const std::int64_t pour_steps = sim->step_count();
    const double pour_ps = sim->particle_steps();
    std::printf("PILE demcal steps %lld time_s %.6g atoms %zu at_rest %d rms_speed %.4g pour_wall_s %.2f\n",
                static_cast<long long>(pour_steps), sim->time_s(), sim->particles().size(), at_rest ? 1 : 0,
                sim->rms_speed_m_s(), pour_s);
    if (!at_rest) std::fprintf(stderr, "warning: the pile did not come to rest within %g s\n", max_time);

    auto report = [&](const char* what, std::int64_t steps, double ps, double loop_s) {
      const double rate = ps / loop_s;
      std::printf("BENCH demcal mode %s threads %d N %zu steps %lld particle_steps %.6e loop_s %.3f "
                  "PS/s %.4e PS/s/core %.4e maxRSS_MiB %.1f version %s contacts_per_particle %.3f "
                  "listed_pairs_per_particle %.3f order %s parking %s parked %d probes %llu switches %llu\n",
                  what, threads, sim->particles().size(), static_cast<long long>(steps), ps, loop_s, rate,
                  rate / threads, peak_rss_mib(), DEMCAL_VERSION,
                  static_cast<double>(sim->contact_count()) / static_cast<double>(sim->particles().size()),
                  static_cast<double>(sim->neighbor_pair_count()) / static_cast<double>(sim->particles().size()),
                  order.c_str(), parking.c_str(), sim->worker_parking()->settled_parked() ? 1 : 0,
                  static_cast<unsigned long long>(sim->worker_parking()->probes()),
                  static_cast<unsigned long long>(sim->worker_parking()->switches()));
      std::fflush(stdout);
    };
    // The pour phase is the whole pour-mode measurement; static mode reports it
    // too (same run, same figure), then times the fixed-N steps.
    report("pour", pour_steps, pour_ps, pour_s);
    if (mode == "static") {
      if (tile_y > 1) sim = demcal::dem::copy_across_slab(o, sim->particles(), tile_y);
      sim->run_steps(warmup_steps);
      const std::int64_t s0 = sim->step_count();
      const double p0 = sim->particle_steps();
      const auto t1 = clock::now();
      sim->run_steps(static_steps);
      const double loop_s = std::chrono::duration<double>(clock::now() - t1).count();
      report("static", sim->step_count() - s0, sim->particle_steps() - p0, loop_s);
    }
    const Aor a = angle_of_repose(sim->particles());
    std::printf("AOR left %.2f deg  right %.2f deg  mean %.2f deg  height_mm %.2f\n", a.left, a.right, a.mean,
                a.height_m * 1e3);
    if (!dump.empty()) write_dump(dump, sim->particles());
    return at_rest ? 0 : 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
