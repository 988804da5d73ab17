// Fuzz target: the configuration reader, io::Config against simple_shear_schema(). The first byte
// picks the form of the rest: 0 an .ini file, 1 a .json file, 2 lines of --set assignments.
// Besides "InputError or nothing", it checks that a refused file or assignment changes no value,
// and that any accepted configuration prints (to_ini, to_json) to text that reads back equal.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include <dem/io/config.hpp>
#include <dem/lab/toolkit/simple_shear_config.hpp>

#include "fuzz_support.hpp"

using namespace dem;

namespace {

void check_round_trip(const io::Config& config, const std::string& name, const std::string& printed) {
  const auto file = fuzz::scratch(name);
  fuzz::write_bytes(file, printed);
  io::Config again(config.schema());
  if (fuzz::refuses_cleanly([&] { again.load_file(file); }))
    fuzz::fail("the printed configuration is refused when read back:\n" + printed);
  fuzz::check(again.to_ini() == config.to_ini(), "the configuration changed in a round trip through " + name);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  static const io::Schema schema = lab::simple_shear_schema();
  const std::string_view text(reinterpret_cast<const char*>(data) + 1, size - 1);
  io::Config config(schema);
  const std::string defaults = config.to_ini();
  switch (data[0] % 3) {
    case 0:
    case 1: {
      const auto file = fuzz::scratch(data[0] % 3 == 0 ? "input.ini" : "input.json");
      fuzz::write_bytes(file, text);
      // Errors name the file, so a user with several configurations knows which one is wrong.
      if (fuzz::refuses_cleanly([&] { config.load_file(file); }, file.string()))
        fuzz::check(config.to_ini() == defaults, "a refused file changed the configuration");
      break;
    }
    default: {
      // One assignment per line, applied in order like repeated --set options.
      for (std::size_t start = 0; start <= text.size();) {
        const std::size_t end = std::min(text.find('\n', start), text.size());
        const std::string assignment(text.substr(start, end - start));
        const std::string before = config.to_ini();
        if (fuzz::refuses_cleanly([&] { config.set(assignment); }))
          fuzz::check(config.to_ini() == before, "a refused --set changed the configuration");
        start = end + 1;
      }
    }
  }
  check_round_trip(config, "printed.ini", config.to_ini());
  check_round_trip(config, "printed.json", config.to_json());
  // The protocol's cross-key checks (leg lists, grading) refuse with InputError too.
  fuzz::refuses_cleanly([&] { (void)lab::simple_shear_config(config); });
  return 0;
}
