// dem::geometry: closest point on a triangle, mesh builders and ASCII STL, checked against
// exact projections, closed-form polygon areas and brute-force sampling.
#include <catch2/catch.hpp>

#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "dem/core/errors.hpp"
#include "dem/geometry/mesh.hpp"
#include "dem/geometry/stl.hpp"
#include "dem/geometry/triangle.hpp"

using dem::pi;
using dem::Vec3;
using Catch::Matchers::Contains;
using namespace dem::geometry;

namespace {

// What the InputError thrown by f says, or a marker that f threw none.
template <class F>
std::string input_error_message(F&& f) {
  try {
    f();
  } catch (const dem::InputError& e) {
    return e.what();
  }
  return "<no InputError thrown>";
}

// A file in the temporary directory, removed at scope exit. The name mixes a random number with
// the clock, because CTest may run test cases as parallel processes.
class TempFile {
 public:
  explicit TempFile(const std::string& content = {}) {
    static std::random_device entropy;
    const auto ticks = std::chrono::steady_clock::now().time_since_epoch().count();
    path_ = std::filesystem::temp_directory_path() /
            ("libdem_test_geometry_" + std::to_string(entropy()) + "_" + std::to_string(ticks) +
             ".stl");
    std::ofstream(path_, std::ios::binary) << content;
  }
  ~TempFile() {
    std::error_code ignored;
    std::filesystem::remove(path_, ignored);
  }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

Vec3 vertex(const TriangleMesh& mesh, std::size_t t, int corner) {
  return mesh.vertices[mesh.triangles[t][corner]];
}

Vec3 normal_of(const TriangleMesh& mesh, std::size_t t) {
  return triangle_normal(vertex(mesh, t, 0), vertex(mesh, t, 1), vertex(mesh, t, 2));
}

}  // namespace

TEST_CASE("closest point on a triangle: exact face, edge and vertex results", "[geometry]") {
  struct Case {
    Vec3 p, expected;
    Feature feature;
    int index;
  };
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  const std::vector<Case> cases = {
      {{0.2, 0.3, 5.0}, {0.2, 0.3, 0.0}, Feature::Face, -1},    // above the interior: its foot
      {{0.25, 0.25, 0.0}, {0.25, 0.25, 0.0}, Feature::Face, -1},  // inside, in the plane
      {{0.5, -1.0, 2.0}, {0.5, 0.0, 0.0}, Feature::Edge, 0},    // beyond ab
      {{1.0, 1.0, -3.0}, {0.5, 0.5, 0.0}, Feature::Edge, 1},    // beyond bc
      {{-2.0, 0.4, 1.0}, {0.0, 0.4, 0.0}, Feature::Edge, 2},    // beyond ca
      {{2.0, 2.0, 0.0}, {0.5, 0.5, 0.0}, Feature::Edge, 1},     // in the plane, beyond bc
      {{0.5, 0.0, 0.0}, {0.5, 0.0, 0.0}, Feature::Edge, 0},     // on ab: edge wins over face
      {{-1.0, -1.0, 1.0}, a, Feature::Vertex, 0},
      {{2.0, -0.5, 0.0}, b, Feature::Vertex, 1},
      {{-0.5, 2.0, -1.0}, c, Feature::Vertex, 2},
      {{0.0, 1.0, 0.0}, c, Feature::Vertex, 2},  // on c itself
  };
  // The same cases after a similarity transform x -> s R x + shift, which keeps every region.
  const double s = 2.5;
  const dem::Mat3 rotation = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  const Vec3 shift(3.0, -1.0, 2.0);
  const auto move = [&](const Vec3& x) -> Vec3 { return s * (rotation * x) + shift; };

  for (const Case& k : cases) {
    INFO("p = " << detail::format_point(k.p));
    const ClosestPoint plain = closest_point_on_triangle(k.p, a, b, c);
    CHECK((plain.point - k.expected).norm() <= 1e-15);  // a few ulps of values <= 1
    CHECK(plain.feature == k.feature);
    CHECK(plain.index == k.index);

    const ClosestPoint moved = closest_point_on_triangle(move(k.p), move(a), move(b), move(c));
    CHECK((moved.point - move(k.expected)).norm() <= 1e-13);  // ulps of coordinates ~10
    const bool on_boundary = k.p == k.expected && k.feature != Feature::Face;
    if (!on_boundary) {  // a point on an edge or vertex may change label under rounding
      CHECK(moved.feature == k.feature);
      CHECK(moved.index == k.index);
    }
  }
}

TEST_CASE("closest point on a triangle agrees with dense sampling", "[geometry]") {
  std::mt19937 rng(20240611);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const auto random_point = [&](double half) {
    Vec3 p;
    for (int axis = 0; axis < 3; ++axis) p[axis] = half * unit(rng);  // fixed draw order
    return p;
  };
  const int n = 120;  // samples per edge
  std::array<int, 7> seen{};  // face, edges 0-2, vertices 0-2
  double worst_too_close = -1.0, worst_too_far = -1.0, worst_off_feature = 0.0;

  for (int tri = 0; tri < 20; ++tri) {
    const Vec3 a = random_point(1), b = random_point(1), c = random_point(1);
    if (triangle_area(a, b, c) < 0.05) continue;  // keep the sampling resolution meaningful
    std::vector<Vec3> samples;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) samples.push_back(a + (b - a) * i / n + (c - a) * j / n);
    // Every triangle point lies in a sub-triangle whose diameter is (longest edge)/n, so some
    // sample is within that distance of the exact closest point.
    const double h = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()}) / n;
    const Vec3 normal = triangle_normal(a, b, c);
    const std::array<Vec3, 3> corner{a, b, c};

    for (int k = 0; k < 200; ++k) {
      Vec3 p = random_point(2);
      if (k % 4 == 0) p -= normal * normal.dot(p - a);  // a quarter in the triangle's plane
      const ClosestPoint q = closest_point_on_triangle(p, a, b, c);
      const double exact = (p - q.point).norm();
      double sampled = 1e300;
      for (const Vec3& x : samples) sampled = std::min(sampled, (p - x).norm());
      worst_too_close = std::max(worst_too_close, exact - sampled);  // no sample may beat it
      worst_too_far = std::max(worst_too_far, sampled - exact - h);

      // The reported feature must hold the point, and p - q must be normal to that feature.
      double off = 0.0;
      if (q.feature == Feature::Vertex) {
        off = (q.point - corner[q.index]).norm();
        ++seen[4 + q.index];
      } else if (q.feature == Feature::Edge) {
        const Vec3 start = corner[q.index], edge = corner[(q.index + 1) % 3] - start;
        const double along = (q.point - start).dot(edge) / edge.squaredNorm();
        off = std::max({(q.point - start - along * edge).norm(), -along, along - 1.0,
                        std::abs((p - q.point).dot(edge.normalized()))});
        ++seen[1 + q.index];
      } else {
        const double area2 = 2.0 * triangle_area(a, b, c);
        for (int m = 0; m < 3; ++m) {  // barycentric coordinates must be >= 0
          const Vec3 e0 = corner[(m + 1) % 3] - q.point, e1 = corner[(m + 2) % 3] - q.point;
          off = std::max(off, -e0.cross(e1).dot(normal) / area2);
        }
        off = std::max(
            {off, std::abs(normal.dot(q.point - a)), (p - q.point).cross(normal).norm()});
        ++seen[0];
      }
      worst_off_feature = std::max(worst_off_feature, off);
    }
  }
  // 1e-12: rounding in coordinates of size ~2, far below the sampling resolution h ~ 0.02.
  CHECK(worst_too_close <= 1e-12);
  CHECK(worst_too_far <= 1e-12);
  CHECK(worst_off_feature <= 1e-12);
  for (int count : seen) CHECK(count > 0);  // every region was exercised
}

