// A laboratory simple-shear curve (shear stress and, optionally, volumetric strain against shear
// strain) read from CSV, and its comparison with a model curve: the study's Table 2 metric
// (docs/model.md 8) plus the two curve features its manual calibration matched, the initial slope
// and the peak.
//
// Units are explicit, never guessed: a value of 2 in a strain column could be 2 % or 200 %, and a
// calibration against the wrong one converges happily to nonsense. So the file says what it holds
// in its header (shear_strain_percent, shear_stress_kPa) or the caller says it (strain_percent),
// and everything is converted to SI (fraction, Pa) on input.
//
// Comparison: the model is interpolated onto the lab strains (as measure::relative_difference
// does), so every lab point counts once however densely the model was sampled.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <dem/io/csv.hpp>
#include <dem/measure/relative_difference.hpp>

namespace dem::lab {

/// How to read a lab CSV.
struct LabCurveOptions {
  bool strain_percent = false;  // strain columns without a _percent suffix are in % (--strain-percent)
};

/// Accepted columns (other columns are ignored):
///   shear_strain | shear_strain_percent           required, -, or % with the suffix
///   shear_stress | shear_stress_kPa               required, Pa, or kPa with the suffix
///   volumetric_strain | volumetric_strain_percent optional, -, or %; the sign convention of the
///                                                 model's output.volumetric_strain_sign
inline constexpr const char* lab_curve_columns_help =
    "a header line naming the columns, then one row per strain point; blank lines and lines\n"
    "starting with '#' are skipped, other columns ignored.\n"
    "  shear_strain               required: fraction (0.05 = 5 %), or % with --strain-percent\n"
    "  shear_strain_percent       required instead: %\n"
    "                             strictly increasing, >= 0 (from the start of shear)\n"
    "  shear_stress               required: Pa\n"
    "  shear_stress_kPa           required instead: kPa\n"
    "  volumetric_strain          optional: fraction, or % with --strain-percent; the sign\n"
    "                             convention of output.volumetric_strain_sign (default dilation positive)\n"
    "  volumetric_strain_percent  optional instead: %\n"
    "Units are never guessed from the values. A dem-simple-shear history.csv (a header with step and stage)\n"
    "is read as its consolidated row and shear rows: one run's curve as the lab curve of another.\n";

struct LabCurve {
  std::filesystem::path file;
  std::vector<double> shear_strain;       // -, strictly increasing, >= 0
  std::vector<double> shear_stress;       // Pa
  std::vector<double> volumetric_strain;  // -, empty if the file has no such column
  std::vector<std::size_t> lines;         // file line of each point (1-based)

  bool has_volumetric() const { return !volumetric_strain.empty(); }
  std::size_t size() const { return shear_strain.size(); }
  double max_strain() const { return shear_strain.empty() ? 0.0 : shear_strain.back(); }  // -
  measure::Curve stress_curve() const { return {shear_strain, shear_stress}; }
  measure::Curve volumetric_curve() const { return {shear_strain, volumetric_strain}; }
};

/// Reads a lab curve. InputError naming the file (and line and column where there is one) for:
/// a missing file, an empty file or one without data rows, a missing required column, two
/// columns for the same quantity (e.g. shear_stress and shear_stress_kPa), a cell that is not a
/// finite number (NaN, inf, text), a negative strain or one not greater than the previous row's,
/// and values whose size says the unit in the header is wrong: a strain beyond 1 (100 %), a peak
/// shear stress below 1 kPa in a Pa column or above 10 MPa in either column. A dem-simple-shear
/// history.csv (its header has `step` and `stage`) is read as its consolidated row and its shear
/// rows (stage 2 and 3), in SI, a row whose strain does not pass the previous one's left out:
/// one run's curve as another's lab curve (docs/size-effect.md, one curve at three scales).
LabCurve read_lab_curve(const std::filesystem::path& file, const LabCurveOptions& options = {});

/// A model curve sampled along the shear (SI).
struct ModelCurve {
  std::vector<double> shear_strain;       // -, strictly increasing
  std::vector<double> shear_stress;       // Pa
  std::vector<double> volumetric_strain;  // -
};

/// The model curve from a SimpleShearTest history (columns shear_strain, shear_stress,
/// volumetric_strain). Rows whose strain does not exceed the previous kept row's are dropped
/// (the consolidation row and a shear row can both sit at strain 0).
ModelCurve model_curve_from_history(const io::CsvData& history);

/// Points with |lab| below these are skipped by the relative difference (docs/model.md 8).
struct ComparisonOptions {
  double eps_stress = 1000.0;  // Pa
  double eps_strain = 1e-4;    // -, for volumetric strain
};

/// Lab against model on the lab's strain points.
struct CurveComparison {
  measure::RelativeDifference stress{};                     // shear stress, %
  std::optional<measure::RelativeDifference> volumetric;    // absent without lab volumetric strain or usable point
  std::vector<double> model_stress;                         // Pa, model at each lab strain (NaN outside its range)
  std::vector<double> model_volumetric;                     // -, same; empty without lab volumetric strain
  std::vector<double> stress_rd_percent;                    // %, per lab point; -1 where skipped
  std::vector<double> volumetric_rd_percent;                // %, per lab point; -1 where skipped
};

/// The relative differences of shear stress and volumetric strain, per point and as max/mean.
/// InputError (from measure::relative_difference) if no lab stress point is usable.
CurveComparison compare_curves(const LabCurve& lab, const ModelCurve& model, const ComparisonOptions& options);

/// The lab strain up to which the initial slope is fitted: the first lab strain at which the
/// shear stress reaches `stress_fraction` of the lab's peak (at least the second lab point).
/// InputError if the curve has fewer than two points or no positive stress.
double slope_strain_limit(const LabCurve& lab, double stress_fraction);

/// Initial slope (Pa per unit strain) of y(x) over the lab points with 0 < x <= x_limit: least
/// squares through the origin, sum(x y) / sum(x^2). `y` holds one value per lab point (the lab's
/// own stresses or a model interpolated onto them); NaN entries are ignored; NaN if no point
/// qualifies.
double initial_slope(const LabCurve& lab, const std::vector<double>& y, double x_limit);

/// The largest finite entry of `y` (one value per lab point), Pa; -inf if there is none.
double peak_value(const std::vector<double>& y);

/// The mean of the finite entries of `y` (one value per lab point) at lab strains >= `from_strain`;
/// NaN if there is none. The calibration's "late dilatancy" is this of the volumetric strain.
double late_mean(const LabCurve& lab, const std::vector<double>& y, double from_strain);

}  // namespace dem::lab
