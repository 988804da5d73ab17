// Snapshots for ParaView: VTK XML PolyData (.vtp) files and a .pvd collection that strings them
// into a time series. PolyData covers everything a DEM run shows: balls as points (scaled into
// spheres by ParaView's Glyph filter from a "radius" array), contacts as line segments (the force
// network) and walls as triangles. ASCII format keeps the files diffable and dependency free; the
// values use 17 significant digits, so positions are exact. Every file is written atomically.
//
// NaN and inf are refused: VTK's ASCII reader cannot parse them and would reject the whole file.
#pragma once

#include <array>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "dem/core/math.hpp"

namespace dem::io {

/// One scalar per point, e.g. {"radius", radii} in m.
struct PointData {
  std::string name;
  std::vector<double> scalars;
};

/// One 3-vector per point, e.g. {"velocity", v} in m/s.
struct VectorData {
  std::string name;
  std::vector<Vec3> vectors;
};

/// One scalar per cell (segment or triangle), e.g. {"normal_force", f} in N.
struct CellData {
  std::string name;
  std::vector<double> scalars;
};

/// Writes points (m) with per-point scalar and vector arrays. Each array must have one entry per
/// point and a unique non-empty name; else dem::InputError naming the array and both counts.
void write_points_vtp(const std::filesystem::path& path, const std::vector<Vec3>& points,
                      const std::vector<PointData>& scalars = {},
                      const std::vector<VectorData>& vectors = {});

/// Writes line segments (end points in m), one cell per segment, with per-segment scalars.
void write_lines_vtp(const std::filesystem::path& path,
                     const std::vector<std::pair<Vec3, Vec3>>& segments,
                     const std::vector<CellData>& cell_scalars = {});

/// Writes a triangle mesh: vertices (m) and triangles as vertex indices (0-based), with
/// per-triangle scalars (e.g. {"wall", index of the wall each triangle belongs to}). An index
/// outside [0, vertices.size()) is a dem::InputError naming the triangle.
void write_triangles_vtp(const std::filesystem::path& path, const std::vector<Vec3>& vertices,
                         const std::vector<std::array<int, 3>>& triangles,
                         const std::vector<CellData>& cell_scalars = {});

/// A ParaView .pvd time series. Each add() rewrites the whole collection file atomically, so it
/// is valid (and loadable while the run continues) after every snapshot.
class PvdCollection {
 public:
  struct Entry {
    double time;                  // s
    std::filesystem::path file;   // as written into the .pvd: relative to its directory if possible
  };

  /// `pvd_path` is the collection file; nothing is written until the first add().
  explicit PvdCollection(std::filesystem::path pvd_path);

  /// Records that `file` holds the state at `time` (s) and rewrites the collection. Times must
  /// be finite and non-decreasing, else dem::InputError.
  void add(double time, const std::filesystem::path& file);

  const std::vector<Entry>& entries() const { return entries_; }

 private:
  std::filesystem::path pvd_path_;
  std::vector<Entry> entries_;
};

}  // namespace dem::io
