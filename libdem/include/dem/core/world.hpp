// The World owns a simulation: its state (WorldState: particles, clumps, walls, the contact sets
// and the clock), the contact model of each contact kind, and the parts it delegates to: the
// broad phase (BroadPhase) that keeps the contact lists, the step's plan (StepPlan: near lists,
// threads' shares, ownership) and, when spread over processes, the subdomains
// (parallel::Subdomains). There are no globals: two Worlds are independent.
//
// A step (leapfrog, as PFC's velocity Verlet with velocities half a step behind, docs/model.md 2):
//   1. rebuild the Verlet lists if something moved more than allowed by the skin, and refresh
//      their near lists (the candidates that can touch soon) if something moved more than allowed
//      by the near skin;
//   2. contact forces from the positions at t and the velocities at t - dt/2, summed per
//      particle in contact order (results do not depend on the thread count);
//      then the bonds' forces, in blocks, summed in bond order (core/world_bonds.cpp);
//   3. controllers run (servo walls, user protocols) and may change wall velocities;
//   4. balls and clumps are integrated with local (non-viscous) damping; walls move;
//   5. the instability checks run; every-N-steps callbacks run.
//
// Typical use:
//   dem::World world{settings};
//   world.add_ball({...});
//   world.set_contact_model(dem::ContactKind::BallBall,
//       dem::make_contact_model<dem::RollingLinearLaw>(params, "ball-ball"));
//   world.step(1000);
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <dem/core/broad_phase.hpp>
#include <dem/core/contact_model.hpp>
#include <dem/core/damping_frame.hpp>
#include <dem/core/step_plan.hpp>
#include <dem/core/thread_team.hpp>
#include <dem/core/world_state.hpp>

namespace dem::parallel {
class DomainComm;
class Subdomains;
}  // namespace dem::parallel

namespace dem {

/// Wall-clock seconds spent in each part of the step, summed over the steps since the World was
/// made or reset_step_timing() (not part of the saved state). For benchmarks: where a step's time
/// goes; the results do not depend on it.
struct StepTiming {
  double rebuilds = 0.0;     // s, neighbour lists (cell grid, pair and wall candidates, near lists)
  double ball_ball = 0.0;    // s, the ball-ball contact laws over the pair list
  double ball_pebble = 0.0;  // s, the ball-pebble contact laws (the rings)
  double ball_facet = 0.0;   // s, the ball-wall contact laws (facet and analytic walls)
  double force_sums = 0.0;   // s, zeroing, planning the threads' shares, summing forces on walls, overlap check
  double controllers = 0.0;  // s, servo walls and protocol controllers
  double integration = 0.0;  // s, balls, clumps and pebbles, walls
  double communication = 0.0;  // s, spread over processes: ghosts, gathered sums, synchronisation
  double total() const {
    return rebuilds + ball_ball + ball_pebble + ball_facet + force_sums + controllers + integration + communication;
  }
};

/// One contact as seen by measurements and outputs, after a step.
struct ContactView {
  ContactKind kind;
  std::size_t first;       // storage index of the ball (piece 1)
  std::int64_t second;     // storage index of piece 2 (ball or pebble), or the wall index
  Vec3 normal;             // unit, piece 1 -> piece 2
  Vec3 point;              // m, contact point
  Vec3 force;              // N, on piece 2
  double normal_force;     // N, elastic, compression positive
  /// m, piece 2 is seen at its position plus this: its periodic image (pair contacts across a
  /// periodic cell's face); zero otherwise. The branch vector is x2 + image_shift - x1.
  Vec3 image_shift = Vec3::Zero();
};

class World {
 public:
  explicit World(WorldSettings settings = {});

