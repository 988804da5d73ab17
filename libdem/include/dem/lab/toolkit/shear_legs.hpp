// A path of shear legs as a part of a protocol: the plates of a shear cell move leg after leg (a
// direction and a strain each, lab/toolkit/shear_leg.hpp), in chunks of steps, until the path's
// strain is done. Its cursor (the leg, the strain the leg started at, the path's strain and the
// plates' offset it was measured at) can be kept in a run's restart files, so that a path resumed
// from one goes on exactly where it was.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include <dem/core/world.hpp>
#include <dem/lab/toolkit/run.hpp>
#include <dem/lab/toolkit/shear_cell.hpp>
#include <dem/lab/toolkit/shear_leg.hpp>

namespace dem::lab {

class ShearLegs {
 public:
  /// InputError for an empty path.
  explicit ShearLegs(std::vector<ShearLeg> legs);

  /// Keeps the cursor in `run` (keys leg, leg_start_strain, path_strain, previous_relative_x/y);
  /// `height` gives the consolidated height (m) a loaded path's strain is measured over.
  void keep_in(Run& run, std::function<double()> height);
  /// A new path from the plates' offset now, at the first leg; `height` (m) is H_c.
  void start(const World& world, const ShearCell& cell, double height);

  /// Steps `world` `chunk_steps` at a time until every leg is done. `start_leg` sets the plates'
  /// motion for a leg when the previous one ends (the first leg's is the caller's, after start());
  /// `after_chunk(strain, done)` runs after every chunk, with the path's strain and whether the
  /// path is done. The chunks end with World::StepEnd::WallsAndClumps: the strain reads the
  /// plates only, and a World spread over processes gathers the rest for the outputs alone.
  void run(World& world, const ShearCell& cell, std::int64_t chunk_steps, const std::function<void(const ShearLeg&)>& start_leg,
           const std::function<void(double strain, bool done)>& after_chunk);

  const std::vector<ShearLeg>& legs() const { return legs_; }
  const ShearLeg& current() const { return legs_.at(leg_ < legs_.size() ? leg_ : legs_.size() - 1); }
  /// The unit direction of the current leg (the last one's once the path is done).
  Vec3 direction() const { return horizontal_direction(current().direction_deg); }
  double strain() const { return path_.strain(); }
  double total_strain() const;
  bool done() const { return leg_ >= legs_.size(); }

 private:
  std::vector<ShearLeg> legs_;
  std::size_t leg_ = 0;
  double leg_start_strain_ = 0.0;  // path strain at the start of the leg
  ShearPath path_;
  Vec3 loaded_ = Vec3::Zero();  // a loaded file's path strain and plate offset (x, y)
};

}  // namespace dem::lab
