#pragma once
// What every tool shares: version and provenance strings, progress on stderr, and the
// one top-level error handler with the exit-code policy (0 ok, 1 failure, 2 usage).
#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <vector>

#include "terrain/error.hpp"

namespace terrain::tools {

// "0.1.0 (git abc1234)"
std::string version();
// `git describe --always --dirty` of the source tree at build time (generated source).
const char* git_hash();

// "TOOL VERSION: ARGV..." recorded in every output file's header or metadata, without the
// options that cannot change an output (-q, -v, --threads).
std::string provenance(int argc, char** argv);

// Verbosity from -q / -v.
struct Verbosity {
  bool quiet = false;
  bool verbose = false;
};
void add_verbosity_flags(CLI::App& app, Verbosity& v);

// GDAL-style "0...10...20...30...40...50...60...70...80...90...100 - done." on stderr;
// empty (silent) when quiet.
terrain::Progress terminal_progress(const Verbosity& v, const std::string& label);

// A diagnostic line on stderr ("TOOL: warning: ..."), suppressed by -q.
void warn(const Verbosity& v, const std::string& message);
// Peak resident memory of this process so far, in MiB (Linux VmHWM; 0 when unknown).
double peak_rss_mib();

// The number of ranks an MPI launcher (mpirun, mpiexec, srun) started this process among,
// from its environment (OMPI_COMM_WORLD_SIZE, PMI_SIZE); 0 when no launcher started it.
int mpi_launcher_size();

// A per-step timing line on stderr at -v.
void step(const Verbosity& v, const std::string& message);

// Threads a tool may be asked for (--threads): 1 .. 1024 (OpenMP's runtime fails far
// below 100000).
inline constexpr int kMaxThreads = 1024;

// Throws Error unless every output differs from every input and from every other output
// (same resolved path, or the same file through another name: a hard or symbolic link).
// Empty strings are skipped.
void check_distinct_paths(const std::vector<std::string>& inputs,
                          const std::vector<std::string>& outputs);

// Option checks for a number > 0 and >= 0 whose message names the value (CLI11's
// PositiveNumber and NonNegativeNumber print the largest double in full).
extern const CLI::Validator kPositive, kNonNegative;

// --memory MIB, declared once for every tool: the bound a run keeps to, in the tool's own
// sense (`help`), at least `least` MiB; its default shown unless 0 (no bound).
CLI::Option* add_memory_option(CLI::App& app, double& mib, const std::string& help, double least);

// --tile-size N, declared once for every tool: the work in pieces of N (rows or samples a
// side, in the tool's sense: `help`), 1 .. `most`; --memory, declared after it, excludes it.
template <class T>
CLI::Option* add_tile_size_option(CLI::App& app, T& n, const std::string& help, T most) {
  return app.add_option("--tile-size", n, help)->check(CLI::Range(T(1), most));
}

// Warns (-q silences it) of each temporary file or scratch folder beside an output that a
// run on it left when it was killed (SIGKILL, a power cut: temp_files.hpp), with the
// command that removes it. Empty strings are skipped.
void warn_stale_temporaries(const Verbosity& v, const std::vector<std::string>& outputs);

// Runs `body` after CLI11 parsing with the exit-code policy. A named option's value that
// parses as a number but not a finite one (nan, inf, 1e999) is a usage error for every
// option of every tool, so no option lets NaN into the arithmetic. CLI11 usage errors -> 2
// (message and a hint to --help), terrain::Error and other exceptions -> 1 with one line
// "TOOL: error: MESSAGE" on stderr, --help -> 0.
int run_main(CLI::App& app, int argc, char** argv, const std::function<int()>& body);

}  // namespace terrain::tools
