#include "solver/time/run.hpp"

#include "solver/core/error.hpp"
#include "solver/core/format.hpp"
#include "solver/core/peak_memory.hpp"
#include "solver/io/atomic_file.hpp"
#include "solver/io/checkpoint.hpp"
#include "solver/io/frame_writer.hpp"
#include "solver/io/history_writer.hpp"
#include "solver/io/run_log.hpp"
#include "solver/parallel/decomposition.hpp"
#include "solver/parallel/ranks.hpp"
#include "solver/time/cost_estimate.hpp"
#include "solver/time/energy_guard.hpp"
#include "solver/time/probes.hpp"
#include "solver/time/progress.hpp"
#include "solver/time/restart_check.hpp"
#include "solver/time/simulation.hpp"
#include "solver/time/stop_signals.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <csignal>
#include <iostream>
#include <optional>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace sphfem {

namespace {

int thread_count() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

// Bodies named in a contact pair, by index.
std::vector<int> contact_bodies(const Case& c) {
  std::vector<int> out;
  for (int b = 0; b < static_cast<int>(c.bodies.size()); ++b)
    for (const ContactSpec& pair : c.contacts)
      if (pair.bodies[0] == c.bodies[b].name || pair.bodies[1] == c.bodies[b].name) {
        out.push_back(b);
        break;
      }
  return out;
}

std::vector<std::string> history_columns(const Case& c, const std::vector<Probe>& probes,
                                         const std::vector<std::string>& bodies) {
  std::vector<std::string> columns{"time", "dt"};
  for (const auto& name : probe_columns(probes))
    columns.push_back(name);
  for (const auto& b : bodies)
    for (const char* k : {".vx", ".vy", ".vz", ".kinetic", ".internal"})
      columns.push_back("body." + b + k);
  for (int b : contact_bodies(c))
    for (const char* k : {".fx", ".fy", ".fz"})
      columns.push_back("contact." + bodies[b] + k);
  for (const char* e : {"kinetic", "internal", "hourglass", "contact", "eroded", "friction",
                        "external_work", "total"})
    columns.push_back(std::string("energy.") + e);
  return columns;
}

void history_row(const Simulation& sim, double dt, const std::vector<Probe>& probes,
                 const std::vector<int>& in_contact, const Energies& e, std::vector<double>& row) {
  row.clear();
  row.push_back(sim.time());
  row.push_back(dt);
  probe_values(probes, sim, row);
  const std::vector<BodyTotals> bodies = sim.bodies();
  for (const auto& b : bodies)
    row.insert(row.end(),
               {b.com_velocity.x(), b.com_velocity.y(), b.com_velocity.z(), b.kinetic, b.internal});
  for (int b : in_contact) {
    const Vec3& f = bodies[b].contact_force;
    row.insert(row.end(), {f.x(), f.y(), f.z()});
  }
  row.insert(row.end(), {e.kinetic, e.internal, e.hourglass, e.contact, e.eroded, e.friction,
                         e.external_work, e.total()});
}

// Energy balance error above which a finished run is flagged (summary.json `warnings`, log).
constexpr double energy_warning = 0.05;

// Runs f; in a distributed run an error on one rank would leave the others waiting in the next
// collective call: it ends the job, with the rank that met it named.
template <class F> void ending_the_job_on_error(bool distributed, F f) {
  if (!distributed) {
    f();
    return;
  }
  try {
    f();
  } catch (const Error& e) {
    std::cerr << detail::concat("sphfem: error on MPI rank ", ranks::rank(), ": ", e.what(),
                                "\n"); // one write: the ranks' lines do not interleave
    ranks::abort(1);
  }
}

// "42 s", "7.5 min", "2.3 h".
std::string duration_text(double seconds) {
  if (seconds < 10)
    return format("%.1f s", seconds);
  if (seconds < 120)
    return format("%.0f s", seconds);
  if (seconds < 7200)
    return format("%.1f min", seconds / 60);
  return format("%.1f h", seconds / 3600);
}

// The checkpoint's meta agrees with this case and model, or an Error says what differs.
void check_restart(const std::filesystem::path& file, const CheckpointMeta& meta, const Case& c,
                   const std::string& model, RunLog& log) {
  check_restart_case(file, meta, c);
  SPHFEM_CHECK(meta.model == model, "checkpoint ", file, " was made from another model (",
               meta.model, "; this case meshes to ", model,
               "): restart with the checkpoint's case, or start afresh");
  if (meta.threads != thread_count())
    log.line("note: the checkpoint was written with " + std::to_string(meta.threads) +
             " threads, this run has " + std::to_string(thread_count()) +
             " (results do not depend on the thread count: tests/e2e/determinism_test.cpp)");
}

} // namespace

