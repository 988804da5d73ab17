// Input files are regular files of a plausible size: a FIFO (which would block the read), a device
// (/dev/zero would be read until memory runs out), a folder and a missing file are refused by
// name, before anything is opened, by every reader.
#include <catch2/catch.hpp>
#include <sys/stat.h>

#include <filesystem>

#include <dem/base/errors.hpp>
#include <dem/base/input_file.hpp>
#include <dem/io/checkpoint.hpp>
#include <dem/io/config.hpp>
#include <dem/io/csv.hpp>
#include <dem/lab/toolkit/lab_curve.hpp>

#include "support/temp_dir.hpp"

using Catch::Matchers::Contains;
namespace fs = std::filesystem;

TEST_CASE("input files: a FIFO, a device, a folder, a missing or an oversized file is refused by name") {
  const dem::testing::TempDir dir("input_file");
  const fs::path fifo = dir.path / "pipe.restart";
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  const fs::path small = dir.write("small.csv", "a,b\n1,2\n");
  const auto refused = [](const fs::path& path, const std::string& kind) {
    CHECK_THROWS_WITH(dem::require_input_file(path, "--from", "a restart file", 1000),
                      Contains("--from = " + path.string()) && Contains(kind) && Contains("must be a restart file"));
  };
  refused(fifo, "is a FIFO");
  refused("/dev/zero", "is a character device");
  refused(dir.path, "is a folder");
  refused(dir.path / "absent.restart", "does not exist");
  CHECK_NOTHROW(dem::require_input_file(small, "--lab", "a CSV file", 1000));
  CHECK_THROWS_WITH(dem::require_input_file(small, "--lab", "a CSV file", 4), Contains("8 bytes") && Contains("at most 4 bytes"));
}

TEST_CASE("input files: every reader refuses a FIFO and /dev/zero at once instead of blocking or filling memory") {
  const dem::testing::TempDir dir("input_readers");
  const fs::path fifo = dir.path / "pipe.csv";
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  const fs::path fifo_ini = dir.path / "pipe.ini";
  REQUIRE(::mkfifo(fifo_ini.c_str(), 0600) == 0);
  for (const fs::path& path : {fifo, fs::path("/dev/zero")}) {
    CHECK_THROWS_AS(dem::io::read_csv(path), dem::InputError);
    CHECK_THROWS_WITH(dem::lab::read_lab_curve(path, {}), Contains("lab curve") && Contains(path.string()));
    CHECK_THROWS_WITH(dem::io::read_checkpoint_protocol(path), Contains("restart file") && Contains(path.string()));
  }
  const dem::io::Schema schema;
  dem::io::Config config(schema);
  CHECK_THROWS_WITH(config.load_file(fifo_ini), Contains("is a FIFO"));
}
