// ASCII STL input and output for facet walls.
//
// Why: plates and rings of a test apparatus are often drawn in CAD and exported as STL. Only
// the ASCII form is supported. It is the form people inspect and edit by hand, and binary STL
// would need a second parser for the same data. A binary file is reported as such.
//
// STL stores three vertices with every facet. The reader merges vertices whose coordinates are
// exactly equal after parsing, which recovers the shared-vertex mesh that facet walls need. There
// is no distance tolerance, so no length scale has to be guessed. Orientation comes from the
// vertex order (right-hand rule), as the STL format defines it. The stored facet normals must
// be numbers but are otherwise ignored, because some exporters write them as zero.
#pragma once

#include <filesystem>
#include <string>

#include "dem/geometry/mesh.hpp"

namespace dem::geometry {

/// Reads an ASCII STL file ("solid name" ... "endsolid name"; several solids are concatenated).
/// Keywords are matched case-insensitively. Coordinates are multiplied by scale (m per file
/// unit; 1e-3 for a file in millimetres). Triangle t of the result is the file's facet t,
/// counting from 0.
/// Throws InputError naming the file, and the line where one applies, for: a missing file, a
/// file that is not ASCII STL, a bad or non-finite number, a facet without exactly 3 vertices,
/// an unexpected keyword or end of file, a file without facets, or a degenerate facet.
TriangleMesh read_stl_ascii(const std::filesystem::path& file, double scale = 1.0);

/// Writes mesh (m) as ASCII STL, with normals from the vertex order. Numbers are written in
/// their shortest form that reads back to the same double, so a round trip is exact.
/// Throws InputError if the mesh is invalid or empty, if solid_name spans several lines, or if
/// the file cannot be written.
void write_stl_ascii(const std::filesystem::path& file, const TriangleMesh& mesh,
                     const std::string& solid_name = "libdem");

}  // namespace dem::geometry
