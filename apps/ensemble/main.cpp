// dem-ensemble: one dem-simple-shear configuration for several seeds, each seed's run a task of a
// task farm: spread over the MPI ranks under mpirun, else run --jobs at a time here. Seed K's run
// goes to OUT/seed_K exactly as `dem-simple-shear --set specimen.seed=K --out OUT/seed_K` writes
// it, so its results do not depend on where it ran. A seed whose folder holds summary.json is not
// run again and one with restart.restart continues from it: the same command resumes.
// scripts/ensemble runs this (--mpi N under mpirun) and writes the seeds' statistics.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <dem/core/errors.hpp>

#include "cli/simple_shear_run.hpp"
#include "cli/task_farm.hpp"

namespace fs = std::filesystem;

namespace {

constexpr const char* usage =
    "dem-ensemble: dem-simple-shear for several seeds, spread over MPI ranks under mpirun\n\n"
    "Usage: dem-ensemble --seeds 1-3 --out DIR [--jobs N] -- [dem-simple-shear options]\n"
    "       mpirun -n 3 dem-ensemble --seeds 1-6 --out DIR -- --preset 2D --threads 1\n\n"
    "  --seeds LIST   seeds, e.g. 1-5 or 1,4,7 (distinct integers >= 0); seed K runs in DIR/seed_K\n"
    "  --out DIR      ensemble folder\n"
    "  --jobs N       seeds at a time on each process (default 1); give each --threads cores / N\n"
    "Options after -- go to every seed's dem-simple-shear (not --out, --from or specimen.seed).\n"
    "A seed with DIR/seed_K/summary.json is done; one with DIR/seed_K/restart.restart continues from it.\n"
    "scripts/ensemble writes the mean and spread over the seeds (ensemble.csv, ensemble.json).\n";

struct EnsembleCommandLine {
  std::vector<long> seeds;
  fs::path out;
  int jobs = 1;
  std::vector<std::string> shear_args;  // after "--"
};

std::vector<long> seed_list(const std::string& text) {
  const std::string allowed = "distinct integers >= 0, like 1-5 or 1,4,7";
  std::vector<long> seeds;
  std::istringstream parts(text);
  for (std::string part; std::getline(parts, part, ',');) {
    try {
      std::size_t used = 0;
      const std::size_t dash = part.find('-', 1);
      const long lo = std::stol(part.substr(0, dash), &used);
      const long hi = dash == std::string::npos ? lo : std::stol(part.substr(dash + 1));
      if (lo < 0 || hi < lo || (dash == std::string::npos && used != part.size())) throw std::invalid_argument(part);
      for (long s = lo; s <= hi; ++s) seeds.push_back(s);
    } catch (const std::logic_error&) {
      throw dem::InputError("--seeds = " + text + ": must be " + allowed);
    }
  }
  if (seeds.empty() || std::set<long>(seeds.begin(), seeds.end()).size() != seeds.size())
    throw dem::InputError("--seeds = " + text + ": must be " + allowed);
  return seeds;
}

// nullopt: --help was printed.
std::optional<EnsembleCommandLine> parse(int argc, char** argv) {
  EnsembleCommandLine cli;
  int a = 1;
  auto value = [&](const std::string& option) {
    if (a + 1 >= argc) throw dem::InputError(option + ": needs a value (see --help)");
    return std::string(argv[++a]);
  };
  for (; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg == "--") break;
    if (arg == "--help" || arg == "-h") {
      std::cout << usage;
      return std::nullopt;
    }
    if (arg == "--seeds") cli.seeds = seed_list(value(arg));
    else if (arg == "--out" || arg == "-o") cli.out = value(arg);
    else if (arg == "--jobs") {
      const std::string jobs = value(arg);
      try {
        cli.jobs = std::stoi(jobs);
      } catch (const std::logic_error&) {
        cli.jobs = 0;
      }
      dem::require(cli.jobs >= 1, "--jobs", jobs, "an integer >= 1");
    } else {
      throw dem::InputError("option " + arg + ": not one of --seeds, --out, --jobs, --help (dem-simple-shear options go after --)");
    }
  }
  for (++a; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg == "--out" || arg == "-o" || arg == "--from" || arg.find("specimen.seed") != std::string::npos)
      throw dem::InputError("dem-simple-shear option " + arg + ": set by dem-ensemble (each seed has its own specimen and folder)");
    cli.shear_args.push_back(arg);
  }
  dem::require(!cli.seeds.empty(), "--seeds", "(missing)", "the seeds to run, e.g. 1-3");
  dem::require(!cli.out.empty(), "--out", "(missing)", "the ensemble folder");
  return cli;
}

