// Snapshot files: gathers balls, contacts, walls and pebbles from the World in ball-id order and
// hands them to the io writers.
#include <dem/lab/toolkit/snapshots.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <locale>
#include <ostream>
#include <sstream>
#include <tuple>
#include <utility>

#include <dem/core/errors.hpp>
#include <dem/io/atomic_file.hpp>
#include <dem/io/csv.hpp>

namespace dem::lab {
namespace {

namespace fs = std::filesystem;

constexpr std::array<const char*, 4> kinds = {"balls", "contacts", "walls", "pebbles"};
const char* const index_header = "label,time_s,shear_strain,balls,contacts";

bool is_safe_label(const std::string& label) {
  if (label.empty()) return false;
  return std::all_of(label.begin(), label.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' ||
           c == '.';
  });
}

fs::path file_of(const fs::path& dir, const char* kind, const std::string& label, const char* extension) {
  return dir / (std::string(kind) + "_" + label + extension);
}

std::vector<std::size_t> sorted_by_id(const ParticleStore& p, bool pebbles) {
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.is_pebble(i) == pebbles) order.push_back(i);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return p.id[a] < p.id[b]; });
  return order;
}

// The wall index of each triangle is what lets ParaView colour or hide single walls.
void write_walls_vtp(const fs::path& path, const std::vector<Wall>& walls) {
  std::vector<Vec3> points;
  std::vector<std::array<int, 3>> triangles;
  std::vector<double> owner;
  for (std::size_t w = 0; w < walls.size(); ++w) {
    const int base = static_cast<int>(points.size());
    for (const Vec3& v : walls[w].mesh.vertices) {
      require(v.allFinite(), "vertex of wall '" + walls[w].name + "'", "non-finite", "finite (m)");
      points.push_back(v);
    }
    for (const auto& t : walls[w].mesh.triangles) {
      triangles.push_back({base + t[0], base + t[1], base + t[2]});
      owner.push_back(static_cast<double>(w));
    }
  }
  io::write_triangles_vtp(path, points, triangles, {{"wall", owner}});
}

// The intact bonds between their balls' centres, in bond order (the order they were made, the same
// on any thread or process count).
void write_bonds(const World& world, const fs::path& vtp, const fs::path& csv) {
  const BondStore& b = world.bonds();
  const ParticleStore& p = world.particles();
  std::vector<std::pair<Vec3, Vec3>> segments;
  std::vector<double> radius, normal_force, shear_force, twist_moment, bend_moment;
  io::CsvTable table({"first_id", "second_id", "radius", "normal_force", "shear_x", "shear_y", "shear_z", "twist_moment",
                      "bend_x", "bend_y", "bend_z"});
  for (std::size_t k = 0; k < b.size(); ++k) {
    if (!b.intact(k)) continue;
    segments.emplace_back(p.x[p.index_of(b.first[k])], p.x[p.index_of(b.second[k])]);
    radius.push_back(b.radius[k]);
    normal_force.push_back(b.normal_force[k]);
    shear_force.push_back(b.shear_force[k].norm());
    twist_moment.push_back(std::abs(b.twist_moment[k]));
    bend_moment.push_back(b.bend_moment[k].norm());
    const Vec3& f = b.shear_force[k];
    const Vec3& m = b.bend_moment[k];
    table.add_row({static_cast<double>(b.first[k]), static_cast<double>(b.second[k]), b.radius[k], b.normal_force[k],
                   f.x(), f.y(), f.z(), b.twist_moment[k], m.x(), m.y(), m.z()});
  }
  io::write_lines_vtp(vtp, segments,
                      {{"normal_force", normal_force}, {"shear_force", shear_force}, {"twist_moment", twist_moment},
                       {"bend_moment", bend_moment}, {"radius", radius}});
  table.save(csv);
}

std::string number_text(double value) {
  std::ostringstream out;
  out.imbue(std::locale::classic());
  out.precision(std::numeric_limits<double>::max_digits10);
  out << value;
  return out.str();
}

}  // namespace

SnapshotWriter::SnapshotWriter(fs::path dir)
    : dir_(std::move(dir)), bond_collection_(dir_ / "bonds.pvd"), broken_bond_collection_(dir_ / "broken_bonds.pvd") {
  require(!dir_.empty(), "snapshot directory", "\"\"", "a path");
  for (const char* kind : kinds) collections_.emplace_back(dir_ / (std::string(kind) + ".pvd"));
}

