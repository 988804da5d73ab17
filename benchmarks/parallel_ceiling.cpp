// parallel-ceiling: how much faster this machine runs T threads than one on work that shares
// nothing, now. On a cloud VM the answer is not T: the hypervisor may place two virtual
// processors on the two hyperthreads of one core, or run another guest beside them, from one
// minute to the next. A code's T-thread speedup can only be judged against this ceiling,
// measured in the same hour.
//
// Three kinds of work, each repeated, one thread and T threads alternating so that a change in
// the machine hits both alike:
//   compute: independent floating-point products and square roots in registers (no memory);
//   cache:   each thread sums its own 8 MiB array, again and again (the shared last-level cache,
//            where a 14,000-ball run's particles and contacts live);
//   memory:  each thread sums its own 64 MiB array (main memory, as a 112,000-ball run's).
// Prints, per kind, the median over the repetitions of
//   ceiling = T x (time of one thread's work alone) / (time of T threads each doing that work),
// which is T on an ideal machine.
#include <boost/program_options.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <vector>
#if defined(_OPENMP)
#include <omp.h>
#endif

namespace po = boost::program_options;

namespace {

/// Eight independent chains of products and a square root: the processor's FP units, no memory.
double compute_work(long rounds) {
  double c[8] = {1.0, 1.1, 1.2, 1.3, 1.4, 1.5, 1.6, 1.7};
  for (long r = 0; r < rounds; ++r)
    for (double& x : c) x = std::sqrt(x * 1.0000001 + 1e-9);
  double sum = 0.0;
  for (double x : c) sum += x;
  return sum;
}

/// Sums an array several times, in eight independent sums so that the cache or memory the array
/// lives in, not the adder's latency, sets the pace.
double memory_work(const std::vector<double>& data, int passes) {
  double sums[8] = {};
  for (int p = 0; p < passes; ++p)
    for (std::size_t i = 0; i + 8 <= data.size(); i += 8)
      for (int s = 0; s < 8; ++s) sums[s] += data[i + static_cast<std::size_t>(s)];
  double sum = 0.0;
  for (double s : sums) sum += s;
  return sum;
}

struct Kind {
  const char* name;
  std::size_t array_doubles;  // per thread, 0: no array
  int passes;                 // over the array: about 0.1 s on one thread
};
constexpr Kind kinds[] = {{"compute", 0, 0}, {"cache", std::size_t{1} << 20, 200}, {"memory", std::size_t{8} << 20, 16}};

/// Seconds for `threads` threads each doing one unit of a kind's work on its own array.
double time_work(const Kind& kind, int threads, long rounds, const std::vector<std::vector<double>>& arrays,
                 double& sink) {
  const auto start = std::chrono::steady_clock::now();
  double sum = 0.0;
#pragma omp parallel num_threads(threads) reduction(+ : sum)
  {
#if defined(_OPENMP)
    const int me = omp_get_thread_num();
#else
    const int me = 0;
#endif
    if (kind.array_doubles == 0) sum += compute_work(rounds);
    else sum += memory_work(arrays[static_cast<std::size_t>(me)], kind.passes);
  }
  sink += sum;
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

int main(int argc, char** argv) {
  int threads = 2, reps = 7;
  po::options_description opts("parallel-ceiling options");
  opts.add_options()("help", "this help")("threads", po::value(&threads)->default_value(2), "threads to compare with one")(
      "reps", po::value(&reps)->default_value(7), "alternating repetitions per kind of work");
  try {
    po::variables_map vm;
    po::store(po::parse_command_line(argc, argv, opts), vm);
    if (vm.count("help")) {
      std::cout << opts << "\n";
      return 0;
    }
    po::notify(vm);
  } catch (const std::exception& e) {
    std::cerr << "parallel-ceiling: " << e.what() << "\n";
    return 2;
  }
  if (threads < 2 || threads > 256) {
    std::cerr << "parallel-ceiling: --threads = " << threads << ": must be 2 to 256\n";
    return 2;
  }
  if (reps < 1) {
    std::cerr << "parallel-ceiling: --reps = " << reps << ": must be >= 1\n";
    return 2;
  }
  const long rounds = 20'000'000;  // about 0.2 s of compute work on one thread
  double sink = 0.0;
  std::printf("threads: %d\nrepetitions: %d\n", threads, reps);
  for (const Kind& kind : kinds) {
    // one array per thread, filled by that thread so that its pages sit near it
    std::vector<std::vector<double>> arrays(static_cast<std::size_t>(threads));
#pragma omp parallel for num_threads(threads)
    for (int t = 0; t < threads; ++t) arrays[static_cast<std::size_t>(t)].assign(kind.array_doubles, 1.0 + t);
    std::vector<double> ceilings;
    for (int r = 0; r < reps; ++r) {
      const double alone = time_work(kind, 1, rounds, arrays, sink);
      const double together = time_work(kind, threads, rounds, arrays, sink);
      ceilings.push_back(threads * alone / together);
    }
    std::sort(ceilings.begin(), ceilings.end());
    std::printf("%s_ceiling: %.2f\n%s_ceiling_range: %.2f-%.2f\n", kind.name, ceilings[ceilings.size() / 2], kind.name,
                ceilings.front(), ceilings.back());
  }
  if (sink == 42.0) std::printf(" \n");  // keeps the work from being optimised away
  return 0;
}