  // --- building -----------------------------------------------------------------------------
  ParticleId add_ball(const BallSpec& spec);
  ClumpId add_clump(const ClumpSpec& spec);
  WallId add_wall(Wall wall);
  /// The law of a contact kind; the contacts' states are made for it at the next rebuild.
  void set_contact_model(ContactKind kind, std::shared_ptr<const ContactModel> model);
  /// New parameters for the law in use on `kind` (the same law_name()): the contact lists and
  /// their history are kept as they are, with no rebuild, so a restored state continues exactly
  /// as the run that wrote it. InputError for another law or for a kind without a law.
  void retune_contact_model(ContactKind kind, std::shared_ptr<const ContactModel> model);
  const ContactModel* contact_model(ContactKind kind) const { return models_[static_cast<std::size_t>(kind)].get(); }

  // --- bonds (contact/bond_store.hpp, contact/parallel_bond.hpp) ------------------------------
  /// Bonds balls `a` and `b` (stable ids, ParticleStore::id) with a linear parallel bond of
  /// parameters `params` (validated), unloaded now; returns its index in bonds(). The bond acts
  /// beside the pair's contact law, after it in every step, until it breaks. An automatic time
  /// step is estimated again, bonds included, at the next step. InputError for a pebble, the same
  /// ball twice, an id out of range, or a World spread over processes (bonds do not cross
  /// subdomains yet).
  std::size_t add_bond(ParticleId a, ParticleId b, const ParallelBondLaw::Params& params);
  const BondStore& bonds() const { return state_.bonds; }
  /// Bond k's branch from its first ball to its second, x2 - x1 (m): in a periodic cell to the
  /// second ball's image nearest the first, as the bond's force is computed.
  Vec3 bond_branch(std::size_t k) const;

  // --- a periodic cell (boundary/periodic_cell.hpp) --------------------------------------------
  /// Puts the particles in a periodic cell: space is tiled with it, particles that leave it come
  /// back through the opposite face, and contacts across its faces are those of the same pair
  /// inside it. The cell deforms with its velocity gradient L (h' = L h, every step); particles'
  /// velocities are absolute (the image across a face moves at v + L h n). Replaces a cell set
  /// before; the lists are remade at the next step, which wraps the particles into the cell.
  ///
  /// Refused (InputError, naming what and why), for now: a cell not periodic on all three axes;
  /// walls (a wall on a periodic axis cuts the tiling; walls across a non-periodic axis come
  /// with partly periodic cells); clumps (their pebbles would wrap one by one); a World spread
  /// over more than one process (its slabs do not wrap yet). A cell must be at least three times
  /// the largest diameter plus the skin thick (checked at each rebuild). Local damping is
  /// measured against the fixed frame unless a DampingFrame is set (not yet the cell's flow).
  void set_periodic_cell(const PeriodicCell& cell);
  /// The cell, or null in open space.
  const PeriodicCell* periodic_cell() const { return state_.cell ? &*state_.cell : nullptr; }
  /// The cell's velocity gradient L (1/s), from the next step on (a controller may set it every
  /// step). InputError without a cell.
  void set_velocity_gradient(const Mat3& velocity_gradient);

  // --- running ------------------------------------------------------------------------------
  /// What every process holds when step() returns, in a World spread over processes.
  enum class StepEnd {
    Whole,          ///< everything: particles, contacts, walls, clumps (one gather of the state)
    WallsAndClumps  ///< walls and clumps only, for a caller that reads nothing else before its
                    ///< next step or gather_state(); reading particles or contacts then throws
  };
  /// Advances n steps. In one process `end` changes nothing.
  void step(std::int64_t n = 1, StepEnd end = StepEnd::Whole);
  /// Steps until `done(world)` is true, checking every `check_every` steps; returns false if
  /// `max_steps` were taken first.
  bool run_until(const std::function<bool(const World&)>& done, std::int64_t check_every, std::int64_t max_steps);
  /// Called every step after the contact forces, before integration (servo walls, protocols).
  void add_controller(std::function<void(World&)> controller);
  /// Which steps record each ball-ball and ball-pebble contact's force and normal force, the
  /// records that for_each_contact, contact_count, unbalanced_force_ratio and state() (restart
  /// files) read. Wall contacts, the particles' sums and the history are written every step, and
  /// the results are the same bits either way.
  enum class ContactRecords {
    WhenRead,  ///< the last step of each step() call and the steps a callback follows: the records
               ///< are current wherever the caller or a callback reads them, and the other steps
               ///< skip 32 of the bytes a touching contact writes (81 with the rolling-resistance
               ///< law's 48-byte history; the default)
    EveryStep  ///< every step, for a controller that reads contacts during a step (reading them
               ///< there in WhenRead mode throws std::logic_error, on the steps that skip them)
  };
  void set_contact_records(ContactRecords records) { contact_records_ = records; }
  ContactRecords contact_records() const { return contact_records_; }
  /// Called after every `every` steps.
  void add_callback(std::int64_t every, std::function<void(World&)> callback);

