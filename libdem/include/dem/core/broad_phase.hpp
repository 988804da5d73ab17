// The World's broad phase: which pieces can touch. It keeps Verlet lists with a skin (every pair
// closer than the sum of radii plus the skin, and every ball within its radius plus the skin of a
// wall's triangles), remade only when something has moved far enough to matter, with each
// touching contact's history carried over by stable particle ids; and, inside those, the near
// lists that the contact loops run over (candidates within a smaller near skin, remade more often),
// which it writes into the step's plan (StepPlan).
//
// The lists and the record of the last rebuild are part of the WorldState (a resumed run rebuilds
// at the same steps); the cell grid and the near lists are derived and remade after a load.
#pragma once

#include <cstdint>
#include <vector>

#include <dem/core/contact_model.hpp>
#include <dem/core/step_plan.hpp>
#include <dem/core/world_state.hpp>
#include <dem/grid/cell_grid.hpp>
#include <dem/grid/periodic_grid.hpp>

namespace dem {

class BroadPhase {
 public:
  /// True when the lists must be remade before the next force computation: the state asks for it,
  /// or a particle or wall has moved so far since the last rebuild that a pair could have come
  /// within reach unseen.
  /// In a periodic cell, an image has moved too: by as much as the cell's edges since.
  static bool needs_rebuild(const WorldState& state);

  /// Remakes the candidate lists of `state` (ball-ball, ball-pebble, ball-facet) and their
  /// incidence, carrying the history of each touching contact over through `models`. `resort`:
  /// re-sorts the particles in cell order first (storage indices change; ids do not).
  ///
  /// In a periodic cell a cell sheared past its tilt limit is first re-mapped to an equivalent,
  /// less skewed one (PeriodicCell::remap_tilt), the particles that have left it are put back
  /// through the opposite face (x - h m, and v - L h m: the image's velocity), and each pair candidate is found with the
  /// image of its piece 2 that piece 1 reaches (PairContacts::image), so a contact across a face
  /// keeps its history by ids as any other. InputError for a cell thinner than three search cells.
  void rebuild(WorldState& state, const ContactModelTable& models, int threads, bool resort);

  /// True when the near lists must be remade: after a rebuild or a load, or when a particle has
  /// moved half the near skin since they were made (in a periodic cell, with the images' travel).
  bool near_stale(const WorldState& state) const;
  /// Remakes the near lists of the pair contacts in `state` (PairPlan::near of `plan`).
  void refresh_near(const WorldState& state, StepPlan& plan, int threads);
  /// The near lists no longer match the contact lists (a load replaced them).
  void invalidate_near() { near_stale_ = true; }

  /// Particle positions when the near lists were made, and the largest squared displacement since
  /// (m^2), which the integrator raises as particles move.
  const std::vector<Vec3>& positions_at_near() const { return x_at_near_; }
  double near_travel_sq() const { return max_near_travel_sq_; }
  void set_near_travel_sq(double travel_sq) { max_near_travel_sq_ = travel_sq; }
  std::int64_t near_refresh_count() const { return near_refreshes_; }

 private:
  /// The candidates of a periodic cell (rebuild's periodic part): wraps the particles into the
  /// cell, re-sorts them if `resort`, and lists the pairs with their images.
  void find_periodic_candidates(WorldState& state, int threads, bool resort, std::vector<std::int32_t>& first,
                                std::vector<std::int32_t>& second, std::vector<std::uint8_t>& image);

  CellGrid grid_;
  PeriodicGrid periodic_grid_;
  Mat3 cell_at_near_ = Mat3::Zero();  // m, a periodic cell's matrix when the near lists were made
  std::vector<Vec3> x_at_near_;
  double max_near_travel_sq_ = 0.0;  // m^2
  double near_skin_ = 0.0;           // m
  bool near_stale_ = true;
  std::int64_t near_refreshes_ = 0;
};

/// The skin of lists made now: WorldSettings::skin, or half the smallest ball radius if that is 0.
double resolved_skin(const WorldState& state);

}  // namespace dem
