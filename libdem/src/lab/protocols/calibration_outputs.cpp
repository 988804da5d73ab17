// The calibration's end: the best trial against the lab curve (comparison.csv), the fitted
// configuration (calibrated.ini) and summary.json, written by the leading process.
#include <dem/lab/protocols/calibration.hpp>

#include <cstdint>
#include <cstring>
#include <ostream>
#include <stdexcept>

#include <dem/io/atomic_file.hpp>
#include <dem/io/csv.hpp>

#include "../../io/json_file.hpp"

namespace dem::lab {
namespace {

// A model curve as its size and the bytes of its three columns (the volumetric one may be empty).
std::string curve_bytes(const ModelCurve& c) {
  std::string bytes;
  for (const std::vector<double>* column : {&c.shear_strain, &c.shear_stress, &c.volumetric_strain}) {
    const std::uint64_t n = column->size();
    bytes.append(reinterpret_cast<const char*>(&n), sizeof n);
    bytes.append(reinterpret_cast<const char*>(column->data()), n * sizeof(double));
  }
  return bytes;
}

ModelCurve curve_from_bytes(const std::string& bytes) {
  ModelCurve c;
  std::size_t at = 0;
  for (std::vector<double>* column : {&c.shear_strain, &c.shear_stress, &c.volumetric_strain}) {
    std::uint64_t n = 0;
    if (at + sizeof n > bytes.size()) throw std::runtime_error("a model curve arrived cut short");
    std::memcpy(&n, bytes.data() + at, sizeof n);
    at += sizeof n;
    if (n > (bytes.size() - at) / sizeof(double)) throw std::runtime_error("a model curve arrived cut short");
    column->resize(n);
    std::memcpy(column->data(), bytes.data() + at, n * sizeof(double));
    at += n * sizeof(double);
  }
  return c;
}

}  // namespace

CurveComparison Calibration::comparison(const TrialResult& trial) {
  // The trial's stored history, or the trial again (both by one process, the curve then to all).
  std::string curve = farm_->on_leader([&] {
    const std::optional<ModelCurve> stored = shears_->stored_curve(trial.trial);
    return stored ? curve_bytes(*stored) : std::string();
  });
  if (curve.empty()) {
    const int threads = std::max(1, settings_.threads);
    shears_->prepare({trial.fit.modulus}, 1, threads);
    curve = farm_->on_leader([&] { return curve_bytes(shears_->shear(trial.fit, target_strain_, trial.trial, threads)); });
  }
  return compare_curves(lab_, curve_from_bytes(curve), settings_.comparison);
}

void Calibration::write_outputs(const CalibrationResult& result, int max_trials) {
  const TrialResult& best = result.best_trial;
  const CurveComparison c = comparison(best);
  if (!farm_->leads()) return;

  std::vector<std::string> columns = {"shear_strain", "lab_shear_stress_Pa", "model_shear_stress_Pa", "shear_stress_rd_percent"};
  if (lab_.has_volumetric())
    for (const char* name : {"lab_volumetric_strain", "model_volumetric_strain", "volumetric_strain_rd_percent"}) columns.emplace_back(name);
  io::CsvTable table(columns);
  for (std::size_t k = 0; k < lab_.size(); ++k) {
    std::vector<double> row = {lab_.shear_strain[k], lab_.shear_stress[k], c.model_stress[k], c.stress_rd_percent[k]};
    if (lab_.has_volumetric())
      row.insert(row.end(), {lab_.volumetric_strain[k], c.model_volumetric[k], c.volumetric_rd_percent[k]});
    table.add_row(row);
  }
  table.save(out_dir_ / "comparison.csv");

  const io::Config calibrated = shear_config_with(config_, result.best);
  io::write_atomically(out_dir_ / "calibrated.ini", [&](std::ostream& out) {
    out << "# dem-calibrate: ball_ball parameters fitted to " << lab_.file.string() << " (trial " << best.trial
        << ", mean RD of shear stress " << detail::short_text(best.stress_rd_mean, 3) << " %)\n"
        << calibrated.to_ini();
  });

  io::Json j;
  j["lab"]["file"] = lab_.file.string();
  j["lab"]["points"] = lab_.size();
  j["lab"]["max_shear_strain"] = lab_.max_strain();
  j["lab"]["peak_shear_stress_Pa"] = lab_peak_;
  j["lab"]["stage_3_target"] = rolling_by_dilatancy_ ? "late dilatancy" : "peak shear stress";
  if (rolling_by_dilatancy_) j["lab"]["late_dilatancy"] = lab_dilatancy_;
  j["lab"]["initial_slope_Pa"] = lab_slope_;
  j["lab"]["initial_slope_up_to_strain"] = slope_limit_;
  auto params = [this](const ContactFit& f) {
    io::Json o;
    o[modulus_key_ + "_Pa"] = f.modulus;
    o["friction"] = f.friction;
    o["rolling_friction"] = f.rolling_friction;
    return o;
  };
  io::Json fitted = io::Json::array();
  if (settings_.fit_modulus) fitted.push_back("emod");
  if (settings_.fit_friction) fitted.push_back("friction");
  if (settings_.fit_rolling) fitted.push_back("rolling");
  j["fitted"] = fitted;
  j["start"] = params(start_);
  j["best"] = params(result.best);
  io::Json& m = j["metrics"];
  m["trial"] = best.trial;
  m["shear_stress_rd_max_percent"] = best.stress_rd_max;
  m["shear_stress_rd_mean_percent"] = best.stress_rd_mean;
  m["shear_stress_points_used"] = best.stress_points_used;
  m["shear_stress_points_skipped"] = best.stress_points_skipped;
  if (best.volumetric_points_used > 0) {
    m["volumetric_strain_rd_max_percent"] = best.volumetric_rd_max;
    m["volumetric_strain_rd_mean_percent"] = best.volumetric_rd_mean;
  } else {
    m["volumetric_strain_rd_max_percent"] = nullptr;
    m["volumetric_strain_rd_mean_percent"] = nullptr;
  }
  m["volumetric_strain_points_used"] = best.volumetric_points_used;
  m["volumetric_strain_points_skipped"] = best.volumetric_points_skipped;
  m["model_initial_slope_Pa"] = best.model_slope;
  m["model_peak_shear_stress_Pa"] = best.model_peak;
  m["eps_stress_Pa"] = settings_.comparison.eps_stress;
  m["eps_strain"] = settings_.comparison.eps_strain;
  j["trials"]["asked"] = result.trials;
  j["trials"]["new"] = result.new_trials;
  j["trials"]["reused"] = result.trials - result.new_trials;
  j["trials"]["in_trials_csv"] = trials_.size();
  j["trials"]["max"] = max_trials;
  io::Json notes = io::Json::array();
  for (const std::string& n : result.stage_notes) notes.push_back(n);
  j["stages"] = notes;
  double trial_seconds = 0;
  for (const TrialResult& t : trials_) trial_seconds += t.seconds;
  j["seconds"] = result.seconds;
  j["trial_seconds_all_runs"] = trial_seconds;
  j["threads"] = settings_.threads;
  j["parallel_trials"] = settings_.parallel_trials;
  j["processes"] = farm_->processes();
  j["configuration"] = io::Json::parse(calibrated.to_json());
  io::save_json(out_dir_ / "summary.json", j);
}

}  // namespace dem::lab
