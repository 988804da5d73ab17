// Snapshots of a run for ParaView and for plotting scripts: the study's force-network pictures
// (contacts in the slab |y| < 2 mm), incremental displacement vectors between snapshots (front
// and side views) and the apparatus around them.
//
// Each write(world, label, time, shear_strain) puts into the output folder:
//   balls_<label>.vtp     free balls (not pebbles) as points: radius (m), id, velocity (m/s),
//                         displacement (m) since the previous snapshot
//   balls_<label>.csv     id,x,y,z,radius,ux,uy,uz,vx,vy,vz   (m, m, m/s)
//   contacts_<label>.vtp  touching ball-ball contacts as segments between the two centres, with
//                         cell data normal_force (N, elastic, compression positive) and
//                         force_magnitude (N, |normal + tangential|)
//   contacts_<label>.csv  x1,y1,z1,x2,y2,z2,cx,cy,cz,normal_force,force_x,force_y,force_z
//                         (centres of balls 1 and 2, contact point c, in m; forces in N, the
//                         force being the one ball 2 receives)
//   walls_<label>.vtp     the triangles of every facet wall at their current position, with cell
//                         data wall (the WallId)
//   pebbles_<label>.vtp   the pebbles of the clumps (the rings) as points: radius (m), clump
// and, for a World with bonds (a cemented specimen; a plain one writes neither):
//   bonds_<label>.vtp     the intact bonds as segments between the two centres, with cell data
//                         normal_force (N, tension positive), shear_force, twist_moment and
//                         bend_moment (magnitudes, N and N m) and radius (m, of the bond's disc)
//   bonds_<label>.csv     first_id,second_id,radius,normal_force,shear_x,shear_y,shear_z,twist_moment,
//                         bend_x,bend_y,bend_z   (the loads on the second ball; m, N, N m)
//   broken_bonds_<label>.vtp  the bonds broken so far, when the caller passes its BrokenBondLog
// and rewrites balls.pvd, contacts.pvd, walls.pvd and pebbles.pvd (and bonds.pvd, broken_bonds.pvd)
// (ParaView time series, time = the `time` argument) and the index snapshots.csv:
// label,time_s,shear_strain,balls,contacts.
// Every file is written atomically. Rows of the CSVs are sorted by ball id, so two snapshots of
// the same run line up row by row.
//
// Displacements: position minus the position of the same ball (ParticleStore::id, which the
// engine's re-sorting of storage does not change) at the previous snapshot; zero at a ball's
// first snapshot. The writer therefore holds the last positions (one Vec3 per ball); resume()
// restores them after a restart. Velocities are the engine's, half a step behind positions.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <unordered_map>
#include <vector>

#include <dem/core/world.hpp>
#include <dem/io/vtk.hpp>
#include <dem/lab/toolkit/broken_bonds.hpp>

namespace dem::lab {

class SnapshotWriter {
 public:
  /// `dir` is created (with parents) at the first write. An empty path is a dem::InputError.
  explicit SnapshotWriter(std::filesystem::path dir);

  /// Writes one snapshot. Throws dem::InputError, before writing anything, if `label` is empty,
  /// has a character other than letters, digits, '_', '-', '.' (it becomes part of file names),
  /// or was used by an earlier snapshot of this writer; if time (s) is not finite or is less
  /// than the previous snapshot's; or if shear_strain (-) is not finite. `broken_bonds`: a
  /// cemented run's log of its broken bonds, written beside the snapshot (none: not written).
  void write(const World& world, const std::string& label, double time, double shear_strain,
             const BrokenBondLog* broken_bonds = nullptr);

  /// Continues the snapshots of an earlier run in the same folder (a resumed simulation): keeps
  /// the first `snapshots` rows of snapshots.csv, deletes the files of later ones, rebuilds the
  /// .pvd collections and reloads the ball positions of the last kept snapshot for the next
  /// displacements. A missing index is an empty series. Throws dem::InputError if the index is
  /// malformed or holds fewer snapshots than asked.
  void resume(std::size_t snapshots);

  /// Number of snapshots written (including those kept by resume()).
  std::size_t snapshots() const { return index_.size(); }

  const std::filesystem::path& directory() const { return dir_; }
  /// Every file of the snapshots written or kept so far: the index, the .pvd collections and
  /// each snapshot's .vtp and .csv files, bond files included (a run lists them in its manifest).
  std::vector<std::filesystem::path> files() const;

 private:
  struct IndexRow {
    std::string label;
    double time;          // s
    double shear_strain;  // -
    std::size_t balls, contacts;
    bool bonds = false, broken_bonds = false;  // bonds_<label>, broken_bonds_<label> written
  };

  void save_index() const;
  void add_to_collections(const IndexRow& row);

  std::filesystem::path dir_;
  std::vector<IndexRow> index_;
  std::vector<io::PvdCollection> collections_;          // balls, contacts, walls, pebbles
  io::PvdCollection bond_collection_, broken_bond_collection_;  // a cemented run's
  std::unordered_map<ParticleId, Vec3> last_position_;  // m, by ball id, at the last snapshot
};

}  // namespace dem::lab
