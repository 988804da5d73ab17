// The output folder a run claims: one run at a time, writable before any work, another run's
// results refused or replaced as a whole, and the temporary files of killed runs cleaned up.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sys/wait.h>
#include <unistd.h>

#include <dem/core/errors.hpp>
#include <dem/io/output_folder.hpp>

using namespace dem;
namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("libdem_output_folder_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  return dir;
}

void write(const fs::path& file, const std::string& text) {
  std::ofstream(file) << text;
}

std::string read(const fs::path& file) {
  std::ifstream in(file);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

io::OutputFolderPolicy policy() {
  io::OutputFolderPolicy p;
  p.run_files = {"history.csv", "snapshots", "final.restart"};
  p.program = "test-program";
  return p;
}

// The pid of a process that has ended: a child that exits at once, reaped.
pid_t ended_pid() {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ::waitpid(child, nullptr, 0);
  return child;
}

// The results of a run made by a claim as a run makes them: files recorded in its manifest.
void write_run(const fs::path& dir) {
  io::OutputFolder run(dir, policy());
  fs::create_directories(dir / "snapshots");
  write(dir / "history.csv", "time\n1\n");
  write(dir / "snapshots" / "balls_0.vtp", "x");
  run.record(dir / "snapshots" / "balls_0.vtp");
}


}  // namespace

TEST_CASE("output folder: a second claim while the first holds it is refused, naming the holder", "[io][output-folder]") {
  const fs::path dir = fresh_dir("lock") / "nested";
  {
    io::OutputFolder first(dir, policy());
    CHECK(fs::is_directory(dir));
    // flock locks belong to an open file: a second open in this process conflicts as another
    // process would.
    CHECK_THROWS_WITH(io::OutputFolder(dir, policy()),
                      Contains("in use by another run") && Contains("pid " + std::to_string(::getpid())) &&
                          Contains("test-program") && Contains(dir.string()));
  }
  CHECK_NOTHROW(io::OutputFolder(dir, policy()));  // released with the first
}


TEST_CASE("output folder: another run's results are refused untouched, or replaced together", "[io][output-folder]") {
  const fs::path dir = fresh_dir("replace");
  write_run(dir);
  write(dir / "notes.txt", "the user's own file");
  CHECK_THROWS_WITH(io::OutputFolder(dir, policy()),
                    Contains("holds the results of another run") && Contains("history.csv, snapshots") && Contains("--replace"));
  CHECK(read(dir / "history.csv") == "time\n1\n");
  CHECK(fs::exists(dir / "snapshots" / "balls_0.vtp"));

  io::OutputFolderPolicy continuing = policy();
  continuing.continues_own_run = true;  // a restart in this folder: its results are the run's own
  {
    io::OutputFolder own(dir, continuing);
    CHECK(own.manifest() == std::vector<std::string>{"history.csv", "snapshots", "final.restart", "snapshots/balls_0.vtp"});
  }
  CHECK(fs::exists(dir / "history.csv"));

  io::OutputFolderPolicy replacing = policy();
  replacing.replace = true;
  io::OutputFolder folder(dir, replacing);
  CHECK(folder.replaced() == std::vector<std::string>{"history.csv", "snapshots"});
  CHECK_FALSE(fs::exists(dir / "history.csv"));
  CHECK_FALSE(fs::exists(dir / "snapshots"));
  CHECK(read(dir / "notes.txt") == "the user's own file");  // not a result: left alone
  CHECK(folder.manifest() == std::vector<std::string>{"history.csv", "snapshots", "final.restart"});
}

TEST_CASE("output folder: a replace removes only what the manifest lists, a user's file in a run folder included", "[io][output-folder]") {
  const fs::path dir = fresh_dir("manifest");
  write_run(dir);
  write(dir / "snapshots" / "my_view.pvsm", "the user's ParaView state");
  write(dir / "snapshots" / "balls_9.vtp", "the user's own copy");  // named like a result, not the run's
  io::OutputFolderPolicy replacing = policy();
  replacing.replace = true;
  {
    io::OutputFolder folder(dir, replacing);
    CHECK(folder.kept() == std::vector<std::string>{"snapshots"});
    CHECK_FALSE(fs::exists(dir / "history.csv"));
    CHECK_FALSE(fs::exists(dir / "snapshots" / "balls_0.vtp"));
    CHECK(read(dir / "snapshots" / "my_view.pvsm") == "the user's ParaView state");
    CHECK(read(dir / "snapshots" / "balls_9.vtp") == "the user's own copy");
  }
  // A manifest that names a path outside the folder is refused before anything is removed.
  write(dir / "history.csv", "time\n");
  write(dir / "manifest.json", R"({"files": ["history.csv", "../elsewhere.txt"]})");
  CHECK_THROWS_WITH(io::OutputFolder(dir, replacing), Contains("manifest.json") && Contains("../elsewhere.txt") &&
                                                          Contains("not a path inside the folder"));
  CHECK(fs::exists(dir / "history.csv"));
}

