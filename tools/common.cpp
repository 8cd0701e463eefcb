#include "common.hpp"

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <set>
#include <stdexcept>

#include "terrain/memory.hpp"
#include "terrain/temp_files.hpp"

namespace terrain::tools {

std::string version() { return std::string(TERRAIN_VERSION) + " (git " + git_hash() + ")"; }

std::string provenance(int argc, char** argv) {
  std::string out = std::string(argc > 0 ? argv[0] : "?");
  if (auto slash = out.rfind('/'); slash != std::string::npos) out = out.substr(slash + 1);
  out += " " + version() + ":";
  // Options that do not change the result are left out, so that outputs made with
  // different thread counts or verbosity are byte-identical.
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "-q" || a == "--quiet" || a == "-v" || a == "--verbose" ||
        a.rfind("--threads=", 0) == 0)
      continue;
    if (a == "--threads") {
      ++i;
      continue;
    }
    out += " " + a;
  }
  return out;
}

void add_verbosity_flags(CLI::App& app, Verbosity& v) {
  app.add_flag("-q,--quiet", v.quiet, "No progress or warnings on stderr (errors still print)");
  app.add_flag("-v,--verbose", v.verbose, "Per-step timings on stderr");
}

terrain::Progress terminal_progress(const Verbosity& v, const std::string& label) {
  if (v.quiet) return {};
  auto last = std::make_shared<int>(-1);
  return [last, label](double f) {
    const int tick = int(f * 40.0 + 1e-9);  // 2.5 % steps, as GDAL's term progress
    if (*last < 0) std::fprintf(stderr, "%s: ", label.c_str());
    while (*last < tick && *last < 40) {
      ++*last;
      if (*last % 4 == 0)
        std::fprintf(stderr, "%d", *last * 10 / 4);
      else
        std::fputc('.', stderr);
    }
    if (tick >= 40 && *last == 40) {
      std::fputs(" - done.\n", stderr);
      *last = 41;
    }
    std::fflush(stderr);
    return true;
  };
}

double peak_rss_mib() {
  std::FILE* f = std::fopen("/proc/self/status", "r");
  if (!f) return 0.0;
  char line[256];
  double kib = 0.0;
  while (std::fgets(line, sizeof line, f))
    if (std::sscanf(line, "VmHWM: %lf kB", &kib) == 1) break;
  std::fclose(f);
  return kib / 1024.0;
}

void warn(const Verbosity& v, const std::string& message) {
  if (!v.quiet) std::cerr << "warning: " << message << "\n";
}

void step(const Verbosity& v, const std::string& message) {
  if (v.verbose && !v.quiet) std::cerr << message << "\n";
}

namespace {

// Throws CLI::ValidationError for the first named option (of `app` or its subcommands)
// whose value is a number that is not finite.
void reject_non_finite(const CLI::App& app) {
  for (const CLI::Option* opt : app.get_options()) {
    if (opt->get_positional()) continue;
    for (const std::string& value : opt->results()) {
      char* end = nullptr;
      const double v = std::strtod(value.c_str(), &end);
      if (!value.empty() && end == value.c_str() + value.size() && !std::isfinite(v))
        throw CLI::ValidationError(opt->get_name(), "'" + value + "' is not a finite number");
    }
  }
  for (const CLI::App* sub : app.get_subcommands()) reject_non_finite(*sub);
}

}  // namespace

namespace {

CLI::Validator number_check(bool zero, const char* name) {
  return CLI::Validator(
      [zero](std::string& text) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        if (end == text.c_str() || *end != '\0' || !(zero ? v >= 0 : v > 0))
          return "'" + text + "' is not a " + (zero ? "non-negative" : "positive") + " number";
        return {};
      },
      name);
}

}  // namespace

const CLI::Validator kPositive = number_check(false, "POSITIVE"),
                     kNonNegative = number_check(true, "NONNEGATIVE");

void check_distinct_paths(const std::vector<std::string>& inputs,
                          const std::vector<std::string>& outputs) {
  namespace fs = std::filesystem;
  auto same = [](const std::string& a, const std::string& b) {
    std::error_code ec1, ec2;
    if (fs::exists(a, ec1) && fs::exists(b, ec2)) return fs::equivalent(a, b, ec1);
    return fs::weakly_canonical(a, ec1) == fs::weakly_canonical(b, ec2);
  };
  for (std::size_t o = 0; o < outputs.size(); ++o) {
    if (outputs[o].empty()) continue;
    for (const std::string& in : inputs)
      if (!in.empty() && same(in, outputs[o]))
        throw terrain::Error("the output '" + outputs[o] + "' is the input '" + in +
                             "': give another output name");
    for (std::size_t k = 0; k < o; ++k)
      if (!outputs[k].empty() && same(outputs[k], outputs[o]))
        throw terrain::Error("two outputs are the same file: '" + outputs[k] + "' and '" +
                             outputs[o] + "'");
  }
}

void warn_stale_temporaries(const Verbosity& v, const std::vector<std::string>& outputs) {
  std::set<std::filesystem::path>
      stale;  // once each: outputs of one stem (m.ply, m.tpyr) find the same
  for (const std::string& out : outputs)
    if (!out.empty())
      for (const std::filesystem::path& p : terrain::stale_temporaries(out)) stale.insert(p);
  for (const std::filesystem::path& p : stale)
    warn(v, "stale temporary '" + p.string() + "' of a run that was killed; remove it (rm -r '" +
                p.string() + "')");
}

int mpi_launcher_size() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
    if (const char* v = std::getenv(name)) return std::max(1, std::atoi(v));
  return std::getenv("PMIX_RANK") ? 1 : 0;
}

int run_main(CLI::App& app, int argc, char** argv, const std::function<int()>& body) {
  const std::string name = app.get_name();
  // A file-size limit (ulimit -f) must fail a write (EFBIG), not kill the tool with its
  // temporary file left behind.
  std::signal(SIGXFSZ, SIG_IGN);
  // SIGINT, SIGTERM and SIGHUP remove this run's temporary files before it dies.
  terrain::install_interrupt_cleanup();
  try {
    app.parse(argc, argv);
    reject_non_finite(app);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << name << ": usage error: " << e.what() << " (see " << name << " --help)\n";
    return 2;
  }
  try {
    if (std::getenv("TERRAIN_MEMORY_MIB"))
      (void)terrain::available_memory();  // a bad value is an error at once
    return body();
  } catch (const CLI::ParseError& e) {  // validation done after parsing is a usage error too
    std::cerr << name << ": usage error: " << e.what() << " (see " << name << " --help)\n";
    return 2;
  } catch (const terrain::Error& e) {
    std::cerr << name << ": error: " << e.what() << "\n";
  } catch (const std::bad_alloc&) {
    std::cerr << name << ": error: out of memory\n";
  } catch (const std::length_error&) {  // a size past what can be allocated at all
    std::cerr
        << name
        << ": error: out of memory (a size larger than can be allocated: check the grid's size and "
           "spacing)\n";
  } catch (const std::exception& e) {
    std::cerr << name << ": error: " << e.what() << "\n";
  }
  return 1;
}

CLI::Option* add_memory_option(CLI::App& app, double& mib, const std::string& help, double least) {
  CLI::Option* o = app.add_option("--memory", mib, help)->check(CLI::Range(least, 16777216.0));
  return mib > 0 ? o->capture_default_str() : o;  // 0: not bounded unless given
}

}  // namespace terrain::tools
