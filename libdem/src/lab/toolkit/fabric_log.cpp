// Fabric CSV: roses of the ball-ball contacts in two planes, one row per bin.
#include <dem/lab/toolkit/fabric_log.hpp>

#include <charconv>
#include <cmath>
#include <fstream>
#include <ostream>
#include <sstream>
#include <utility>

#include <dem/core/errors.hpp>
#include <dem/io/atomic_file.hpp>

namespace dem::lab {
namespace {

const char* const header =
    "label,shear_strain,plane,bin_lo_deg,bin_hi_deg,contact_count,contact_fraction,mean_normal_force_N,"
    "a,theta_a_deg,f0_N,a_n,theta_n_deg,a_direct,theta_a_direct_deg,contacts_total,mean_force_all_N";

constexpr measure::RosePlane planes[] = {measure::RosePlane::ShearXZ, measure::RosePlane::HorizontalXY};
constexpr const char* plane_names[] = {"xz", "xy"};

void require_label(const std::string& label) {
  bool ok = !label.empty();
  for (const char c : label)
    ok = ok && ((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' ||
                c == '.');
  require(ok, "fabric state label", "\"" + label + "\"", "non-empty, made of letters, digits, '_', '-', '.'");
}

// 17 significant digits; an empty cell for a value that does not exist (NaN: no contacts).
std::string cell(double value) {
  if (!std::isfinite(value)) return {};
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::general, 17);
  return {buffer, result.ptr};
}

std::vector<std::string> split_commas(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream in(line);
  for (std::string c; std::getline(in, c, ',');) cells.push_back(c);
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

int bins_of(double bin_width_deg) { return static_cast<int>(std::lround(180.0 / bin_width_deg)); }

}  // namespace

FabricLog::FabricLog(std::filesystem::path csv_file, double bin_width_deg)
    : csv_file_(std::move(csv_file)), bin_width_deg_(bin_width_deg) {
  require(!csv_file_.empty() && csv_file_.has_filename(), "fabric log file", csv_file_.string(), "a file name");
  measure::rose({}, planes[0], bin_width_deg_);  // validates the bin width now, not at the first record
}

void FabricLog::record(const World& world, const std::string& label, double shear_strain) {
  require_label(label);
  require(std::isfinite(shear_strain), "shear_strain of fabric state " + label, shear_strain, "finite");
  std::vector<measure::ContactSample> contacts;
  double force_sum = 0.0;  // N
  world.for_each_contact([&](const ContactView& c) {
    if (c.kind != ContactKind::BallBall || !(c.normal_force > 0.0)) return;
    contacts.push_back({c.normal, c.normal_force});
    force_sum += c.normal_force;
  });
  const double mean_force = contacts.empty() ? std::nan("") : force_sum / static_cast<double>(contacts.size());

  std::vector<measure::Rose> roses;
  for (std::size_t p = 0; p < 2; ++p) {
    const measure::Rose r = measure::rose(contacts, planes[p], bin_width_deg_);
    const std::string fits = cell(r.a) + ',' + cell(r.theta_a_deg) + ',' + cell(r.f0) + ',' + cell(r.a_n) + ',' +
                             cell(r.theta_n_deg) + ',' + cell(r.a_direct) + ',' + cell(r.theta_a_direct_deg) + ',' +
                             std::to_string(contacts.size()) + ',' + cell(mean_force);
    for (std::size_t m = 0; m < r.count.size(); ++m) {
      rows_.push_back(label + ',' + cell(shear_strain) + ',' + plane_names[p] + ',' + cell(r.bin_lo_deg[m]) + ',' +
                      cell(r.bin_lo_deg[m] + r.bin_width_deg) + ',' + std::to_string(r.count[m]) + ',' +
                      cell(r.fraction[m]) + ',' + cell(r.mean_normal_force[m]) + ',' + fits);
    }
    roses.push_back(r);
  }
  ++states_;
  last_roses_ = std::move(roses);
  save();
}

void FabricLog::resume(std::size_t states) {
  std::vector<std::string> kept;
  std::ifstream in(csv_file_);
  const auto rows_per_state = static_cast<std::size_t>(2 * bins_of(bin_width_deg_));
  if (in) {
    std::string line;
    if (std::getline(in, line) && line != header)
      throw InputError("fabric log " + csv_file_.string() + " has the header '" + line + "': must be '" + header + "'");
    while (kept.size() < states * rows_per_state && std::getline(in, line)) {
      const auto cells = split_commas(line);
      double lo = 0.0, hi = 0.0;
      const bool ok = cells.size() == 17 &&
                      std::from_chars(cells[3].data(), cells[3].data() + cells[3].size(), lo).ec == std::errc() &&
                      std::from_chars(cells[4].data(), cells[4].data() + cells[4].size(), hi).ec == std::errc();
      if (!ok || std::abs(hi - lo - bin_width_deg_) > 1e-9 * bin_width_deg_)
        throw InputError("fabric log " + csv_file_.string() + " line " + std::to_string(kept.size() + 2) + " '" + line +
                         "': must be a row of 17 cells with bins " + cell(bin_width_deg_) + " degrees wide");
      kept.push_back(line);
    }
  }
  if (kept.size() < states * rows_per_state)
    throw InputError("fabric log " + csv_file_.string() + " holds " + std::to_string(kept.size() / rows_per_state) +
                     " complete states: cannot resume after " + std::to_string(states));
  rows_ = std::move(kept);
  states_ = states;
  last_roses_.clear();
  save();
}

void FabricLog::save() const {
  io::write_atomically(csv_file_, [this](std::ostream& out) {
    out << header << '\n';
    for (const auto& row : rows_) out << row << '\n';
  });
}

}  // namespace dem::lab
