#include <dem/lab/toolkit/shear_outputs.hpp>

#include <cstdio>
#include <optional>

#include <dem/core/pair_geometry.hpp>
#include <dem/lab/toolkit/broken_bonds.hpp>
#include <dem/lab/toolkit/cementation.hpp>
#include <dem/lab/toolkit/fabric_log.hpp>
#include <dem/lab/toolkit/snapshots.hpp>
#include <dem/measure/fabric.hpp>
#include <dem/measure/shear_uniformity.hpp>

namespace dem::lab {

namespace {

std::string label_for(double strain) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "strain_%04.1f", 100.0 * strain);  // e.g. strain_20.0 (percent)
  std::string s(buf);
  for (char& c : s)
    if (c == ' ') c = '0';
  return s;
}

// Pairs of the list whose surfaces are closer than `gap` (m): touching, or about to.
std::size_t contacts_within_gap(const World& w, ContactKind kind, double gap) {
  const ParticleStore& p = w.particles();
  const PairContacts& pairs = w.pair_contacts(kind);
  std::optional<ImageShifts> images;  // a periodic cell's: pairs across its faces
  if (w.periodic_cell()) images = w.periodic_cell()->image_shifts();
  std::size_t n = 0;
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const auto i = static_cast<std::size_t>(pairs.first[k]), j = static_cast<std::size_t>(pairs.second[k]);
    if (contact_branch(pairs, k, p.x.data(), images ? &*images : nullptr).norm() - p.radius[i] - p.radius[j] < gap) ++n;
  }
  return n;
}

}  // namespace

ShearOutputs::ShearOutputs(Run& run, const NgiSpecimen& specimen, std::function<Vec3()> direction)
    : run_(run), specimen_(specimen), direction_(std::move(direction)), history_(run.folder() / "history.csv") {
  fabric_ = std::make_unique<FabricLog>(run.folder() / "fabric.csv");
  snapshots_ = std::make_unique<SnapshotWriter>(run.folder() / "snapshots");
  add_columns();
  run.keep("next_output_strain", next_row_strain_);
  run.keep("next_fabric", next_fabric_);
  run.keep("next_snapshot", next_snapshot_);
  ProfileInterval& interval = uniformity_->interval();
  for (const auto& [end, x] : {std::pair{"bottom", &interval.bottom}, std::pair{"top", &interval.top}}) {
    const std::string name = std::string("profile_") + end;
    run.keep(name + "_x", x->x());
    run.keep(name + "_y", x->y());
    run.keep(name + "_z", x->z());
  }
  run.keep_points("profile_reference", interval.positions);  // by ball id, NaN for pebbles
  if (specimen_.config().cementation.after != CementAfter::None) broken_bonds_ = std::make_unique<BrokenBondLog>(run, "broken_bond_strains");
  // Rows written up to the restart point are kept; later ones belong to the run that stopped.
  run.keep("history_rows", [this] { return static_cast<double>(history_.rows()); }, [this](double rows) {
    history_.resume(run_.loaded_folder() / "history.csv", static_cast<std::size_t>(rows));
  });
  run.on_claim([this] {
    if (!run_.loaded()) return;
    fabric_->resume(next_fabric_);
    snapshots_->resume(next_snapshot_);
    run_.record_outputs(snapshots_->files());
  });
}

ShearOutputs::~ShearOutputs() = default;

void ShearOutputs::record(double strain, bool force) {
  const OutputConfig& out = specimen_.config().output;
  World& world = run_.world();
  shear_strain_ = strain;
  const auto fabric_due = [&] { return next_fabric_ < out.fabric_strains.size() && strain >= out.fabric_strains[next_fabric_] - 1e-12; };
  const auto snapshot_due = [&] {
    return next_snapshot_ < out.snapshot_strains.size() && strain >= out.snapshot_strains[next_snapshot_] - 1e-12;
  };
  if (broken_bonds_) broken_bonds_->update(world, strain);  // the bonds broken in the last chunk
  const bool row = force || strain >= next_row_strain_ - 1e-12;
  if (row || fabric_due() || snapshot_due()) world.gather_state();  // after a step that left only the walls whole
  if (row) {
    history_.record();
    specimen_.require_no_escape(strain);  // after the row: it shows the state in which the ball was lost
    while (next_row_strain_ <= strain + 1e-12) next_row_strain_ += out.every_strain;
  }
  for (; fabric_due(); ++next_fabric_) fabric_->record(world, label_for(out.fabric_strains[next_fabric_]), strain);
  for (; snapshot_due(); ++next_snapshot_) {
    const std::string label = label_for(out.snapshot_strains[next_snapshot_]);
    snapshots_->write(world, label, world.time(), strain, broken_bonds_.get());
    run_.record_outputs(snapshots_->files());
  }
}

