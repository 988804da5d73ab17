// Lab curves: io::read_csv does the parsing and reports bad cells by line; this file adds the
// meaning (which columns, which units, increasing strain) and the comparison with a model.
#include <dem/lab/toolkit/lab_curve.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include <dem/base/input_file.hpp>
#include <dem/core/errors.hpp>

namespace dem::lab {
namespace {

bool is_data_line(const std::string& line) {
  const auto first = line.find_first_not_of(" \t\r");
  return first != std::string::npos && line[first] != '#';
}

// File line of every data row: read_csv skips blank and comment lines, so row k is not line k + 2.
std::vector<std::size_t> data_line_numbers(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::vector<std::size_t> lines;
  bool header = false;
  std::string line;
  for (std::size_t number = 1; std::getline(in, line); ++number) {
    if (!is_data_line(line)) continue;
    if (header) lines.push_back(number);
    header = true;
  }
  return lines;
}

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& name : names) out += (out.empty() ? "" : ", ") + name;
  return out;
}

// Index of the column holding `plain` or `suffixed`, or nullopt; InputError if both are present.
std::optional<std::size_t> find_one(const io::CsvData& data, const std::filesystem::path& file, const std::string& plain,
                                    const std::string& suffixed, bool& is_suffixed) {
  std::optional<std::size_t> plain_at, suffixed_at;
  for (std::size_t i = 0; i < data.columns.size(); ++i) {
    if (data.columns[i] == plain) plain_at = i;
    if (data.columns[i] == suffixed) suffixed_at = i;
  }
  if (plain_at && suffixed_at)
    throw InputError("lab curve " + file.string() + ": header has both '" + plain + "' and '" + suffixed +
                     "': must have only one of them (the suffix states the unit)");
  is_suffixed = suffixed_at.has_value();
  return suffixed_at ? suffixed_at : plain_at;
}

// True when the header names a dem-simple-shear history.csv (its `step` and `stage` columns).
bool is_shear_history(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line) && !is_data_line(line)) {
  }
  std::vector<std::string> names;
  std::istringstream cells(line);
  for (std::string name; std::getline(cells, name, ',');) names.push_back(name.substr(0, name.find_last_not_of(" \t\r") + 1));
  auto has = [&](const char* name) { return std::find(names.begin(), names.end(), name) != names.end(); };
  return has("step") && has("stage") && has("shear_strain");
}

// A history's shear as a lab curve: the consolidated row and the shearing ones (stage 2 and 3:
// lab/toolkit/specimen_file.hpp's ShearStage), a row whose strain does not pass the previous kept
// row's left out (the consolidated row and the first shear row can both sit at 0).
void keep_shear_rows(io::CsvData& data, std::vector<std::size_t>& lines, const std::filesystem::path& file) {
  const std::size_t stage = data.column("stage"), strain = data.column("shear_strain");
  io::CsvData kept = data;
  kept.rows.clear();
  std::vector<std::size_t> kept_lines;
  for (std::size_t r = 0; r < data.rows.size(); ++r) {
    const auto& row = data.rows[r];
    if (!(row[stage] >= 2.0 && row[stage] <= 3.0)) continue;
    if (!kept.rows.empty() && !(row[strain] > kept.rows.back()[strain])) continue;
    kept.rows.push_back(row);
    kept_lines.push_back(r < lines.size() ? lines[r] : 0);
  }
  if (kept.rows.size() < 2)
    throw InputError("lab curve " + file.string() + ": a simple-shear history with " + std::to_string(kept.rows.size()) +
                     " row(s) of its consolidated specimen and shear (stage 2 and 3): must hold the shear");
  data = std::move(kept);
  lines = std::move(kept_lines);
}

std::string number(double v) {
  std::ostringstream out;
  out.precision(10);
  out << v;
  return out.str();
}

}  // namespace

