#pragma once
// Errors and progress reporting shared by every libterrain function.
#include <functional>
#include <stdexcept>
#include <string>

namespace terrain {

// Failure a user can act on (bad input, impossible request, failed I/O). The message is
// one line, names the file or parameter at fault, and never ends with a period.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Progress callback: called with the fraction done in [0, 1]; returning false cancels
// the work, which then throws Cancelled. An empty callback reports nothing.
using Progress = std::function<bool(double fraction)>;

// No-data samples where a grid needs values (a caller may say how else to read the input).
class NodataError : public Error {
 public:
  using Error::Error;
};

class Cancelled : public Error {
 public:
  Cancelled() : Error("cancelled") {}
};

// Calls `progress` (if set) with `fraction` and throws Cancelled when it asks to stop.
inline void report(const Progress& progress, double fraction) {
  if (progress && !progress(fraction)) throw Cancelled();
}

// A sub-range [begin, end] of an outer progress callback, for multi-step work.
inline Progress sub_progress(const Progress& outer, double begin, double end) {
  if (!outer) return {};
  return [outer, begin, end](double f) { return outer(begin + (end - begin) * f); };
}

}  // namespace terrain