void ShearOutputs::add_columns() {
  const World& world = run_.world();
  const SimpleShearConfig& config = specimen_.config();
  // The state of the row, measured once, read by the columns that follow.
  history_.before_row([this] { row_ = specimen_.measure(direction_()); });
  const ShearState& s = row_;
  auto field = [&](const char* name, const double& value) { history_.add(name, [&value] { return value; }); };
  auto count = [&](const char* name, const std::size_t& value) { history_.add(name, [&value] { return static_cast<double>(value); }); };
  auto compression = [&s](int i, int j) { return [&s, i, j] { return -s.sphere.stress(i, j); }; };
  const auto direction = direction_;
  field("time", s.time);
  history_.add("step", [&world] { return static_cast<double>(world.step_count()); });
  history_.add("stage", [this] { return static_cast<double>(specimen_.stage()); });
  field("shear_strain_x", s.shear_strain_x);
  field("shear_strain_y", s.shear_strain_y);
  field("shear_strain", s.shear_strain);
  field("shear_stress_x", s.shear_stress_x);
  field("shear_stress_y", s.shear_stress_y);
  field("shear_stress", s.shear_stress);
  field("shear_stress_bottom", s.shear_stress_bottom);
  field("vertical_stress", s.vertical_stress);
  field("vertical_stress_bottom", s.vertical_stress_bottom);
  field("height", s.height);
  field("volumetric_strain", s.volumetric_strain);
  field("lateral_stress", s.lateral_stress);
  history_.add("k0", [&s] { return s.vertical_stress > 0 ? s.lateral_stress / s.vertical_stress : 0.0; });
  field("sigma_1", s.sphere.principal.sigma_1);
  field("sigma_2", s.sphere.principal.sigma_2);
  field("sigma_3", s.sphere.principal.sigma_3);
  field("principal_rotation_deg", s.principal_rotation_deg);
  history_.add("ms_sxx", compression(0, 0));
  history_.add("ms_syy", compression(1, 1));
  history_.add("ms_szz", compression(2, 2));
  history_.add("ms_sxy", compression(0, 1));
  history_.add("ms_sxz", compression(0, 2));
  history_.add("ms_syz", compression(1, 2));
  history_.add("ms_shear_stress", [&s, direction] { return direction().dot(Mat3(-s.sphere.stress) * Vec3::UnitZ()); });
  field("coordination_number", s.sphere.coordination_number);
  count("contacts", s.contacts);
  field("mean_contact_force", s.mean_contact_force);
  field("porosity", s.sphere.porosity);
  field("kinetic_energy", s.kinetic_energy);
  history_.add("inertial_number", [this] { return specimen_.stage() >= ShearStage::Consolidated ? specimen_.inertial_number() : 0.0; });
  // How uniformly it shears, and the study's non-coaxiality (docs/model.md 8.1).
  field("specimen_porosity", s.specimen_porosity);
  count("balls_outside", s.balls_outside);
  // Contacts two ways: active (F_n > 0: "contacts") and within the detection gap.
  history_.add("contacts_within_detection", [&world, &config] {
    return static_cast<double>(contacts_within_gap(world, ContactKind::BallBall, config.measure.detection_gap_ratio * config.grading.smallest()));
  });
  field("mechanical_coordination_number", s.sphere.mechanical_coordination_number);
  history_.add("strain_rate_direction_deg", [&s, direction] {
    const Vec3 d = direction();
    const Mat3 rate = -s.sphere.strain_rate;  // compression positive
    return measure::major_direction_deg(d.dot(rate * d), rate(2, 2), d.dot(rate * Vec3::UnitZ()));
  });
  history_.add("non_coaxiality_deg", [&s, direction] {
    return measure::non_coaxiality_deg(Mat3(-s.sphere.stress), Mat3(-s.sphere.strain_rate), direction());
  });
  // The left-right asymmetry of the ball-ball roses in the x-z plane about the vertical, and
  // their tilts (measure/fabric.hpp): the inhomogeneity the study reads in its 4D roses.
  history_.add({"rose_count_asymmetry", "rose_force_asymmetry", "rose_count_tilt_deg", "rose_force_tilt_deg"},
               [&world](std::vector<double>& row) {
                 std::vector<measure::ContactSample> contacts;
                 world.for_each_contact([&](const ContactView& c) {
                   if (c.kind == ContactKind::BallBall && c.normal_force > 0.0) contacts.push_back({c.normal, c.normal_force});
                 });
                 const measure::RoseAsymmetry a = measure::rose_asymmetry(measure::rose(contacts, measure::RosePlane::ShearXZ));
                 row.insert(row.end(), {a.count, a.force, a.count_tilt_deg, a.force_tilt_deg});
               });
  uniformity_ = std::make_unique<UniformityProbe>(world, specimen_.cell(), config.measure.profile_bins);
  uniformity_->add_columns(history_, direction);
  add_ring_columns(history_, world, specimen_.cell());
  if (config.cementation.after != CementAfter::None) add_bond_columns(history_, world);  // a plain run's columns stay as they were
}

}  // namespace dem::lab
