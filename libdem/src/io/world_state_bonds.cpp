// The bonds in a restart file (format 4 on): written as their arrays, in bond order; read back
// with every id, parameter, value and status a later step trusts checked first.
#include <cmath>
#include <string>

#include <dem/core/errors.hpp>
#include "world_state_reader.hpp"

namespace dem::checkpoint {


namespace {

std::vector<double> numbers(Reader& r, const std::string& field, std::size_t bonds) {
  std::vector<double> v = r.vec<double>(field);
  check_length(v.size(), bonds, field, "one per bond");
  for (std::size_t k = 0; k < v.size(); ++k)
    if (!std::isfinite(v[k])) refuse(field + "[" + std::to_string(k) + "]", v[k], "finite");
  return v;
}

std::vector<Vec3> vectors(Reader& r, const std::string& field, std::size_t bonds) {
  std::vector<Vec3> v = r.vec<Vec3>(field);
  check_length(v.size(), bonds, field, "one per bond");
  check_finite(v, field);
  return v;
}

}  // namespace

BondStore read_bonds(Reader& r, const ParticleStore& p) {
  BondStore b;
  b.first = r.vec<ParticleId>("bond first ids");
  const std::size_t n = b.first.size();
  b.second = r.vec<ParticleId>("bond second ids");
  check_length(b.second.size(), n, "bond second ids", "one per bond");
  b.radius = numbers(r, "bond radius", n);
  b.normal_stiffness = numbers(r, "bond normal_stiffness", n);
  b.shear_stiffness = numbers(r, "bond shear_stiffness", n);
  b.tensile_strength = numbers(r, "bond tensile_strength", n);
  b.cohesion = numbers(r, "bond cohesion", n);
  b.friction_angle = numbers(r, "bond friction_angle", n);
  b.normal_force = numbers(r, "bond normal_force", n);
  b.shear_force = vectors(r, "bond shear_force", n);
  b.twist_moment = numbers(r, "bond twist_moment", n);
  b.bend_moment = vectors(r, "bond bend_moment", n);
  b.status = r.vec<std::uint8_t>("bond status");
  check_length(b.status.size(), n, "bond status", "one per bond");
  const auto count = static_cast<ParticleId>(p.size());
  for (std::size_t k = 0; k < n; ++k) {
    const std::string what = "bond " + std::to_string(k);
    for (const ParticleId id : {b.first[k], b.second[k]}) {
      if (id < 0 || id >= count) refuse(what + " ball id", id, "in [0, " + std::to_string(count) + ")");
      if (p.is_pebble(p.index_of(id))) refuse(what + " ball id", id, "a free ball, not a pebble");
    }
    if (b.first[k] == b.second[k]) refuse(what + " ball ids", b.first[k], "two different balls");
    b.params(k).validate(what);
    if (b.status[k] > static_cast<std::uint8_t>(BondStatus::broken_shear))
      refuse(what + " status", static_cast<int>(b.status[k]), "0 (intact), 1 (broken in tension) or 2 (broken in shear)");
  }
  return b;
}

}  // namespace dem::checkpoint