  double time() const { return state_.clock.time; }     // s
  std::int64_t step_count() const { return state_.clock.steps; }
  double time_step() const { return state_.clock.dt; }  // s (0 until the first step if automatic)
  void set_time_step(double dt);
  /// Critical time step estimate min over bodies of sqrt(m/K) (docs/model.md 3.2), s.
  double critical_time_step() const;
  /// Re-estimates the automatic time step now (after generation or a stiffness change).
  void update_time_step();
  /// The configured thread team (WorldSettings::threads, auto resolved); a step may run on fewer
  /// while the machine is busy (thread_team()).
  int threads() const { return team_.most(); }
  /// How many threads the steps run on, and how often each size was used.
  const ThreadTeam& thread_team() const { return team_; }
  /// Where the steps' time went so far (StepTiming).
  const StepTiming& step_timing() const { return timing_; }
  void reset_step_timing() { timing_ = {}; }

  // --- one simulation over several processes (domain decomposition) ---------------------------
  /// Spreads this World over the processes of `comm`: every process builds the same World (the
  /// same balls, walls, clumps and models, or the same restart file) and calls this. Each then
  /// owns a subdomain, a contiguous run of the cell-sorted storage (so a run of grid cells),
  /// balanced by contact count at every neighbour-list rebuild: it computes the contacts of its
  /// particles, using ghost copies of their partners within reach plus skin sent by their owners
  /// every step, and integrates its particles. Wall, clump and pebble sums are gathered in the
  /// serial order, so every process steps the same walls and clumps, and the results are the
  /// serial ones bit for bit for any number of processes and threads.
  ///
  /// Between calls of step() (unless a step ended with StepEnd::WallsAndClumps) and when an
  /// every-N-steps callback runs, every process holds the whole state (particles, contacts,
  /// walls), so queries, outputs and restart files work as in one process; the contacts' history
  /// is gathered when state() asks for it. During a step, controllers see walls and clumps:
  /// reading particles or contacts there throws. One process (or none): nothing changes.
  void spread_over(std::shared_ptr<parallel::DomainComm> comm);
  /// Processes this World is spread over (1 unless spread_over), and this one's number.
  int ranks() const;
  int rank() const;
  /// Every process gets the whole state now (after a step that ended with WallsAndClumps; a
  /// collective call). Nothing to do in one process, or when the state is whole already.
  void gather_state() { synchronise(); }
  /// This process's particles (storage indices [first, second)) since the last rebuild; all of
  /// them in one process.
  std::pair<std::size_t, std::size_t> owned_range() const;

