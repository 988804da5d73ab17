#include "common_options.hpp"

#include <dem/base/input_file.hpp>
#include <dem/core/errors.hpp>
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

io::Config resolve_config(io::Schema schema, const po::variables_map& vm) {
  io::Config config(std::move(schema));
  if (vm.count("preset"))
    for (const auto& [key, value] : lab::preset_values(vm["preset"].as<std::string>())) config.set(key, value);
  if (vm.count("config")) config.load_file(vm["config"].as<std::string>());
  if (vm.count("set"))
    for (const std::string& assignment : vm["set"].as<std::vector<std::string>>()) config.set(assignment);
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