LabCurve read_lab_curve(const std::filesystem::path& file, const LabCurveOptions& options) {
  require_input_file(file, "lab curve", "a CSV file of the laboratory curve", max_text_input_bytes);
  // A run's history.csv may be the "lab" curve (one scale calibrated to another's): its empty
  // cells (NaN) are allowed, in columns the curve does not read.
  const bool history = is_shear_history(file);
  io::CsvData data = io::read_csv(file, history ? io::Missing::Allowed : io::Missing::Refused);
  const std::string where = "lab curve " + file.string();
  if (data.rows.empty()) throw InputError(where + ": has a header but no data rows: must hold at least one strain point");
  std::vector<std::size_t> lines = data_line_numbers(file);
  if (history) keep_shear_rows(data, lines, file);
  auto line_of = [&](std::size_t row) { return row < lines.size() ? lines[row] : 0; };

  bool strain_suffixed = false, stress_suffixed = false, volumetric_suffixed = false;
  const auto strain_col = find_one(data, file, "shear_strain", "shear_strain_percent", strain_suffixed);
  const auto stress_col = find_one(data, file, "shear_stress", "shear_stress_kPa", stress_suffixed);
  const auto volumetric_col = find_one(data, file, "volumetric_strain", "volumetric_strain_percent", volumetric_suffixed);
  if (!strain_col)
    throw InputError(where + ": no column 'shear_strain' (fraction) or 'shear_strain_percent' (%); columns are: " +
                     joined(data.columns));
  if (!stress_col)
    throw InputError(where + ": no column 'shear_stress' (Pa) or 'shear_stress_kPa' (kPa); columns are: " +
                     joined(data.columns));

  const double strain_scale = (strain_suffixed || options.strain_percent) ? 0.01 : 1.0;
  const double volumetric_scale = (volumetric_suffixed || options.strain_percent) ? 0.01 : 1.0;
  const double stress_scale = stress_suffixed ? 1e3 : 1.0;
  const std::string& strain_name = data.columns[*strain_col];

  LabCurve lab;
  lab.file = file;
  for (std::size_t r = 0; r < data.rows.size(); ++r) {
    const auto& row = data.rows[r];
    const double strain = row[*strain_col] * strain_scale;
    const std::string at = where + ":" + std::to_string(line_of(r)) + ": column '" + strain_name + "' ";
    for (const auto column : {strain_col, stress_col, volumetric_col})
      if (column && !std::isfinite(row[*column]))
        throw InputError(where + ":" + std::to_string(line_of(r)) + ": column '" + data.columns[*column] +
                         "' is missing (nan): must be a number");
    if (strain < 0.0) throw InputError(at + "= " + number(row[*strain_col]) + ": must be >= 0 (shear strain from the start of shear)");
    if (r > 0 && !(strain > lab.shear_strain.back()))
      throw InputError(at + "= " + number(row[*strain_col]) + ": must be greater than the previous point's " +
                       number(data.rows[r - 1][*strain_col]) + " (line " +
                       std::to_string(line_of(r - 1)) + "): shear strain must increase strictly");
    lab.shear_strain.push_back(strain);
    lab.shear_stress.push_back(row[*stress_col] * stress_scale);
    if (volumetric_col) lab.volumetric_strain.push_back(row[*volumetric_col] * volumetric_scale);
    lab.lines.push_back(line_of(r));
  }
  // Units that do not fit a simple-shear test are a mislabelled column far more often than data:
  // percent read as a fraction would shear the model to hundreds of percent.
  for (std::size_t r = 0; r < lab.shear_strain.size(); ++r) {
    const std::string at = where + ":" + std::to_string(lab.lines[r]) + ": column '";
    if (lab.shear_strain[r] > 1.0)
      throw InputError(at + strain_name + "' = " + number(data.rows[r][*strain_col]) + " is a shear strain above 1 (100 %)" +
                       (strain_scale == 1.0 ? ": if the column is in percent, name it shear_strain_percent or give --strain-percent"
                                            : ": a simple-shear test does not reach it"));
    if (volumetric_col && std::abs(lab.volumetric_strain[r]) > 1.0)
      throw InputError(at + data.columns[*volumetric_col] + "' = " + number(data.rows[r][*volumetric_col]) +
                       " is a volumetric strain beyond 1 (100 %)" +
                       (volumetric_scale == 1.0 ? ": if the column is in percent, name it volumetric_strain_percent or give --strain-percent"
                                                : ""));
  }
  double largest_stress = 0.0;
  for (double tau : lab.shear_stress) largest_stress = std::max(largest_stress, std::abs(tau));
  if (!stress_suffixed && largest_stress > 0.0 && largest_stress < 1e3)
    throw InputError(where + ": column 'shear_stress' (Pa) peaks at " + number(largest_stress) +
                     " Pa, below 1 kPa: if the column is in kPa, name it shear_stress_kPa");
  // A simple-shear test on soil stays far below 10 MPa; Pa values under a kPa header reach it.
  constexpr double most_stress = 10e6;  // Pa
  if (largest_stress > most_stress)
    throw InputError(where + ": column '" + data.columns[*stress_col] + "' peaks at " +
                     number(largest_stress / stress_scale) + (stress_suffixed ? " kPa" : " Pa") + ", above 10 MPa" +
                     (stress_suffixed ? ": if the column is in Pa, name it shear_stress"
                                      : ": a simple-shear test on soil does not reach it"));
  return lab;
}

