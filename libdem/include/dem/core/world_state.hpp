// What a World is at a step, as plain data: the settings, the clock, the particles, clumps and
// walls, the contact lists of each kind with their law history, the bonds, and the broad phase's
// record of the last rebuild. A restart file holds exactly this (io/world_state.hpp), so a run
// resumed from it continues bit for bit. What is not here is code or derived data: contact
// models, controllers, callbacks, the damping frame, the thread count, the cell grid, and the
// step's plan (StepPlan: near lists, threads' shares; remade on the next step).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <dem/boundary/clump.hpp>
#include <dem/boundary/periodic_cell.hpp>
#include <dem/boundary/wall.hpp>
#include <dem/contact/bond_store.hpp>
#include <dem/contact/contact_sets.hpp>
#include <dem/core/particles.hpp>

namespace dem {

struct WorldSettings {
  double time_step = 0.0;            // s; 0: estimated from stiffnesses and masses (docs/model.md 3.2)
  double time_step_safety = 0.8;     // -, dt = safety * critical estimate
  double local_damping = 0.7;        // -, PFC local damping alpha (0 for dynamic problems)
  Vec3 gravity = Vec3::Zero();       // m/s^2
  double skin = 0.0;                 // m, Verlet skin; 0: half the smallest ball radius
  double near_skin = 0.0;            // m, the pair loops skip candidates farther apart than this,
                                     //    refreshing the list as particles move; 0: a fifth of the
                                     //    skin. Speed only: results do not depend on it
  int sort_every = 20;               // re-sort particles in cell order every this many rebuilds (0: never)
  int threads = 0;                   // the team; 0: auto, the cores this process may run on
                                     //    (OMP_NUM_THREADS where set, else its affinity mask)
  bool adapt_threads = true;         // a step runs on fewer threads while that is faster (a busy
                                     //    machine: core/thread_team.hpp). Speed only
  double max_overlap_ratio = 1.0;    // -, overlap / smaller radius that stops the run as unstable
                                     //    (soft calibrated sands reach 0.5 in strong force chains)
  double max_step_travel_ratio = 0.25;  // -, distance moved in one step / radius that stops the run
  bool pebble_pebble_contacts = false;  // contacts between pebbles of different clumps (ball-pebble law)
};

/// The World's clock.
struct WorldClock {
  double time = 0.0;       // s
  std::int64_t steps = 0;
  double dt = 0.0;         // s, the time step in use (0 until the first step if automatic)
};

/// The contact lists: one set per kind of contact, each with its own list, law history and
/// geometry. Code that handles every set iterates them with for_each_set, in the order the forces
/// are computed and summed (which the bits of the results depend on); a new set is a member here
/// and an entry there.
struct WorldContacts {
  WorldContacts() {
    ball_pebble.kind = ContactKind::BallPebble;
    ball_surface.surfaces = true;
  }
  PairContacts ball_ball;     // kind BallBall
  PairContacts ball_pebble;
  WallContacts ball_facet;    // balls on mesh walls
  WallContacts ball_surface;  // balls on analytic walls (planes, cylinders): the ball-facet law

  /// Calls f(set) for each set in force order: ball-ball, ball-pebble, ball-facet, ball-surface.
  template <class F>
  void for_each_set(F&& f) {
    f(ball_ball), f(ball_pebble), f(ball_facet), f(ball_surface);
  }
  template <class F>
  void for_each_set(F&& f) const {
    f(ball_ball), f(ball_pebble), f(ball_facet), f(ball_surface);
  }
  /// Calls f(set) for the pair sets only (those with near lists, thread shares and incidence).
  template <class F>
  void for_each_pair_set(F&& f) {
    f(ball_ball), f(ball_pebble);
  }
  template <class F>
  void for_each_pair_set(F&& f) const {
    f(ball_ball), f(ball_pebble);
  }
  /// Calls f(set) for the wall sets only: ball-facet, then ball-surface.
  template <class F>
  void for_each_wall_set(F&& f) {
    f(ball_facet), f(ball_surface);
  }
  template <class F>
  void for_each_wall_set(F&& f) const {
    f(ball_facet), f(ball_surface);
  }
  /// The law that computes a set: its own kind for pairs; the ball-facet law for every wall.
  static ContactKind law_kind(const PairContacts& c) { return c.kind; }
  static ContactKind law_kind(const WallContacts&) { return ContactKind::BallFacet; }

  PairContacts& pairs(ContactKind kind) { return kind == ContactKind::BallPebble ? ball_pebble : ball_ball; }
  const PairContacts& pairs(ContactKind kind) const { return kind == ContactKind::BallPebble ? ball_pebble : ball_ball; }
};

/// When the lists were last made, and how far things have moved since: a resumed run rebuilds at
/// the same steps as the run that wrote it.
struct RebuildRecord {
  std::vector<Vec3> x_at_rebuild;          // m, particle positions at the last rebuild
  std::vector<Vec3> wall_disp_at_rebuild;  // m, wall displacements at the last rebuild
  bool need_rebuild = true;                // something was added or changed: rebuild before the next step
  std::int64_t rebuilds = 0;
  double max_travel_sq = 0.0;              // m^2, largest squared particle displacement since
  double max_wall_travel = 0.0;            // m, largest wall displacement since
  double skin = 0.0;                       // m, the skin of the current lists
  Mat3 cell_at_rebuild = Mat3::Zero();     // m, a periodic cell's matrix at the last rebuild
};

struct WorldState {
  WorldSettings settings;
  WorldClock clock;
  ParticleStore particles;
  std::vector<Clump> clumps;
  std::vector<Wall> walls;
  WorldContacts contacts;
  /// Bonds between balls (contact/bond_store.hpp): they outlive contacts, until they break.
  BondStore bonds;
  RebuildRecord rebuild;
  /// The periodic cell the particles live in (World::set_periodic_cell); none: open space.
  std::optional<PeriodicCell> cell;
};

}  // namespace dem
