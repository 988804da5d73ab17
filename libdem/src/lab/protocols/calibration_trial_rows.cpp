// trials.csv and the trials' bytes (calibration_trial_rows.hpp).
#include "calibration_trial_rows.hpp"

#include <cstring>
#include <iterator>
#include <stdexcept>

#include <dem/core/errors.hpp>
#include <dem/io/csv.hpp>

namespace fs = std::filesystem;

namespace dem::lab::detail {
namespace {

// The columns of trials.csv, each declared once with the field it holds: the writer prints them in
// this order, the reader finds each by its name.
struct TrialColumn {
  const char* name;
  double (*get)(const TrialResult&);
  void (*set)(TrialResult&, double);
};
#define DEM_TRIAL_COLUMN(name, field, type) \
  TrialColumn{name, [](const TrialResult& t) { return static_cast<double>(t.field); }, [](TrialResult& t, double v) { t.field = static_cast<type>(v); }}
const TrialColumn trial_columns[] = {
    DEM_TRIAL_COLUMN("trial", trial, int),
    DEM_TRIAL_COLUMN("stage", stage, int),
    DEM_TRIAL_COLUMN("modulus", fit.modulus, double),  // named by the law's key in files (trial_column_names)
    DEM_TRIAL_COLUMN("friction", fit.friction, double),
    DEM_TRIAL_COLUMN("rolling_friction", fit.rolling_friction, double),
    DEM_TRIAL_COLUMN("shear_stress_rd_max_percent", stress_rd_max, double),
    DEM_TRIAL_COLUMN("shear_stress_rd_mean_percent", stress_rd_mean, double),
    DEM_TRIAL_COLUMN("volumetric_strain_rd_max_percent", volumetric_rd_max, double),
    DEM_TRIAL_COLUMN("volumetric_strain_rd_mean_percent", volumetric_rd_mean, double),
    DEM_TRIAL_COLUMN("shear_stress_points_used", stress_points_used, double),
    DEM_TRIAL_COLUMN("shear_stress_points_skipped", stress_points_skipped, double),
    DEM_TRIAL_COLUMN("volumetric_strain_points_used", volumetric_points_used, double),
    DEM_TRIAL_COLUMN("volumetric_strain_points_skipped", volumetric_points_skipped, double),
    DEM_TRIAL_COLUMN("model_initial_slope_Pa", model_slope, double),
    DEM_TRIAL_COLUMN("model_peak_shear_stress_Pa", model_peak, double),
    DEM_TRIAL_COLUMN("model_late_dilatancy", model_dilatancy, double),
    DEM_TRIAL_COLUMN("seconds", seconds, double),
};
#undef DEM_TRIAL_COLUMN

// The columns' names in trials.csv: the modulus under the law's own key (effective_modulus, the
// only one before other laws could be fitted, or youngs_modulus).
std::vector<std::string> trial_column_names(const std::string& modulus_key) {
  std::vector<std::string> names;
  for (const TrialColumn& c : trial_columns) names.push_back(std::string(c.name) == "modulus" ? modulus_key : c.name);
  return names;
}

}  // namespace

std::string trials_bytes(const std::vector<TrialResult>& trials) {
  std::string bytes;
  for (const TrialResult& t : trials)
    for (const TrialColumn& c : trial_columns) {
      const double v = c.get(t);
      bytes.append(reinterpret_cast<const char*>(&v), sizeof v);
    }
  return bytes;
}

std::vector<TrialResult> trials_from_bytes(const std::string& bytes) {
  constexpr std::size_t row_bytes = std::size(trial_columns) * sizeof(double);
  if (bytes.size() % row_bytes != 0)
    throw std::runtime_error("trial results arrived with " + std::to_string(bytes.size()) + " bytes, not a multiple of " +
                             std::to_string(row_bytes));
  std::vector<TrialResult> trials(bytes.size() / row_bytes);
  for (std::size_t r = 0; r < trials.size(); ++r)
    for (std::size_t k = 0; k < std::size(trial_columns); ++k) {
      double v = 0;
      std::memcpy(&v, bytes.data() + r * row_bytes + k * sizeof v, sizeof v);
      trial_columns[k].set(trials[r], v);
    }
  return trials;
}

// Rows of trials.csv (or of a trial folder's result.csv), each column found by its name.
std::vector<TrialResult> read_trial_rows(const fs::path& file, const std::string& modulus_key) {
  const io::CsvData data = io::read_csv(file);
  std::vector<std::size_t> index;
  for (const std::string& name : trial_column_names(modulus_key)) index.push_back(data.column(name));  // InputError names a missing one
  require(data.columns.size() == index.size(), file.string() + " columns", data.columns.size(),
          std::to_string(index.size()) + ", the columns dem-calibrate writes (no others)");
  std::vector<TrialResult> rows;
  for (const auto& row : data.rows) {
    TrialResult t;
    for (std::size_t k = 0; k < index.size(); ++k) trial_columns[k].set(t, row[index[k]]);
    rows.push_back(t);
  }
  return rows;
}

void write_trial_rows(const fs::path& file, const std::vector<TrialResult>& rows, const std::string& modulus_key) {
  io::CsvTable table(trial_column_names(modulus_key));
  for (const TrialResult& t : rows) {
    std::vector<double> row;
    for (const TrialColumn& c : trial_columns) row.push_back(c.get(t));
    table.add_row(row);
  }
  table.save(file);
}

}  // namespace dem::lab::detail