ModelCurve model_curve_from_history(const io::CsvData& history) {
  const std::size_t strain = history.column("shear_strain"), stress = history.column("shear_stress"),
                    volumetric = history.column("volumetric_strain");
  ModelCurve model;
  for (const auto& row : history.rows) {
    if (!model.shear_strain.empty() && !(row[strain] > model.shear_strain.back())) continue;
    model.shear_strain.push_back(row[strain]);
    model.shear_stress.push_back(row[stress]);
    model.volumetric_strain.push_back(row[volumetric]);
  }
  return model;
}

CurveComparison compare_curves(const LabCurve& lab, const ModelCurve& model, const ComparisonOptions& options) {
  require(std::isfinite(options.eps_stress) && options.eps_stress >= 0, "eps_stress (Pa)", options.eps_stress, "finite and >= 0");
  require(std::isfinite(options.eps_strain) && options.eps_strain >= 0, "eps_strain", options.eps_strain, "finite and >= 0");
  CurveComparison out;
  const measure::Curve stress_model{model.shear_strain, model.shear_stress};
  out.stress = measure::relative_difference(lab.stress_curve(), stress_model, options.eps_stress);

  // Per-point values with the rule of measure::relative_difference: skip |lab| < eps, lab = 0,
  // and lab points outside the model's strain range (interpolate gives NaN there).
  auto per_point = [&](const std::vector<double>& lab_y, const measure::Curve& curve, double eps,
                       std::vector<double>& model_y, std::vector<double>& rd) {
    for (std::size_t k = 0; k < lab.size(); ++k) {
      const double y = measure::interpolate(curve, lab.shear_strain[k]);
      model_y.push_back(y);
      const bool used = std::isfinite(y) && lab_y[k] != 0.0 && std::abs(lab_y[k]) >= eps;
      rd.push_back(used ? 100.0 * std::abs(lab_y[k] - y) / std::abs(lab_y[k]) : -1.0);
    }
  };
  per_point(lab.shear_stress, stress_model, options.eps_stress, out.model_stress, out.stress_rd_percent);
  if (lab.has_volumetric()) {
    const measure::Curve volumetric_model{model.shear_strain, model.volumetric_strain};
    per_point(lab.volumetric_strain, volumetric_model, options.eps_strain, out.model_volumetric, out.volumetric_rd_percent);
    // relative_difference refuses a comparison without any usable point; then there is no metric.
    if (std::any_of(out.volumetric_rd_percent.begin(), out.volumetric_rd_percent.end(), [](double rd) { return rd >= 0; }))
      out.volumetric = measure::relative_difference(lab.volumetric_curve(), volumetric_model, options.eps_strain);
  }
  return out;
}

double slope_strain_limit(const LabCurve& lab, double stress_fraction) {
  require(stress_fraction > 0 && stress_fraction <= 1, "slope stress fraction", stress_fraction, "in (0, 1]");
  if (lab.size() < 2) throw InputError("lab curve " + lab.file.string() + ": fewer than two points: cannot fit an initial slope");
  const double peak = peak_value(lab.shear_stress);
  if (!(peak > 0.0)) throw InputError("lab curve " + lab.file.string() + ": no positive shear stress: cannot fit an initial slope");
  for (std::size_t k = 1; k < lab.size(); ++k)
    if (lab.shear_stress[k] >= stress_fraction * peak) return lab.shear_strain[k];
  return lab.max_strain();
}

double initial_slope(const LabCurve& lab, const std::vector<double>& y, double x_limit) {
  require(y.size() == lab.size(), "initial_slope values", y.size(), "one per lab point (" + std::to_string(lab.size()) + ")");
  // Through the origin, not through the first point or with a free intercept: the shear stress a
  // specimen keeps from consolidation grows with E* and belongs to its response, and a free
  // intercept would absorb the stiff start of the curve, leaving the frictional part.
  double sxx = 0.0, sxy = 0.0;
  for (std::size_t k = 0; k < lab.size(); ++k) {
    const double x = lab.shear_strain[k];
    if (x <= 0.0 || x > x_limit || !std::isfinite(y[k])) continue;
    sxx += x * x;
    sxy += x * y[k];
  }
  return sxx > 0 ? sxy / sxx : std::numeric_limits<double>::quiet_NaN();
}

double peak_value(const std::vector<double>& y) {
  double peak = -std::numeric_limits<double>::infinity();
  for (double v : y)
    if (std::isfinite(v)) peak = std::max(peak, v);
  return peak;
}

double late_mean(const LabCurve& lab, const std::vector<double>& y, double from_strain) {
  require(y.size() == lab.size(), "late_mean values", y.size(), "one per lab point (" + std::to_string(lab.size()) + ")");
  double sum = 0.0;
  int used = 0;
  for (std::size_t k = 0; k < lab.size(); ++k)
    if (lab.shear_strain[k] >= from_strain && std::isfinite(y[k])) sum += y[k], ++used;
  return used > 0 ? sum / used : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace dem::lab
