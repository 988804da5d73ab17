// dem-ensemble: one dem-simple-shear configuration for several seeds, each seed's run a task of a
// task farm: spread over the MPI ranks under mpirun, else run --jobs at a time here. Seed K's run
// goes to OUT/seed_K exactly as `dem-simple-shear --set specimen.seed=K --out OUT/seed_K` writes
// it, so its results do not depend on where it ran. A seed whose folder holds summary.json is not
// run again and one with restart.restart continues from it: the same command resumes.
// scripts/ensemble runs this (--mpi N under mpirun) and writes the seeds' statistics.
#include <omp.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <dem/core/errors.hpp>
#include <dem/io/folder_lock.hpp>

#include "cli/simple_shear_run.hpp"
#include "cli/task_farm.hpp"

namespace fs = std::filesystem;

namespace {

constexpr const char* usage =
    "dem-ensemble: dem-simple-shear for several seeds, spread over MPI ranks under mpirun\n\n"
    "Usage: dem-ensemble --seeds 1-3 --out DIR [--jobs N] -- [dem-simple-shear options]\n"
    "       mpirun -n 3 dem-ensemble --seeds 1-6 --out DIR -- --preset 2D --threads 1\n\n"
    "  --seeds LIST   seeds, e.g. 1-5 or 1,4,7 (distinct integers >= 0); seed K runs in DIR/seed_K\n"
    "  --out DIR      ensemble folder (under mpirun: on a file system every rank sees)\n"
    "  --jobs N       seeds at a time on each process (default 1); each gets cores / N threads unless the\n"
    "                 options after -- set --threads or engine.threads\n"
    "Options after -- go to every seed's dem-simple-shear (not --out, --from or specimen.seed).\n"
    "A seed with DIR/seed_K/summary.json is done; one with DIR/seed_K/restart.restart continues from it.\n"
    "scripts/ensemble writes the mean and spread over the seeds (ensemble.csv, ensemble.json).\n";

struct EnsembleCommandLine {
  std::vector<long> seeds;
  fs::path out;
  int jobs = 1;
  std::vector<std::string> shear_args;  // after "--"
};

constexpr long most_seeds = 100000;

// A whole non-negative integer, or nullopt.
std::optional<long> whole_number(const std::string& text) {
  if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos || text.size() > 12) return std::nullopt;
  return std::stol(text);
}

std::vector<long> seed_list(const std::string& text) {
  const auto refuse = [&] {
    return dem::InputError("--seeds = " + text + ": must be distinct integers >= 0, like 1-5 or 1,4,7, at most " +
                           std::to_string(most_seeds) + " of them");
  };
  std::vector<long> seeds;
  std::istringstream parts(text);
  for (std::string part; std::getline(parts, part, ',');) {
    const std::size_t dash = part.find('-');
    const std::optional<long> lo = whole_number(part.substr(0, dash));
    const std::optional<long> hi = dash == std::string::npos ? lo : whole_number(part.substr(dash + 1));
    if (!lo || !hi || *hi < *lo || *hi - *lo >= most_seeds - static_cast<long>(seeds.size())) throw refuse();
    for (long s = *lo; s <= *hi; ++s) seeds.push_back(s);
  }
  if (seeds.empty() || text.back() == ',' || std::set<long>(seeds.begin(), seeds.end()).size() != seeds.size()) throw refuse();
  return seeds;
}

// The options dem-ensemble sets for each seed, in any of their spellings.
bool set_by_ensemble(const std::string& arg) {
  for (const char* option : {"--out", "--from", "--replace"})
    if (arg.rfind(option, 0) == 0) return true;
  return (arg.rfind("-o", 0) == 0 && arg.rfind("--", 0) != 0) || arg.find("specimen.seed") != std::string::npos;
}