// Seed `seed`'s run, to its end or its error; the line says which.
std::string run_seed(const EnsembleCommandLine& cli, long seed, int rank) {
  const fs::path folder = cli.out / ("seed_" + std::to_string(seed));
  if (fs::exists(folder / "summary.json")) return "done already (" + folder.string() + ")";
  const fs::path restart = folder / "restart.restart";
  const bool resume = fs::exists(restart);
  std::vector<std::string> args = {"dem-simple-shear"};
  args.insert(args.end(), cli.shear_args.begin(), cli.shear_args.end());
  for (const std::string& more : {std::string("--set"), "specimen.seed=" + std::to_string(seed), std::string("--out"), folder.string()})
    args.push_back(more);
  if (resume) args.insert(args.end(), {"--from", restart.string()});
  else args.emplace_back("--replace");  // a seed killed before its first restart file starts again
  std::vector<char*> argv;
  for (std::string& arg : args) argv.push_back(arg.data());
  fs::create_directories(folder);
  std::ofstream log(folder / "run.log", resume ? std::ios::app : std::ios::trunc);
  std::cout << ("seed " + std::to_string(seed) + ": running on rank " + std::to_string(rank) + ", log in " +
                (folder / "run.log").string() + "\n")
            << std::flush;
  try {
    std::ostringstream help;
    const auto shear = dem::cli::parse_shear_command_line(static_cast<int>(argv.size()), argv.data(), "dem-simple-shear",
                                                          "simple shear", help);
    if (!shear) throw dem::InputError("dem-simple-shear options print text and run nothing (--help, --print-config)");
    dem::cli::run_simple_shear(*shear, log, "dem-ensemble");
    return "done";
  } catch (const std::exception& e) {
    log << "dem-ensemble: " << e.what() << "\n";
    return std::string("failed: ") + e.what();
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::optional<EnsembleCommandLine> cli;
  std::unique_ptr<dem::parallel::TaskFarm> farm;
  try {
    cli = parse(argc, argv);
    if (!cli) return 0;
    farm = dem::cli::open_task_farm(argc, argv);
  } catch (const dem::InputError& e) {
    std::cerr << "dem-ensemble: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "dem-ensemble: " << e.what() << "\n";
    return 1;
  }
  try {
    if (farm->leads()) fs::create_directories(cli->out);
    farm->barrier();
    int failed = 0;
    farm->run(
        cli->seeds.size(), cli->jobs, [&](std::size_t k) { return run_seed(*cli, cli->seeds[k], farm->process()); },
        [&](std::size_t k, const std::string& outcome) {
          failed += outcome.rfind("failed", 0) == 0;
          if (farm->leads()) std::cout << "seed " << cli->seeds[k] << ": " << outcome << std::endl;
        });
    if (farm->leads())
      std::cout << cli->seeds.size() - static_cast<std::size_t>(failed) << " of " << cli->seeds.size() << " seed(s) done in "
                << cli->out.string() << "/seed_K" << (farm->processes() > 1 ? " on " + std::to_string(farm->processes()) + " MPI ranks" : "")
                << "\n";
    return failed > 0 ? 1 : 0;
  } catch (const dem::InputError& e) {
    return dem::cli::end_on_error(*farm, "dem-ensemble", e, 2, std::cerr);
  } catch (const std::exception& e) {
    return dem::cli::end_on_error(*farm, "dem-ensemble", e, 1, std::cerr);
  }
}
