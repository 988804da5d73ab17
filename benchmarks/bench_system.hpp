// The peers' benchmark system, shared by dem-bench's timed run and its packing generator: the
// 70 mm cylinder, the contact law (constant kn = kt, Coulomb friction, rolling resistance
// kr = kt Rbar^2, mass-proportional dashpots), the time step and dashpot rate derived from the
// radii, the packing file format and the vertical stress measured as the peers measure it.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <dem/dem.hpp>

namespace dem::bench {

constexpr double cylinder_radius = 0.035;  // m
constexpr double density = 2650.0;         // kg/m^3
constexpr double normal_stiffness = 7e4;   // N/m, also the shear stiffness
constexpr double friction = 0.5;
constexpr double rolling_friction = 0.17;
constexpr double wall_speed = 0.005;  // m/s, top plate of the timed run

/// Time step, dashpot rate and skin for balls with diameters in [d_min, d_max]: dt = 0.2
/// sqrt(m_min / kn) rounded down to 2 significant digits; gamma_n (1/s) for damping ratio 0.2
/// between two balls of the mean mass of diameters uniform in [d_min, d_max], rounded to 3
/// digits; skin a quarter of d_min.
struct SystemParams {
  double d_min = 0, d_max = 0, time_step = 0, gamma_n = 0, skin = 0;
};
SystemParams system_params(double d_min, double d_max);

/// The benchmark's law on every contact kind, with the given friction (the generator grows and
/// compresses the packing without friction, then switches it on with retune_contact_model).
std::shared_ptr<const ContactModel> bench_law(double gamma_n, double mu, double mu_r);

/// Hertz-Mindlin (LIGGGHTS damping) in the place of bench_law, to time one law against the other:
/// Young's modulus such that the Hertz secant stiffness F_n / delta at the packing's mean
/// ball-ball overlap and effective radius is the benchmark's kn (the packing was made with kn, so
/// its forces stay about the same), Poisson's ratio 0.25, the restitution of bench_law's damping
/// ratio 0.2 (0.527), the same friction and rolling friction. `balls`: the packing. `damping`:
/// LIGGGHTS's dashpot (the default) or LAMMPS's Tsuji dashpot, the peer compare-peers runs it against.
HertzMindlinParams bench_hertz_params(const std::vector<BallSpec>& balls, double mu, double mu_r,
                                      HertzDamping damping = HertzDamping::liggghts,
                                      HertzRolling rolling = HertzRolling::epsd);

/// Side wall (a circumscribed polygon of `segments` facets, from z = -1 mm to side_top), bottom
/// plane z = 0 and a top plane at top_z; returns the top wall's id.
WallId add_cylinder_walls(World& world, double top_z, double side_top, int segments);
/// The same system's walls as analytic surfaces (the peers' own walls): a cylinder of the 35 mm
/// radius, a bottom plane at z = 0 and a top plane at top_z. Returns the top plane's id.
WallId add_analytic_walls(World& world, double top_z);

/// Ball-ball contact virial sum_c d_z F_z over the cylinder volume below top_z, Pa (compression
/// positive), as the peers' `compute stress/atom` summed over the atoms.
double vertical_stress(const World& world, double top_z);

/// A packing file: '# key value' header lines (written by the generator) and 'x y z radius' (m)
/// lines. header_value() is NaN for a missing key.
struct Packing {
  std::vector<BallSpec> balls;
  std::vector<std::pair<std::string, double>> header;
  double header_value(const std::string& key) const;
};
/// Reads a packing; a missing header key is also looked up in '<name>_info.txt' beside the file
/// (the format of packings made by other tools).
Packing read_packing(const std::string& path);

/// Version of the generator's recipe, written into every generated file ('# recipe N'): a change
/// to the recipe raises it, so that compare-peers remakes the packings it cached.
constexpr int packing_recipe = 1;

/// Options of `dem-bench --generate`.
struct GenerateOptions {
  std::string size;    // 1750, 14k or 112k (or 4D, 2D, 1D)
  std::string out;     // packing file to write
  unsigned long long seed = 1;
  int threads = 1;
};
/// Makes the benchmark packing (recipe in packing_generator.cpp), writes it and prints progress.
void generate_packing(const GenerateOptions& options);

}  // namespace dem::bench
