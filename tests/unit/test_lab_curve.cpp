// Lab curves for dem-calibrate: every unusable file is refused with a message that names the
// file, the line and the column where there is one, and what is allowed.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <dem/core/errors.hpp>
#include <dem/lab/toolkit/lab_curve.hpp>

using dem::InputError;
using dem::lab::LabCurve;
using dem::lab::read_lab_curve;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

// Files in a folder of this process, removed when the tests end.
struct Folder {
  fs::path path = fs::temp_directory_path() / ("libdem_lab_curve_" + std::to_string(::getpid()));
  Folder() { fs::create_directories(path); }
  ~Folder() {
    std::error_code ignored;
    fs::remove_all(path, ignored);
  }
};

fs::path lab_file(const std::string& name, const std::string& text) {
  static const Folder folder;
  const fs::path file = folder.path / name;
  std::ofstream(file) << text;
  return file;
}

}  // namespace

TEST_CASE("lab curve: a good file with comments, blank lines and extra columns", "[lab-curve]") {
  const fs::path file = lab_file("good.csv",
                                 "# NGI simple shear, Leighton Buzzard B, 200 kPa\n"
                                 "time_s,shear_strain,shear_stress,volumetric_strain\n"
                                 "\n"
                                 "0,0,0,0\n"
                                 "# a comment between rows\n"
                                 "10,0.001,5000,-0.0001\n"
                                 "20,0.002,9000,-0.0002\r\n");
  const LabCurve lab = read_lab_curve(file);
  REQUIRE(lab.size() == 3);
  CHECK(lab.shear_strain[2] == 0.002);
  CHECK(lab.shear_stress[1] == 5000.0);
  CHECK(lab.volumetric_strain[2] == -0.0002);
  CHECK(lab.max_strain() == 0.002);
  // Lines are those of the file, not row indices: comments and blank lines count.
  CHECK(lab.lines == std::vector<std::size_t>{4, 6, 7});
}

TEST_CASE("lab curve: a simple-shear history.csv gives its consolidated row and shear rows", "[lab-curve]") {
  // Generation (stage 1) and consolidation rows before, a repeated strain 0, missing values (nan)
  // in a column the curve does not read.
  const fs::path file = lab_file("history.csv",
                                 "time,step,stage,shear_strain,shear_stress,volumetric_strain,bonds_intact\n"
                                 "0.1,100,1,0,0,0,nan\n"
                                 "0.2,200,2,0,0,0,nan\n"
                                 "0.3,300,3,0,120,0,nan\n"
                                 "0.4,400,3,0.01,30000,-0.001,5\n"
                                 "0.5,500,3,0.02,52000,0.002,4\n"
                                 "0.6,600,4,0.02,52000,0.002,4\n");
  const LabCurve lab = read_lab_curve(file);
  CHECK(lab.shear_strain == std::vector<double>{0.0, 0.01, 0.02});
  CHECK(lab.shear_stress == std::vector<double>{0.0, 30000.0, 52000.0});
  CHECK(lab.volumetric_strain == std::vector<double>{0.0, -0.001, 0.002});
  CHECK(lab.lines == std::vector<std::size_t>{3, 5, 6});
  // A history that never sheared is no curve; an empty cell in a column the curve reads is named.
  CHECK_THROWS_WITH(read_lab_curve(lab_file("unsheared.csv", "step,stage,shear_strain,shear_stress\n1,1,0,0\n2,2,0,0\n")),
                    Contains("stage 2 and 3") && Contains("1 row"));
  CHECK_THROWS_WITH(read_lab_curve(lab_file("hole.csv", "step,stage,shear_strain,shear_stress\n1,2,0,0\n2,3,0.01,nan\n")),
                    Contains("hole.csv:3") && Contains("'shear_stress' is missing (nan)"));
}

TEST_CASE("lab curve: missing columns name the file and list the columns", "[lab-curve]") {
  const fs::path no_strain = lab_file("no_strain.csv", "strain,shear_stress\n0,0\n0.01,1000\n");
  CHECK_THROWS_AS(read_lab_curve(no_strain), InputError);
  CHECK_THROWS_WITH(read_lab_curve(no_strain), Contains("no_strain.csv") && Contains("shear_strain_percent") &&
                                                   Contains("columns are: strain, shear_stress"));
  const fs::path no_stress = lab_file("no_stress.csv", "shear_strain,tau\n0,0\n");
  CHECK_THROWS_WITH(read_lab_curve(no_stress), Contains("no_stress.csv") && Contains("shear_stress_kPa"));
  const fs::path both = lab_file("both.csv", "shear_strain,shear_strain_percent,shear_stress\n0,0,0\n");
  CHECK_THROWS_WITH(read_lab_curve(both), Contains("both") && Contains("only one"));
}