nlohmann::json solve(const Case& c, const Model& model, const SolveOptions& options) {
  const auto& out = options.out_dir;
  // A distributed run: every rank steps its share; rank 0 alone writes the history (its rows are
  // sums over the ranks) and the checkpoint (its arrays are made whole by
  // Simulation::gather_state first) and speaks; each rank writes its piece of a frame.
  const bool writer = ranks::rank() == 0;
  std::optional<Decomposition> decomposition;
  EntityCosts costs;
  if (ranks::distributed()) {
    costs = entity_costs(model, c.body_groups(), MirrorParticles(c));
    decomposition = decompose(model, costs, ranks::size());
  }
  if (writer)
    std::filesystem::create_directories(out);
  RunLog log(writer ? out / "run.log" : std::filesystem::path("/dev/null"), options.echo && writer);

  Simulation sim(c, model, decomposition ? &*decomposition : nullptr);
  if (decomposition)
    log.line("distributed over " + std::to_string(ranks::size()) +
             " MPI ranks (recursive coordinate bisection weighted by cost)");
  const auto probes = locate_probes(c, model);
  const Index nodes = sim.nodes().size(), elements = sim.elements().size();
  const Index particles = model.particle_count();
  const double dt0 = sim.stable_dt();
  log.line("case " + c.name + ": " + std::to_string(nodes) + " nodes, " + std::to_string(elements) +
           " hexahedra, " + std::to_string(particles) + " particles; " +
           std::to_string(thread_count()) + " threads");
  const ParticleSystem& sph = sim.particle_system();
  // Entries that a pair loop visits: the lists of real and background particles (mirror
  // images gather nothing).
  const long long list_entries = sph.pair_loop_entries();
  if (!sph.empty()) {
    const Particles& p = sph.particles();
    const Index rows = p.rows(), images = p.total() - rows;
    log.line("SPH sums: " + std::to_string(p.size()) + " particles, " +
             std::to_string(rows - p.size()) + " background particles, " + std::to_string(images) +
             " mirror images; " + std::to_string(list_entries) +
             " neighbour-list entries of particles and background particles");
  }
  const double steps = std::ceil(c.time.end / dt0);
  log.line("stable step " + format("%.4e", dt0) + " s, about " + format("%.0f", steps) +
           " steps to t = " + format("%.4e", c.time.end) + " s");
  const double estimate =
      estimated_wall_s({elements, nodes, particles, list_entries, steps, thread_count()});
  log.line("estimated wall time " + duration_text(estimate) +
           " (costs per element, node, particle and neighbour measured in bench/README.md)");
  for (const auto& p : probes)
    log.line("probe " + p.name + " on " + (p.on_particle ? "particle " : "node ") +
             std::to_string(p.node) + " at (" + format("%.6g", p.position.x()) + ", " +
             format("%.6g", p.position.y()) + ", " + format("%.6g", p.position.z()) + ") m");

  const std::string fingerprint = model_fingerprint(model);
  std::optional<CheckpointMeta> restart;
  if (!options.restart.empty()) {
    restart = read_checkpoint_meta(options.restart);
    check_restart(options.restart, *restart, c, fingerprint, log);
  }

  // A distributed run writes its frames in parallel: each rank its piece, rank 0 the files
  // naming them (io/frame_writer.hpp).
  std::unique_ptr<FrameWriter> frames;
  if (c.output.frames && (writer || decomposition))
    frames = std::make_unique<FrameWriter>(out, sim.elements(), sim.particle_system().particles(),
                                           sim.materials());
  const auto write_frame = [&] {
    const Particles& p = sim.particle_system().particles();
    if (!decomposition) {
      frames->write(sim.time(), sim.nodes(), sim.elements(), p);
      return;
    }
    const FramePiece piece{ranks::rank(), ranks::size(), sim.own_elements(),
                           sim.particle_system().own_real_rows()};
    frames->write(sim.time(), sim.nodes(), sim.elements(), p, &piece);
  };
  HistoryWriter history(out, history_columns(c, probes, sim.body_names()));
  std::vector<double> row;
  const std::vector<int> in_contact = contact_bodies(c);
  // Output times are compared with a relative tolerance so round-off in t never skips one.
  const double eps = 1e-9 * c.time.end;
  double next_frame = c.time.output_interval, next_history = c.time.history_interval;
  // Everything a checkpoint holds: the simulation, the history so far, the frames listed and
  // the next output times.
  const auto persist = [&](StateArchive& a) {
    sim.persist(a);
    history.persist(a);
    if (frames)
      frames->persist(a);
    a.value("run/next_frame", next_frame);
    a.value("run/next_history", next_history);
  };
  const auto checkpoint = [&] {
    sim.gather_state(GatherTo::writer);
    // Every rank takes part in the element fields' gathers (Simulation::persist); rank 0 writes.
    ending_the_job_on_error(decomposition.has_value(), [&] {
      if (writer) {
        write_checkpoint(out / "checkpoint.h5",
                         {sim.time(), sim.steps(), thread_count(), fingerprint, c.keys}, persist);
      } else {
        DiscardingArchive gathers_only;
        sim.persist(gathers_only);
      }
    });
  };
  if (restart) {
    read_checkpoint(options.restart, persist);
    if (writer)
      history.flush(); // only once the whole checkpoint has been read
    log.line("restart from " + options.restart.string() + " at t = " + format("%.6e", sim.time()) +
             " s, step " + std::to_string(sim.steps()));
  } else {
    if (frames)
      write_frame();
    history_row(sim, 0.0, probes, in_contact, sim.energies(), row);
    history.append(row);
    if (writer)
      history.flush();
  }
  // The history's rows go to the files on rank 0 only.
  const auto flush = [&] {
    if (writer)
      history.flush();
  };

  const StopSignals signals;
  EnergyGuard guard(c.time.energy_limit, 0.05 * c.time.end);
  Progress progress(c.time.end, log);
  const auto start = std::chrono::steady_clock::now();
  auto last_checkpoint = start;
  const long long first_step = sim.steps();
  int rebalances = 0;
  double dt = dt0;
  while (sim.time() < c.time.end - eps) {
    dt = std::min(sim.stable_dt(), c.time.end - sim.time());
    SPHFEM_CHECK(dt > 1e-6 * dt0, "time step collapsed to ", dt, " s at t = ", sim.time(), " s (",
                 dt0, " s at start): elements are being crushed; the run is unstable");
    ending_the_job_on_error(decomposition.has_value(), [&] { sim.step(dt); });
    const bool last = sim.time() >= c.time.end - eps;
    const bool history_due = last || sim.time() >= next_history - eps;
    const bool frame_due = last || sim.time() >= next_frame - eps;
    // Signals and the wall clock differ between ranks: rank 0's clock and any rank's signal
    // decide for all.
    int signal = signals.received();
    const auto now = std::chrono::steady_clock::now();
    const CheckpointSpec& every = c.output.checkpoint;
    int wall_due = every.wall_s > 0 &&
                   std::chrono::duration<double>(now - last_checkpoint).count() >= every.wall_s;
    if (decomposition) {
      signal = ranks::max(signal);
      wall_due = every.wall_s > 0 && ranks::max(writer ? wall_due : 0);
    }
    const bool checkpoint_due =
        !last && ((every.steps > 0 && sim.steps() % every.steps == 0) || wall_due);
    // At the rows and frames only, whose times the case fixes: the cuts do not depend on the
    // wall clock or on signals, so a run repeats them.
    if ((history_due || frame_due) && decomposition && options.rebalance > 0) {
      const Rebalance r = sim.rebalance(model, costs, options.rebalance);
      if (r.done) {
        ++rebalances;
        log.line("t = " + format("%.4e", sim.time()) + " s: rebalanced, imbalance " +
                 format("%.3f", r.before) + " → " + format("%.3f", r.after) +
                 " (largest rank's cost per step / mean, entities' current costs)");
      }
    }
    if (history_due) {
      const Energies e = sim.energies();
      SPHFEM_CHECK(std::isfinite(e.total()), "energy is not finite at t = ", sim.time(),
                   " s (step ", sim.steps(), "): the run is unstable; last good frame kept");
      history_row(sim, dt, probes, in_contact, e, row);
      history.append(row);
      try {
        if (decomposition && guard.trips(sim, e))
          sim.gather_state(); // its message names the fastest entity of all
        guard.check(sim, e);
      } catch (const Error&) {
        progress.finish();
        flush(); // the rows up to the blow-up: they show it growing
        throw;
      }
      while (next_history <= sim.time() + eps)
        next_history += c.time.history_interval > 0 ? c.time.history_interval : dt;
    }
    if (frame_due) {
      if (frames)
        write_frame();
      flush();
      while (next_frame <= sim.time() + eps)
        next_frame += c.time.output_interval;
    }
    progress.update(sim.steps(), sim.time(), dt);
    if (signal != 0) {
      progress.finish();
      flush();
      checkpoint();
      const std::string file = (out / "checkpoint.h5").string();
      throw Interrupted(detail::concat("interrupted by ", signal == SIGINT ? "SIGINT" : "SIGTERM",
                                       " at t = ", format("%.6e", sim.time()), " s (step ",
                                       sim.steps(), "); checkpoint ", file,
                                       " written; continue with: sphfem solve ", c.file.string(),
                                       " -o ", out.string(), " --restart ", file,
                                       " (and the same --set options)"),
                        signal);
    }
    if (checkpoint_due) {
      checkpoint();
      last_checkpoint = now;
    }
  }
  progress.finish();
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  flush();
  checkpoint();

  const Energies e = sim.energies();
  const double balance = sim.balance_error(e);
  nlohmann::json summary;
  summary["case"] = c.name;
  if (!c.file.empty())
    summary["case_file"] = std::filesystem::absolute(c.file).lexically_normal().string();
  summary["steps"] = sim.steps();
  summary["time"] = sim.time();
  summary["wall_s"] = wall;
  summary["entity_steps_per_s"] =
      wall > 0 ? double(particles + elements) * double(sim.steps() - first_step) / wall : 0.0;
  summary["threads"] = thread_count();
  summary["counts"] = {{"particles", particles},
                       {"nodes", nodes},
                       {"elements", elements},
                       {"background_particles", Index(model.background_nodes.size())}};
  summary["dt"] = {{"initial", dt0}, {"final", sim.stable_dt()}};
  summary["energy"] = {{"kinetic", e.kinetic},
                       {"internal", e.internal},
                       {"hourglass", e.hourglass},
                       {"contact", e.contact},
                       {"eroded", e.eroded},
                       {"friction", e.friction},
                       {"external_work", e.external_work},
                       {"total", e.total()},
                       {"balance_error", balance}};
  summary["momentum_drift"] = sim.momentum_drift();
  for (const auto& b : sim.bodies())
    summary["bodies"][b.name] = {
        {"mass", b.mass},
        {"com_velocity", {b.com_velocity.x(), b.com_velocity.y(), b.com_velocity.z()}},
        {"killed_particles", b.killed_particles},
        {"eroded_elements", b.eroded_elements},
        {"kinetic_energy", b.kinetic},
        {"internal_energy", b.internal}};
  for (const auto& p : probes)
    summary["probes"][p.name] = {{p.on_particle ? "particle" : "node", p.node},
                                 {"position", {p.position.x(), p.position.y(), p.position.z()}}};
  if (const auto& plane = c.output.section) {
    summary["section_plane"] = {
        {"point", {plane->point.x(), plane->point.y(), plane->point.z()}},
        {"normal", {plane->normal.x(), plane->normal.y(), plane->normal.z()}}};
    if (plane->u_range)
      summary["section_plane"]["u_range"] = {(*plane->u_range)[0], (*plane->u_range)[1]};
  }
  if (const auto& scene = c.scene)
    summary["scene"] = {{"name", scene->name},
                        {"preset", scene->preset},
                        {"symmetry", scene->symmetry},
                        {"obliquity_deg", scene->obliquity},
                        {"spacing", scene->spacing},
                        {"core_half_width", scene->core_half_width},
                        {"projectile", {{"velocity", scene->velocity}}}};
  // A step factor near its limit keeps the run stable but lets the energy drift (docs/
  // stability.md: SPH at cfl 0.9–1.0 ends 10–14% off); say so where the user looks.
  summary["warnings"] = nlohmann::json::array();
  if (balance > energy_warning) {
    summary["warnings"].push_back(
        "energy balance error " + format("%.1f%%", 100 * balance) + " is above " +
        format("%.0f%%", 100 * energy_warning) +
        ": the step is too large for this model (time.cfl " + format("%g", c.time.cfl) +
        ", sph.cfl " + format("%g", c.sph.cfl) +
        ") or the contact too stiff; results are suspect (docs/stability.md)");
  }
  summary["units"] = {{"time", "s"},       {"energy", "J"},   {"mass", "kg"},
                      {"velocity", "m/s"}, {"position", "m"}, {"wall_s", "s"}};
  // The largest rank's peak resident memory (each rank's, when distributed), MB.
  const double peak_mb = peak_resident_mb();
  const std::vector<double> peaks =
      decomposition ? ranks::gather_all(std::array{peak_mb}) : std::vector<double>{peak_mb};
  summary["peak_resident_MB"] = *std::max_element(peaks.begin(), peaks.end());
  if (decomposition) {
    // What the ranks sent each other per step, per entity: the halos, the element forces, the
    // background particles, and at each rebuild the migrating particles and the positions of
    // the rows near each rank's (the gathers for checkpoints and new cuts not counted).
    const double sent = ranks::sum_in_rank_order(std::array{double(sim.halo_bytes())})[0];
    const double entity_steps = double(particles + elements) * double(sim.steps() - first_step);
    summary["ranks"] = ranks::size();
    summary["halo_bytes_per_entity_step"] = entity_steps > 0 ? sent / entity_steps : 0.0;
    summary["rebalances"] = rebalances;
    summary["migrations"] = sim.particle_system().migrations();
    // Each rank's halo over what it owns, as the partition census counts it, on the last share.
    const Simulation::HaloShare share = sim.halo_share();
    const std::vector<double> shares = ranks::gather_all(std::array{share.halo, share.own});
    double mean = 0, largest = 0;
    for (std::size_t r = 0; r < shares.size(); r += 2) {
      const double fraction = shares[r + 1] > 0 ? shares[r] / shares[r + 1] : 0.0;
      mean += fraction / ranks::size();
      largest = std::max(largest, fraction);
    }
    summary["halo_fraction"] = {{"mean", mean}, {"max", largest}};
    summary["peak_resident_MB_per_rank"] = peaks;
    // The rows each rank holds at the end, of real particles and of background particles: its
    // own, those near them and those of the nodes it steps.
    const Particles& p = sim.particle_system().particles();
    const std::vector<double> rows =
        ranks::gather_all(std::array{double(p.size()), double(p.background)});
    std::vector<Index> held_particles, held_background;
    for (std::size_t r = 0; r < rows.size(); r += 2) {
      held_particles.push_back(static_cast<Index>(rows[r]));
      held_background.push_back(static_cast<Index>(rows[r + 1]));
    }
    summary["rows_held_per_rank"] = {{"particles", held_particles},
                                     {"background_particles", held_background}};
    log.line("ranks exchanged " + format("%.3g", sent / 1e6) + " MB (" +
             format("%.3g", entity_steps > 0 ? sent / entity_steps : 0.0) +
             " B per entity-step) for their halos; halo fraction " + format("%.3f", mean) +
             " mean, " + format("%.3f", largest) + " largest (halo rows and nodes / own)");
  }
  if (writer)
    write_text_atomically(out / "summary.json", summary.dump(2) + "\n");

  log.line("done: " + std::to_string(sim.steps()) + " steps in " + format("%.2f", wall) + " s (" +
           format("%.3g", summary["entity_steps_per_s"].get<double>()) +
           " entity-steps/s); energy balance error " + format("%.2e", balance) + "; peak memory " +
           format("%.0f", summary["peak_resident_MB"].get<double>()) + " MB" +
           (decomposition ? " (largest rank)" : ""));
  for (const auto& warning : summary["warnings"])
    log.line("warning: " + warning.get<std::string>());
  return summary;
}

} // namespace sphfem