void SnapshotWriter::write(const World& world, const std::string& label, double time, double shear_strain,
                           const BrokenBondLog* broken_bonds) {
  require(is_safe_label(label), "snapshot label", "\"" + label + "\"",
          "non-empty, made of letters, digits, '_', '-', '.' (it is part of file names)");
  for (const auto& row : index_)
    require(row.label != label, "snapshot label", label, "new (an earlier snapshot has it)");
  require(std::isfinite(time), "snapshot time (s)", time, "finite");
  if (!index_.empty())
    require(time >= index_.back().time, "snapshot time (s)", time,
            ">= the previous snapshot's time " + number_text(index_.back().time));
  require(std::isfinite(shear_strain), "snapshot shear_strain", shear_strain, "finite");

  const ParticleStore& p = world.particles();

  // Balls.
  const std::vector<std::size_t> balls = sorted_by_id(p, false);
  std::vector<Vec3> ball_x, ball_v, ball_u;
  std::vector<double> ball_r, ball_id;
  io::CsvTable ball_csv({"id", "x", "y", "z", "radius", "ux", "uy", "uz", "vx", "vy", "vz"});
  std::unordered_map<ParticleId, Vec3> positions;
  for (const std::size_t i : balls) {
    const auto last = last_position_.find(p.id[i]);
    const Vec3 u = last == last_position_.end() ? Vec3::Zero() : Vec3(p.x[i] - last->second);
    ball_x.push_back(p.x[i]);
    ball_v.push_back(p.v[i]);
    ball_u.push_back(u);
    ball_r.push_back(p.radius[i]);
    ball_id.push_back(p.id[i]);
    ball_csv.add_row({static_cast<double>(p.id[i]), p.x[i].x(), p.x[i].y(), p.x[i].z(), p.radius[i], u.x(), u.y(),
                      u.z(), p.v[i].x(), p.v[i].y(), p.v[i].z()});
    positions.emplace(p.id[i], p.x[i]);
  }

  // Ball-ball contacts, ordered by the ids of their balls.
  struct Contact {
    ParticleId id1, id2;
    std::size_t i, j;
    Vec3 point, force;
    double normal_force;
  };
  std::vector<Contact> contacts;
  world.for_each_contact([&](const ContactView& c) {
    if (c.kind != ContactKind::BallBall || !(c.normal_force > 0.0)) return;
    const auto j = static_cast<std::size_t>(c.second);
    contacts.push_back({p.id[c.first], p.id[j], c.first, j, c.point, c.force, c.normal_force});
  });
  std::sort(contacts.begin(), contacts.end(),
            [](const Contact& a, const Contact& b) { return std::tie(a.id1, a.id2) < std::tie(b.id1, b.id2); });
  std::vector<std::pair<Vec3, Vec3>> segments;
  std::vector<double> normal_force, force_magnitude;
  io::CsvTable contact_csv(
      {"x1", "y1", "z1", "x2", "y2", "z2", "cx", "cy", "cz", "normal_force", "force_x", "force_y", "force_z"});
  for (const Contact& c : contacts) {
    const Vec3& a = p.x[c.i];
    const Vec3& b = p.x[c.j];
    segments.emplace_back(a, b);
    normal_force.push_back(c.normal_force);
    force_magnitude.push_back(c.force.norm());
    contact_csv.add_row({a.x(), a.y(), a.z(), b.x(), b.y(), b.z(), c.point.x(), c.point.y(), c.point.z(),
                         c.normal_force, c.force.x(), c.force.y(), c.force.z()});
  }

  // Pebbles.
  std::vector<Vec3> pebble_x;
  std::vector<double> pebble_r, pebble_clump;
  for (const std::size_t i : sorted_by_id(p, true)) {
    pebble_x.push_back(p.x[i]);
    pebble_r.push_back(p.radius[i]);
    pebble_clump.push_back(p.clump[i]);
  }

  const std::array<fs::path, 4> vtp = {file_of(dir_, kinds[0], label, ".vtp"), file_of(dir_, kinds[1], label, ".vtp"),
                                       file_of(dir_, kinds[2], label, ".vtp"), file_of(dir_, kinds[3], label, ".vtp")};
  io::write_points_vtp(vtp[0], ball_x, {{"radius", ball_r}, {"id", ball_id}},
                       {{"velocity", ball_v}, {"displacement", ball_u}});
  ball_csv.save(file_of(dir_, kinds[0], label, ".csv"));
  io::write_lines_vtp(vtp[1], segments, {{"normal_force", normal_force}, {"force_magnitude", force_magnitude}});
  contact_csv.save(file_of(dir_, kinds[1], label, ".csv"));
  write_walls_vtp(vtp[2], world.walls());
  io::write_points_vtp(vtp[3], pebble_x, {{"radius", pebble_r}, {"clump", pebble_clump}});
  const bool bonded = !world.bonds().empty();
  if (bonded) write_bonds(world, file_of(dir_, "bonds", label, ".vtp"), file_of(dir_, "bonds", label, ".csv"));
  if (broken_bonds) broken_bonds->write_vtp(world, file_of(dir_, "broken_bonds", label, ".vtp"));

  const IndexRow row{label, time, shear_strain, balls.size(), contacts.size(), bonded, broken_bonds != nullptr};
  add_to_collections(row);
  index_.push_back(row);
  save_index();
  last_position_ = std::move(positions);
}

void SnapshotWriter::add_to_collections(const IndexRow& row) {
  for (std::size_t k = 0; k < kinds.size(); ++k)
    collections_[k].add(row.time, file_of(dir_, kinds[k], row.label, ".vtp"));
  if (row.bonds) bond_collection_.add(row.time, file_of(dir_, "bonds", row.label, ".vtp"));
  if (row.broken_bonds) broken_bond_collection_.add(row.time, file_of(dir_, "broken_bonds", row.label, ".vtp"));
}

