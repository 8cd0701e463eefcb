// terrain/temp_files.hpp: temporary names that fit and never repeat, the interrupt handler
// that removes registered temporaries and ends the process by its signal, deferred
// interrupts around a set of renames, and stale temporaries of dead processes.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "terrain/atomic_file.hpp"
#include "terrain/error.hpp"
#include "terrain/temp_files.hpp"
#include "test_support.hpp"

namespace terrain {
namespace {

namespace fs = std::filesystem;

TEST(TempFiles, SiblingNamesFitAndNeverRepeat) {
  const fs::path dir = "/some/dir";
  const std::string ext = ".ply";
  for (const std::size_t stem : {1u, 200u, 251u, 400u}) {
    const fs::path target = dir / (std::string(stem, 'a') + ext);
    const fs::path a = temporary_sibling(target), b = temporary_sibling(target);
    EXPECT_NE(a, b);
    EXPECT_LE(a.filename().string().size(), 255u) << stem;
    EXPECT_EQ(a.parent_path(), dir);
    EXPECT_EQ(a.extension(), ext);
    EXPECT_EQ(a.filename().string()[0], '.');
  }
  // A multi-byte character is never cut in half.
  std::string utf8;
  for (int i = 0; i < 200; ++i) utf8 += "\xc3\xa9";  // 'e' with an acute accent, 2 bytes
  const std::string name = temporary_sibling(dir / (utf8 + ".tif")).filename().string();
  EXPECT_LE(name.size(), 255u);
  const std::size_t stem_end = name.find(".tmp");
  EXPECT_EQ((stem_end - 1) % 2, 0u) << "the stem keeps whole characters";
}

// In a child: a registered file, a signal inside DeferInterrupts (the file stays, the code
// after the signal runs), then the scope's end (the file goes and the child dies by it).
TEST(TempFiles, DeferredInterruptRemovesTemporariesAndEndsByTheSignal) {
  terrain::test::ScratchDir dir;
  const std::string temp = dir.path("t.tmp"), marker = dir.path("after_signal");
  const pid_t pid = ::fork();
  if (pid == 0) {
    install_interrupt_cleanup();
    std::ofstream(temp) << "x";
    const TempRegistration reg(temp);
    {
      const DeferInterrupts defer;
      ::raise(SIGTERM);
      if (fs::exists(temp)) std::ofstream(marker) << "deferred";
    }
    ::_exit(0);  // not reached: the deferred signal ends the process
  }
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << status;
  EXPECT_TRUE(fs::exists(marker)) << "the signal was not deferred";
  EXPECT_FALSE(fs::exists(temp)) << "the registered temporary was left";
}

// Issue 48: an interrupted GeoPackage write left SQLite's journal beside the output (the
// temporary .gpkg went, its '-journal' stayed); the handler removes SQLite's side files
// of every registered file, and the folders a NewDirectories made, deepest first.
TEST(TempFiles, InterruptRemovesSqliteSideFilesAndNewFolders) {
  terrain::test::ScratchDir dir;
  const std::string gpkg = dir.path("t.gpkg"), deep = dir.path("a/b/c");
  const pid_t pid = ::fork();
  if (pid == 0) {
    install_interrupt_cleanup();
    const NewDirectories made(deep);
    const TempRegistration reg(gpkg);
    for (const char* side : {"", "-journal", "-wal", "-shm"}) std::ofstream(gpkg + side) << "x";
    std::ofstream(deep + "/.staged.tmp") << "x";
    const TempRegistration staged(deep + "/.staged.tmp");
    ::raise(SIGINT);
    ::_exit(0);  // not reached
  }
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGINT) << status;
  std::vector<std::string> left;
  for (const auto& e : fs::recursive_directory_iterator(dir.path("")))
    left.push_back(e.path().string());
  EXPECT_TRUE(left.empty()) << "left: " << (left.empty() ? "" : left.front());
}

// NewDirectories keeps its folders only when kept; a folder that existed is never removed.
TEST(TempFiles, NewDirectoriesGoUnlessKept) {
  terrain::test::ScratchDir dir;
  fs::create_directories(dir.path("old"));
  {
    const NewDirectories made(dir.path("old/x/y"));
    EXPECT_TRUE(fs::is_directory(dir.path("old/x/y")));
  }
  EXPECT_FALSE(fs::exists(dir.path("old/x")));
  EXPECT_TRUE(fs::is_directory(dir.path("old")));
  {
    NewDirectories made(dir.path("old/k"));
    made.keep();
  }
  EXPECT_TRUE(fs::is_directory(dir.path("old/k")));
  std::ofstream(dir.path("file")) << "x";
  EXPECT_THROW(NewDirectories(dir.path("file/sub")), Error);
}

// Issue 48: an output that was read-only came back 0644; a replaced file keeps its mode,
// as cp and GDAL keep it.
TEST(AtomicFile, AReplacedFileKeepsItsMode) {
  terrain::test::ScratchDir dir;
  const std::string f = dir.path("o.csv");
  for (const fs::perms mode : {fs::perms(0444), fs::perms(0640), fs::perms(0755)}) {
    std::ofstream(f) << "old";
    fs::permissions(f, mode, fs::perm_options::replace);
    write_file_atomic(f, "new");
    EXPECT_EQ(terrain::test::file_bytes(f), "new");
    EXPECT_EQ(fs::status(f).permissions() & fs::perms::mask, mode) << std::oct << int(mode);
    fs::permissions(f, fs::perms(0644), fs::perm_options::replace);
  }
}

TEST(TempFiles, StaleTemporariesAreThoseOfDeadProcesses) {
  terrain::test::ScratchDir dir;
  const pid_t dead = ::fork();
  if (dead == 0) ::_exit(0);
  ::waitpid(dead, nullptr, 0);
  const std::string target = dir.path("out.dv");
  std::ofstream(dir.path(".out.tmp" + std::to_string(dead) + "-1.dv")) << "x";
  fs::create_directory(dir.path(".out.scratch" + std::to_string(dead) + "-abcdef"));
  std::ofstream(dir.path(".out.tmp" + std::to_string(::getpid()) + "-1.dv"))
      << "x";  // ours: not stale
  std::ofstream(dir.path(".other.tmp" + std::to_string(dead) + "-1.dv"))
      << "x";  // another output's
  const auto stale = stale_temporaries(target);
  EXPECT_EQ(stale.size(), 2u);
}

}  // namespace
}  // namespace terrain
