// ASCII STL reader and writer. The reader is a small tokenizer with a hand-written grammar, so
// that every error can name its line. Numbers go through std::from_chars and std::to_chars,
// which ignore the locale and make the round trip exact.
#include "dem/geometry/stl.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "dem/base/errors.hpp"
#include "dem/base/input_file.hpp"
#include "dem/geometry/triangle.hpp"

namespace dem::geometry {

namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// ASCII control characters other than whitespace only occur in binary files.
bool is_binary(char c) { return static_cast<unsigned char>(c) < 0x20 && !is_space(c); }

bool is_keyword(std::string_view token, std::string_view keyword) {
  const auto lower = [](char c) {
    return c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c;
  };
  return token.size() == keyword.size() &&
         std::equal(token.begin(), token.end(), keyword.begin(),
                    [&](char t, char k) { return lower(t) == k; });
}

std::optional<double> parse_number(std::string_view text) {
  // from_chars takes no leading '+', which some exporters write.
  if (text.size() > 1 && text[0] == '+' && text[1] != '-') text.remove_prefix(1);
  double value = 0.0;
  const auto result = std::from_chars(text.data(), text.data() + text.size(), value);
  if (result.ec != std::errc() || result.ptr != text.data() + text.size()) return std::nullopt;
  return value;
}

class StlParser {
 public:
  StlParser(std::istream& in, std::string file, double scale)
      : in_(in), file_(std::move(file)), scale_(scale) {}

  TriangleMesh parse() {
    const auto first = next_token();
    if (!first) fail(0, "file is empty: must start with \"solid\" (ASCII STL)");
    if (!is_keyword(*first, "solid")) {
      fail(line_number_, "first word = \"" + std::string(*first) +
                             "\": must be \"solid\" (only ASCII STL is supported, not binary)");
    }
    skip_rest_of_line();  // solid name
    while (true) {
      const std::string_view word = expect("\"facet\" or \"endsolid\"");
      if (is_keyword(word, "facet")) {
        read_facet();
      } else if (is_keyword(word, "endsolid")) {
        skip_rest_of_line();
        const auto after = next_token();
        if (!after) break;
        if (!is_keyword(*after, "solid")) unexpected(*after, "\"solid\" or end of file");
        skip_rest_of_line();
      } else {
        unexpected(word, "\"facet\" or \"endsolid\"");
      }
    }
    if (mesh_.triangles.empty()) fail(0, "no facets: must contain at least one facet");
    check_degenerate();
    return std::move(mesh_);  // indices are in range by construction
  }

 private:
  [[noreturn]] void fail(int line, const std::string& what) const {
    std::string where = "STL file \"" + file_ + "\"";
    if (line > 0) where += ", line " + std::to_string(line);
    throw InputError(where + ": " + what);
  }

  [[noreturn]] void unexpected(std::string_view word, const std::string& allowed) const {
    fail(line_number_, "word = \"" + std::string(word) + "\": must be " + allowed);
  }

  // Next whitespace-separated word; the view lives until the next call.
  std::optional<std::string_view> next_token() {
    while (true) {
      while (position_ < line_.size() && is_space(line_[position_])) ++position_;
      if (position_ < line_.size()) break;
      if (!std::getline(in_, line_)) return std::nullopt;
      ++line_number_;
      position_ = 0;
      if (std::any_of(line_.begin(), line_.end(), is_binary)) {
        fail(line_number_, "binary data: must be ASCII STL (binary STL is not supported)");
      }
    }
    const std::size_t start = position_;
    while (position_ < line_.size() && !is_space(line_[position_])) ++position_;
    return std::string_view(line_).substr(start, position_ - start);
  }

  void skip_rest_of_line() { position_ = line_.size(); }

  // Messages are built only on failure: these run for every word of the file.
  [[noreturn]] void end_of_file(const std::string& expected) const {
    fail(line_number_, "unexpected end of file: expected " + expected);
  }

  std::string_view expect(const char* allowed) {
    const auto word = next_token();
    if (!word) end_of_file(allowed);
    return *word;
  }

  void expect_keyword(std::string_view keyword) {
    const auto word = next_token();
    if (word && is_keyword(*word, keyword)) return;
    std::string allowed = "\"";  // appended, not "\"" + ...: GCC 12 -O3 warns falsely (-Wrestrict)
    allowed.append(keyword).push_back('"');
    if (!word) end_of_file(allowed);
    unexpected(*word, allowed);
  }

  Vec3 read_point(const char* what, bool must_be_finite) {
    Vec3 point;
    for (int axis = 0; axis < 3; ++axis) {
      const auto name = [&] { return std::string(what) + ' ' + "xyz"[axis] + " coordinate"; };
      const auto word = next_token();
      if (!word) end_of_file("a number (" + name() + ")");
      const auto value = parse_number(*word);
      if (!value) fail(line_number_, name() + " = \"" + std::string(*word) + "\": must be a number");
      if (must_be_finite && !std::isfinite(*value)) {
        fail(line_number_, name() + " = " + std::string(*word) + ": must be finite");
      }
      point[axis] = *value;
    }
    return point;
  }

