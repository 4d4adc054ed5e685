// Leftovers of killed runs: which are stale, what the next run removes or restores, and the
// folder swap with and without an atomic exchange.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

#include "io/crash_recovery.h"
#include "test_support.h"

namespace fs = std::filesystem;

namespace ndfmip::test {
namespace {

// The number of a process that has exited (and been reaped): no process has it now.
long deadPid() {
    pid_t pid = ::fork();
    if (pid == 0) ::_exit(0);
    int status = 0;
    ::waitpid(pid, &status, 0);
    return long(pid);
}

std::set<std::string> names(const fs::path& dir) {
    std::set<std::string> out;
    for (const auto& entry : fs::directory_iterator(dir)) out.insert(entry.path().filename());
    return out;
}

void makeFolder(const fs::path& dir, const std::string& content) {
    fs::create_directories(dir);
    writeBytes(dir / "manifest.json", content);
}

TEST(CrashRecovery, WritersAreAliveOnlyWhileTheirProcessIs) {
    const long dead = deadPid();
    EXPECT_FALSE(writerMayBeAlive(dead, 2000000000));
    EXPECT_FALSE(writerMayBeAlive(long(::getpid()), 2000000000))
        << "this process has no leftovers yet";
    EXPECT_TRUE(writerMayBeAlive(long(::getppid()), 2000000000));
    // A running process that started after the leftover was written merely reuses the number.
    EXPECT_FALSE(writerMayBeAlive(long(::getppid()), 1000));
}

TEST(CrashRecovery, StaleFoldersAreRemovedAndAMissingTargetIsRestored) {
    TempDir tmp("recover");
    const fs::path dir = tmp.path / "bake";
    const std::string dead = std::to_string(deadPid()), alive = std::to_string(::getppid());
    // Killed between the two renames of a swap: no bake, the old one set aside, the new staged.
    makeFolder(tmp.path / ("bake.old-" + dead), "old");
    makeFolder(tmp.path / ("bake.partial-" + dead), "new");
    // A bake still running elsewhere, and names that only look alike.
    makeFolder(tmp.path / ("bake.partial-" + alive), "running");
    makeFolder(tmp.path / ("other.partial-" + dead), "other");
    makeFolder(tmp.path / "bake.partial-x1", "user");
    makeFolder(tmp.path / ("bake.partial-" + dead + "x"), "user");
    recoverFolderLeftovers(dir);
    EXPECT_EQ(fileBytes(dir / "manifest.json"), "old");
    EXPECT_EQ(names(tmp.path),
              (std::set<std::string>{"bake", "bake.partial-" + alive, "other.partial-" + dead,
                                     "bake.partial-x1", "bake.partial-" + dead + "x"}));
    // With the target there, a stale set-aside copy is only removed.
    makeFolder(tmp.path / ("bake.old-" + dead), "older");
    recoverFolderLeftovers(dir);
    EXPECT_EQ(fileBytes(dir / "manifest.json"), "old");
    EXPECT_FALSE(fs::exists(tmp.path / ("bake.old-" + dead)));
}

TEST(CrashRecovery, StaleTemporaryFilesAreRemoved) {
    TempDir tmp("recover-tmp");
    const std::string dead = std::to_string(deadPid()), alive = std::to_string(::getppid());
    const fs::path out = tmp.path / "out.exr";
    writeBytes(out, "complete");
    writeBytes(tmp.path / ("out.exr.tmp-" + dead + "-0123abcd"), "half");
    writeBytes(tmp.path / ("out.exr.tmp-" + alive + "-0123abcd"), "writing");
    writeBytes(tmp.path / ("out.png.tmp-" + dead + "-0123abcd"), "another file's");
    removeStaleTemporaries(out);
    EXPECT_EQ(names(tmp.path),
              (std::set<std::string>{"out.exr", "out.exr.tmp-" + alive + "-0123abcd",
                                     "out.png.tmp-" + dead + "-0123abcd"}));
}

TEST(CrashRecovery, ReplaceFolderWithAndWithoutExchange) {
    TempDir tmp("replace");
    const fs::path dir = tmp.path / "bake", staging = tmp.path / "bake.partial-1";
    for (bool exchange : {true, false}) {
        SCOPED_TRACE(exchange);
        makeFolder(dir, "old");
        writeBytes(dir / "old_only.exr", "x");
        makeFolder(staging, "new");
        ASSERT_TRUE(replaceFolder(staging, dir, exchange).ok());
        EXPECT_EQ(fileBytes(dir / "manifest.json"), "new");
        EXPECT_FALSE(fs::exists(dir / "old_only.exr"));
        EXPECT_EQ(names(tmp.path), (std::set<std::string>{"bake"}));
        fs::remove_all(dir);
    }
    // No earlier folder: a plain rename.
    makeFolder(staging, "first");
    ASSERT_TRUE(replaceFolder(staging, dir).ok());
    EXPECT_EQ(fileBytes(dir / "manifest.json"), "first");
    EXPECT_EQ(names(tmp.path), (std::set<std::string>{"bake"}));
}

} // namespace
} // namespace ndfmip::test
