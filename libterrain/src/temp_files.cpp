#include "terrain/temp_files.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <climits>
#include <cstring>
#include <mutex>
#include <system_error>

#include "terrain/error.hpp"

namespace terrain {

namespace fs = std::filesystem;

namespace {

// The registry the signal handler reads: fixed slots of fixed-size paths, so that the
// handler allocates nothing and reads only lock-free atomics (async-signal-safe).
enum : int { kFree = 0, kFilling = 1, kFile = 2, kFolder = 3 };
struct Slot {
  std::atomic<int> state{kFree};
  char path[PATH_MAX];
};
constexpr int kSlots = 256;
std::array<Slot, kSlots> slots;

// Removes the files directly inside the folder `path` (getdents64 and unlinkat: no
// allocation), then the folder.
void remove_folder_in_handler(const char* path) {
  const int fd = ::open(path, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd >= 0) {
    alignas(8) char buf[4096];
    for (;;) {
      const long n = ::syscall(SYS_getdents64, fd, buf, sizeof buf);
      if (n <= 0) break;
      for (long at = 0; at < n;) {
        struct Entry {
          ino64_t ino;
          off64_t off;
          unsigned short reclen;
          unsigned char type;
          char name[1];
        };
        const auto* e = reinterpret_cast<const Entry*>(buf + at);
        if (std::strcmp(e->name, ".") != 0 && std::strcmp(e->name, "..") != 0)
          ::unlinkat(fd, e->name, 0);
        at += e->reclen;
      }
    }
    ::close(fd);
  }
  ::rmdir(path);
}

std::atomic<int> deferring{0}, pending{0};

void on_signal(int sig) {
  if (deferring.load() > 0) {  // a DeferInterrupts is alive: it cleans up and re-raises
    pending.store(sig);
    return;
  }
  const int saved = errno;
  for (Slot& s : slots)
    if (s.state.load(std::memory_order_acquire) == kFile) {
      ::unlink(s.path);
      // SQLite's files beside a GeoPackage being written (its rollback journal, or the WAL
      // and shared-memory files): a stack buffer, no allocation.
      for (const char* suffix : {"-journal", "-wal", "-shm"}) {
        char side[PATH_MAX + 16];
        const std::size_t n = std::strlen(s.path), k = std::strlen(suffix);
        std::memcpy(side, s.path, n);
        std::memcpy(side + n, suffix, k + 1);
        ::unlink(side);
      }
    }
  for (Slot& s : slots)
    if (s.state.load(std::memory_order_acquire) == kFolder) remove_folder_in_handler(s.path);
  errno = saved;
  ::signal(sig, SIG_DFL);
  ::raise(sig);
}

std::atomic<unsigned long> counter{0};

// `stem` cut to at most `max` bytes, never inside a UTF-8 character.
std::string cut(std::string stem, std::size_t max) {
  if (stem.size() <= max) return stem;
  std::size_t n = max;
  while (n > 0 && (static_cast<unsigned char>(stem[n]) & 0xC0) == 0x80) --n;
  stem.resize(n);
  return stem;
}

// ".STEM." (STEM cut so that any temporary name of `target` fits NAME_MAX) and ".EXT".
std::pair<std::string, std::string> name_parts(const fs::path& target) {
  std::string stem = target.stem().string(), ext = target.extension().string();
  if (ext.size() > 16) stem += ext, ext.clear();  // not an extension a driver looks at
  // "." STEM ".scratch" PID(<= 10) "-" N or XXXXXX (<= 20) EXT
  constexpr std::size_t kFixed = 1 + 8 + 10 + 1 + 20;
  // Appended piece by piece: `"." + std::string` trips GCC 12's -Wrestrict false positive (PR
  // 105329).
  std::string prefix(".");
  prefix += cut(stem, NAME_MAX - kFixed - ext.size());
  prefix += '.';
  return {prefix, ext};
}

}  // namespace

void install_interrupt_cleanup() {
  static std::once_flag once;
  std::call_once(once, [] {
    struct sigaction sa {};
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
      struct sigaction old {};
      // A signal ignored by whoever started us (nohup, a shell's background job) stays ignored.
      if (::sigaction(sig, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;
      ::sigaction(sig, &sa, nullptr);
    }
  });
}

DeferInterrupts::DeferInterrupts() { ++deferring; }

DeferInterrupts::~DeferInterrupts() {
  if (--deferring == 0)
    if (const int sig = pending.exchange(0)) on_signal(sig);
}

TempRegistration::TempRegistration(const fs::path& path, bool folder) {
  if (path.empty()) return;
  const std::string p = fs::absolute(path).lexically_normal().string();
  if (p.size() >= PATH_MAX) return;  // the file system refuses such a path anyway
  for (int i = 0; i < kSlots; ++i) {
    int expected = kFree;
    if (!slots[std::size_t(i)].state.compare_exchange_strong(expected, kFilling,
                                                             std::memory_order_acq_rel))
      continue;
    std::memcpy(slots[std::size_t(i)].path, p.c_str(), p.size() + 1);
    slots[std::size_t(i)].state.store(folder ? kFolder : kFile, std::memory_order_release);
    slot_ = i;
    return;
  }
  // More than kSlots temporaries at once: this one is not cleaned on a signal (never seen).
}

TempRegistration::~TempRegistration() {
  if (slot_ >= 0) slots[std::size_t(slot_)].state.store(kFree, std::memory_order_release);
}

TempRegistration& TempRegistration::operator=(TempRegistration&& other) noexcept {
  if (this != &other) {
    if (slot_ >= 0) slots[std::size_t(slot_)].state.store(kFree, std::memory_order_release);
    slot_ = other.slot_;
    other.slot_ = -1;
  }
  return *this;
}

bool is_registered_temporary(const fs::path& path) {
  const std::string p = fs::absolute(path).lexically_normal().string();
  for (const Slot& s : slots)
    if (s.state.load(std::memory_order_acquire) == kFile && p == s.path) return true;
  return false;
}

fs::path temporary_sibling(const fs::path& target) {
  const auto [prefix, ext] = name_parts(target);
  return target.parent_path() /
         (prefix + "tmp" + std::to_string(::getpid()) + "-" + std::to_string(++counter) + ext);
}

ScratchDir::ScratchDir(const fs::path& near) {
  const std::string name =
      name_parts(near).first + "scratch" + std::to_string(::getpid()) + "-XXXXXX";
  std::string templ = (near.parent_path() / name).string();
  if (::mkdtemp(templ.data()) == nullptr)
    throw Error("cannot create a scratch folder beside '" + near.string() +
                "': " + std::strerror(errno));
  path_ = templ;
  registration_ = TempRegistration(path_, true);
}

ScratchDir::~ScratchDir() {
  std::error_code ec;
  fs::remove_all(path_, ec);
}

NewDirectories::NewDirectories(const fs::path& path) {
  std::error_code ec;
  for (fs::path p = fs::absolute(path).lexically_normal(); !p.empty() && !fs::exists(p, ec);
       p = p.parent_path()) {
    created_.push_back(p);
    if (p == p.parent_path()) break;
  }
  // Registered deepest first: the handler empties and removes the folders in that order.
  for (const fs::path& p : created_) registrations_.emplace_back(p, true);
  fs::create_directories(path, ec);
  if (ec) {
    registrations_.clear();
    std::error_code ignored;
    for (const fs::path& p : created_) fs::remove(p, ignored);
    throw Error("cannot create the directory '" + path.string() + "': " + ec.message());
  }
}

NewDirectories::~NewDirectories() {
  registrations_.clear();
  std::error_code ec;
  for (const fs::path& p : created_) fs::remove(p, ec);  // only when empty
}

void NewDirectories::keep() {
  registrations_.clear();
  created_.clear();
}

std::vector<fs::path> stale_temporaries(const fs::path& target) {
  std::vector<fs::path> out;
  const std::string prefix = name_parts(target).first;
  fs::path dir = target.parent_path();
  if (dir.empty()) dir = ".";
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.compare(0, prefix.size(), prefix) != 0) continue;
    std::size_t at = prefix.size();
    for (const char* kind : {"tmp", "scratch"})
      if (name.compare(at, std::strlen(kind), kind) == 0) {
        at += std::strlen(kind);
        break;
      }
    if (at == prefix.size()) continue;
    std::size_t digits = at;
    while (digits < name.size() && std::isdigit(static_cast<unsigned char>(name[digits]))) ++digits;
    if (digits == at || digits - at > 10) continue;
    if (digits < name.size() && name[digits] != '-' && name[digits] != '.') continue;
    const long pid = std::stol(name.substr(at, digits - at));
    if (pid <= 0 || pid == long(::getpid())) continue;
    if (::kill(pid_t(pid), 0) != 0 && errno == ESRCH) out.push_back(it->path());
  }
  return out;
}

}  // namespace terrain