TEST_CASE("triangle area, normal and validation", "[geometry]") {
  const Vec3 a(1, 1, 1), b(3, 1, 1), c(1, 4, 1);
  CHECK(triangle_area(a, b, c) == Approx(3.0).epsilon(1e-15));  // legs 2 and 3
  CHECK((triangle_normal(a, b, c) - Vec3(0, 0, 1)).norm() <= 1e-15);
  CHECK((triangle_normal(a, c, b) - Vec3(0, 0, -1)).norm() <= 1e-15);  // right-hand rule
  CHECK_NOTHROW(validate_triangle(a, b, c, 1.0));

  CHECK_THAT(input_error_message([] { validate_triangle({0, 0, 0}, {1, 1, 1}, {2, 2, 2}, 1.0); }),
             Contains("degenerate") && Contains("c = (2, 2, 2)"));
  const Vec3 bad(0, std::nan(""), 0);
  CHECK_THAT(input_error_message([&] { validate_triangle(a, bad, c, 1.0); }),
             Contains("b = (0, nan, 0)") && Contains("must be finite"));
  // Legs of 1e-7 m: area 5e-15 m^2 is degenerate for a 1 m object, fine for a 1 um one.
  const Vec3 tiny_b(1e-7, 0, 0), tiny_c(0, 1e-7, 0);
  CHECK_THROWS_AS(validate_triangle(Vec3::Zero(), tiny_b, tiny_c, 1.0), dem::InputError);
  CHECK_NOTHROW(validate_triangle(Vec3::Zero(), tiny_b, tiny_c, 1e-6));
  CHECK_THAT(input_error_message([&] { validate_triangle(a, b, c, 0.0); }),
             Contains("length_scale = 0"));
}