// A seed's dem-simple-shear command line.
std::vector<std::string> seed_arguments(const EnsembleCommandLine& cli, long seed, const fs::path& folder, bool resume) {
  std::vector<std::string> args = {"dem-simple-shear"};
  // Seeds run side by side share the cores, unless the options choose a team themselves.
  const bool chooses_threads = std::any_of(cli.shear_args.begin(), cli.shear_args.end(),
                                           [](const std::string& arg) { return arg.find("threads") != std::string::npos; });
  if (cli.jobs > 1 && !chooses_threads)
    args.insert(args.end(), {"--set", "engine.threads=" + std::to_string(std::max(1, omp_get_max_threads() / cli.jobs))});
  args.insert(args.end(), cli.shear_args.begin(), cli.shear_args.end());
  for (const std::string& more : {std::string("--set"), "specimen.seed=" + std::to_string(seed), std::string("--out"), folder.string()})
    args.push_back(more);
  if (resume) args.insert(args.end(), {"--from", (folder / "restart.restart").string()});
  else args.emplace_back("--replace");  // a seed killed before its first restart file starts again
  return args;
}

std::optional<dem::cli::ShearCommandLine> parse_seed(std::vector<std::string> args, std::ostream& out) {
  std::vector<char*> argv;
  for (std::string& arg : args) argv.push_back(arg.data());
  return dem::cli::parse_shear_command_line(static_cast<int>(argv.size()), argv.data(), "dem-simple-shear", "simple shear", out);
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
      const std::optional<long> n = whole_number(jobs);
      dem::require(n && *n >= 1 && *n <= 4096, "--jobs", jobs, "an integer from 1 to 4096");
      cli.jobs = static_cast<int>(*n);
    } else {
      throw dem::InputError("option " + arg + ": not one of --seeds, --out, --jobs, --help (dem-simple-shear options go after --)");
    }
  }
  for (++a; a < argc; ++a) {
    const std::string arg = argv[a];
    if (set_by_ensemble(arg))
      throw dem::InputError("dem-simple-shear option " + arg + ": set by dem-ensemble (--out, --from, --replace and "
                            "specimen.seed: each seed has its own specimen and folder)");
    cli.shear_args.push_back(arg);
  }
  dem::require(!cli.seeds.empty(), "--seeds", "(missing)", "the seeds to run, e.g. 1-3");
  dem::require(!cli.out.empty(), "--out", "(missing)", "the ensemble folder");
  // The seeds' options are checked once here, so that a mistake ends the run before any seed.
  std::ostringstream printed;
  if (!parse_seed(seed_arguments(cli, cli.seeds.front(), cli.out / "seed_check", false), printed))
    throw dem::InputError("dem-simple-shear options that print text and run nothing (--help, --print-config): not for an ensemble");
  return cli;
}

// Seed `seed`'s run, to its end or its error; the line says which.
std::string run_seed(const EnsembleCommandLine& cli, long seed, int rank) {
  const fs::path folder = cli.out / ("seed_" + std::to_string(seed));
  fs::create_directories(folder);
  // The seed's folder is this ensemble's before anything in it is read or written: a second
  // ensemble into the same folder leaves a running seed's run.log and results alone.
  std::optional<dem::io::FolderLock> seed_lock;
  try {
    seed_lock.emplace(folder, ".ensemble.lock", "dem-ensemble");
  } catch (const dem::InputError& e) {
    return std::string("failed: ") + e.what();
  }
  if (fs::exists(folder / "summary.json")) return "done already (" + folder.string() + ")";
  const bool resume = fs::exists(folder / "restart.restart");
  std::ofstream log(folder / "run.log", resume ? std::ios::app : std::ios::trunc);
  std::cout << ("seed " + std::to_string(seed) + ": running on rank " + std::to_string(rank) + ", log in " +
                (folder / "run.log").string() + "\n")
            << std::flush;
  try {
    std::ostringstream printed;
    const auto shear = parse_seed(seed_arguments(cli, seed, folder, resume), printed);
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
    farm->on_leader([&] {
      fs::create_directories(cli->out);
      return std::string();
    });
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
