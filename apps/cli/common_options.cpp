#include "common_options.hpp"

#include <dem/base/input_file.hpp>
#include <dem/core/errors.hpp>
#include <dem/core/law_registry.hpp>
#include <dem/lab/toolkit/simple_shear_config.hpp>

namespace po = boost::program_options;

namespace dem::cli {

void add_common_options(po::options_description& opts, const std::string& preset_help, const std::string& config_help, const std::string& set_example) {
  opts.add_options()("help,h", "print this help and every configuration key");
  if (!preset_help.empty()) opts.add_options()("preset", po::value<std::string>()->default_value("4D"), preset_help.c_str());
  opts.add_options()(
      "config,c", po::value<std::string>(), config_help.c_str())(
      "set,s", po::value<std::vector<std::string>>()->composing(), ("override one key, e.g. --set " + set_example + " (repeatable)").c_str())(
      "threads", po::value<int>(), "threads (same as --set engine.threads=N; default auto: the cores this process may run on)")(
      "print-config", "print the resolved configuration (INI) and exit");
}

po::variables_map parse_options(int argc, char** argv, const po::options_description& opts) {
  po::variables_map vm;
  try {
    po::store(po::parse_command_line(argc, argv, opts), vm);
    po::notify(vm);
  } catch (const po::error& e) {
    throw InputError(std::string("command line: ") + e.what() + " (see --help)");
  }
  return vm;
}

namespace {

// A preset gives the parameters of its own law (the study's rrlinear E*, for one). A user who
// chooses another law for a contact type has not given those: they go back to their defaults, so
// that the check against keys of a law not chosen (lab/toolkit/contact_config) refuses only what
// the user wrote. `preset` holds the preset's values; a key the user set to another value stays (and
// is refused there); one set to the preset's own value is dropped with it.
void drop_preset_keys_of_other_laws(io::Config& config, const std::vector<std::pair<std::string, std::string>>& preset) {
  for (const auto& [key, value] : preset) {
    const auto dot = key.find('.');
    if (dot == std::string::npos || config.schema().find(key.substr(0, dot) + ".law") == nullptr) continue;
    const std::string section = key.substr(0, dot), name = key.substr(dot + 1);
    const LawEntry& law = contact_law(config.text(section + ".law"), section + ".law");
    bool of_law = name == "law";
    for (const LawParameter& p : law.parameters) of_law = of_law || p.name == name;
    bool a_law_parameter = false;
    for (const LawEntry& other : contact_laws())
      for (const LawParameter& p : other.parameters) a_law_parameter = a_law_parameter || p.name == name;
    if (of_law || !a_law_parameter) continue;
    io::Config preset_only(config.schema());
    preset_only.set(key, value);
    if (config.exact_text(key) != preset_only.exact_text(key)) continue;  // the user's own value
    config.set(key, config.schema().find(key)->default_value);
  }
}

}  // namespace

io::Config resolve_config(io::Schema schema, const po::variables_map& vm) {
  io::Config config(std::move(schema));
  std::vector<std::pair<std::string, std::string>> preset;
  if (vm.count("preset")) preset = lab::preset_values(vm["preset"].as<std::string>());
  for (const auto& [key, value] : preset) config.set(key, value);
  if (vm.count("config")) config.load_file(vm["config"].as<std::string>());
  if (vm.count("set"))
    for (const std::string& assignment : vm["set"].as<std::vector<std::string>>()) config.set(assignment);
  drop_preset_keys_of_other_laws(config, preset);
  if (vm.count("threads")) {
    const int threads = vm["threads"].as<int>();
    require(threads >= 1, "--threads", threads, ">= 1");
    config.set("engine.threads", std::to_string(threads));
  }
  return config;
}

std::filesystem::path restart_file(const po::variables_map& vm) {
  if (!vm.count("from")) return {};
  std::filesystem::path from = vm["from"].as<std::string>();
  const std::string allowed = std::filesystem::is_directory(from)
                                  ? "a restart file, e.g. " + (from / "consolidated.restart").string() + " or " +
                                        (from / "restart.restart").string()
                                  : "a restart file";
  require_input_file(from, "--from", allowed, max_restart_file_bytes);
  return from;
}

}  // namespace dem::cli