  // --- state ---------------------------------------------------------------------------------
  const ParticleStore& particles() const {
    if (domains_) require_whole("particles()");  // spread over processes only
    return state_.particles;
  }
  /// Mutable access; call invalidate_contacts() after moving particles or changing radii by hand.
  ParticleStore& particles() {
    if (domains_) require_whole("particles()");  // spread over processes only
    return state_.particles;
  }
  void invalidate_contacts() { state_.rebuild.need_rebuild = true; }
  const std::vector<Clump>& clumps() const { return state_.clumps; }
  std::vector<Clump>& clumps() { return state_.clumps; }
  const std::vector<Wall>& walls() const { return state_.walls; }
  Wall& wall(WallId id) { return state_.walls.at(static_cast<std::size_t>(id)); }
  const Wall& wall(WallId id) const { return state_.walls.at(static_cast<std::size_t>(id)); }
  const WorldSettings& settings() const { return state_.settings; }
  void set_local_damping(double alpha);
  /// The field local damping measures velocities against (DampingFrame; the fixed frame unless
  /// set). Not part of the WorldState: a protocol that uses it sets it from a controller every step
  /// (lab::plate_damping_frame follows a shear cell's plates), so damping_frame() between steps
  /// shows the frame of the last step.
  void set_damping_frame(const DampingFrame& frame);
  const DampingFrame& damping_frame() const { return damping_frame_; }
  /// Overlap / smaller radius above which a step stops with InstabilityError (> 0). Restart files
  /// carry it; a protocol that loads one can raise it again afterwards.
  void set_max_overlap_ratio(double ratio);
  void set_gravity(const Vec3& g) { state_.settings.gravity = g; }

  /// Visits every touching contact of the last step (a ball on an analytic wall: kind ball-facet).
  void for_each_contact(const std::function<void(const ContactView&)>& visit) const;
  /// Number of touching contacts of a type in the last step (ball-facet: with facet and analytic walls).
  std::size_t contact_count(ContactKind kind) const;
  /// Translational + rotational kinetic energy of balls and clumps, J (velocities at t - dt/2).
  double kinetic_energy() const;
  /// Mean |unbalanced force| over free balls divided by the mean contact normal force (PFC's ratio).
  double unbalanced_force_ratio() const;

  // --- internals exposed for checkpoints and tests --------------------------------------------
  const PairContacts& pair_contacts(ContactKind kind) const;
  /// How the last step shared out a pair set (near list, threads' shares, deferred parts).
  const PairPlan& pair_plan(ContactKind kind) const { return plan_.pairs(kind); }
  const WallContacts& wall_contacts() const {
    if (domains_) require_whole("wall_contacts()");
    return state_.contacts.ball_facet;
  }
  std::int64_t rebuild_count() const { return state_.rebuild.rebuilds; }
  std::int64_t near_refresh_count() const { return broad_phase_.near_refresh_count(); }
  /// Forces a neighbour-list rebuild with re-sorting now (tests of history preservation).
  void rebuild_now(bool resort);

  // --- the state as data (restart files: io/world_state.hpp) --------------------------------
  /// Everything a restart file holds (WorldState). On a World spread over processes this gathers
  /// the contacts' history, so every process calls it at the same point (as the apps' protocols,
  /// which run the same code on every rank, do).
  const WorldState& state() const;
  /// Replaces the state with `state`, which io::read_world_state has read and checked against the
  /// contact models set now: its lists are trusted as they are. An automatic time step more than
  /// 10 % above safety x the critical estimate of the models set now (stiffer parameters than the
  /// saved run's) is re-estimated.
  void restore(WorldState state);

 private:
  void rebuild(bool resort);
  /// The contact forces of this step; `record_pair_forces`: the pair contacts' records too.
  void compute_forces(bool record_pair_forces);
  /// The bonds' forces of this step, added after the contact laws' (world_bonds.cpp).
  void compute_bond_forces();
  void integrate();
  /// Places every pebble where its clump puts it, each thread the pebbles stored in its range of
  /// the integration (the particles whose forces it mostly summed), after the clumps moved.
  void update_pebbles();
  std::int64_t pebble_count() const;
  /// Remakes the pebble layout below if the storage changed since it was made.
  void refresh_pebble_layout();
  /// Each pebble's force and torque about its clump's centre, in the clumps' order (pebble_force_,
  /// pebble_torque_), for the clumps to add up in that order (after refresh_pebble_layout).
  void pebble_shares();
  struct PebbleSlot;
  /// The pebbles (in pebbles_in_storage_) stored in the calling thread's range of the integration,
  /// inside a parallel region (all of them outside one).
  std::pair<const PebbleSlot*, const PebbleSlot*> pebbles_of_this_thread() const;
  /// The worst overlap of a step, and the contact set it is in.
  struct WorstOverlap {
    OverlapMonitor monitor;
    std::variant<std::monostate, const PairContacts*, const WallContacts*> set;
  };
  void check_stability(const WorstOverlap& worst);
  /// InstabilityError for particle `particle`: what happened, when, and the likely cause (the
  /// time step when it is above the stable estimate; otherwise the contact type `kind` of an
  /// overlap when it is softer than the stiffest, or the load).
  [[noreturn]] void fail(const std::string& what, std::size_t particle, std::optional<ContactKind> kind = std::nullopt) const;

