// Leftovers of killed runs: which are stale, what the next run removes or restores, and the
// folder swap with and without an atomic exchange.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include "io/crash_recovery.h"
#include "ndfmip/bake_file.h"
#include "ndfmip/io.h"
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

// PREFIX followed by n, appended (GCC 12 warns wrongly of "prefix" + std::to_string(n)).
std::string numbered(const char* prefix, int n) {
    std::string text = prefix;
    text += std::to_string(n);
    return text;
}

std::set<std::string> names(const fs::path& dir) {
    std::set<std::string> out;
    for (const auto& entry : fs::directory_iterator(dir)) out.insert(entry.path().filename());
    return out;
}

std::string readBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

void makeFolder(const fs::path& dir, const std::string& content) {
    fs::create_directories(dir);
    writeBytes(dir / "manifest.json", content);
}

TEST(CrashRecovery, WritersAreAliveOnlyWhileTheirProcessIs) {
    const long dead = deadPid();
    EXPECT_FALSE(writerMayBeAlive(dead, 2000000000));
    // This process too: another of its threads may be writing.
    EXPECT_TRUE(writerMayBeAlive(long(::getpid()), 2000000000));
    EXPECT_FALSE(writerMayBeAlive(long(::getpid()), 1000)) << "an earlier process with this number";
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

// The render's EXR and PNG: both written, or on a failure the earlier pair kept as it was, the
// message naming the file asked for (not its temporary) and no temporary left.
TEST(CrashRecovery, ExrWithPreviewIsWrittenAsAPair) {
    TempDir tmp("exr-pair");
    Image image(4, 2, 3), preview(4, 2, 3);
    image.at(1, 1)[0] = 7.5f;
    preview.at(1, 1)[0] = 0.5f;
    const std::string exr = tmp.file("out.exr"), png = tmp.file("out.png");
    ASSERT_TRUE(saveExrWithPreview(exr, image, png, preview));
    Result<SourceImage> readExr = loadImage(exr), readPng = loadImage(png);
    ASSERT_TRUE(readExr && readPng);
    EXPECT_EQ(readExr->image.at(1, 1)[0], 7.5f);
    EXPECT_NEAR(readPng->image.at(1, 1)[0], 0.5f, 1.f / 255.f);
    EXPECT_EQ(names(tmp.path), (std::set<std::string>{"out.exr", "out.png"}));

    // A folder where the PNG goes: the earlier pair stays, byte for byte.
    const std::string before = readBytes(exr);
    fs::create_directory(tmp.path / "taken.png");
    Status s = saveExrWithPreview(exr, Image(2, 2, 3), tmp.file("taken.png"), preview);
    ASSERT_FALSE(s);
    EXPECT_EQ(s.error.rfind(tmp.file("taken.png") + ": ", 0), 0u) << s.error;
    EXPECT_EQ(readBytes(exr), before);
    EXPECT_EQ(names(tmp.path), (std::set<std::string>{"out.exr", "out.png", "taken.png"}));

    // No preview asked for: the EXR alone.
    ASSERT_TRUE(saveExrWithPreview(tmp.file("alone.exr"), image, "", Image{}));
    EXPECT_TRUE(fs::exists(tmp.path / "alone.exr"));
    EXPECT_FALSE(fs::exists(tmp.path / "alone.png"));
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

TEST(CrashRecovery, WriterTagsAreUniqueAndNameThisProcess) {
    std::vector<std::string> tags(16 * 8);
    std::vector<std::thread> threads;
    for (size_t t = 0; t < 16; ++t)
        threads.emplace_back([&tags, t] {
            for (size_t k = 0; k < 8; ++k) tags[t * 8 + k] = writerTag();
        });
    for (std::thread& thread : threads) thread.join();
    const std::set<std::string> distinct(tags.begin(), tags.end());
    EXPECT_EQ(distinct.size(), tags.size());
    for (const std::string& tag : tags)
        EXPECT_EQ(tag.rfind(std::to_string(::getpid()) + "-", 0), 0u) << tag;
}

TEST(CrashRecovery, LeftoversOfThisProcessAreKeptAndNewNamesRecognised) {
    TempDir tmp("recover-tagged");
    const fs::path dir = tmp.path / "bake";
    const std::string dead = std::to_string(deadPid());
    makeFolder(dir, "current");
    // Another thread of this process is writing; a dead process's tagged staging is stale.
    makeFolder(tmp.path / ("bake.partial-" + writerTag()), "writing");
    makeFolder(tmp.path / ("bake.partial-" + dead + "-7-1"), "killed");
    recoverFolderLeftovers(dir);
    const std::set<std::string> left = names(tmp.path);
    EXPECT_EQ(left.size(), 2u);
    EXPECT_TRUE(left.count("bake"));
    EXPECT_FALSE(left.count("bake.partial-" + dead + "-7-1"));
}

// Threads of one process writing folders beside one another, some of them the same folder:
// every write succeeds, each folder ends complete (one writer's), no staging is left.
TEST(CrashRecovery, ThreadsWritingFoldersBesideEachOtherAllSucceed) {
    TempDir tmp("recover-threads");
    constexpr int kThreads = 16;
    std::vector<std::string> errors(kThreads);
    std::vector<std::thread> threads;
    for (int t = 0; t < kThreads; ++t)
        threads.emplace_back([&, t] {
            // Even threads: a folder of their own; odd ones: all the same folder.
            const std::string name =
                (tmp.path / (t % 2 == 0 ? numbered("own", t) : std::string("shared"))).string();
            for (int round = 0; round < 4; ++round) {
                Status s = writeFolderWhole(
                    name, [](const fs::path&) { return Status::success(); },
                    [t](const fs::path& staging) {
                        for (int f = 0; f < 8; ++f)
                            writeBytes(staging / numbered("f", f), std::to_string(t));
                        return Status::success();
                    });
                if (!s) errors[size_t(t)] = s.error;
            }
        });
    for (std::thread& thread : threads) thread.join();
    for (int t = 0; t < kThreads; ++t) EXPECT_EQ(errors[size_t(t)], "") << "thread " << t;
    std::set<std::string> expected{"shared"};
    for (int t = 0; t < kThreads; t += 2) expected.insert(numbered("own", t));
    EXPECT_EQ(names(tmp.path), expected);
    // The shared folder is one writer's whole: all 8 files from the same thread.
    const std::string writer = fileBytes(tmp.path / "shared" / "f0");
    for (int f = 0; f < 8; ++f)
        EXPECT_EQ(fileBytes(tmp.path / "shared" / numbered("f", f)), writer);
    EXPECT_EQ(names(tmp.path / "shared").size(), 8u);
}

// What the Python module's threads do: bakes into one parent folder, through the library, 16
// at once, some of them to the same output. Every bake succeeds and leaves a readable bake.
TEST(CrashRecovery, ThreadsBakingIntoOneFolderAllSucceed) {
    TempDir tmp("recover-bakes");
    const std::string input = tmp.file("map.png");
    Image map = randomNormals(16, 16, 0.5f, 7);
    for (float& v : map.pixels) v = 0.5f * (v + 1.f); // stored as (n + 1) / 2
    ASSERT_TRUE(savePng(input, map, 16));
    constexpr int kThreads = 16;
    std::vector<std::string> errors(kThreads);
    std::vector<std::thread> threads;
    for (int t = 0; t < kThreads; ++t)
        threads.emplace_back([&, t] {
            BakeFileOptions options;
            options.method = t % 3 == 0 ? "naive" : "toksvig";
            options.force = true;
            const std::string output =
                tmp.file(t < 12 ? numbered("map", t) + ".bake" : std::string("same.bake"));
            Result<BakeFileReport> baked = bakeFile(input, output, options);
            if (!baked) errors[size_t(t)] = baked.error().message;
        });
    for (std::thread& thread : threads) thread.join();
    for (int t = 0; t < kThreads; ++t) EXPECT_EQ(errors[size_t(t)], "") << "thread " << t;
    for (int t = 0; t < 12; ++t) EXPECT_TRUE(loadBake(tmp.file(numbered("map", t) + ".bake"))) << t;
    EXPECT_TRUE(loadBake(tmp.file("same.bake")));
    EXPECT_TRUE(leftovers(tmp.path).empty());
}

} // namespace
} // namespace ndfmip::test
