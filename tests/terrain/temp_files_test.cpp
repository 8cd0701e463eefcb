// terrain/temp_files.hpp: temporary names that fit and never repeat, the interrupt handler
// that removes registered temporaries and ends the process by its signal, deferred
// interrupts around a set of renames, and stale temporaries of dead processes.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>

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

TEST(TempFiles, StaleTemporariesAreThoseOfDeadProcesses) {
  terrain::test::ScratchDir dir;
  const pid_t dead = ::fork();
  if (dead == 0) ::_exit(0);
  ::waitpid(dead, nullptr, 0);
  const std::string target = dir.path("out.dv");
  std::ofstream(dir.path(".out.tmp" + std::to_string(dead) + "-1.dv")) << "x";
  fs::create_directory(dir.path(".out.scratch" + std::to_string(dead) + "-abcdef"));
  std::ofstream(dir.path(".out.tmp" + std::to_string(::getpid()) + "-1.dv")) << "x";  // ours: not stale
  std::ofstream(dir.path(".other.tmp" + std::to_string(dead) + "-1.dv")) << "x";       // another output's
  const auto stale = stale_temporaries(target);
  EXPECT_EQ(stale.size(), 2u);
}

}  // namespace
}  // namespace terrain
