#include "bench_system.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace dem::bench {

namespace {

/// x rounded to `digits` significant digits, as printf's %.<digits>g (the peers' parameter
/// script rounds the same way, through text).
double round_digits(double x, int digits) {
  return std::stod((std::ostringstream() << std::setprecision(digits) << x).str());
}

}  // namespace

SystemParams system_params(double d_min, double d_max) {
  SystemParams p;
  p.d_min = d_min;
  p.d_max = d_max;
  const double kn = normal_stiffness;
  const double m_min = density * pi / 6 * d_min * d_min * d_min;
  // E[d^3] for d uniform in [d_min, d_max]
  const double d3_mean = (std::pow(d_max, 4) - std::pow(d_min, 4)) / (4 * (d_max - d_min));
  const double m_mean = density * pi / 6 * d3_mean;
  const double tc = std::sqrt(m_min / kn);
  const double scale = std::pow(10.0, std::floor(std::log10(0.2 * tc)) - 1);
  p.time_step = round_digits(std::floor(0.2 * tc / scale) * scale, 2);
  p.gamma_n = round_digits(2 * 0.2 * std::sqrt(kn / (m_mean / 2)), 3);
  p.skin = 0.25 * d_min;
  return p;
}

std::shared_ptr<const ContactModel> bench_law(double gamma_n, double mu, double mu_r) {
  auto law = RollingLinearLaw::Params::constant(normal_stiffness, normal_stiffness, mu, mu_r);
  law.normal_damping_rate = gamma_n;
  law.shear_damping_rate = gamma_n;
  return make_contact_model<RollingLinearLaw>(law, "contact");
}

HertzMindlinParams bench_hertz_params(const std::vector<BallSpec>& balls, double mu, double mu_r, HertzDamping damping,
                                      HertzRolling rolling) {
  // The touching pairs by a sweep along x: each ball against those after it within two radii.
  std::vector<const BallSpec*> by_x;
  double r_max = 0.0;
  for (const BallSpec& b : balls) by_x.push_back(&b), r_max = std::max(r_max, b.radius);
  std::sort(by_x.begin(), by_x.end(), [](const BallSpec* a, const BallSpec* b) { return a->position.x() < b->position.x(); });
  double overlap_sum = 0.0, radius_sum = 0.0;
  std::size_t pairs = 0;
  for (std::size_t i = 0; i < by_x.size(); ++i)
    for (std::size_t j = i + 1; j < by_x.size() && by_x[j]->position.x() - by_x[i]->position.x() < 2 * r_max; ++j) {
      const double reach = by_x[i]->radius + by_x[j]->radius;
      const double overlap = reach - (by_x[j]->position - by_x[i]->position).norm();
      if (overlap <= 0.0) continue;
      overlap_sum += overlap;
      radius_sum += by_x[i]->radius * by_x[j]->radius / reach;
      ++pairs;
    }
  if (pairs == 0) throw InputError("--law hertz-mindlin: the packing has no touching balls to match the stiffness at");
  const double overlap = overlap_sum / static_cast<double>(pairs), r_eff = radius_sum / static_cast<double>(pairs);
  const double nu = 0.25;
  const double effective_modulus = 3.0 * normal_stiffness / (4.0 * std::sqrt(r_eff * overlap));  // 4/3 E* a = kn
  const double restitution = std::exp(-pi * 0.2 / std::sqrt(1.0 - 0.2 * 0.2));
  HertzMindlinParams p =
      HertzMindlinParams::material(effective_modulus * 2.0 * (1.0 - nu * nu), nu, restitution, mu, mu_r, damping);
  p.rolling = rolling;
  return p;
}

WallId add_cylinder_walls(World& world, double top_z, double side_top, int segments) {
  // Circumscribed polygon: its flat faces are tangent to the 35 mm circle, as the analytic wall.
  const double r_poly = cylinder_radius / std::cos(pi / segments);
  const double half = cylinder_radius + 0.0005;
  world.add_wall(make_facet_wall("side", geometry::make_cylinder_shell(Vec3(0, 0, -0.001), r_poly, side_top + 0.001, segments, true),
                                 Vec3::UnitX()));
  world.add_wall(make_facet_wall("bottom", geometry::make_rectangle(Vec3::Zero(), Vec3(half, 0, 0), Vec3(0, half, 0)), -Vec3::UnitZ()));
  return world.add_wall(
      make_facet_wall("top", geometry::make_rectangle(Vec3(0, 0, top_z), Vec3(half, 0, 0), Vec3(0, half, 0)), Vec3::UnitZ()));
}

WallId add_analytic_walls(World& world, double top_z) {
  const double plate_area = pi * cylinder_radius * cylinder_radius;
  world.add_wall(make_cylinder_wall("side", Vec3::Zero(), Vec3::UnitZ(), cylinder_radius,
                                    2 * pi * cylinder_radius * top_z));
  world.add_wall(make_plane_wall("bottom", Vec3::Zero(), -Vec3::UnitZ(), plate_area));
  return world.add_wall(make_plane_wall("top", Vec3(0, 0, top_z), Vec3::UnitZ(), plate_area));
}

double vertical_stress(const World& world, double top_z) {
  const auto& c = world.pair_contacts(ContactKind::BallBall);
  const auto& p = world.particles();
  double virial = 0.0;
  for (std::size_t k = 0; k < c.size(); ++k) {
    if (c.normal_force[k] <= 0.0) continue;
    const Vec3 d = p.x[static_cast<std::size_t>(c.second[k])] - p.x[static_cast<std::size_t>(c.first[k])];
    virial += d.z() * c.force[k].z();
  }
  return virial / (pi * cylinder_radius * cylinder_radius * top_z);
}

double Packing::header_value(const std::string& key) const {
  for (const auto& [k, v] : header)
    if (k == key) return v;
  return std::nan("");
}

Packing read_packing(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError("--packing = " + path + ": cannot open the file");
  Packing packing;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty()) continue;
    if (line[0] == '#') {
      std::istringstream fields(line.substr(1));
      std::string key;
      double value;
      if (fields >> key >> value) packing.header.emplace_back(key, value);
      continue;
    }
    std::istringstream fields(line);
    BallSpec b;
    if (!(fields >> b.position.x() >> b.position.y() >> b.position.z() >> b.radius))
      throw InputError(path + ":" + std::to_string(number) + ": expected 'x y z radius' (m), got '" + line + "'");
    b.density = density;
    packing.balls.push_back(b);
  }
  if (packing.balls.empty()) throw InputError("--packing = " + path + ": no balls in the file");
  // Packings made by other tools keep their values in <name>_info.txt ('key value' lines).
  const auto dot = path.rfind(".txt");
  std::ifstream info(path.substr(0, dot) + "_info.txt");
  while (std::getline(info, line)) {
    std::istringstream fields(line);
    std::string key;
    double value;
    if (fields >> key >> value && std::isnan(packing.header_value(key))) packing.header.emplace_back(key, value);
  }
  return packing;
}

}  // namespace dem::bench
