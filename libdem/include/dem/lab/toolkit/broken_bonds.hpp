// The broken bonds of a cemented run, for ParaView (docs/cementation.md): which bonds broke, how,
// and at what strain of the protocol. The World knows how each bond broke and the loads that
// broke it (BondStore); the strain is the protocol's (the shear apps' shear strain, an element
// test's axial or shear strain or cycles, named as its history names it), so this part notes it
// for each bond the first time it sees the bond broken, and keeps those strains in the run's
// restart files (a resumed run writes the same files as the uninterrupted one).
//
// write_vtp() writes the broken bonds as points (VTK polydata, atomically), at the bond point now
// (on the line of centres, halfway across the gap or the overlap), with point data:
//   mode                 1 broken in tension, 2 in shear (BondStatus)
//   <strain>_broken      the protocol's strain when it was first seen broken (shear_strain_broken
//                        in the shear apps; axial_strain_broken in a triaxial element test)
//   energy_released_J    the strain energy the bond held on the step it broke (J)
//   first_id, second_id  the two balls' ids
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <dem/core/world.hpp>
#include <dem/lab/toolkit/run.hpp>

namespace dem::lab {

class BrokenBondLog {
 public:
  /// Keeps its strains in `run`'s restart files under `key`; `run` must outlive it. `strain_name`:
  /// the history column of the strain update() is given (the VTK array is <strain_name>_broken).
  BrokenBondLog(Run& run, const std::string& key, std::string strain_name = "shear_strain");

  /// Notes `strain` (the protocol's, as strain_name says) for every bond broken since the last call.
  void update(const World& world, double strain);
  /// Writes the bonds broken so far (noted by update()) to `file`.
  void write_vtp(const World& world, const std::filesystem::path& file) const;
  /// The shear strain each bond was first seen broken at (NaN: intact when last seen), by bond.
  std::vector<double> strains() const;

 private:
  std::string strain_name_;
  std::vector<Vec3> seen_;  // per bond: (shear strain when first seen broken, 0, 0); NaN: not yet
};

}  // namespace dem::lab
