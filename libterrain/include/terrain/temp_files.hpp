#pragma once
// The temporary files and folders of a run: named so that two runs never share one and
// every name fits the file system's 255-byte limit, registered so that SIGINT, SIGTERM and
// SIGHUP remove them before the process dies, and found again by a later run when a killed
// process (SIGKILL, a power cut) left them behind.
//
// Names, beside the target `DIR/STEM.EXT`:
//   DIR/.STEM.tmpPID-N.EXT        a file being written (AtomicFile), renamed onto the target
//   DIR/.STEM.scratchPID-XXXXXX/  a private scratch folder (ScratchDir, mkdtemp)
// STEM is cut (at a UTF-8 character boundary) so that the name fits, PID is the writing
// process and N counts this process's temporaries, so names never repeat within a run.
#include <filesystem>
#include <string>
#include <vector>

namespace terrain {

// Installs handlers for SIGINT, SIGTERM and SIGHUP that remove every registered path (a
// folder with the files in it) and then end the process by the same signal, so the exit
// status still says which signal ended it. Idempotent; every tool calls it at start.
void install_interrupt_cleanup();

// While alive, SIGINT/SIGTERM/SIGHUP wait: the handler only notes the signal, and the
// destructor of the last DeferInterrupts then cleans up and ends the process by it. Made
// around the renames of a set of outputs, so that an interrupt leaves every output new or
// every output old (a mask would not do: the signal may reach any thread).
class DeferInterrupts {
 public:
  DeferInterrupts();
  ~DeferInterrupts();
  DeferInterrupts(const DeferInterrupts&) = delete;
  DeferInterrupts& operator=(const DeferInterrupts&) = delete;
};

// While alive, `path` is removed if the process is interrupted (see above). Registering
// does not create anything; destroying the registration does not remove anything.
class TempRegistration {
 public:
  TempRegistration() = default;
  // `folder`: remove the files directly inside it, then the folder itself.
  explicit TempRegistration(const std::filesystem::path& path, bool folder = false);
  ~TempRegistration();
  TempRegistration(TempRegistration&& other) noexcept : slot_(other.slot_) { other.slot_ = -1; }
  TempRegistration& operator=(TempRegistration&& other) noexcept;
  TempRegistration(const TempRegistration&) = delete;
  TempRegistration& operator=(const TempRegistration&) = delete;

 private:
  int slot_ = -1;
};

// True when `path` is a temporary file this process has registered and not yet released
// (a writer handed a staged path writes it in place instead of nesting a second temporary).
bool is_registered_temporary(const std::filesystem::path& path);

// "DIR/.STEM.tmpPID-N.EXT" for `target` (see above), unique within this process.
std::filesystem::path temporary_sibling(const std::filesystem::path& target);

// A private folder beside `near` ("DIR/.STEM.scratchPID-XXXXXX", mode 0700), registered
// for interrupts, removed with everything in it when destroyed. Throws Error when it
// cannot be created.
class ScratchDir {
 public:
  explicit ScratchDir(const std::filesystem::path& near);
  ~ScratchDir();
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  TempRegistration registration_;
};

// Creates the folder `path` and its missing parents for outputs; the folders it created
// are removed again (when empty) on destruction unless keep() was called, and on
// SIGINT/SIGTERM/SIGHUP: a failed or interrupted run leaves no empty folder behind.
// Throws Error when a folder cannot be created.
class NewDirectories {
 public:
  explicit NewDirectories(const std::filesystem::path& path);
  ~NewDirectories();
  NewDirectories(const NewDirectories&) = delete;
  NewDirectories& operator=(const NewDirectories&) = delete;
  void keep();

 private:
  std::vector<std::filesystem::path> created_;  // deepest first
  std::vector<TempRegistration> registrations_;
};

// Temporaries beside `target` (files and scratch folders named as above) whose process is
// no longer running: what an earlier run killed by SIGKILL left behind.
std::vector<std::filesystem::path> stale_temporaries(const std::filesystem::path& target);

}  // namespace terrain