TEST_CASE("lab curve: strain must increase strictly and be >= 0, the message gives line and column", "[lab-curve]") {
  const fs::path back = lab_file("back.csv", "shear_strain_percent,shear_stress_kPa\n0,0\n1,10\n# note\n0.5,12\n");
  CHECK_THROWS_WITH(read_lab_curve(back), Contains("back.csv:5") && Contains("'shear_strain_percent'") &&
                                              Contains("0.5") && Contains("line 3") && Contains("increase strictly"));
  const fs::path flat = lab_file("flat.csv", "shear_strain,shear_stress\n0,0\n0.01,10\n0.01,12\n");
  CHECK_THROWS_WITH(read_lab_curve(flat), Contains("flat.csv:4") && Contains("increase strictly"));
  const fs::path negative = lab_file("negative.csv", "shear_strain,shear_stress\n-0.001,0\n0.01,10\n");
  CHECK_THROWS_WITH(read_lab_curve(negative), Contains("negative.csv:2") && Contains(">= 0"));
}

TEST_CASE("lab curve: NaN, text and empty files are refused by line", "[lab-curve]") {
  const fs::path nan = lab_file("nan.csv", "shear_strain,shear_stress\n0,0\n0.01,nan\n");
  CHECK_THROWS_WITH(read_lab_curve(nan), Contains("nan.csv:3") && Contains("shear_stress") && Contains("NaN"));
  const fs::path text = lab_file("text.csv", "shear_strain,shear_stress\n0,0\n0.01,12kPa\n");
  CHECK_THROWS_WITH(read_lab_curve(text), Contains("text.csv:3") && Contains("not a number"));
  const fs::path empty = lab_file("empty.csv", "");
  CHECK_THROWS_WITH(read_lab_curve(empty), Contains("empty.csv") && Contains("empty"));
  const fs::path header_only = lab_file("header_only.csv", "shear_strain,shear_stress\n# nothing yet\n");
  CHECK_THROWS_WITH(read_lab_curve(header_only), Contains("header_only.csv") && Contains("no data rows"));
  CHECK_THROWS_WITH(read_lab_curve(lab_file("missing_dir_check.csv", "x\n").parent_path() / "does_not_exist.csv"),
                    Contains("does_not_exist.csv") && Contains("does not exist"));
}

TEST_CASE("lab curve: percent read as a fraction and kPa read as Pa are refused with the column name to use", "[lab-curve]") {
  // The case: strains in percent without the suffix would make the calibration shear to 500 %.
  const fs::path percent = lab_file("percent.csv", "shear_strain,shear_stress\n0,0\n2,60000\n5,80000\n");
  CHECK_THROWS_WITH(read_lab_curve(percent), Contains("percent.csv:3") && Contains("above 1 (100 %)") &&
                                                 Contains("shear_strain_percent") && Contains("--strain-percent"));
  dem::lab::LabCurveOptions as_percent;
  as_percent.strain_percent = true;
  CHECK(read_lab_curve(percent, as_percent).shear_strain.back() == Approx(0.05));
  const fs::path volumetric = lab_file("volumetric.csv", "shear_strain,shear_stress,volumetric_strain\n0,0,0\n0.02,6e4,-1.5\n");
  CHECK_THROWS_WITH(read_lab_curve(volumetric), Contains("volumetric_strain") && Contains("beyond 1"));
  // A simple-shear curve that never reaches 1 kPa is a kPa column without its suffix.
  const fs::path kilo = lab_file("kilo.csv", "shear_strain,shear_stress\n0,0\n0.02,60\n0.05,80\n");
  CHECK_THROWS_WITH(read_lab_curve(kilo), Contains("peaks at 80 Pa") && Contains("shear_stress_kPa"));
  const fs::path named = lab_file("named.csv", "shear_strain,shear_stress_kPa\n0,0\n0.02,60\n0.05,80\n");
  CHECK(read_lab_curve(named).shear_stress.back() == Approx(8e4));
  // Pa values under a kPa header: 80,000 kPa (80 MPa) is no soil's simple-shear strength.
  const fs::path pascals = lab_file("pascals.csv", "shear_strain,shear_stress_kPa\n0,0\n0.02,60000\n0.05,80000\n");
  CHECK_THROWS_WITH(read_lab_curve(pascals), Contains("'shear_stress_kPa' peaks at 80000 kPa") && Contains("above 10 MPa") &&
                                                 Contains("name it shear_stress"));
  const fs::path huge = lab_file("huge.csv", "shear_strain,shear_stress\n0,0\n0.02,6e9\n");
  CHECK_THROWS_WITH(read_lab_curve(huge), Contains("peaks at 6000000000 Pa") && Contains("does not reach it"));
}
