// VTK XML PolyData writer. All three kinds of file share one writer: points plus one kind of
// cell (Verts, Lines or Polys) given as connectivity and offsets, as the format stores them.
// Points get Verts cells too, so ParaView shows them without a Glyph filter.
#include "dem/io/vtk.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <locale>
#include <ostream>
#include <set>

#include "dem/core/errors.hpp"
#include "dem/io/atomic_file.hpp"

namespace dem::io {
namespace {

namespace fs = std::filesystem;

std::string xml_escape(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

void check_array(const std::string& name, std::size_t count, std::size_t expected,
                 const std::string& per, std::set<std::string>& seen) {
  require(!name.empty(), "VTK data array name", "\"\"", "non-empty");
  require(seen.insert(name).second, "VTK data array name", name, "unique within one file");
  if (count != expected)
    throw InputError("VTK data array '" + name + "' has " + std::to_string(count) +
                     " entries: must have one per " + per + ", i.e. " + std::to_string(expected));
}

void check_finite(const std::string& array, std::size_t index, double value) {
  if (!std::isfinite(value))
    require(false, "VTK array '" + array + "' entry " + std::to_string(index), value,
            "finite (VTK cannot read NaN or inf)");
}

void write_scalars(std::ostream& out, const std::string& name, const std::vector<double>& values) {
  for (std::size_t i = 0; i < values.size(); ++i) check_finite(name, i, values[i]);
  out << "        <DataArray type=\"Float64\" Name=\"" << xml_escape(name)
      << "\" format=\"ascii\">\n";
  for (std::size_t i = 0; i < values.size(); ++i)
    out << (i % 6 == 0 ? "          " : " ") << values[i] << (i % 6 == 5 ? "\n" : "");
  if (values.size() % 6 != 0) out << '\n';
  out << "        </DataArray>\n";
}

void write_vectors(std::ostream& out, const std::string* name, const std::vector<Vec3>& values) {
  const std::string label = name ? *name : std::string("points");
  for (std::size_t i = 0; i < values.size(); ++i)
    for (int k = 0; k < 3; ++k) check_finite(label, i, values[i][k]);
  out << "        <DataArray type=\"Float64\"";
  if (name) out << " Name=\"" << xml_escape(*name) << "\"";
  out << " NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (const auto& v : values) out << "          " << v.x() << ' ' << v.y() << ' ' << v.z() << '\n';
  out << "        </DataArray>\n";
}

void write_ints(std::ostream& out, const char* name, const std::vector<std::int64_t>& values) {
  out << "        <DataArray type=\"Int64\" Name=\"" << name << "\" format=\"ascii\">\n";
  for (std::size_t i = 0; i < values.size(); ++i)
    out << (i % 12 == 0 ? "          " : " ") << values[i] << (i % 12 == 11 ? "\n" : "");
  if (values.size() % 12 != 0) out << '\n';
  out << "        </DataArray>\n";
}

struct Cells {
  std::string kind;  // "Verts", "Lines" or "Polys"
  std::vector<std::int64_t> connectivity;
  std::vector<std::int64_t> offsets;  // end of each cell in connectivity
};

void write_polydata(const fs::path& path, const std::vector<Vec3>& points, const Cells& cells,
                    const std::vector<PointData>& point_scalars,
                    const std::vector<VectorData>& point_vectors,
                    const std::vector<CellData>& cell_scalars) {
  std::set<std::string> seen;
  for (const auto& a : point_scalars)
    check_array(a.name, a.scalars.size(), points.size(), "point", seen);
  for (const auto& a : point_vectors)
    check_array(a.name, a.vectors.size(), points.size(), "point", seen);
  for (const auto& a : cell_scalars)
    check_array(a.name, a.scalars.size(), cells.offsets.size(), "cell", seen);

  write_atomically(path, [&](std::ostream& out) {
    out.imbue(std::locale::classic());
    out.precision(std::numeric_limits<double>::max_digits10);
    out << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"PolyData\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
        << "  <PolyData>\n    <Piece NumberOfPoints=\"" << points.size() << '"';
    for (const char* kind : {"Verts", "Lines", "Strips", "Polys"})
      out << " NumberOf" << kind << "=\"" << (cells.kind == kind ? cells.offsets.size() : 0) << '"';
    out << ">\n      <PointData";
    // The first arrays become ParaView's active ones (what Glyph scales and orients by).
    if (!point_scalars.empty())
      out << " Scalars=\"" << xml_escape(point_scalars.front().name) << '"';
    if (!point_vectors.empty())
      out << " Vectors=\"" << xml_escape(point_vectors.front().name) << '"';
    out << ">\n";
    for (const auto& a : point_scalars) write_scalars(out, a.name, a.scalars);
    for (const auto& a : point_vectors) write_vectors(out, &a.name, a.vectors);
    out << "      </PointData>\n      <CellData";
    if (!cell_scalars.empty()) out << " Scalars=\"" << xml_escape(cell_scalars.front().name) << '"';
    out << ">\n";
    for (const auto& a : cell_scalars) write_scalars(out, a.name, a.scalars);
    out << "      </CellData>\n      <Points>\n";
    write_vectors(out, nullptr, points);
    out << "      </Points>\n      <" << cells.kind << ">\n";
    write_ints(out, "connectivity", cells.connectivity);
    write_ints(out, "offsets", cells.offsets);
    out << "      </" << cells.kind << ">\n    </Piece>\n  </PolyData>\n</VTKFile>\n";
  });
}

}  // namespace

void write_points_vtp(const fs::path& path, const std::vector<Vec3>& points,
                      const std::vector<PointData>& scalars,
                      const std::vector<VectorData>& vectors) {
  Cells cells{"Verts", {}, {}};
  for (std::size_t i = 0; i < points.size(); ++i) {
    cells.connectivity.push_back(static_cast<std::int64_t>(i));
    cells.offsets.push_back(static_cast<std::int64_t>(i + 1));
  }
  write_polydata(path, points, cells, scalars, vectors, {});
}

void write_lines_vtp(const fs::path& path, const std::vector<std::pair<Vec3, Vec3>>& segments,
                     const std::vector<CellData>& cell_scalars) {
  std::vector<Vec3> points;
  Cells cells{"Lines", {}, {}};
  for (const auto& [a, b] : segments) {
    points.push_back(a);
    points.push_back(b);
    cells.connectivity.push_back(static_cast<std::int64_t>(points.size() - 2));
    cells.connectivity.push_back(static_cast<std::int64_t>(points.size() - 1));
    cells.offsets.push_back(static_cast<std::int64_t>(points.size()));
  }
  write_polydata(path, points, cells, {}, {}, cell_scalars);
}

void write_triangles_vtp(const fs::path& path, const std::vector<Vec3>& vertices,
                         const std::vector<std::array<int, 3>>& triangles,
                         const std::vector<CellData>& cell_scalars) {
  Cells cells{"Polys", {}, {}};
  const auto vertex_count = static_cast<std::int64_t>(vertices.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (const int index : triangles[t]) {
      require(index >= 0 && index < vertex_count,
              "vertex index of triangle " + std::to_string(t), index,
              "in [0, " + std::to_string(vertex_count) + ") (the number of vertices)");
      cells.connectivity.push_back(index);
    }
    cells.offsets.push_back(static_cast<std::int64_t>(cells.connectivity.size()));
  }
  write_polydata(path, vertices, cells, {}, {}, cell_scalars);
}

PvdCollection::PvdCollection(fs::path pvd_path) : pvd_path_(std::move(pvd_path)) {
  require(!pvd_path_.empty() && pvd_path_.has_filename(), "PVD collection path",
          pvd_path_.string(), "a file name");
}

void PvdCollection::add(double time, const fs::path& file) {
  require(std::isfinite(time), "PVD snapshot time (s)", time, "finite");
  if (!entries_.empty())
    require(time >= entries_.back().time, "PVD snapshot time (s)", time,
            ">= the previous snapshot time " + std::to_string(entries_.back().time));
  // ParaView resolves relative names against the .pvd's directory, so the output folder can move.
  const fs::path base = fs::absolute(pvd_path_).parent_path().lexically_normal();
  const fs::path absolute_file = fs::absolute(file).lexically_normal();
  fs::path relative = absolute_file.lexically_relative(base);
  entries_.push_back({time, relative.empty() ? absolute_file : relative});

  write_atomically(pvd_path_, [this](std::ostream& out) {
    out.imbue(std::locale::classic());
    out.precision(std::numeric_limits<double>::max_digits10);
    out << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
        << "  <Collection>\n";
    for (const auto& entry : entries_)
      out << "    <DataSet timestep=\"" << entry.time << "\" group=\"\" part=\"0\" file=\""
          << xml_escape(entry.file.generic_string()) << "\"/>\n";
    out << "  </Collection>\n</VTKFile>\n";
  });
}

}  // namespace dem::io