TEST_CASE("output folder: results without a manifest lose only their named files, and a run folder is refused", "[io][output-folder]") {
  const fs::path dir = fresh_dir("legacy");
  fs::create_directories(dir / "snapshots");
  write(dir / "history.csv", "time\n1\n");
  write(dir / "snapshots" / "balls_0.vtp", "x");  // a run before manifests, or the user's: nobody can tell
  io::OutputFolderPolicy replacing = policy();
  replacing.replace = true;
  CHECK_THROWS_WITH(io::OutputFolder(dir, replacing),
                    Contains("snapshots/") && Contains("manifest.json") && Contains("remove snapshots/ yourself"));
  CHECK(fs::exists(dir / "history.csv"));  // refused: nothing removed
  fs::remove_all(dir / "snapshots");
  io::OutputFolder folder(dir, replacing);
  CHECK(folder.replaced() == std::vector<std::string>{"history.csv"});
  CHECK_FALSE(fs::exists(dir / "history.csv"));
}

TEST_CASE("output folder: temporary files of ended processes are removed, those of running ones kept", "[io][output-folder]") {
  const fs::path dir = fresh_dir("leftovers");
  fs::create_directories(dir / "snapshots");
  const std::string dead = std::to_string(ended_pid()), alive = std::to_string(::getppid());
  write(dir / ("history.csv.tmp." + dead), "time\n1,");
  write(dir / "snapshots" / ("balls_3.vtp.tmp." + dead), "<VTK");
  write(dir / ("fabric.csv.tmp." + alive), "being written");
  write(dir / "history.csv.tmp.notapid", "x");
  io::OutputFolderPolicy resuming = policy();
  resuming.continues_own_run = true;  // snapshots/ is there: the killed run's own
  io::OutputFolder folder(dir, resuming);
  CHECK(folder.leftovers_removed() == 2);
  CHECK_FALSE(fs::exists(dir / ("history.csv.tmp." + dead)));
  CHECK_FALSE(fs::exists(dir / "snapshots" / ("balls_3.vtp.tmp." + dead)));
  CHECK(fs::exists(dir / ("fabric.csv.tmp." + alive)));
  CHECK(fs::exists(dir / "history.csv.tmp.notapid"));
}

TEST_CASE("output folder: a user's file named like a temporary survives, and a refused claim sweeps nothing", "[io][output-folder]") {
  const fs::path dir = fresh_dir("user_tmp");
  fs::create_directories(dir / "my_data");
  const std::string dead = std::to_string(ended_pid());
  write(dir / ("notes.txt.tmp." + dead), "the user's own");
  write(dir / "my_data" / ("table.csv.tmp." + dead), "the user's own");
  write(dir / ("history.csv.tmp." + dead), "a killed run's");
  write(dir / "history.csv", "time\n");  // another run's results: refused without replace
  CHECK_THROWS_WITH(io::OutputFolder(dir, policy()), Contains("holds the results of another run"));
  CHECK(fs::exists(dir / ("history.csv.tmp." + dead)));  // refused: nothing touched
  io::OutputFolderPolicy replacing = policy();
  replacing.replace = true;
  io::OutputFolder folder(dir, replacing);
  CHECK(folder.leftovers_removed() == 1);
  CHECK_FALSE(fs::exists(dir / ("history.csv.tmp." + dead)));
  CHECK(read(dir / ("notes.txt.tmp." + dead)) == "the user's own");
  CHECK(read(dir / "my_data" / ("table.csv.tmp." + dead)) == "the user's own");
}

TEST_CASE("output folder: a file, or a folder that cannot be created, is refused before any work", "[io][output-folder]") {
  const fs::path dir = fresh_dir("unusable");
  fs::create_directories(dir);
  write(dir / "a_file", "x");
  CHECK_THROWS_AS(io::OutputFolder(dir / "a_file", policy()), InputError);
  CHECK_THROWS_WITH(io::OutputFolder(dir / "a_file", policy()), Contains("is a file, not a folder"));
  CHECK_THROWS_WITH(io::OutputFolder(dir / "a_file" / "sub", policy()), Contains("cannot be created"));
}
