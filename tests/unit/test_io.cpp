// dem::io file output: atomic replacement, CSV round trips and VTK files parsed back. Every
// number is compared exactly: 17 significant digits make double -> text -> double the identity.
#include <catch2/catch.hpp>


#include <cmath>
#include <fstream>
#include <iterator>
#include <sstream>
#include <vector>

#include "dem/core/errors.hpp"
#include "dem/io/atomic_file.hpp"
#include "dem/io/csv.hpp"
#include "dem/io/vtk.hpp"

#include "support/temp_dir.hpp"

namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {

using dem::testing::TempDir;

std::string slurp(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void put(const fs::path& file, const std::string& text) { std::ofstream(file) << text; }

std::size_t entries_in(const fs::path& dir) {
  const auto count = std::distance(fs::directory_iterator(dir), fs::directory_iterator());
  return static_cast<std::size_t>(count);
}

// True if every <tag> has its </tag> in order; <?...?> and <.../> stand alone.
bool tags_balanced(const std::string& xml) {
  std::vector<std::string> open;
  for (auto lt = xml.find('<'); lt != std::string::npos; lt = xml.find('<', lt + 1)) {
    const auto gt = xml.find('>', lt);
    if (gt == std::string::npos) return false;
    const std::string tag = xml.substr(lt + 1, gt - lt - 1);
    if (tag.front() == '?' || tag.back() == '/') continue;
    const bool closing = tag.front() == '/';
    const std::string name = tag.substr(closing, tag.find_first_of(" \n") - closing);
    if (!closing) open.push_back(name);
    else if (open.empty() || open.back() != name) return false;
    else open.pop_back();
  }
  return open.empty();
}

std::string attribute(const std::string& xml, const std::string& name, std::size_t from = 0) {
  const auto start = xml.find(name + "=\"", from);
  if (start == std::string::npos) return "<missing>";
  const auto value = start + name.size() + 2;
  return xml.substr(value, xml.find('"', value) - value);
}

// The numbers inside <DataArray ... Name="name" ...> ... </DataArray>.
std::vector<double> data_array(const std::string& xml, const std::string& name) {
  const auto tag = xml.find("Name=\"" + name + "\"");
  if (tag == std::string::npos) return {};
  const auto begin = xml.find('>', tag) + 1;
  std::istringstream in(xml.substr(begin, xml.find("</DataArray>", begin) - begin));
  return {std::istream_iterator<double>(in), std::istream_iterator<double>()};
}

}  // namespace

TEST_CASE("write_atomically replaces the file and leaves no temporary", "[io]") {
  TempDir dir("atomic");
  const fs::path file = dir.path / "sub" / "deeper" / "out.txt";  // parents do not exist yet
  dem::io::write_atomically(file, [](std::ostream& out) { out << "first\n"; });
  dem::io::write_atomically(file, [](std::ostream& out) { out << "second\n"; });
  CHECK(slurp(file) == "second\n");
  CHECK(entries_in(file.parent_path()) == 1);

  const std::string bytes("a\0b\r\n\xff", 6);
  dem::io::write_atomically_binary(dir.path / "raw.bin", [&](std::ostream& out) { out << bytes; });
  CHECK(slurp(dir.path / "raw.bin") == bytes);
}

TEST_CASE("write_atomically keeps the old file when writing fails", "[io]") {
  TempDir dir("atomic_fail");
  const fs::path file = dir.path / "out.txt";
  put(file, "old\n");

  CHECK_THROWS_WITH(dem::io::write_atomically(file, [](std::ostream& out) {
    out << "partial";
    throw std::runtime_error("simulated crash");
  }), "simulated crash");
  CHECK(slurp(file) == "old\n");
  CHECK(entries_in(dir.path) == 1);

  CHECK_THROWS_WITH(dem::io::write_atomically(file, [](std::ostream& out) {
    out.setstate(std::ios::badbit);
  }), Contains(file.string()));
  CHECK(slurp(file) == "old\n");
  CHECK(entries_in(dir.path) == 1);

  // A regular file where a parent directory should be: the directory cannot be created.
  CHECK_THROWS_WITH(dem::io::write_atomically(file / "child.txt", [](std::ostream&) {}),
                    Contains((file / "child.txt").string()));
  CHECK_THROWS_AS(dem::io::write_atomically(dir.path, [](std::ostream&) {}), dem::InputError);
}

TEST_CASE("CsvTable saves values that read_csv reads back exactly", "[io][csv]") {
  TempDir dir("csv");
  dem::io::CsvTable table({"t_s", "tau_Pa", "porosity"});
  table.add_row({0.0, 0.1, 1.0 / 3.0});
  table.add_row({1e-300, -2.5e10, 3.141592653589793});
  table.save(dir.path / "log.csv");
  table.add_row({2.0, 4.9e-324, 0.7});  // denormal minimum: the hardest case for round trips
  table.save(dir.path / "log.csv");     // rewritten whole, not appended twice

  const auto data = dem::io::read_csv(dir.path / "log.csv");
  CHECK(data.columns == table.columns());
  CHECK(data.rows == table.rows());  // exact
  CHECK(data.column("porosity") == 2);
  CHECK(table.column_index("tau_Pa") == 1);
  CHECK(slurp(dir.path / "log.csv").rfind("t_s,tau_Pa,porosity\n0,0.10000000000000001,", 0) == 0);
}

TEST_CASE("CsvTable rejects bad columns and rows", "[io][csv]") {
  using dem::io::CsvTable;
  CHECK_THROWS_AS(CsvTable({}), dem::InputError);
  CHECK_THROWS_WITH(CsvTable({"a", ""}), Contains("empty"));
  CHECK_THROWS_WITH(CsvTable({"a", "b,c"}), Contains("b,c") && Contains("comma"));
  CHECK_THROWS_WITH(CsvTable({"a", "b", "a"}), Contains("'a'") && Contains("twice"));
  CsvTable table({"a", "b", "c"});
  CHECK_THROWS_WITH(table.add_row({1.0, 2.0}), Contains("2 values") && Contains("must have 3"));
  CHECK_THROWS_WITH(table.add_row({1.0, std::nan(""), 3.0}), Contains("'b'") && Contains("nan"));
  CHECK_THROWS_WITH(table.column_index("d"), Contains("'d'") && Contains("a, b, c"));
  CHECK(table.rows().empty());
}

TEST_CASE("A table that allows missing values writes NaN as nan and reads it back; infinities stay refused", "[io][csv]") {
  using dem::io::CsvTable;
  using dem::io::Missing;
  TempDir dir("csv_missing");
  CsvTable table({"a", "b"}, Missing::Allowed);
  table.add_row({1.5, std::nan("")});
  table.add_row({-std::nan(""), 2.0});  // the sign of a NaN is not kept: every missing value is "nan"
  CHECK_THROWS_WITH(table.add_row({1.0, HUGE_VAL}), Contains("'b'") && Contains("NaN (missing)"));
  table.save(dir.path / "t.csv");
  std::ifstream in(dir.path / "t.csv");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  CHECK(text == "a,b\n1.5,nan\nnan,2\n");
  const auto back = dem::io::read_csv(dir.path / "t.csv", Missing::Allowed);
  CHECK(back.rows[0][0] == 1.5);
  CHECK(std::isnan(back.rows[0][1]));
  CHECK(std::isnan(back.rows[1][0]));
  // Read by default rules, the same file is refused: a NaN there means the run went wrong.
  CHECK_THROWS_WITH(dem::io::read_csv(dir.path / "t.csv"), Contains("'nan'"));
  std::ofstream(dir.path / "inf.csv") << "a\ninf\n";
  CHECK_THROWS_WITH(dem::io::read_csv(dir.path / "inf.csv", Missing::Allowed), Contains("infinite"));
}

TEST_CASE("read_csv skips comments and blanks, trims spaces, accepts CRLF", "[io][csv]") {
  TempDir dir("csv_read");
  const fs::path file = dir.path / "in.csv";
  put(file, "# produced by hand\n\n  x , y \r\n1, 2.5\r\n  # mid comment\n-3e2 ,+4\n\n");
  const auto data = dem::io::read_csv(file);
  CHECK(data.columns == std::vector<std::string>{"x", "y"});
  CHECK(data.rows == std::vector<std::vector<double>>{{1.0, 2.5}, {-300.0, 4.0}});
}

TEST_CASE("read_csv errors name the file, the line and the problem", "[io][csv]") {
  TempDir dir("csv_errors");
  const fs::path file = dir.path / "bad.csv";
  const auto message_for = [&](const std::string& text) {
    put(file, text);
    try {
      dem::io::read_csv(file);
    } catch (const dem::InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK_THROWS_WITH(dem::io::read_csv(dir.path / "absent.csv"),
                    Contains("absent.csv") && Contains("does not exist"));
  CHECK_THAT(message_for("# only a comment\n\n"), Contains(file.string()) && Contains("empty"));
  CHECK_THAT(message_for("a,b\n1,2\n\n3\n"),
             Contains(file.string() + ":4:") && Contains("1 cells") && Contains("must have 2"));
  CHECK_THAT(message_for("a,b\n1,abc\n"), Contains(":2:") && Contains("'abc'") && Contains("'b'"));
  CHECK_THAT(message_for("a,b\n1,\n"), Contains(":2:") && Contains("not a number"));
  CHECK_THAT(message_for("a,b\n1,2x\n"), Contains("'2x'") && Contains("not a number"));
  CHECK_THAT(message_for("a,b\n1,+-2\n"), Contains("'+-2'") && Contains("not a number"));
  CHECK_THAT(message_for("a,b\nnan,1\n"), Contains("'nan'") && Contains("NaN or infinite"));
  CHECK_THAT(message_for("a,b\n1,-inf\n"), Contains("'-inf'") && Contains("NaN or infinite"));
  CHECK_THAT(message_for("a,b\n1,1e999\n"), Contains("'1e999'") && Contains("out of the range"));
  CHECK_THAT(message_for("a,a\n"), Contains(":1:") && Contains("twice"));
}

TEST_CASE("write_points_vtp writes points and arrays that parse back", "[io][vtk]") {
  TempDir dir("vtk_points");
  const fs::path file = dir.path / "balls.vtp";
  const std::vector<dem::Vec3> points{{0.0, 0.0, 0.0}, {0.1, -0.2, 0.3}, {1e-3, 2.0 / 3.0, 5.0}};
  const std::vector<double> radius{1e-3, 2e-3, 1.5e-3};  // m
  const std::vector<dem::Vec3> velocity{{1, 0, 0}, {0, 1, 0}, {0, 0, -9.81}};  // m/s
  dem::io::write_points_vtp(file, points, {{"radius", radius}}, {{"velocity", velocity}});

  const std::string xml = slurp(file);
  CHECK(tags_balanced(xml));
  CHECK(xml.find("<VTKFile type=\"PolyData\"") != std::string::npos);
  CHECK(attribute(xml, "NumberOfPoints") == "3");
  CHECK(attribute(xml, "NumberOfVerts") == "3");
  CHECK(data_array(xml, "radius") == radius);
  CHECK(data_array(xml, "velocity") == std::vector<double>{1, 0, 0, 0, 1, 0, 0, 0, -9.81});
  const auto points_at = xml.find("<Points>");
  std::istringstream in(xml.substr(xml.find('>', xml.find("<DataArray", points_at)) + 1));
  for (const auto& p : points) {
    dem::Vec3 read;
    in >> read.x() >> read.y() >> read.z();
    CHECK(read == p);
  }
  CHECK(data_array(xml, "connectivity") == std::vector<double>{0, 1, 2});
  CHECK(data_array(xml, "offsets") == std::vector<double>{1, 2, 3});
}

TEST_CASE("write_lines_vtp and write_triangles_vtp write their cells", "[io][vtk]") {
  TempDir dir("vtk_cells");
  const dem::Vec3 o(0, 0, 0), x(1, 0, 0), y(0, 1, 0), z(0, 0, 1);
  dem::io::write_lines_vtp(dir.path / "forces.vtp", {{o, x}, {y, z}},
                           {{"normal_force", {10.0, 0.25}}});
  const std::string lines = slurp(dir.path / "forces.vtp");
  CHECK(tags_balanced(lines));
  CHECK(attribute(lines, "NumberOfPoints") == "4");
  CHECK(attribute(lines, "NumberOfLines") == "2");
  CHECK(data_array(lines, "normal_force") == std::vector<double>{10.0, 0.25});
  CHECK(data_array(lines, "connectivity") == std::vector<double>{0, 1, 2, 3});
  CHECK(data_array(lines, "offsets") == std::vector<double>{2, 4});

  dem::io::write_triangles_vtp(dir.path / "wall.vtp", {o, x, y, z}, {{0, 1, 2}, {0, 2, 3}}, {{"wall", {0.0, 1.0}}});
  const std::string wall = slurp(dir.path / "wall.vtp");
  CHECK(tags_balanced(wall));
  CHECK(attribute(wall, "NumberOfPoints") == "4");
  CHECK(attribute(wall, "NumberOfPolys") == "2");
  CHECK(data_array(wall, "connectivity") == std::vector<double>{0, 1, 2, 0, 2, 3});
  CHECK(data_array(wall, "offsets") == std::vector<double>{3, 6});
  CHECK(data_array(wall, "wall") == std::vector<double>{0, 1});
}

TEST_CASE("VTK writers reject inconsistent input without writing", "[io][vtk]") {
  TempDir dir("vtk_errors");
  const fs::path file = dir.path / "bad.vtp";
  const std::vector<dem::Vec3> two{{0, 0, 0}, {1, 1, 1}};
  CHECK_THROWS_WITH(dem::io::write_points_vtp(file, two, {{"radius", {1.0, 2.0, 3.0}}}),
                    Contains("'radius'") && Contains("3 entries") && Contains("2"));
  CHECK_THROWS_WITH(dem::io::write_points_vtp(file, two, {}, {{"velocity", {dem::Vec3::Zero()}}}),
                    Contains("'velocity'") && Contains("1 entries"));
  CHECK_THROWS_WITH(dem::io::write_points_vtp(file, two, {{"r", {1, 2}}, {"r", {3, 4}}}),
                    Contains("r") && Contains("unique"));
  CHECK_THROWS_WITH(dem::io::write_points_vtp(file, two, {{"radius", {1.0, std::nan("")}}}),
                    Contains("radius") && Contains("finite"));
  CHECK_THROWS_WITH(dem::io::write_lines_vtp(file, {{two[0], two[1]}}, {{"force", {}}}),
                    Contains("'force'") && Contains("0 entries") && Contains("1"));
  CHECK_THROWS_WITH(dem::io::write_triangles_vtp(file, two, {{0, 1, 2}}),
                    Contains("triangle 0") && Contains("2") && Contains("[0, 2)"));
  CHECK_THROWS_WITH(dem::io::write_triangles_vtp(file, {two[0], two[1], {0, 1, 0}}, {{0, 1, 2}}, {{"wall", {0.0, 1.0}}}),
                    Contains("'wall'") && Contains("2 entries") && Contains("1"));
  CHECK_FALSE(fs::exists(file));
  CHECK(entries_in(dir.path) == 0);
}

TEST_CASE("PvdCollection lists snapshots relative to the .pvd file", "[io][vtk]") {
  TempDir dir("pvd");
  dem::io::PvdCollection series(dir.path / "run.pvd");
  series.add(0.0, dir.path / "frames" / "balls_0.vtp");
  series.add(2.5e-4, dir.path / "frames" / "balls_1.vtp");
  const std::string xml = slurp(dir.path / "run.pvd");
  CHECK(tags_balanced(xml));
  CHECK(attribute(xml, "type") == "Collection");
  const auto second = xml.find("<DataSet", xml.find("<DataSet") + 1);
  CHECK(attribute(xml, "timestep", second) == "0.00025000000000000001");
  CHECK(attribute(xml, "file", second) == "frames/balls_1.vtp");
  CHECK(series.entries().size() == 2);
  CHECK_THROWS_WITH(series.add(1e-4, dir.path / "late.vtp"),
                    Contains("0.0001") && Contains("previous"));
  CHECK_THROWS_AS(series.add(std::nan(""), dir.path / "x.vtp"), dem::InputError);
}