TEST_CASE("discs: polygon area, normals and rim", "[geometry]") {
  const Vec3 centre(0.1, -0.2, 0.3), normal(1, 2, 2);  // |normal| = 3
  const double r = 0.035;                              // m
  for (int n : {3, 4, 7, 64, 1000}) {
    INFO("segments = " << n);
    const TriangleMesh disc = make_disc(centre, r, normal, n);
    REQUIRE(disc.triangles.size() == static_cast<std::size_t>(n));
    // Exact area of the regular n-gon; 1e-12 covers rounding in a sum of n terms.
    CHECK(disc.area() == Approx(0.5 * n * r * r * std::sin(2 * pi / n)).epsilon(1e-12));
    for (std::size_t t = 0; t < disc.triangles.size(); ++t) {
      CHECK((normal_of(disc, t) - normal / 3.0).norm() <= 1e-12);
    }
    for (std::size_t i = 1; i < disc.vertices.size(); ++i) {
      CHECK((disc.vertices[i] - centre).norm() == Approx(r).epsilon(1e-12));
      CHECK(std::abs((disc.vertices[i] - centre).dot(normal / 3.0)) <= 1e-12 * r);
    }
  }
  // The inscribed polygon falls short of pi r^2 by (2 pi/n)^2/6 = 6.6e-6 relative for n = 1000.
  const double polygon = make_disc(centre, r, normal, 1000).area();
  CHECK(polygon < pi * r * r);
  CHECK(polygon == Approx(pi * r * r).epsilon(7e-6));
}

TEST_CASE("rectangles, translation and merging", "[geometry]") {
  const Vec3 centre(1, 2, 3), half_u(0.3, 0.4, 0), half_v(0, 0, 0.2);
  TriangleMesh plate = make_rectangle(centre, half_u, half_v);
  CHECK(plate.area() == Approx(4 * 0.5 * 0.2).epsilon(1e-14));  // sides 2|u| by 2|v|
  for (std::size_t t = 0; t < 2; ++t) {
    CHECK((normal_of(plate, t) - Vec3(0.8, -0.6, 0)).norm() <= 1e-15);
  }
  auto [low, high] = plate.bounding_box();
  CHECK((low - Vec3(0.7, 1.6, 2.8)).norm() <= 1e-15);
  CHECK((high - Vec3(1.3, 2.4, 3.2)).norm() <= 1e-15);

  plate.translate(Vec3(-1, 0, 0.5));
  std::tie(low, high) = plate.bounding_box();
  CHECK((low - Vec3(-0.3, 1.6, 3.3)).norm() <= 1e-15);
  CHECK((high - Vec3(0.3, 2.4, 3.7)).norm() <= 1e-15);

  const TriangleMesh disc = make_disc(Vec3::Zero(), 0.5, Vec3::UnitZ(), 16);
  const TriangleMesh both = merge(disc, plate);
  CHECK(both.vertices.size() == disc.vertices.size() + 4);
  REQUIRE(both.triangles.size() == disc.triangles.size() + 2);
  CHECK(both.area() == Approx(disc.area() + plate.area()).epsilon(1e-15));
  for (std::size_t t = 0; t < 2; ++t) {
    for (int m = 0; m < 3; ++m) {
      CHECK(vertex(both, disc.triangles.size() + t, m) == vertex(plate, t, m));
    }
  }
  CHECK_NOTHROW(both.validate());
}