  int vertex_index(const Vec3& point) {
    // std::map compares with <, so -0.0 and 0.0 count as the same coordinate, as they should.
    const std::array<double, 3> key{point.x(), point.y(), point.z()};
    const auto [it, inserted] = index_of_.try_emplace(key, static_cast<int>(mesh_.vertices.size()));
    if (inserted) mesh_.vertices.push_back(point);
    return it->second;
  }

  void read_facet() {
    const int facet_line = line_number_;
    expect_keyword("normal");
    read_point("facet normal", false);  // unused, see stl.hpp
    expect_keyword("outer");
    expect_keyword("loop");
    std::array<int, 3> triangle{};
    int count = 0;
    while (true) {
      const std::string_view word = expect("\"vertex\" or \"endloop\"");
      if (is_keyword(word, "endloop")) break;
      if (!is_keyword(word, "vertex")) unexpected(word, "\"vertex\" or \"endloop\"");
      const Vec3 point = scale_ * read_point("vertex", true);
      if (count < 3) triangle[count] = vertex_index(point);
      ++count;
    }
    if (count != 3) {
      fail(facet_line, "facet has " + std::to_string(count) + " vertices: must have exactly 3");
    }
    expect_keyword("endfacet");
    mesh_.triangles.push_back(triangle);
    facet_lines_.push_back(facet_line);
  }

  // Same test as TriangleMesh::validate, but naming the facet's line.
  void check_degenerate() const {
    const auto [low, high] = mesh_.bounding_box();
    const double diagonal = (high - low).norm();  // m
    if (diagonal == 0.0) {
      fail(facet_lines_[0], "facet 0: all vertices coincide at " + detail::format_point(low) +
                                "; a facet must have non-zero area");
    }
    for (std::size_t t = 0; t < mesh_.triangles.size(); ++t) {
      const auto& [i, j, k] = mesh_.triangles[t];
      try {
        validate_triangle(mesh_.vertices[i], mesh_.vertices[j], mesh_.vertices[k], diagonal);
      } catch (const InputError& e) {
        fail(facet_lines_[t], "facet " + std::to_string(t) + ": " + e.what());
      }
    }
  }

  std::istream& in_;
  std::string file_;
  double scale_;  // m per file unit
  std::string line_;
  std::size_t position_ = 0;
  int line_number_ = 0;
  TriangleMesh mesh_;
  std::map<std::array<double, 3>, int> index_of_;
  std::vector<int> facet_lines_;  // line of each facet's "facet" keyword
};

void write_number(std::ostream& out, double value) {
  std::array<char, 32> buffer{};  // the longest double, "-2.2250738585072014e-308", has 24
  const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  out << ' ';
  out.write(buffer.data(), result.ptr - buffer.data());
}

void write_point(std::ostream& out, const Vec3& p) {
  for (int axis = 0; axis < 3; ++axis) write_number(out, p[axis]);
  out << '\n';
}

}  // namespace

TriangleMesh read_stl_ascii(const std::filesystem::path& file, double scale) {
  require(std::isfinite(scale) && scale > 0.0, "STL scale", scale,
          "finite and > 0 (m per file unit, e.g. 1e-3 for millimetres)");
  require_input_file(file, "STL file", "an ASCII STL file", max_text_input_bytes);
  std::ifstream in(file);
  if (!in) throw InputError("STL file = \"" + file.string() + "\": must be readable");
  return StlParser(in, file.string(), scale).parse();
}

void write_stl_ascii(const std::filesystem::path& file, const TriangleMesh& mesh,
                     const std::string& solid_name) {
  require(solid_name.find_first_of("\r\n") == std::string::npos, "STL solid name",
          "\"" + solid_name + "\"", "a single line");
  require(!mesh.triangles.empty(), "STL mesh triangle count", 0, ">= 1");
  mesh.validate();
  std::ofstream out(file);
  if (!out) {
    throw InputError("STL output file = \"" + file.string() +
                     "\": must be writable (does its directory exist?)");
  }
  out << "solid " << solid_name << '\n';
  for (const auto& [i, j, k] : mesh.triangles) {
    const Vec3& a = mesh.vertices[i];
    const Vec3& b = mesh.vertices[j];
    const Vec3& c = mesh.vertices[k];
    out << "  facet normal";
    write_point(out, triangle_normal(a, b, c));
    out << "    outer loop\n";
    for (const Vec3* v : {&a, &b, &c}) {
      out << "      vertex";
      write_point(out, *v);
    }
    out << "    endloop\n  endfacet\n";
  }
  out << "endsolid " << solid_name << '\n';
  out.flush();
  if (!out) throw InputError("STL output file = \"" + file.string() + "\": writing failed");
}

}  // namespace dem::geometry