  // Spread over processes: each delegates to the Subdomains (world_domains.cpp) and does nothing
  // in one process.
  /// std::logic_error naming `what` when a spread World is read between a step that ended with
  /// StepEnd::WallsAndClumps (or, during a step, from a controller) and the next gather.
  void require_whole(const char* what) const;
  /// Throws std::logic_error naming `what` if the last step did not record the pair contacts'
  /// forces (ContactRecords::WhenRead, read from a controller).
  void require_pair_records(const char* what) const;
  bool spread() const { return domains_ != nullptr; }
  /// Subdomains, ghosts and slices from the lists now (after a rebuild or a load).
  void plan_domains();
  /// The lists changed (a rebuild or a load): plan again before the next forces.
  void forget_domains();
  /// A step starts: other processes' particles and contacts held here go stale until a gather.
  void copies_go_stale();
  /// Keeps in the near lists only the contacts this process computes.
  void keep_local_near();
  /// After the contact loops: the pebbles' sums and the wall contacts' records of every process,
  /// and the step's worst overlap ratio over them (global_worst reads it).
  void share_contact_results(double local_worst_ratio);
  /// After integration: the ghosts' positions and velocities from their owners.
  void share_ghosts();
  /// Every process gets every particle and contact record from their owners (not the history).
  void synchronise();
  /// Every process gets every contact's history (before a rebuild, or for state()).
  void synchronise_history();
  /// The largest of `values` over the processes (element by element, in place).
  void global_max(double* values, std::size_t count);
  /// The worst overlap over all processes (after share_contact_results), with the whole state
  /// synchronised if it stops the run.
  WorstOverlap global_worst(const WorstOverlap& local);

  WorldState state_;
  ContactModelTable models_{};
  BroadPhase broad_phase_;
  DampingFrame damping_frame_;
  ThreadTeam team_;
  int threads_ = 1;  // this step's team: team_.size()
  std::vector<std::function<void(World&)>> controllers_;
  std::vector<std::pair<std::int64_t, std::function<void(World&)>>> callbacks_;
  StepTiming timing_;
  StepPlan plan_;
  std::shared_ptr<parallel::Subdomains> domains_;  // null: one process
  ContactRecords contact_records_ = ContactRecords::WhenRead;
  bool pair_records_current_ = true;  // the last step recorded the pair contacts' forces
  // Where the pebbles are stored, so that a step looks up no ids: the pebbles in storage order,
  // each with its clump and place in it, and clump c's pebbles at [pebble_begin_[c],
  // pebble_begin_[c + 1]) of the per-pebble arrays below, in the clump's order. Stale after
  // anything that moves particles in storage or adds some (a rebuild's re-sort, a new ball or
  // clump, a restored state).
  struct PebbleSlot {
    std::int32_t index;  // in storage
    std::int32_t clump;
    std::int32_t place;  // in the clump's pebbles and pebble_offsets
  };
  std::vector<PebbleSlot> pebbles_in_storage_;
  std::vector<std::size_t> pebble_begin_;
  std::vector<Vec3> pebble_force_, pebble_torque_;  // N, N m: pebble_shares()
  std::vector<Mat3> clump_rotation_;  // each clump's orientation as a matrix, for placing pebbles
  bool pebble_layout_stale_ = true;
};

}  // namespace dem