TEST_CASE("cylinder shells: area, normals and bounding box", "[geometry]") {
  const Vec3 base(0.01, -0.02, -0.005);
  const double r = 0.035, h = 0.02;  // m
  for (int n : {3, 8, 100}) {
    for (bool inward : {false, true}) {
      INFO("segments = " << n << ", inward = " << inward);
      const TriangleMesh shell = make_cylinder_shell(base, r, h, n, inward);
      const double x = pi / n;
      CHECK(shell.area() == Approx(2 * pi * r * h * std::sin(x) / x).epsilon(1e-12));
      // Each side's normal is radial at the side's middle angle, and the centroid's angle lies
      // within half a side (pi/n) of it.
      double worst = 1.0;
      for (std::size_t t = 0; t < shell.triangles.size(); ++t) {
        const Vec3 centroid = (vertex(shell, t, 0) + vertex(shell, t, 1) + vertex(shell, t, 2)) / 3;
        const Vec3 radial = Vec3(centroid.x() - base.x(), centroid.y() - base.y(), 0).normalized();
        const Vec3 normal = normal_of(shell, t);
        CHECK(std::abs(normal.z()) <= 1e-12);
        worst = std::min(worst, (inward ? -1.0 : 1.0) * normal.dot(radial));
      }
      CHECK(worst >= std::cos(x) - 1e-12);
    }
  }
  const auto [low, high] = make_cylinder_shell(base, r, h, 8, false).bounding_box();
  // 8 sides put vertices at 0, 90, 180 and 270 degrees, so the box is exactly +-r.
  CHECK((low - (base + Vec3(-r, -r, 0))).norm() <= 1e-15);
  CHECK((high - (base + Vec3(r, r, h))).norm() <= 1e-15);
}

TEST_CASE("mesh and builder input errors name the quantity", "[geometry]") {
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}};
  mesh.triangles = {{0, 1, 2}, {0, 1, 5}};
  CHECK_THAT(input_error_message([&] { mesh.validate(); }),
             Contains("mesh triangle 1 vertex index = 5") && Contains("[0, 4)"));
  mesh.triangles[1] = {0, 1, 3};  // collinear
  CHECK_THAT(input_error_message([&] { mesh.validate(); }),
             Contains("mesh triangle 1 (vertex indices 0, 1, 3)") && Contains("degenerate"));
  mesh.vertices[2].x() = INFINITY;
  CHECK_THAT(input_error_message([&] { mesh.validate(); }), Contains("mesh vertex 2"));
  CHECK_THROWS_AS(TriangleMesh{}.bounding_box(), dem::InputError);

  CHECK_THAT(input_error_message([] { make_disc(Vec3::Zero(), 0.0, Vec3::UnitZ(), 8); }),
             Contains("disc radius = 0"));
  CHECK_THAT(input_error_message([] { make_disc(Vec3::Zero(), 1.0, Vec3::Zero(), 8); }),
             Contains("disc normal = (0, 0, 0)"));
  CHECK_THAT(input_error_message([] { make_disc(Vec3::Zero(), 1.0, Vec3::UnitZ(), 2); }),
             Contains("disc segments = 2"));
  CHECK_THAT(input_error_message([] { make_cylinder_shell(Vec3::Zero(), 1.0, -1.0, 8, true); }),
             Contains("cylinder height = -1"));
  CHECK_THAT(input_error_message(
                 [] { make_rectangle(Vec3::Zero(), Vec3::UnitX(), Vec3(1, 1, 0)); }),
             Contains("perpendicular"));
  CHECK_THAT(input_error_message([] { make_rectangle(Vec3::Zero(), Vec3::UnitX(), Vec3::Zero()); }),
             Contains("rectangle |half_v| = 0"));
}

TEST_CASE("STL: write then read gives the same triangles exactly", "[geometry]") {
  const TriangleMesh mesh = merge(make_cylinder_shell(Vec3(0.1, 0.2, 0.3), 0.035, 0.02, 24, true),
                                  make_rectangle(Vec3(1, 1, 1), Vec3(0.1, 0, 0), Vec3(0, 0.3, 0)));
  const TempFile file;
  write_stl_ascii(file.path(), mesh, "ring and plate");
  const TriangleMesh back = read_stl_ascii(file.path());
  // All vertices of `mesh` are distinct and used, so merging recovers as many.
  CHECK(back.vertices.size() == mesh.vertices.size());
  REQUIRE(back.triangles.size() == mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int m = 0; m < 3; ++m) CHECK(vertex(back, t, m) == vertex(mesh, t, m));  // bit-exact
  }
}