std::vector<fs::path> SnapshotWriter::files() const {
  std::vector<fs::path> written;
  std::error_code error;
  if (fs::exists(dir_ / "snapshots.csv", error)) written.push_back(dir_ / "snapshots.csv");
  if (!index_.empty())
    for (const char* kind : kinds) written.push_back(dir_ / (std::string(kind) + ".pvd"));
  if (!bond_collection_.entries().empty()) written.push_back(dir_ / "bonds.pvd");
  if (!broken_bond_collection_.entries().empty()) written.push_back(dir_ / "broken_bonds.pvd");
  for (const auto& row : index_) {
    for (const char* kind : kinds) {
      written.push_back(file_of(dir_, kind, row.label, ".vtp"));
      if (kind == kinds[0] || kind == kinds[1]) written.push_back(file_of(dir_, kind, row.label, ".csv"));
    }
    if (row.bonds) {
      written.push_back(file_of(dir_, "bonds", row.label, ".vtp"));
      written.push_back(file_of(dir_, "bonds", row.label, ".csv"));
    }
    if (row.broken_bonds) written.push_back(file_of(dir_, "broken_bonds", row.label, ".vtp"));
  }
  return written;
}

void SnapshotWriter::save_index() const {
  io::write_atomically(dir_ / "snapshots.csv", [this](std::ostream& out) {
    out << index_header << '\n';
    for (const auto& row : index_)
      out << row.label << ',' << number_text(row.time) << ',' << number_text(row.shear_strain) << ',' << row.balls
          << ',' << row.contacts << '\n';
  });
}

void SnapshotWriter::resume(std::size_t snapshots) {
  const fs::path index_file = dir_ / "snapshots.csv";
  std::vector<IndexRow> rows;
  std::ifstream in(index_file);
  if (in) {
    std::string line;
    if (std::getline(in, line) && line != index_header)
      throw InputError("snapshot index " + index_file.string() + " has the header '" + line + "': must be '" +
                       index_header + "'");
    while (std::getline(in, line)) {
      std::istringstream cells(line);
      cells.imbue(std::locale::classic());
      IndexRow row{};
      char c1 = 0, c2 = 0, c3 = 0;
      std::getline(cells, row.label, ',');
      cells >> row.time >> c1 >> row.shear_strain >> c2 >> row.balls >> c3 >> row.contacts;
      if (!cells || c1 != ',' || c2 != ',' || c3 != ',' || !is_safe_label(row.label) || !(cells >> std::ws).eof())
        throw InputError("snapshot index " + index_file.string() + " line " + std::to_string(rows.size() + 2) + " '" +
                         line + "': must be label,time_s,shear_strain,balls,contacts");
      rows.push_back(row);
    }
  }
  if (rows.size() < snapshots)
    throw InputError("snapshot index " + index_file.string() + " lists " + std::to_string(rows.size()) +
                     " snapshots: cannot resume after " + std::to_string(snapshots));

  for (std::size_t k = snapshots; k < rows.size(); ++k) {
    for (const char* kind : kinds)
      for (const char* extension : {".vtp", ".csv"}) fs::remove(file_of(dir_, kind, rows[k].label, extension));
    for (const char* extension : {".vtp", ".csv"}) fs::remove(file_of(dir_, "bonds", rows[k].label, extension));
    fs::remove(file_of(dir_, "broken_bonds", rows[k].label, ".vtp"));
  }
  rows.resize(snapshots);
  // A cemented run's bond files are not in the index: their presence says which snapshots have them.
  for (IndexRow& row : rows) {
    row.bonds = fs::exists(file_of(dir_, "bonds", row.label, ".vtp"));
    row.broken_bonds = fs::exists(file_of(dir_, "broken_bonds", row.label, ".vtp"));
  }

  last_position_.clear();
  if (!rows.empty()) {
    const io::CsvData balls = io::read_csv(file_of(dir_, kinds[0], rows.back().label, ".csv"));
    const std::size_t id = balls.column("id"), x = balls.column("x"), y = balls.column("y"), z = balls.column("z");
    for (const auto& r : balls.rows) last_position_[static_cast<ParticleId>(r[id])] = Vec3(r[x], r[y], r[z]);
  }
  collections_.clear();
  for (const char* kind : kinds) collections_.emplace_back(dir_ / (std::string(kind) + ".pvd"));
  bond_collection_ = io::PvdCollection(dir_ / "bonds.pvd");
  broken_bond_collection_ = io::PvdCollection(dir_ / "broken_bonds.pvd");
  for (const auto& row : rows) add_to_collections(row);
  if (rows.empty())
    for (const char* kind : kinds) fs::remove(dir_ / (std::string(kind) + ".pvd"));
  if (bond_collection_.entries().empty()) fs::remove(dir_ / "bonds.pvd");
  if (broken_bond_collection_.entries().empty()) fs::remove(dir_ / "broken_bonds.pvd");
  index_ = std::move(rows);
  save_index();
}

}  // namespace dem::lab
