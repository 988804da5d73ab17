// A contact law bound to its parameters and to the engine's loops: the ContactModel that a World
// runs for one contact type. A law (contact/contact_law.hpp) knows its two pieces; the model runs it
// over the contacts of a step, with the step's plan (core/step_plan.hpp: threads, shares,
// processes), so the laws stay free of all of that.
//
//   world.set_contact_model(dem::ContactKind::BallBall,
//       dem::make_contact_model<dem::RollingLinearLaw>(params, "ball-ball"));
//
// make_contact_model's loops are in dem/core/contact_loops.hpp: include that, or dem/dem.hpp,
// where you call it for a law of your own; the built-in laws' loops are compiled in the library.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <dem/boundary/periodic_cell.hpp>
#include <dem/contact/contact_law.hpp>
#include <dem/contact/contact_sets.hpp>
#include <dem/contact/hertz_mindlin_law.hpp>
#include <dem/contact/kinematics.hpp>
#include <dem/contact/linear_law.hpp>
#include <dem/core/step_plan.hpp>

namespace dem {

struct ParticleStore;
struct Wall;

/// What one call of the contact loops reads and writes besides its contacts, made by the World for
/// each step: the particles, walls and time step, where the sums go, and the step's plan
/// (StepPlan, which owns it) as the loops read it.
struct KernelContext {
  const ParticleStore* particles = nullptr;
  const std::vector<Wall>* walls = nullptr;
  double dt = 0.0;  // s
  int threads = 1;
  /// Per-particle sums (N, N m) that the pair loops add each contact's force and torque into,
  /// in contact order. With several threads (`shared` set), thread t takes the contacts
  /// PairPlan::shares[t] to shares[t + 1], and a particle whose contacts fall in more than one
  /// share is marked in `shared` (StepPlan::shared): the first share adds into it directly, the
  /// later ones leave their parts in PairPlan::deferred, which are added after the loop, share by
  /// share (no two threads ever write one particle). Every particle's sum is then the serial one,
  /// bit for bit, for any thread count.
  Vec3* scatter_force = nullptr;
  Vec3* scatter_torque = nullptr;
  const std::uint8_t* shared = nullptr;  // null: one thread, nothing shared
  /// Each thread's fraction of a loop's work (StepPlan::thread_fractions); null, or not one per
  /// thread: equal.
  const std::vector<double>* thread_fractions = nullptr;
  /// Whether the pair loops write each contact's force and normal force (PairContacts::force,
  /// normal_force) this step: only on steps after which they can be read (World::ContactRecords).
  /// The sums into the particles, the history and `touching` are written on every step.
  bool record_pair_forces = true;
  /// Where the wall loops add each touching wall contact into its ball's sums (scatter_force,
  /// scatter_torque) and its wall's totals (force, moment, contact count, stiffness), in contact
  /// order, each thread its own share as soon as the shares before it are added: the records stay
  /// in the cache of the core that wrote them. Null: the World adds them after the loops (as a
  /// World spread over processes must, once the subdomains have shared their records).
  std::vector<Wall>* wall_totals = nullptr;
  /// The wall loops compute the contacts of this process's balls only, storage indices
  /// [owned_begin, owned_end) (StepPlan::owned_begin); the others keep their records.
  std::int64_t owned_begin = 0;
  std::int64_t owned_end = std::numeric_limits<std::int64_t>::max();
  /// In a periodic cell, each image code's position and velocity shift this step
  /// (PeriodicCell::image_shifts): the pair loops shift each contact's piece 2 by its
  /// PairContacts::image. Null without a cell: the loops compiled without shifts run.
  const ImageShifts* images = nullptr;
};

/// Worst contact of a step, for the instability check.
struct OverlapMonitor {
  double ratio = 0.0;    // overlap / radius of the smaller piece
  std::int64_t contact = -1;
};

/// A contact law bound to its parameters, for one contact type.
class ContactModel {
 public:
  virtual ~ContactModel() = default;
  virtual const char* law_name() const = 0;

  /// Computes the forces of all pair candidates (ball-ball or ball-pebble) into `contacts`, over
  /// the near candidates and threads' shares of `plan`.
  virtual void compute(PairContacts& contacts, PairPlan& plan, const KernelContext& ctx,
                       OverlapMonitor& worst) const = 0;
  /// Computes the forces of all ball-facet candidates into `contacts`.
  virtual void compute(WallContacts& contacts, const KernelContext& ctx, OverlapMonitor& worst) const = 0;
  /// Stiffnesses of one contact, for time-step estimates.
  virtual ContactStiffness stiffness(const ContactKinematics& k) const = 0;

  /// Resizes `buffer` to `count` fresh States.
  virtual void reset_states(StateBuffer& buffer, std::size_t count) const = 0;
  /// Builds `target` (count = source_of.size()): entry k copies source[source_of[k]], or is fresh if
  /// -1; on up to `threads` OpenMP threads (each entry is its own: the same for any count).
  virtual void remap_states(const StateBuffer& source, const std::vector<std::int64_t>& source_of,
                            StateBuffer& target, int threads) const = 0;
};

/// The law of each contact kind, indexed by ContactKind (null: none set).
using ContactModelTable = std::array<std::shared_ptr<const ContactModel>, contact_kind_count>;

/// Binds a law to its parameters (validated here; `where` names them in errors, e.g. "ball-ball").
template <ContactLaw Law>
std::shared_ptr<const ContactModel> make_contact_model(const typename Law::Params& params,
                                                       const std::string& where = "contact");

// The built-in laws' loops are compiled once, in the library (src/core/builtin_law_loops.cpp): a
// program that sets these laws compiles none of the loop templates, and every program runs the
// same machine code for them.
extern template std::shared_ptr<const ContactModel> make_contact_model<LinearLaw>(const LinearLaw::Params&,
                                                                                 const std::string&);
extern template std::shared_ptr<const ContactModel> make_contact_model<RollingLinearLaw>(
    const RollingLinearLaw::Params&, const std::string&);
extern template std::shared_ptr<const ContactModel> make_contact_model<HertzMindlinLaw>(
    const HertzMindlinLaw::Params&, const std::string&);

}  // namespace dem