TEST_CASE("STL: hand-written files, vertex merging and unit scale", "[geometry]") {
  // A 10 mm square as two facets; upper-case keywords, CRLF endings, zero normals and several
  // spellings of the same numbers, all of which must merge into 4 vertices.
  const TempFile file(
      "solid square\r\n facet normal 0 0 0\r\n  outer loop\r\n   vertex 0 0 0\r\n"
      "   vertex 10 0 0\r\n   vertex 10 10 -0\r\n  endloop\r\n endfacet\r\n"
      " FACET NORMAL 0 0 1\r\n  OUTER LOOP\r\n   VERTEX -0.0 0 0\r\n   VERTEX 1e1 +10.0 0\r\n"
      "   VERTEX 0 10 0\r\n  ENDLOOP\r\n ENDFACET\r\nENDSOLID square\r\n"
      "solid second\nfacet normal 0 0 1 outer loop vertex 0 0 1 vertex 1 0 1 vertex 0 1 1 endloop\n"
      "endfacet\nendsolid\n");
  const TriangleMesh mesh = read_stl_ascii(file.path(), 1e-3);  // mm -> m
  CHECK(mesh.vertices.size() == 7);
  REQUIRE(mesh.triangles.size() == 3);
  CHECK(mesh.triangles[0][0] == mesh.triangles[1][0]);  // shared diagonal
  CHECK(mesh.triangles[0][2] == mesh.triangles[1][1]);
  for (std::size_t t = 0; t < 3; ++t) CHECK(normal_of(mesh, t) == Vec3::UnitZ());
  CHECK(mesh.area() == Approx(1e-4 + 0.5e-6).epsilon(1e-12));  // (10 mm)^2 + half of (1 mm)^2
  const auto [low, high] = mesh.bounding_box();
  CHECK((high - Vec3(0.01, 0.01, 0.001)).norm() <= 1e-18);
  CHECK(low == Vec3::Zero());
}

TEST_CASE("STL: errors name the file and the line", "[geometry]") {
  const std::string header = "solid s\nfacet normal 0 0 1\n  outer loop\n";  // lines 1-3
  const std::string tail = "  endloop\nendfacet\nendsolid s\n";
  const auto read_error = [](const std::string& content) {
    const TempFile file(content);
    const std::string message = input_error_message([&] { read_stl_ascii(file.path()); });
    CHECK_THAT(message, Contains(file.path().filename().string()));
    return message;
  };
  CHECK_THAT(read_error(""), Contains("file is empty"));
  CHECK_THAT(read_error("hello world\n"), Contains("line 1") && Contains("first word = \"hello\""));
  const std::string binary("solid x\x01\x02\0\0\n", 12);  // as in a binary STL header
  CHECK_THAT(read_error(binary), Contains("line 1") && Contains("binary"));
  CHECK_THAT(read_error(header + "vertex 0 0 0\nvertex 1 0 0\nvertex 0 1 zero\n" + tail),
             Contains("line 6") && Contains("vertex z coordinate = \"zero\": must be a number"));
  CHECK_THAT(read_error(header + "vertex 0 0 0\nvertex 1 inf 0\nvertex 0 1 0\n" + tail),
             Contains("line 5") && Contains("must be finite"));
  CHECK_THAT(read_error(header + "vertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nvertex 1 1 0\n" + tail),
             Contains("line 2") && Contains("facet has 4 vertices: must have exactly 3"));
  CHECK_THAT(read_error(header + "vertex 0 0 0\nvertex 1 0 0\n" + tail),
             Contains("line 2") && Contains("facet has 2 vertices"));
  CHECK_THAT(read_error(header + "vertex 0 0 0\nvertex 1 0 0\n"),
             Contains("line 5") && Contains("unexpected end of file"));
  CHECK_THAT(read_error("solid s\nfacet normal 0 0 1\n  outer loops\n"),
             Contains("line 3") && Contains("word = \"loops\": must be \"loop\""));
  CHECK_THAT(read_error(header + "vertex 0 0 0\nvertex 1 1 1\nvertex 2 2 2\n" + tail),
             Contains("line 2") && Contains("facet 0") && Contains("degenerate"));
  CHECK_THAT(read_error("solid s\nendsolid s\n"), Contains("no facets"));

  const std::filesystem::path missing = TempFile().path();  // removed again at once
  CHECK_THAT(input_error_message([&] { read_stl_ascii(missing); }),
             Contains(missing.string()) && Contains("does not exist"));
  CHECK_THAT(input_error_message([&] { read_stl_ascii(missing, 0.0); }), Contains("STL scale = 0"));
  const TriangleMesh plate = make_rectangle(Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY());
  const auto no_dir = missing / "no_such_dir" / "x.stl";
  CHECK_THAT(input_error_message([&] { write_stl_ascii(no_dir, plate); }),
             Contains("must be writable"));
  CHECK_THROWS_AS(write_stl_ascii(missing, TriangleMesh{}), dem::InputError);
}
