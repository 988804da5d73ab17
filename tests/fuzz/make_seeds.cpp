// Writes the seed inputs of the fuzz corpora: valid files of each format, plus a few typical
// mistakes, so that fuzzing starts from the structure of real inputs. Run it again after a format
// change (a new restart-file version makes the old checkpoint seeds stop at the version check):
//   <build>/tests/fuzz_make_seeds tests/fuzz/corpus
// Files are named seed-*; fuzzing adds the others (tests/fuzz/README.md).
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <dem/io/config.hpp>
#include <dem/io/csv.hpp>
#include <dem/lab/toolkit/simple_shear_config.hpp>

#include "checkpoint_world.hpp"
#include "fuzz_support.hpp"

using namespace dem;
namespace fs = std::filesystem;

namespace {

fs::path root;
int written = 0;

// `mode` is the first byte of targets that read one (fuzz_config, fuzz_checkpoint), -1 for none.
void seed(const std::string& target, const std::string& name, int mode, const std::string& body) {
  const std::string bytes = mode >= 0 ? std::string(1, static_cast<char>(mode)) + body : body;
  if (bytes.size() > 4000) {
    std::fprintf(stderr, "skipping %s/%s: %zu bytes (the corpus keeps inputs under 4 KB)\n", target.c_str(),
                 name.c_str(), bytes.size());
    return;
  }
  fs::create_directories(root / target);
  fuzz::write_bytes(root / target / ("seed-" + name), bytes);
  ++written;
}

std::string read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A protocol block like the simple-shear one: the loader returns it unread.
const std::string protocol = "stage 3\nball_count 4\npath_strain 0.0125\nhistory_rows 7\n";

void checkpoint_seed(const std::string& name, const World& world) {
  const fs::path file = fuzz::scratch("seed.restart");
  io::save_checkpoint(file, world, protocol);
  const std::string bytes = read_bytes(file);
  seed("checkpoint", name + "-file", 0, bytes);
  // Mode 1: the payload alone; the target frames it again.
  seed("checkpoint", name + "-payload", 1,
       bytes.substr(fuzz::checkpoint_header, bytes.size() - fuzz::checkpoint_header - 8));
}

BallSpec ball(double x, double y, double z, double r) {
  BallSpec b;
  b.position = Vec3(x, y, z);
  b.radius = r;
  b.density = 2650.0;
  return b;
}

void checkpoint_seeds() {
  {
    World world = fuzz::checkpoint_world();
    checkpoint_seed("empty", world);
  }
  {
    // Saved before and after the first step, which builds the neighbour lists.
    World world = fuzz::checkpoint_world();
    world.add_ball(ball(0, 0, 1e-3, 0.5e-3));
    checkpoint_seed("one-ball-unstepped", world);
    world.step(1);
    checkpoint_seed("one-ball", world);
  }
  {
    // Balls settling on a floor: ball-ball and ball-facet contacts with history.
    World world = fuzz::checkpoint_world();
    world.set_gravity(Vec3(0, 0, -9.81));
    world.add_wall(make_facet_wall("floor", geometry::make_rectangle(Vec3::Zero(), Vec3(2e-3, 0, 0), Vec3(0, 2e-3, 0)),
                                   -Vec3::UnitZ()));
    world.add_ball(ball(0, 0, 0.49e-3, 0.5e-3));
    world.add_ball(ball(0.99e-3, 0, 0.49e-3, 0.5e-3));
    world.add_ball(ball(0.5e-3, 0, 1.3e-3, 0.5e-3));
    world.step(300);
    checkpoint_seed("pile", world);
  }
  {
    // A two-pebble clump pressed by a ball: ball-pebble contacts and clump state.
    World world = fuzz::checkpoint_world();
    ClumpSpec clump;
    clump.pebbles = {{Vec3(0, 0, 0), 0.4e-3}, {Vec3(0.6e-3, 0, 0), 0.4e-3}};
    clump.with_pebble_mass(2650.0);
    world.add_clump(clump);
    BallSpec b = ball(0.3e-3, 0, 0.85e-3, 0.5e-3);
    b.velocity = Vec3(0, 0, -0.01);
    world.add_ball(b);
    world.step(50);
    checkpoint_seed("clump", world);
  }
}

void config_seeds() {
  const io::Schema schema = lab::simple_shear_schema();
  const io::Config defaults(schema);
  // Whole files are too long for the corpus: one seed per INI section and per JSON object.
  const std::string ini = defaults.to_ini();
  for (std::size_t start = ini.find('['); start != std::string::npos;) {
    const std::size_t next = ini.find("\n[", start);
    const std::string section = ini.substr(start, next == std::string::npos ? std::string::npos : next + 1 - start);
    seed("config", "ini-" + section.substr(1, section.find(']') - 1), 0, section);
    start = next == std::string::npos ? next : next + 1;
  }
  // to_json() prints one object per section, each starting on a line `  "section": {`.
  const std::string json = defaults.to_json();
  for (std::size_t start = json.find("\n  \""); start != std::string::npos;) {
    const std::size_t end = json.find("\n  }", start);
    const std::string section = json.substr(start + 1, end + 4 - start - 1);
    const std::size_t quote = section.find('"') + 1;
    seed("config", "json-" + section.substr(quote, section.find('"', quote) - quote), 1, "{\n" + section + "\n}\n");
    start = json.find("\n  \"", end);
  }
  for (const char* preset : {"1D", "2D", "4D"}) {
    std::string lines;
    for (const auto& [key, value] : lab::preset_values(preset)) lines += key + "=" + value + "\n";
    seed("config", std::string("set-preset-") + preset, 2, lines);
  }
  seed("config", "set-legs", 2, "shear.directions_deg=0,90,180\nshear.leg_strains=0.1, 0.1 ,0.05\n");
  seed("config", "set-mode", 2, "shear.mode = constant-volume\noutput.volumetric_strain_sign=compression-positive\n");
  // Typical mistakes: each must be refused with a message.
  seed("config", "bad-ini-typo", 0, "[contact]\nfricton = 0.5\n");
  seed("config", "bad-ini-range", 0, "[specimen]\nporosity = 1.5\n");
  seed("config", "bad-ini-duplicate", 0, "[shear]\ntarget_strain=0.1\n[shear]\ntarget_strain=0.2\n");
  seed("config", "bad-json-nested", 1, "{\"shear\": {\"target\": {\"strain\": 0.1}}}");
  seed("config", "bad-json-array", 1, "[1, 2, 3]");
  seed("config", "bad-json-duplicate", 1, "{\"shear\": {\"target_strain\": 0.1, \"target_strain\": 0.2}}");
  // Deeper than max_config_depth within 4 KB (the unit test has 50,000 levels).
  seed("config", "bad-json-deep", 1,
       "{\"shear\": {\"target_strain\": " + std::string(1900, '[') + std::string(1900, ']') + "}}");
  seed("config", "bad-json-list", 1, "{\"output\": {\"fabric_strains\": [0, [0.1], \"x\"]}}");
  seed("config", "bad-set-form", 2, "shear.target_strain\n=0.1\nshear.target_strain=1e999\n");
  seed("config", "bad-set-list", 2, "output.snapshot_strains=0,0.1,\noutput.snapshot_strains=,\n");
}

void csv_seeds() {
  io::CsvTable table({"time", "shear_strain", "shear_stress", "porosity"});
  table.add_row({0.0, 0.0, 0.0, 0.37});
  table.add_row({1.25e-3, 0.005, 18345.123456789, 0.3712});
  table.add_row({2.5e-3, -0.01, -2.2250738585072014e-308, 4.9406564584124654e-324});
  table.add_row({-0.0, 1e300, 123456789012345678.0, 0.1});
  const fs::path file = fuzz::scratch("seed.csv");
  table.save(file);
  seed("csv", "history", -1, read_bytes(file));
  seed("csv", "comments-blank-crlf", -1, "# a comment\r\n\r\ntime , stress\r\n  1 ,  2.5e3\r\n# end\r\n+3,-4\r\n");
  seed("csv", "one-column", -1, "x\n1\n2\n3\n");
  seed("csv", "header-only", -1, "a,b,c\n");
  seed("csv", "bad-cells", -1, "a,b\n1,nan\n1,inf\n0x10,1\n1e400,2\n");
  seed("csv", "bad-rows", -1, "a,b\n1\n1,2,3\n");
  seed("csv", "bad-header", -1, "a,,a\n1,2,3\n");
  seed("csv", "empty", -1, "");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s CORPUS_ROOT (e.g. tests/fuzz/corpus)\n", argv[0]);
    return 2;
  }
  root = argv[1];
  checkpoint_seeds();
  config_seeds();
  csv_seeds();
  std::printf("%d seeds written under %s\n", written, root.c_str());
  return 0;
}
